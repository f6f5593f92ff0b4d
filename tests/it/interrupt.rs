//! Interrupting a real render with SIGINT, SIGTERM and SIGHUP: each run exits with code 130,
//! leaves only complete frames (EXR and PNG both, no temporaries), and `--resume` finishes the
//! animation with files byte-identical to an uninterrupted render.

use crate::common;

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use envshadow::output::stats::{FrameStats, read_stats};

// Enough frames that the third interruption still finds work left: a run may publish two or
// three frames (two are in flight) before its signal lands, and faster shading made that
// likelier with 8.
const FRAMES: usize = 24;

fn spec(dir: &Path) -> PathBuf {
    let p = dir.join("anim.toml");
    // Each frame takes a fraction of a second (brute force at 200 lights), so a signal sent
    // as soon as the first frame appears lands while later frames are rendering.
    fs::write(
        &p,
        format!(
            "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 200\n[motion]\nframes = {FRAMES}\n\
             [render]\nwidth = 160\nheight = 120\nmethod = \"brute\"\ntile = 32\n"
        ),
    )
    .unwrap();
    p
}

fn frames_done(dir: &Path) -> usize {
    common::file_names(dir)
        .iter()
        .filter(|n| n.starts_with("frame_") && n.ends_with(".png"))
        .count()
}

/// Every file but stats.csv, whose `thread_seconds` column is a timing (and the frame records
/// under `records/`, which hold it too).
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    common::file_names(dir)
        .into_iter()
        .filter(|n| n != "stats.csv" && dir.join(n).is_file())
        .map(|n| {
            let bytes = fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect()
}

/// stats.csv's rows, read by the library's reader, with the seconds (a timing) zeroed.
fn stats_without_time(dir: &Path) -> Vec<FrameStats> {
    let mut rows = read_stats(&dir.join("stats.csv")).unwrap();
    for r in &mut rows {
        r.thread_seconds = 0.0;
    }
    rows
}

fn render(spec: &Path, out: &Path, resume: bool) -> Command {
    let mut cmd = common::bin();
    cmd.arg("render")
        .arg(spec)
        .arg("--out")
        .arg(out)
        .args(["--no-report", "--threads", "2"]);
    if resume {
        cmd.arg("--resume");
    }
    cmd
}

/// Starts a render, waits for one more complete frame than `before`, sends `signal`, and
/// checks the interrupted run's exit code, message and files.
fn interrupt(spec: &Path, out: &Path, signal: &str) {
    let before = frames_done(out);
    let mut child = render(spec, out, before > 0)
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while frames_done(out) <= before {
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "no frame appeared"
        );
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the render ended before it could be interrupted: {status}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let sent = Command::new("kill")
        .args(["-s", signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "SIG{signal}: {err}");
    assert!(
        err.lines()
            .last()
            .unwrap()
            .contains("interrupted; complete frames are kept, run again with --resume"),
        "{err}"
    );
    let files = common::file_names(out);
    assert!(
        !files.iter().any(|n| n.contains(".tmp")),
        "temporaries left after SIG{signal}: {files:?}"
    );
    let done = frames_done(out);
    assert!(
        done < FRAMES,
        "SIG{signal} came too late to interrupt anything"
    );
    // Only complete frames: an EXR for every PNG and the other way round, each readable.
    for f in 0..FRAMES {
        let exr = out.join(format!("frame_{f:04}.exr"));
        let png = out.join(format!("frame_{f:04}.png"));
        assert_eq!(
            exr.exists(),
            png.exists(),
            "frame {f} half written: {files:?}"
        );
        if exr.exists() {
            envshadow::output::exr::read_frame(&exr).unwrap();
            image::open(&png).unwrap();
        }
    }
    assert_eq!(
        stats_without_time(out).len(),
        done,
        "stats.csv rows for the written frames"
    );
}

#[test]
fn interrupted_renders_keep_complete_frames_and_resume_to_identical_files() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let whole = tmp.path().join("whole");
    let o = render(&spec, &whole, false).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let parts = tmp.path().join("parts");
    for signal in ["INT", "TERM", "HUP"] {
        interrupt(&spec, &parts, signal);
    }
    let o = render(&spec, &parts, true).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("already rendered, skipped (--resume)"),
        "{err}"
    );

    let (a, b) = (contents(&whole), contents(&parts));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    // The frames, lights.json and settings.txt.
    assert_eq!(a.len(), 2 * FRAMES + 2, "{:?}", a.keys());
    for (name, bytes) in &a {
        assert!(
            bytes == &b[name],
            "{name} differs after interrupt and resume"
        );
    }
    assert_eq!(stats_without_time(&whole), stats_without_time(&parts));
}
