//! Pixels shared by every tile of a frame [ours, §8].
//!
//! The coarse levels of the grid order are few pixels that trace many rays (the coarse grid
//! traces every light). A tile whose halo re-evaluated them would repeat the dearest work of
//! its neighbours. Instead they are evaluated once per frame, level by level, each pixel by the
//! tile that contains it, and kept here; tiles then copy what they read. A lattice pixel is a
//! pure function of the frame, so the result is the same whatever evaluates it.

use crate::bits;
use crate::blockers::Blockers;
use crate::buffers::{RaySplit, TileBuffers};
use crate::context::Surface;

/// Evaluated pixels on a frame-anchored lattice (every `step`-th pixel in x and y).
#[derive(Default)]
pub struct Lattice {
    step: u32,
    cols: u32,
    rows: u32,
    words: usize,
    have: Vec<bool>,
    surf: Vec<Surface>,
    /// above, vis and traced bitsets, `3 · words` per pixel.
    bits: Vec<u64>,
    rays: Vec<u32>,
    split: Vec<RaySplit>,
    /// Predicted from the previous frame (`--temporal`), and how many of its pairs were
    /// dropped there (a tile counts them as its own pixels').
    temporal: Vec<bool>,
    stale: Vec<u32>,
    blockers: Blockers,
}

/// The pixels one tile evaluated in one shared phase, to be inserted into the lattice.
#[derive(Default)]
pub struct LatticePatch {
    index: Vec<u32>,
    surf: Vec<Surface>,
    bits: Vec<u64>,
    rays: Vec<u32>,
    split: Vec<RaySplit>,
    temporal: Vec<bool>,
    stale: Vec<u32>,
    blk_len: Vec<u32>,
    blk_light: Vec<u16>,
    blk_dist: Vec<f32>,
}

impl Lattice {
    /// An empty lattice over a `width`×`height` frame; `step == 0` holds nothing.
    pub fn new(width: u32, height: u32, step: u32, words: usize) -> Lattice {
        if step == 0 {
            return Lattice::default();
        }
        let cols = width.div_ceil(step);
        let rows = height.div_ceil(step);
        let n = (cols * rows) as usize;
        let mut blockers = Blockers::default();
        blockers.reset(n);
        Lattice {
            step,
            cols,
            rows,
            words,
            have: vec![false; n],
            surf: vec![Surface::default(); n],
            bits: vec![0; n * 3 * words],
            rays: vec![0; n],
            split: vec![RaySplit::default(); n],
            temporal: vec![false; n],
            stale: vec![0; n],
            blockers,
        }
    }

    /// The spacing of the lattice (0: it holds nothing).
    pub fn step(&self) -> u32 {
        self.step
    }

    /// The lattice index of frame pixel (x, y), if it lies on the lattice.
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        if self.step == 0 || !x.is_multiple_of(self.step) || !y.is_multiple_of(self.step) {
            return None;
        }
        let (c, r) = (x / self.step, y / self.step);
        (c < self.cols && r < self.rows).then_some((r * self.cols + c) as usize)
    }

    /// Rays traced at the evaluated lattice pixels inside `rect`: where the coarse levels were
    /// unsure, the finer ones trace most, so this ranks tiles by the work they will do.
    pub fn rays_in(&self, rect: crate::tile::Rect) -> u64 {
        if self.step == 0 {
            return 0;
        }
        let mut sum = 0u64;
        for r in rect.y0.div_ceil(self.step)..rect.y1.div_ceil(self.step).min(self.rows) {
            for c in rect.x0.div_ceil(self.step)..rect.x1.div_ceil(self.step).min(self.cols) {
                sum += u64::from(self.rays[(r * self.cols + c) as usize]);
            }
        }
        sum
    }

    /// Copies evaluated pixel (x, y) into region pixel `i` of `bufs`.
    pub fn copy_into(&self, x: u32, y: u32, bufs: &mut TileBuffers, i: usize) -> bool {
        let Some(k) = self.index(x, y).filter(|&k| self.have[k]) else {
            return false;
        };
        let w = self.words;
        bufs.valid[i] = true;
        bufs.surf[i] = self.surf[k];
        bufs.voter[i] = self.surf[k].hit;
        // This pixel's above, vis and traced rows, one after the other.
        let src = bits::rows(&self.bits, 3 * w).row(k);
        let pixel = bits::rows(src, w);
        bits::rows_mut(&mut bufs.above, w)
            .row_mut(i)
            .copy_from_slice(pixel.row(0));
        bits::rows_mut(&mut bufs.vis, w)
            .row_mut(i)
            .copy_from_slice(pixel.row(1));
        bits::rows_mut(&mut bufs.traced, w)
            .row_mut(i)
            .copy_from_slice(pixel.row(2));
        bufs.rays[i] = self.rays[k];
        bufs.split[i] = self.split[k];
        bufs.temporal[i] = self.temporal[k];
        bufs.stale[i] = self.stale[k];
        bufs.blockers.begin(i);
        for (j, t) in self.blockers.of(k) {
            bufs.blockers.push(i, j, t);
        }
        true
    }

    /// Adds a tile's newly evaluated pixels.
    pub fn insert(&mut self, patch: &LatticePatch) {
        let w = self.words;
        let mut b = 0usize;
        for (n, &k) in patch.index.iter().enumerate() {
            let k = k as usize;
            self.have[k] = true;
            self.surf[k] = patch.surf[n];
            bits::rows_mut(&mut self.bits, 3 * w)
                .row_mut(k)
                .copy_from_slice(bits::rows(&patch.bits, 3 * w).row(n));
            self.rays[k] = patch.rays[n];
            self.split[k] = patch.split[n];
            self.temporal[k] = patch.temporal[n];
            self.stale[k] = patch.stale[n];
            self.blockers.begin(k);
            for _ in 0..patch.blk_len[n] {
                self.blockers
                    .push(k, patch.blk_light[b] as usize, patch.blk_dist[b]);
                b += 1;
            }
        }
    }
}

