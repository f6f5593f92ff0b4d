//! Temporal prediction (`--temporal`, issue 10): against brute force, independent of tiles,
//! threads and how the animation is split into jobs, and falling back to the spatial method
//! where there is no previous frame.

use crate::common::{self, Failures};

use std::path::Path;

use envshadow::anim::{AnimFlags, Animation};
use envshadow::coordinator::{render_animation, thread_pool};
use envshadow::film::Counts;
use envshadow::film::{Channel, Film};
use envshadow::frame::Temporal;
use envshadow::frame::{render_frame, render_frame_with};
use envshadow::frame_files::FrameFiles;
use envshadow::history::Carried;
use envshadow::inputs::Inputs;
use envshadow::output::stats::read_stats;
use envshadow::predict::FloodTo;
use envshadow::run::{RunOptions, Silent};

/// A small bunny animation: `kind` = orbit, spin or environment, 3° per frame, validated,
/// temporal.
fn bunny(kind: &str, width: u32, height: u32, lights: usize, out: &Path) -> Animation {
    let text = bunny_spec(kind, width, height, lights, out);
    Animation::parse(&text, Path::new("bunny.toml"), &AnimFlags::default()).unwrap()
}

/// [`bunny`]'s spec text.
fn bunny_spec(kind: &str, width: u32, height: u32, lights: usize, out: &Path) -> String {
    format!(
        "[scene]\nfile = \"{}\"\n[environment]\nfile = \"{}\"\n[lights]\ncount = {lights}\n\
         [camera]\ntarget = [0.0, 0.075, 0.0]\ndistance = 0.45\nelevation = 25.0\n\
         [motion]\nkind = \"{kind}\"\nframes = 12\ndegrees_per_frame = 3.0\n\
         [render]\nwidth = {width}\nheight = {height}\nvalidate = true\ntemporal = true\n\
         keyframe = 4\n[output]\ndir = \"{}\"\n",
        common::asset("bunny_on_plane.glb").display(),
        common::asset("studio_small_03_1k.hdr").display(),
        out.display()
    )
}

/// Renders frames `0..n` as one chain (frame 0 spatial, each later frame reading the one
/// before) with `tile` and `threads`; returns each frame's film and counts.
fn chain(
    anim: &Animation,
    inputs: &Inputs,
    n: usize,
    tile: u32,
    threads: usize,
) -> Vec<(Film, Counts)> {
    let mut a = anim.clone();
    a.render.tile = tile;
    let pool = thread_pool(threads).unwrap();
    let mut prev: Option<Carried> = None;
    let mut out = Vec::new();
    for f in 0..n {
        let link = Temporal {
            prev: prev.as_ref(),
            carry: true,
            no_validate: false,
        };
        let (film, stats, carried) = pool
            .install(|| render_frame_with(&a, inputs, f, None, &Silent, &link))
            .unwrap();
        prev = carried;
        out.push((film, stats.counts));
    }
    out
}

/// Stated bound on wrong (pixel, light) pairs with temporal prediction at 160×120, in % of
/// queries: as for the spatial method at this size (predict.rs), with room for the
/// errors a chain carries forward.
const ERROR_BOUND: f64 = 0.25;

#[test]
fn temporal_prediction_agrees_with_brute_force_within_its_stated_error() {
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for kind in ["orbit", "spin", "environment"] {
        let anim = bunny(kind, 160, 120, 100, dir.path());
        let inputs = Inputs::load(&anim).unwrap();
        let frames = chain(&anim, &inputs, 4, 32, 0);
        for (f, (film, c)) in frames.iter().enumerate() {
            failures.case(&format!("{kind} frame {f}"), || {
                // Where it traced, it agrees with brute force exactly.
                assert_eq!(c.wrong_traced, 0, "wrong where traced");
                let err = c.error_percent();
                assert!(err <= ERROR_BOUND, "{err:.4} % wrong pairs");
                if f == 0 {
                    assert_eq!(c.temporal_pixels, 0, "the first frame is spatial");
                } else {
                    // Almost every surface pixel was seen in the previous frame.
                    let hit = film
                        .plane(Channel::Visible)
                        .unwrap()
                        .iter()
                        .filter(|&&v| v > 0.0)
                        .count() as u64;
                    assert!(
                        c.temporal_pixels * 10 >= hit * 8,
                        "only {} of ~{hit} pixels predicted temporally",
                        c.temporal_pixels
                    );
                    assert!(c.temporal_rays <= c.rays, "more temporal rays than rays");
                }
                // Pixels without a wrong pair equal the brute-force image exactly.
                let wrong = film.plane(Channel::Wrong).unwrap();
                let reference = film.layer(Channel::REFERENCE).unwrap();
                for (i, w) in wrong.iter().enumerate() {
                    if *w == 0.0 {
                        assert_eq!(film.beauty(i), reference[i], "pixel {i}");
                    }
                }
            });
        }
    }
    failures.assert_none();
}

