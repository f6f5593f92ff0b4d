//! Frame names and numbers as a compositor's pipeline wants them (issue 40): Blender's `#`
//! output pattern, a start frame number in the names and the EXR header, and frame rates
//! stored exactly (29.97 is 30000/1001); everything that finds a folder's frames by name
//! (resume, the report, the video, the farm's assembly) follows the pattern.

use std::fs;
use std::path::Path;
use std::process::Output;

use envshadow::output::exr::{ReadFrame, read_frame};
use exr::meta::attribute::{AttributeValue, Text};

use crate::common;

const SPEC: &str = "anims/shapes-turntable.toml";
/// Tiny frames of the shapes turntable.
const TINY: &[&str] = &["--width", "32", "--height", "24", "--lights", "20"];

/// `envshadow render SPEC TINY EXTRA --out OUT -q`, frames 0 and 1 unless `extra` says.
fn render(out: &Path, extra: &[&str]) -> Output {
    let frames: &[&str] = if extra.contains(&"--frames") {
        &[]
    } else {
        &["--frames", "0-1"]
    };
    common::bin()
        .arg("render")
        .arg(SPEC)
        .args(TINY)
        .args(frames)
        .args(extra)
        .args(["-q", "--out"])
        .arg(out)
        .output()
        .unwrap()
}

#[track_caller]
fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}\nstderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The frame files (`.exr`, `.png`) in `dir`, sorted.
fn frame_files(dir: &Path) -> Vec<String> {
    common::file_names(dir)
        .into_iter()
        .filter(|n| n.ends_with(".exr") || n.ends_with(".png"))
        .collect()
}

fn header_i32(frame: &ReadFrame, name: &str) -> Option<i32> {
    match frame.attributes.other.get(&Text::from(name)) {
        Some(AttributeValue::I32(v)) => Some(*v),
        _ => None,
    }
}

/// `--output-pattern turntable_####` names both files of every frame so (and nothing
/// `frame_NNNN`), and the report links the frames by those names.
#[test]
fn the_output_pattern_names_the_exr_and_png_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    ok(&render(&out, &["--output-pattern", "turntable_####"]));
    assert_eq!(
        frame_files(&out),
        [
            "turntable_0000.exr",
            "turntable_0000.png",
            "turntable_0001.exr",
            "turntable_0001.png"
        ]
    );
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("href=\"turntable_0001.png\""), "{html}");
    assert!(
        !html.contains("frame_0001.png"),
        "the report links frame_NNNN"
    );
    // Without #, four digits are appended, as Blender does.
    let plain = tmp.path().join("plain");
    ok(&render(
        &plain,
        &["--output-pattern", "beauty.", "--no-report"],
    ));
    assert_eq!(
        frame_files(&plain),
        [
            "beauty.0000.exr",
            "beauty.0000.png",
            "beauty.0001.exr",
            "beauty.0001.png"
        ]
    );
}

/// `--frame-start 1001`: frame index 0 is number 1001 in its file names and in the EXR's
/// `envshadow/frame`; a spec's `frame_start = 1` numbers from 1, as Blender does.
#[test]
fn the_start_frame_numbers_the_names_and_the_exr_header() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    ok(&render(
        &out,
        &[
            "--output-pattern",
            "shot_###_beauty",
            "--frame-start",
            "1001",
            "--no-report",
        ],
    ));
    assert_eq!(
        frame_files(&out),
        [
            "shot_1001_beauty.exr",
            "shot_1001_beauty.png",
            "shot_1002_beauty.exr",
            "shot_1002_beauty.png"
        ]
    );
    for (name, number) in [
        ("shot_1001_beauty.exr", 1001),
        ("shot_1002_beauty.exr", 1002),
    ] {
        let f = read_frame(&out.join(name)).unwrap();
        assert_eq!(header_i32(&f, "envshadow/frame"), Some(number), "{name}");
    }
    // From a spec: Blender's numbering.
    let spec = tmp.path().join("blender.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[motion]\nframes = 2\n[output]\nframe_start = 1\n",
    )
    .unwrap();
    let numbered = tmp.path().join("numbered");
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args([
            "--width",
            "32",
            "--height",
            "24",
            "--lights",
            "20",
            "-q",
            "--no-report",
        ])
        .arg("--out")
        .arg(&numbered)
        .output()
        .unwrap();
    ok(&o);
    assert_eq!(
        frame_files(&numbered),
        [
            "frame_0001.exr",
            "frame_0001.png",
            "frame_0002.exr",
            "frame_0002.png"
        ]
    );
    let f = read_frame(&numbered.join("frame_0002.exr")).unwrap();
    assert_eq!(header_i32(&f, "envshadow/frame"), Some(2));
}

