//! `brute`: trace every shadow query (the "true" row of Table 1).

use super::Predictor;
use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// Traces one shadow ray per (pixel, light) pair with N·ω > 0.
pub struct Brute;

impl Predictor for Brute {
    fn name(&self) -> &'static str {
        "brute"
    }

    fn solve(&self, ctx: &FrameContext, tile: Rect, work: &mut TileWork) {
        let lights = ctx.light_count();
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let i = work.region.index(x, y);
                let s = work.surf[i];
                if !s.hit {
                    continue;
                }
                let mut traced = 0u32;
                let words = work.words;
                let bits = &mut work.vis[i * words..(i + 1) * words];
                for j in 0..lights {
                    if !ctx.above(&s, j) {
                        continue;
                    }
                    traced += 1;
                    if ctx.trace(&s, j) {
                        bits[j >> 6] |= 1 << (j & 63);
                    }
                }
                work.rays[i] = traced;
                work.counts.queries += traced as u64;
                work.counts.rays += traced as u64;
            }
        }
    }
}
