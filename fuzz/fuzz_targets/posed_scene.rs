//! Animation specs as a spinning render poses the scene: the spin's transform of a small scene
//! at the first, middle and last frames, and the BVH built over each posed copy.
#![no_main]

use std::path::Path;
use std::sync::OnceLock;

use envshadow::scene::Scene;
use libfuzzer_sys::fuzz_target;

#[path = "../src/exercise.rs"]
mod exercise;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    static SCENE: OnceLock<Scene> = OnceLock::new();
    let scene = SCENE.get_or_init(exercise::small_scene);
    let _ = exercise::posed_scene(text, Path::new("fuzz/spec.toml"), scene);
});
