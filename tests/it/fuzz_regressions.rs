//! Inputs the fuzz campaign (fuzz/, FUZZING.md) found crashing, hanging or exhausting memory,
//! kept under tests/data/fuzz/TARGET/ and replayed here through the same calls as the fuzz
//! targets, plus the seed corpora in fuzz/seeds/. Each must give a result (Ok or an input error
//! naming the file), never a panic.

use std::path::{Path, PathBuf};

use envshadow::error::InputError;

use crate::common::Failures;
use envshadow::scene::Scene;

#[path = "../../fuzz/src/exercise.rs"]
mod exercise;
#[path = "../../fuzz/src/files.rs"]
mod files;

fn inputs(target: &str) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut v = Vec::new();
    for dir in [
        root.join("tests/data/fuzz").join(target),
        root.join("fuzz/seeds").join(target),
    ] {
        if let Ok(rd) = std::fs::read_dir(&dir) {
            v.extend(
                rd.filter_map(|e| e.ok())
                    .map(|e| e.path())
                    .filter(|p| p.extension().is_none_or(|e| e != "expect")),
            );
        }
    }
    v.sort();
    v
}

/// An error must be an input error naming `name` (the path the loader was given), and contain
/// the text of `INPUT.expect` where the regression has one (release builds wrap integer
/// overflows the fuzzer's debug assertions caught, so "no panic" alone would not tell).
fn check_error(result: anyhow::Result<()>, name: &str, input: &Path) {
    let mut expect = input.as_os_str().to_owned();
    expect.push(".expect");
    if let Ok(text) = std::fs::read_to_string(&expect) {
        let msg = match &result {
            Ok(()) => String::new(),
            Err(e) => format!("{e:#}"),
        };
        assert!(msg.contains(text.trim()), "{}: {msg}", input.display());
    }
    if let Err(e) = result {
        let msg = format!("{e:#}");
        assert!(
            e.chain().any(|c| c.downcast_ref::<InputError>().is_some()),
            "{}: not an input error: {msg}",
            input.display()
        );
        assert!(msg.contains(name), "{}: {msg}", input.display());
        assert!(!msg.contains('\n'), "{}: {msg}", input.display());
    }
}

/// Replays every kept input of `target` through `run`, each a case of one table: every input
/// that panics or fails wrongly is listed, and a target with no inputs at all (a moved folder)
/// fails instead of passing.
fn replay(target: &str, mut run: impl FnMut(&Path)) {
    let mut failures = Failures::new();
    for input in inputs(target) {
        failures.case(&input.display().to_string(), || run(&input));
    }
    failures.assert_none();
}

#[test]
fn anim_spec_inputs() {
    let scene = Scene::shapes();
    let path = Path::new("fuzz/spec.toml");
    replay("anim_spec", |input| {
        let bytes = std::fs::read(input).unwrap();
        let Ok(text) = std::str::from_utf8(&bytes) else {
            return;
        };
        check_error(
            exercise::anim_spec(text, path, &scene),
            "fuzz/spec.toml",
            input,
        );
    });
}

#[test]
fn posed_scene_inputs() {
    let scene = exercise::small_scene();
    let path = Path::new("fuzz/spec.toml");
    replay("posed_scene", |input| {
        let bytes = std::fs::read(input).unwrap();
        let Ok(text) = std::str::from_utf8(&bytes) else {
            return;
        };
        check_error(
            exercise::posed_scene(text, path, &scene),
            "fuzz/spec.toml",
            input,
        );
    });
}

#[test]
fn gltf_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let path = files::model_folder(dir.path()).join("fuzz.gltf");
    replay("gltf", |input| {
        let bytes = std::fs::read(input).unwrap();
        check_error(exercise::gltf(&bytes, &path), "fuzz.gltf", input);
    });
}

