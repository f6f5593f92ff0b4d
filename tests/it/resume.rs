//! Killing a render at any instant, then running it again with `--resume`: every frame ends
//! byte-identical to an uninterrupted render's, with exactly one `stats.csv` row each and no
//! temporary left; a folder rendered with other settings is refused (issue 20, items 3 and 5).
//! The kills come from strace's fault injection (before each rename, i.e. right after the
//! one before it; a full disk at each write) and at seeded random instants.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use crate::common::{self, Failures};

const FRAMES: usize = 3;

/// A 3-frame shapes turntable into `dir/out`, two frames in flight at once.
fn spec(dir: &Path) -> PathBuf {
    let spec = dir.join("anim.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 40\n[motion]\nframes = 3\n\
         [render]\nwidth = 96\nheight = 64\ntile = 32\nspp = 4\nthreads = 2\n",
    )
    .unwrap();
    spec
}

/// `PROGRAM [PREFIX…] envshadow render SPEC --out OUT --no-report -q`: `program` is the
/// binary itself, or a tool that runs it (strace).
fn command(program: &str, prefix: &[&str], spec: &Path, out: &Path) -> Command {
    let mut c = Command::new(program);
    c.args(prefix);
    if program != env!("CARGO_BIN_EXE_envshadow") {
        c.arg(env!("CARGO_BIN_EXE_envshadow"));
    }
    c.arg("render")
        .arg(spec)
        .arg("--out")
        .arg(out)
        .args(["--no-report", "-q"]);
    c
}

fn render(spec: &Path, out: &Path, extra: &[&str]) -> Output {
    command(env!("CARGO_BIN_EXE_envshadow"), &[], spec, out)
        .args(extra)
        .output()
        .unwrap()
}

