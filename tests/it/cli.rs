//! The binary end to end: a small render, its files, determinism, resume, and bad inputs.

use crate::common::{self, Failures};

use std::fs;
use std::path::{Path, PathBuf};

use envshadow::output::exr::read_frame;
use envshadow::output::stats::read_stats;

fn shapes_spec(dir: &Path, extra: &str) -> PathBuf {
    let spec = dir.join("anim.toml");
    fs::write(
        &spec,
        format!(
            "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 30\n[motion]\nframes = 3\n\
             [render]\nwidth = 64\nheight = 48\ntile = 16\n[output]\ndir = \"{}\"\n{extra}",
            dir.join("out").display()
        ),
    )
    .unwrap();
    spec
}

fn frame_files(dir: &Path) -> Vec<String> {
    common::file_names(dir)
        .into_iter()
        .filter(|n| n.starts_with("frame_") || n.ends_with(".tmp"))
        .collect()
}

#[test]
fn render_writes_frames_stats_and_lights_deterministically() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let out = tmp.path().join("out");
    let run = |extra: &[&str]| {
        let o = common::bin()
            .arg("render")
            .arg(&spec)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    run(&["--frames", "0..2"]);
    assert_eq!(
        frame_files(&out),
        [
            "frame_0000.exr",
            "frame_0000.png",
            "frame_0001.exr",
            "frame_0001.png"
        ]
    );
    let exr = read_frame(&out.join("frame_0001.exr")).unwrap();
    assert_eq!((exr.width, exr.height), (64, 48));
    for ch in ["R", "G", "B", "shadow.rays", "shadow.visible"] {
        assert!(exr.channel(ch).is_some(), "channel {ch} missing");
    }
    let rays: f32 = exr.channel("shadow.rays").unwrap().iter().sum();
    assert!(rays > 0.0);
    let png = image::open(out.join("frame_0000.png")).unwrap();
    assert_eq!((png.width(), png.height()), (64, 48));

    // The header keeps its documented leading columns; the values are read through the
    // library's one reader of stats.csv, by column name, never by position.
    let stats = fs::read_to_string(out.join("stats.csv")).unwrap();
    assert!(stats.starts_with(
        "frame,method,lights,width,height,queries,rays_traced,percent_traced,halo_pixels,halo_rays,thread_seconds,wrong_visible"
    ));
    let rows = read_stats(&out.join("stats.csv")).unwrap();
    assert_eq!(rows.len(), 2, "{rows:?}");
    let row = &rows[0];
    assert_eq!(
        (
            row.frame,
            row.method.as_str(),
            row.lights,
            row.width,
            row.height
        ),
        (0, "grid-nowarp-uncertainty", 30, 64, 48)
    );
    let c = &row.counts;
    assert!(
        c.rays < c.queries,
        "the default method predicts some shadows"
    );
    assert!(
        row.image_error.is_none() && c.wrong_visible == 0,
        "no validation columns without --validate"
    );
    // Where the rays went adds up to the rays traced: the every-light and flooded rays fit
    // in it, the rest being the prediction's own (read_stats derives rays_unsure as that).
    assert!(
        c.rays_every_light + c.rays_flooded <= c.rays,
        "{} + {} of {} rays",
        c.rays_every_light,
        c.rays_flooded,
        c.rays
    );
    assert!(c.rays_every_light > 0 && c.rays_flooded >= c.flood_fixes);

    let lights: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("lights.json")).unwrap()).unwrap();
    assert_eq!(lights["lights"].as_array().unwrap().len(), 30);

    // Same inputs, other thread count and tile size: identical files.
    let first = fs::read(out.join("frame_0001.exr")).unwrap();
    let first_png = fs::read(out.join("frame_0001.png")).unwrap();
    run(&["--frames", "1", "--threads", "1", "--tile", "0"]);
    assert_eq!(first, fs::read(out.join("frame_0001.exr")).unwrap());
    assert_eq!(first_png, fs::read(out.join("frame_0001.png")).unwrap());

    // Resume renders only the missing frame and keeps the other rows.
    let log = run(&["--resume"]);
    assert!(log.contains("frame 0: already rendered"), "{log}");
    assert!(log.contains("1 frames rendered, 2 skipped"), "{log}");
    assert_eq!(frame_files(&out).len(), 6);
    let frames: Vec<usize> = read_stats(&out.join("stats.csv"))
        .unwrap()
        .iter()
        .map(|r| r.frame)
        .collect();
    assert_eq!(frames, [0, 1, 2]);
}