/// `--resume` finds a patterned folder's complete frames by their names and skips them:
/// only the frame not yet there is rendered, and the others' files are untouched.
#[test]
fn resume_with_an_output_pattern_skips_complete_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let names = [
        "--output-pattern",
        "tt_####",
        "--frame-start",
        "1",
        "--no-report",
    ];
    ok(&render(&out, &names));
    let first = fs::read(out.join("tt_0001.exr")).unwrap();
    let modified = fs::metadata(out.join("tt_0001.exr"))
        .unwrap()
        .modified()
        .unwrap();
    let mut again = names.to_vec();
    again.extend(["--resume", "--frames", "0-2"]);
    ok(&render(&out, &again));
    let runs = common::csv_by_name(&out.join("records/runs.csv"));
    let last = runs.last().unwrap();
    assert_eq!(
        (
            last["frames_rendered"].as_str(),
            last["frames_skipped"].as_str()
        ),
        ("1", "2"),
        "{runs:?}"
    );
    assert_eq!(fs::read(out.join("tt_0001.exr")).unwrap(), first);
    assert_eq!(
        fs::metadata(out.join("tt_0001.exr"))
            .unwrap()
            .modified()
            .unwrap(),
        modified
    );
    assert!(out.join("tt_0003.png").is_file());
    assert_eq!(common::csv_by_name(&out.join("stats.csv")).len(), 3);
}

