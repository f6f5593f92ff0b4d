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

use envshadow::anim::{AnimFlags, Animation};
use envshadow::coordinator::thread_pool;
use envshadow::film::{Channel, Counts, Film};
use envshadow::frame::{Temporal, render_frame, render_frame_with};
use envshadow::history::Carried;
use envshadow::inputs::Inputs;
use envshadow::run::Silent;
use envshadow::scene::Scene;
use envshadow::tile::Rect;

use crate::common::{self, require_tools};

/// A model, one of its animations and the times compared.
struct Case {
    file: &'static str,
    animation: usize,
    times: &'static [f64],
}

/// Every case: the samplers file's two animations (every sampler kind; STEP and LINEAR
/// between keys), Khronos's InterpolationTest (its nine animations, one per sampler kind and
/// path: STEP, and LINEAR translation and scale, between keys; CUBICSPLINE and LINEAR
/// rotations at keys), SimpleSkin, RiggedSimple (a two-joint skin whose rotations are
/// LINEAR: compared at its keys), AnimatedMorphCube (two morph targets on positions, normals
/// and tangents, LINEAR weights: between keys) and Fox (a skinned character, two of its three
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
        file: "InterpolationTest.glb",
        animation: 0, // Step Scale (keys at 1/24, 5/12, 7/8, 5/4, 5/3 s)
        times: &[0.0, 0.2, 0.6, 1.0, 1.5, 2.0],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 1, // Linear Scale
        times: &[0.0, 0.2, 0.6, 1.1, 1.5],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 2, // CubicSpline Scale: at its keys
        times: &[
            0.0416666679084301,
            0.4166666567325592,
            0.875,
            1.25,
            1.6666666269302368,
        ],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 3, // Step Rotation (keys at 0, 5/12, 7/8, 5/4, 41/24 s)
        times: &[0.2, 0.6, 1.0, 1.5, 1.8],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 4, // CubicSpline Rotation: at its keys
        times: &[0.0, 0.4166666567325592, 0.875, 1.25, 1.7083333730697632],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 5, // Linear Rotation: at its keys
        times: &[0.0, 0.4166666567325592, 0.875, 1.25, 1.7083333730697632],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 6, // Step Translation (keys at 0, 11/24, 5/6, 31/24, 41/24 s)
        times: &[0.2, 0.6, 1.0, 1.5, 1.8],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 7, // CubicSpline Translation: at its keys
        times: &[
            0.0,
            0.4166666567325592,
            0.8333333134651184,
            1.25,
            1.6666666269302368,
        ],
    },
    Case {
        file: "InterpolationTest.glb",
        animation: 8, // Linear Translation
        times: &[0.1, 0.3, 0.7, 1.0, 1.4],
    },
    Case {
        file: "SimpleSkin.gltf",
        animation: 0,
        times: &[1.0, 2.5],
    },
    Case {
        file: "RiggedSimple.glb",
        animation: 0,
        // Its three keys (24 fps frames 1, 25 and 50), as the file's f32 times.
        times: &[0.04166661947965622, 1.0416669845581055, 2.083333015441895],
    },
    Case {
        file: "AnimatedMorphCube.glb",
        animation: 0,
        times: &[0.0, 0.55, 1.3, 2.02, 3.7],
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
    // Where our rest pose lies from each of Blender's poses: some pose must move the model
    // well past the tolerance, or the case could not tell playback from none.
    let rest: Vec<[f64; 3]> = scene
        .positions
        .iter()
        .map(|p| (p.as_dvec3() + scene.origin).to_array())
        .collect();
    let moved = theirs
        .iter()
        .map(|(_, b)| farthest_from(&rest, b).max(farthest_from(b, &rest)) / size)
        .fold(0.0, f64::max);
    assert!(
        moved > 1e-2,
        "{} animation {}: no pose moves the model from its rest ({moved:.2e})",
        case.file,
        case.animation
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

/// A spec playing `file`'s animation (`animation`, `end`) at `fps` over `frames` frames of a
/// still camera (or `motion`), small and validated.
fn spec(file: &str, motion: &str, frames: usize, scene_keys: &str, fps: u32) -> Animation {
    let text = format!(
        "[scene]\nfile = \"{}\"\n{scene_keys}\n[lights]\ncount = 24\n\
         [motion]\nkind = \"{motion}\"\nframes = {frames}\n\
         [render]\nwidth = 64\nheight = 48\nvalidate = true\n[output]\nfps = {fps}\n",
        data(file).display()
    );
    Animation::parse(&text, Path::new("anim.toml"), &AnimFlags::default()).unwrap()
}

fn film(anim: &Animation, inputs: &Inputs, frame: usize) -> Film {
    render_frame(anim, inputs, frame, None, &Silent).unwrap().0
}

#[test]
fn frames_past_the_end_loop_or_hold() {
    // samplers.gltf's animation is 2 s long; at 4 fps frame 8 is its end, frame 9 is 2.25 s.
    let looped = spec("samplers.gltf", "none", 12, "animation_end = \"loop\"", 4);
    let inputs = Inputs::load(&looped).unwrap();
    common::assert_same_film(&film(&looped, &inputs, 9), &film(&looped, &inputs, 1));
    let held = spec("samplers.gltf", "none", 12, "animation_end = \"hold\"", 4);
    let inputs = Inputs::load(&held).unwrap();
    common::assert_same_film(&film(&held, &inputs, 9), &film(&held, &inputs, 8));
    // And the animation does play: frame 1 is not frame 0.
    let (a, b) = (film(&held, &inputs, 0), film(&held, &inputs, 1));
    assert!(a.layer(Channel::BEAUTY) != b.layer(Channel::BEAUTY));
}

#[test]
fn frames_past_the_end_are_refused_under_stop() {
    let stop = spec("samplers.gltf", "none", 12, "animation_end = \"stop\"", 4);
    let err = format!("{:#}", Inputs::load(&stop).err().unwrap());
    assert!(
        err.contains("frame 9 is at 2.2500 s, past the end of the animation (2.0000 s long")
            && err.contains("the last frame it covers is 8"),
        "{err}"
    );
    // Frames within it render.
    let mut within = stop.clone();
    within.frames = envshadow::frames::FrameSet::range(0..9);
    assert!(Inputs::load(&within).is_ok());
}

#[test]
fn an_animation_the_file_lacks_is_refused_naming_those_it_has() {
    let walk = spec("Fox.glb", "none", 2, "animation = \"Trot\"", 24);
    let err = format!("{:#}", Inputs::load(&walk).err().unwrap());
    assert!(
        err.contains("no animation named \"Trot\" (its animations: 0: Survey, 1: Walk, 2: Run)"),
        "{err}"
    );
    let index = spec("Fox.glb", "none", 2, "animation = 3", 24);
    let err = format!("{:#}", Inputs::load(&index).err().unwrap());
    assert!(err.contains("no animation 3"), "{err}");
    // A file without animations plays none by default, and refuses a named one.
    let bunny = common::asset("bunny.glb");
    let text = format!(
        "[scene]\nfile = \"{}\"\nanimation = \"Walk\"\n",
        bunny.display()
    );
    let a = Animation::parse(&text, Path::new("b.toml"), &AnimFlags::default()).unwrap();
    let err = format!("{:#}", Inputs::load(&a).err().unwrap());
    assert!(err.contains("(it has none)"), "{err}");
}

#[test]
fn the_camera_frames_every_pose_not_the_rest_pose() {
    // The samplers file's first animation moves the step cube, scales the cubic cube and
    // bends the bar: the frame's bounds hold every frame's posed model.
    let anim = spec("samplers.gltf", "orbit", 12, "ground = \"none\"", 6);
    let inputs = Inputs::load(&anim).unwrap();
    let (lo, hi) = inputs.scene.model_bounds();
    let rest = {
        let mut s = inputs.scene.clone();
        s.framing = None;
        s.model_bounds()
    };
    assert_ne!((lo, hi), rest, "the poses reach beyond the rest pose");
    let slack = (hi - lo).length() * 1e-6;
    for frame in 0..anim.frame_count {
        let posed = inputs.posed(&anim, frame, None).unwrap().unwrap();
        for p in &posed.positions {
            assert!(
                p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
                "frame {frame}: {p} outside the framed bounds {lo}..{hi}"
            );
        }
    }
}

#[test]
fn the_ground_lies_under_every_pose_not_the_rest_pose() {
    // The running fox reaches below its rest pose: the ground added under it lies at the
    // lowest point of any frame's pose, so no paw sinks into it.
    let anim = spec(
        "Fox.glb",
        "none",
        24,
        "animation = \"Run\"\nground = \"always\"",
        24,
    );
    let inputs = Inputs::load(&anim).unwrap();
    let scene = &inputs.scene;
    let first = scene.added_ground.expect("a ground was added");
    let ground: Vec<f32> = scene.triangles[first..]
        .iter()
        .flatten()
        .map(|&i| scene.positions[i as usize].y)
        .collect();
    let level = ground[0];
    assert!(ground.iter().all(|&y| y == level), "the ground is flat");
    let lowest = |s: &Scene| {
        s.model_triangles()
            .iter()
            .flatten()
            .map(|&i| s.positions[i as usize].y)
            .fold(f32::INFINITY, f32::min)
    };
    let posed = (0..anim.frame_count)
        .map(|f| lowest(&inputs.posed(&anim, f, None).unwrap().unwrap()))
        .fold(f32::INFINITY, f32::min);
    let rest = lowest(scene);
    let size = {
        let (lo, hi) = scene.model_bounds();
        (hi - lo).length()
    };
    assert!(
        posed < rest - 1e-3 * size,
        "the run reaches below the rest pose ({posed} vs {rest})"
    );
    assert_eq!(level, posed, "the ground lies at the lowest posed point");
}

/// The text of [`spec`]'s spec, written to `dir` for the commands that read a spec file.
fn spec_file(dir: &Path, file: &str, scene_keys: &str) -> PathBuf {
    let text = format!(
        "[scene]\nfile = \"{}\"\n{scene_keys}\n[lights]\ncount = 24\n\
         [motion]\nkind = \"orbit\"\nframes = 12\n\
         [render]\nwidth = 64\nheight = 48\nspp = 1\n[output]\nfps = 24\n",
        data(file).display()
    );
    let path = dir.join("anim.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn export_writes_the_frames_pose_as_a_render_poses_it() {
    // The walking fox's frame 5: scene.ply holds the posed scene a render of that frame
    // traces (Inputs::posed), not the rest pose.
    let dir = tempfile::tempdir().unwrap();
    let spec = spec_file(dir.path(), "Fox.glb", "animation = \"Walk\"");
    let out = dir.path().join("exp");
    let mut flags = AnimFlags::default();
    flags.output.dir = Some(out.clone());
    let args = envshadow::export::ExportArgs {
        spec: spec.clone(),
        frame: 5,
        flags,
    };
    envshadow::export::run(&args).unwrap();
    let anim = Animation::load(&spec, &AnimFlags::default()).unwrap();
    let inputs = Inputs::load(&anim).unwrap();
    let want = inputs.posed(&anim, 5, None).unwrap().unwrap();
    assert_ne!(want.positions, inputs.scene.positions, "the frame is posed");
    let (ply, start, _) = common::read_ply(&out.join("scene.ply"));
    // 11 floats per vertex, the position first.
    let got: Vec<glam::Vec3> = (0..want.positions.len())
        .map(|v| {
            let f = |k: usize| {
                let at = start + v * 44 + 4 * k;
                f32::from_le_bytes(ply[at..at + 4].try_into().unwrap())
            };
            glam::Vec3::new(f(0), f(1), f(2))
        })
        .collect();
    assert_eq!(got, want.positions);
}

/// `envshadow bench`'s rows for frame 5 of `spec` (one thread, one repeat).
fn bench_rows(spec: &Path) -> Vec<envshadow::bench::BenchRow> {
    use clap::Parser;
    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        bench: envshadow::bench::BenchArgs,
    }
    let spec = spec.to_str().unwrap();
    let cli = Cli::parse_from(
        ["bench", "--scene", spec, "--frame", "5", "--repeat", "1"]
            .into_iter()
            .chain(["--threads", "1"]),
    );
    envshadow::bench::measure(&cli.bench, |_| {}).unwrap()
}

#[test]
fn bench_times_the_frames_pose_as_a_render_poses_it() {
    // Under an orbiting camera the walking fox is posed every frame: bench reports each frame
    // as building its own posed scene and BVH (its split's build column), as render_frame
    // does; the fox at rest shares the run's one BVH.
    let dir = tempfile::tempdir().unwrap();
    let walking = bench_rows(&spec_file(dir.path(), "Fox.glb", "animation = \"Walk\""));
    assert!(!walking.is_empty());
    for r in &walking {
        assert!(
            r.build_in_frame,
            "{}: the posed frame builds its BVH",
            r.variant.label
        );
        assert!(r.split.is_some());
    }
    let still = bench_rows(&spec_file(dir.path(), "Fox.glb", "animation = \"none\""));
    assert!(still.iter().all(|r| !r.build_in_frame));
}

#[test]
fn a_pose_rebuilds_only_the_hierarchy_of_the_triangles_the_animation_moves() {
    // The walking fox on its added ground: every pose shares the ground's hierarchy and
    // rebuilds the fox's alone (issue 41), and the split answers as a whole build would.
    let anim = spec("Fox.glb", "orbit", 12, "animation = \"Walk\"", 24);
    let inputs = Inputs::load(&anim).unwrap();
    let moving: usize = inputs.animated_triangles().iter().map(|r| r.len()).sum();
    let total = inputs.scene.triangle_count();
    assert!(0 < moving && moving < total, "{moving} of {total} move");
    for frame in [3, 7] {
        let posed = inputs.posed(&anim, frame, None).unwrap().expect("posed");
        let accel = inputs.posed_accel(&posed, false);
        assert_eq!(
            (accel.built_triangles(), accel.triangle_count()),
            (moving, total)
        );
        let whole = posed.accel();
        let camera = anim.camera(&inputs.scene, frame).unwrap();
        let o = camera.position;
        for (x, y) in (0..camera.height).flat_map(|y| (0..camera.width).map(move |x| (x, y))) {
            let d = camera.ray_dir(x, y);
            let hit = accel.intersect(o, d);
            assert_eq!(hit, whole.intersect(o, d), "frame {frame} pixel ({x}, {y})");
            // And a shadow ray from the hit, straight up.
            if let Some(h) = hit {
                let p = o + d * (h.t * 0.999);
                assert_eq!(
                    accel.occluded(p, glam::Vec3::Y),
                    whole.occluded(p, glam::Vec3::Y)
                );
            }
        }
    }
    // A spin moves every triangle: its frames build the whole.
    let posed = inputs.posed(&anim, 3, None).unwrap().expect("posed");
    assert_eq!(inputs.posed_accel(&posed, true).built_triangles(), total);
}

#[test]
fn an_animated_frame_is_identical_whatever_the_tiles_and_threads() {
    // The fox walking under an orbiting camera: the frame's posed scene and BVH are built per
    // frame, and neither the tiles nor the threads change a bit; nor does a region render.
    let anim = spec("Fox.glb", "orbit", 12, "animation = \"Walk\"", 24);
    let inputs = Inputs::load(&anim).unwrap();
    let render = |tile: u32, threads: usize, region: Option<Rect>| {
        let mut a = anim.clone();
        a.render.tile = tile;
        let pool = thread_pool(threads).unwrap();
        pool.install(|| render_frame(&a, &inputs, 5, region, &Silent))
            .unwrap()
            .0
    };
    let want = render(16, 1, None);
    for (tile, threads) in [(8, 2), (64, 2), (24, 3)] {
        common::assert_same_film(&render(tile, threads, None), &want);
    }
    // A region render's pixels are the whole frame's.
    let region = Rect {
        x0: 16,
        y0: 8,
        x1: 48,
        y1: 40,
    };
    let part = render(16, 2, Some(region));
    let (w, whole) = (64usize, want.layer(Channel::BEAUTY).unwrap());
    let got = part.layer(Channel::BEAUTY).unwrap();
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let i = y as usize * w + x as usize;
            assert_eq!(got[i], whole[i], "pixel ({x}, {y})");
        }
    }
}

