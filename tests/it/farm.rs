//! Rendering on several machines: plan / job / assemble, and scripts/farm.sh over three sshd
//! "hosts" on loopback (127.0.0.2–4; tests/farm-hosts.sh starts and stops them by PID).
//! Every farm render must equal a one-process render byte for byte.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use envshadow::output::stats::{FrameStats, read_stats};

use crate::common;

const BIN: &str = env!("CARGO_BIN_EXE_envshadow");
const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const SPEC: &str = "anims/shapes-turntable.toml";
/// 8 frames of the shapes turntable, small enough to keep the farm test to seconds.
const FLAGS: &[&str] = &[
    "--frames",
    "0..8",
    "--width",
    "160",
    "--height",
    "120",
    "--lights",
    "50",
    "--tile",
    "32",
    "--threads",
    "1",
];

pub(crate) fn envshadow(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(ROOT)
        .output()
        .expect("running envshadow")
}

pub(crate) fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "exit {:?}\nstdout: {}\nstderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A one-process render of the test frames into `dir`.
fn reference(dir: &Path) {
    let mut args = vec![
        "render",
        SPEC,
        "--out",
        dir.to_str().unwrap(),
        "--no-report",
        "-q",
    ];
    args.extend_from_slice(FLAGS);
    ok(&envshadow(&args));
}

/// Every frame file of `reference` exists in `dir` with the same bytes.
fn assert_same_frames(reference: &Path, dir: &Path) {
    let mut n = 0;
    for f in 0..8 {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            let a = fs::read(reference.join(&name)).unwrap();
            let b = fs::read(dir.join(&name))
                .unwrap_or_else(|e| panic!("{}: {e}", dir.join(&name).display()));
            assert!(a == b, "{name} differs from the one-process render");
            n += 1;
        }
    }
    assert_eq!(n, 16);
    assert_eq!(
        fs::read(reference.join("lights.json")).unwrap(),
        fs::read(dir.join("lights.json")).unwrap()
    );
}

/// stats.csv's rows, read by the library's reader, with the seconds zeroed (wall-clock time
/// differs between runs).
fn stats_without_seconds(dir: &Path) -> Vec<FrameStats> {
    let mut rows = read_stats(&dir.join("stats.csv")).unwrap();
    for r in &mut rows {
        r.thread_seconds = 0.0;
    }
    rows
}

