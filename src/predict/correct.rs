//! Correcting a prediction by tracing (ALGORITHM.md §6): the queued lights are traced, and a
//! trace the flood rule says floods queues its untraced above-horizon neighbour lights (all,
//! or with [`FloodTo::Contrary`] only those predicted opposite to the traced answer), until no
//! trace disagrees. Which neighbours a trace floods to depends only on the prediction and the
//! traced answer, so the traced set does not depend on the queue's order.

use super::flood::{Flood, FloodTo};
use super::scratch::Scratch;
use crate::accel::PACKET;
use crate::bits;
use crate::buffers::{RaySplit, TileBuffers};
use crate::context::FrameContext;

/// How a pixel is decided where it sits in its method's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct At {
    /// Which neighbours a flooding trace queues, resolved for the pixel's level.
    pub flood_to: FloodTo,
    /// Keep the pixel's blockers: later pixels read them for a warping vote.
    pub keep_blockers: bool,
    /// Also keep, for each light predicted blocked, the warped blocker that voted for it
    /// ([ours]; the order says).
    pub keep_predicted: bool,
    /// Inside a pixel (the voters closer than a pixel apart): a light on which three of four
    /// voters agree is taken from them rather than traced.
    pub majority: bool,
    /// The pixel's voters lie closer than a pixel apart (samples per pixel): closer than the
    /// previous frame's pixels, so `--temporal` leaves it to them.
    pub inside: bool,
}

impl At {
    /// The pixel's own rule where it depends on its `voters` (region pixels, evaluated):
    /// [`FloodTo::Adaptive`] becomes `All` where a voter's flooding caught a wrong prediction,
    /// `Contrary` elsewhere.
    #[inline]
    pub fn for_voters(self, bufs: &TileBuffers, voters: &[usize]) -> At {
        if self.flood_to != FloodTo::Adaptive {
            return self;
        }
        let busy = voters.iter().any(|&q| bufs.split[q].fixes > 0);
        At {
            flood_to: if busy {
                FloodTo::All
            } else {
                FloodTo::Contrary
            },
            ..self
        }
    }
}

/// Traces the queued lights of region pixel `i` (begun, hit) starting from the prediction in
/// the scratch (`pred_vis`, `uncertain`, `queued`), flooding where `F` says, then records the
/// pixel's blockers when `at.keep_blockers`. Sets the pixel's `vis`, `traced`, `rays` and
/// `split`.
pub fn correct<F: Flood>(
    ctx: &FrameContext,
    bufs: &mut TileBuffers,
    sc: &mut Scratch,
    i: usize,
    at: At,
) {
    queue_predicted(sc);
    trace_queue::<F>(ctx, bufs, sc, i, at);
}

/// The initial queue: the lights the prediction queued (`sc.queued`), ascending.
#[inline]
fn queue_predicted(sc: &mut Scratch) {
    sc.queue.clear();
    bits::for_each(&sc.queued, |j| sc.queue.push(j as u32));
}

/// [`correct`] that floods only into lights outside `closed` (`closed` ⊆ the pixel's
/// above-horizon lights, disjoint from `sc.queued`): lights whose prediction is trusted are
/// never queued by a neighbour's trace.
pub fn correct_closed<F: Flood>(
    ctx: &FrameContext,
    bufs: &mut TileBuffers,
    sc: &mut Scratch,
    i: usize,
    at: At,
    closed: &[u64],
) {
    queue_predicted(sc);
    for (q, &c) in sc.queued.iter_mut().zip(closed) {
        *q |= c;
    }
    trace_queue::<F>(ctx, bufs, sc, i, at);
}

