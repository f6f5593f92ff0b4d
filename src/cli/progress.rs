//! Progress on stderr: an indicatif bar on a terminal, plain lines (one per frame) in a log.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use envshadow::coordinator::Progress;
use envshadow::output::stats::FrameStats;
use indicatif::{ProgressBar, ProgressStyle};

use super::say;

/// Progress as an indicatif bar on a terminal, plain lines (one per frame) otherwise.
pub struct Reporter {
    bar: Option<ProgressBar>,
    start: Instant,
    rays: AtomicU64,
    frames: Mutex<(usize, usize)>,
    tiles: AtomicU64,
}

impl Reporter {
    pub fn new(terminal: bool) -> Reporter {
        Reporter {
            bar: terminal.then(ProgressBar::hidden),
            start: Instant::now(),
            rays: AtomicU64::new(0),
            frames: Mutex::new((0, 0)),
            tiles: AtomicU64::new(0),
        }
    }

    fn rays_per_second(&self) -> f64 {
        self.rays.load(Ordering::Relaxed) as f64 / self.start.elapsed().as_secs_f64().max(1e-9)
    }
}

impl Progress for Reporter {
    fn begin(&self, frames: usize, tiles: usize) {
        *self.frames.lock().unwrap() = (0, frames);
        if let Some(bar) = &self.bar {
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            bar.set_length((frames * tiles) as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {bar:30} {msg} tiles {pos}/{len} ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar.set_message(format!("frame 0/{frames}"));
        } else {
            say(&format!("rendering {frames} frames of {tiles} tiles"));
        }
    }

    fn tile_done(&self, rays: u64) {
        self.rays.fetch_add(rays, Ordering::Relaxed);
        self.tiles.fetch_add(1, Ordering::Relaxed);
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
    }

    fn frame_done(&self, s: &FrameStats) {
        let (done, total) = {
            let mut f = self.frames.lock().unwrap();
            f.0 += 1;
            *f
        };
        let line = format!(
            "frame {} ({done}/{total}): {:.2} thread-s, {:.2} % of {} queries traced, {:.1} M rays/s",
            s.frame,
            s.thread_seconds,
            s.counts.percent_traced(),
            s.counts.queries,
            self.rays_per_second() / 1e6
        );
        match &self.bar {
            Some(bar) => {
                bar.set_message(format!(
                    "frame {done}/{total} {:.1} Mrays/s",
                    self.rays_per_second() / 1e6
                ));
                bar.println(line);
            }
            None => say(&line),
        }
    }

    fn frame_skipped(&self, frame: usize) {
        self.note(&format!(
            "frame {frame}: already rendered, skipped (--resume)"
        ));
    }

    fn warning(&self, msg: &str) {
        self.note(&format!("warning: {msg}"));
    }

    fn note(&self, msg: &str) {
        match &self.bar {
            Some(bar) => bar.println(msg),
            None => say(msg),
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// `-q`: no progress, but what the input had that is not rendered is still said.
pub struct Quiet;

impl Progress for Quiet {
    fn warning(&self, msg: &str) {
        say(&format!("warning: {msg}"));
    }
}
