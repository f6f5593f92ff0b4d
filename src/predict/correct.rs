//! Predicting one pixel from its voters, then correcting the prediction by tracing
//! (ALGORITHM.md §4 and §6).
//!
//! Voting: each valid neighbour (inside the frame, not background) votes for the lights it
//! believes blocked at the current pixel — [`Vote::NoWarp`]: one vote for each light it found
//! blocked itself; [`Vote::Warp`]: one vote per blocker, for the cell the blocker lands in when
//! re-aimed from the current point (the paper counts warped blockers per cell). With
//! K_j = voters with light j above their horizon [ours] and votes_j ≥ K_j read as "all agree":
//! - uncertainty rule: K_j < min_voters → trace; every such voter voted → blocked; none voted →
//!   visible; otherwise uncertain → trace, and flood [paper idea, ours exact rule];
//! - boundary rule: any vote → blocked, else visible; trace lights whose prediction differs
//!   from an adjacent light's (Agrawala et al. 2000), and lights no voter has above its horizon.
//!
//! Flooding: after each trace, if the light was uncertain or its traced value differs from its
//! prediction, its untraced above-horizon neighbour lights are traced too, until no trace
//! disagrees ([`FloodTo::All`]); or [ours] only those neighbours predicted opposite to the
//! traced value ([`FloodTo::Contrary`]). The traced set does not depend on the queue's order:
//! which neighbours a trace floods to depends only on the prediction and the traced answer.
//!
//! Everything per light is a bitset word operation; the only per-light loops are over
//! lights that are traced or whose cells received warped blockers.

use super::bits;
use crate::accel::PACKET;
use crate::frame::{FrameContext, TileWork};

/// How neighbours vote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vote {
    /// Re-aim each neighbour's blockers from the current point; vote for the cell they hit.
    Warp,
    /// A neighbour's blocked light votes for itself.
    NoWarp,
}

/// Which lights are traced beyond the prediction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flood {
    /// Trace lights the voters disagree on, and flood from them.
    Uncertainty,
    /// Trace lights at the visible/blocked boundary of the prediction, flood on mistakes.
    Boundary,
}

/// Which neighbours a flooding trace queues (`--flood-to`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FloodTo {
    /// Every untraced above-horizon neighbour light: a ring around each uncertain or
    /// mispredicted light [ALGORITHM.md §6].
    All,
    /// [ours, the default] [`Contrary`](Self::Contrary) at the pixels of the grid's finest
    /// level (spacing 1: three pixels in four), [`All`](Self::All) at the coarser levels. A
    /// wrong pair at a coarse pixel is a wrong vote for every finer pixel it predicts; at the
    /// finest level it reaches at most the last pass's pixels, and those vote for nobody. On
    /// the paper's scenes it traces about a fifth fewer rays than `all` for 0–3.5 % more wrong
    /// pairs (BENCHMARKS.md, "Where the default method's rays go"). Orders without levels
    /// (the scanline) flood to all.
    #[default]
    ContraryFinest,
    /// [ours] Only the untraced above-horizon neighbours whose prediction is the opposite of
    /// the traced answer: the border between the two lights is where the prediction and the
    /// truth disagree. A neighbour predicted like the traced answer is taken as predicted.
    /// On the paper's scenes it traces about a third fewer rays for 1.1–1.9× the wrong pairs
    /// (BENCHMARKS.md, "Flooding only to contrary neighbours").
    Contrary,
}

impl FloodTo {
    pub const ALL: [FloodTo; 3] = [FloodTo::All, FloodTo::ContraryFinest, FloodTo::Contrary];

    /// The name on the command line and in animation specs.
    pub fn name(self) -> &'static str {
        match self {
            FloodTo::All => "all",
            FloodTo::ContraryFinest => "contrary-finest",
            FloodTo::Contrary => "contrary",
        }
    }
}

impl std::fmt::Display for FloodTo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FloodTo {
    type Err = String;
    fn from_str(s: &str) -> Result<FloodTo, String> {
        FloodTo::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                format!("unknown flood rule {s:?}; expected all, contrary-finest or contrary")
            })
    }
}