#[test]
fn lights_command_writes_json_and_picture() {
    let tmp = tempfile::tempdir().unwrap();
    let json = tmp.path().join("lights.json");
    let png = tmp.path().join("cells.png");
    let o = common::bin()
        .args(["lights"])
        .arg(common::asset("grace.hdr"))
        .args(["-n", "50", "--json"])
        .arg(&json)
        .arg("--png")
        .arg(&png)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&fs::read_to_string(&json).unwrap()).unwrap();
    let lights = v["lights"].as_array().unwrap();
    assert_eq!(lights.len(), 50);
    for l in lights {
        assert_eq!(l["direction"].as_array().unwrap().len(), 3);
        assert!(l["solid_angle"].as_f64().unwrap() > 0.0);
    }
    let img = image::open(&png).unwrap();
    assert!(img.width() >= 256);
}

/// Runs `envshadow ARGS` expecting a bad-input failure: exit code 2, the problem on the first
/// line of stderr containing every `needle`, no panic, and no frame left in `out`. Our errors
/// are that one line; clap's usage errors (a flag's value refused by its parser) add their
/// usage and hints below it.
fn expect_bad_input(args: &[&std::ffi::OsStr], needles: &[&str], out: &Path) {
    let o = common::bin().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "args {args:?}: stderr {err}");
    assert!(!err.contains("panicked"), "{err}");
    let line = common::error_line(&err);
    for n in needles {
        assert!(
            line.to_lowercase().contains(&n.to_lowercase()),
            "{n:?} not in the first line of {err}"
        );
    }
    assert!(frame_files(out).is_empty(), "{:?}", frame_files(out));
}