/// A turning environment (issue 22, item 3) at the size the acceptance figures are measured
/// at (640×480, 200 lights, 3° per frame): a whole chain of the default key-frame interval,
/// each frame against brute force within 0.05 % wrong pairs, tracing less than 70 % of what
/// the spatial method traces for the same frame (54–55 % on this map when written; 62–63 %
/// since every traced light floods, which found thin occluders between two lights).
#[test]
fn environment_turntable_agrees_with_brute_force_within_0_05_percent() {
    let dir = tempfile::tempdir().unwrap();
    let text = bunny_spec("environment", 640, 480, 200, dir.path()).replace("keyframe = 4\n", "");
    let anim = Animation::parse(&text, Path::new("bunny.toml"), &AnimFlags::default()).unwrap();
    assert_eq!(
        anim.render.keyframe, 8,
        "the environment's default key-frame interval"
    );
    let inputs = Inputs::load(&anim).unwrap();
    let n = anim.render.keyframe as usize;
    let frames = chain(&anim, &inputs, n, 64, 0);
    let mut spatial = anim.clone();
    spatial.render.temporal = false;
    spatial.render.validate = false;
    let mut failures = Failures::new();
    for (f, (_, c)) in frames.iter().enumerate() {
        failures.case(&format!("frame {f}"), || {
            assert_eq!(c.wrong_traced, 0, "wrong where traced");
            let err = c.error_percent();
            assert!(err <= 0.05, "{err:.4} % wrong pairs");
            if f > 0 {
                let (_, s) = render_frame(&spatial, &inputs, f, None, &Silent).unwrap();
                let share = c.rays as f64 / s.counts.rays as f64;
                assert!(
                    c.temporal_pixels > 0 && share < 0.7,
                    "{:.1} % of the spatial rays",
                    share * 100.0
                );
            }
        });
    }
    failures.assert_none();
}

#[test]
fn temporal_chains_are_identical_whatever_the_tiles_and_threads() {
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for (kind, flood_to, method) in [
        ("orbit", FloodTo::All, "grid-nowarp-uncertainty"),
        ("spin", FloodTo::ContraryFinest, "grid-nowarp-uncertainty"),
        ("orbit", FloodTo::Contrary, "grid-nowarp-uncertainty"),
        ("spin", FloodTo::ContraryFinest, "scan-nowarp-uncertainty"),
        (
            "environment",
            FloodTo::ContraryFinest,
            "grid-nowarp-uncertainty",
        ),
        ("environment", FloodTo::All, "scan-nowarp-uncertainty"),
    ] {
        let mut anim = bunny(kind, 96, 72, 48, dir.path());
        anim.render.flood_to = flood_to;
        anim.render.method = method.parse().unwrap();
        let inputs = Inputs::load(&anim).unwrap();
        let reference = chain(&anim, &inputs, 3, 0, 1);
        for (tile, threads) in [(8, 2), (16, 1), (64, 2)] {
            let got = chain(&anim, &inputs, 3, tile, threads);
            for (f, ((film, c), (rf, rc))) in got.iter().zip(&reference).enumerate() {
                let tag =
                    format!("{method} {kind} {flood_to} frame {f} tile {tile} threads {threads}");
                failures.check(
                    film.layer(Channel::BEAUTY).unwrap() == rf.layer(Channel::BEAUTY).unwrap(),
                    || format!("{tag}: beauty differs"),
                );
                failures.check(
                    film.plane(Channel::Rays).unwrap() == rf.plane(Channel::Rays).unwrap(),
                    || format!("{tag}: rays differ"),
                );
                failures.check(
                    film.plane(Channel::Wrong) == rf.plane(Channel::Wrong),
                    || format!("{tag}: wrong pairs differ"),
                );
                failures.check_eq(common::without_halo(*c), common::without_halo(*rc), || {
                    format!("{tag}: counts")
                });
            }
        }
    }
    failures.assert_none();
}

#[test]
fn without_a_previous_frame_the_spatial_method_decides() {
    let dir = tempfile::tempdir().unwrap();
    let anim = bunny("orbit", 96, 72, 48, dir.path());
    let inputs = Inputs::load(&anim).unwrap();
    let mut spatial = anim.clone();
    spatial.render.temporal = false;
    // Frame 2 with no previous frame given (a chain's first frame) is the spatial frame.
    let none = Temporal::default();
    let (t, ts, _) = render_frame_with(&anim, &inputs, 2, None, &Silent, &none).unwrap();
    let (s, ss, _) = render_frame_with(&spatial, &inputs, 2, None, &Silent, &none).unwrap();
    assert!(
        t.layer(Channel::BEAUTY).unwrap() == s.layer(Channel::BEAUTY).unwrap()
            && t.plane(Channel::Rays).unwrap() == s.plane(Channel::Rays).unwrap()
    );
    assert_eq!(ts.counts, ss.counts);
    assert_eq!(ts.counts.temporal_pixels, 0);
}

