//! `none`: no shadows at all, every light visible. The baseline cost of a frame without
//! shadows, against which the shadow methods are timed.

use super::Predictor;
use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// Marks every light visible and traces nothing.
pub struct NoShadows;

impl Predictor for NoShadows {
    fn name(&self) -> &'static str {
        "none"
    }

    fn solve(&self, ctx: &FrameContext, tile: Rect, work: &mut TileWork) {
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let i = work.region.index(x, y);
                let s = work.surf[i];
                if !s.hit {
                    continue;
                }
                let mut above = 0u64;
                let words = work.words;
                let bits = &mut work.vis[i * words..(i + 1) * words];
                for j in 0..ctx.light_count() {
                    if ctx.above(&s, j) {
                        above += 1;
                        bits[j >> 6] |= 1 << (j & 63);
                    }
                }
                work.counts.queries += above;
            }
        }
    }
}