#[test]
fn bad_inputs_fail_with_one_clear_line_and_no_output() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = dir.join("out");
    let os = |s: &str| std::ffi::OsString::from(s);
    let render = |spec: &Path, extra: &[&str]| {
        let mut v = vec![os("render"), spec.as_os_str().to_owned()];
        v.extend(extra.iter().map(|s| os(s)));
        v
    };
    // A table of cases: every bad input not refused properly is listed, not only the first.
    let mut failures = Failures::new();
    let mut check = |args: Vec<std::ffi::OsString>, needles: &[&str]| {
        let refs: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        let label = args
            .iter()
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ");
        failures.case(&label, || expect_bad_input(&refs, needles, &out));
    };

    // The spec itself.
    check(
        render(&dir.join("nope.toml"), &[]),
        &["nope.toml", "cannot read"],
    );
    let write_spec = |name: &str, text: &str| {
        let p = dir.join(name);
        fs::write(&p, text).unwrap();
        p
    };
    let base = format!("[output]\ndir = \"{}\"\n", out.display());
    let p = write_spec("syntax.toml", &format!("{base}[scene\nbuiltin = 1\n"));
    check(render(&p, &[]), &["syntax.toml", "line"]);
    let p = write_spec(
        "unknown.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n[render]\nwidht = 10\n"),
    );
    check(render(&p, &[]), &["unknown.toml", "widht"]);
    // Samples per pixel and the pixel filter, in the spec and on the command line.
    let p = write_spec(
        "spp.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n[render]\nspp = 7\n"),
    );
    check(render(&p, &[]), &["spp.toml", "[render] spp = 7", "square"]);
    let shapes = write_spec(
        "shapes.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n"),
    );
    check(render(&shapes, &["--spp", "5"]), &["--spp 5", "square"]);
    check(render(&shapes, &["--spp", "0"]), &["--spp 0", "square"]);
    check(
        render(&shapes, &["--trace-all-share", "101"]),
        &["--trace-all-share 101", "percentage"],
    );
    let p = write_spec(
        "share.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n[render]\ntrace_all_share = 150\n"),
    );
    check(
        render(&p, &[]),
        &["share.toml", "[render] trace_all_share = 150", "percentage"],
    );
    check(
        render(&shapes, &["--filter", "lanczos"]),
        &["lanczos", "blackman-harris"],
    );
    check(
        render(&shapes, &["--filter-width", "0.2"]),
        &["--filter-width 0.2", "0.5 to 8"],
    );
    let p = write_spec(
        "type.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n[render]\nwidth = \"wide\"\n"),
    );
    check(render(&p, &[]), &["type.toml", "width"]);
    let p = write_spec(
        "zero.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 0\n"),
    );
    check(render(&p, &[]), &["zero.toml", "zero lights"]);
    let good = write_spec(
        "good.toml",
        &format!("{base}[scene]\nbuiltin = \"shapes\"\n"),
    );
    check(render(&good, &["--lights", "0"]), &["zero lights"]);
    check(
        render(&good, &["--width", "100000", "--height", "100000"]),
        &["good.toml", "100000x100000"],
    );
    check(render(&good, &["--lights", "1000000"]), &["1000000 lights"]);
    check(render(&good, &["--method", "magic"]), &["magic"]);
    check(
        render(&good, &["--frames", "5..9"]),
        &[
            "--frames",
            "frame(s) 5..9 are past the animation's last frame, 0",
        ],
    );
    // A list names the frames outside, and a bad piece is named by clap's message.
    check(
        render(&good, &["--frames", "0,2-9"]),
        &["--frames", "0,2..10: frame(s) 2..10", "numbered from 0"],
    );
    check(
        render(&good, &["--frames", "0,2-x"]),
        &["--frames", "piece \"2-x\"", "\"x\" is not a frame number"],
    );

    // Scene files.
    let scene_spec = |name: &str, file: &Path| {
        write_spec(
            name,
            &format!(
                "{base}[scene]\nfile = \"{}\"\n[render]\nwidth = 16\nheight = 16\n",
                file.display()
            ),
        )
    };
    check(
        render(&scene_spec("s1.toml", &dir.join("missing.glb")), &[]),
        &["missing.glb"],
    );
    let bad_json = dir.join("broken.gltf");
    fs::write(
        &bad_json,
        "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ {",
    )
    .unwrap();
    check(
        render(&scene_spec("s2.toml", &bad_json), &[]),
        &["broken.gltf"],
    );
    let glb = fs::read(common::asset("bunny_res4.glb")).unwrap();
    let truncated = dir.join("truncated.glb");
    fs::write(&truncated, &glb[..glb.len() / 2]).unwrap();
    check(
        render(&scene_spec("s3.toml", &truncated), &[]),
        &["truncated.glb"],
    );

    // Environment maps.
    let env_spec = |name: &str, file: &Path| {
        write_spec(
            name,
            &format!(
                "{base}[scene]\nbuiltin = \"shapes\"\n[environment]\nfile = \"{}\"\n[render]\nwidth = 16\nheight = 16\n",
                file.display()
            ),
        )
    };
    let garbage = dir.join("garbage.exr");
    fs::write(&garbage, b"this is not an exr file at all").unwrap();
    check(
        render(&env_spec("e1.toml", &garbage), &[]),
        &["garbage.exr"],
    );
    let hdr = dir.join("badheader.hdr");
    fs::write(
        &hdr,
        b"#?NOTRADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n",
    )
    .unwrap();
    check(render(&env_spec("e2.toml", &hdr), &[]), &["badheader.hdr"]);
    for (name, value, what) in [("nan.exr", f32::NAN, "nan"), ("neg.exr", -1.0, "negative")] {
        let path = dir.join(name);
        write_float_exr(
            &path,
            8,
            4,
            |x, y| if (x, y) == (3, 2) { value } else { 1.0 },
        );
        check(render(&env_spec("e3.toml", &path), &[]), &[name, what]);
    }
    check(
        render(&env_spec("e4.toml", &dir.join("nothere.hdr")), &[]),
        &["nothere.hdr"],
    );
    let lights_out = dir.join("l.json");
    let o = common::bin()
        .arg("lights")
        .arg(&garbage)
        .arg("--json")
        .arg(&lights_out)
        .output()
        .unwrap();
    failures.check_eq(o.status.code(), Some(2), || {
        "lights on garbage.exr: exit code".to_string()
    });
    failures.check(!lights_out.exists(), || {
        "lights on garbage.exr wrote l.json".to_string()
    });
    failures.assert_none();
}

fn write_float_exr(path: &Path, w: usize, h: usize, f: impl Fn(usize, usize) -> f32 + Sync) {
    use exr::prelude::*;
    let layer = SpecificChannels::rgb(|Vec2(x, y)| (f(x, y), 1.0f32, 1.0f32));
    Image::from_channels((w, h), layer)
        .write()
        .to_file(path)
        .unwrap();
}

