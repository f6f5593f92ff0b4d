//! Coarse-to-fine grid order (ALGORITHM.md §5) [paper].
//!
//! Every light is traced at the pixels of a coarse grid with spacing h0, anchored to the frame
//! (pixels with x ≡ y ≡ 0 mod h0). Then for h = h0, h0/2, …, 2 with s = h/2: pass A predicts
//! the square centres (x ≡ y ≡ s mod h) from their four diagonal neighbours at (±s, ±s);
//! pass B predicts the edge midpoints from their four axis neighbours at distance s. A pass
//! reads only earlier passes, so the pixels of a pass are independent of each other.
//!
//! Tiles [ours]: the coarse grid and the h0 level are evaluated once per frame into a
//! [`Lattice`] shared by all tiles (phase by phase, each pixel by the tile containing it). Then
//! each tile evaluates the finer passes. Within a level a pixel reads at most s away along an
//! axis, and a pass-B pixel reads pass-A centres that read s further: 2s per level, so the
//! final phase reaches h0/2 + … + 2 = h0 − 2 pixels beyond the tile. Inside that region only
//! the pixels the tile transitively depends on are evaluated — marked walking the passes
//! backwards — so a tile produces exactly the whole-frame render's pixels and counts.

use super::correct::{Flood, Rule, Vote, solve_pixel};
use super::temporal::solve_temporal;
use super::{Lattice, LatticePatch, Params, Predictor};
use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// A grid method: the coarse-to-fine order with a voting and a correction rule.
pub struct Grid {
    name: &'static str,
    rule: Rule,
    h0: u32,
}

impl Grid {
    pub fn new(name: &'static str, vote: Vote, flood: Flood, params: Params) -> Grid {
        // Boundary flooding predicts in binary, any vote → blocked [paper]: one voter with the
        // light above its horizon is enough. The voter threshold is the uncertainty rule's.
        let min_voters = match flood {
            Flood::Uncertainty => params.min_voters,
            Flood::Boundary => 1,
        };
        Grid {
            name,
            rule: Rule {
                vote,
                flood,
                flood_to: params.flood_to,
                min_voters,
                // [ours]: a grid voter is s pixels away and every light it predicted
                // blocked should still vote (docs/methods.md).
                keep_predicted: true,
            },
            h0: params.h0,
        }
    }

    /// Number of passes: the coarse grid, then A and B for each level.
    fn passes(&self) -> usize {
        1 + 2 * self.h0.trailing_zeros() as usize
    }
}

/// The pass that evaluates frame pixel (x, y): 0 for the coarse grid, then 2l+1 (A) and
/// 2l+2 (B) at level l (h = h0 >> l).
#[inline]
pub fn pass_of(x: u32, y: u32, h0: u32) -> usize {
    if x % h0 == 0 && y % h0 == 0 {
        return 0;
    }
    let (mut h, mut p) = (h0, 1);
    loop {
        let s = h / 2;
        if x % s == 0 && y % s == 0 {
            return if x % h == s && y % h == s { p } else { p + 1 };
        }
        h = s;
        p += 2;
    }
}

/// The (up to four) frame pixels a pixel of pass `p` reads, inside the frame.
#[inline]
fn voters_of(x: u32, y: u32, p: usize, h0: u32, frame: Rect, out: &mut [(u32, u32); 4]) -> usize {
    let s = (h0 >> ((p - 1) / 2)) / 2;
    let (x, y, s) = (x as i64, y as i64, s as i64);
    let cand = if p % 2 == 1 {
        [
            (x - s, y - s),
            (x + s, y - s),
            (x - s, y + s),
            (x + s, y + s),
        ]
    } else {
        [(x, y - s), (x - s, y), (x + s, y), (x, y + s)]
    };
    let mut n = 0;
    for (cx, cy) in cand {
        if cx >= frame.x0 as i64
            && cy >= frame.y0 as i64
            && cx < frame.x1 as i64
            && cy < frame.y1 as i64
        {
            out[n] = (cx as u32, cy as u32);
            n += 1;
        }
    }
    n
}

