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
    std::fs::write(dir.path().join("buffer.bin"), files::triangle_buffer()).unwrap();
    std::fs::write(dir.path().join("texture.png"), files::texture_png()).unwrap();
    let path = dir.path().join("fuzz.gltf");
    replay("gltf", |input| {
        let bytes = std::fs::read(input).unwrap();
        check_error(exercise::gltf(&bytes, &path), "fuzz.gltf", input);
    });
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