#[test]
fn table_and_bench_commands_measure_every_requested_configuration() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let csv = tmp.path().join("table.csv");
    let o = common::bin()
        .args(["table", "--scene"])
        .arg(&spec)
        .args([
            "--lights", "20,40", "--width", "48", "--height", "32", "--csv",
        ])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = String::from_utf8_lossy(&o.stdout);
    for m in envshadow::paper::table1_methods() {
        assert!(
            table.contains(&format!("| {m} |")),
            "{m} missing from\n{table}"
        );
    }
    let rows = common::csv_by_name(&csv);
    assert_eq!(rows.len(), 2 * 6, "{rows:?}");
    let brute = &rows[0];
    assert_eq!(
        (
            brute["method"].as_str(),
            brute["flood_to"].as_str(),
            brute["lights"].as_str(),
            brute["percent_traced"].as_str()
        ),
        ("brute", "", "20", "100.0000")
    );

    // The sweep's parameters reach the renders: a stricter voter threshold traces more.
    let traced = |flags: &[&str]| {
        let o = common::bin()
            .args(["table", "--scene"])
            .arg(&spec)
            .args(["--lights", "40", "--width", "96", "--height", "64"])
            .args(["--methods", "grid-nowarp-uncertainty", "--csv"])
            .arg(&csv)
            .args(flags)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let heading = String::from_utf8_lossy(&o.stdout)
            .lines()
            .next()
            .unwrap()
            .to_string();
        let pct: f64 = common::csv_by_name(&csv)[0]["percent_traced"]
            .parse()
            .unwrap();
        (heading, pct)
    };
    let (plain, p3) = traced(&[]);
    let (strict, p4) = traced(&["--min-voters", "4"]);
    assert!(!plain.contains("min_voters"), "{plain}");
    assert!(strict.contains("min_voters 4"), "{strict}");
    assert!(p4 > p3, "--min-voters 4 traced {p4} %, the default {p3} %");
    // Busy voters (the default 4) trace more than without them, and never more than asking
    // four voters everywhere.
    let (_, calm) = traced(&["--busy-voters", "0"]);
    assert!(
        calm <= p3 && p3 <= p4,
        "--busy-voters 0 traced {calm} %, the default {p3} %, --min-voters 4 {p4} %"
    );

    let o = common::bin()
        .args(["bench", "--scene"])
        .arg(&spec)
        .args([
            "--lights",
            "16",
            "--threads",
            "1",
            "--methods",
            "none,brute,grid-nowarp-uncertainty",
            "--flood-to",
            "all,contrary",
        ])
        .args(["--width", "40", "--height", "30", "--repeat", "1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().filter(|l| l.starts_with("| 16 |")).collect();
    // The flood rule multiplies only the method it can change.
    assert_eq!(lines.len(), 4, "{out}");
    assert!(
        lines[0].contains("| none |") && lines[0].contains("| 1.00 |"),
        "{out}"
    );
    assert!(
        lines[3].contains("| grid-nowarp-uncertainty --flood-to contrary |"),
        "{out}"
    );
}

/// Issue 20, item 4: one writer per output folder. Two renders into one folder used to both
/// exit 0 with `stats.csv` last-writer-wins. While another process holds the folder's lock
/// (here the test, as a running render would), a render refuses with exit 2, naming the
/// folder and the holder's PID, and writes nothing; with `--wait` it writes nothing while the
/// lock is held and renders once it is released.
#[test]
fn a_render_into_a_folder_another_render_holds_refuses_or_waits() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let out = tmp.path().join("out");
    fs::create_dir_all(&out).unwrap();
    let held = fs::File::open(&out).unwrap();
    held.try_lock()
        .expect("the test takes the folder's lock first");
    let render = |extra: &[&str]| {
        let mut c = common::bin();
        c.arg("render")
            .arg(&spec)
            .args(["--frames", "0..1", "--no-report", "-q"])
            .args(extra);
        c
    };

    let o = render(&[]).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    let pid = format!("PID {}", std::process::id());
    for needle in [out.to_str().unwrap(), pid.as_str(), "--wait"] {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(
        common::file_names(&out).is_empty(),
        "a refused render wrote {:?}",
        common::file_names(&out)
    );

    let mut waiting = render(&["--wait"]).spawn().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let still = waiting.try_wait().unwrap();
    let early = common::file_names(&out);
    drop(held);
    let status = waiting.wait().unwrap();
    assert!(still.is_none(), "--wait did not wait: exited {still:?}");
    assert!(
        early.is_empty(),
        "--wait wrote {early:?} while the folder was held"
    );
    assert!(status.success(), "--wait render failed: {status}");
    let done = common::file_names(&out);
    for f in [
        "frame_0000.exr",
        "frame_0000.png",
        "lights.json",
        "stats.csv",
    ] {
        assert!(done.iter().any(|n| n == f), "{f} missing from {done:?}");
    }
}

/// Issue 20, item 3 (its temporaries): a render killed mid-write (SIGKILL, power) leaves
/// `frame_NNNN.exr.envshadow-<pid>….tmp` files that no later run removed. A render into the
/// folder — here `--resume`, the command every message suggests — removes every temporary of
/// ours and keeps everything else, `.tmp` names shaped like our older unmarked ones included
/// (issue 39: they may be the user's).
#[test]
fn resume_removes_the_temporaries_a_killed_render_left() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let out = tmp.path().join("out");
    fs::create_dir_all(&out).unwrap();
    let stale = [
        "frame_0001.exr.envshadow-999999-0-0badcafe.tmp",
        "frame_0001.png.envshadow-4242-0-00000000.tmp",
        "stats.csv.envshadow-17-3-00000001.tmp",
    ];
    let kept = [
        "notes.tmp",
        "README.txt",
        "frame_0001.png.4242.tmp",
        "stats.csv.17-3-00000001.tmp",
    ];
    for n in stale.iter().chain(&kept) {
        fs::write(out.join(n), b"half").unwrap();
    }
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args(["--frames", "0..2", "--resume", "--no-report", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let left = common::file_names(&out);
    for n in stale {
        assert!(!left.iter().any(|l| l == n), "{n} left: {left:?}");
    }
    for n in kept
        .iter()
        .chain(&["frame_0000.exr", "frame_0001.exr", "stats.csv"])
    {
        assert!(left.iter().any(|l| l == n), "{n} missing: {left:?}");
    }
}

#[test]
fn scene_lights_flag_lights_the_frame_with_the_files_lights_or_ignores_them() {
    // The circuit board places a sun: by default a note names it and lights.json lists it;
    // --scene-lights=false says it is ignored and lights.json has the map's lights alone.
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("board.toml");
    let glb = common::assets_dir().join("corpus/objects_on_circuit_board.glb");
    fs::write(
        &spec,
        format!(
            "[scene]\nfile = \"{}\"\n[lights]\ncount = 20\n[motion]\nframes = 1\n\
             [render]\nwidth = 32\nheight = 24\n",
            glb.display()
        ),
    )
    .unwrap();
    let mut failures = Failures::new();
    for (flag, note, lights) in [
        (
            None,
            "the scene file's 1 light joins the map's: directional 'Sun'",
            21,
        ),
        (
            Some("--scene-lights=false"),
            "the scene file's 1 light ignored ([lights] scene_lights = false)",
            20,
        ),
    ] {
        failures.case(flag.unwrap_or("default"), || {
            let out = tmp.path().join(format!("out-{lights}"));
            let o = common::bin()
                .arg("render")
                .arg(&spec)
                .args(flag)
                .arg("--out")
                .arg(&out)
                .arg("--no-report")
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&o.stderr);
            assert!(o.status.success(), "{stderr}");
            assert!(stderr.contains(note), "{stderr}");
            let json: serde_json::Value =
                serde_json::from_slice(&fs::read(out.join("lights.json")).unwrap()).unwrap();
            let listed = json["lights"].as_array().unwrap().len();
            assert_eq!(listed, lights);
            assert_eq!(json.get("scene_lights").is_some(), lights == 21);
        });
    }
    failures.assert_none();
}
/// `envshadow ARGS`: (exit code, stdout, stderr).
fn run_bin(args: &[&str]) -> (Option<i32>, String, String) {
    let o = common::bin().args(args).output().unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Issue 22, item 7: main.rs kept only the first line of clap's errors, losing the name of
/// the missing argument and the "did you mean" hint. Usage errors now read as clap writes
/// them (usage line, tip, exit 2), uncoloured when stderr is not a terminal.
#[test]
fn clap_errors_keep_the_missing_argument_and_the_hint() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let spec = spec.to_str().unwrap();
    let mut failures = Failures::new();
    for (args, needles) in [
        (
            &["render"][..],
            &[
                "required arguments were not provided",
                "<SPEC>",
                "Usage: envshadow render",
            ][..],
        ),
        (
            &["render", spec, "--frmes", "1"],
            &[
                "unexpected argument '--frmes'",
                "tip:",
                "'--frames'",
                "Usage:",
            ],
        ),
        (
            &["rnder"],
            &["unrecognized subcommand 'rnder'", "tip:", "'render'"],
        ),
        (
            &["plan", spec],
            &["required arguments were not provided", "--jobs <N>"],
        ),
        (
            &["render", spec, "--frames", "1-3,x"],
            &[
                "'1-3,x'",
                "piece \"x\"",
                "A-B (B included)",
                "A..B (B excluded)",
            ],
        ),
    ] {
        let (code, out, err) = run_bin(args);
        let label = args.join(" ");
        failures.check_eq(code, Some(2), || format!("{label}: exit code"));
        failures.check(out.is_empty(), || format!("{label}: stdout {out:?}"));
        for n in needles {
            failures.check(err.contains(n), || format!("{label}: {n:?} not in {err}"));
        }
        failures.check(!err.contains('\u{1b}'), || {
            format!("{label}: colour codes on a pipe: {err:?}")
        });
    }
    // Help and version are not errors: stdout, exit 0.
    for args in [&["--help"][..], &["render", "--help"], &["--version"]] {
        let (code, out, _) = run_bin(args);
        failures.check_eq(code, Some(0), || format!("{args:?}: exit code"));
        failures.check(!out.is_empty(), || format!("{args:?}: nothing on stdout"));
    }
    failures.assert_none();
}

/// Issue 22, item 7: `-q` was on 2 of 10 commands and `-v` on none. Both are global: every
/// command's help lists them, either side of the command's name.
#[test]
fn every_command_takes_quiet_and_verbose() {
    let (_, help, _) = run_bin(&["--help"]);
    // The commands, from the help's list ("  render  Render an …").
    let commands: Vec<String> = help
        .split("Commands:")
        .nth(1)
        .unwrap()
        .split("Options:")
        .next()
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("  ").filter(|r| !r.starts_with(' ')))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(String::from)
        .collect();
    assert!(commands.len() >= 13, "{commands:?}");
    let mut failures = Failures::new();
    for c in &commands {
        let (code, out, err) = run_bin(&[c, "--help"]);
        failures.check_eq(code, Some(0), || format!("{c} --help: {err}"));
        for flag in ["-q, --quiet", "-v, --verbose"] {
            failures.check(out.contains(flag), || format!("{c} --help lacks {flag}"));
        }
    }
    // Before the command or after it; not both at once.
    let (code, out, _) = run_bin(&["-q", "methods"]);
    failures.check(code == Some(0) && out.contains("(default)"), || {
        format!("-q methods still lists the methods: {out}")
    });
    let (code, _, err) = run_bin(&["methods", "-q", "-v"]);
    failures.check_eq(code, Some(2), || format!("-q -v: {err}"));
    failures.check(err.contains("cannot be used with"), || err.clone());
    failures.assert_none();
}