impl Grid {
    /// The rule at the pixels of pass `p`: the finest level's two passes read voters one
    /// pixel away and are read by nothing coarser.
    fn rule_at(&self, p: usize) -> Rule {
        self.rule.at_level(p + 2 >= self.passes())
    }

    /// The voters' distance s of pass `p` (≥ 1).
    fn spacing(&self, p: usize) -> u32 {
        (self.h0 >> ((p - 1) / 2)) / 2
    }

    /// How far the final phase's dependencies reach: 2s per unshared level.
    fn final_reach(&self) -> u32 {
        (SHARED_PASSES..self.passes())
            .step_by(2)
            .map(|p| 2 * self.spacing(p))
            .sum()
    }

    fn shared(&self) -> usize {
        SHARED_PASSES.min(self.passes())
    }

    /// Copies the lattice pixels inside `region` into `work`; those inside `tile` count as
    /// the tile's own (their rays are the tile's).
    fn copy_lattice(&self, lattice: &Lattice, region: Rect, tile: Rect, work: &mut TileWork) {
        let step = self.lattice_step();
        let (x0, y0) = (
            region.x0.div_ceil(step) * step,
            region.y0.div_ceil(step) * step,
        );
        for y in (y0..region.y1).step_by(step as usize) {
            for x in (x0..region.x1).step_by(step as usize) {
                let i = region.index(x, y);
                if lattice.copy_into(x, y, work, i) && tile.contains(x, y) {
                    work.needed[i] = true;
                }
            }
        }
    }

    /// The valid voters of pixel (x, y) in pass `p`, as region indices.
    fn voters(
        &self,
        work: &TileWork,
        frame: Rect,
        x: u32,
        y: u32,
        p: usize,
        out: &mut [usize; 4],
    ) -> usize {
        let mut nb = [(0u32, 0u32); 4];
        let n = voters_of(x, y, p, self.h0, frame, &mut nb);
        let mut nv = 0;
        for &(vx, vy) in &nb[..n] {
            let q = work.region.index(vx, vy);
            if work.surf[q].hit {
                out[nv] = q;
                nv += 1;
            }
        }
        nv
    }
}

/// Passes evaluated once per frame into the lattice: the coarse grid and the h0 level's
/// A and B passes (lattice spacing h0/2). They hold 1/64 of the pixels at h0 = 16 but, as the
/// coarse grid traces every light, a large share of the rays; sharing them keeps the halos
/// cheap (BENCHMARKS.md has the halo figures).
const SHARED_PASSES: usize = 3;