/// A rate given as 29.97 (flag) or "30000/1001" (spec) is the rational 30000/1001 in the
/// EXR's `framesPerSecond`, not 2997/100; 23.976 is 24000/1001.
#[test]
fn ntsc_frame_rates_are_exact_rationals_in_the_exr_header() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = common::Failures::new();
    for (fps, want) in [
        ("29.97", (30000, 1001)),
        ("30000/1001", (30000, 1001)),
        ("23.976", (24000, 1001)),
        ("25", (25, 1)),
    ] {
        let out = tmp.path().join(fps.replace('/', "_"));
        let o = render(&out, &["--fps", fps, "--frames", "0", "--no-report"]);
        if failures.check(o.status.success(), || {
            format!("--fps {fps}: {}", String::from_utf8_lossy(&o.stderr))
        }) {
            let f = read_frame(&out.join("frame_0000.exr")).unwrap();
            failures.check_eq(f.attributes.frames_per_second, Some(want), || {
                format!("--fps {fps}")
            });
        }
    }
    // A spec's string.
    let spec = tmp.path().join("ntsc.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[output]\nfps = \"30000/1001\"\n",
    )
    .unwrap();
    let out = tmp.path().join("spec");
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args(TINY)
        .args(["--frames", "0", "-q", "--no-report", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    if failures.check(o.status.success(), || {
        format!("spec: {}", String::from_utf8_lossy(&o.stderr))
    }) {
        let f = read_frame(&out.join("frame_0000.exr")).unwrap();
        failures.check_eq(f.attributes.frames_per_second, Some((30000, 1001)), || {
            "spec".into()
        });
    }
    failures.assert_none();
}

/// `envshadow video` encodes a patterned folder's frames (numbered from its start frame) at
/// the render's exact NTSC rate: ffprobe reads 30000/1001.
#[test]
fn video_is_made_from_patterned_frames_at_the_exact_rate() {
    if !common::require_tools(
        common::this_test!(),
        &["ffmpeg", "ffprobe"],
        "apt-get install ffmpeg",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    ok(&render(
        &out,
        &[
            "--output-pattern",
            "turntable_####",
            "--frame-start",
            "1",
            "--fps",
            "29.97",
            "--frames",
            "0-2",
            "--no-report",
        ],
    ));
    let o = common::bin().arg("video").arg(&out).output().unwrap();
    ok(&o);
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains("3 frames (1–3)"), "{said}");
    let probe = std::process::Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args(["-show_entries", "stream=r_frame_rate,nb_read_frames"])
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(out.join("video.mp4"))
        .output()
        .unwrap();
    ok(&probe);
    let info = String::from_utf8_lossy(&probe.stdout);
    for want in ["r_frame_rate=30000/1001", "nb_read_frames=3"] {
        assert!(info.lines().any(|l| l == want), "{want} not in:\n{info}");
    }
}

/// A farm render with a pattern assembles its frames under the pattern's names, the very
/// files a one-process render writes.
#[test]
fn farm_assembly_writes_the_patterned_names() {
    let tmp = tempfile::tempdir().unwrap();
    let (one, farm) = (tmp.path().join("one"), tmp.path().join("farm"));
    let names = [
        "--output-pattern",
        "f_##",
        "--frame-start",
        "7",
        "--tile",
        "16",
    ];
    let mut flags: Vec<&str> = TINY.to_vec();
    flags.extend(["--frames", "0-1"]);
    flags.extend(names);
    ok(&render(&one, &[&names[..], &["--no-report"]].concat()));
    let o = farm.to_str().unwrap();
    let run = |args: &[&str]| {
        let out = common::bin().args(args).args(&flags).output().unwrap();
        ok(&out);
    };
    run(&["plan", SPEC, "--out", o, "--jobs", "2", "--by", "tiles"]);
    for k in ["0", "1"] {
        run(&[
            "render", SPEC, "--out", o, "--job", k, "--of", "2", "--by", "tiles", "-q",
        ]);
    }
    let assembled = common::bin()
        .args(["assemble", o, "--no-report"])
        .output()
        .unwrap();
    ok(&assembled);
    let files = frame_files(&farm);
    assert_eq!(files, ["f_07.exr", "f_07.png", "f_08.exr", "f_08.png"]);
    for name in files {
        assert!(
            fs::read(one.join(&name)).unwrap() == fs::read(farm.join(&name)).unwrap(),
            "{name} differs from the one-process render"
        );
    }
}

/// A pattern that is a path, or has `%` (ffmpeg's sequence patterns read it), is refused
/// naming the flag or the spec's key; nothing is rendered.
#[test]
fn bad_output_patterns_are_refused_naming_the_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = common::Failures::new();
    for bad in ["renders/tt_####", "tt_%04d", "a#b#"] {
        let out = tmp.path().join("out");
        let o = render(&out, &["--output-pattern", bad]);
        let err = String::from_utf8_lossy(&o.stderr);
        failures.check(
            !o.status.success()
                && err.contains("--output-pattern")
                && err.contains("is not a frame name pattern"),
            || format!("{bad}: {err}"),
        );
        failures.check(frame_files(&out).is_empty(), || {
            format!("{bad}: frames written")
        });
    }
    let spec = tmp.path().join("bad.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[output]\noutput_pattern = \"../x_##\"\n",
    )
    .unwrap();
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .arg("--out")
        .arg(tmp.path().join("spec"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    failures.check(
        !o.status.success()
            && err.contains("bad.toml")
            && err.contains("output_pattern")
            && err.contains("a name, not a path"),
        || format!("spec: {err}"),
    );
    failures.assert_none();
}
