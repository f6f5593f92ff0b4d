//! Progress on stderr: an indicatif bar on a terminal, plain lines (one per frame, with the
//! time elapsed and an estimate of the time left) in a log; with `-v` also a line per tile
//! and the library's details.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use envshadow::output::stats::FrameStats;
use envshadow::run::{Progress, TileDone};
use indicatif::{ProgressBar, ProgressStyle};

use super::say;

/// Progress as an indicatif bar on a terminal, plain lines (one per frame) otherwise.
pub struct Reporter {
    bar: Option<ProgressBar>,
    verbose: bool,
    /// When the run began rendering (`begin`): what the elapsed time and the rate count from.
    begun: Mutex<Instant>,
    rays: AtomicU64,
    frames: Mutex<(usize, usize)>,
    tiles: AtomicU64,
    /// Tiles of the whole run: frames × tiles per frame.
    all_tiles: AtomicU64,
}

impl Reporter {
    pub fn new(terminal: bool, verbose: bool) -> Reporter {
        Reporter {
            bar: terminal.then(ProgressBar::hidden),
            verbose,
            begun: Mutex::new(Instant::now()),
            rays: AtomicU64::new(0),
            frames: Mutex::new((0, 0)),
            tiles: AtomicU64::new(0),
            all_tiles: AtomicU64::new(0),
        }
    }

    fn elapsed(&self) -> f64 {
        self.begun.lock().unwrap().elapsed().as_secs_f64()
    }

    fn rays_per_second(&self) -> f64 {
        self.rays.load(Ordering::Relaxed) as f64 / self.elapsed().max(1e-9)
    }

    /// `elapsed 0:01:05, ETA 0:03:10`: the time left at the rate tiles have finished so far
    /// (tiles rather than frames: two frames are in flight, and a tile is a finer step).
    fn clock(&self) -> String {
        let elapsed = self.elapsed();
        let done = self.tiles.load(Ordering::Relaxed) as f64;
        let all = self.all_tiles.load(Ordering::Relaxed) as f64;
        let eta = if done >= all {
            "0:00:00".to_string()
        } else if done == 0.0 {
            "unknown".to_string()
        } else {
            hms(elapsed * (all - done) / done)
        };
        format!("elapsed {}, ETA {eta}", hms(elapsed))
    }

    fn line(&self, msg: &str) {
        match &self.bar {
            Some(bar) => bar.println(msg),
            None => say(msg),
        }
    }
}

/// Seconds as `H:MM:SS`.
fn hms(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

impl Progress for Reporter {
    fn begin(&self, frames: usize, tiles: usize) {
        *self.frames.lock().unwrap() = (0, frames);
        *self.begun.lock().unwrap() = Instant::now();
        self.all_tiles
            .store((frames * tiles) as u64, Ordering::Relaxed);
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

    fn tile_done(&self, t: &TileDone) {
        self.rays.fetch_add(t.counts.rays, Ordering::Relaxed);
        self.tiles.fetch_add(1, Ordering::Relaxed);
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
        if self.verbose {
            // A tile of background only asks nothing: say so rather than "0 of 0 (0.00 %)".
            let traced = if t.counts.queries == 0 {
                "no shadow queries (no lit surface)".to_string()
            } else {
                format!(
                    "{} of {} queries traced ({:.2} %)",
                    t.counts.rays,
                    t.counts.queries,
                    t.counts.percent_traced()
                )
            };
            self.line(&format!(
                "frame {} tile {} [{}]: {traced}, {:.3} s",
                t.frame, t.index, t.rect, t.seconds
            ));
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
            // A log has no bar: each line says how long the run has taken and has left.
            None => say(&format!("{line}; {}", self.clock())),
        }
        if self.verbose {
            let c = &s.counts;
            self.line(&format!(
                "frame {}: {} rays = {} where the prediction was unsure + {} at pixels tracing \
                 every light + {} flooded ({} of them fixed a wrong prediction); {} pixels from \
                 the previous frame ({} rays{}); halo {} pixels, {} rays",
                s.frame,
                c.rays,
                c.rays_unsure(),
                c.rays_every_light,
                c.rays_flooded,
                c.flood_fixes,
                c.temporal_pixels,
                c.temporal_rays,
                stale_note(c.temporal_stale),
                c.halo_pixels,
                c.halo_rays
            ));
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
        self.line(msg);
    }

    fn detail(&self, msg: &str) {
        if self.verbose {
            self.line(msg);
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// `-q`: nothing but errors, which are not progress.
pub struct Quiet;

impl Progress for Quiet {}

/// What `-v` says of the previous frame's pairs a file's animation made stale: nothing when
/// none were (a rigid frame's line is as it was).
fn stale_note(stale: u64) -> String {
    if stale == 0 {
        String::new()
    } else {
        format!(", {stale} of its pairs dropped where the animation moved")
    }
}
