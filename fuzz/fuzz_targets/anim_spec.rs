//! Animation spec (TOML) parsing, flag overrides and limits, then the per-frame camera and
//! scene motion of the parsed animation.
#![no_main]

use std::path::Path;
use std::sync::OnceLock;

use envshadow::anim::{Animation, Overrides};
use envshadow::scene::Scene;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(anim) = Animation::parse(text, Path::new("fuzz/spec.toml"), &Overrides::default())
    else {
        return;
    };
    static SHAPES: OnceLock<Scene> = OnceLock::new();
    let scene = SHAPES.get_or_init(Scene::shapes);
    for frame in [0, anim.frame_count / 2, anim.frame_count - 1] {
        if let Ok(camera) = anim.camera(scene, frame) {
            let _ = anim.scene_transform(frame, camera.target);
        }
    }
});
