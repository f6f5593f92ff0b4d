//! An evaluation order (ALGORITHM.md §5): in which passes the pixels of a frame are decided,
//! and which earlier pixels vote for each. The tile driver walks the passes; an order only
//! answers questions about pixels, so the pixel loop and its bookkeeping live once.
//!
//! Passes are numbered from 0. A pixel reads only pixels of earlier passes, or earlier pixels
//! of its own pass in row-major order (the scanline), never later ones. The first
//! [`shared_passes`](Order::shared_passes) passes hold few pixels that many tiles read: the
//! driver evaluates them once per frame into a lattice (every
//! [`lattice_step`](Order::lattice_step)-th pixel) that every tile copies from.

use crate::key::Key;
use crate::tile::Rect;

/// Which pixels are decided in which pass, and who votes for them.
pub trait Order: Send + Sync {
    /// The order's name, as method names spell it (`grid`, `scan`).
    fn name(&self) -> &'static str;

    /// Number of passes.
    fn passes(&self) -> usize {
        1
    }

    /// The pass that decides frame pixel (x, y).
    fn pass_of(&self, x: u32, y: u32) -> usize {
        let _ = (x, y);
        0
    }

    /// The frame pixels pixel (x, y) of `pass` reads, in the order they vote (ties between
    /// warped blockers go to the first), inside `frame`; returns how many of `out` are set.
    fn voters(&self, x: u32, y: u32, pass: usize, frame: Rect, out: &mut [(u32, u32); 4]) -> usize {
        let _ = (x, y, pass, frame, out);
        0
    }

    /// Whether pixels of `pass` are read by later pixels (and so keep their blockers for a
    /// warping vote).
    fn read_later(&self, pass: usize) -> bool {
        let _ = pass;
        false
    }

    /// Whether `pass` is at the order's finest level, whose pixels mislead no coarser pixel
    /// (where `--flood-to contrary-finest` floods to contrary lights only).
    fn finest(&self, pass: usize) -> bool {
        let _ = pass;
        false
    }

    /// How far (in lattice steps) the voters of `pass` lie along each axis, for orders whose
    /// passes have levels (`None`: the order has none).
    fn spacing(&self, pass: usize) -> Option<u32> {
        let _ = pass;
        None
    }

    /// Whether a pixel keeps, besides its traced blockers, the warped blocker that voted for
    /// each light it predicted blocked ([ours]; docs/methods.md).
    fn keeps_predicted(&self) -> bool {
        false
    }

    /// Passes evaluated once per frame into the lattice (0: none).
    fn shared_passes(&self) -> usize {
        0
    }

    /// Spacing of the lattice holding the shared passes' pixels (0: none).
    fn lattice_step(&self) -> u32 {
        0
    }

    /// How far beyond a tile the shared passes' pixels it depends on reach (directly or
    /// through other shared pixels): a region render runs the shared passes that far out.
    fn shared_reach(&self) -> u32 {
        0
    }

    /// The pixels whose surfaces and visibility a tile's `phase` may read or evaluate: the
    /// tile plus its halo, inside `frame`. Phases below `shared_passes` are those passes;
    /// the last phase evaluates every remaining pass.
    fn region(&self, frame: Rect, tile: Rect, phase: usize) -> Rect {
        let _ = (frame, phase);
        tile
    }

    /// The settings this order reads ([`Key::H0`], [`Key::ScanBlock`]).
    fn reads(&self) -> &'static [Key] {
        &[]
    }
}
