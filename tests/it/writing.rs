//! Writing off the critical path (issue 38, item 3): frames are written several at once, on
//! different threads, while later frames render. Each test holds a frame's writing open until
//! what it guards has happened (a condition, never a time); the time-out only turns a
//! regression into a failure instead of a hang.

use std::collections::BTreeSet;
use std::sync::{Condvar, Mutex};
use std::thread::ThreadId;
use std::time::Duration;

use envshadow::anim::Animation;
use envshadow::coordinator::render_animation;
use envshadow::error::Result;
use envshadow::film::Film;
use envshadow::output::stats::FrameStats;
use envshadow::run::{FrameSink, Progress, RunOptions, Silent, TileDone};

use crate::common;

/// Long enough for any machine to reach the awaited condition; only a regression waits it out.
const HANG: Duration = Duration::from_secs(120);

/// A small animation of `frames` frames on two workers: each frame its own chain, or with
/// `one_chain` a single chain (temporal prediction from frame 0), each frame rendered after the
/// one before by the same thread.
fn small(frames: usize, one_chain: bool, out: &std::path::Path) -> Animation {
    let temporal = if one_chain {
        format!("temporal = true\nkeyframe = {frames}\n")
    } else {
        String::new()
    };
    common::animation(&format!(
        "[environment]\nbuiltin = \"sky\"\n[lights]\ncount = 8\n\
         [camera]\ntarget = [0.0, 0.45, 0.0]\ndistance = 6.5\n\
         [motion]\nkind = \"orbit\"\nframes = {frames}\nturn_degrees = 90.0\n\
         [render]\nwidth = 48\nheight = 32\ntile = 16\nthreads = 2\n{temporal}\
         [output]\ndir = \"{}\"\n",
        out.display()
    ))
}

/// What the sinks below saw, behind one lock with the condition variable they wait on.
#[derive(Default)]
struct Seen {
    /// Writes in progress now (frame, thread), and the first two found at once.
    writing: Vec<(usize, ThreadId)>,
    met: Vec<(usize, ThreadId)>,
    /// Whether what a test awaited happened; whether a wait gave up (later ones then pass,
    /// so that a regression fails once instead of waiting at every frame).
    happened: bool,
    gave_up: bool,
    /// Each write: its frame and the thread it ran on.
    writes: Vec<(usize, ThreadId)>,
    /// Frames with a finished tile.
    tiles_of: BTreeSet<usize>,
}

#[derive(Default)]
struct Watch {
    seen: Mutex<Seen>,
    changed: Condvar,
}

impl Watch {
    /// Waits until `done` holds of what has been seen, or [`HANG`] passes (or passed once
    /// before); says whether it held.
    fn wait_for(&self, done: impl Fn(&Seen) -> bool) -> bool {
        let seen = self.seen.lock().unwrap();
        let (mut seen, _) = self
            .changed
            .wait_timeout_while(seen, HANG, |s| !done(s) && !s.gave_up)
            .unwrap();
        let held = done(&seen);
        seen.gave_up |= !held;
        held
    }

    fn update(&self, f: impl FnOnce(&mut Seen)) {
        f(&mut self.seen.lock().unwrap());
        self.changed.notify_all();
    }
}

/// Holds each write until another write is in progress beside it.
struct Rendezvous(Watch);

impl FrameSink for Rendezvous {
    fn frame_done(&self, _: usize) -> bool {
        false
    }

    fn write(&self, _: &Film, stats: &FrameStats) -> Result<()> {
        let me = (stats.frame, std::thread::current().id());
        self.0.update(|s| {
            s.writing.push(me);
            s.writes.push(me);
            if s.met.is_empty() && s.writing.len() >= 2 {
                s.met = s.writing.clone();
            }
        });
        // Once two writes have met, later ones (the last frame's, alone) pass.
        self.0.wait_for(|s| !s.met.is_empty());
        self.0.update(|s| s.writing.retain(|w| *w != me));
        Ok(())
    }
}

/// Two frames are written at the same time by different threads: each write waits until
/// another is in progress, which a single writer (each frame written after the one before)
/// never lets happen.
#[test]
fn two_frames_are_written_at_once_by_different_threads() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small(4, false, dir.path());
    let mut sink = Rendezvous(Watch::default());
    let summary = render_animation(&anim, &RunOptions::default(), &mut sink, &Silent).unwrap();
    assert_eq!(summary.rendered, 4);
    let seen = sink.0.seen.into_inner().unwrap();
    let [(f0, t0), (f1, t1), ..] = seen.met[..] else {
        panic!("frames were written one at a time: {:?}", seen.writes)
    };
    assert!(f0 != f1 && t0 != t1, "met: {:?}", seen.met);
    let mut frames: Vec<usize> = seen.writes.iter().map(|w| w.0).collect();
    frames.sort_unstable();
    assert_eq!(frames, [0, 1, 2, 3], "each frame written once");
}

/// Holds the first frame's write until a tile of the next frame has finished. It sees the
/// tiles as the run's progress.
struct WhileRendering<'w>(&'w Watch);

impl FrameSink for WhileRendering<'_> {
    fn frame_done(&self, _: usize) -> bool {
        false
    }

    fn write(&self, _: &Film, stats: &FrameStats) -> Result<()> {
        let mut first = false;
        self.0.update(|s| {
            first = s.writes.is_empty();
            s.writes.push((stats.frame, std::thread::current().id()));
        });
        if first {
            let next = stats.frame + 1;
            let rendered = self.0.wait_for(|s| s.tiles_of.contains(&next));
            self.0.update(|s| s.happened = rendered);
        }
        Ok(())
    }
}

impl Progress for Watch {
    fn tile_done(&self, tile: &TileDone) {
        self.update(|s| {
            s.tiles_of.insert(tile.frame);
        });
    }
}

/// A frame's writing does not hold up its chain: in a single chain (each frame read by the
/// next, so one thread renders them in turn), the next frame renders while the first is
/// written, which writing a frame before rendering the next never lets happen.
#[test]
fn the_next_frame_renders_while_a_frame_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let anim = small(3, true, dir.path());
    let watch = Watch::default();
    let summary = render_animation(
        &anim,
        &RunOptions::default(),
        &mut WhileRendering(&watch),
        &watch,
    )
    .unwrap();
    assert_eq!(summary.rendered, 3);
    let seen = watch.seen.into_inner().unwrap();
    assert!(
        seen.happened,
        "the next frame waited for the first frame's writing (writes: {:?})",
        seen.writes
    );
}