#[test]
fn a_deforming_frame_reads_the_previous_frame_only_where_nothing_moved_across() {
    // With --temporal, the walking fox's frames read the previous frame on the still ground,
    // except the pairs whose rays may cross where the fox was or is (src/moved.rs): they trace
    // fewer rays than the frames rendered alone, and their wrong pairs against brute force stay
    // within the acceptance's 0.05 % of the queries above the frame alone's (at this size and
    // 24 lights the spatial method alone misses 0.2 %; at 640×480 both are under 0.01 %,
    // docs/temporal.md).
    let mut anim = spec("Fox.glb", "orbit", 12, "animation = \"Walk\"", 24);
    anim.render.width = 160;
    anim.render.height = 120;
    let inputs = Inputs::load(&anim).unwrap();
    let alone: Vec<_> = (0..4)
        .map(|f| render_frame(&anim, &inputs, f, None, &Silent).unwrap().1)
        .collect();
    anim.render.temporal = true;
    let mut prev: Option<Carried> = None;
    let (mut rays, mut rays_alone) = (0, 0);
    for (f, want) in alone.iter().enumerate() {
        let link = Temporal {
            prev: prev.as_ref(),
            carry: true,
            no_validate: false,
        };
        let (_, stats, carried) =
            render_frame_with(&anim, &inputs, f, None, &Silent, &link).unwrap();
        let c = stats.counts;
        if f == 0 {
            // The chain's first frame has no previous frame: as alone.
            assert_eq!(c, want.counts);
        } else {
            assert!(c.temporal_pixels > 0, "frame {f} reads the previous frame");
            assert!(
                c.temporal_stale > 0,
                "frame {f}: pairs the fox moved across dropped"
            );
            rays += c.rays;
            rays_alone += want.counts.rays;
        }
        let wrong = (c.wrong_visible + c.wrong_blocked) as f64;
        let alone = (want.counts.wrong_visible + want.counts.wrong_blocked) as f64;
        assert!(
            wrong <= alone + 5e-4 * c.queries as f64,
            "frame {f}: {wrong} wrong pairs of {} ({alone} alone)",
            c.queries
        );
        prev = carried;
    }
    assert!(
        rays < rays_alone,
        "{rays} rays with --temporal, {rays_alone} without"
    );
}

