//! The tile driver: renders one tile of one frame with any method (pbrt's tile integrator).
//! It walks the method's [`Order`] pass by pass over the tile and the halo the tile depends
//! on, and for each pixel does the bookkeeping every method shares — the primary ray and the
//! above-horizon lights, the valid voters, the previous frame's voters first (`--temporal`),
//! then the method's [`Rule`](crate::predict::Rule) — and at the end counts the tile's work,
//! validates it against brute force (`--validate`) and shades it (ALGORITHM.md §2).
//!
//! A frame's shared passes (the grid's coarse levels) run first over all tiles into a
//! [`Lattice`] ([`FrameWork::shared_phase`]); each tile then copies what it reads from it and
//! evaluates the remaining passes ([`FrameWork::tile`]), so a tile's pixels are bit for bit
//! those of the whole frame.

use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;
use crate::film::{Counts, TileResult};
use crate::lattice::{Lattice, LatticePatch};
use crate::predict::temporal::solve_temporal;
use crate::predict::{At, Order, Scratch, Shadows};
use crate::shade::radiance;
use crate::tile::Rect;

/// One thread's reusable buffers: the tile's pixels and the method's per-pixel scratch side by
/// side, allocated once and reused across tiles and frames.
#[derive(Default)]
pub struct Slot {
    pub bufs: TileBuffers,
    pub scratch: Scratch,
    /// The final phase's pixels sorted by pass (region indices), where each pass starts in
    /// it, and which pixels the tile depends on.
    by_pass: Vec<u32>,
    pass_start: Vec<usize>,
    need: Vec<bool>,
}

/// One frame's shadow work, shared read-only by the threads rendering its tiles.
pub struct FrameWork<'a> {
    pub ctx: &'a FrameContext<'a>,
    /// The method built for this frame (with the previous frame, if temporal).
    pub shadows: &'a Shadows<'a>,
    /// Also trace every query and count the method's mistakes (`--validate`).
    pub validate: bool,
}

