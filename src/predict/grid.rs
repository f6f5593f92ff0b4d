//! Coarse-to-fine grid order (ALGORITHM.md §5) [paper].
//!
//! Every light is traced at the pixels of a coarse grid with spacing h0, anchored to the frame
//! (pixels with x ≡ y ≡ 0 mod h0). Then for h = h0, h0/2, …, 2 with s = h/2: pass A predicts
//! the square centres (x ≡ y ≡ s mod h) from their four diagonal neighbours at (±s, ±s);
//! pass B predicts the edge midpoints from their four axis neighbours at distance s. A pass
//! reads only earlier passes, so the pixels of a pass are independent of each other.
//!
//! Tiles [ours]: the coarse grid and the h0 level are evaluated once per frame into a lattice
//! shared by all tiles (phase by phase, each pixel by the tile containing it). Then each tile
//! evaluates the finer passes. Within a level a pixel reads at most s away along an axis, and
//! a pass-B pixel reads pass-A centres that read s further: 2s per level, so the final phase
//! reaches h0/2 + … + 2 = h0 − 2 pixels beyond the tile. Inside that region the driver
//! evaluates only the pixels the tile transitively depends on, so a tile produces exactly the
//! whole-frame render's pixels and counts.

use super::order::Order;
use super::params::Params;
use crate::key::Key;
use crate::tile::Rect;

/// The coarse-to-fine grid with coarse spacing h0.
pub struct Grid {
    h0: u32,
}

/// Passes evaluated once per frame into the lattice: the coarse grid and the h0 level's
/// A and B passes (lattice spacing h0/2). They hold 1/64 of the pixels at h0 = 16 but, as the
/// coarse grid traces every light, a large share of the rays; sharing them keeps the halos
/// cheap (BENCHMARKS.md has the halo figures).
const SHARED_PASSES: usize = 3;

impl Grid {
    pub fn new(params: &Params) -> Grid {
        Grid { h0: params.h0 }
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
}

/// The pass that evaluates frame pixel (x, y): 0 for the coarse grid, then 2l+1 (A) and
/// 2l+2 (B) at level l (h = h0 >> l, s = h/2). The level is that of the largest power of two
/// s < h0 dividing both coordinates; the square centres (A) are odd multiples of s in both.
#[inline]
pub fn pass_of(x: u32, y: u32, h0: u32) -> usize {
    let top = h0.trailing_zeros();
    // trailing_zeros(0) = 32: the origin row and column divide by everything.
    let (tx, ty) = (x.trailing_zeros(), y.trailing_zeros());
    let t = tx.min(ty);
    if t >= top {
        return 0;
    }
    let level = (top - 1 - t) as usize;
    1 + 2 * level + usize::from(tx != ty)
}

/// The (up to four) frame pixels a pixel of pass `p` ≥ 1 reads, inside the frame: the
/// diagonal neighbours at (±s, ±s) in pass A, the axis neighbours at distance s in pass B.
#[inline]
pub fn voters_of(
    x: u32,
    y: u32,
    p: usize,
    h0: u32,
    frame: Rect,
    out: &mut [(u32, u32); 4],
) -> usize {
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

impl Order for Grid {
    fn name(&self) -> &'static str {
        "grid"
    }

    /// The coarse grid, then A and B for each level.
    fn passes(&self) -> usize {
        1 + 2 * self.h0.trailing_zeros() as usize
    }

    fn pass_of(&self, x: u32, y: u32) -> usize {
        pass_of(x, y, self.h0)
    }

    fn voters(&self, x: u32, y: u32, pass: usize, frame: Rect, out: &mut [(u32, u32); 4]) -> usize {
        if pass == 0 {
            return 0; // the coarse grid traces every light
        }
        voters_of(x, y, pass, self.h0, frame, out)
    }

    /// Pixels of the last pass are never read.
    fn read_later(&self, pass: usize) -> bool {
        pass + 1 < self.passes()
    }

    /// The finest level's two passes read voters one pixel away and are read by nothing
    /// coarser.
    fn finest(&self, pass: usize) -> bool {
        pass + 2 >= self.passes()
    }

    fn spacing(&self, pass: usize) -> Option<u32> {
        (pass > 0).then(|| Grid::spacing(self, pass))
    }

    /// [ours]: a grid voter is s pixels away and every light it predicted blocked should still
    /// vote (docs/methods.md).
    fn keeps_predicted(&self) -> bool {
        true
    }

    fn shared_passes(&self) -> usize {
        SHARED_PASSES.min(self.passes())
    }

    fn lattice_step(&self) -> u32 {
        let levels = (self.shared_passes() - 1) / 2;
        self.h0 >> levels
    }

    fn shared_reach(&self) -> u32 {
        // The final phase's reach, plus the shared passes' own: a pass-B pixel reads pass-A
        // centres h0/2 away, which read the coarse grid h0/2 further.
        self.final_reach() + if self.shared_passes() > 1 { self.h0 } else { 0 }
    }

    fn region(&self, frame: Rect, tile: Rect, phase: usize) -> Rect {
        let reach = if phase < self.shared_passes() {
            if phase == 0 { 0 } else { self.spacing(phase) }
        } else {
            self.final_reach()
        };
        tile.grow(reach).intersect(&frame)
    }

    fn reads(&self) -> &'static [Key] {
        &[Key::H0, Key::PixelMajority]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition: walk the levels down from h0 until s divides both coordinates.
    fn pass_by_levels(x: u32, y: u32, h0: u32) -> usize {
        if x.is_multiple_of(h0) && y.is_multiple_of(h0) {
            return 0;
        }
        let (mut h, mut p) = (h0, 1);
        loop {
            let s = h / 2;
            if x.is_multiple_of(s) && y.is_multiple_of(s) {
                return if x % h == s && y % h == s { p } else { p + 1 };
            }
            h = s;
            p += 2;
        }
    }

    #[test]
    fn pass_of_follows_the_levels() {
        for h0 in [2, 4, 8, 16, 32, 64, 128, 256] {
            for y in 0..300 {
                for x in 0..300 {
                    assert_eq!(
                        pass_of(x, y, h0),
                        pass_by_levels(x, y, h0),
                        "({x}, {y}) h0 {h0}"
                    );
                }
            }
        }
    }

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