/// Issue 37: `envshadow methods` named 5 of the 11 settings the methods read, from a list of
/// its own. Each method now lists every setting it reads (its order's and rule's typed keys),
/// and together they list every method setting.
#[test]
fn methods_lists_every_setting_each_method_reads() {
    use envshadow::predict::Method;
    use envshadow::settings::method_settings;
    let (code, out, err) = run_bin(&["methods"]);
    assert_eq!(code, Some(0), "{err}");
    // One block per method: its heading line ("name (default): parts"), then indented lines.
    let mut listed: Vec<(String, Vec<String>)> = Vec::new();
    for line in out.lines() {
        if !line.starts_with(' ') {
            let name = line.split([':', ' ']).next().unwrap_or("").to_string();
            listed.push((name, Vec::new()));
        } else if let Some(flags) = line.trim().strip_prefix("settings:") {
            let last = listed.last_mut().expect("a method before its settings");
            last.1 = flags.split_whitespace().map(String::from).collect();
        }
    }
    let names: Vec<&str> = listed.iter().map(|(n, _)| n.as_str()).collect();
    let all: Vec<&str> = Method::all().map(|m| m.name()).collect();
    assert_eq!(names, all, "{out}");
    let mut union = Vec::new();
    for (m, (_, got)) in Method::all().zip(&listed) {
        let want: Vec<String> = method_settings()
            .filter(|&k| m.reads(k))
            .map(|k| format!("--{}", k.flag()))
            .collect();
        assert_eq!(got, &want, "{m}");
        union.extend(want);
    }
    for k in method_settings() {
        let flag = format!("--{}", k.flag());
        assert!(union.contains(&flag), "no method lists {flag}: {out}");
    }
    // The default method reads the grid's and the uncertainty rule's settings.
    let default = &listed[all
        .iter()
        .position(|&n| n == Method::DEFAULT.name())
        .unwrap()]
    .1;
    for flag in [
        "--h0",
        "--min-voters",
        "--flood-to",
        "--temporal",
        "--trace-all-share",
    ] {
        assert!(default.iter().any(|f| f == flag), "{flag}: {default:?}");
    }
}