/// The `uri-*` seeds reach URI resolution in the fuzz target's folder both ways: each spelling
/// that leaves the folder (a file outside exists, so only the check refuses it) is refused
/// naming its URI, and the ones that stay inside load. Without this, a seed set that never got
/// past the JSON would pass the replay above.
#[test]
fn uri_seeds_reach_resolution_and_only_the_inside_ones_load() {
    let dir = tempfile::tempdir().unwrap();
    let path = files::model_folder(dir.path()).join("fuzz.gltf");
    let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/gltf");
    let loads = [
        "uri-link-in.gltf",
        "uri-percent-name.gltf",
        "uri-back-in.gltf",
    ];
    let refused = [
        (
            "uri-parent.gltf",
            "'../outside.bin' lies outside the model's folder",
        ),
        (
            "uri-percent-parent.gltf",
            "'%2e%2e/outside.bin' lies outside",
        ),
        ("uri-absolute.gltf", "'/etc/passwd' lies outside"),
        ("uri-file-scheme.gltf", "'file:///etc/passwd' lies outside"),
        ("uri-file-host.gltf", "names a file on another host"),
        ("uri-link-out.gltf", "'outside-link.bin' lies outside"),
        ("uri-http.gltf", "unsupported URI scheme"),
        (
            "uri-image-file-scheme.gltf",
            "'file:///etc/passwd' lies outside",
        ),
        (
            "uri-image-parent.gltf",
            "'%2E%2E/%2E%2E/etc/passwd' lies outside",
        ),
    ];
    let mut failures = Failures::new();
    for name in loads {
        failures.case(name, || {
            let bytes = std::fs::read(seeds.join(name)).unwrap();
            if let Err(e) = exercise::gltf(&bytes, &path) {
                panic!("refused: {e:#}");
            }
        });
    }
    for (name, why) in refused {
        failures.case(name, || {
            let bytes = std::fs::read(seeds.join(name)).unwrap();
            match exercise::gltf(&bytes, &path) {
                Ok(()) => panic!("loaded"),
                Err(e) => assert!(format!("{e:#}").contains(why), "{e:#}"),
            }
        });
    }
    failures.assert_none();
}

#[test]
fn draco_inputs() {
    replay("draco", |input| {
        let bytes = std::fs::read(input).unwrap();
        let r = exercise::draco(&bytes, Path::new("fuzz/mesh.gltf")).map(|_| ());
        check_error(r, "fuzz/mesh.gltf", input);
    });
}

/// The `draco` seeds reach past the decoder's header into every connectivity and attribute
/// decoder (their values read out) under the limits they declare; only the stream cut short
/// and the point cloud (not a mesh) are refused.
#[test]
fn draco_seeds_decode_within_their_declared_limits() {
    let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/draco");
    let mut failures = Failures::new();
    for input in inputs("draco") {
        let name = input.file_name().unwrap().to_str().unwrap().to_string();
        if !input.starts_with(&seeds) {
            continue;
        }
        failures.case(&name, || {
            let bytes = std::fs::read(&input).unwrap();
            let r = exercise::draco(&bytes, Path::new("fuzz/mesh.gltf"));
            match name.as_str() {
                "cube-draco-broken.drc" | "points.drc" => assert!(r.is_err(), "{name} decoded"),
                _ => assert!(r.unwrap() > 0, "{name} decoded to nothing"),
            }
        });
    }
    failures.assert_none();
}

fn map_inputs(target: &str, name: &str) {
    replay(target, |input| {
        let bytes = std::fs::read(input).unwrap();
        check_error(exercise::envmap(&bytes, Path::new(name)), name, input);
    });
}

#[test]
fn envmap_exr_inputs() {
    map_inputs("envmap_exr", "fuzz/map.exr");
}

#[test]
fn envmap_hdr_inputs() {
    map_inputs("envmap_hdr", "fuzz/map.hdr");
}

#[test]
fn lights_json_inputs() {
    replay("lights_json", |input| {
        let bytes = std::fs::read(input).unwrap();
        let r = exercise::lights_json(&bytes, Path::new("fuzz/lights.json"));
        check_error(r, "fuzz/lights.json", input);
    });
}
