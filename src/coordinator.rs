//! The coordinator: loads an animation's inputs once, renders its frames tile by tile over a
//! worker pool — two frames in flight, so the next frame's tiles start while the last tiles of
//! the current one finish — and hands finished frames to a few writer threads, which encode
//! them on a pool of their own while rendering goes on, several frames at once. Memory stays
//! bounded by the frames rendering and the frames being written.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use crossbeam_channel::{Receiver, Sender, bounded};

use crate::anim::Animation;
use crate::cancel::Cancel;
use crate::error::Result;
use crate::film::{Counts, Film};
use crate::frame::{Temporal, render_tile_list};
use crate::history::Carried;
use crate::output;
use crate::output::lock::FolderLock;
use crate::output::stats::FrameStats;
use crate::temporal::{Chain, chains};
use crate::tile::{Rect, Tile};

use crate::inputs::{Inputs, scene_lights_note};
use crate::run::{FrameSink, Progress, RunOptions, RunSummary, Silent};

/// Frames rendered at once (see `render_animation`); the memory estimate counts them.
const FRAMES_IN_FLIGHT: usize = crate::limits::FRAMES_IN_FLIGHT;
/// Frames written at once; the memory estimate counts them too.
const WRITES_IN_FLIGHT: usize = crate::limits::WRITES_IN_FLIGHT;

/// The tiles a run renders and the region that bounds them: `--region`'s tiles, or the
/// tiles of `indices` (sorted; the frame-anchored grid) with their bounding rectangle, so
/// the shared phases reach as far as their halos and each tile gets the bits of a
/// whole-frame render.
fn selection(anim: &Animation, opts: &RunOptions) -> (Vec<Tile>, Option<Rect>) {
    let Some(indices) = &opts.tiles else {
        return (anim.render.tiles(opts.region), opts.region);
    };
    let all = anim.render.tiles(None);
    let whole = indices.len() == all.len();
    let list: Vec<Tile> = all
        .into_iter()
        .filter(|t| indices.binary_search(&t.index).is_ok())
        .collect();
    let bbox = (!whole).then(|| crate::tile::bounding(&list));
    (list, bbox)
}

/// A thread pool with `threads` workers (0: one per core).
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("envshadow-worker-{i}"))
        .build()
        .context("starting the worker threads")
}

/// The pool frames are encoded on, as many threads as the workers: apart from theirs, so that
/// a worker waiting inside a frame's encoding never picks up a whole frame's rendering (rayon
/// lets a thread blocked in a join run any queued job), nor a frame's rendering a write.
/// Rendering and writing share the cores through the system's scheduler; once rendering is
/// over, the last frames' writing has every core.
fn write_pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("envshadow-encoder-{i}"))
        .build()
        .context("starting the writing threads")
}

/// Renders the animation's selected frames into its output folder.
pub fn render_animation(
    anim: &Animation,
    opts: &RunOptions,
    sink: &mut dyn FrameSink,
    progress: &dyn Progress,
) -> Result<RunSummary> {
    let start = Instant::now();
    let started_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    if anim.render.temporal && opts.region.is_some() {
        crate::bail_input!(
            "--region",
            "cannot be combined with temporal prediction: a frame's pixels depend on the \
             whole previous frame"
        );
    }
    // Inputs first: a bad input leaves nothing behind, not even an empty folder.
    let inputs = load(anim, progress)?;
    opts.cancel.check()?;
    let dir = &anim.output.dir;
    output::create_output_dir(dir)?;
    // One writer per folder, from the first file written to the last.
    let _lock = FolderLock::acquire(dir, opts.wait)?;
    // Holding the lock, no other writer is mid-write: whatever temporaries the folder holds
    // were left by a render that was killed, and would stay for good.
    output::remove_stale_temporaries(dir)?;
    let warnings: Vec<String> = inputs
        .scene
        .warnings
        .iter()
        .chain(&inputs.env.warnings)
        .cloned()
        .collect();
    sink.input_warnings(&warnings);
    sink.begin()?;
    inputs.lights.write_json(&dir.join("lights.json"))?;
    if !opts.resume {
        note_rerendered(anim, &*sink, progress);
    }

    let todo: Vec<usize> = anim
        .frames
        .iter()
        .filter(|&f| {
            let done = opts.resume && sink.frame_done(f);
            if done {
                progress.frame_skipped(f);
            }
            !done
        })
        .collect();
    // With temporal prediction, frames come in chains from a key frame, each frame reading
    // its predecessor; a chain's frames outside this run are rendered, not written.
    let work = chains(&todo, anim.render.temporal, |f| anim.key_frame_of(f));
    let warmup: usize = work
        .iter()
        .map(|c| c.frames.iter().filter(|f| !f.1).count())
        .sum();
    if warmup > 0 {
        progress.note(&format!(
            "temporal: {warmup} frame(s) not asked for are rendered (not written) so that each \
             frame asked for is predicted from its predecessor, as in a run of every frame \
             from its chain's key frame"
        ));
    }
    let (list, region) = selection(anim, opts);
    progress.begin(todo.len(), list.len());
    let pool = thread_pool(anim.render.threads)?;
    let encoders = write_pool(pool.current_num_threads())?;
    let run = Run {
        anim,
        inputs: &inputs,
        pool: &pool,
        encoders: &encoders,
        list: &list,
        region,
        cancel: &opts.cancel,
        progress,
        timeline: Timeline::default(),
    };
    let done = run.chains(&work, &*sink);
    progress.finish();
    let done = done?;
    // Frames finished before the stop are written; the rest waits for `--resume`.
    opts.cancel.check()?;
    let summary = RunSummary {
        rendered: done.rendered,
        skipped: anim.frames.len() - todo.len(),
        counts: done.counts,
        seconds: start.elapsed().as_secs_f64(),
        started_unix,
        threads: pool.current_num_threads(),
        thread_seconds: done.thread_seconds,
    };
    sink.finish(&summary)?;
    Ok(summary)
}