#[test]
fn jobs_assemble_into_the_one_process_render_and_name_what_is_missing() {
    let tmp = tempfile::tempdir().unwrap();
    let (refdir, out) = (tmp.path().join("ref"), tmp.path().join("farm"));
    reference(&refdir);
    let o = out.to_str().unwrap();
    let mut plan = vec!["plan", SPEC, "--out", o, "--jobs", "4", "--by", "both"];
    plan.extend_from_slice(FLAGS);
    let planned = envshadow(&plan);
    ok(&planned);
    let lines = String::from_utf8_lossy(&planned.stdout).into_owned();
    assert_eq!(lines, fs::read_to_string(out.join("jobs.txt")).unwrap());
    assert_eq!(lines.lines().count(), 4);
    for k in 0..4 {
        let ks = k.to_string();
        let mut job = vec![
            "render", SPEC, "--out", o, "--job", &ks, "--of", "4", "--by", "both", "-q",
        ];
        job.extend_from_slice(FLAGS);
        ok(&envshadow(&job));
    }
    ok(&envshadow(&["assemble", o, "--no-report"]));
    assert_same_frames(&refdir, &out);
    assert_eq!(stats_without_seconds(&refdir), stats_without_seconds(&out));

    // An explicit --frames/--tiles job lands in the folder of the planned job it equals.
    let first = lines.lines().next().unwrap();
    let cols: Vec<&str> = first.split('\t').collect();
    let folder = out.join("jobs").join(cols[3]);
    let before = fs::read(folder.join("tiles_0001.exr")).unwrap();
    fs::remove_file(folder.join("tiles_0001.exr")).unwrap();
    let mut explicit = vec![
        "render", SPEC, "--out", o, "--tiles", cols[2], "--resume", "-q",
    ];
    explicit.extend_from_slice(FLAGS);
    let frames_at = explicit.iter().position(|a| *a == "--frames").unwrap();
    explicit[frames_at + 1] = cols[1];
    let o2 = envshadow(&explicit);
    ok(&o2);
    assert_eq!(fs::read(folder.join("tiles_0001.exr")).unwrap(), before);

    // Break three jobs three ways: assemble names each, exits 2, and writes the rest.
    let folders: Vec<String> = lines
        .lines()
        .map(|l| l.split('\t').nth(3).unwrap().to_string())
        .collect();
    fs::remove_dir_all(out.join("jobs").join(&folders[1])).unwrap();
    let broken = out.join("jobs").join(&folders[2]).join("tiles_0004.exr");
    let mut exr = fs::read(&broken).unwrap();
    let mid = exr.len() / 2;
    exr[mid] ^= 0xff;
    fs::write(&broken, exr).unwrap();
    fs::remove_file(out.join("jobs").join(&folders[3]).join("tiles_0005.json")).unwrap();
    for f in 0..8 {
        let _ = fs::remove_file(out.join(format!("frame_{f:04}.exr")));
    }
    let bad = envshadow(&["assemble", o, "--no-report"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("missing job 1 ") && err.contains(&folders[1]),
        "{err}"
    );
    assert!(
        err.contains("corrupt job 2 ") && err.contains("checksum"),
        "{err}"
    );
    assert!(
        err.contains("incomplete job 3 ") && err.contains("frames 5 not"),
        "{err}"
    );
    assert!(!err.contains("job 0 "), "{err}");
    // Job 1 owns frames 0..4 of the `both` split (2 frame ranges × 2 strips): those frames
    // cannot be assembled; frames 6 and 7 owe nothing to the broken jobs.
    assert!(!out.join("frame_0000.exr").exists());
    assert!(out.join("frame_0007.exr").exists());
}

/// Cryptomatte through jobs: each job publishes the ID mattes' manifests beside its tiles
/// (assembling never loads the scene, and refused `--cryptomatte` for want of them), and the
/// assembled frames are the one-process render's bytes; a job without the manifests is named.
#[test]
fn cryptomatte_jobs_assemble_into_the_one_process_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let (refdir, out) = (tmp.path().join("ref"), tmp.path().join("farm"));
    let mut flags: Vec<&str> = FLAGS.to_vec();
    flags[1] = "0..2";
    flags.push("--cryptomatte");
    let (r, o) = (refdir.to_str().unwrap(), out.to_str().unwrap());
    let mut one = vec!["render", SPEC, "--out", r, "--no-report", "-q"];
    one.extend_from_slice(&flags);
    ok(&envshadow(&one));
    let mut plan = vec!["plan", SPEC, "--out", o, "--jobs", "2", "--by", "tiles"];
    plan.extend_from_slice(&flags);
    ok(&envshadow(&plan));
    for k in ["0", "1"] {
        let mut job = vec![
            "render", SPEC, "--out", o, "--job", k, "--of", "2", "--by", "tiles", "-q",
        ];
        job.extend_from_slice(&flags);
        ok(&envshadow(&job));
    }
    ok(&envshadow(&["assemble", o, "--no-report"]));
    for f in 0..2 {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            let same = fs::read(refdir.join(&name)).unwrap() == fs::read(out.join(&name)).unwrap();
            assert!(same, "{name} differs from the one-process render");
        }
    }
    let folder = fs::read_dir(out.join("jobs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.join("cryptomatte.json").exists())
        .expect("a job folder with cryptomatte.json");
    fs::remove_file(folder.join("cryptomatte.json")).unwrap();
    let bad = envshadow(&["assemble", o, "--no-report"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("no cryptomatte.json"), "{err}");
}

/// Issue 39: the loader's warnings (here a base colour factor clamped and an ignored
/// extension) reach an assembled farm render's `settings.txt` and frame headers
/// (`envshadow/warnings.N`) as they reach a one-process render's: the jobs keep them in
/// `job.json`, since assembling loads no inputs. Before, the farm's frames lost them.
#[test]
fn loader_warnings_reach_the_assembled_settings_and_frame_headers() {
    let tmp = tempfile::tempdir().unwrap();
    let t = |name: &str| tmp.path().join(name).to_str().unwrap().to_string();
    let text = fs::read_to_string(Path::new(ROOT).join("tests/data/formats/cube.gltf")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] =
        serde_json::json!([1.5, 0.5, 0.25, 1.0]);
    doc["extensionsUsed"] = serde_json::json!(["EXT_not_a_real_extension"]);
    fs::write(tmp.path().join("cube.gltf"), doc.to_string()).unwrap();
    let flags = [
        "--width",
        "64",
        "--height",
        "48",
        "--lights",
        "20",
        "--tile",
        "32",
        "--threads",
        "1",
    ];
    let (model, cube, r, o) = (t("cube.gltf"), t("cube.toml"), t("ref"), t("farm"));
    let mut spec = vec!["render", &model, "--write-spec", &cube, "-q"];
    spec.extend_from_slice(&flags);
    ok(&envshadow(&spec));
    let run = |args: &[&str]| {
        let mut v = args.to_vec();
        v.extend_from_slice(&["--frames", "0..2"]);
        v.extend_from_slice(&flags);
        ok(&envshadow(&v));
    };
    run(&["render", &cube, "--out", &r, "--no-report", "-q"]);
    run(&[
        "plan", &cube, "--out", &o, "--jobs", "2", "--by", "tiles", "-q",
    ]);
    for k in ["0", "1"] {
        run(&[
            "render", &cube, "--out", &o, "--job", k, "--of", "2", "--by", "tiles", "-q",
        ]);
    }
    ok(&envshadow(&["assemble", &o, "--no-report"]));
    let (refdir, out) = (Path::new(&r), Path::new(&o));
    let settings = fs::read_to_string(refdir.join("settings.txt")).unwrap();
    assert!(
        settings.contains("[warnings] 1 = ") && settings.contains("clamped"),
        "{settings}"
    );
    assert!(settings.contains("EXT_not_a_real_extension"), "{settings}");
    assert_eq!(
        settings,
        fs::read_to_string(out.join("settings.txt")).unwrap()
    );
    for f in 0..2 {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            let a = fs::read(refdir.join(&name)).unwrap();
            let b = fs::read(out.join(&name)).unwrap();
            assert!(a == b, "{name} differs from the one-process render");
        }
        let exr = fs::read(out.join(format!("frame_{f:04}.exr"))).unwrap();
        let key = b"envshadow/warnings.1";
        assert!(
            exr.windows(key.len()).any(|w| w == key),
            "frame {f}: no {key:?}"
        );
    }
}

/// Issue 20, item 1: `render --job K --of N --resume` renders again exactly the frames whose
/// files are missing, truncated or corrupt (the SHA-256 that tiles_NNNN.json records is
/// checked, not only the size), and `assemble --pending` names the jobs a re-run must render.
#[test]
fn a_job_resume_renders_again_only_its_damaged_frames_and_pending_names_the_jobs() {
    let tmp = tempfile::tempdir().unwrap();
    let (refdir, out) = (tmp.path().join("ref"), tmp.path().join("farm"));
    reference(&refdir);
    let o = out.to_str().unwrap();
    let mut plan = vec!["plan", SPEC, "--out", o, "--jobs", "4", "-q"];
    plan.extend_from_slice(FLAGS);
    ok(&envshadow(&plan));
    let job = |k: usize| {
        let ks = k.to_string();
        let mut a = vec![
            "render", SPEC, "--out", o, "--job", &ks, "--of", "4", "--resume",
        ];
        a.extend_from_slice(FLAGS);
        ok(&envshadow(&a))
    };
    for k in 0..4 {
        job(k);
    }
    let folders = planned_folders(&out);
    flip_a_byte(&folders[0].join("tiles_0001.exr"));
    truncate_half(&folders[1].join("tiles_0002.exr"));
    fs::remove_file(folders[2].join("tiles_0003.exr")).unwrap();
    let before = stamps(&out.join("jobs"));
    for (k, want) in [
        "1 frames rendered, 7 skipped",
        "1 frames rendered, 7 skipped",
        "1 frames rendered, 7 skipped",
        "0 frames rendered, 8 skipped",
    ]
    .iter()
    .enumerate()
    {
        let err = job(k);
        assert!(err.contains(want), "job {k}: {err}");
    }
    for (path, st) in &before {
        let name = path.file_name().unwrap().to_string_lossy();
        if name.starts_with("tiles_")
            && !["tiles_0001", "tiles_0002", "tiles_0003"]
                .iter()
                .any(|f| name.starts_with(f))
        {
            assert_eq!(stamp(path), *st, "{} was written again", path.display());
        }
    }
    ok(&envshadow(&["assemble", o, "--no-report"]));
    assert_same_frames(&refdir, &out);

    // Nothing to do: --pending prints nothing. Then three jobs damaged three other ways.
    let pending = |what: &str| {
        let p = envshadow(&["assemble", o, "--pending"]);
        let err = ok(&p);
        assert!(err.contains(what), "{err}");
        (String::from_utf8_lossy(&p.stdout).into_owned(), err)
    };
    let (lines, _) = pending("0 of 4 jobs to render (8 of 8 frames complete)");
    assert_eq!(lines, "");
    flip_a_byte(&folders[1].join("tiles_0006.exr"));
    fs::remove_file(folders[2].join("lights.json")).unwrap();
    fs::remove_dir_all(&folders[3]).unwrap();
    let (lines, err) = pending("3 of 4 jobs to render (0 of 8 frames complete)");
    let planned: Vec<String> = fs::read_to_string(out.join("jobs.txt"))
        .unwrap()
        .lines()
        .map(|l| format!("{l}\n"))
        .collect();
    assert_eq!(lines, planned[1..].concat());
    assert!(
        err.contains("corrupt job 1 ") && err.contains("tiles_0006.exr: checksum mismatch"),
        "{err}"
    );
    assert!(
        err.contains("bad job 2 ") && err.contains("no lights.json"),
        "{err}"
    );
    assert!(err.contains("missing job 3 "), "{err}");
    assert!(!err.contains("job 0 "), "{err}");
}

/// A file as it lies on disk: (inode, modification time in ns, length). A file written again
/// gets another inode even with the same bytes (files are published by renaming a new one).
fn stamp(p: &Path) -> (u64, i128, u64) {
    let m = fs::metadata(p).unwrap();
    (
        m.ino(),
        m.mtime() as i128 * 1_000_000_000 + m.mtime_nsec() as i128,
        m.len(),
    )
}

/// [`stamp`] of every file under `dir`, by path.
fn stamps(dir: &Path) -> BTreeMap<PathBuf, (u64, i128, u64)> {
    walk(dir)
        .into_iter()
        .filter(|p| p.is_file())
        .map(|p| {
            let s = stamp(&p);
            (p, s)
        })
        .collect()
}

/// The job folders of `out`'s plan, by job index (from jobs.txt).
fn planned_folders(out: &Path) -> Vec<PathBuf> {
    fs::read_to_string(out.join("jobs.txt"))
        .unwrap()
        .lines()
        .map(|l| out.join("jobs").join(l.split('\t').nth(3).unwrap()))
        .collect()
}

/// Flips one byte in the middle of `p`: same size, other content.
fn flip_a_byte(p: &Path) {
    let mut bytes = fs::read(p).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0xff;
    fs::write(p, bytes).unwrap();
}

/// Cuts `p` to half its size.
fn truncate_half(p: &Path) {
    let f = fs::OpenOptions::new().write(true).open(p).unwrap();
    let len = f.metadata().unwrap().len();
    f.set_len(len / 2).unwrap();
}

#[test]
fn plan_refuses_tiles_of_frames_and_bad_jobs() {
    let tmp = tempfile::tempdir().unwrap();
    let o = tmp.path().join("x");
    let o = o.to_str().unwrap();
    let mut a = vec!["render", SPEC, "--out", o, "--job", "9", "--of", "4"];
    a.extend_from_slice(FLAGS);
    let r = envshadow(&a);
    assert_eq!(r.status.code(), Some(2));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("job 9 does not exist"), "{err}");
    let mut a = vec!["render", SPEC, "--out", o, "--tiles", "0-99"];
    a.extend_from_slice(FLAGS);
    let r = envshadow(&a);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("tile 99 does not exist"));
    let r = envshadow(&["plan", SPEC, "--out", o, "--jobs", "0"]);
    assert_eq!(r.status.code(), Some(2));
    let r = envshadow(&["assemble", tmp.path().to_str().unwrap()]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("nothing to assemble"));
    let v = envshadow(&["version", "--build"]);
    let line = String::from_utf8_lossy(&v.stdout).trim().to_string();
    assert!(
        line.starts_with("envshadow ") && line.contains(" build "),
        "{line}"
    );
}

