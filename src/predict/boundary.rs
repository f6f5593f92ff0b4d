//! Boundary flooding (ALGORITHM.md §6) [paper]: the prediction is binary — any vote → blocked,
//! else visible — and the lights traced are those at the edge of the predicted shadow (whose
//! prediction differs from an adjacent above-horizon light's, Agrawala et al. 2000) and those
//! no voter has above its horizon; a trace floods only when it disagrees.

use super::{Flood, Scratch};
use crate::bits;
use crate::context::FrameContext;

/// Trace the visible/blocked boundary of the prediction, flood on mistakes.
pub struct Boundary;

impl Flood for Boundary {
    const NAME: &'static str = "boundary";
    const READS: &'static [&'static str] = &[];

    /// [paper] any vote → blocked: one voter with the light above its horizon is enough.
    fn min_voters(_setting: u32) -> u32 {
        1
    }

    #[inline]
    fn predict(my: u64, enough: u64, any: u64, _all: u64) -> (u64, u64) {
        (my & any, my & !enough)
    }

    /// Lights whose prediction differs from an adjacent above-horizon light's.
    fn queue_more(ctx: &FrameContext, mine: &[u64], sc: &mut Scratch) {
        for (m, &word) in mine.iter().enumerate() {
            let mut my = word;
            while my != 0 {
                let j = m * 64 + my.trailing_zeros() as usize;
                my &= my - 1;
                let pj = bits::get(&sc.pred_vis, j);
                let edge = ctx.lights.neighbors(j).iter().any(|&a| {
                    let a = a as usize;
                    bits::get(mine, a) && bits::get(&sc.pred_vis, a) != pj
                });
                if edge {
                    bits::set(&mut sc.queued, j);
                }
            }
        }
    }

    #[inline]
    fn floods(_uncertain: bool, disagrees: bool) -> bool {
        disagrees
    }
}
