//! Issue 40: the look changed from the command line — the environment's map, rotation and
//! intensity, the camera's distance, elevation, azimuth, field of view and the file's own
//! camera, the frame count and degrees per frame — each flag rendering as its spec key does,
//! bad values refused naming the flag, a model's turntable lengthened by `--frames`, and
//! `--write-spec` writing a spec that renders the same frames.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::{self, Failures};

/// A tiny built-in shapes render (32×24, 20 lights, 1 spp, 4 frames of orbit) with `env`,
/// `camera` and `motion` lines added to their tables (`motion` may give its own `frames`).
fn shapes_spec(path: &Path, env: &str, camera: &str, motion: &str) -> PathBuf {
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    let frames = if motion.contains("frames =") {
        ""
    } else {
        "frames = 4"
    };
    fs::write(
        path,
        format!(
            "name = \"look\"\n[scene]\nbuiltin = \"shapes\"\n[environment]\n{env}\n\
             [camera]\n{camera}\n[lights]\ncount = 20\n[motion]\n{frames}\n{motion}\n\
             [render]\nwidth = 32\nheight = 24\ntile = 16\n"
        ),
    )
    .unwrap();
    path.to_path_buf()
}

/// Runs `envshadow render spec flags…`.
fn run(spec: &Path, flags: &[&str]) -> Output {
    common::bin()
        .arg("render")
        .arg(spec)
        .args(flags)
        .output()
        .unwrap()
}

