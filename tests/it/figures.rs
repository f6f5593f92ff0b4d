//! Per-frame figures a user can trust (issue 23, defect 3): stats.csv's time is each frame's
//! own compute time, the run records its wall time, and the share traced counts every ray.

use crate::common;

use std::path::Path;

use envshadow::output::runs::RunRecord;
use envshadow::output::stats::read_stats;

/// Renders `frames` of the shapes turntable at 320×240 into `out` with `threads` and `flags`:
/// large enough that the frames, not the loading, fill the run's wall time.
fn render(out: &Path, threads: usize, frames: &str, flags: &[&str]) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let status = common::bin()
        .args(["render", "anims/shapes-turntable.toml", "--frames", frames])
        .args([
            "--width", "320", "--height", "240", "--lights", "100", "--spp", "1",
        ])
        .args([
            "--threads",
            &threads.to_string(),
            "--no-report",
            "-q",
            "--out",
        ])
        .arg(out)
        .args(flags)
        .current_dir(root)
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
}

#[test]
fn frame_thread_seconds_add_up_to_at_most_threads_times_wall_time() {
    // Two frames are in flight at once, so per-frame wall-clock times overlapped (55 s of them
    // in a 28.7 s run on two threads); a frame's thread-seconds count only its own work, so a
    // run's add up to at most its threads × its wall time. At one thread the frames fill most
    // of the run: counting a frame's tasks twice (in its elapsed time and again as tasks)
    // would break the bound there.
    let dir = tempfile::tempdir().unwrap();
    for (threads, flags) in [(1, &[][..]), (2, &[][..]), (1, &["--temporal"][..])] {
        let out = dir.path().join(format!("t{threads}-{}", flags.len()));
        render(&out, threads, "0..8", flags);
        let rows = read_stats(&out.join("stats.csv")).unwrap();
        let runs = RunRecord::read_all(&out).unwrap();
        assert_eq!(rows.len(), 8);
        assert_eq!(runs.len(), 1, "{runs:?}");
        let run = &runs[0];
        assert_eq!((run.threads, run.frames_rendered), (threads, 8));
        let sum: f64 = rows.iter().map(|r| r.thread_seconds).sum();
        assert!(rows.iter().all(|r| r.thread_seconds > 0.0), "{rows:?}");
        // Four decimals per row in stats.csv.
        assert!(
            sum <= threads as f64 * run.wall_seconds + 8.0 * 5e-5,
            "{threads} threads {flags:?}: frames sum to {sum:.4} thread-s in a run of {:.4} s",
            run.wall_seconds
        );
        assert!(
            (run.thread_seconds - sum).abs() <= 8.0 * 5e-5 + 1e-3,
            "{run:?} vs {sum}"
        );
        let rays: u64 = rows.iter().map(|r| r.counts.traced()).sum();
        assert_eq!(run.rays_traced, rays);
    }
    // A resumed run adds its own row.
    let out = dir.path().join("t1-0");
    render(&out, 1, "0..10", &["--resume"]);
    let runs = RunRecord::read_all(&out).unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!((runs[1].frames_rendered, runs[1].frames_skipped), (2, 8));
}

#[test]
fn the_share_traced_counts_every_ray_the_frame_traced() {
    // bench --dump-rays records every shadow ray the frame traced (tiles' halos included,
    // validation excluded); the frame's count and share traced must be of the same rays.
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = common::bin()
        .args([
            "bench",
            "--scene",
            "anims/shapes-turntable.toml",
            "--lights",
            "50",
        ])
        .args([
            "--width", "160", "--height", "120", "--spp", "1", "--tile", "32",
        ])
        .args([
            "--method",
            "grid-nowarp-uncertainty",
            "--threads",
            "1",
            "--repeat",
            "1",
        ])
        .arg("--csv")
        .arg("--dump-rays")
        .arg(dir.path())
        .current_dir(root)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let csv = String::from_utf8(out.stdout).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    let traced: u64 = col("rays_traced").parse().unwrap();
    let halo: u64 = col("halo_rays").parse().unwrap();
    let queries: u64 = col("queries").parse().unwrap();
    let percent: f64 = col("percent_traced").parse().unwrap();
    let dump = dir.path().join("rays-50-grid-nowarp-uncertainty.bin");
    let dumped = envshadow::raydump::read(&dump).unwrap().rays.len() as u64;
    assert_eq!(
        traced, dumped,
        "counted {traced} rays, the frame traced {dumped}"
    );
    assert!(
        halo > 0,
        "tiles of 32 evaluate halos: the test would prove little"
    );
    assert!((percent - 100.0 * traced as f64 / queries as f64).abs() < 1e-3);
}
