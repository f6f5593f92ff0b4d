//! Warp (ALGORITHM.md §3–4) [paper]: each voter's blockers are re-aimed from the current point
//! and vote, one vote per blocker, for the light whose cell they land in (the paper counts
//! warped blockers per cell). The only per-light loops run over the voters' blockers and the
//! cells they reach.

use super::{Scratch, Vote};
use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;

/// Neighbours' warped blockers vote.
pub struct Warp;

impl Vote for Warp {
    const NAME: &'static str = "warp";
    const READS_BLOCKERS: bool = true;

    fn gather(
        ctx: &FrameContext,
        bufs: &TileBuffers,
        sc: &mut Scratch,
        i: usize,
        voters: &[usize],
    ) {
        let s = bufs.surf[i];
        let w = bufs.words;
        for &q in voters {
            let pq = bufs.surf[q].p;
            for (j, t) in bufs.blockers.of(q) {
                let b = pq + ctx.light_dir[j] * t;
                let d = b - s.p;
                if s.n.dot(d) <= 0.0 {
                    continue; // re-aimed below the current horizon: cannot block it
                }
                let len = d.length();
                if len <= 0.0 {
                    continue;
                }
                let dn = d / len;
                let c = ctx.lights.cell_of_near(dn, j) as usize;
                if sc.votes[c] == 0 {
                    sc.touched.push(c as u32);
                }
                sc.votes[c] = sc.votes[c].saturating_add(1);
                // [ours] a light predicted blocked keeps the warped blocker best aligned with
                // it, so later pixels can warp it in turn.
                let align = dn.dot(ctx.light_dir[c]);
                if align > sc.best_dot[c] {
                    sc.best_dot[c] = align;
                    sc.best_dist[c] = d.dot(ctx.light_dir[c]).max(0.0);
                }
            }
        }
        // A cell's votes are all its voters' when there are at least as many as voters with
        // the light above their horizon.
        sc.vote_any.fill(0);
        sc.vote_all.fill(0);
        for &c in &sc.touched {
            let c = c as usize;
            bits::set(&mut sc.vote_any, c);
            let k_j = voters
                .iter()
                .filter(|&&q| bits::get(&bufs.above[q * w..(q + 1) * w], c))
                .count();
            if sc.votes[c] as usize >= k_j {
                bits::set(&mut sc.vote_all, c);
            }
        }
    }

    #[inline]
    fn word(
        _bufs: &TileBuffers,
        sc: &Scratch,
        _voters: &[usize],
        m: usize,
        _above: &[u64],
    ) -> (u64, u64) {
        (sc.vote_any[m], sc.vote_all[m])
    }
}