impl FrameWork<'_> {
    fn order(&self) -> &dyn Order {
        self.shadows.order.as_ref()
    }

    fn frame(&self) -> Rect {
        Rect::frame(self.ctx.camera.width, self.ctx.camera.height)
    }

    /// Phases shared through the lattice (0: none).
    pub fn shared_phases(&self) -> usize {
        self.order().shared_passes()
    }

    /// How far beyond a tile the shared phases' pixels it depends on reach.
    pub fn shared_reach(&self) -> u32 {
        self.order().shared_reach()
    }

    /// An empty lattice for this frame's shared phases.
    pub fn lattice(&self) -> Lattice {
        let c = &self.ctx.camera;
        Lattice::new(
            c.width,
            c.height,
            self.order().lattice_step(),
            self.ctx.words(),
        )
    }

    /// Sizes `slot` for `tile` and the region `phase` reads, and copies in the lattice pixels
    /// there (those inside the tile count as the tile's own: their rays are the tile's).
    fn prepare(&self, slot: &mut Slot, tile: Rect, phase: usize, lattice: &Lattice) {
        let region = self.order().region(self.frame(), tile, phase);
        debug_assert!(region.intersect(&tile) == tile);
        let bufs = &mut slot.bufs;
        bufs.prepare(self.ctx, tile, region);
        slot.scratch.prepare(self.ctx.light_count());
        let step = lattice.step();
        if step == 0 {
            return;
        }
        let (x0, y0) = (
            region.x0.div_ceil(step) * step,
            region.y0.div_ceil(step) * step,
        );
        for y in (y0..region.y1).step_by(step as usize) {
            for x in (x0..region.x1).step_by(step as usize) {
                let i = region.index(x, y);
                if lattice.copy_into(x, y, bufs, i) && tile.contains(x, y) {
                    bufs.needed[i] = true;
                }
            }
        }
    }

    /// Decides frame pixel (x, y) of `pass` (decided `at`): its surface and above-horizon
    /// lights, its valid voters, then the previous frame's voters where it has them, else the
    /// method's rule. Returns its region index.
    fn evaluate(&self, slot: &mut Slot, x: u32, y: u32, pass: usize, at: At, frame: Rect) -> usize {
        let (ctx, order) = (self.ctx, self.order());
        let Slot { bufs, scratch, .. } = slot;
        let i = bufs.begin_pixel(ctx, x, y);
        let mut candidates = [(0u32, 0u32); 4];
        let n = order.voters(x, y, pass, frame, &mut candidates);
        let mut voters = [0usize; 4];
        let mut nv = 0;
        for &(vx, vy) in &candidates[..n] {
            let q = bufs.region.index(vx, vy);
            if bufs.surf[q].hit {
                voters[nv] = q;
                nv += 1;
            }
        }
        let voters = &voters[..nv];
        if let Some(prev) = self.shadows.prev {
            let min_voters = self.shadows.params.min_voters;
            if solve_temporal(ctx, bufs, scratch, prev, i, voters, min_voters, at) {
                return i;
            }
        }
        self.shadows.rule.solve(ctx, bufs, scratch, i, voters, at);
        i
    }

    /// Runs shared phase `phase` (a pass evaluated once per frame) on `tile`: evaluates the
    /// pass's pixels inside the tile and returns them for the frame's lattice.
    pub fn shared_phase(
        &self,
        tile: Rect,
        slot: &mut Slot,
        phase: usize,
        lattice: &Lattice,
    ) -> LatticePatch {
        self.prepare(slot, tile, phase, lattice);
        let mut patch = LatticePatch::default();
        let (at, frame) = (self.shadows.at(phase), self.frame());
        let step = lattice.step();
        let (x0, y0) = (tile.x0.div_ceil(step) * step, tile.y0.div_ceil(step) * step);
        for y in (y0..tile.y1).step_by(step as usize) {
            for x in (x0..tile.x1).step_by(step as usize) {
                if self.order().pass_of(x, y) != phase {
                    continue;
                }
                let i = self.evaluate(slot, x, y, phase, at, frame);
                patch.record(lattice, x, y, &slot.bufs, i);
            }
        }
        patch
    }

    /// Renders `tile` (the final phase): evaluates the remaining passes at the pixels the tile
    /// depends on — marked walking the passes backwards from the tile — then counts, validates
    /// and shades. `slot` keeps the tile's buffers afterwards (for the frame's carried data).
    pub fn tile(&self, tile: Rect, slot: &mut Slot, lattice: &Lattice) -> TileResult {
        let order = self.order();
        let (shared, passes) = (order.shared_passes(), order.passes());
        self.prepare(slot, tile, shared, lattice);
        let region = slot.bufs.region;
        let frame = self.frame();
        // The region's unshared pixels, by pass, each pass in row-major order.
        slot.pass_start.clear();
        slot.pass_start.resize(passes + 1, 0);
        slot.by_pass.clear();
        if passes == shared + 1 {
            // One pass: the region in row-major order.
            slot.pass_start[passes] = region.area();
            slot.by_pass.extend(0..region.area() as u32);
        } else {
            for y in region.y0..region.y1 {
                for x in region.x0..region.x1 {
                    let p = order.pass_of(x, y);
                    if p >= shared {
                        slot.pass_start[p + 1] += 1;
                    }
                }
            }
            for p in 0..passes {
                slot.pass_start[p + 1] += slot.pass_start[p];
            }
            let mut fill = slot.pass_start.clone();
            slot.by_pass.resize(slot.pass_start[passes], 0);
            for y in region.y0..region.y1 {
                for x in region.x0..region.x1 {
                    let p = order.pass_of(x, y);
                    if p >= shared {
                        slot.by_pass[fill[p]] = region.index(x, y) as u32;
                        fill[p] += 1;
                    }
                }
            }
        }
        // The pixels the tile depends on: without a halo, its own; else its own, then
        // backwards through the passes (and backwards within a pass, whose pixels may read
        // earlier ones of the same pass) every voter of a needed pixel.
        slot.need.clear();
        slot.need.resize(region.area(), region == tile);
        let rw = region.width();
        let coords = |i: u32| (region.x0 + i % rw, region.y0 + i / rw);
        if region != tile {
            for y in tile.y0..tile.y1 {
                for x in tile.x0..tile.x1 {
                    slot.need[region.index(x, y)] = true;
                }
            }
            let mut candidates = [(0u32, 0u32); 4];
            for p in (shared..passes).rev() {
                for k in (slot.pass_start[p]..slot.pass_start[p + 1]).rev() {
                    let i = slot.by_pass[k];
                    if !slot.need[i as usize] {
                        continue;
                    }
                    let (x, y) = coords(i);
                    let n = order.voters(x, y, p, frame, &mut candidates);
                    for &(vx, vy) in &candidates[..n] {
                        slot.need[region.index(vx, vy)] = true;
                    }
                }
            }
        }
        for p in shared..passes {
            let at = self.shadows.at(p);
            for k in slot.pass_start[p]..slot.pass_start[p + 1] {
                let i = slot.by_pass[k];
                if slot.need[i as usize] {
                    let (x, y) = coords(i);
                    self.evaluate(slot, x, y, p, at, frame);
                }
            }
        }
        let counts = count_work(&slot.bufs);
        shade(self.ctx, &slot.bufs, self.validate, counts)
    }
}

