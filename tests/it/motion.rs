//! Motions (issue 22, item 3): the environment turning around a still scene, sequences of
//! motions in one spec (`[[motion]]`), and the bad sequences refused.

use crate::common::{self, Failures};

use std::path::Path;

use envshadow::anim::{AnimFlags, Animation, MotionKind};
use envshadow::coordinator::render_animation;
use envshadow::film::Channel;
use envshadow::frame::render_frame;
use envshadow::frame_files::FrameFiles;
use envshadow::inputs::Inputs;
use envshadow::output::stats::read_stats;
use envshadow::run::{RunOptions, Silent};

/// The bunny under `motion` (TOML text of the motion tables), 3° per frame unless said.
fn bunny(motion: &str, width: u32, height: u32, lights: usize, out: &Path) -> Animation {
    let text = format!(
        "[scene]\nfile = \"{}\"\n[environment]\nfile = \"{}\"\n[lights]\ncount = {lights}\n\
         [camera]\ntarget = [0.0, 0.075, 0.0]\ndistance = 0.45\nelevation = 25.0\n\
         {motion}\n[render]\nwidth = {width}\nheight = {height}\n[output]\ndir = \"{}\"\n",
        common::asset("bunny_on_plane.glb").display(),
        common::asset("studio_small_03_1k.hdr").display(),
        out.display()
    );
    Animation::parse(&text, Path::new("bunny.toml"), &AnimFlags::default()).unwrap()
}

/// The background turns with the lights: a frame of a turning environment shows behind the
/// model what a still frame with `[environment] rotation` turned as far shows (to rounding:
/// the two turns are applied one after the other instead of at once), and not what the
/// unturned frame shows.
#[test]
fn a_turning_environment_turns_the_background_with_the_lights() {
    let dir = tempfile::tempdir().unwrap();
    let turning = "[motion]\nkind = \"environment\"\nframes = 4\ndegrees_per_frame = 30.0";
    let mut anim = bunny(turning, 96, 72, 16, dir.path());
    anim.render.method = "brute".parse().unwrap();
    let inputs = Inputs::load(&anim).unwrap();
    let (turned, _) = render_frame(&anim, &inputs, 2, None, &Silent).unwrap();
    let (unturned, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let mut still = bunny(
        "[motion]\nkind = \"none\"\nframes = 1",
        96,
        72,
        16,
        dir.path(),
    );
    still.env_rotation_deg = 60.0;
    still.render.method = anim.render.method;
    let still_inputs = Inputs::load(&still).unwrap();
    let (rotated, _) = render_frame(&still, &still_inputs, 0, None, &Silent).unwrap();
    // Brute force traces every light at every surface pixel: no rays, no surface.
    let background: Vec<usize> = (0..turned.plane(Channel::Rays).unwrap().len())
        .filter(|&i| turned.plane(Channel::Rays).unwrap()[i] == 0.0)
        .collect();
    assert!(
        background.len() > 500,
        "{} background pixels",
        background.len()
    );
    let (mut moved, mut worst) = (0, 0.0f32);
    for &i in &background {
        assert_eq!(
            rotated.plane(Channel::Rays).unwrap()[i],
            0.0,
            "pixel {i} is background in both"
        );
        for c in 0..3 {
            let (a, b) = (turned.beauty(i)[c], rotated.beauty(i)[c]);
            worst = worst.max((a - b).abs() / b.abs().max(1e-3));
            if (turned.beauty(i)[c] - unturned.beauty(i)[c]).abs() > 0.01 * b.abs() {
                moved += 1;
            }
        }
    }
    assert!(
        worst < 1e-3,
        "background differs from the rotated map's by {worst}"
    );
    assert!(
        moved * 2 > background.len(),
        "only {moved} background values changed"
    );
    // The lights turned too (the model is lit from elsewhere), the geometry did not.
    assert_ne!(
        turned.layer(Channel::BEAUTY).unwrap(),
        unturned.layer(Channel::BEAUTY).unwrap()
    );
    let (a, b) = (inputs.lights_at(&anim, 0), inputs.lights_at(&anim, 2));
    let d = a.lights[0].dir;
    let (s, c) = (60f32.to_radians().sin(), 60f32.to_radians().cos());
    let want = glam::Vec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c);
    assert!((b.lights[0].dir - want).length() < 1e-5);
}