// ---- the ssh farm ----

/// Three pretend hosts; stopped (by PID) when dropped, even when the test fails.
struct Hosts {
    dir: PathBuf,
}

impl Hosts {
    fn start(dir: &Path) -> Hosts {
        let o = Command::new("bash")
            .arg(Path::new(ROOT).join("tests/farm-hosts.sh"))
            .args(["start", dir.to_str().unwrap(), "3"])
            .output()
            .unwrap();
        let hosts = Hosts {
            dir: dir.to_path_buf(),
        };
        ok(&o);
        hosts
    }
    fn crash(&self, k: usize) {
        ok(&Command::new("bash")
            .arg(Path::new(ROOT).join("tests/farm-hosts.sh"))
            .args(["crash", self.dir.to_str().unwrap(), &k.to_string()])
            .output()
            .unwrap());
    }
}

impl Drop for Hosts {
    fn drop(&mut self) {
        let _ = Command::new("bash")
            .arg(Path::new(ROOT).join("tests/farm-hosts.sh"))
            .args(["stop", self.dir.to_str().unwrap()])
            .status();
    }
}

/// What the ssh farm test runs: GNU parallel and rsync (scripts/farm.sh), ssh, ssh-keygen,
/// pgrep and sshd (tests/farm-hosts.sh, which starts /usr/sbin/sshd by path).
const FARM_TOOLS: &[&str] = &[
    "parallel",
    "ssh",
    "ssh-keygen",
    "rsync",
    "pgrep",
    "/usr/sbin/sshd",
];