/// Renders `frames` of `anim` as one `--temporal` chain on the current thread pool; returns
/// each frame's counts.
fn chain_counts(anim: &Animation, inputs: &Inputs, frames: std::ops::Range<usize>) -> Vec<Counts> {
    let mut prev: Option<Carried> = None;
    let mut out = Vec::new();
    for f in frames {
        let link = Temporal {
            prev: prev.as_ref(),
            carry: true,
            no_validate: false,
        };
        let (_, stats, carried) = render_frame_with(anim, inputs, f, None, &Silent, &link).unwrap();
        out.push(stats.counts);
        prev = carried;
    }
    out
}

#[test]
fn a_held_pose_drops_no_previous_pair_whatever_the_threads_rendered_before() {
    // Walk is 0.708 s long: at 24 fps frames 17 on hold its last pose, so frames 30 and 31 show
    // one pose and frame 31 reads frame 30 as a still scene's: every pair may vote, none is
    // dropped. The grid's coarse levels are evaluated once per frame and copied into the tiles
    // (src/lattice.rs), which once lost the dropped-pair count: a copied pixel showed what the
    // thread's buffers held from an earlier deforming frame (tens of pairs "dropped" on a
    // held frame, only after the walking fox had been rendered on the same threads).
    let mut held = spec(
        "Fox.glb",
        "none",
        40,
        "animation = \"Walk\"\nanimation_end = \"hold\"",
        24,
    );
    held.render.temporal = true;
    let inputs = Inputs::load(&held).unwrap();
    let fresh = thread_pool(1)
        .unwrap()
        .install(|| chain_counts(&held, &inputs, 30..32));
    // The same frames on a thread that rendered the walking fox first.
    let mut walking = spec("Fox.glb", "orbit", 12, "animation = \"Walk\"", 24);
    walking.render.temporal = true;
    // Another size: the copied pixels fall where its tiles' own pixels were.
    walking.render.width = 160;
    walking.render.height = 120;
    let walking_inputs = Inputs::load(&walking).unwrap();
    let after = thread_pool(2).unwrap().install(|| {
        let moving = chain_counts(&walking, &walking_inputs, 0..3);
        assert!(
            moving[1..].iter().all(|c| c.temporal_stale > 0),
            "the walking fox drops pairs"
        );
        chain_counts(&held, &inputs, 30..32)
    });
    let c = &fresh[1];
    assert!(
        c.temporal_pixels > 0,
        "the held pose reads the previous frame"
    );
    assert_eq!(c.temporal_stale, 0, "no pair dropped on a held pose");
    assert!(c.rays < fresh[0].rays, "reading it saves rays");
    assert_eq!(
        after, fresh,
        "what the threads rendered before changes nothing"
    );
}

