//! The vocabulary of a run: how the library reports progress ([`Progress`]), where finished
//! frames go ([`FrameSink`]), what a run is asked ([`RunOptions`]) and what it did
//! ([`RunSummary`]). The coordinator, the frame renderer, the frame files and the farm's job
//! writer all speak it.

use crate::cancel::Cancel;
use crate::error::Result;
use crate::film::{Counts, Film};
use crate::output::stats::FrameStats;
use crate::tile::Rect;

/// Progress reports from the library; the CLI decides how to show them (a bar or log lines).
pub trait Progress: Sync {
    /// The run starts: `frames` to render, `tiles` per frame.
    fn begin(&self, _frames: usize, _tiles: usize) {}
    /// A tile finished.
    fn tile_done(&self, _tile: &TileDone) {}
    /// A frame finished rendering (it is being written).
    fn frame_done(&self, _stats: &FrameStats) {}
    /// A frame was skipped because its files exist (`--resume`).
    fn frame_skipped(&self, _frame: usize) {}
    /// A one-line note for the user.
    fn note(&self, _msg: &str) {}
    /// Something the input had that is not rendered (a loader skipped it).
    fn warning(&self, _msg: &str) {}
    /// A one-line note worth showing only to who asked for detail (`-v`): timings, sizes.
    fn detail(&self, _msg: &str) {}
    /// The run ended.
    fn finish(&self) {}
}

/// One finished tile, as [`Progress::tile_done`] reports it.
#[derive(Clone, Copy, Debug)]
pub struct TileDone {
    pub frame: usize,
    /// The tile's number in the frame-anchored grid, and its pixels.
    pub index: usize,
    pub rect: Rect,
    pub counts: Counts,
    /// Wall-clock seconds of this tile alone (tiles run in parallel).
    pub seconds: f64,
}

/// Reports nothing.
pub struct Silent;
impl Progress for Silent {}

/// Where a run's finished frames go: frame files and `stats.csv` in the output folder
/// (`frame_files::FrameFiles`), or a farm job's tile images and statistics (the farm's `JobWriter`).
/// Several frames are written at once, from different threads: `write` takes `&self`.
pub trait FrameSink: Send + Sync {
    /// Called once the output folder exists, before any frame is rendered.
    fn begin(&mut self) -> Result<()> {
        Ok(())
    }
    /// What loading the inputs warned about, before [`begin`](Self::begin): a sink that
    /// records the run keeps it with the run's settings.
    fn input_warnings(&mut self, _warnings: &[String]) {}
    /// Whether `frame` is already complete here (`--resume` skips it).
    fn frame_done(&self, frame: usize) -> bool;
    /// Publishes one finished frame. Called inside a rayon pool of as many threads as the
    /// render's workers, which its encoding may use, for several frames at once, in the order
    /// frames finish: what it writes must not depend on that order.
    fn write(&self, film: &Film, stats: &FrameStats) -> Result<()>;
    /// The run ended with every frame written: what it did.
    fn finish(&mut self, _summary: &RunSummary) -> Result<()> {
        Ok(())
    }
}

/// Options of a run beyond the animation itself.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Skip frames whose EXR and PNG already exist.
    pub resume: bool,
    /// Render only this pixel rectangle (the rest of the frame stays black).
    pub region: Option<Rect>,
    /// Render only these tiles of the frame-anchored grid (sorted; a farm job's), as a region
    /// render of their bounding rectangle would.
    pub tiles: Option<Vec<usize>>,
    /// Stops the run between tiles: complete frames are written, frames in flight dropped.
    pub cancel: Cancel,
    /// When another render holds the output folder, wait for it rather than refuse
    /// ([`FolderLock`](crate::output::lock::FolderLock)).
    pub wait: bool,
}

/// What a run did.
#[derive(Clone, Debug, Default)]
pub struct RunSummary {
    pub rendered: usize,
    pub skipped: usize,
    /// The written frames' counts.
    pub counts: Counts,
    /// Wall-clock seconds of the whole run, loading included.
    pub seconds: f64,
    /// When it started, Unix seconds.
    pub started_unix: u64,
    /// Worker threads.
    pub threads: usize,
    /// The thread-seconds of every frame rendered (warm-up frames included).
    pub thread_seconds: f64,
}