/// A render of `spec` into `dir` that must succeed.
fn render_ok(spec: &Path, dir: &Path) {
    let o = render(spec, dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `--resume` into `out` must succeed and leave it as `reference`; what does not goes into
/// `failures` under `label`.
fn resume_matches(failures: &mut Failures, label: &str, spec: &Path, out: &Path, reference: &Path) {
    let again = render(spec, out, &["--resume"]);
    if failures.check(again.status.success(), || {
        format!("{label}: resume failed: {}", stderr(&again))
    }) {
        for d in differences(out, reference) {
            failures.check(false, || format!("{label}: {d}"));
        }
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `stats.csv`'s rows without the timing column, in file order.
fn rows_without_seconds(dir: &Path) -> Vec<String> {
    common::csv_by_name(&dir.join("stats.csv"))
        .into_iter()
        .map(|mut row| {
            row.remove("thread_seconds");
            format!("{row:?}")
        })
        .collect()
}

/// What differs between `out` and the uninterrupted `reference`: frame bytes, rows (one per
/// frame, equal but for the seconds), temporaries left in the folder or its records.
fn differences(out: &Path, reference: &Path) -> Vec<String> {
    let mut diff = Vec::new();
    for f in 0..FRAMES {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            if fs::read(out.join(&name)).ok() != fs::read(reference.join(&name)).ok() {
                diff.push(format!("{name} differs or is missing"));
            }
        }
    }
    let (rows, want) = (rows_without_seconds(out), rows_without_seconds(reference));
    if rows != want {
        diff.push(format!(
            "stats.csv has {} rows, {} expected, or they differ",
            rows.len(),
            want.len()
        ));
    }
    for dir in [out.to_path_buf(), out.join("records")] {
        for n in common::file_names(&dir) {
            if n.ends_with(".tmp") {
                diff.push(format!("{n} left in {}", dir.display()));
            }
        }
    }
    diff
}

/// Runs the render under strace with `inject` (a strace fault-injection expression) into a
/// fresh `out`, then `--resume` without faults; records what differs from `reference`.
/// Returns whether the injection fired (the run did not finish cleanly).
fn fault_then_resume(
    failures: &mut Failures,
    label: &str,
    spec: &Path,
    out: &Path,
    reference: &Path,
    inject: &str,
) -> bool {
    let _ = fs::remove_dir_all(out);
    let strace = ["-f", "-qq", "-o", "/dev/null", "-e", inject];
    let o = command("strace", &strace, spec, out).output().unwrap();
    let fired = !o.status.success();
    // A fault is an error or a kill (exit 0: it never came), never a panic or an abort.
    let code = o.status.code();
    failures.check(matches!(code, None | Some(0) | Some(1)), || {
        format!("{label}: exit {code:?}: {}", stderr(&o))
    });
    resume_matches(failures, label, spec, out, reference);
    fired
}

#[test]
fn a_kill_before_any_rename_or_a_full_disk_at_any_write_then_resume_loses_nothing() {
    if !common::require_tools(common::this_test!(), &["strace"], "apt-get install strace") {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let reference = tmp.path().join("reference");
    render_ok(&spec, &reference);
    let out = tmp.path().join("out");
    let mut failures = Failures::new();
    // strace counts a syscall per thread: the main thread publishes settings.txt and
    // lights.json, the writers then each frame's PNG, record, EXR and stats.csv, a frame's four
    // on one thread, frames on several threads at once. A fault at the n-th call of each
    // thread reaches every publication of every thread.
    let publications = 4 * FRAMES;
    for (syscall, fault) in [("rename", "signal=SIGKILL"), ("write", "error=ENOSPC")] {
        let mut fired = 0;
        for n in 1..=publications + 1 {
            let inject = format!("inject={syscall}:{fault}:when={n}");
            if fault_then_resume(&mut failures, &inject, &spec, &out, &reference, &inject) {
                fired += 1;
            }
        }
        // The n-th call fires where some thread made n: up to the most one thread published
        // (one frame's at least, every frame's at most); one more than all finishes untouched.
        failures.check((4..=publications).contains(&fired), || {
            format!("{syscall} faults that fired: {fired}, expected 4 to {publications}")
        });
    }
    failures.assert_none();
}

#[test]
fn sigkill_at_random_instants_then_resume_loses_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let reference = tmp.path().join("reference");
    render_ok(&spec, &reference);
    let out = tmp.path().join("out");
    let mut failures = Failures::new();
    // Seeded instants over about the length of a render: the outcome must not depend on them.
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    for k in 0..12 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let delay = Duration::from_millis(seed % 400);
        let _ = fs::remove_dir_all(&out);
        let mut child = command(env!("CARGO_BIN_EXE_envshadow"), &[], &spec, &out)
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(delay);
        let _ = child.kill();
        let _ = child.wait();
        let label = format!("kill {k} after {delay:?}");
        resume_matches(&mut failures, &label, &spec, &out, &reference);
    }
    failures.assert_none();
}

#[test]
fn resume_refuses_a_folder_rendered_with_other_settings_naming_the_first_difference() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = tmp.path().join("out");
    let o = render(&spec, &out, &["--frames", "0..2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before: Vec<(String, Vec<u8>)> = common::file_names(&out)
        .into_iter()
        .filter(|n| n.starts_with("frame_") || n == "stats.csv")
        .map(|n| (n.clone(), fs::read(out.join(&n)).unwrap()))
        .collect();
    let mut failures = Failures::new();
    for (flags, named) in [
        (&["--width", "128"][..], "[render] width = 96, now 128"),
        (&["--lights", "20"][..], "[lights] count = 40, now 20"),
        (
            &["--method", "brute"][..],
            "[render] method = grid-nowarp-uncertainty, now brute",
        ),
        (&["--validate"][..], "[render] validate = false, now true"),
    ] {
        let mut args = vec!["--resume"];
        args.extend_from_slice(flags);
        let o = render(&spec, &out, &args);
        let err = stderr(&o);
        failures.check(
            o.status.code() == Some(2) && err.contains(named) && err.contains("cannot resume"),
            || format!("{flags:?}: exit {:?}: {err}", o.status.code()),
        );
    }
    // Refused runs changed nothing; the same settings resume, and threads and tiles, which
    // change no pixel, are free.
    for (name, bytes) in &before {
        failures.check(
            fs::read(out.join(name)).ok().as_ref() == Some(bytes),
            || format!("{name} changed by a refused resume"),
        );
    }
    let o = render(&spec, &out, &["--resume", "--threads", "1", "--tile", "0"]);
    failures.check(o.status.success(), || {
        format!("same settings: {}", stderr(&o))
    });
    failures.check_eq(rows_without_seconds(&out).len(), FRAMES, || {
        "rows after the resume".into()
    });
    // Without --resume, other settings render the frames again (and become the folder's).
    let o = render(&spec, &out, &["--width", "128"]);
    failures.check(o.status.success(), || format!("no resume: {}", stderr(&o)));
    let settings = fs::read_to_string(out.join("settings.txt")).unwrap_or_default();
    failures.check(settings.contains("[render] width = 128"), || {
        format!("settings.txt not updated: {settings}")
    });
    failures.assert_none();
}

/// A frame whose EXR or PNG no longer matches its record (corrupted, truncated, replaced) is
/// rendered again by `--resume`; the frames that match are not touched.
#[test]
fn resume_renders_again_exactly_the_frames_whose_files_do_not_match_their_record() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = tmp.path().join("out");
    render_ok(&spec, &out);
    let reference = tmp.path().join("reference");
    render_ok(&spec, &reference);
    // Same-size corruption of frame 0's EXR, a truncated PNG of frame 1; frame 2 untouched.
    let exr0 = out.join("frame_0000.exr");
    let mut bytes = fs::read(&exr0).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0xff;
    fs::write(&exr0, &bytes).unwrap();
    let png1 = out.join("frame_0001.png");
    let len = fs::metadata(&png1).unwrap().len();
    fs::File::options()
        .write(true)
        .open(&png1)
        .unwrap()
        .set_len(len / 2)
        .unwrap();
    let untouched = fs::metadata(out.join("frame_0002.exr"))
        .unwrap()
        .modified()
        .unwrap();
    std::thread::sleep(Duration::from_millis(20));
    let o = render(&spec, &out, &["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut failures = Failures::new();
    for d in differences(&out, &reference) {
        failures.check(false, || d);
    }
    failures.check(
        fs::metadata(out.join("frame_0002.exr"))
            .unwrap()
            .modified()
            .unwrap()
            == untouched,
        || "frame 2 matched its record but was rendered again".into(),
    );
    failures.assert_none();
}

/// A farm's assembled folder is the folder a one-process render leaves: `settings.txt` and
/// each frame with its record, so `render --resume` into it renders nothing again.
#[test]
fn an_assembled_farm_folder_resumes_as_a_one_process_render() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = tmp.path().join("out");
    let o_str = out.to_str().unwrap();
    let run = |args: &[&str]| {
        let o = common::bin().args(args).output().unwrap();
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        stderr(&o)
    };
    let spec_str = spec.to_str().unwrap();
    run(&["plan", spec_str, "--jobs", "2", "--out", o_str]);
    for k in ["0", "1"] {
        run(&[
            "render", spec_str, "--job", k, "--of", "2", "--out", o_str, "-q",
        ]);
    }
    run(&["assemble", o_str]);
    let reference = tmp.path().join("reference");
    render_ok(&spec, &reference);
    assert_eq!(
        fs::read_to_string(out.join("settings.txt")).unwrap(),
        fs::read_to_string(reference.join("settings.txt")).unwrap()
    );
    let log = run(&[
        "render",
        spec_str,
        "--out",
        o_str,
        "--resume",
        "--no-report",
    ]);
    assert!(log.contains("0 frames rendered, 3 skipped"), "{log}");
    let diff = differences(&out, &reference);
    assert!(diff.is_empty(), "{diff:?}");
}