/// Reused per-pixel scratch: bitsets, the flood queue, warped-blocker bookkeeping.
#[derive(Default)]
pub struct Scratch {
    words: usize,
    pub(super) pred_vis: Vec<u64>,
    pub(super) uncertain: Vec<u64>,
    pub(super) queued: Vec<u64>,
    queue: Vec<u32>,
    /// Warped blockers per cell, and the cells that got any (set bits: some vote; every
    /// above-horizon voter's worth of votes).
    votes: Vec<u8>,
    vote_any: Vec<u64>,
    vote_all: Vec<u64>,
    /// Best warped blocker per cell: alignment with the light and distance along it.
    best_dot: Vec<f32>,
    best_dist: Vec<f32>,
    touched: Vec<u32>,
    /// Distance to the traced blocker per light (valid where traced and blocked).
    hit_dist: Vec<f32>,
    /// Bitset rows for the temporal predictor ([`EXT_ROWS`] × words).
    pub(super) ext: Vec<u64>,
}

/// Rows of `Scratch::ext`: the temporal prediction (blocked, sure), before and after pulling
/// it through a spinning object's turn.
pub(super) const EXT_ROWS: usize = 6;

impl Scratch {
    /// Sizes the scratch for `lights` lights.
    pub fn prepare(&mut self, lights: usize) {
        let w = lights.div_ceil(64);
        if self.words == w && self.best_dot.len() == lights {
            return;
        }
        self.words = w;
        self.ext = vec![0; EXT_ROWS * w];
        self.pred_vis = vec![0; w];
        self.uncertain = vec![0; w];
        self.queued = vec![0; w];
        self.queue = Vec::with_capacity(lights);
        self.votes = vec![0; lights];
        self.vote_any = vec![0; w];
        self.vote_all = vec![0; w];
        self.best_dot = vec![f32::NEG_INFINITY; lights];
        self.best_dist = vec![0.0; lights];
        self.touched = Vec::with_capacity(lights);
        self.hit_dist = vec![0.0; lights];
    }
}

/// Which rule and order a prediction uses.
#[derive(Clone, Copy, Debug)]
pub struct Rule {
    pub vote: Vote,
    pub flood: Flood,
    /// Which neighbours a flooding trace queues.
    pub flood_to: FloodTo,
    pub min_voters: u32,
    /// Which blockers a pixel keeps for later warping: only its traced hits ([paper] §3), or
    /// also, for lights predicted blocked, the warped blocker that voted for them ([ours]).
    pub keep_predicted: bool,
}

impl Rule {
    /// The rule at a pixel of the grid's finest level (`finest`) or a coarser one: resolves
    /// [`FloodTo::ContraryFinest`] to the rule [`correct`] applies there.
    pub fn at_level(self, finest: bool) -> Rule {
        let flood_to = match self.flood_to {
            FloodTo::ContraryFinest if finest => FloodTo::Contrary,
            FloodTo::ContraryFinest => FloodTo::All,
            f => f,
        };
        Rule { flood_to, ..self }
    }
}