/// `-q` prints only errors, `-v` adds a line per tile, the inputs' loading time and each
/// frame's rays by kind and writing time; the default is in between.
#[test]
fn quiet_says_nothing_and_verbose_says_more() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let spec = spec.to_str().unwrap();
    let render = |extra: &[&str]| {
        let mut a = vec!["render", spec, "--frames", "0,2", "--no-report"];
        a.extend_from_slice(extra);
        let (code, out, err) = run_bin(&a);
        assert_eq!(code, Some(0), "{err}");
        (out, err)
    };
    let (out, err) = render(&["-q"]);
    assert_eq!((out.as_str(), err.as_str()), ("", ""));
    let (_, normal) = render(&[]);
    assert!(normal.contains("frame 2 (") && normal.contains("2 frames rendered"));
    assert!(!normal.contains(" tile "), "{normal}");
    let (_, verbose) = render(&["-v"]);
    // 64x48 in tiles of 16: 12 tiles a frame, one line each.
    let tiles = verbose.lines().filter(|l| l.contains(" tile ")).count();
    assert_eq!(tiles, 24, "{verbose}");
    for needle in [
        "frame 0 tile 11 [48,32,64,48]: ",
        "inputs in ",
        "frame 2: written in ",
        "at pixels tracing every light",
        // The sky's tiles ask nothing, and say so (they printed "0 of 0 queries traced").
        "frame 0 tile 0 [0,0,16,16]: no shadow queries (no lit surface), ",
    ] {
        assert!(verbose.contains(needle), "{needle:?} not in {verbose}");
    }
    assert!(!verbose.contains(" 0 of 0 "), "{verbose}");
    // What a command exists to print stays; its "wrote" lines go with -q.
    let json = tmp.path().join("l.json");
    let (code, out, err) = run_bin(&[
        "lights",
        "builtin:sky",
        "-n",
        "8",
        "--json",
        json.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!((code, out.as_str(), err.as_str()), (Some(0), "", ""));
    assert!(json.exists());
    let (_, out, _) = run_bin(&["version", "-q"]);
    assert!(out.starts_with("envshadow "), "{out}");
}

/// Issue 22, item 7: a log (stderr not a terminal) got one line per frame with no time
/// elapsed and no estimate of the time left. Each frame's line now ends with both, in
/// H:MM:SS; the last one's ETA is 0:00:00.
#[test]
fn log_lines_carry_elapsed_time_and_eta() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(tmp.path(), "");
    let log = tmp.path().join("render.log");
    let status = common::bin()
        .arg("render")
        .arg(&spec)
        .args(["--no-report", "--threads", "1"])
        .stderr(fs::File::create(&log).unwrap())
        .status()
        .unwrap();
    assert!(status.success());
    let text = fs::read_to_string(&log).unwrap();
    let frames: Vec<&str> = text.lines().filter(|l| l.starts_with("frame ")).collect();
    assert_eq!(frames.len(), 3, "{text}");
    let hms = |s: &str| {
        let p: Vec<&str> = s.split(':').collect();
        p.len() == 3
            && p[0].parse::<u32>().is_ok()
            && p[1].len() == 2
            && p[1].parse::<u32>().is_ok_and(|m| m < 60)
            && p[2].len() == 2
            && p[2].parse::<u32>().is_ok_and(|s| s < 60)
    };
    for l in &frames {
        let (_, clock) = l.rsplit_once("; ").unwrap_or_else(|| panic!("{l}"));
        let (elapsed, eta) = clock
            .strip_prefix("elapsed ")
            .and_then(|c| c.split_once(", ETA "))
            .unwrap_or_else(|| panic!("no elapsed/ETA in {l:?}"));
        assert!(hms(elapsed) && hms(eta), "{l}");
    }
    assert!(frames[2].ends_with("ETA 0:00:00"), "{text}");
    assert!(text.starts_with("rendering 3 frames of 12 tiles"), "{text}");
}