fn files(dir: &Path, frames: std::ops::Range<usize>) -> Vec<Vec<u8>> {
    frames
        .flat_map(|f| {
            ["exr", "png"]
                .map(|ext| std::fs::read(dir.join(format!("frame_{f:04}.{ext}"))).unwrap())
        })
        .collect()
}

#[test]
fn one_job_and_split_jobs_write_identical_frames() {
    let root = tempfile::tempdir().unwrap();
    let (one, split) = (root.path().join("one"), root.path().join("split"));
    let mut anim = bunny("spin", 64, 48, 32, &one);
    anim.render.validate = false;
    anim.frames = (0..7).into();
    render_animation(
        &anim,
        &RunOptions::default(),
        &mut FrameFiles::new(&anim, &RunOptions::default()),
        &Silent,
    )
    .unwrap();
    // Two jobs split in the middle of a chain (key frames 0 and 4): the second warms up from
    // frame 0 without writing frames 0 and 1.
    anim.output.dir = split.clone();
    for range in [0..2, 2..7] {
        anim.frames = range.into();
        render_animation(
            &anim,
            &RunOptions::default(),
            &mut FrameFiles::new(&anim, &RunOptions::default()),
            &Silent,
        )
        .unwrap();
    }
    assert!(files(&one, 0..7) == files(&split, 0..7));
    assert_eq!(anim.frame_alignment(), 4);
    // The warm-up frames were not written by the second job: stats rows come from both.
    let rows = read_stats(&split.join("stats.csv")).unwrap();
    let frames: Vec<usize> = rows.iter().map(|r| r.frame).collect();
    assert_eq!(frames, (0..7).collect::<Vec<_>>());
}

#[test]
fn temporal_flags_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("t.toml");
    std::fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let mut failures = Failures::new();
    for (args, needle) in [
        (
            vec!["--temporal", "--method", "brute"],
            "--temporal true does not apply to brute",
        ),
        (
            vec!["--temporal", "--keyframe", "10001"],
            "--keyframe 10001: must be",
        ),
        (
            vec!["--keyframe", "8"],
            "--keyframe applies only with temporal",
        ),
        (vec!["--temporal", "--region", "0,0,8,8"], "--region"),
    ] {
        let o = common::bin()
            .arg("render")
            .arg(&spec)
            .args(&args)
            .arg("--out")
            .arg(&out)
            .arg("-q")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        failures.check_eq(o.status.code(), Some(2), || format!("{args:?}: exit code"));
        failures.check(err.contains(needle), || {
            format!("{args:?}: {needle:?} not in {err}")
        });
        failures.check_eq(err.trim().lines().count(), 1, || {
            format!("{args:?}: lines of {err}")
        });
    }
    failures.assert_none();
}

#[test]
fn savings_plot_compares_two_renders() {
    let root = tempfile::tempdir().unwrap();
    let (with, without) = (root.path().join("t"), root.path().join("s"));
    let mut anim = bunny("orbit", 64, 48, 32, &with);
    anim.render.validate = false;
    anim.frames = (0..3).into();
    render_animation(
        &anim,
        &RunOptions::default(),
        &mut FrameFiles::new(&anim, &RunOptions::default()),
        &Silent,
    )
    .unwrap();
    anim.render.temporal = false;
    anim.output.dir = without.clone();
    render_animation(
        &anim,
        &RunOptions::default(),
        &mut FrameFiles::new(&anim, &RunOptions::default()),
        &Silent,
    )
    .unwrap();
    let s = envshadow::savings::write_savings(&with, &without, None).unwrap();
    assert_eq!(s.png, with.join("savings.png"));
    assert_eq!(s.frames.len(), 3);
    // The key frame is the same spatial frame in both; later frames trace fewer rays.
    assert_eq!(s.frames[0].1, s.frames[0].2);
    assert!(s.frames[1..].iter().all(|r| r.1 < r.2), "{:?}", s.frames);
    let img = image::open(&s.png).unwrap();
    assert_eq!((img.width(), img.height()), (800, 360));
    // A folder without stats.csv is bad input naming the file.
    let e = envshadow::savings::write_savings(&with, root.path(), None).unwrap_err();
    assert!(format!("{e:#}").contains("stats.csv"), "{e:#}");
}