/// [`correct`] from an initial queue already in `sc.queue`: the lights of `sc.queued`, in any
/// order (the tests permute it; the traced set must not change).
// Word loops index several parallel bitsets at once; iterator chains would hide that.
#[allow(clippy::needless_range_loop)]
#[inline]
fn trace_queue<F: Flood>(
    ctx: &FrameContext,
    bufs: &mut TileBuffers,
    sc: &mut Scratch,
    i: usize,
    at: At,
) {
    let s = bufs.surf[i];
    let w = bufs.words;
    let TileBuffers {
        above,
        vis,
        traced,
        rays,
        split,
        blockers,
        ..
    } = bufs;
    let mine = bits::rows(above, w).row(i);
    // 3. Correction: trace the queue, flooding where a trace was uncertain or disagreed.
    let tr = bits::rows_mut(traced, w).into_row(i);
    let out = bits::rows_mut(vis, w).into_row(i);
    tr.fill(0);
    out.copy_from_slice(&sc.pred_vis);
    let mut head = 0;
    // Lights queued beyond this were queued by flooding.
    let predicted_queue = sc.queue.len();
    let mut fixes = 0;
    // The queue is traced in waves of up to PACKET lights, one packet from the pixel's point
    // each (one ray at a time when the blockers' distances are kept). A wave's results are
    // taken in queue order and flooding only appends to the queue, so the traced set and the
    // queue's order are those of tracing one light at a time.
    while head < sc.queue.len() {
        let wave = head..sc.queue.len().min(head + PACKET);
        let blocked = if at.keep_blockers {
            0
        } else {
            ctx.trace_packet(&s, &sc.queue[wave.clone()])
        };
        for (k, q) in wave.clone().enumerate() {
            let j = sc.queue[q] as usize;
            bits::set(tr, j);
            let visible = if at.keep_blockers {
                match ctx.trace_blocker(&s, j) {
                    Some(t) => {
                        sc.hit_dist[j] = t;
                        false
                    }
                    None => true,
                }
            } else {
                blocked & (1 << k) == 0
            };
            let predicted = bits::get(&sc.pred_vis, j);
            if q >= predicted_queue && visible != predicted {
                fixes += 1;
            }
            if visible {
                bits::set(out, j);
            } else {
                bits::clear(out, j);
            }
            if F::floods(bits::get(&sc.uncertain, j), visible != predicted) {
                // Untraced above-horizon neighbours (with `Contrary`, those predicted
                // opposite to this answer), appended in ascending order (as the adjacency
                // lists them), a word at a time.
                let nb = ctx.lights.neighbor_bits(j);
                for m in 0..w {
                    let to = match at.flood_to {
                        // `Auto` is resolved per frame (`Params::for_cutouts`),
                        // `ContraryFinest` per pass by the driver (`FloodTo::at_level`),
                        // `Adaptive` per pixel (`At::for_voters`), before they get here.
                        FloodTo::All
                        | FloodTo::ContraryFinest
                        | FloodTo::Adaptive
                        | FloodTo::Auto => !0,
                        FloodTo::Contrary if visible => !sc.pred_vis[m],
                        FloodTo::Contrary => sc.pred_vis[m],
                    };
                    let mut new = nb[m] & mine[m] & !sc.queued[m] & to;
                    sc.queued[m] |= new;
                    while new != 0 {
                        sc.queue.push((m * 64) as u32 + new.trailing_zeros());
                        new &= new - 1;
                    }
                }
            }
        }
        head = wave.end;
    }
    let n = sc.queue.len() as u32;
    rays[i] = n;
    split[i] = RaySplit {
        every: 0,
        flooded: n - predicted_queue as u32,
        fixes,
    };

    // 4. Blockers of this pixel: traced hits, and (at.keep_predicted) for predicted-blocked
    //    lights the warped blocker that voted for them.
    if at.keep_blockers {
        blockers.begin(i);
        for m in 0..w {
            let mut blocked = mine[m] & !out[m];
            while blocked != 0 {
                let j = m * 64 + blocked.trailing_zeros() as usize;
                blocked &= blocked - 1;
                if bits::get(tr, j) {
                    blockers.push(i, j, sc.hit_dist[j]);
                } else if at.keep_predicted && sc.best_dot[j] > f32::NEG_INFINITY {
                    blockers.push(i, j, sc.best_dist[j]);
                }
            }
        }
    }
    forget_votes(sc);
}

/// Clears the warped-blocker tallies the pixel's vote left in the scratch.
pub(super) fn forget_votes(sc: &mut Scratch) {
    for &c in &sc.touched {
        sc.best_dot[c as usize] = f32::NEG_INFINITY;
        sc.votes[c as usize] = 0;
    }
    sc.touched.clear();
}

#[cfg(test)]
mod tests {
    use super::super::boundary::Boundary;
    use super::super::testkit::{
        DOWN, Frame, R, UP, and_not, buffers, list, origin, set_of, spiral, star,
    };
    use super::super::uncertainty::Uncertainty;
    use super::*;

    type Solve = fn(&FrameContext, &mut TileBuffers, &mut Scratch, usize, At);

