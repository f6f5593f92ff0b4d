//! Boundary flooding (ALGORITHM.md §6) [paper]: the prediction is binary — any vote → blocked,
//! else visible — and the lights traced are those at the edge of the predicted shadow (whose
//! prediction differs from an adjacent above-horizon light's, Agrawala et al. 2000) and those
//! no voter has above its horizon; a trace floods only when it disagrees.

use super::flood::Flood;
use super::scratch::Scratch;
use crate::bits;
use crate::context::FrameContext;
use crate::key::Key;

/// Trace the visible/blocked boundary of the prediction, flood on mistakes.
pub struct Boundary;

impl Flood for Boundary {
    const NAME: &'static str = "boundary";
    const READS: &'static [Key] = &[Key::SurfaceVoters];

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

#[cfg(test)]
mod tests {
    use super::super::flood::table;
    use super::super::testkit::{DOWN, Frame, R, UP, and_not, list, set_of, spiral, star};
    use super::*;

    /// A pixel's above-horizon and predicted-blocked lights, what was queued before
    /// `queue_more` and what must be after.
    struct Case<'a> {
        name: &'a str,
        mine: &'a [usize],
        blocked: &'a [usize],
        before: &'a [usize],
        want: Vec<usize>,
    }

    #[test]
    fn predicts_blocked_on_any_vote_and_traces_what_no_voter_sees() {
        let (t, f) = (true, false);
        let rows = [
            // Below this pixel's horizon: neither, whatever the votes.
            ((f, f, f, f), (f, f)),
            ((f, t, t, f), (f, f)),
            ((f, t, t, t), (f, f)),
            ((f, f, t, t), (f, f)),
            // No voter has it above its horizon: traced (a warped vote may still land there).
            ((t, f, f, f), (f, t)),
            ((t, f, t, f), (t, t)),
            ((t, f, t, t), (t, t)),
            // Some voter sees it: any vote → blocked, none → visible; never unsure.
            ((t, t, f, f), (f, f)),
            ((t, t, t, f), (t, f)),
            ((t, t, t, t), (t, f)),
        ];
        let failures = table::predict_failures(Boundary::predict, &rows);
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    #[test]
    fn floods_only_when_mistaken() {
        let (t, f) = (true, false);
        let want = [((f, f), f), ((f, t), t), ((t, f), f), ((t, t), t)];
        let failures = table::floods_failures(Boundary::floods, want);
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    #[test]
    fn min_voters_is_one_whatever_the_setting() {
        for s in 0..=8 {
            assert_eq!(Boundary::min_voters(s), 1, "setting {s}");
        }
    }

    /// On the star (UP borders every ring light, ring lights their two ring neighbours, DOWN
    /// every ring light): the lights queued are the above-horizon ones with an above-horizon
    /// neighbour predicted otherwise; lights already queued stay queued.
    #[test]
    fn queues_the_edges_of_the_predicted_shadow() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let up_and_ring: Vec<usize> = (0..DOWN).collect();
        let all_but_r2: Vec<usize> = up_and_ring.iter().copied().filter(|&j| j != R[2]).collect();
        let cases = vec![
            // DOWN's prediction bit is clear (not above) but it has no say.
            Case {
                name: "all visible: no edge",
                mine: &up_and_ring,
                blocked: &[],
                before: &[],
                want: vec![],
            },
            Case {
                name: "UP blocked: UP and every ring light",
                mine: &up_and_ring,
                blocked: &[UP],
                before: &[],
                want: up_and_ring.clone(),
            },
            Case {
                name: "R0 blocked: R0, UP and R0's ring neighbours",
                mine: &up_and_ring,
                blocked: &[R[0]],
                before: &[],
                want: vec![UP, R[0], R[1], R[5]],
            },
            Case {
                name: "R0, R1, R5 blocked: all but R3, whose neighbours are all visible",
                mine: &up_and_ring,
                blocked: &[R[0], R[1], R[5]],
                before: &[],
                want: vec![UP, R[0], R[1], R[2], R[4], R[5]],
            },
            Case {
                name: "R2 below the horizon is no neighbour: R1 blocked queues R1, UP, R0",
                mine: &all_but_r2,
                blocked: &[R[1]],
                before: &[],
                want: vec![UP, R[0], R[1]],
            },
            Case {
                name: "an already queued light stays queued",
                mine: &up_and_ring,
                blocked: &[],
                before: &[R[3]],
                want: vec![R[3]],
            },
        ];
        let mut failures = Vec::new();
        let mut sc = Scratch::default();
        sc.prepare(ctx.light_count());
        for case in cases {
            let mine = set_of(w, case.mine);
            sc.pred_vis
                .copy_from_slice(&and_not(&mine, &set_of(w, case.blocked)));
            sc.queued.copy_from_slice(&set_of(w, case.before));
            Boundary::queue_more(&ctx, &mine, &mut sc);
            let got = list(&sc.queued);
            if got != case.want {
                failures.push(format!(
                    "{}: queued {got:?}, want {:?}",
                    case.name, case.want
                ));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// The same rule past the first word: 150 lights, the upper half above the horizon, a
    /// shadow over x > 0.3. Each light is checked against the definition, read off its
    /// neighbour list.
    #[test]
    fn queues_the_edges_in_every_word() {
        let dirs = spiral(150);
        let frame = Frame::new(&dirs);
        let ctx = frame.ctx();
        let w = ctx.words();
        let mine: Vec<usize> = (0..dirs.len()).filter(|&j| dirs[j].y > 0.0).collect();
        let blocked: Vec<usize> = mine.iter().copied().filter(|&j| dirs[j].x > 0.3).collect();
        let mut sc = Scratch::default();
        sc.prepare(ctx.light_count());
        let mine = set_of(w, &mine);
        sc.pred_vis
            .copy_from_slice(&and_not(&mine, &set_of(w, &blocked)));
        Boundary::queue_more(&ctx, &mine, &mut sc);
        let want: Vec<usize> = list(&mine)
            .into_iter()
            .filter(|&j| {
                ctx.lights.neighbors(j).iter().any(|&a| {
                    let a = a as usize;
                    bits::get(&mine, a) && blocked.contains(&a) != blocked.contains(&j)
                })
            })
            .collect();
        let got = list(&sc.queued);
        assert!(
            want.iter().any(|&j| j >= 64),
            "the edge must reach past the first word"
        );
        assert_eq!(got, want);
    }
}
