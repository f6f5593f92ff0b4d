//! Run-time SIMD dispatch must not change a bit: farm hosts with and without AVX2 render the
//! same frames. `ENVSHADOW_NO_AVX2` forces the SSE2 kernels, so one host can compare both;
//! `envshadow version --kernels` shows which ran, so the comparison cannot pass by rendering
//! the same kernels twice.

use crate::common::{self, Failures};

use std::fs;
use std::path::Path;
use std::process::Command;

/// `cmd` with `ENVSHADOW_NO_AVX2` set or removed.
fn with_no_avx2(mut cmd: Command, no_avx2: bool) -> Command {
    if no_avx2 {
        cmd.env("ENVSHADOW_NO_AVX2", "1");
    } else {
        cmd.env_remove("ENVSHADOW_NO_AVX2");
    }
    cmd
}

/// The kernels a process of the binary runs, from `envshadow version --kernels`.
fn kernels(no_avx2: bool) -> String {
    let mut cmd = with_no_avx2(common::bin(), no_avx2);
    let o = cmd.args(["version", "--kernels"]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    out.lines()
        .find_map(|l| l.strip_prefix("kernels "))
        .unwrap_or_else(|| panic!("no kernels line in {out:?}"))
        .to_string()
}

/// Whether this CPU has AVX2 (what the binary runs without the variable). Where it has not,
/// says so on stderr, past libtest's capture: the AVX2 half of these tests cannot run here.
fn cpu_has_avx2(test: &str) -> bool {
    #[cfg(target_arch = "x86_64")]
    let has = std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let has = false;
    if !has {
        common::notice(&format!(
            "SKIPPED part of {test}: this CPU has no AVX2, so only the SSE2 (or scalar) kernels run"
        ));
    }
    has
}

#[test]
fn no_avx2_variable_switches_the_kernels() {
    let avx2 = cpu_has_avx2(common::this_test!());
    let fallback = if cfg!(target_arch = "x86_64") {
        "sse2"
    } else {
        "scalar"
    };
    assert_eq!(kernels(true), fallback, "with ENVSHADOW_NO_AVX2");
    assert_eq!(
        kernels(false),
        if avx2 { "avx2" } else { fallback },
        "without ENVSHADOW_NO_AVX2"
    );
}

fn render(dir: &Path, name: &str, method: &str, no_avx2: bool) -> std::path::PathBuf {
    let out = dir.join(name);
    let spec = dir.join(format!("{name}.toml"));
    fs::write(
        &spec,
        format!(
            "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 120\n[motion]\nframes = 2\n\
             [render]\nwidth = 96\nheight = 72\ntile = 16\nmethod = \"{method}\"\n\
             [output]\ndir = \"{}\"\n",
            out.display()
        ),
    )
    .unwrap();
    let mut cmd = with_no_avx2(common::bin(), no_avx2);
    let o = cmd
        .args(["render", "-q", "--no-report"])
        .arg(&spec)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

#[test]
fn avx2_and_sse2_kernels_write_identical_frames() {
    if cpu_has_avx2(common::this_test!()) {
        // The two renders below run different kernels (no_avx2_variable_switches_the_kernels
        // checks the variable itself).
        assert_ne!(kernels(false), kernels(true));
    }
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for method in ["brute", "grid-nowarp-uncertainty", "grid-warp-boundary"] {
        failures.case(method, || {
            let a = render(dir.path(), &format!("{method}-avx2"), method, false);
            let b = render(dir.path(), &format!("{method}-sse2"), method, true);
            for frame in ["frame_0000", "frame_0001"] {
                for ext in ["exr", "png"] {
                    let file = format!("{frame}.{ext}");
                    let (x, y) = (
                        fs::read(a.join(&file)).unwrap(),
                        fs::read(b.join(&file)).unwrap(),
                    );
                    assert!(x == y, "{file} differs between the AVX2 and SSE2 kernels");
                }
            }
        });
    }
    failures.assert_none();
}