impl LatticePatch {
    /// Records region pixel `i` of `bufs`, which is lattice pixel (x, y) of `lattice`.
    pub fn record(&mut self, lattice: &Lattice, x: u32, y: u32, bufs: &TileBuffers, i: usize) {
        let k = lattice
            .index(x, y)
            .expect("shared passes evaluate lattice pixels only");
        let w = bufs.words;
        self.index.push(k as u32);
        self.surf.push(bufs.surf[i]);
        for v in [&bufs.above, &bufs.vis, &bufs.traced] {
            self.bits.extend_from_slice(bits::rows(v, w).row(i));
        }
        self.rays.push(bufs.rays[i]);
        self.split.push(bufs.split[i]);
        self.temporal.push(bufs.temporal[i]);
        self.stale.push(bufs.stale[i]);
        let mut n = 0;
        for (j, t) in bufs.blockers.of(i) {
            self.blk_light.push(j as u16);
            self.blk_dist.push(t);
            n += 1;
        }
        self.blk_len.push(n);
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::tile::Rect;

    /// Empty buffers over `region`, `words` words per bitset (what `prepare` sizes).
    fn buffers(region: Rect, words: usize) -> TileBuffers {
        let n = region.area();
        let mut b = TileBuffers {
            tile: region,
            region,
            words,
            surf: vec![Surface::default(); n],
            needed: vec![false; n],
            valid: vec![false; n],
            voter: vec![false; n],
            above: vec![0; n * words],
            vis: vec![0; n * words],
            traced: vec![0; n * words],
            rays: vec![0; n],
            split: vec![RaySplit::default(); n],
            temporal: vec![false; n],
            stale: vec![0; n],
            ..TileBuffers::default()
        };
        b.blockers.reset(n);
        b
    }

    /// Everything a lattice pixel carries.
    #[derive(Debug, PartialEq)]
    struct Pixel {
        surf: Surface,
        bits: [Vec<u64>; 3],
        rays: u32,
        split: RaySplit,
        temporal: bool,
        stale: u32,
        blockers: Vec<(usize, f32)>,
    }

    fn read(b: &TileBuffers, i: usize) -> Pixel {
        let row = |v: &[u64]| bits::rows(v, b.words).row(i).to_vec();
        Pixel {
            surf: b.surf[i],
            bits: [row(&b.above), row(&b.vis), row(&b.traced)],
            rays: b.rays[i],
            split: b.split[i],
            temporal: b.temporal[i],
            stale: b.stale[i],
            blockers: b.blockers.of(i).collect(),
        }
    }

    fn write(b: &mut TileBuffers, i: usize, p: &Pixel) {
        let w = b.words;
        b.surf[i] = p.surf;
        for (v, row) in [&mut b.above, &mut b.vis, &mut b.traced]
            .into_iter()
            .zip(&p.bits)
        {
            bits::rows_mut(v, w).row_mut(i).copy_from_slice(row);
        }
        b.rays[i] = p.rays;
        b.split[i] = p.split;
        b.temporal[i] = p.temporal;
        b.stale[i] = p.stale;
        b.blockers.begin(i);
        for &(j, t) in &p.blockers {
            b.blockers.push(i, j, t);
        }
    }

    /// A pixel unlike any other `seed` gives, light bits in both words.
    fn pixel(seed: u32, blockers: &[(usize, f32)]) -> Pixel {
        let s = seed as f32;
        let k = u64::from(seed);
        Pixel {
            surf: Surface {
                p: Vec3::new(s, s + 0.5, -s),
                n: Vec3::Y,
                ng: Vec3::Z,
                origin: Vec3::new(s, s + 0.5, 1.0 - s),
                albedo: Vec3::splat(0.1 * s),
                dir: Vec3::new(0.0, -s, 1.0).normalize(),
                hit: true,
                catcher: seed % 2 == 1,
                ..Surface::default()
            },
            bits: [
                vec![0xf0f0 ^ k, 0x3 << k],
                vec![0x0ff0 ^ k, 0x1 << k],
                vec![0xff00 ^ k, 0x2 << k],
            ],
            rays: 10 + seed,
            split: RaySplit {
                every: seed,
                flooded: seed + 1,
                fixes: seed + 2,
            },
            temporal: seed % 2 == 1,
            stale: 20 + seed,
            blockers: blockers.to_vec(),
        }
    }

    /// Three lattice pixels recorded from one tile's buffers (between them a pixel off the
    /// lattice, whose blockers come first in the buffers), inserted, and copied into another
    /// tile's buffers at other region indices: every field comes back, each pixel its own
    /// blockers.
    #[test]
    fn a_recorded_pixel_comes_back_whole() {
        let (width, height, step, words) = (41, 30, 8, 2);
        let mut lattice = Lattice::new(width, height, step, words);
        let src_region = Rect::new(8, 8, 20, 20);
        let mut src = buffers(src_region, words);
        let off = src_region.index(9, 8);
        write(&mut src, off, &pixel(9, &[(1, 9.0)]));
        // (x, y, pixel): blockers in both words, none, and one.
        let pixels = [
            (8, 8, pixel(1, &[(3, 1.5), (70, 2.25)])),
            (16, 8, pixel(2, &[])),
            (16, 16, pixel(3, &[(65, 0.5)])),
        ];
        let mut patch = LatticePatch::default();
        for (x, y, p) in &pixels {
            let i = src_region.index(*x, *y);
            write(&mut src, i, p);
            patch.record(&lattice, *x, *y, &src, i);
        }
        lattice.insert(&patch);

        let dst_region = Rect::new(0, 0, 24, 24);
        let mut dst = buffers(dst_region, words);
        write(&mut dst, dst_region.index(1, 1), &pixel(7, &[(5, 5.0)]));
        let mut failures = Vec::new();
        for (x, y, want) in &pixels {
            let i = dst_region.index(*x, *y);
            if !lattice.copy_into(*x, *y, &mut dst, i) {
                failures.push(format!("({x}, {y}) not copied"));
                continue;
            }
            let got = read(&dst, i);
            if got != *want {
                failures.push(format!("({x}, {y}): got {got:?}\n  want {want:?}"));
            }
        }
        // Lattice pixels never inserted, and pixels off the lattice, are not copied.
        for (x, y) in [(0, 0), (8, 16), (9, 8), (12, 12)] {
            if lattice.copy_into(x, y, &mut dst, dst_region.index(x, y)) {
                failures.push(format!("({x}, {y}) copied but never inserted"));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// Frame pixels on the lattice (multiples of the step, inside the frame) have an index,
    /// row-major over its columns; no other pixel does.
    #[test]
    fn only_lattice_pixels_have_an_index() {
        // 41 × 30 at step 8: 6 columns (0..=40), 4 rows (0..=24).
        let lattice = Lattice::new(41, 30, 8, 1);
        let cases = [
            ((0, 0), Some(0)),
            ((8, 0), Some(1)),
            ((40, 0), Some(5)),
            ((0, 8), Some(6)),
            ((16, 24), Some(20)),
            ((40, 24), Some(23)),
            ((48, 0), None),
            ((0, 32), None),
            ((9, 8), None),
            ((8, 9), None),
            ((4, 4), None),
            ((1, 0), None),
        ];
        let mut failures: Vec<String> = cases
            .iter()
            .filter(|&&((x, y), want)| lattice.index(x, y) != want)
            .map(|&((x, y), want)| format!("({x}, {y}): {:?}, want {want:?}", lattice.index(x, y)))
            .collect();
        if Lattice::new(41, 30, 0, 1).index(0, 0).is_some() {
            failures.push("a lattice of step 0 holds (0, 0)".into());
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
}