/// `scripts/farm.sh SPEC --hosts … --out OUT EXTRA -- FLAGS` with this test binary, not
/// waited for.
fn farm(hosts: &Hosts, out: &Path, extra: &[&str]) -> Running {
    farm_with(Path::new(BIN), hosts, out, extra)
}

/// [`farm`] with another envshadow binary (`ENVSHADOW`).
fn farm_with(bin: &Path, hosts: &Hosts, out: &Path, extra: &[&str]) -> Running {
    let mut c = Command::new("bash");
    c.arg(Path::new(ROOT).join("scripts/farm.sh"))
        .arg(SPEC)
        .args(["--hosts", hosts.dir.join("hosts").to_str().unwrap()])
        .args(["--out", out.to_str().unwrap()])
        .args([
            "--ssh",
            &format!("ssh -F {}", hosts.dir.join("ssh_config").display()),
        ])
        .args(["--timeout", "120"])
        .args(extra)
        .arg("--")
        .args(FLAGS)
        .current_dir(ROOT)
        .env("ENVSHADOW", bin)
        .env("PARALLEL_HOME", hosts.dir.join("parallel-home"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = c.spawn().expect("starting scripts/farm.sh");
    let out = drain(child.stdout.take().expect("farm.sh's stdout"));
    let err = drain(child.stderr.take().expect("farm.sh's stderr"));
    Running { child, out, err }
}

/// A farm.sh run: its process, and threads reading its stdout and stderr as it writes them.
/// A pipe nobody reads fills at 64 KiB and then blocks the writer: farm.sh copies parallel's
/// and ssh's messages to its stderr, which the tests used to read only at the end: with the
/// filter blocked, nothing more would reach farm.log, which some tests wait on.
struct Running {
    child: Child,
    out: std::thread::JoinHandle<Vec<u8>>,
    err: std::thread::JoinHandle<Vec<u8>>,
}

impl Running {
    fn id(&self) -> u32 {
        self.child.id()
    }
}

/// Reads `pipe` to its end on a thread of its own.
fn drain(mut pipe: impl std::io::Read + Send + 'static) -> std::thread::JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = pipe.read_to_end(&mut bytes);
        bytes
    })
}

/// One attempt in GNU parallel's job log.
#[derive(Clone, Debug)]
struct Attempt {
    host: String,
    exit: i32,
    signal: i32,
    /// Start time, Unix seconds.
    start: f64,
    /// The plan job it ran (`--job K` in its command).
    job: usize,
}

/// The jobs attempted after the first `first` attempts of the job log (a re-run's), in order.
fn jobs_run_since(out: &Path, first: usize) -> Vec<usize> {
    joblog(out)[first..].iter().map(|a| a.job).collect()
}