    /// The star's lights the roof blocks from the origin (see the testkit).
    const BLOCKED: [usize; 3] = [R[0], R[1], R[5]];

    /// One pixel at the origin under the roof, every star light but DOWN above its horizon, a
    /// hand-made prediction, and what correcting it must trace.
    struct Case {
        name: &'static str,
        solve: Solve,
        flood_to: FloodTo,
        predicted_blocked: &'static [usize],
        uncertain: &'static [usize],
        queued: &'static [usize],
        traced: &'static [usize],
        flooded: u32,
        fixes: u32,
    }

    fn flood_cases() -> Vec<Case> {
        let (unc, bnd): (Solve, Solve) = (correct::<Uncertainty>, correct::<Boundary>);
        vec![
            Case {
                name: "UP predicted blocked, traced visible: all floods to every ring light",
                solve: unc,
                flood_to: FloodTo::All,
                predicted_blocked: &[UP, R[0], R[1], R[5]],
                uncertain: &[],
                queued: &[UP],
                traced: &[UP, R[0], R[1], R[2], R[3], R[4], R[5]],
                flooded: 6,
                fixes: 0,
            },
            Case {
                name: "UP predicted blocked, traced visible: contrary floods to those predicted \
                       blocked",
                solve: unc,
                flood_to: FloodTo::Contrary,
                predicted_blocked: &[UP, R[0], R[1], R[5]],
                uncertain: &[],
                queued: &[UP],
                traced: &[UP, R[0], R[1], R[5]],
                flooded: 3,
                fixes: 0,
            },
            // R[0] and R[5] wrongly predicted visible: tracing R[0] finds R[5], whose trace
            // floods on to R[4].
            Case {
                name: "R0 predicted visible, traced blocked: all floods and cascades",
                solve: unc,
                flood_to: FloodTo::All,
                predicted_blocked: &[R[1]],
                uncertain: &[],
                queued: &[R[0]],
                traced: &[UP, R[0], R[1], R[4], R[5]],
                flooded: 4,
                fixes: 1,
            },
            Case {
                name: "R0 predicted visible, traced blocked: contrary floods to those predicted \
                       visible only",
                solve: unc,
                flood_to: FloodTo::Contrary,
                predicted_blocked: &[R[1]],
                uncertain: &[],
                queued: &[R[0]],
                traced: &[UP, R[0], R[4], R[5]],
                flooded: 3,
                fixes: 1,
            },
            Case {
                name: "boundary floods on disagreement like uncertainty",
                solve: bnd,
                flood_to: FloodTo::All,
                predicted_blocked: &[R[1]],
                uncertain: &[],
                queued: &[R[0]],
                traced: &[UP, R[0], R[1], R[4], R[5]],
                flooded: 4,
                fixes: 1,
            },
            Case {
                name: "an uncertain light floods though its trace agrees (all)",
                solve: unc,
                flood_to: FloodTo::All,
                predicted_blocked: &BLOCKED,
                uncertain: &[R[2]],
                queued: &[R[2]],
                traced: &[UP, R[1], R[2], R[3]],
                flooded: 3,
                fixes: 0,
            },
            Case {
                name: "an uncertain light floods though its trace agrees (contrary)",
                solve: unc,
                flood_to: FloodTo::Contrary,
                predicted_blocked: &BLOCKED,
                uncertain: &[R[2]],
                queued: &[R[2]],
                traced: &[R[1], R[2]],
                flooded: 1,
                fixes: 0,
            },
            Case {
                name: "boundary: an uncertain light whose trace agrees does not flood",
                solve: bnd,
                flood_to: FloodTo::All,
                predicted_blocked: &BLOCKED,
                uncertain: &[R[2]],
                queued: &[R[2]],
                traced: &[R[2]],
                flooded: 0,
                fixes: 0,
            },
        ]
    }

