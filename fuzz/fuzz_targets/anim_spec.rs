//! Animation spec (TOML) parsing, flag overrides and limits, then the per-frame camera and
//! scene motion of the parsed animation.
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
    static SHAPES: OnceLock<Scene> = OnceLock::new();
    let scene = SHAPES.get_or_init(Scene::shapes);
    let _ = exercise::anim_spec(text, Path::new("fuzz/spec.toml"), scene);
});