/// The job log's attempts, every run's (farm.sh appends), columns found by the names in its
/// header line. A line still being written is skipped (the log is read while parallel runs).
fn joblog(out: &Path) -> Vec<Attempt> {
    let Ok(text) = fs::read_to_string(out.join("logs/joblog")) else {
        return Vec::new();
    };
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split('\t').collect();
    let col = |name: &str| header.iter().position(|h| h.trim() == name);
    let (Some(host), Some(exit), Some(signal), Some(start), Some(command)) = (
        col("Host"),
        col("Exitval"),
        col("Signal"),
        col("Starttime"),
        col("Command"),
    ) else {
        return Vec::new();
    };
    lines
        .filter_map(|l| {
            let c: Vec<&str> = l.split('\t').collect();
            let cmd = c.get(command..)?.join("\t");
            let job = cmd
                .split("--job ")
                .nth(1)?
                .split(' ')
                .next()?
                .parse()
                .ok()?;
            Some(Attempt {
                host: c.get(host)?.trim().to_string(),
                exit: c.get(exit)?.trim().parse().ok()?,
                signal: c.get(signal)?.trim().parse().ok()?,
                start: c.get(start)?.trim().parse().ok()?,
                job,
            })
        })
        .collect()
}

/// Waits until `cond` holds, looking every 20 ms. What is waited for is an event (a file, a
/// log line); the two minutes only turn a hang into a failure.
fn wait_until(what: &str, mut cond: impl FnMut() -> bool) {
    let start = Instant::now();
    while !cond() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "waited two minutes for {what}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A stand-in for envshadow on the hosts (`farm.sh --envshadow`) that holds jobs at a known
/// point, so a test can act while they surely run: each `render` writes `started.PID` (the
/// host's name) into the gate's folder and waits until `open` exists there — before it
/// renders, or (`after`) once the job's files are written. Anything else (the build check)
/// goes straight to the test binary.
struct Gate {
    dir: PathBuf,
    script: PathBuf,
}

impl Gate {
    fn new(dir: &Path, after: bool) -> Gate {
        fs::create_dir_all(dir).unwrap();
        let script = dir.with_extension("sh");
        let (before, after) = if after {
            ("false", "true")
        } else {
            ("true", "false")
        };
        fs::write(
            &script,
            format!(
                "#!/bin/sh\n\
                 g='{g}'\n\
                 if [ \"$1\" = render ]; then\n\
                 \x20   if {after}; then '{bin}' \"$@\" || exit $?; fi\n\
                 \x20   echo \"${{PARALLEL_SSHHOST:-?}}\" >\"$g/.started.$$\" && mv \"$g/.started.$$\" \"$g/started.$$\"\n\
                 \x20   while [ ! -e \"$g/open\" ]; do sleep 0.02; done\n\
                 \x20   if {before}; then exec '{bin}' \"$@\"; fi\n\
                 \x20   exit 0\n\
                 fi\n\
                 exec '{bin}' \"$@\"\n",
                g = dir.display(),
                bin = BIN,
            ),
        )
        .unwrap();
        fs::set_permissions(&script, fs::Permissions::from_mode(0o755)).unwrap();
        Gate {
            dir: dir.to_path_buf(),
            script,
        }
    }

    fn path(&self) -> &str {
        self.script.to_str().unwrap()
    }

    /// The hosts of the renders that reached the gate so far, one per render.
    fn started(&self) -> Vec<String> {
        common::file_names(&self.dir)
            .into_iter()
            .filter(|n| n.starts_with("started."))
            .map(|n| {
                fs::read_to_string(self.dir.join(n))
                    .unwrap()
                    .trim()
                    .to_string()
            })
            .collect()
    }

    fn open(&self) {
        fs::write(self.dir.join("open"), "").unwrap();
    }
}

fn finish(run: Running) -> (Option<i32>, String) {
    let Running {
        mut child,
        out,
        err,
    } = run;
    let status = child.wait().unwrap();
    let (out, err) = (out.join().unwrap(), err.join().unwrap());
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out),
        String::from_utf8_lossy(&err)
    );
    (status.code(), text)
}