/// Says, once, how many of the frames asked for are already complete here from these very
/// settings: a plain run renders them again, which `--resume` would skip. (The check is
/// `--resume`'s own; it hashes only frames whose record names these settings.)
fn note_rerendered(anim: &Animation, sink: &dyn FrameSink, progress: &dyn Progress) {
    let complete = anim.frames.iter().filter(|&f| sink.frame_done(f)).count();
    if complete > 0 {
        progress.note(&format!(
            "{complete} complete frame{} of this render already here will be rendered again \
             and overwritten; --resume would skip {}",
            if complete == 1 { "" } else { "s" },
            if complete == 1 { "it" } else { "them" }
        ));
    }
}

/// Loads `anim`'s inputs and tells the user what became of them: the loader's warnings, the
/// scene file's lights, a ground added under the model. Every frame's camera is checked, so a
/// spec whose camera breaks at some frame (an `up` along the view) is refused before
/// lights.json or any frame is written.
fn load(anim: &Animation, progress: &dyn Progress) -> Result<Inputs> {
    let loading = Instant::now();
    let inputs = Inputs::load(anim)?;
    progress.detail(&format!(
        "inputs in {:.2} s: {} ({} triangles), {} ({}x{}), {} lights",
        loading.elapsed().as_secs_f64(),
        inputs.scene.source,
        inputs.scene.triangles.len(),
        inputs.env.source,
        inputs.env.width,
        inputs.env.height,
        inputs.lights.len()
    ));
    for f in anim.frames.iter() {
        anim.camera(&inputs.scene, f)?;
    }
    for w in inputs.scene.warnings.iter().chain(&inputs.env.warnings) {
        progress.warning(w);
    }
    if let Some(note) = scene_lights_note(anim, &inputs.scene) {
        progress.note(&note);
    }
    if inputs.scene.added_ground.is_some() {
        let catcher = inputs.scene.catcher.last().copied().unwrap_or(false);
        progress.note(&format!(
            "{} has no ground under the model: added {} (`[scene] ground = \"none\"` or \
             --ground none leaves it out)",
            inputs.scene.source,
            if catcher {
                "a shadow-catcher ground"
            } else {
                "a grey ground"
            }
        ));
    }
    Ok(inputs)
}

/// One run's rendering: the frames' common inputs, the pool and the tiles every frame renders.
struct Run<'r> {
    anim: &'r Animation,
    inputs: &'r Inputs,
    pool: &'r rayon::ThreadPool,
    /// Where frames are encoded ([`write_pool`]).
    encoders: &'r rayon::ThreadPool,
    list: &'r [Tile],
    region: Option<Rect>,
    cancel: &'r Cancel,
    progress: &'r dyn Progress,
    /// When frames rendered, for what the writing of each frame overlapped.
    timeline: Timeline,
}

/// What the writer and the chains did: the frames written and their counts, and every frame's
/// thread-seconds (warm-up frames included).
#[derive(Default)]
struct Done {
    rendered: usize,
    counts: Counts,
    thread_seconds: f64,
    /// The frames' writing: wall seconds summed over frames, and the part of them during
    /// which some frame was rendering.
    writing: f64,
    overlapped: f64,
}

