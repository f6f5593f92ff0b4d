//! What each fuzz target does with its input, shared with tests/it/fuzz_regressions.rs so that a
//! kept crashing input is replayed through exactly the calls the fuzzer made. Each returns the
//! loader's result; whatever loads is also used the way a render would use it.

// Each fuzz target includes this file and calls one of its functions.
#![allow(dead_code)]

use std::path::Path;

use envshadow::anim::{AnimFlags, Animation};
use envshadow::envmap::EnvMap;
use envshadow::error::Result;
use envshadow::lights::{LightSet, Sampler, parse_json};
use envshadow::limits::Budget;
use envshadow::scene::{Material, Scene};
use glam::{Mat4, Vec2, Vec3};

/// The memory budget the loaders are held to here: half of libFuzzer's `-rss_limit_mb=2048`
/// (scripts/fuzz.sh). An input the budget accepts and that still runs out of that limit (an
/// OOM finding) is one whose memory the estimate fell short of.
pub const BUDGET_BYTES: u64 = 1 << 30;

fn budget() -> Budget {
    Budget::default().with_limit(BUDGET_BYTES)
}

/// An animation spec, then the camera and scene motion at its first, middle and last frames.
pub fn anim_spec(text: &str, path: &Path, scene: &Scene) -> Result<()> {
    let anim = Animation::parse(text, path, &AnimFlags::default())?;
    for frame in [0, anim.frame_count / 2, anim.frame_count - 1] {
        if anim.camera(scene, frame).is_ok()
            && let Ok(pivot) = anim.pivot(scene)
        {
            let _ = anim.scene_transform(frame, pivot);
        }
    }
    Ok(())
}

/// A glTF or GLB file (within [`BUDGET_BYTES`]), then a BVH over what loaded and rays from six
/// sides; then the same for the scene spun a quarter turn about its centre, as a spinning
/// animation poses it.
pub fn gltf(data: &[u8], path: &Path) -> Result<()> {
    let scene = Scene::load_bytes_within(data, path, &mut budget())?;
    // Building is linear in the triangles; keep the executions fast.
    if scene.triangles.len() > 100_000 {
        return Ok(());
    }
    trace(&scene);
    let (lo, hi) = scene.bounds();
    let centre = (lo + hi) * 0.5;
    let spin = Mat4::from_translation(centre)
        * Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2)
        * Mat4::from_translation(-centre);
    trace(&scene.transformed(spin));
    Ok(())
}

/// A Draco stream as the glTF loader decodes a primitive's (`envshadow::scene::draco`): the
/// first two bytes (little-endian) are the largest count the primitive's accessors declare,
/// which bounds the decode; the rest is the stream. Inputs under two bytes are skipped.
pub fn draco(data: &[u8], path: &Path) -> Result<usize> {
    let Some((declared, stream)) = data.split_first_chunk::<2>() else {
        return Ok(0);
    };
    let largest = u64::from(u16::from_le_bytes(*declared));
    envshadow::scene::draco::decode_stream(path, stream, largest)
}

/// A spec's spin as a render poses the scene ([`Animation::scene_transform`] about its pivot,
/// then the BVH over the posed copy, as `render_tile_list` in src/coordinator.rs does) at its
/// first, middle and last frames, with rays through each.
pub fn posed_scene(text: &str, path: &Path, scene: &Scene) -> Result<()> {
    let anim = Animation::parse(text, path, &AnimFlags::default())?;
    let pivot = anim.pivot(scene)?;
    // As `Inputs::load` refuses a spin that could overflow.
    for s in anim.motion.segments() {
        if s.kind == envshadow::motion::MotionKind::Spin
            && let Some(why) =
                scene.turn_problem(s.pivot.map_or(pivot.target, |p| scene.to_local(p)))
        {
            return Err(envshadow::error::input_error(path, why));
        }
    }
    for frame in [0, anim.frame_count / 2, anim.frame_count - 1] {
        anim.camera(scene, frame)?;
        if let Some(m) = anim.scene_transform(frame, pivot) {
            trace(&scene.transformed(m));
        }
    }
    Ok(())
}

/// A small scene for [`posed_scene`]: a ground square and a tetrahedron standing on it, off
/// centre (6 triangles).
pub fn small_scene() -> Scene {
    let positions = vec![
        Vec3::new(-2.0, 0.0, -2.0),
        Vec3::new(2.0, 0.0, -2.0),
        Vec3::new(2.0, 0.0, 2.0),
        Vec3::new(-2.0, 0.0, 2.0),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(1.5, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 1.2, 0.4),
    ];
    let triangles = vec![
        [0, 3, 2],
        [0, 2, 1],
        [4, 5, 7],
        [5, 6, 7],
        [6, 4, 7],
        [4, 6, 5],
    ];
    Scene {
        normals: vec![Vec3::Y; positions.len()],
        uvs: vec![Vec2::ZERO; positions.len()],
        positions,
        tri_material: vec![0; triangles.len()],
        triangles,
        materials: vec![Material::default_grey()],
        source: "fuzz:small".into(),
        ..Scene::default()
    }
}

/// A BVH over `scene` and rays towards its centre from six sides.
fn trace(scene: &Scene) {
    let accel = scene.accel();
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
        // A scene near f32's range puts the origin past it; a render refuses such a scene
        // (its camera is not finite), and the ray's own check is a debug assertion.
        if !origin.is_finite() {
            continue;
        }
        let _ = accel.intersect(origin, -d);
        let _ = accel.occluded(origin, -d);
    }
}

/// An environment map (format from `path`'s extension, within [`BUDGET_BYTES`]), reduced to
/// lights by both samplers.
pub fn envmap(data: &[u8], path: &Path) -> Result<()> {
    let env = EnvMap::decode_within(data, path, &mut budget())?;
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
