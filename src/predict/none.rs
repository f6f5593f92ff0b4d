//! `none`: no shadows at all, every light visible. The baseline cost of a frame without
//! shadows, against which the shadow methods are timed.

use super::{Lattice, LatticePatch, Predictor};
use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// Marks every above-horizon light visible and traces nothing.
pub struct NoShadows;

impl Predictor for NoShadows {
    fn name(&self) -> &'static str {
        "none"
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
        let w = work.words;
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let i = work.begin_pixel(ctx, x, y);
                let (above, vis) = (
                    &work.above[i * w..(i + 1) * w],
                    &mut work.vis[i * w..(i + 1) * w],
                );
                vis.copy_from_slice(above);
            }
        }
    }
}