/// Queries and rays of the tile's pixels, and the halo's work apart.
fn count_work(bufs: &TileBuffers) -> Counts {
    let (r, t, w) = (bufs.region, bufs.tile, bufs.words);
    let mut c = Counts::default();
    for y in r.y0..r.y1 {
        for x in r.x0..r.x1 {
            let i = r.index(x, y);
            if t.contains(x, y) {
                debug_assert!(bufs.needed[i], "method left pixel ({x}, {y}) unevaluated");
                c.queries += bits::count(TileBuffers::row(&bufs.above, i, w)) as u64;
                c.rays += bufs.rays[i] as u64;
                let why = bufs.split[i];
                c.rays_every_light += why.every as u64;
                c.rays_flooded += why.flooded as u64;
                c.flood_fixes += why.fixes as u64;
                if bufs.temporal[i] {
                    c.temporal_pixels += 1;
                    c.temporal_rays += bufs.rays[i] as u64;
                }
            } else if bufs.needed[i] {
                c.halo_pixels += 1;
                c.halo_rays += bufs.rays[i] as u64;
            }
        }
    }
    c
}

/// Shades the tile's pixels and, with `validate`, traces every query again to count the
/// method's mistakes and shade the brute-force reference.
fn shade(ctx: &FrameContext, bufs: &TileBuffers, validate: bool, mut counts: Counts) -> TileResult {
    let tile = bufs.tile;
    let w = bufs.words;
    let n = tile.area();
    let mut beauty = Vec::with_capacity(n);
    let mut rays = Vec::with_capacity(n);
    let mut visible = Vec::with_capacity(n);
    let mut wrong = validate.then(|| Vec::with_capacity(n));
    let mut reference = validate.then(|| Vec::with_capacity(n));
    let mut truth = vec![0u64; w];
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let i = bufs.region.index(x, y);
            let s = bufs.surf[i];
            rays.push(bufs.rays[i] as f32);
            if !s.hit {
                let r = ctx.env.radiance(ctx.camera.ray_dir(x, y)).to_array();
                beauty.push(r);
                visible.push(0.0);
                if let (Some(wr), Some(rf)) = (&mut wrong, &mut reference) {
                    wr.push(0.0);
                    rf.push(r);
                }
                continue;
            }
            let vis = TileBuffers::row(&bufs.vis, i, w);
            let above = TileBuffers::row(&bufs.above, i, w);
            let lit = radiance(&ctx.shade_lights, s.n, s.albedo, vis);
            beauty.push(lit.to_array());
            let n_above = bits::count(above);
            visible.push(if n_above > 0 {
                bits::count(vis) as f32 / n_above as f32
            } else {
                0.0
            });
            if let (Some(wr), Some(rf)) = (&mut wrong, &mut reference) {
                // The truth: every query traced again, those the method traced included,
                // so a method that mis-records a trace shows up as `wrong_traced`.
                for k in 0..w {
                    truth[k] = 0;
                    let mut m = above[k];
                    while m != 0 {
                        let j = k * 64 + m.trailing_zeros() as usize;
                        m &= m - 1;
                        if ctx.trace(&s, j) {
                            truth[k] |= 1 << (j & 63);
                        }
                    }
                }
                let traced = TileBuffers::row(&bufs.traced, i, w);
                for k in 0..w {
                    counts.wrong_traced +=
                        ((vis[k] ^ truth[k]) & above[k] & traced[k]).count_ones() as u64;
                }
                let (mut wv, mut wb) = (0u64, 0u64);
                for k in 0..w {
                    wv += (vis[k] & !truth[k] & above[k]).count_ones() as u64;
                    wb += (!vis[k] & truth[k] & above[k]).count_ones() as u64;
                }
                counts.wrong_visible += wv;
                counts.wrong_blocked += wb;
                counts.wrong_pixels += u64::from(wv + wb > 0);
                wr.push((wv + wb) as f32);
                rf.push(radiance(&ctx.shade_lights, s.n, s.albedo, &truth).to_array());
            }
        }
    }
    TileResult {
        rect: tile,
        beauty,
        rays,
        visible,
        wrong,
        reference,
        counts,
    }
}