#[test]
fn farm_over_ssh_renders_the_same_frames_survives_a_crash_and_resumes() {
    if !common::require_tools(
        common::this_test!(),
        FARM_TOOLS,
        "apt-get install openssh-server openssh-client parallel rsync procps",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let refdir = tmp.path().join("ref");
    reference(&refdir);
    let hdir = tmp.path().join("hosts");
    fs::create_dir_all(&hdir).unwrap();
    let hosts = Hosts::start(&hdir);

    // Shared filesystem: every host runs this very binary by path.
    let out = tmp.path().join("shared");
    let (code, log) = finish(farm(&hosts, &out, &["--shared-fs", "--jobs", "6"]));
    assert_eq!(code, Some(0), "{log}");
    assert_same_frames(&refdir, &out);
    assert_eq!(stats_without_seconds(&refdir), stats_without_seconds(&out));
    assert!(log.contains("per-host logs in"), "{log}");
    let hosts_used: BTreeSet<String> = joblog(&out).into_iter().map(|a| a.host).collect();
    assert!(hosts_used.len() >= 2, "jobs ran on {hosts_used:?}");

    // No shared filesystem: binary and spec shipped, job folders returned, hosts cleaned.
    let out = tmp.path().join("unshared");
    let unshared = ["--no-shared-fs", "--jobs", "6"];
    let clean = || {
        for k in 1..=3 {
            let left: Vec<_> = walk(&hdir.join(format!("h{k}/home")));
            assert!(left.is_empty(), "left on host {k}: {left:?}");
        }
    };
    let (code, log) = finish(farm(&hosts, &out, &unshared));
    assert_eq!(code, Some(0), "{log}");
    assert_same_frames(&refdir, &out);
    clean();
    // A frame damaged here: the job runs again with what its folder holds, so the host
    // renders that frame only.
    truncate_half(&planned_folders(&out)[2].join("tiles_0004.exr"));
    let summaries = |out: &Path| -> Vec<String> {
        let mut v = Vec::new();
        for p in walk(&out.join("logs/hosts")) {
            let text = fs::read_to_string(&p).unwrap();
            v.extend(
                text.lines()
                    .filter(|l| l.contains(" frames rendered, "))
                    .map(str::to_string),
            );
        }
        v
    };
    let before = summaries(&out).len();
    let (code, log) = finish(farm(&hosts, &out, &unshared));
    assert_eq!(code, Some(0), "{log}");
    assert_same_frames(&refdir, &out);
    clean();
    let after = summaries(&out);
    assert_eq!(after.len(), before + 1, "{after:?}");
    assert_eq!(
        after
            .iter()
            .filter(|l| l.contains("job 2 ") && l.contains("1 frames rendered, 7 skipped"))
            .count(),
        1,
        "{after:?}"
    );

    // A host with another build is refused, by name, before any job starts.
    for k in 1..=3 {
        let b = hdir.join(format!("h{k}/bin/envshadow"));
        if k == 3 {
            // Another build says so: the identity is no longer the executable's hash.
            fs::write(
                &b,
                format!(
                    "#!/bin/sh\nif [ \"$1\" = version ]; then echo 'envshadow 0.1.0 build 0000000000000000'; exit 0; fi\nexec '{BIN}' \"$@\"\n"
                ),
            )
            .unwrap();
            fs::set_permissions(&b, fs::Permissions::from_mode(0o755)).unwrap();
        } else {
            std::os::unix::fs::symlink(BIN, &b).unwrap();
        }
    }
    let out = tmp.path().join("refused");
    let (code, log) = finish(farm(
        &hosts,
        &out,
        &["--envshadow", "envshadow", "--jobs", "6"],
    ));
    assert_eq!(code, Some(2), "{log}");
    assert!(
        log.contains("host fh3 runs envshadow 0.1.0 build 0000000000000000")
            && log.contains("refus"),
        "{log}"
    );
    assert!(
        !log.contains("host fh1 runs") && !log.contains("host fh2 runs"),
        "{log}"
    );
    assert!(!out.join("logs/joblog").exists() && !out.join("jobs").exists());

    // A host crashes mid-run (its sshd and every process under it): the jobs are retried on
    // the others and the frames are still the same. Jobs are held at the gate until one is
    // surely running on fh3; the host falls, then the gate opens.
    let gate = Gate::new(&tmp.path().join("crash-gate"), false);
    let out = tmp.path().join("crash");
    let child = farm(
        &hosts,
        &out,
        &["--envshadow", gate.path(), "--jobs", "12", "--by", "both"],
    );
    wait_until("a job on fh3", || gate.started().iter().any(|h| h == "fh3"));
    hosts.crash(3);
    let crashed_at = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_secs_f64();
    gate.open();
    let (code, log) = finish(child);
    assert_eq!(code, Some(0), "{log}");
    assert_same_frames(&refdir, &out);
    // The job log keeps each job's last attempt: the run went on after the crash, every job
    // succeeded, and none of them on the crashed host after it fell.
    let attempts = joblog(&out);
    let after: Vec<_> = attempts.iter().filter(|a| a.start > crashed_at).collect();
    assert!(!after.is_empty(), "{attempts:?}");
    assert!(after.iter().all(|a| a.host != "fh3"), "{attempts:?}");
    assert!(
        attempts.iter().all(|a| a.exit == 0 && a.signal == 0),
        "{attempts:?}"
    );
    let jobs: BTreeSet<usize> = attempts.iter().map(|a| a.job).collect();
    assert_eq!(jobs.len(), planned_folders(&out).len());
    drop(hosts);
}

/// The hosts, the reference render and a temporary folder for one ssh farm test; None when
/// the tools are missing (see `common::require_tools`).
fn farm_setup(test: &str) -> Option<(tempfile::TempDir, PathBuf, Hosts)> {
    if !common::require_tools(
        test,
        FARM_TOOLS,
        "apt-get install openssh-server openssh-client parallel rsync procps",
    ) {
        return None;
    }
    let tmp = tempfile::tempdir().unwrap();
    let refdir = tmp.path().join("ref");
    reference(&refdir);
    let hdir = tmp.path().join("hosts");
    fs::create_dir_all(&hdir).unwrap();
    let hosts = Hosts::start(&hdir);
    Some((tmp, refdir, hosts))
}

/// Issue 20, item 9: SIGHUP lets running jobs finish and starts no new one; the same command
/// again runs exactly the jobs that did not run. Deterministic: the jobs are held at a gate
/// until GNU parallel has said that it took the signal, so no job can end (and free a slot for
/// another) before then, however fast or loaded the machine.
#[test]
fn sighup_lets_running_jobs_finish_and_the_same_command_renders_the_rest() {
    let Some((tmp, refdir, hosts)) = farm_setup(common::this_test!()) else {
        return;
    };
    let gate = Gate::new(&tmp.path().join("gate"), false);
    let out = tmp.path().join("hup");
    let args = ["--envshadow", gate.path(), "--jobs", "12", "--by", "both"];
    let child = farm(&hosts, &out, &args);
    wait_until("a job to start", || !gate.started().is_empty());
    let _ = Command::new("kill")
        .args(["-HUP", &child.id().to_string()])
        .status();
    wait_until("GNU parallel to take the SIGHUP", || {
        fs::read_to_string(out.join("logs/farm.log"))
            .is_ok_and(|l| l.contains("SIGHUP received. No new jobs will be started"))
    });
    gate.open();
    let (code, log) = finish(child);
    assert_eq!(code, Some(129), "{log}");
    let first = joblog(&out);
    let total = planned_folders(&out).len();
    let done: BTreeSet<usize> = first
        .iter()
        .filter(|a| a.exit == 0)
        .map(|a| a.job)
        .collect();
    // Exactly the jobs that had started ran, each to its end.
    assert_eq!(first.len(), gate.started().len(), "{first:?}");
    assert_eq!(done.len(), first.len(), "{first:?}");
    assert!(
        !done.is_empty() && done.len() < total,
        "{done:?} of {total}"
    );

    let (code, log) = finish(farm(&hosts, &out, &args));
    assert_eq!(code, Some(0), "{log}");
    assert!(log.contains("resuming"), "{log}");
    let rerun = jobs_run_since(&out, first.len());
    let rerun_set: BTreeSet<usize> = rerun.iter().copied().collect();
    assert_eq!(rerun.len(), rerun_set.len(), "a job ran twice: {rerun:?}");
    let missing: BTreeSet<usize> = (0..total).filter(|j| !done.contains(j)).collect();
    assert_eq!(
        rerun_set, missing,
        "the re-run must run exactly the missing jobs"
    );
    assert_same_frames(&refdir, &out);
    drop(hosts);
}

/// Issue 20, item 1: a farm re-run decides from the files which jobs to run. A tile image
/// with a flipped byte (same size), a truncated one, a frame's statistics removed and a job
/// folder deleted by hand: the same command renders those four jobs again — in each only the
/// damaged frame, all of the deleted one — leaves the other jobs' files untouched, and
/// assembles the one-process frames.
#[test]
fn farm_rerun_renders_exactly_the_jobs_whose_files_are_damaged_or_gone() {
    let Some((tmp, refdir, hosts)) = farm_setup(common::this_test!()) else {
        return;
    };
    let out = tmp.path().join("farm");
    let args = ["--shared-fs", "--jobs", "6"];
    let (code, log) = finish(farm(&hosts, &out, &args));
    assert_eq!(code, Some(0), "{log}");
    let first = joblog(&out).len();
    let folders = planned_folders(&out);
    assert_eq!(folders.len(), 6);

    flip_a_byte(&folders[0].join("tiles_0003.exr"));
    truncate_half(&folders[1].join("tiles_0005.exr"));
    fs::remove_file(folders[2].join("tiles_0006.json")).unwrap();
    fs::remove_dir_all(&folders[3]).unwrap();
    for f in 0..8 {
        fs::remove_file(out.join(format!("frame_{f:04}.exr"))).unwrap();
    }
    let before = stamps(&out.join("jobs"));
    let (code, log) = finish(farm(&hosts, &out, &args));
    assert_eq!(code, Some(0), "{log}");
    assert!(log.contains("resuming: 4 of 6 jobs"), "{log}");
    assert_same_frames(&refdir, &out);
    let rerun = jobs_run_since(&out, first);
    assert_eq!(
        rerun.iter().copied().collect::<BTreeSet<_>>(),
        BTreeSet::from([0, 1, 2, 3]),
        "{rerun:?}"
    );
    assert_eq!(rerun.len(), 4, "{rerun:?}");

    // Jobs 4 and 5 did not run: every file of theirs is the very same. Jobs 0–2 rendered
    // their damaged frame only: their other frames' files are the same.
    let damaged = [(0, "tiles_0003"), (1, "tiles_0005"), (2, "tiles_0006")];
    let mut same = 0;
    for (path, st) in &before {
        let k = folders.iter().position(|f| path.starts_with(f)).unwrap();
        let name = path.file_name().unwrap().to_string_lossy();
        let rendered = damaged
            .iter()
            .any(|(j, frame)| *j == k && name.starts_with(frame));
        if k >= 4 || (name.starts_with("tiles_") && !rendered) {
            assert_eq!(stamp(path), *st, "{} was written again", path.display());
            same += 1;
        } else if rendered {
            assert_ne!(
                stamp(path),
                *st,
                "{} was not rendered again",
                path.display()
            );
        }
    }
    // 2 untouched jobs × (8 frames × 2 files + job.json + lights.json) + 3 × 7 frames × 2.
    assert_eq!(same, 2 * 18 + 3 * 14, "{before:?}");
    drop(hosts);
}

/// Issue 20, item 2: the build identity is what decides the bits, not the executable's bytes.
/// `cargo test --release` links another `target/release/envshadow` from the same source (see
/// build.rs); a copy of the test binary with a byte appended stands for it — another file
/// that runs the same code. A farm run with one, interrupted, continues with the other.
#[test]
fn another_build_of_the_same_source_resumes_the_farm() {
    let Some((tmp, refdir, hosts)) = farm_setup(common::this_test!()) else {
        return;
    };
    let other = tmp.path().join("other-build/envshadow");
    fs::create_dir_all(other.parent().unwrap()).unwrap();
    let mut bytes = fs::read(BIN).unwrap();
    bytes.push(0);
    fs::write(&other, bytes).unwrap();
    fs::set_permissions(&other, fs::Permissions::from_mode(0o755)).unwrap();
    let version = |bin: &Path| {
        let o = Command::new(bin)
            .args(["version", "--build"])
            .output()
            .unwrap();
        ok(&o);
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    assert_eq!(version(Path::new(BIN)), version(&other));

    let out = tmp.path().join("farm");
    let args = ["--jobs", "6"];
    let (code, log) = finish(farm(&hosts, &out, &args));
    assert_eq!(code, Some(0), "{log}");
    let first = joblog(&out).len();
    // What an interruption leaves: a job that never ran, one that stopped half-way.
    let folders = planned_folders(&out);
    fs::remove_dir_all(&folders[1]).unwrap();
    for f in 4..8 {
        fs::remove_file(folders[4].join(format!("tiles_{f:04}.json"))).unwrap();
    }
    let (code, log) = finish(farm_with(&other, &hosts, &out, &args));
    assert_eq!(code, Some(0), "{log}");
    assert_same_frames(&refdir, &out);
    let rerun: BTreeSet<usize> = jobs_run_since(&out, first).into_iter().collect();
    assert_eq!(rerun, BTreeSet::from([1, 4]));
    drop(hosts);
}

/// Issue 20, item 8: with --no-shared-fs, a SIGTERM leaves nothing on the hosts — not the
/// shipped spec, not the folders of the jobs it stopped, not a job's tar file. The jobs are
/// held once their files are written on the hosts, so the signal surely finds them there.
#[test]
fn no_shared_fs_leaves_nothing_on_the_hosts_after_sigterm() {
    let Some((tmp, refdir, hosts)) = farm_setup(common::this_test!()) else {
        return;
    };
    let gate = Gate::new(&tmp.path().join("gate"), true);
    let out = tmp.path().join("term");
    let args = ["--no-shared-fs", "--envshadow", gate.path(), "--jobs", "6"];
    let child = farm(&hosts, &out, &args);
    wait_until("a job to render on a host", || !gate.started().is_empty());
    let _ = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status();
    let (code, log) = finish(child);
    assert_eq!(code, Some(129), "{log}");
    let homes = |what: &str| {
        for k in 1..=3 {
            let left = walk(&hosts.dir.join(format!("h{k}/home")));
            assert!(left.is_empty(), "{what}: left on host fh{k}: {left:?}");
        }
    };
    homes("after SIGTERM");
    let local: Vec<PathBuf> = walk(&out)
        .into_iter()
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.starts_with(".stage") || n.starts_with(".unpack") || n.ends_with(".tar")
        })
        .collect();
    assert!(local.is_empty(), "{local:?}");

    // The same command again, the gate open: the rest is rendered, the hosts are clean.
    gate.open();
    let (code, log) = finish(farm(&hosts, &out, &args));
    assert_eq!(code, Some(0), "{log}");
    assert_same_frames(&refdir, &out);
    homes("after the re-run");
    drop(hosts);
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut v = Vec::new();
    if let Ok(rd) = fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                v.extend(walk(&p));
            }
            v.push(p);
        }
    }
    v
}

