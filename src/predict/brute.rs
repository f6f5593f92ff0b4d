//! `brute`: trace every shadow query (the "true" row of Table 1).

use super::{Lattice, LatticePatch, Predictor};
use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// Traces one shadow ray per (pixel, light) pair with N·ω > 0.
pub struct Brute;

impl Predictor for Brute {
    fn name(&self) -> &'static str {
        "brute"
    }

    fn solve(
        &self,
        ctx: &FrameContext,
        tile: Rect,
        work: &mut TileWork,
        _phase: usize,
        _lattice: &Lattice,
        _patch: &mut LatticePatch,
    ) {
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let i = work.begin_pixel(ctx, x, y);
                work.trace_all(ctx, i, false);
            }
        }
    }
}