/// "The model spins, then the light turns around it": each motion's first frame starts a
/// temporal chain (its frames predicted from their own pixels; the environment's chain is
/// 8 frames long, so 4 is its only key frame here), the frames after it read
/// their predecessor, every frame within the stated error; rendered as one job or as jobs
/// split inside the chains, the same files.
#[test]
fn a_sequence_of_motions_renders_as_one_job_or_split() {
    let root = tempfile::tempdir().unwrap();
    let (one, split) = (root.path().join("one"), root.path().join("split"));
    let sequence = "[[motion]]\nkind = \"spin\"\nframes = \"0-3\"\nturn_degrees = 12.0\n\
                    [[motion]]\nkind = \"environment\"\nframes = \"4-9\"\ndegrees_per_frame = 3.0\n";
    let mut anim = bunny(sequence, 96, 72, 48, &one);
    anim.render.temporal = true;
    anim.render.validate = true;
    anim = anim.with_render(&Default::default()).unwrap();
    assert_eq!(anim.frame_count, 10);
    assert_eq!(anim.motion.kind_at(3), MotionKind::Spin);
    assert_eq!(anim.motion.kind_at(4), MotionKind::Environment);
    // The model stays where the spin left it while the light turns.
    let target = envshadow::anim::Pivot {
        target: glam::Vec3::new(0.0, 0.075, 0.0),
        origin: glam::DVec3::ZERO,
    };
    assert_eq!(
        anim.scene_transform(4, target),
        anim.scene_transform(9, target)
    );
    assert_ne!(
        anim.scene_transform(3, target),
        anim.scene_transform(4, target)
    );
    assert_eq!(anim.motion.environment_degrees(3), None);
    assert_eq!(anim.motion.environment_degrees(9), Some(15.0));
    let options = RunOptions::default();
    render_animation(
        &anim,
        &options,
        &mut FrameFiles::new(&anim, &options),
        &Silent,
    )
    .unwrap();
    let rows = read_stats(&one.join("stats.csv")).unwrap();
    let mut failures = Failures::new();
    for r in &rows {
        let key = [0, 4].contains(&r.frame);
        let t = r.counts.temporal_pixels;
        failures.check(key == (t == 0), || {
            format!("frame {}: {t} temporal pixels", r.frame)
        });
        let err = r.counts.error_percent();
        failures.check(err <= 0.25, || {
            format!("frame {}: {err} % wrong pairs", r.frame)
        });
    }
    failures.assert_none();
    // Jobs starting inside the spin's chain and inside the environment's.
    anim.output.dir = split.clone();
    anim.render.validate = false;
    let mut plain = anim.clone();
    plain.output.dir = one.join("plain");
    plain.frames = (0..10).into();
    render_animation(
        &plain,
        &options,
        &mut FrameFiles::new(&plain, &options),
        &Silent,
    )
    .unwrap();
    for range in [0..3, 3..6, 6..10] {
        anim.frames = range.into();
        render_animation(
            &anim,
            &options,
            &mut FrameFiles::new(&anim, &options),
            &Silent,
        )
        .unwrap();
    }
    for f in 0..10 {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            let (a, b) = (
                std::fs::read(plain.output.dir.join(&name)).unwrap(),
                std::fs::read(split.join(&name)).unwrap(),
            );
            assert!(a == b, "{name} differs");
        }
    }
    assert_eq!(anim.frame_alignment(), 4);
}

/// A spec with one `[motion]` table keeps its settings record (resumed folders rendered
/// before sequences existed still match), and the environment kind has its own.
#[test]
fn one_motion_table_keeps_its_settings_record() {
    let dir = tempfile::tempdir().unwrap();
    for (motion, wants) in [
        (
            "[motion]\nkind = \"spin\"\nframes = 8\ndegrees_per_frame = 3.0",
            &[
                "[motion] kind = spin\n",
                "[motion] frames = 8\n",
                "[motion] degrees_per_frame = 3\n",
                "[motion] pivot = auto\n",
            ][..],
        ),
        (
            "[[motion]]\nframes = 2\n[[motion]]\nkind = \"environment\"\nframes = 2\n",
            &[
                "[[motion]] 1 kind = orbit\n",
                "[[motion]] 2 kind = environment\n",
                "[[motion]] 2 frames = 2-3\n",
            ][..],
        ),
    ] {
        let lines = bunny(motion, 32, 24, 8, dir.path())
            .settings_record()
            .unwrap()
            .text();
        for want in wants {
            assert!(lines.contains(want), "{want:?} not in\n{lines}");
        }
    }
}