#[test]
fn the_pairs_a_deforming_frame_drops_are_counted_alike_whatever_the_tiles_and_threads() {
    // The dropped pairs of the grid's coarse levels, evaluated once per frame, are counted by
    // the tiles they are copied into: as the frame's other counts, they do not depend on
    // which tile or thread evaluated them (they once showed what the thread's buffers held).
    let mut anim = spec("Fox.glb", "orbit", 12, "animation = \"Walk\"", 24);
    anim.render.temporal = true;
    anim.render.width = 96;
    anim.render.height = 72;
    let inputs = Inputs::load(&anim).unwrap();
    // The halo's counts are the tiles' own (their extra work), the others the frame's.
    let counts = |tile: u32, threads: usize| {
        let mut a = anim.clone();
        a.render.tile = tile;
        let mut c = thread_pool(threads)
            .unwrap()
            .install(|| chain_counts(&a, &inputs, 0..3));
        for c in &mut c {
            (c.halo_pixels, c.halo_rays) = (0, 0);
        }
        c
    };
    let want = counts(16, 1);
    assert!(want[1..].iter().all(|c| c.temporal_stale > 0), "{want:?}");
    for (tile, threads) in [(32, 2), (24, 3), (96, 1)] {
        assert_eq!(
            counts(tile, threads),
            want,
            "tile {tile}, {threads} threads"
        );
    }
}

#[test]
fn a_z_up_file_poses_stood_up() {
    // `[scene] up = "z"` turns the loaded scene; its poses turn the same way.
    let file = Scene::load(&data("samplers.gltf")).unwrap();
    let stood = file.clone().stood_up(envshadow::scene::Up::Z);
    for t in [0.25, 1.2] {
        let want = file
            .rig
            .as_ref()
            .unwrap()
            .posed(&file, 0, t)
            .stood_up(envshadow::scene::Up::Z);
        let got = stood.rig.as_ref().unwrap().posed(&stood, 0, t);
        for (g, w) in got.positions.iter().zip(&want.positions) {
            assert!((*g - *w).length() < 1e-6, "at {t} s: {g} vs {w}");
        }
        assert_ne!(got.positions, stood.positions, "the pose moved something");
    }
}