    /// Every case, tracing in packets and one light at a time (keeping blockers): the traced
    /// set, the rays and their split, and the visibility (traced lights as traced, the others
    /// as predicted). DOWN borders every ring light but is below the horizon: never traced.
    #[test]
    fn flooding_queues_the_neighbours_its_rule_names() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let mine: Vec<usize> = (0..DOWN).collect();
        let mut failures = Vec::new();
        for case in flood_cases() {
            for keep_blockers in [false, true] {
                let (mut bufs, mut sc) = buffers(&ctx, &[origin()]);
                bufs.above.copy_from_slice(&set_of(w, &mine));
                let blocked = set_of(w, case.predicted_blocked);
                sc.pred_vis.copy_from_slice(&and_not(&bufs.above, &blocked));
                sc.uncertain.copy_from_slice(&set_of(w, case.uncertain));
                sc.queued.copy_from_slice(&set_of(w, case.queued));
                let at = At {
                    flood_to: case.flood_to,
                    keep_blockers,
                    keep_predicted: false,
                    majority: false,
                    inside: false,
                };
                (case.solve)(&ctx, &mut bufs, &mut sc, 0, at);
                let want_vis: Vec<usize> = mine
                    .iter()
                    .copied()
                    .filter(|j| {
                        if case.traced.contains(j) {
                            !BLOCKED.contains(j)
                        } else {
                            !case.predicted_blocked.contains(j)
                        }
                    })
                    .collect();
                let want_split = RaySplit {
                    every: 0,
                    flooded: case.flooded,
                    fixes: case.fixes,
                };
                let got = (
                    list(&bufs.traced),
                    bufs.rays[0],
                    bufs.split[0],
                    list(&bufs.vis),
                );
                let want = (
                    case.traced.to_vec(),
                    case.traced.len() as u32,
                    want_split,
                    want_vis,
                );
                if got != want {
                    failures.push(format!(
                        "{} (keep_blockers {keep_blockers}):\n  got  (traced, rays, split, \
                         vis) {got:?}\n  want {want:?}",
                        case.name
                    ));
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// A pixel keeping blockers records its traced hits at their distance and, with
    /// `keep_predicted`, the warped blocker that voted for an untraced predicted-blocked light.
    #[test]
    fn kept_blockers_are_the_traced_hits_and_the_voting_ones() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let mut failures = Vec::new();
        for keep_predicted in [false, true] {
            let (mut bufs, mut sc) = buffers(&ctx, &[origin()]);
            bufs.above
                .copy_from_slice(&set_of(w, &(0..DOWN).collect::<Vec<_>>()));
            // Predicted: the truth. Traced: R[2], flooding (contrary) to R[1] alone, so R[0]
            // and R[5] stay predicted blocked; a warped blocker voted for R[0] only.
            sc.pred_vis
                .copy_from_slice(&and_not(&bufs.above, &set_of(w, &BLOCKED)));
            sc.uncertain.copy_from_slice(&set_of(w, &[R[2]]));
            sc.queued.copy_from_slice(&set_of(w, &[R[2]]));
            sc.best_dot[R[0]] = 0.9;
            sc.best_dist[R[0]] = 2.5;
            let at = At {
                flood_to: FloodTo::Contrary,
                keep_blockers: true,
                keep_predicted,
                majority: false,
                inside: false,
            };
            correct::<Uncertainty>(&ctx, &mut bufs, &mut sc, 0, at);
            let got: Vec<(usize, f32)> = bufs.blockers.of(0).collect();
            let mut want = vec![(R[1], f32::NAN)];
            if keep_predicted {
                want.insert(0, (R[0], 2.5));
            }
            // R[1] leaves the origin at 45° elevation towards +X+Z: the roof is √2 away.
            let close = got.len() == want.len()
                && got.iter().zip(&want).all(|(g, w)| {
                    g.0 == w.0
                        && if w.1.is_nan() {
                            (g.1 - 2f32.sqrt()).abs() < 1e-3
                        } else {
                            g.1 == w.1
                        }
                });
            if !close {
                failures.push(format!(
                    "keep_predicted {keep_predicted}: got {got:?}, want {want:?} (NaN: √2)"
                ));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// A deterministic shuffle (Fisher–Yates on a fixed linear congruential sequence).
    fn shuffle(q: &mut [u32]) {
        let mut s = 0x2545_f491u32;
        for k in (1..q.len()).rev() {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            q.swap(k, (s >> 8) as usize % (k + 1));
        }
    }

    /// What correcting a pixel leaves: visibility, traced set, rays, split, blockers.
    type Outcome = (Vec<u64>, Vec<u64>, u32, RaySplit, Vec<(usize, f32)>);

    /// `adaptive` floods to all where a voter's flooding caught a wrong prediction, to
    /// contrary lights where none did; the other rules are left as they are.
    #[test]
    fn adaptive_flooding_follows_the_voters_fixes() {
        let mut bufs = TileBuffers {
            split: vec![RaySplit::default(); 3],
            ..TileBuffers::default()
        };
        bufs.split[2].fixes = 1;
        let at = |flood_to| At {
            flood_to,
            keep_blockers: false,
            keep_predicted: false,
            majority: false,
            inside: false,
        };
        let resolved = |f, voters: &[usize]| at(f).for_voters(&bufs, voters).flood_to;
        assert_eq!(resolved(FloodTo::Adaptive, &[0, 1]), FloodTo::Contrary);
        assert_eq!(resolved(FloodTo::Adaptive, &[0, 2]), FloodTo::All);
        assert_eq!(resolved(FloodTo::Adaptive, &[]), FloodTo::Contrary);
        for f in [FloodTo::All, FloodTo::Contrary] {
            assert_eq!(resolved(f, &[0, 2]), f);
            assert_eq!(resolved(f, &[0, 1]), f);
        }
    }

    /// ALGORITHM.md §6: the traced set does not depend on the queue's order. 300 lights (five
    /// words) under the roof, a prediction whose shadow edge crosses the true one, more queued
    /// lights than a packet holds: ascending (what `correct` builds), descending and shuffled
    /// initial queues give the same outcome, for both flood rules, both neighbour rules, and
    /// both ways of tracing.
    #[test]
    fn the_traced_set_does_not_depend_on_the_queue_order() {
        type Trace = fn(&FrameContext, &mut TileBuffers, &mut Scratch, usize, At);
        let dirs = spiral(300);
        let frame = Frame::new(&dirs);
        let ctx = frame.ctx();
        let rules: [(&str, Trace); 2] = [
            ("uncertainty", trace_queue::<Uncertainty>),
            ("boundary", trace_queue::<Boundary>),
        ];
        type Reorder = fn(&mut [u32]);
        let orders: [(&str, Reorder); 3] = [
            ("ascending", |_| {}),
            ("descending", |q| q.reverse()),
            ("shuffled", shuffle),
        ];
        let run = |trace: Trace, at: At, order: Reorder| -> (Outcome, usize) {
            let (mut bufs, mut sc) = buffers(&ctx, &[origin()]);
            crate::shade::above_horizon(&ctx.shade_lights, origin().n, &mut bufs.above);
            for (j, d) in dirs.iter().enumerate() {
                if !bits::get(&bufs.above, j) {
                    continue;
                }
                if d.z <= 0.3 {
                    bits::set(&mut sc.pred_vis, j);
                }
                if j % 7 == 0 {
                    bits::set(&mut sc.uncertain, j);
                }
                if j % 7 == 0 || j % 5 == 0 {
                    bits::set(&mut sc.queued, j);
                }
            }
            queue_predicted(&mut sc);
            let queued = sc.queue.len();
            order(&mut sc.queue);
            trace(&ctx, &mut bufs, &mut sc, 0, at);
            let outcome = (
                bufs.vis.clone(),
                bufs.traced.clone(),
                bufs.rays[0],
                bufs.split[0],
                bufs.blockers.of(0).collect(),
            );
            (outcome, queued)
        };
        let mut failures = Vec::new();
        for (rule, trace) in rules {
            for flood_to in [FloodTo::All, FloodTo::Contrary] {
                for keep_blockers in [false, true] {
                    let at = At {
                        flood_to,
                        keep_blockers,
                        keep_predicted: false,
                        majority: false,
                        inside: false,
                    };
                    let (want, queued) = run(trace, at, orders[0].1);
                    // The case must exercise what it guards: several waves, and flooding.
                    assert!(queued > PACKET, "{rule}: only {queued} queued");
                    assert!(want.3.flooded > 0, "{rule} {flood_to}: nothing flooded");
                    assert_eq!(want.2 as usize, bits::count(&want.1) as usize);
                    for &(name, order) in &orders[1..] {
                        let (got, _) = run(trace, at, order);
                        if got != want {
                            failures.push(format!(
                                "{rule} {flood_to} keep_blockers {keep_blockers}: {name} \
                                 queue gives {} rays, split {:?}, traced {:?}; ascending {} \
                                 rays, split {:?}, traced {:?}",
                                got.2,
                                got.3,
                                list(&got.1),
                                want.2,
                                want.3,
                                list(&want.1)
                            ));
                        }
                    }
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
}