/// With `--temporal`, a frame reads its whole previous frame: plan splits by frames on key
/// frames, refuses tile strips, and the assembled frames equal a one-process temporal render.
#[test]
fn temporal_jobs_split_on_key_frames_and_assemble_identically() {
    let tmp = tempfile::tempdir().unwrap();
    let (refdir, out) = (tmp.path().join("ref"), tmp.path().join("farm"));
    let mut flags: Vec<&str> = FLAGS.to_vec();
    flags.extend_from_slice(&["--temporal", "--keyframe", "4"]);
    let mut args = vec![
        "render",
        SPEC,
        "--out",
        refdir.to_str().unwrap(),
        "--no-report",
        "-q",
    ];
    args.extend_from_slice(&flags);
    ok(&envshadow(&args));

    let o = out.to_str().unwrap();
    let mut tiles = vec!["plan", SPEC, "--out", o, "--jobs", "3", "--by", "tiles"];
    tiles.extend_from_slice(&flags);
    let refused = envshadow(&tiles);
    assert_eq!(refused.status.code(), Some(2));
    assert!(!out.join("jobs.txt").exists());

    let mut plan = vec!["plan", SPEC, "--out", o, "--jobs", "3"];
    plan.extend_from_slice(&flags);
    let planned = envshadow(&plan);
    ok(&planned);
    let lines = String::from_utf8_lossy(&planned.stdout).into_owned();
    // 8 frames in groups of 4: two jobs, each starting on a key frame, with every tile.
    let frames: Vec<&str> = lines
        .lines()
        .map(|l| l.split('\t').nth(1).unwrap())
        .collect();
    assert_eq!(frames, ["0..4", "4..8"], "{lines}");
    for k in 0..2 {
        let ks = k.to_string();
        let mut job = vec!["render", SPEC, "--out", o, "--job", &ks, "--of", "3", "-q"];
        job.extend_from_slice(&flags);
        ok(&envshadow(&job));
    }
    ok(&envshadow(&["assemble", o, "--no-report"]));
    assert_same_frames(&refdir, &out);
    assert_eq!(stats_without_seconds(&refdir), stats_without_seconds(&out));
}
