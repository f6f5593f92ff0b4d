//! Correcting a prediction by tracing (ALGORITHM.md §6): the queued lights are traced, and a
//! trace the flood rule says floods queues its untraced above-horizon neighbour lights (all,
//! or with [`FloodTo::Contrary`] only those predicted opposite to the traced answer), until no
//! trace disagrees. Which neighbours a trace floods to depends only on the prediction and the
//! traced answer, so the traced set does not depend on the queue's order.

use super::{Flood, FloodTo, Scratch};
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
    let mine = &above[i * w..(i + 1) * w];
    // 3. Correction: trace the queue, flooding where a trace was uncertain or disagreed.
    let tr = &mut traced[i * w..(i + 1) * w];
    let out = &mut vis[i * w..(i + 1) * w];
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
                        // `ContraryFinest` is resolved per pass by the driver
                        // (`FloodTo::at_level`) before it gets here.
                        FloodTo::All | FloodTo::ContraryFinest => !0,
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
    for &c in &sc.touched {
        sc.best_dot[c as usize] = f32::NEG_INFINITY;
        sc.votes[c as usize] = 0;
    }
    sc.touched.clear();
}