/// Predicts and corrects region pixel `i` (already begun) from the region pixels `voters`
/// (valid: evaluated, not background; at most four). With no voters every query is traced.
/// `keep_blockers`: record the pixel's blockers for later warping.
// Word loops index several parallel bitsets at once; iterator chains would hide that.
#[allow(clippy::needless_range_loop)]
pub fn solve_pixel(
    ctx: &FrameContext,
    work: &mut TileWork,
    i: usize,
    voters: &[usize],
    rule: Rule,
    keep_blockers: bool,
) {
    let s = work.surf[i];
    if !s.hit {
        return;
    }
    if voters.is_empty() {
        work.trace_all(ctx, i, keep_blockers);
        return;
    }
    debug_assert!(voters.len() <= 4);
    let w = work.words;
    let nv = voters.len();
    let TileWork {
        above,
        vis,
        blockers,
        surf,
        scratch: sc,
        ..
    } = work;

    // 1. Votes. No warp: a voter's blocked lights, read word by word in step 2. Warp: each
    //    voter's blockers, re-aimed from this point, counted per cell they land in [paper].
    if rule.vote == Vote::Warp {
        for &q in voters {
            let pq = surf[q].p;
            for (j, t) in blockers.of(q) {
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
                // [ours] a light predicted blocked keeps the warped blocker best
                // aligned with it, so later pixels can warp it in turn.
                let align = dn.dot(ctx.light_dir[c]);
                if align > sc.best_dot[c] {
                    sc.best_dot[c] = align;
                    sc.best_dist[c] = d.dot(ctx.light_dir[c]).max(0.0);
                }
            }
        }
    }

    // 2. Prediction, word by word: `any` = some vote, `all` = votes_j ≥ K_j.
    let mine = &above[i * w..(i + 1) * w];
    let mut above_words = [0u64; 4];
    if rule.vote == Vote::Warp {
        sc.vote_any.fill(0);
        sc.vote_all.fill(0);
        for &c in &sc.touched {
            let c = c as usize;
            bits::set(&mut sc.vote_any, c);
            let k_j = voters
                .iter()
                .filter(|&&q| bits::get(&above[q * w..(q + 1) * w], c))
                .count();
            if sc.votes[c] as usize >= k_j {
                bits::set(&mut sc.vote_all, c);
            }
        }
    }
    for m in 0..w {
        for (k, &q) in voters.iter().enumerate() {
            above_words[k] = above[q * w + m];
        }
        let (any, all) = match rule.vote {
            Vote::Warp => (sc.vote_any[m], sc.vote_all[m]),
            Vote::NoWarp => {
                let (mut all, mut any) = (!0u64, 0u64);
                for (k, &q) in voters.iter().enumerate() {
                    let v = above_words[k] & !vis[q * w + m];
                    all &= !above_words[k] | v;
                    any |= v;
                }
                (any, all & any)
            }
        };
        let enough = bits::at_least(&above_words[..nv], rule.min_voters);
        let my = mine[m];
        let (blocked, unsure) = match rule.flood {
            Flood::Uncertainty => (my & enough & all, my & (!enough | (any & !all))),
            Flood::Boundary => (my & any, my & !enough),
        };
        sc.pred_vis[m] = my & !blocked;
        sc.uncertain[m] = unsure;
        sc.queued[m] = unsure;
    }
    if rule.flood == Flood::Boundary {
        // Lights whose prediction differs from an adjacent above-horizon light's.
        for m in 0..w {
            let mut my = mine[m];
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

    correct(ctx, work, i, rule, keep_blockers);
}

/// Steps 3 and 4 of [`solve_pixel`], shared with the temporal predictor: traces the queued
/// lights of region pixel `i` starting from the prediction in the scratch (`pred_vis`,
/// `uncertain`, `queued`), flooding (`rule.flood`, `rule.flood_to`) where a trace was uncertain
/// or disagreed, then records the pixel's blockers when `keep_blockers` (and, with
/// `rule.keep_predicted`, the warped blockers of lights predicted blocked).
#[allow(clippy::needless_range_loop)]
pub(super) fn correct(
    ctx: &FrameContext,
    work: &mut TileWork,
    i: usize,
    rule: Rule,
    keep_blockers: bool,
) {
    let s = work.surf[i];
    let w = work.words;
    let TileWork {
        above,
        vis,
        traced,
        rays,
        split,
        blockers,
        scratch: sc,
        ..
    } = work;
    let mine = &above[i * w..(i + 1) * w];
    // 3. Correction: trace the queue, flooding where a trace was uncertain or disagreed.
    sc.queue.clear();
    bits::for_each(&sc.queued, |j| sc.queue.push(j as u32));
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
        let blocked = if keep_blockers {
            0
        } else {
            ctx.trace_packet(&s, &sc.queue[wave.clone()])
        };
        for (k, q) in wave.clone().enumerate() {
            let j = sc.queue[q] as usize;
            bits::set(tr, j);
            let visible = if keep_blockers {
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
            let flood = match rule.flood {
                Flood::Uncertainty => bits::get(&sc.uncertain, j) || visible != predicted,
                Flood::Boundary => visible != predicted,
            };
            if flood {
                // Untraced above-horizon neighbours (with `Contrary`, those predicted
                // opposite to this answer), appended in ascending order (as the adjacency
                // lists them), a word at a time.
                let nb = ctx.lights.neighbor_bits(j);
                for m in 0..w {
                    let to = match rule.flood_to {
                        // `ContraryFinest` is resolved per pixel by the order
                        // (`Rule::at_level`) before it gets here.
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
    split[i] = crate::frame::RaySplit {
        every: 0,
        flooded: n - predicted_queue as u32,
        fixes,
    };

    // 4. Blockers of this pixel: traced hits, and (rule.keep_predicted) for predicted-blocked
    //    lights the warped blocker that voted for them.
    if keep_blockers {
        blockers.begin(i);
        for m in 0..w {
            let mut blocked = mine[m] & !out[m];
            while blocked != 0 {
                let j = m * 64 + blocked.trailing_zeros() as usize;
                blocked &= blocked - 1;
                if bits::get(tr, j) {
                    blockers.push(i, j, sc.hit_dist[j]);
                } else if rule.keep_predicted && sc.best_dot[j] > f32::NEG_INFINITY {
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