impl Run<'_> {
    /// Renders the chains of `work` and hands every written frame to `sink`, returning the
    /// first error of any chain or writer.
    ///
    /// Two chains in flight share the pool: while the last tiles of one frame finish, idle
    /// workers take tiles of the other chain's frame. Each driver thread renders its chain's
    /// frames in order (a frame starts once its predecessor is complete, so its tiles read the
    /// whole previous frame) and hands each finished film to a free writer thread; up to
    /// [`WRITES_IN_FLIGHT`] frames are written at once, each encoded in parallel beside the
    /// tiles ([`write_pool`]). Files are per frame, so the order frames are written in does
    /// not matter. A driver waits while every writer is busy, so memory stays bounded by the
    /// chains in flight (each holds at most the previous frame's carried data and the one
    /// being built) and the writers' frames.
    fn chains(&self, work: &[Chain], sink: &dyn FrameSink) -> Result<Done> {
        let next = AtomicUsize::new(0);
        let failed = AtomicBool::new(false);
        let first_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
        let thread_seconds = Mutex::new(0.0f64);
        let fail = |e: anyhow::Error| {
            failed.store(true, Ordering::Relaxed);
            first_error.lock().unwrap().get_or_insert(e);
        };
        // No queue: a finished frame goes straight to a writer that is free.
        let (tx, rx) = bounded::<(Film, FrameStats)>(0);
        let to_write: usize = work
            .iter()
            .map(|c| c.frames.iter().filter(|f| f.1).count())
            .sum();
        let written = std::thread::scope(|s| {
            let writers: Vec<_> = (0..WRITES_IN_FLIGHT.min(to_write))
                .map(|k| {
                    let rx = rx.clone();
                    let (failed, fail) = (&failed, &fail);
                    s.spawn(move || self.write(k, rx, sink, failed, fail))
                })
                .collect();
            drop(rx);
            for _ in 0..FRAMES_IN_FLIGHT.min(work.len()) {
                let tx = tx.clone();
                let (next, failed, fail, thread_seconds) = (&next, &failed, &fail, &thread_seconds);
                s.spawn(move || {
                    loop {
                        let k = next.fetch_add(1, Ordering::Relaxed);
                        if k >= work.len()
                            || failed.load(Ordering::Relaxed)
                            || self.cancel.is_cancelled()
                        {
                            break;
                        }
                        match self.chain(&work[k], &tx, failed, thread_seconds) {
                            Ok(true) => {}
                            Ok(false) => break, // the writers failed; reported below
                            Err(e) => {
                                fail(e);
                                break;
                            }
                        }
                    }
                });
            }
            drop(tx);
            let mut done = Done::default();
            for w in writers {
                let d = w
                    .join()
                    .map_err(|_| anyhow::anyhow!("a writer thread panicked"))?;
                done.rendered += d.rendered;
                done.counts += d.counts;
                done.writing += d.writing;
                done.overlapped += d.overlapped;
            }
            Ok::<_, anyhow::Error>(done)
        });
        if let Some(e) = first_error.into_inner().unwrap() {
            return Err(e);
        }
        let mut done = written?;
        done.thread_seconds = thread_seconds.into_inner().unwrap();
        if done.rendered > 0 {
            self.progress.detail(&format!(
                "writing: {} frames in {:.2} s summed ({:.3} s each), {:.0} % of it while frames \
                 rendered; the last frame written {:.3} s after the last frame rendered",
                done.rendered,
                done.writing,
                done.writing / done.rendered as f64,
                100.0 * done.overlapped / done.writing.max(1e-9),
                self.timeline.tail().as_secs_f64()
            ));
        }
        Ok(done)
    }

    /// Renders one chain's frames in order, each reading its predecessor's carried data, and
    /// sends the frames to write over `tx`. Returns false if the writer has gone (it failed)
    /// and stops early once another chain failed or the run is stopped.
    fn chain(
        &self,
        chain: &Chain,
        tx: &Sender<(Film, FrameStats)>,
        failed: &AtomicBool,
        thread_seconds: &Mutex<f64>,
    ) -> Result<bool> {
        let frames = &chain.frames;
        let mut prev: Option<Carried> = None;
        for (n, &(frame, write)) in frames.iter().enumerate() {
            if failed.load(Ordering::Relaxed) || self.cancel.is_cancelled() {
                break;
            }
            let link = Temporal {
                prev: prev.as_ref(),
                carry: n + 1 < frames.len(),
                no_validate: !write,
            };
            let shown: &dyn Progress = if write { self.progress } else { &Silent };
            let span = self.timeline.rendering(frame);
            let rendered = self.pool.install(|| {
                render_tile_list(
                    self.anim,
                    self.inputs,
                    frame,
                    self.list,
                    self.region,
                    shown,
                    &link,
                    self.cancel,
                )
            });
            self.timeline.rendered(span);
            let (film, stats, carried) = rendered?;
            *thread_seconds.lock().unwrap() += stats.thread_seconds;
            // The previous frame's data has been used: free it now.
            prev = carried;
            if !write {
                continue;
            }
            self.progress.frame_done(&stats);
            if tx.send((film, stats)).is_err() {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Writer thread `k`: hands each finished frame it receives to `sink`, on the encoders'
    /// pool (the encoding is parallel inside), and says how long that took and what rendering
    /// went on meanwhile. Stops at the first error (then `fail`s the run) or once another writer
    /// failed; the frames it did not take stay unwritten, for `--resume`.
    fn write(
        &self,
        k: usize,
        rx: Receiver<(Film, FrameStats)>,
        sink: &dyn FrameSink,
        failed: &AtomicBool,
        fail: &(dyn Fn(anyhow::Error) + Sync),
    ) -> Done {
        let mut done = Done::default();
        for (mut film, stats) in rx {
            if failed.load(Ordering::Relaxed) {
                break;
            }
            let guarded = film.guard_finite(self.anim.output.half);
            if guarded > 0 {
                self.progress.warning(&format!(
                    "frame {}: {guarded} pixel values were not finite (or negative where they \
                     cannot be) and were clamped before writing",
                    stats.frame
                ));
            }
            let from = Instant::now();
            if let Err(e) = self.encoders.install(|| sink.write(&film, &stats)) {
                fail(e);
                break;
            }
            let to = Instant::now();
            self.timeline.written(to);
            let (frames, beside) = self.timeline.overlap(from, to);
            let seconds = (to - from).as_secs_f64();
            let meanwhile = if frames.is_empty() {
                "while no frame rendered".to_string()
            } else {
                format!(
                    "overlapping the rendering of frame{} {} for {:.3} s of it",
                    if frames.len() > 1 { "s" } else { "" },
                    frames
                        .iter()
                        .map(|f| f.to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                    beside.as_secs_f64()
                )
            };
            self.progress.detail(&format!(
                "frame {}: written in {seconds:.3} s by writer {k}, {meanwhile}",
                stats.frame
            ));
            done.writing += seconds;
            done.overlapped += beside.as_secs_f64();
            done.counts += stats.counts;
            done.rendered += 1;
        }
        done
    }
}

/// When each frame rendered and when the last one was written: what a frame's writing
/// overlapped, measured.
#[derive(Default)]
struct Timeline {
    /// Each frame rendered or rendering: its number, start and end.
    renders: Mutex<Vec<(usize, Instant, Option<Instant>)>>,
    last_written: Mutex<Option<Instant>>,
}

impl Timeline {
    /// `frame` starts rendering; returns its place for [`rendered`](Self::rendered).
    fn rendering(&self, frame: usize) -> usize {
        let mut r = self.renders.lock().unwrap();
        r.push((frame, Instant::now(), None));
        r.len() - 1
    }

    fn rendered(&self, span: usize) {
        self.renders.lock().unwrap()[span].2 = Some(Instant::now());
    }

    fn written(&self, at: Instant) {
        let mut last = self.last_written.lock().unwrap();
        *last = Some(last.map_or(at, |l| l.max(at)));
    }

    /// The frames whose rendering overlapped `from..to`, and how much of that time some frame
    /// was rendering (the union of their spans within it).
    fn overlap(&self, from: Instant, to: Instant) -> (Vec<usize>, Duration) {
        let now = Instant::now();
        let mut spans: Vec<(Instant, Instant, usize)> = self
            .renders
            .lock()
            .unwrap()
            .iter()
            .filter_map(|&(f, a, b)| {
                let (a, b) = (a.max(from), b.unwrap_or(now).min(to));
                (a < b).then_some((a, b, f))
            })
            .collect();
        spans.sort();
        let (mut covered, mut reach) = (Duration::ZERO, from);
        for &(a, b, _) in &spans {
            let a = a.max(reach);
            if b > a {
                covered += b - a;
                reach = b;
            }
        }
        let mut frames: Vec<usize> = spans.iter().map(|s| s.2).collect();
        frames.sort_unstable();
        frames.dedup();
        (frames, covered)
    }

    /// How long after the last frame finished rendering the last frame was written: the
    /// writing that rendering could not hide.
    fn tail(&self) -> Duration {
        let rendered = self
            .renders
            .lock()
            .unwrap()
            .iter()
            .filter_map(|r| r.2)
            .max();
        match (rendered, *self.last_written.lock().unwrap()) {
            (Some(r), Some(w)) => w.saturating_duration_since(r),
            _ => Duration::ZERO,
        }
    }
}