/// Issue 22, item 7: `envshadow completions SHELL` for the five shells clap_complete knows;
/// bash's script completes every command.
#[test]
fn completions_name_every_command() {
    let (code, bash, err) = run_bin(&["completions", "bash"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(bash.contains("complete -F _envshadow"), "{bash}");
    // The words offered after `envshadow `, and a case for each command's own flags.
    let top = bash
        .lines()
        .find(|l| l.trim_start().starts_with("opts=\"-q -v"))
        .unwrap_or_else(|| panic!("no top-level word list in {bash}"));
    for c in [
        "render",
        "lights",
        "bench",
        "table",
        "report",
        "plan",
        "assemble",
        "methods",
        "version",
        "export",
        "savings",
        "completions",
        "man",
    ] {
        assert!(
            top.split_whitespace().any(|w| w.trim_matches('"') == c),
            "{c} not offered: {top}"
        );
        assert!(bash.contains(&format!("envshadow,{c})")), "no case for {c}");
    }
    assert!(bash.contains("--frames") && bash.contains("--quiet"));
    for shell in ["zsh", "fish", "powershell", "elvish"] {
        let (code, script, err) = run_bin(&["completions", shell]);
        assert_eq!(code, Some(0), "{shell}: {err}");
        assert!(
            script.contains("render") && script.contains("--frames"),
            "{shell}"
        );
    }
    let (code, _, err) = run_bin(&["completions", "tcsh"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("[possible values: bash, elvish, fish, powershell, zsh]"),
        "{err}"
    );
}

/// Issue 22, item 7: `envshadow man` prints envshadow(1) in roff; `--out DIR` writes a page
/// per command. The pages are ASCII (other characters as groff's `\[uXXXX]`), so groff reads
/// them without a warning even without preconv.
#[test]
fn man_pages_are_roff_that_groff_reads_without_warnings() {
    let (code, page, err) = run_bin(&["man"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(page.contains(".TH envshadow 1 "), "{page}");
    for section in [".SH NAME", ".SH SYNOPSIS", ".SH OPTIONS", ".SH SUBCOMMANDS"] {
        assert!(page.contains(section), "{section} missing");
    }
    assert!(
        page.contains("envshadow\\-render(1)"),
        "the commands' pages named"
    );
    assert!(page.is_ascii());
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("man1");
    let (code, _, err) = run_bin(&["man", "--out", dir.to_str().unwrap(), "-q"]);
    assert_eq!((code, err.as_str()), (Some(0), ""));
    // One page per command --help lists (but `help`), and the main page.
    let (_, help, _) = run_bin(&["--help"]);
    let mut expected: Vec<String> = help
        .split("Commands:")
        .nth(1)
        .unwrap()
        .lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(|c| format!("envshadow-{c}.1"))
        .collect();
    expected.push("envshadow.1".into());
    expected.sort();
    let mut pages = common::file_names(&dir);
    pages.sort();
    assert!(expected.len() >= 15, "{help}");
    assert_eq!(pages, expected);
    let render = fs::read_to_string(dir.join("envshadow-render.1")).unwrap();
    assert!(
        render.contains(".TH envshadow-render 1  \"envshadow "),
        "{render}"
    );
    assert!(render.contains("\\fB\\-\\-frames\\fR"), "{render}");
    assert_eq!(fs::read_to_string(dir.join("envshadow.1")).unwrap(), page);
    if !common::require_tools(
        common::this_test!(),
        &["groff"],
        "apt-get install groff-base",
    ) {
        return;
    }
    for p in &pages {
        let o = std::process::Command::new("groff")
            .args(["-man", "-Tutf8", "-ww", "-z"])
            .arg(dir.join(p))
            .output()
            .unwrap();
        let warnings = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success() && warnings.is_empty(), "{p}: {warnings}");
    }
}

/// Issue 22, item 7: `farm.sh --help` printed its usage on stderr and exited 2, as for a
/// mistake. --help prints on stdout and exits 0 (both scripts); missing arguments still get
/// the usage on stderr and exit 2.
#[test]
fn farm_and_slurm_scripts_print_help_on_stdout() {
    for script in ["scripts/farm.sh", "scripts/slurm.sh"] {
        let run = |args: &[&str]| {
            std::process::Command::new("bash")
                .arg(script)
                .args(args)
                .current_dir(env!("CARGO_MANIFEST_DIR"))
                .output()
                .unwrap()
        };
        let o = run(&["--help"]);
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{script} --help");
        assert!(
            o.stderr.is_empty(),
            "{script}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            out.contains(&format!("{script} ANIM.toml")) && out.contains("Exit: 0"),
            "{out}"
        );
        let o = run(&[]);
        assert_eq!(o.status.code(), Some(2), "{script} without arguments");
        assert!(o.stdout.is_empty());
        assert!(String::from_utf8_lossy(&o.stderr).contains("Exit: 0"));
    }
}
