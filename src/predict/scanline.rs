//! Scanline order (ALGORITHM.md §5) [paper]: pixels in row-major order, each predicted from
//! its left, upper-left and upper neighbours' warped blockers (traced hits only); any vote → blocked; boundary
//! flooding; a pixel with no voters is traced in full.
//!
//! Tiles [ours]: in the paper the scan runs over the whole frame, so a pixel depends on every
//! pixel above and to the left of it. Here the scan restarts at frame-anchored blocks of
//! `scan_block` pixels (default 64): a pixel reads only neighbours in its own block. A tile's
//! halo is then the part of its blocks above and to the left of it; tiles that are multiples
//! of the block (the default 64) have none.

use super::correct::{Flood, FloodTo, Rule, Vote, solve_pixel};
use super::{Lattice, LatticePatch, Params, Predictor};
use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// The scanline method with warped blockers and boundary flooding.
pub struct Scanline {
    name: &'static str,
    block: u32,
    flood_to: FloodTo,
}

impl Scanline {
    pub fn new(name: &'static str, params: Params) -> Scanline {
        Scanline {
            name,
            block: params.scan_block,
            flood_to: params.flood_to,
        }
    }
}

impl Predictor for Scanline {
    fn name(&self) -> &'static str {
        self.name
    }

    fn region(&self, _ctx: &FrameContext, tile: Rect, _phase: usize) -> Rect {
        let b = self.block;
        Rect::new(tile.x0 / b * b, tile.y0 / b * b, tile.x1, tile.y1)
    }

    fn solve(
        &self,
        ctx: &FrameContext,
        _tile: Rect,
        work: &mut TileWork,
        _phase: usize,
        _lattice: &Lattice,
        _patch: &mut LatticePatch,
    ) {
        let region = work.region;
        let b = self.block;
        // [paper] any vote → blocked: one voter is enough.
        let rule = Rule {
            vote: Vote::Warp,
            flood: Flood::Boundary,
            flood_to: self.flood_to,
            min_voters: 1,
            // [paper] §3: only traced hits are blockers. Keeping predicted ones too lets a
            // misprediction travel along the row: fewer rays, up to 3× the wrong pairs at
            // 400 lights (docs/methods.md).
            keep_predicted: false,
        }
        // No levels: `contrary-finest` floods to all (the same traces under boundary flooding
        // anyway).
        .at_level(false);
        let mut voters = [0usize; 3];
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let i = work.begin_pixel(ctx, x, y);
                let (bx, by) = (x / b * b, y / b * b);
                let mut n = 0;
                for (ok, vx, vy) in [
                    (x > bx, x.wrapping_sub(1), y),
                    (x > bx && y > by, x.wrapping_sub(1), y.wrapping_sub(1)),
                    (y > by, x, y.wrapping_sub(1)),
                ] {
                    if ok {
                        let q = region.index(vx, vy);
                        if work.surf[q].hit {
                            voters[n] = q;
                            n += 1;
                        }
                    }
                }
                solve_pixel(ctx, work, i, &voters[..n], rule, true);
            }
        }
    }
}
