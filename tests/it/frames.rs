//! Frame lists (`--frames 1,3`, `1-10:2`, issue 22 item 7): a list renders exactly the frames
//! it names, each with the bits the same frame has in a render of every frame — also with
//! `--temporal`, where a frame's predecessor must be rendered first, through `--resume`, and
//! split into farm jobs.

use std::fs;
use std::path::{Path, PathBuf};

use envshadow::output::stats::read_stats;

use crate::common;

/// The shapes turntable, 12 frames of 64×48 with 30 lights, writing into `dir/out`.
fn spec(dir: &Path) -> PathBuf {
    let spec = dir.join("anim.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 30\n[motion]\nframes = 12\n\
         [render]\nwidth = 64\nheight = 48\ntile = 16\n",
    )
    .unwrap();
    spec
}

/// `envshadow render SPEC --out OUT --no-report FLAGS…`; its stderr.
fn render(spec: &Path, out: &Path, flags: &[&str]) -> String {
    let o = common::bin()
        .arg("render")
        .arg(spec)
        .arg("--out")
        .arg(out)
        .arg("--no-report")
        .args(flags)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{flags:?}: {err}");
    err
}

fn envshadow(args: &[&str]) {
    let o = common::bin().args(args).output().unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The frame numbers of the frame files in `dir`.
fn frames_in(dir: &Path) -> Vec<usize> {
    let mut v: Vec<usize> = common::file_names(dir)
        .iter()
        .filter_map(|n| n.strip_prefix("frame_")?.strip_suffix(".exr")?.parse().ok())
        .collect();
    v.sort();
    v
}

/// Frames `frames` of `a` and `b` are the same files, and their stats.csv rows agree but for
/// the seconds.
fn same_frames(a: &Path, b: &Path, frames: &[usize]) {
    for f in frames {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            assert!(
                fs::read(a.join(&name)).unwrap() == fs::read(b.join(&name)).unwrap(),
                "{name} differs between {} and {}",
                a.display(),
                b.display()
            );
        }
    }
    let rows = |d: &Path| {
        let mut r = read_stats(&d.join("stats.csv")).unwrap();
        r.retain(|s| frames.contains(&s.frame));
        for s in &mut r {
            s.thread_seconds = 0.0;
        }
        r
    };
    assert_eq!(rows(a), rows(b));
}

#[test]
fn a_frame_list_renders_only_its_frames_with_the_bits_of_a_range() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let (whole, list) = (tmp.path().join("whole"), tmp.path().join("list"));
    render(&spec, &whole, &["--frames", "0..4", "-q"]);
    let log = render(&spec, &list, &["--frames", "1,3"]);
    assert_eq!(frames_in(&list), [1, 3]);
    assert!(log.contains("rendering 2 frames"), "{log}");
    same_frames(&whole, &list, &[1, 3]);
    let rows: Vec<usize> = read_stats(&list.join("stats.csv"))
        .unwrap()
        .iter()
        .map(|r| r.frame)
        .collect();
    assert_eq!(rows, [1, 3]);
    // Blender's forms: inclusive dashes and steps.
    let stepped = tmp.path().join("stepped");
    render(&spec, &stepped, &["--frames", "0-2:2,3", "-q"]);
    assert_eq!(frames_in(&stepped), [0, 2, 3]);
    same_frames(&whole, &stepped, &[0, 2, 3]);
}

/// With `--temporal` a frame reads its predecessor's carried data. A list that skips a
/// frame still gets its frames as a run of every frame has them: the frames between the
/// chain's key frame and each listed frame are rendered, not written (`temporal::chains`), so
/// frame 3 is predicted from frame 2 whether 2 was asked for or not. A later `--resume` of
/// the whole range fills in the rest with the same bits.
#[test]
fn a_temporal_frame_list_has_the_bits_of_a_whole_run_and_resumes() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let (whole, list) = (tmp.path().join("whole"), tmp.path().join("list"));
    let temporal = ["--temporal", "--keyframe", "4"];
    let with = |frames: &'static str| {
        let mut v = vec!["--frames", frames];
        v.extend_from_slice(&temporal);
        v
    };
    render(&spec, &whole, &with("0-6"));
    let log = render(&spec, &list, &with("1,3,6"));
    assert_eq!(frames_in(&list), [1, 3, 6]);
    // Chains 0..4 and 4..8: frames 0 and 2, then 4 and 5, rendered to warm them up.
    assert!(log.contains("temporal: 4 frame(s) not asked for"), "{log}");
    same_frames(&whole, &list, &[1, 3, 6]);
    // The temporal prediction did happen in the listed frames (not a restarted chain).
    let row3 = read_stats(&list.join("stats.csv"))
        .unwrap()
        .into_iter()
        .find(|r| r.frame == 3)
        .unwrap();
    assert!(row3.counts.temporal_pixels > 0, "{row3:?}");
    let log = render(
        &spec,
        &list,
        &with("0-6")
            .into_iter()
            .chain(["--resume"])
            .collect::<Vec<_>>(),
    );
    assert!(log.contains("4 frames rendered, 3 skipped"), "{log}");
    same_frames(&whole, &list, &[0, 1, 2, 3, 4, 5, 6]);
}

/// A list split into farm jobs (by frames: whole temporal groups per job) assembles into the
/// frames one process writes for the same list.
#[test]
fn farm_jobs_of_a_frame_list_assemble_into_the_one_process_render() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let (one, farm) = (tmp.path().join("one"), tmp.path().join("farm"));
    let flags = ["--frames", "1,3,6-9:3", "--temporal", "--keyframe", "4"];
    render(&spec, &one, &[&flags[..], &["-q"]].concat());
    let (s, o) = (spec.to_str().unwrap(), farm.to_str().unwrap());
    envshadow(&[&["plan", s, "--out", o, "--jobs", "3", "-q"][..], &flags].concat());
    let lines = fs::read_to_string(farm.join("jobs.txt")).unwrap();
    let frames: Vec<&str> = lines
        .lines()
        .map(|l| l.split('\t').nth(1).unwrap())
        .collect();
    assert_eq!(frames, ["1,3", "6", "9"], "{lines}");
    for k in ["0", "1", "2"] {
        let job = ["render", s, "--out", o, "--job", k, "--of", "3", "-q"];
        envshadow(&[&job[..], &flags].concat());
    }
    envshadow(&["assemble", o, "--no-report", "-q"]);
    assert_eq!(frames_in(&farm), [1, 3, 6, 9]);
    same_frames(&one, &farm, &[1, 3, 6, 9]);
}