impl Predictor for Grid {
    fn name(&self) -> &'static str {
        self.name
    }

    fn shared_phases(&self) -> usize {
        self.shared()
    }

    fn shared_reach(&self) -> u32 {
        // The final phase's reach, plus the shared passes' own: a pass-B pixel reads pass-A
        // centres h0/2 away, which read the coarse grid h0/2 further.
        self.final_reach() + if self.shared() > 1 { self.h0 } else { 0 }
    }

    fn lattice_step(&self) -> u32 {
        let levels = (self.shared() - 1) / 2;
        self.h0 >> levels
    }

    fn region(&self, ctx: &FrameContext, tile: Rect, phase: usize) -> Rect {
        let reach = if phase < self.shared() {
            if phase == 0 { 0 } else { self.spacing(phase) }
        } else {
            self.final_reach()
        };
        let frame = Rect::frame(ctx.camera.width, ctx.camera.height);
        tile.grow(reach).intersect(&frame)
    }

    fn solve(
        &self,
        ctx: &FrameContext,
        tile: Rect,
        work: &mut TileWork,
        phase: usize,
        lattice: &Lattice,
        patch: &mut LatticePatch,
    ) {
        let region = work.region;
        let frame = Rect::frame(ctx.camera.width, ctx.camera.height);
        let warp = self.rule.vote == Vote::Warp;
        let mut voters = [0usize; 4];
        let shared = self.shared();
        self.copy_lattice(lattice, region, tile, work);

        if phase < shared {
            // A shared phase: this pass's pixels inside the tile, read by later passes, so
            // warping methods keep their blockers.
            let step = self.lattice_step();
            let (x0, y0) = (tile.x0.div_ceil(step) * step, tile.y0.div_ceil(step) * step);
            for y in (y0..tile.y1).step_by(step as usize) {
                for x in (x0..tile.x1).step_by(step as usize) {
                    if pass_of(x, y, self.h0) != phase {
                        continue;
                    }
                    let i = work.begin_pixel(ctx, x, y);
                    let nv = if phase == 0 {
                        0
                    } else {
                        self.voters(work, frame, x, y, phase, &mut voters)
                    };
                    let rule = self.rule_at(phase);
                    if solve_temporal(ctx, work, i, &voters[..nv], rule, warp) {
                        // predicted from the previous frame
                    } else if phase == 0 {
                        work.trace_all(ctx, i, warp);
                    } else {
                        solve_pixel(ctx, work, i, &voters[..nv], rule, warp);
                    }
                    patch.record(lattice, x, y, work, i);
                }
            }
            return;
        }

        // The final phase: the unshared passes, only at the pixels the tile depends on.
        let passes = self.passes();
        let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); passes];
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let p = pass_of(x, y, self.h0);
                if p >= shared {
                    buckets[p].push(region.index(x, y) as u32);
                }
            }
        }
        let rw = region.width();
        let coords = |i: u32| (region.x0 + i % rw, region.y0 + i / rw);
        let mut need = vec![false; region.area()];
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                need[region.index(x, y)] = true;
            }
        }
        let mut nb = [(0u32, 0u32); 4];
        for p in (shared..passes).rev() {
            for &i in &buckets[p] {
                if !need[i as usize] {
                    continue;
                }
                let (x, y) = coords(i);
                let n = voters_of(x, y, p, self.h0, frame, &mut nb);
                for &(vx, vy) in &nb[..n] {
                    need[region.index(vx, vy)] = true;
                }
            }
        }
        // Pixels of the last pass are never read: they keep no blockers.
        for (p, bucket) in buckets.iter().enumerate().skip(shared) {
            let keep = warp && p + 1 < passes;
            for &i in bucket {
                if !need[i as usize] {
                    continue;
                }
                let (x, y) = coords(i);
                let i = work.begin_pixel(ctx, x, y);
                let nv = self.voters(work, frame, x, y, p, &mut voters);
                let rule = self.rule_at(p);
                if solve_temporal(ctx, work, i, &voters[..nv], rule, keep) {
                    continue;
                }
                solve_pixel(ctx, work, i, &voters[..nv], rule, keep);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pixel_has_one_pass_and_reads_only_earlier_passes() {
        let h0 = 16;
        let frame = Rect::frame(70, 50);
        let mut nb = [(0, 0); 4];
        let mut per_pass = [0usize; 9];
        for y in 0..50 {
            for x in 0..70 {
                let p = pass_of(x, y, h0);
                per_pass[p] += 1;
                if p > 0 {
                    let n = voters_of(x, y, p, h0, frame, &mut nb);
                    assert!(n >= 1, "({x}, {y}) pass {p} has no voters");
                    for &(vx, vy) in &nb[..n] {
                        assert!(pass_of(vx, vy, h0) < p, "({x},{y}) p{p} reads ({vx},{vy})");
                        assert!(x.abs_diff(vx) < h0 && y.abs_diff(vy) < h0);
                    }
                }
            }
        }
        // 5 × 4 coarse pixels in a 70 × 50 frame.
        assert_eq!(per_pass[0], 20);
        // The finest B pass holds about half the pixels.
        assert!(per_pass[8] > 70 * 50 * 2 / 5);
    }
}
