//! What each fuzz target does with its input, shared with tests/it/fuzz_regressions.rs so that a
//! kept crashing input is replayed through exactly the calls the fuzzer made. Each returns the
//! loader's result; whatever loads is also used the way a render would use it.

// Each fuzz target includes this file and calls one of its functions.
#![allow(dead_code)]

use std::path::Path;

use envshadow::accel::Accel;
use envshadow::anim::{AnimFlags, Animation};
use envshadow::envmap::EnvMap;
use envshadow::error::Result;
use envshadow::lights::{LightSet, Sampler, parse_json};
use envshadow::scene::Scene;
use glam::Vec3;

/// An animation spec, then the camera and scene motion at its first, middle and last frames.
pub fn anim_spec(text: &str, path: &Path, scene: &Scene) -> Result<()> {
    let anim = Animation::parse(text, path, &AnimFlags::default())?;
    for frame in [0, anim.frame_count / 2, anim.frame_count - 1] {
        if let Ok(camera) = anim.camera(scene, frame) {
            let _ = anim.scene_transform(frame, camera.target);
        }
    }
    Ok(())
}

/// A glTF or GLB file, then a BVH over what loaded and rays from six sides.
pub fn gltf(data: &[u8], path: &Path) -> Result<()> {
    let scene = Scene::load_bytes(data, path)?;
    // Building is linear in the triangles; keep the executions fast.
    if scene.triangles.len() > 100_000 {
        return Ok(());
    }
    let accel = Accel::build(&scene.positions, &scene.triangles);
    let (lo, hi) = scene.bounds();
    let centre = (lo + hi) * 0.5;
    for d in [
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::NEG_X,
        Vec3::NEG_Y,
        Vec3::NEG_Z,
    ] {
        let origin = centre + d * ((hi - lo).length() + 1.0);
        let _ = accel.intersect(origin, -d);
        let _ = accel.occluded(origin, -d);
    }
    Ok(())
}

/// An environment map (format from `path`'s extension), reduced to lights by both samplers.
pub fn envmap(data: &[u8], path: &Path) -> Result<()> {
    let env = EnvMap::decode(data, path)?;
    // Sampling is linear in the texels; keep the executions fast.
    if env.width * env.height > 1 << 16 {
        return Ok(());
    }
    for sampler in [Sampler::Sis, Sampler::MedianCut] {
        for n in [1, 7, 32] {
            if let Ok(set) = LightSet::build(&env, n, sampler) {
                let _ = set.cell_of(Vec3::new(0.3, 0.5, -0.8).normalize());
            }
        }
    }
    Ok(())
}

/// A lights JSON file, then the O(1) cell lookup of the lights it rebuilt.
pub fn lights_json(data: &[u8], path: &Path) -> Result<()> {
    let set = parse_json(data, path)?;
    for d in [Vec3::X, Vec3::NEG_Y, Vec3::new(0.6, 0.0, 0.8)] {
        let _ = set.cell_of(d);
    }
    Ok(())
}
