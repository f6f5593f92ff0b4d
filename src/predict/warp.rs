//! Warp (ALGORITHM.md §3–4) [paper]: each voter's blockers are re-aimed from the current point
//! and vote, one vote per blocker, for the light whose cell they land in (the paper counts
//! warped blockers per cell). The only per-light loops run over the voters' blockers and the
//! cells they reach.
//!
//! Point and spot lights of the scene file [ours] have no cell to land in (a point light is
//! seen from each pixel along its own direction, and a blocker re-aimed from another point
//! blocks it only if it lands exactly on the segment to it): their blockers are not warped,
//! and they are voted as [`NoWarp`](super::nowarp::NoWarp) votes — each voter's own answer for
//! that light, which neighbouring pixels, seeing the light from nearly the same direction,
//! mostly share.

use super::scratch::Scratch;
use super::vote::Vote;
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
        let directional = ctx.light_dir.len();
        for &q in voters {
            let pq = bufs.surf[q].origin;
            for (j, t) in bufs.blockers.of(q) {
                if j >= directional {
                    continue; // a point light's blocker: not warped
                }
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
                .filter(|&&q| bits::get(bits::rows(&bufs.above, w).row(q), c))
                .count();
            if sc.votes[c] as usize >= k_j {
                bits::set(&mut sc.vote_all, c);
            }
        }
        // Point and spot lights: the voters' own answers.
        for j in directional..ctx.light_count() {
            let (mut any, mut all) = (false, true);
            for &q in voters {
                if bits::get(bits::rows(&bufs.above, w).row(q), j) {
                    let blocked = !bits::get(bits::rows(&bufs.vis, w).row(q), j);
                    any |= blocked;
                    all &= blocked;
                }
            }
            if any {
                bits::set(&mut sc.vote_any, j);
                if all {
                    bits::set(&mut sc.vote_all, j);
                }
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

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::testkit::{DOWN, Frame, R, UP, at, buffers, list, origin, set_of, star};
    use super::*;

    /// A voter: where it is, its above-horizon lights, its blockers (light, distance).
    struct Voter {
        p: Vec3,
        above: Vec<usize>,
        blockers: Vec<(usize, f32)>,
    }

    fn voter(x: f32, y: f32, blockers: &[(usize, f32)]) -> Voter {
        Voter {
            p: Vec3::new(x, y, 0.0),
            above: (0..DOWN).collect(),
            blockers: blockers.to_vec(),
        }
    }

    /// Votes of `voters` for the star's origin pixel: `(any, all)` as light lists, and the
    /// scratch after gathering.
    fn votes(frame: &Frame, voters: &[Voter]) -> ((Vec<usize>, Vec<usize>), Scratch) {
        let ctx = frame.ctx();
        let w = ctx.words();
        let mut surfaces = vec![origin()];
        surfaces.extend(voters.iter().map(|v| at(v.p)));
        let (mut bufs, mut sc) = buffers(&ctx, &surfaces);
        for (k, v) in voters.iter().enumerate() {
            let q = k + 1;
            bits::rows_mut(&mut bufs.above, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &v.above));
            bufs.blockers.begin(q);
            for &(j, t) in &v.blockers {
                bufs.blockers.push(q, j, t);
            }
        }
        let ids: Vec<usize> = (1..=voters.len()).collect();
        Warp::gather(&ctx, &bufs, &mut sc, 0, &ids);
        let (mut any, mut all) = (vec![0; w], vec![0; w]);
        let mut above = [0u64; 4];
        for m in 0..w {
            for (k, &q) in ids.iter().enumerate() {
                above[k] = bufs.above[q * w + m];
            }
            (any[m], all[m]) = Warp::word(&bufs, &sc, &ids, m, &above[..ids.len()]);
        }
        ((list(&any), list(&all)), sc)
    }

    #[test]
    fn warped_votes_land_in_the_cell_the_blocker_is_seen_in() {
        let s2 = 2f32.sqrt();
        // A voter at (1, 0, 0) blocked towards R[3] (up and to −X) at √2: the blocker is at
        // (0, 1, 0), straight above the origin, so it votes for UP, not R[3]. Likewise a voter
        // at (−1, 0, 0) blocked towards R[0] at √2. A voter at (3, −2, 0) blocked towards
        // R[0] at √2 has its blocker at (4, −1, 0): below the origin's horizon.
        // (what, voters, lights with some vote, lights with every vote)
        type Case = (&'static str, Vec<Voter>, Vec<usize>, Vec<usize>);
        let cases: Vec<Case> = vec![
            (
                "a blocker re-aimed into UP's cell votes for UP",
                vec![voter(1.0, 0.0, &[(R[3], s2)])],
                vec![UP],
                vec![UP],
            ),
            (
                "a blocker re-aimed below the current horizon does not vote",
                vec![voter(3.0, -2.0, &[(R[0], s2)])],
                vec![],
                vec![],
            ),
            (
                "one vote of two voters with the light above is not all",
                vec![voter(1.0, 0.0, &[(R[3], s2)]), voter(-1.0, 0.0, &[])],
                vec![UP],
                vec![],
            ),
            (
                "both voters' blockers land in UP: all",
                vec![
                    voter(1.0, 0.0, &[(R[3], s2)]),
                    voter(-1.0, 0.0, &[(R[0], s2)]),
                ],
                vec![UP],
                vec![UP],
            ),
            (
                "a voter with the light below its horizon is not counted",
                vec![
                    voter(1.0, 0.0, &[(R[3], s2)]),
                    Voter {
                        above: R.to_vec(),
                        ..voter(-1.0, 0.0, &[])
                    },
                ],
                vec![UP],
                vec![UP],
            ),
        ];
        let frame = Frame::new(&star());
        let mut failures = Vec::new();
        for (name, voters, any, all) in cases {
            let (got, _) = votes(&frame, &voters);
            let want = (any, all);
            if got != want {
                failures.push(format!("{name}: (any, all) {got:?}, want {want:?}"));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// [ours] a cell keeps its best-aligned warped blocker, whichever voter comes first.
    #[test]
    fn a_cell_keeps_its_best_aligned_blocker() {
        let s2 = 2f32.sqrt();
        let frame = Frame::new(&star());
        // Exactly above the origin at height 1, and at (0.5, 1.5, 0): in UP's cell too, at
        // 1.5 along UP but less aligned with it.
        let exact = || voter(1.0, 0.0, &[(R[3], s2)]);
        let off = || voter(-1.0, 0.0, &[(R[0], 1.5 * s2)]);
        let mut failures = Vec::new();
        for (name, voters) in [
            ("exact first", vec![exact(), off()]),
            ("exact last", vec![off(), exact()]),
        ] {
            let ((any, _), sc) = votes(&frame, &voters);
            let got = (any, sc.best_dot[UP], sc.best_dist[UP]);
            let ok = got.0 == [UP] && (got.1 - 1.0).abs() < 1e-5 && (got.2 - 1.0).abs() < 1e-5;
            if !ok {
                failures.push(format!("{name}: (any, best dot, best dist) {got:?}"));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
}
