//! The build identity (`envshadow version --build`, `build` in farm plans and job manifests):
//! a hash of what decides the output bits, computed when the crate is compiled.
//!
//! It used to be the SHA-256 of the executable, which changes when nothing that reaches a
//! pixel does. `cargo test --release` relinks `target/release/envshadow` into a different file
//! than `cargo build --release` from the same source: the tests' dev-dependency `tempfile`
//! turns on rustix's `fs` feature (Cargo unifies a dev-dependency's features into the normal
//! dependencies when it builds test targets), and rustix's new feature set changes its
//! metadata hash and with it the symbol names of every crate above it. rustix is reached only
//! through clap → terminal_size (the width of `--help`), so both executables render the same
//! bits; the debug info's absolute source paths likewise made two checkouts of one commit
//! "different builds". A farm interrupted, then `cargo test`, then run again, never finished.
//!
//! So the identity hashes the inputs of the compilation instead:
//! - every file under `src/`, `build.rs`, `Cargo.toml` and `Cargo.lock` (paths relative to the
//!   crate, so where the checkout lies does not matter; the lock file pins every dependency's
//!   version and checksum);
//! - the compiler, `rustc -vV` (version, commit, host, LLVM);
//! - the target triple, the profile and its opt-level;
//! - the flags: `CARGO_ENCODED_RUSTFLAGS` (RUSTFLAGS and `build.rustflags` alike) and the
//!   target features they result in (`-C target-cpu=native` names no feature itself but
//!   turns on the build machine's, and a native build can hit a ray differently);
//! - the crate's own enabled features.
//!
//! Left out on purpose: debug-info level, codegen units and LTO (they do not change float
//! results: Rust allows no fast-math and no contraction into FMA), and the features Cargo
//! unifies into dependencies, which a build script cannot see. The latter are why
//! `cargo test --release` is harmless today; a dev-dependency that turned on a feature of a
//! crate on the pixels' path (glam, libm, obvhs, exr, image) would break that (Cargo.toml
//! says so beside [dev-dependencies]).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

fn main() {
    let root = PathBuf::from(env("CARGO_MANIFEST_DIR"));
    let mut h = Sha256::new();
    let mut put = |label: &str, bytes: &[u8]| {
        // Length-prefixed, so no two different inputs hash the same stream.
        h.update((label.len() as u64).to_le_bytes());
        h.update(label.as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(bytes);
    };
    put("identity", b"envshadow build identity 1");

    let mut files = vec![
        PathBuf::from("build.rs"),
        PathBuf::from("Cargo.toml"),
        PathBuf::from("Cargo.lock"),
    ];
    sources(&root, Path::new("src"), &mut files);
    files.sort();
    for f in &files {
        let name = f
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/");
        match std::fs::read(root.join(f)) {
            Ok(bytes) => put(&format!("file {name}"), &bytes),
            // A crate packaged without its lock file: the dependencies are whatever Cargo
            // resolved, which the identity cannot see.
            Err(_) if name == "Cargo.lock" => put("no Cargo.lock", b""),
            Err(e) => panic!("build.rs: reading {}: {e}", root.join(f).display()),
        }
    }

    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let out = std::process::Command::new(&rustc)
        .arg("-vV")
        .output()
        .unwrap_or_else(|e| panic!("build.rs: running {rustc} -vV: {e}"));
    assert!(out.status.success(), "build.rs: {rustc} -vV failed");
    put("rustc -vV", &out.stdout);

    for var in [
        "TARGET",
        "PROFILE",
        "OPT_LEVEL",
        "CARGO_ENCODED_RUSTFLAGS",
        "CARGO_CFG_TARGET_FEATURE",
    ] {
        put(var, std::env::var(var).unwrap_or_default().as_bytes());
    }
    let mut features: Vec<String> = std::env::vars()
        .filter_map(|(k, _)| k.strip_prefix("CARGO_FEATURE_").map(str::to_string))
        .collect();
    features.sort();
    put("features", features.join(",").as_bytes());

    let id = format!("{:x}", h.finalize());
    println!("cargo:rustc-env=ENVSHADOW_BUILD_ID={}", &id[..16]);
    for path in ["src", "build.rs", "Cargo.toml", "Cargo.lock"] {
        println!("cargo:rerun-if-changed={path}");
    }
    println!("cargo:rerun-if-env-changed=RUSTFLAGS");
    println!("cargo:rerun-if-env-changed=CARGO_ENCODED_RUSTFLAGS");
}

fn env(name: &str) -> String {
    std::env::var(name).unwrap_or_else(|_| panic!("build.rs: {name} is not set"))
}

/// Every file below `root/dir`, as paths relative to `root`.
fn sources(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    let rd = std::fs::read_dir(root.join(dir))
        .unwrap_or_else(|e| panic!("build.rs: listing {}: {e}", root.join(dir).display()));
    for e in rd {
        let e = e.unwrap_or_else(|e| panic!("build.rs: listing {}: {e}", dir.display()));
        let rel = dir.join(e.file_name());
        if e.file_type().is_ok_and(|t| t.is_dir()) {
            sources(root, &rel, out);
        } else {
            out.push(rel);
        }
    }
}
