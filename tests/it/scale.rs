//! The same scene at any scale and far from the world's origin renders the same (issue 23):
//! shadow rays leave the surface by a bound on the hit point's own rounding error (src/offset.rs),
//! BVH boxes are not culled within a fixed distance of a ray's origin, and a scene far from the
//! origin is rendered relative to a render origin near it (src/scene/origin.rs).
//!
//! Validation cannot see these errors — brute force shares the shadow-ray origin — so each
//! scaled or moved render is compared with the unscaled one.

use std::path::{Path, PathBuf};

use crate::common::{self, Failures, Gltf};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::coordinator::thread_pool;
use envshadow::film::{Channel, Film};
use envshadow::frame::render_frame;
use envshadow::inputs::Inputs;
use envshadow::motion::{Motion, MotionKind};
use envshadow::run::Silent;
use envshadow::scene::Scene;
use envshadow::settings::{LightsLayer, RenderLayer};
use serde_json::json;

/// Writes `scene`'s triangles (one primitive per material, its base colour) as `name.glb` in
/// `dir`, under one node scaled by `scale` and moved by `translation`.
pub fn write_scene(
    scene: &Scene,
    dir: &Path,
    name: &str,
    scale: f64,
    translation: [f64; 3],
) -> PathBuf {
    let mut g = Gltf::default();
    let flat = |v: &[glam::Vec3]| -> Vec<f32> { v.iter().flat_map(|p| p.to_array()).collect() };
    let pos = g.floats("VEC3", &flat(&scene.positions));
    let nrm = g.floats("VEC3", &flat(&scene.normals));
    let mut primitives = Vec::new();
    for m in 0..scene.materials.len() {
        let idx: Vec<u32> = scene
            .triangles
            .iter()
            .zip(&scene.tri_material)
            .filter(|&(_, &tm)| tm as usize == m)
            .flat_map(|(t, _)| *t)
            .collect();
        if idx.is_empty() {
            continue;
        }
        let acc = g.indices(&idx);
        primitives.push(json!({
            "attributes": {"POSITION": pos, "NORMAL": nrm},
            "indices": acc,
            "material": m,
        }));
    }
    let materials: Vec<_> = scene
        .materials
        .iter()
        .map(|m| {
            let c = m.base_color;
            json!({"pbrMetallicRoughness": {"baseColorFactor": [c.x, c.y, c.z, 1.0]}})
        })
        .collect();
    let doc = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [scale, scale, scale], "translation": translation}],
        "meshes": [{"primitives": primitives}],
        "materials": materials,
    });
    g.write_glb(dir, name, doc)
}

/// Frame `frame` of the model's auto-framed turntable (or spin) under the studio map: 200×150,
/// 100 lights, the default method, two threads.
fn render(model: &Path, spin: bool, frame: usize) -> Film {
    let flags = AnimFlags {
        lights: LightsLayer {
            count: Some(100),
            ..Default::default()
        },
        render: RenderLayer {
            width: Some(200),
            height: Some(150),
            spp: Some(1),
            ..Default::default()
        },
        ..Default::default()
    };
    let env = common::asset("studio_small_03_1k.hdr");
    let mut anim = Animation::of_model(model, Some(&env), &flags).unwrap();
    if spin {
        let orbit = &anim.motion.segments()[0];
        anim.motion = Motion::single(MotionKind::Spin, orbit.frames.end, orbit.degrees_per_frame);
    }
    let inputs = Inputs::load(&anim).unwrap();
    let pool = thread_pool(2).unwrap();
    let (film, _) = pool
        .install(|| render_frame(&anim, &inputs, frame, None, &Silent))
        .unwrap();
    film
}

/// RMSE of `a` against `b` over all pixels and channels, over the mean of `b`.
fn rel_rmse(a: &Film, b: &Film) -> f64 {
    let (mut se, mut sum, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for (x, y) in a
        .layer(Channel::BEAUTY)
        .unwrap()
        .iter()
        .zip(&b.layer(Channel::BEAUTY).unwrap())
    {
        for c in 0..3 {
            let d = f64::from(x[c]) - f64::from(y[c]);
            se += d * d;
            sum += f64::from(y[c]);
            n += 1.0;
        }
    }
    (se / n).sqrt() / (sum / n)
}

#[test]
fn the_same_scene_at_any_scale_or_place_renders_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = Scene::load(&common::asset("bunny_on_plane.glb")).unwrap();
    let base = write_scene(&bunny, dir.path(), "unit", 1.0, [0.0; 3]);
    let mut failures = Failures::new();
    for spin in [false, true] {
        let frame = if spin { 5 } else { 0 };
        let want = render(&base, spin, frame);
        let want_pct = want.counts.percent_traced();
        assert!(want_pct > 1.0 && want_pct < 50.0, "{want_pct}");
        for (scale, shift) in [
            (1e-4, 0.0),
            (1e-2, 0.0),
            (1e2, 0.0),
            (1e4, 0.0),
            (1.0, 1e6),
            (1e-2, 1e6),
        ] {
            let name = format!("s{scale:e}-t{shift:e}");
            let moved = write_scene(&bunny, dir.path(), &name, scale, [shift, 0.0, -shift]);
            let case = format!(
                "{} scale {scale:e}, moved {shift:e}",
                if spin { "spin" } else { "orbit" }
            );
            failures.case(&case, || {
                let got = render(&moved, spin, frame);
                let pct = got.counts.percent_traced();
                let rel = rel_rmse(&got, &want);
                eprintln!(
                    "{case}: {pct:.4} % traced (unscaled {want_pct:.4} %), relative RMSE {rel:.2e}"
                );
                assert!(
                    (pct - want_pct).abs() <= 0.01 * want_pct,
                    "{pct:.4} % traced against {want_pct:.4} %"
                );
                assert!(
                    rel <= 1e-3,
                    "relative RMSE {rel:.2e} against the unscaled render"
                );
            });
        }
    }
    failures.assert_none();
}

#[test]
fn far_scenes_keep_their_shape_and_report_world_positions() {
    // Moved 10⁶ by its node, the scene's coordinates are the unmoved scene's (the render origin
    // takes the move off in f64: equal but for f64's rounding of the move, 2⁻³³ here, where f32
    // world coordinates would be 2⁻⁴ apart), and the file's bounds say where it is.
    let dir = tempfile::tempdir().unwrap();
    let bunny = Scene::load(&common::asset("bunny_on_plane.glb")).unwrap();
    let unit = Scene::load(&write_scene(&bunny, dir.path(), "u", 1.0, [0.0; 3])).unwrap();
    let far = Scene::load(&write_scene(&bunny, dir.path(), "f", 1.0, [1e6, 0.0, -1e6])).unwrap();
    assert_eq!(unit.origin, glam::DVec3::ZERO);
    assert_eq!(far.origin, glam::DVec3::new(1e6, 0.0, -1e6));
    assert_eq!(far.positions.len(), unit.positions.len());
    for (k, (a, b)) in far.positions.iter().zip(&unit.positions).enumerate() {
        assert!(
            (*a - *b).abs().max_element() <= 2e-10,
            "vertex {k}: {a} vs {b}"
        );
    }
    let p = glam::Vec3::new(0.5, 0.25, -0.125);
    assert_eq!(
        far.to_world(p),
        glam::Vec3::new(1e6 + 0.5, 0.25, -1e6 - 0.125)
    );
    assert_eq!(far.to_local(far.to_world(p)), p);
}