/// Renders `spec` (a spec or a model) with `flags` into `out`, `-q` and no report; panics
/// with its stderr unless it succeeds.
#[track_caller]
fn render(spec: &Path, out: &Path, flags: &[&str]) {
    let mut args = vec!["--out", out.to_str().unwrap(), "-q", "--no-report"];
    args.extend(flags);
    let o = run(spec, &args);
    assert!(
        o.status.success(),
        "{flags:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A frame's EXR and PNG bytes.
fn frame(out: &Path, n: usize) -> (Vec<u8>, Vec<u8>) {
    let read = |ext: &str| {
        let p = out.join(format!("frame_{n:04}.{ext}"));
        fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    (read("exr"), read("png"))
}

/// Each look flag renders frame 1 byte for byte as the spec key it stands for, and
/// otherwise than the spec without it (the flag does something).
#[test]
fn each_look_flag_renders_as_its_spec_key() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let map = common::asset("OrientationLatLong.exr");
    let map_key = format!("file = {:?}", map.display().to_string());
    let base = shapes_spec(&dir.join("base/look.toml"), "", "", "");
    render(&base, &dir.join("base/out"), &["--frames", "1"]);
    let plain = frame(&dir.join("base/out"), 1);
    // (label, flags, [environment], [camera], [motion] lines of the equivalent spec)
    let cases: Vec<(&str, Vec<&str>, &str, &str, &str)> = vec![
        (
            "env-rotation",
            vec!["--env-rotation", "90"],
            "rotation = 90.0",
            "",
            "",
        ),
        (
            "env-intensity",
            vec!["--env-intensity", "0.5"],
            "intensity = 0.5",
            "",
            "",
        ),
        (
            "env",
            vec!["--env", map.to_str().unwrap()],
            map_key.as_str(),
            "",
            "",
        ),
        (
            "distance",
            vec!["--distance", "9"],
            "",
            "distance = 9.0",
            "",
        ),
        (
            "elevation",
            vec!["--elevation", "-10"],
            "",
            "elevation = -10.0",
            "",
        ),
        (
            "azimuth",
            vec!["--azimuth", "-60"],
            "",
            "azimuth = -60.0",
            "",
        ),
        ("vfov", vec!["--vfov", "25"], "", "vfov = 25.0", ""),
        ("fov alias", vec!["--fov", "25"], "", "vfov = 25.0", ""),
        (
            "frame-count",
            vec!["--frame-count", "12"],
            "",
            "",
            "frames = 12",
        ),
        (
            "degrees-per-frame",
            vec!["--degrees-per-frame", "20"],
            "",
            "",
            "degrees_per_frame = 20.0",
        ),
    ];
    let mut f = Failures::new();
    for (i, (label, flags, env, camera, motion)) in cases.into_iter().enumerate() {
        let case = dir.join(format!("case{i}"));
        let mut with_flags = flags.clone();
        with_flags.extend(["--frames", "1"]);
        render(&base, &case.join("flag"), &with_flags);
        let spec = shapes_spec(&case.join("key/look.toml"), env, camera, motion);
        render(&spec, &case.join("key/out"), &["--frames", "1"]);
        let (by_flag, by_key) = (
            frame(&case.join("flag"), 1),
            frame(&case.join("key/out"), 1),
        );
        f.check(by_flag == by_key, || {
            format!("{label}: the flag's frame differs from the spec key's")
        });
        f.check(by_flag.0 != plain.0 && by_flag.1 != plain.1, || {
            format!("{label}: the flag changed nothing")
        });
    }
    f.assert_none();
}

/// A flag wins over the spec's own key; and a placing flag replaces the spec's `position`.
#[test]
fn a_look_flag_overrides_the_specs_key() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let spec = shapes_spec(
        &dir.join("a/look.toml"),
        "rotation = 30.0",
        "elevation = 40.0\nposition = [0.0, 3.0, 6.0]",
        "",
    );
    render(
        &spec,
        &dir.join("a/out"),
        &[
            "--frames",
            "0",
            "--elevation",
            "10",
            "--env-rotation",
            "-20",
        ],
    );
    let want = shapes_spec(
        &dir.join("b/look.toml"),
        "rotation = -20.0",
        "elevation = 10.0",
        "",
    );
    render(&want, &dir.join("b/out"), &["--frames", "0"]);
    assert!(frame(&dir.join("a/out"), 0) == frame(&dir.join("b/out"), 0));
}

/// Bad values are refused before any work (exit 2), the message naming the flag and the
/// value as typed.
#[test]
fn bad_look_values_are_refused_naming_the_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = shapes_spec(&tmp.path().join("look.toml"), "", "", "");
    let cases: &[(&[&str], &str)] = &[
        (&["--distance", "-1"], "--distance -1: "),
        (&["--vfov", "180"], "--vfov 180: "),
        (&["--vfov", "0"], "--vfov 0: "),
        (&["--elevation", "95"], "--elevation 95: "),
        (&["--azimuth", "inf"], "--azimuth inf: "),
        (&["--env-intensity", "-0.5"], "--env-intensity -0.5: "),
        (&["--env-rotation", "nan"], "--env-rotation NaN: "),
        (&["--frame-count", "0"], "--frame-count 0: "),
        (&["--degrees-per-frame", "nan"], "--degrees-per-frame NaN: "),
        (&["--gltf-camera", "--elevation", "5"], "--elevation"),
    ];
    let mut f = Failures::new();
    for (flags, want) in cases {
        let out = tmp.path().join("out");
        let mut args = flags.to_vec();
        args.extend(["--out", out.to_str().unwrap()]);
        let o = run(&spec, &args);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        f.check(o.status.code() == Some(2), || {
            format!("{flags:?}: exit {:?}, not 2", o.status.code())
        });
        f.check(err.contains(want), || {
            format!("{flags:?}: {want:?} not in {err}")
        });
    }
    f.check(!tmp.path().join("out").exists(), || {
        "a refused render wrote its folder".into()
    });
    // A sequence of motions has no one frame count to change.
    let seq = tmp.path().join("seq.toml");
    fs::write(
        &seq,
        "[scene]\nbuiltin = \"shapes\"\n[[motion]]\nframes = 2\n[[motion]]\nkind = \"spin\"\nframes = 2\n",
    )
    .unwrap();
    let o = run(&seq, &["--frame-count", "8"]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    f.check(o.status.code() == Some(2), || "sequence: exit not 2".into());
    f.check(
        err.contains("--frame-count") && err.contains("[[motion]]"),
        || err.clone(),
    );
    f.assert_none();
}

/// `render model.glb --frames 0-119` on the 72-frame default turntable renders frame 119,
/// the turntable lengthened at its 5° a frame: frame 80 is the frame a
/// `--degrees-per-frame 5 --frame-count 120` render draws.
#[test]
fn frames_past_a_models_default_turntable_lengthen_it() {
    let tmp = tempfile::tempdir().unwrap();
    let model = common::asset("bunny_res4.glb");
    let small = [
        "--width", "32", "--height", "24", "--lights", "20", "--spp", "1",
    ];
    let grown = tmp.path().join("grown");
    let mut flags = small.to_vec();
    flags.extend(["--frames", "0-119:80,119"]);
    render(&model, &grown, &flags);
    for n in [0, 80, 119] {
        assert!(
            grown.join(format!("frame_{n:04}.exr")).is_file(),
            "frame {n}"
        );
    }
    let settings = fs::read_to_string(grown.join("settings.txt")).unwrap();
    assert!(settings.contains("[motion] frames = 120"), "{settings}");
    let counted = tmp.path().join("counted");
    let mut flags = small.to_vec();
    flags.extend([
        "--frames",
        "80",
        "--frame-count",
        "120",
        "--degrees-per-frame",
        "5",
    ]);
    render(&model, &counted, &flags);
    assert!(frame(&grown, 80) == frame(&counted, 80));
}

/// `--write-spec` writes the resolved settings (a model's turntable with look flags, past
/// its default frames) as a spec that, rendered from another folder, writes the same frames,
/// byte for byte, and the same settings record.
#[test]
fn write_spec_renders_the_same_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let model = common::asset("bunny_res4.glb");
    let flags = [
        "--width",
        "32",
        "--height",
        "24",
        "--lights",
        "20",
        "--spp",
        "4",
        "--elevation",
        "12",
        "--azimuth",
        "-30",
        "--vfov",
        "35",
        "--env-rotation",
        "45",
        "--env-intensity",
        "0.4",
        "--frames",
        "0,75",
        "--background",
        "color",
        "--background-color",
        "0.1,0.2,0.3",
        "--method",
        "brute",
    ];
    let direct = tmp.path().join("direct");
    render(&model, &direct, &flags);
    let spec = tmp.path().join("specs/sub/turntable.toml");
    let mut write = flags.to_vec();
    write.extend(["--write-spec", spec.to_str().unwrap()]);
    let o = common::bin()
        .arg("render")
        .arg(&model)
        .args(&write)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!direct.join("frame_0001.exr").exists());
    let names = common::file_names(spec.parent().unwrap());
    assert_eq!(
        names,
        vec!["turntable.toml".to_string()],
        "a temporary left behind"
    );
    // Rendered from elsewhere: its paths are absolute.
    let again = tmp.path().join("again");
    let o = common::bin()
        .current_dir(tmp.path().join("specs"))
        .args([
            "render",
            "sub/turntable.toml",
            "-q",
            "--no-report",
            "--frames",
            "0,75",
        ])
        .arg("--out")
        .arg(&again)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for n in [0, 75] {
        assert!(frame(&direct, n) == frame(&again, n), "frame {n} differs");
    }
    let record = |d: &Path| fs::read_to_string(d.join("settings.txt")).unwrap();
    assert_eq!(record(&direct), record(&again));
}

