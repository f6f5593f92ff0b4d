//! Pixels shared by every tile of a frame [ours, §8].
//!
//! The coarse levels of the grid order are few pixels that trace many rays (the coarse grid
//! traces every light). A tile whose halo re-evaluated them would repeat the dearest work of
//! its neighbours. Instead they are evaluated once per frame, level by level, each pixel by the
//! tile that contains it, and kept here; tiles then copy what they read. A lattice pixel is a
//! pure function of the frame, so the result is the same whatever evaluates it.

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
    /// Predicted from the previous frame (`--temporal`).
    temporal: Vec<bool>,
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
        if self.step == 0 || x % self.step != 0 || y % self.step != 0 {
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
        bufs.surf[i] = self.surf[k];
        let src = &self.bits[k * 3 * w..(k + 1) * 3 * w];
        bufs.above[i * w..(i + 1) * w].copy_from_slice(&src[..w]);
        bufs.vis[i * w..(i + 1) * w].copy_from_slice(&src[w..2 * w]);
        bufs.traced[i * w..(i + 1) * w].copy_from_slice(&src[2 * w..]);
        bufs.rays[i] = self.rays[k];
        bufs.split[i] = self.split[k];
        bufs.temporal[i] = self.temporal[k];
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
            self.bits[k * 3 * w..(k + 1) * 3 * w]
                .copy_from_slice(&patch.bits[n * 3 * w..(n + 1) * 3 * w]);
            self.rays[k] = patch.rays[n];
            self.split[k] = patch.split[n];
            self.temporal[k] = patch.temporal[n];
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
        self.bits.extend_from_slice(&bufs.above[i * w..(i + 1) * w]);
        self.bits.extend_from_slice(&bufs.vis[i * w..(i + 1) * w]);
        self.bits
            .extend_from_slice(&bufs.traced[i * w..(i + 1) * w]);
        self.rays.push(bufs.rays[i]);
        self.split.push(bufs.split[i]);
        self.temporal.push(bufs.temporal[i]);
        let mut n = 0;
        for (j, t) in bufs.blockers.of(i) {
            self.blk_light.push(j as u16);
            self.blk_dist.push(t);
            n += 1;
        }
        self.blk_len.push(n);
    }
}
