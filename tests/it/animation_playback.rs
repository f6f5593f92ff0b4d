//! Playback of a glTF file's own animation (node channels, skins, morph targets): our posed
//! vertices against Blender's evaluation of the same file and time.
//!
//! Blender (Debian's 3.4, its glTF importer, `frame_set`, the evaluated meshes; see
//! scripts/blender-pose.py) is the independent side. Its importer is exact for `STEP` and
//! `LINEAR` translation, scale and weights at any time, but it turns `CUBICSPLINE` into Bézier
//! curves with automatic handles (the file's tangents dropped) and interpolates rotations
//! component-wise rather than by slerp: where an animation has those, we compare at its key
//! times, where both are exact. Between keys, the samplers are checked against the
//! specification's formulas by the unit tests of src/scene/clip.rs.
//!
//! The vertices are compared as sets (Blender's importer merges and splits vertices): every
//! vertex of ours lies within 1e-4 of the model's size of one of Blender's, and every one of
//! Blender's of one of ours. Blender's answers are also kept in tests/data/gltf-anim/*.blender.json
//! (remade by `scripts/blender-pose.py`, the command in each case below), so the comparison
//! runs without Blender too; with Blender installed (CI installs it) it runs live as well.

use std::path::{Path, PathBuf};

use envshadow::scene::Scene;

use crate::common::require_tools;

/// A model, one of its animations and the times compared.
struct Case {
    file: &'static str,
    animation: usize,
    times: &'static [f64],
}

/// Every case: the samplers file's two animations (every sampler kind; STEP and LINEAR
/// between keys), Khronos's SimpleSkin and Fox (a skinned character, two of its three
/// animations).
const CASES: &[Case] = &[
    Case {
        file: "samplers.gltf",
        animation: 0,
        times: &[0.0, 0.5, 1.5, 2.0],
    },
    Case {
        file: "samplers.gltf",
        animation: 1,
        times: &[0.3, 0.8, 1.7, 2.5],
    },
    Case {
        file: "SimpleSkin.gltf",
        animation: 0,
        times: &[1.0, 2.5],
    },
    Case {
        file: "Fox.glb",
        animation: 0,
        times: &[0.0, 1.0, 2.5],
    },
    Case {
        file: "Fox.glb",
        animation: 2,
        times: &[0.5],
    },
];

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf-anim")
        .join(name)
}

/// The stored Blender answer for a case.
fn reference(case: &Case) -> PathBuf {
    data(&format!("{}.a{}.blender.json", case.file, case.animation))
}

/// Our vertices of `scene` posed at time `t` of `animation`, in world space.
fn ours(scene: &Scene, animation: usize, t: f64) -> Vec<[f64; 3]> {
    let rig = scene.rig.as_ref().expect("the file has a rig");
    let posed = rig.posed(scene, animation, t);
    posed
        .positions
        .iter()
        .map(|p| {
            let w = p.as_dvec3() + scene.origin;
            [w.x, w.y, w.z]
        })
        .collect()
}

/// Blender's poses from its JSON: one vertex list per time.
fn poses(json: &str) -> Vec<(f64, Vec<[f64; 3]>)> {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v["poses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let vertices = p["vertices"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| {
                    let c = x.as_array().unwrap();
                    [0, 1, 2].map(|k| c[k].as_f64().unwrap())
                })
                .collect();
            (p["time"].as_f64().unwrap(), vertices)
        })
        .collect()
}

/// The farthest any point of `a` lies from its nearest point of `b`.
fn farthest_from(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .map(|p| {
            b.iter()
                .map(|q| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>())
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        })
        .fold(0.0, f64::max)
}

/// The model's size: its rest pose's bounding-box diagonal.
fn size(scene: &Scene) -> f64 {
    let (lo, hi) = scene.bounds();
    f64::from((hi - lo).length())
}

/// Compares each time of `case` with Blender's answer `json`; returns the worst distance
/// over the model's size, and fails naming the case and time past 1e-4.
fn compare(case: &Case, json: &str) -> f64 {
    let scene = Scene::load(&data(case.file)).unwrap();
    let size = size(&scene);
    let theirs = poses(json);
    assert_eq!(
        theirs.iter().map(|p| p.0).collect::<Vec<_>>(),
        case.times,
        "{}: Blender's answer holds other times",
        case.file
    );
    let mut worst = 0.0f64;
    for (t, blender) in &theirs {
        let ours = ours(&scene, case.animation, *t);
        let d = farthest_from(&ours, blender).max(farthest_from(blender, &ours)) / size;
        assert!(
            d <= 1e-4,
            "{} animation {} at {t} s: a vertex lies {d:.2e} of the model's size from the other side's nearest",
            case.file,
            case.animation
        );
        worst = worst.max(d);
    }
    worst
}

/// Runs scripts/blender-pose.py on a case; its JSON.
fn blender(case: &Case, out: &Path) -> String {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/blender-pose.py");
    let mut cmd = std::process::Command::new("blender");
    cmd.args(["-b", "--factory-startup", "--python-exit-code", "1", "-P"])
        .arg(&script)
        .arg("--")
        .arg(data(case.file))
        .arg(out)
        .args(["--animation", &case.animation.to_string()])
        .args(case.times.iter().map(|t| t.to_string()));
    let run = cmd.output().expect("blender runs");
    assert!(
        run.status.success(),
        "blender failed on {}: {}",
        case.file,
        String::from_utf8_lossy(&run.stderr)
    );
    std::fs::read_to_string(out).unwrap()
}

#[test]
fn posed_vertices_match_blenders_stored_answers() {
    for case in CASES {
        let json = std::fs::read_to_string(reference(case)).unwrap();
        let worst = compare(case, &json);
        eprintln!(
            "{} animation {}: worst {worst:.2e} of the model's size",
            case.file, case.animation
        );
    }
}

#[test]
fn posed_vertices_match_blender() {
    if !require_tools(
        "posed_vertices_match_blender",
        &["blender"],
        "apt-get install blender python3-numpy",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (k, case) in CASES.iter().enumerate() {
        let json = blender(case, &dir.path().join(format!("{k}.json")));
        let worst = compare(case, &json);
        eprintln!(
            "{} animation {} (Blender now): worst {worst:.2e} of the model's size",
            case.file, case.animation
        );
    }
}

#[test]
fn skins_and_default_weights_shape_the_rest_pose() {
    // The samplers file's morph cube has default weights (0.25, 0): target 0 lifts its top
    // face by 0.5, so at rest the top stands at 0.25 + 0.125 above the node (y = 0.5).
    let scene = Scene::load(&data("samplers.gltf")).unwrap();
    let part = scene
        .parts
        .iter()
        .find(|p| p.node.as_deref() == Some("morph cube"))
        .unwrap();
    let top = scene.triangles[part.triangles.clone()]
        .iter()
        .flatten()
        .map(|&i| scene.positions[i as usize].y)
        .fold(f32::MIN, f32::max);
    assert!((top - 0.875).abs() < 1e-6, "top at {top}");
}