/// A spec render's `--write-spec`: a sequence of motions, a spec-relative map and the
/// camera flags come back as one spec that renders the same frame.
#[test]
fn write_spec_of_a_spec_keeps_its_sequence_and_map() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("specs");
    fs::create_dir_all(&dir).unwrap();
    fs::copy(common::asset("OrientationLatLong.exr"), dir.join("map.exr")).unwrap();
    let spec = dir.join("seq.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[environment]\nfile = \"map.exr\"\n[lights]\ncount = 20\n\
         [[motion]]\nkind = \"spin\"\nframes = 3\nturn_degrees = 100.0\n\
         [[motion]]\nkind = \"environment\"\nframes = \"3-5\"\nturn_degrees = 50.0\n\
         [render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    let flags = ["--frames", "4", "--distance", "8", "--elevation", "30"];
    let direct = tmp.path().join("direct");
    render(&spec, &direct, &flags);
    let written = tmp.path().join("written.toml");
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args(flags)
        .arg("--write-spec")
        .arg(&written)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = fs::read_to_string(&written).unwrap();
    assert!(text.contains("[[motion]]"), "{text}");
    let again = tmp.path().join("again");
    render(&written, &again, &["--frames", "4"]);
    assert!(frame(&direct, 4) == frame(&again, 4));
}
