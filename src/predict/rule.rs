//! A method's rule: how a pixel's visibility is decided from its voters. [`Predict`] votes
//! ([`Vote`]), predicts and corrects by tracing ([`Flood`], [`correct`]); `brute` and `none`
//! have rules of their own ([`TraceAll`](super::brute::TraceAll),
//! [`Unshadowed`](super::none::Unshadowed)).

use std::marker::PhantomData;

use super::correct::{At, correct, forget_votes};
use super::flood::Flood;
use super::params::Params;
use super::scratch::Scratch;
use super::vote::Vote;
use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;
use crate::key::Key;

/// How a pixel's visibility is decided.
pub trait Rule: Send + Sync {
    /// The voting and flood rules' names (`""` where the rule has none).
    fn parts(&self) -> (&'static str, &'static str);

    /// Whether pixels must keep their blockers for the votes of later pixels.
    fn reads_blockers(&self) -> bool {
        false
    }

    /// The settings the rule reads.
    fn reads(&self) -> &'static [Key] {
        &[]
    }

    /// How many of a pixel's `voters` (region pixels, evaluated) must see a light for the
    /// rule to predict it. The temporal rules read their spatial voters with it, so they
    /// trust those voters no more than the rule itself does.
    fn min_voters(&self, bufs: &TileBuffers, voters: &[usize]) -> u32 {
        let _ = (bufs, voters);
        1
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
    trace_all_share: u32,
    rules: PhantomData<(V, F)>,
}

impl<V: Vote, F: Flood> Predict<V, F> {
    pub fn new(params: &Params) -> Predict<V, F> {
        // Settings only some flood rules read (not `boundary`'s one voter) are off for the rest.
        let reads = |key: Key| F::READS.contains(&key);
        Predict {
            min_voters: F::min_voters(params.min_voters),
            surface_voters: params.surface_voters,
            all_voters: params.all_voters && reads(Key::AllVoters),
            busy_voters: if reads(Key::BusyVoters) {
                params.busy_voters
            } else {
                0
            },
            trace_all_share: if reads(Key::TraceAllShare) {
                params.trace_all_share
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

    fn reads(&self) -> &'static [Key] {
        F::READS
    }

    /// `--min-voters`, raised to all of them with `--all-voters` and to `--busy-voters` where a
    /// voter's flooding caught a wrong prediction.
    fn min_voters(&self, bufs: &TileBuffers, voters: &[usize]) -> u32 {
        let mut min_voters = self.min_voters;
        if self.all_voters {
            min_voters = min_voters.max(voters.len() as u32);
        }
        if self.busy_voters > 0 && voters.iter().any(|&q| bufs.split[q].fixes > 0) {
            min_voters = min_voters.max(self.busy_voters);
        }
        min_voters
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
        let min_voters = Rule::min_voters(self, bufs, voters);
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
        F::queue_more(ctx, bits::rows(&bufs.above, w).row(i), sc);
        if self.trace_all_share > 0 && self.too_unsure(bufs, sc, i) {
            // [ours] The voters know little here: every light is traced, as at a pixel without
            // voters, and counted as every-light rays with no flood fixes. (Counting the
            // predictions the trace found wrong as fixes, so that neighbours ask four voters,
            // traced 5–9 % more on the cut-out panels and the metal spheres for 1–4 % fewer
            // wrong pairs: BENCHMARKS.md.)
            bufs.trace_all(ctx, i, at.keep_blockers);
            forget_votes(sc);
            return;
        }
        // 3–4. Trace the queue, flooding; keep the blockers.
        correct::<F>(ctx, bufs, sc, i, at);
    }
}

impl<V, F> Predict<V, F> {
    /// Whether the prediction in the scratch leaves at least `trace_all_share` percent of
    /// pixel `i`'s above-horizon lights to trace.
    #[inline]
    fn too_unsure(&self, bufs: &TileBuffers, sc: &Scratch, i: usize) -> bool {
        let w = bufs.words;
        let above = bits::count(bits::rows(&bufs.above, w).row(i));
        let queued = bits::count(&sc.queued);
        above > 0 && queued * 100 >= self.trace_all_share * above
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

#[cfg(test)]
mod tests {
    use super::super::nowarp::NoWarp;
    use super::super::testkit::{
        CONTRARY, DOWN, Frame, R, UP, at, buffers, list, origin, set_of, star,
    };
    use super::super::uncertainty::Uncertainty;
    use super::*;
    use crate::buffers::RaySplit;
    use glam::Vec3;

    /// The origin under the roof, with four voters beside it that agree UP is blocked (it is
    /// visible) and disagree on the three lights the roof blocks: 3 of its 7 lights (43 %)
    /// are uncertain. Returns what solving it with `--trace-all-share share` gives: (traced,
    /// visible, split).
    fn solve_with_share(share: u32) -> (Vec<usize>, Vec<usize>, RaySplit) {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let near = [(-0.01, 0.0), (0.01, 0.0), (0.0, -0.01), (0.0, 0.01)];
        let mut surfaces = vec![origin()];
        surfaces.extend(near.map(|(x, z)| at(Vec3::new(x, 0.0, z))));
        let (mut bufs, mut sc) = buffers(&ctx, &surfaces);
        let lights: Vec<usize> = (0..DOWN).collect();
        let roofed = [R[0], R[1], R[5]];
        for q in 0..5 {
            bits::rows_mut(&mut bufs.above, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &lights));
            if q == 0 {
                continue; // the pixel decided: nothing visible yet, as `begin_pixel` leaves it
            }
            let seen: Vec<usize> = lights
                .iter()
                .copied()
                .filter(|&j| j != UP && (q <= 2 || !roofed.contains(&j)))
                .collect();
            bits::rows_mut(&mut bufs.vis, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &seen));
        }
        let rule = Predict::<NoWarp, Uncertainty>::new(&Params {
            trace_all_share: share,
            ..Params::default()
        });
        rule.solve(&ctx, &mut bufs, &mut sc, 0, &[1, 2, 3, 4], CONTRARY);
        (list(&bufs.traced[..w]), list(&bufs.vis[..w]), bufs.split[0])
    }

    #[test]
    fn a_pixel_uncertain_of_its_share_of_lights_traces_them_all() {
        let (traced, vis, split) = solve_with_share(40);
        assert_eq!(traced, (0..DOWN).collect::<Vec<_>>(), "every light traced");
        assert_eq!(vis, [UP, R[2], R[3], R[4]], "the truth");
        // UP, predicted blocked by every voter, is found visible by the trace.
        let want = RaySplit {
            every: 7,
            flooded: 0,
            fixes: 0,
        };
        assert_eq!(split, want);
    }

    #[test]
    fn below_its_share_a_pixel_corrects_the_prediction_light_by_light() {
        for share in [0, 50] {
            let (traced, _, split) = solve_with_share(share);
            assert_eq!(split.every, 0, "share {share}: traced {traced:?}");
            assert!(traced.len() < DOWN, "share {share}: traced {traced:?}");
            for j in [R[0], R[1], R[5]] {
                assert!(traced.contains(&j), "share {share}: uncertain {j} traced");
            }
        }
    }
}