/// Bad motions are refused before anything is written: exit 2, one line naming the spec and
/// the motion and key.
#[test]
fn bad_motion_sequences_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for (motion, needle) in [
        (
            "[[motion]]\nkind = \"spin\"\nframes = \"0-71\"\n[[motion]]\nkind = \"environment\"\nframes = \"70-143\"\n",
            "[[motion]] 2 frames = \"70-143\" overlaps [[motion]] 1 (frames 0-71)",
        ),
        (
            "[[motion]]\nframes = \"0-71\"\n[[motion]]\nframes = \"80-143\"\n",
            "[[motion]] 2 frames = \"80-143\" leaves frames 72-79 without a motion",
        ),
        (
            "[[motion]]\nframes = 4\n[[motion]]\nkind = \"hdri\"\nframes = 4\n",
            "[[motion]] 2 kind = \"hdri\": expected \"orbit\", \"spin\", \"environment\" or \"none\"",
        ),
        (
            "[motion]\nkind = \"sun\"\nframes = 4\n",
            "[motion] kind = \"sun\": expected",
        ),
        (
            "[[motion]]\nframes = 4\n[[motion]]\nframes = 4\nturns = 2\n",
            "turns",
        ),
        (
            "[[motion]]\nframes = \"4\"\n",
            "[[motion]] 1 frames = \"4\" leaves frames 0-3 without a motion",
        ),
        ("[[motion]]\nframes = -3\n", "frames"),
        (
            "[[motion]]\nkind = \"environment\"\nframes = 4\npivot = [0.0, 0.0, 0.0]\n",
            "[[motion]] 1 pivot applies only to kind = \"spin\"",
        ),
        (
            "[[motion]]\nkind = \"environment\"\nframes = 4\ndegrees_per_frame = nan\n",
            "[[motion]] 1 degrees_per_frame = NaN is not a finite number",
        ),
        (
            "[[motion]]\nframes = 4\n[[motion]]\nframes = \"4-100000000\"\n",
            "[[motion]] 2 frames: the animation would have",
        ),
    ] {
        let spec = dir.path().join("seq.toml");
        let out = dir.path().join("out");
        std::fs::write(
            &spec,
            format!("[scene]\nbuiltin = \"shapes\"\n{motion}[render]\nwidth = 16\nheight = 12\n"),
        )
        .unwrap();
        let o = common::bin()
            .arg("render")
            .arg(&spec)
            .arg("--out")
            .arg(&out)
            .arg("-q")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        failures.check_eq(o.status.code(), Some(2), || {
            format!("{motion:?}: exit code ({err})")
        });
        failures.check(err.contains(needle) && err.contains("seq.toml"), || {
            format!("{motion:?}: {needle:?} not in {err}")
        });
        failures.check_eq(err.trim().lines().count(), 1, || {
            format!("{motion:?}: lines of {err}")
        });
        failures.check(!out.exists(), || {
            format!("{motion:?}: {} was created", out.display())
        });
    }
    failures.assert_none();
}

/// The default turntable of a model (`envshadow render model.glb`) frames the cylinder the
/// model sweeps as it turns: every vertex of the model stays inside the frame at every angle,
/// and the model fills most of it at its widest (a bounding sphere left a long, flat model
/// such as the toy plane at half the frame).
#[test]
fn the_default_turntable_keeps_the_turning_model_in_frame_and_fills_it() {
    let mut failures = Failures::new();
    for (model, least_fill) in [
        // 0.50 with the bounding sphere; 0.72 as the turning cylinder.
        ("corpus/toy_plane.glb", 0.65),
        ("corpus/lion_statue.glb", 0.6),
        ("bunny.glb", 0.6),
    ] {
        failures.case(model, || {
            let path = common::asset(model);
            let anim = Animation::of_model(&path, None, &AnimFlags::default()).unwrap();
            let inputs = Inputs::load(&anim).unwrap();
            let scene = &inputs.scene;
            let (w, h) = (anim.render.width as f32, anim.render.height as f32);
            let frames = anim.motion.segments()[0].frames.clone();
            let mut widest = 0.0f32;
            for frame in frames.step_by(3) {
                let cam = anim.camera(scene, frame).unwrap();
                let (mut lo, mut hi) = ((f32::MAX, f32::MAX), (f32::MIN, f32::MIN));
                for &v in scene.model_triangles().iter().flatten() {
                    let (x, y) = cam
                        .project(scene.positions[v as usize])
                        .expect("a vertex behind the camera");
                    lo = (lo.0.min(x), lo.1.min(y));
                    hi = (hi.0.max(x), hi.1.max(y));
                }
                assert!(
                    lo.0 >= 0.0 && lo.1 >= 0.0 && hi.0 <= w && hi.1 <= h,
                    "frame {frame}: the model spans ({lo:?})–({hi:?}) of {w}×{h}"
                );
                widest = widest.max(((hi.0 - lo.0) / w).max((hi.1 - lo.1) / h));
            }
            assert!(
                widest >= least_fill,
                "at its widest the model fills {widest:.2} of the frame (want ≥ {least_fill})"
            );
        });
    }
    failures.assert_none();
}
