//! A file's own animation through jobs (issue 41, item 4): every process poses the scene and
//! builds its BVH for each frame it renders, and with `--temporal` a chain's warm-up frames
//! pose again the frames they carry forward; tiles, threads, job processes and GNU parallel
//! must still assemble into the one-process render byte for byte.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use envshadow::output::stats::{FrameStats, read_stats};

use crate::common;
use crate::farm::{envshadow, ok};

const BIN: &str = env!("CARGO_BIN_EXE_envshadow");
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The walking fox under an orbiting camera, small: 80×60 at 4 samples per pixel in tiles of
/// 16, 24 lights, 8 frames.
fn write_spec(dir: &Path) -> PathBuf {
    let fox = Path::new(ROOT).join("tests/data/gltf-anim/Fox.glb");
    let text = format!(
        "[scene]\nfile = \"{}\"\nanimation = \"Walk\"\n[lights]\ncount = 24\n\
         [motion]\nkind = \"orbit\"\nframes = 8\n\
         [render]\nwidth = 80\nheight = 60\nspp = 4\ntile = 16\n[output]\nfps = 24\n",
        fox.display()
    );
    let spec = dir.join("fox.toml");
    fs::write(&spec, text).unwrap();
    spec
}

/// A one-process render of `spec` into `out` with `flags`.
fn render(spec: &Path, out: &Path, flags: &[&str]) {
    let mut args = vec![
        "render",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--no-report",
        "-q",
    ];
    args.extend_from_slice(flags);
    ok(&envshadow(&args));
}

/// Every frame file of `frames` in `want` exists in `got` with the same bytes.
fn assert_same_frames(want: &Path, got: &Path, frames: std::ops::Range<usize>) {
    for f in frames {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            let a = fs::read(want.join(&name)).unwrap();
            let b = fs::read(got.join(&name))
                .unwrap_or_else(|e| panic!("{}: {e}", got.join(&name).display()));
            assert!(a == b, "{name} differs from the one-process render");
        }
    }
}

/// stats.csv's rows with the seconds zeroed (a timing) and without the halo's work (the one
/// count that depends on the tiles).
fn stats_without_seconds(dir: &Path) -> Vec<FrameStats> {
    let mut rows = read_stats(&dir.join("stats.csv")).unwrap();
    for r in &mut rows {
        r.thread_seconds = 0.0;
        r.counts = common::without_halo(r.counts);
    }
    rows
}

#[test]
fn an_animated_frame_is_identical_whatever_the_tiles_threads_and_processes() {
    // The reference: one process, one thread, tiles of 32. The jobs: three processes, each
    // rendering a strip of tiles of 16 on its own number of threads, assembled.
    let tmp = tempfile::tempdir().unwrap();
    let spec = write_spec(tmp.path());
    let (refdir, out) = (tmp.path().join("ref"), tmp.path().join("jobs"));
    render(
        &spec,
        &refdir,
        &["--frames", "3..5", "--tile", "32", "--threads", "1"],
    );
    let (s, o) = (spec.to_str().unwrap(), out.to_str().unwrap());
    let flags = ["--frames", "3..5"];
    let mut plan = vec!["plan", s, "--out", o, "--jobs", "3", "--by", "tiles"];
    plan.extend_from_slice(&flags);
    ok(&envshadow(&plan));
    for (k, threads) in [("0", "2"), ("1", "1"), ("2", "3")] {
        let mut job = vec![
            "render",
            s,
            "--out",
            o,
            "--job",
            k,
            "--of",
            "3",
            "--by",
            "tiles",
            "--threads",
            threads,
            "-q",
        ];
        job.extend_from_slice(&flags);
        ok(&envshadow(&job));
    }
    ok(&envshadow(&["assemble", o, "--no-report"]));
    assert_same_frames(&refdir, &out, 3..5);
    assert_eq!(stats_without_seconds(&refdir), stats_without_seconds(&out));
}

#[test]
fn a_farm_run_of_an_animated_model_equals_one_process() {
    // GNU parallel runs the plan's jobs at once, as scripts/farm.sh does on each host; with
    // --temporal every job starts on a key frame, and a run starting inside a chain renders
    // its warm-up frames again (posing the frames it carries forward).
    if !common::require_tools(
        common::this_test!(),
        &["parallel"],
        "apt-get install parallel",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let spec = write_spec(tmp.path());
    let s = spec.to_str().unwrap();
    let flags = ["--frames", "0..8", "--temporal", "--keyframe", "4"];
    let refdir = tmp.path().join("ref");
    render(&spec, &refdir, &flags);
    let out = tmp.path().join("farm");
    let o = out.to_str().unwrap();
    let mut plan = vec!["plan", s, "--out", o, "--jobs", "2"];
    plan.extend_from_slice(&flags);
    ok(&envshadow(&plan));
    let mut job = vec![
        "-j",
        "2",
        "--halt",
        "now,fail=1",
        BIN,
        "render",
        s,
        "--out",
        o,
        "--job",
        "{}",
        "--of",
        "2",
        "--threads",
        "1",
        "-q",
    ];
    job.extend_from_slice(&flags);
    job.extend_from_slice(&[":::", "0", "1"]);
    let ran = Command::new("parallel")
        .args(&job)
        .current_dir(ROOT)
        .env("PARALLEL_HOME", tmp.path().join("parallel-home"))
        .output()
        .expect("running GNU parallel");
    ok(&ran);
    ok(&envshadow(&["assemble", o, "--no-report"]));
    assert_same_frames(&refdir, &out, 0..8);
    assert_eq!(stats_without_seconds(&refdir), stats_without_seconds(&out));
    // Frames 2..8 alone: 2 and 3 read warm-up frames 0 and 1, rendered again here.
    let late = tmp.path().join("late");
    render(
        &spec,
        &late,
        &["--frames", "2..8", "--temporal", "--keyframe", "4"],
    );
    assert_same_frames(&refdir, &late, 2..8);
    // The animated frames did read their predecessors.
    let rows = stats_without_seconds(&refdir);
    assert!(
        rows.iter()
            .filter(|r| r.frame % 4 != 0)
            .all(|r| r.counts.temporal_pixels > 0),
        "{rows:?}"
    );
}
