//! A method's rule: how a pixel's visibility is decided from its voters. [`Predict`] votes
//! ([`Vote`]), predicts and corrects by tracing ([`Flood`], [`correct`]); `brute` and `none`
//! have rules of their own ([`TraceAll`](super::TraceAll), [`Unshadowed`](super::Unshadowed)).

use std::marker::PhantomData;

use super::correct::{At, correct};
use super::{Flood, Params, Scratch, Vote};
use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;

/// How a pixel's visibility is decided.
pub trait Rule: Send + Sync {
    /// The voting and flood rules' names (`""` where the rule has none).
    fn parts(&self) -> (&'static str, &'static str);

    /// Whether pixels must keep their blockers for the votes of later pixels.
    fn reads_blockers(&self) -> bool {
        false
    }

    /// The settings the rule reads.
    fn reads(&self) -> &'static [&'static str] {
        &[]
    }

    /// Decides region pixel `i` (begun: surface and above-horizon lights set) from the region
    /// pixels `voters` (valid: evaluated, not background; at most four): sets its `vis`,
    /// `traced`, `rays` and `split`, and its blockers when `at.keep_blockers`.
    fn solve(
        &self,
        ctx: &FrameContext,
        bufs: &mut TileBuffers,
        sc: &mut Scratch,
        i: usize,
        voters: &[usize],
        at: At,
    );
}

/// Vote with `V`, predict and correct with `F`. A pixel without voters traces every light.
pub struct Predict<V, F> {
    min_voters: u32,
    surface_voters: bool,
    all_voters: bool,
    busy_voters: u32,
    rules: PhantomData<(V, F)>,
}

impl<V: Vote, F: Flood> Predict<V, F> {
    pub fn new(params: &Params) -> Predict<V, F> {
        Predict {
            min_voters: F::min_voters(params.min_voters),
            surface_voters: params.surface_voters,
            // Only where the flood rule counts voters at all (not `boundary`'s one voter).
            all_voters: params.all_voters && F::READS.contains(&"all_voters"),
            busy_voters: if F::READS.contains(&"busy_voters") {
                params.busy_voters
            } else {
                0
            },
            rules: PhantomData,
        }
    }
}

impl<V: Vote, F: Flood> Rule for Predict<V, F> {
    fn parts(&self) -> (&'static str, &'static str) {
        (V::NAME, F::NAME)
    }

    fn reads_blockers(&self) -> bool {
        V::READS_BLOCKERS
    }

    fn reads(&self) -> &'static [&'static str] {
        F::READS
    }

    fn solve(
        &self,
        ctx: &FrameContext,
        bufs: &mut TileBuffers,
        sc: &mut Scratch,
        i: usize,
        voters: &[usize],
        at: At,
    ) {
        if !bufs.surf[i].hit {
            return;
        }
        let mut same = [0usize; 4];
        let voters = if self.surface_voters {
            let n = on_surface(bufs, i, voters, &mut same);
            &same[..n]
        } else {
            voters
        };
        if voters.is_empty() {
            bufs.trace_all(ctx, i, at.keep_blockers);
            return;
        }
        debug_assert!(voters.len() <= 4);
        let at = at.for_voters(bufs, voters);
        let (w, nv) = (bufs.words, voters.len());
        // How many voters must see a light for it to be predicted.
        let mut min_voters = self.min_voters;
        if self.all_voters {
            min_voters = min_voters.max(nv as u32);
        }
        if self.busy_voters > 0 && voters.iter().any(|&q| bufs.split[q].fixes > 0) {
            min_voters = min_voters.max(self.busy_voters);
        }
        // 1. What the votes need (warp: the voters' blockers re-aimed from this point).
        V::gather(ctx, bufs, sc, i, voters);
        // 2. The prediction, word by word: `any` = some vote, `all` = every voter's vote.
        let mut above = [0u64; 4];
        for m in 0..w {
            for (k, &q) in voters.iter().enumerate() {
                above[k] = bufs.above[q * w + m];
            }
            let (any, all) = V::word(bufs, sc, voters, m, &above[..nv]);
            let enough = bits::at_least(&above[..nv], min_voters);
            let my = bufs.above[i * w + m];
            let (mut blocked, mut unsure) = F::predict(my, enough, any, all);
            // [ours] A point or spot light has no neighbours, so no light-space edge to trace
            // or flood along: where its voters disagree it is traced, whatever the flood rule
            // (for uncertainty flooding this is already so).
            unsure |= my & ctx.point_bits[m] & any & !all;
            if at.majority && nv == 4 && unsure != 0 {
                let (b, v) = majority(bufs, voters, m, &above);
                blocked |= unsure & b;
                unsure &= !(b | v);
            }
            sc.pred_vis[m] = my & !blocked;
            sc.uncertain[m] = unsure;
            sc.queued[m] = unsure;
        }
        F::queue_more(ctx, &bufs.above[i * w..(i + 1) * w], sc);
        // 3–4. Trace the queue, flooding; keep the blockers.
        correct::<F>(ctx, bufs, sc, i, at);
    }
}

/// The `voters` of pixel `i` on its surface, into `out`; returns how many. A voter's normal
/// within about 37° of the pixel's (cosine 0.8) and its point within about 17° of the pixel's
/// tangent plane (sine 0.3) [ours].
fn on_surface(bufs: &TileBuffers, i: usize, voters: &[usize], out: &mut [usize; 4]) -> usize {
    let s = bufs.surf[i];
    let mut n = 0;
    for &q in voters {
        let v = bufs.surf[q];
        let d = v.p - s.p;
        if s.n.dot(v.n) >= 0.8 && s.n.dot(d).abs() <= 0.3 * d.length() {
            out[n] = q;
            n += 1;
        }
    }
    n
}

/// Word `m` of the lights every one of the four `voters` has above its horizon and at least
/// three of them found blocked (`.0`) or visible (`.1`), from their own visibility.
#[inline]
fn majority(bufs: &TileBuffers, voters: &[usize], m: usize, above: &[u64; 4]) -> (u64, u64) {
    let w = bufs.words;
    let all_above = above[0] & above[1] & above[2] & above[3];
    let mut vis = [0u64; 4];
    let mut blocked = [0u64; 4];
    for (k, &q) in voters.iter().enumerate() {
        vis[k] = bufs.vis[q * w + m];
        blocked[k] = !vis[k];
    }
    (
        all_above & bits::at_least(&blocked, 3),
        all_above & bits::at_least(&vis, 3),
    )
}
