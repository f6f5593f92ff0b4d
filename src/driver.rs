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
//!
//! With several samples per pixel (`--spp`) the methods run on the samples: a tile of pixels
//! is a tile of k × k times as many samples, and everything below — orders, voters, halos,
//! the lattice, the buffers — addresses samples (sample (x, y) is stratum (x mod k, y mod k)
//! of pixel (x div k, y div k)). Only the last step, shading, gathers each pixel's own samples
//! into its value; the filter is importance-sampled into the sample positions
//! (`crate::samples`), so no pixel reads another's samples.

use crate::accel::PACKET;
use crate::bits;
use crate::buffers::TileBuffers;
use crate::catcher::{self, Catchers};
use crate::context::{FrameContext, Surface};
use crate::cryptomatte::{Ids, RANKS, Ranking};
use crate::film::{BACKGROUND_DEPTH, Channel, Counts, Holds, Planes, TileResult};
use crate::history::CarryPatch;
use crate::lattice::{Lattice, LatticePatch};
use crate::predict::{At, Link, Order, Scratch, Shadows};
use crate::radiance::{group_radiance, radiance_at};
use crate::shade::LambertCache;
use crate::shading_rate::{ShadingRate, group};
use crate::tile::Rect;
use glam::Vec3;

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
    /// The method built for this frame.
    pub shadows: &'a Shadows,
    /// What the frame reads of the previous frame and keeps for the next (`--temporal`).
    pub link: &'a Link<'a>,
    /// Also trace every query and count the method's mistakes (`--validate`).
    pub validate: bool,
    /// How often a pixel's samples are shaded (`--shading-rate`).
    pub shading_rate: ShadingRate,
    /// The scene's IDs, with Cryptomatte (`--cryptomatte`).
    pub ids: Option<&'a Ids>,
}

impl FrameWork<'_> {
    fn order(&self) -> &dyn Order {
        self.shadows.order.as_ref()
    }

    /// Samples per pixel side.
    fn k(&self) -> u32 {
        self.ctx.samples.k
    }

    /// The frame's samples.
    fn frame(&self) -> Rect {
        let k = self.k();
        Rect::frame(self.ctx.camera.width * k, self.ctx.camera.height * k)
    }

    /// The samples of the pixels of `r`.
    fn samples_of(&self, r: Rect) -> Rect {
        let k = self.k();
        Rect::new(r.x0 * k, r.y0 * k, r.x1 * k, r.y1 * k)
    }

    /// Phases shared through the lattice (0: none).
    pub fn shared_phases(&self) -> usize {
        self.order().shared_passes()
    }

    /// How far beyond a tile, in pixels, the shared phases' samples it depends on reach.
    pub fn shared_reach(&self) -> u32 {
        self.order().shared_reach().div_ceil(self.k())
    }

    /// An empty lattice for this frame's shared phases.
    pub fn lattice(&self) -> Lattice {
        let f = self.frame();
        Lattice::new(f.x1, f.y1, self.order().lattice_step(), self.ctx.words())
    }

    /// Rays the lattice traced inside the pixels of `tile`: ranks tiles by the work they will
    /// do (where the coarse levels were unsure, the finer ones trace most).
    pub fn rays_in(&self, lattice: &Lattice, tile: Rect) -> u64 {
        lattice.rays_in(self.samples_of(tile))
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
            if bufs.voter[q] {
                voters[nv] = q;
                nv += 1;
            }
        }
        let voters = &voters[..nv];
        if self
            .link
            .solve(ctx, self.shadows, bufs, scratch, (i, voters), at)
        {
            return i;
        }
        self.shadows.rule.solve(ctx, bufs, scratch, i, voters, at);
        i
    }

    /// Runs shared phase `phase` (a pass evaluated once per frame) on the pixels of `tile`:
    /// evaluates the pass's samples inside the tile and returns them for the frame's lattice.
    pub fn shared_phase(
        &self,
        tile: Rect,
        slot: &mut Slot,
        phase: usize,
        lattice: &Lattice,
    ) -> LatticePatch {
        let tile = self.samples_of(tile);
        self.prepare(slot, tile, phase, lattice);
        let mut patch = LatticePatch::default();
        let (at, frame) = (self.shadows.at(self.ctx, phase), self.frame());
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

    /// The channels this frame's films hold beyond the ones every film does: its tiles' and
    /// the whole frame's alike.
    pub fn holds(&self) -> Holds {
        Holds {
            validated: self.validate,
            samples: self.k() > 1,
            transparent: self.ctx.backdrop.is_transparent(),
            cryptomatte: self.ids.is_some(),
        }
    }

    /// Renders the pixels of `pixels` (the final phase): evaluates the remaining passes at the
    /// samples the tile depends on — marked walking the passes backwards from the tile — then
    /// counts, validates and shades. Returns the tile's result and what it carries forward for
    /// the next frame (if the frame's link keeps anything).
    pub fn tile(
        &self,
        pixels: Rect,
        slot: &mut Slot,
        lattice: &Lattice,
    ) -> (TileResult, Option<CarryPatch>) {
        let tile = self.samples_of(pixels);
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
        if self.k() > 1 {
            self.prime(slot);
        }
        for p in shared..passes {
            let at = self.shadows.at(self.ctx, p);
            for k in slot.pass_start[p]..slot.pass_start[p + 1] {
                let i = slot.by_pass[k];
                if slot.need[i as usize] {
                    let (x, y) = coords(i);
                    self.evaluate(slot, x, y, p, at, frame);
                }
            }
        }
        let counts = count_halo(&slot.bufs);
        let result = shade(
            self.ctx,
            (self.shading_rate, self.ids),
            &slot.bufs,
            pixels,
            self.holds(),
            counts,
        );
        (result, self.link.keep(self.ctx, &slot.bufs))
    }
}

impl FrameWork<'_> {
    /// Traces the primary rays of the samples the tile's passes will evaluate (`slot.need`,
    /// not the lattice's), a pixel's together ([`FrameContext::surfaces`]: the same surfaces
    /// as one ray at a time), and marks them primed for [`TileBuffers::begin_pixel`].
    fn prime(&self, slot: &mut Slot) {
        let (k, order) = (self.k(), self.order());
        let shared = order.shared_passes();
        let one_pass = order.passes() == shared + 1;
        let Slot { bufs, need, .. } = slot;
        let region = bufs.region;
        // A packet: strata of one pixel, and their places in the region.
        let (mut strata, mut index) = ([0u32; PACKET], [0usize; PACKET]);
        let trace = |bufs: &mut TileBuffers, pixel, strata: &[u32], index: &[usize]| {
            self.ctx.surfaces(pixel, strata, &mut bufs.surf, index);
            for &i in index {
                bufs.primed[i] = true;
            }
        };
        for py in region.y0 / k..region.y1.div_ceil(k) {
            for px in region.x0 / k..region.x1.div_ceil(k) {
                let mut n = 0;
                for s in 0..k * k {
                    let (x, y) = (px * k + s % k, py * k + s / k);
                    if !region.contains(x, y) {
                        continue;
                    }
                    let i = region.index(x, y);
                    if !need[i] || !(one_pass || order.pass_of(x, y) >= shared) {
                        continue;
                    }
                    (strata[n], index[n]) = (s, i);
                    n += 1;
                    if n == PACKET {
                        trace(bufs, (px, py), &strata, &index);
                        n = 0;
                    }
                }
                if n > 0 {
                    trace(bufs, (px, py), &strata[..n], &index[..n]);
                }
            }
        }
    }
}

/// The halo's work: pixels outside the tile the method evaluated for it, and their rays (the
/// tile's own are counted as it is shaded).
fn count_halo(bufs: &TileBuffers) -> Counts {
    let (r, t) = (bufs.region, bufs.tile);
    let mut c = Counts::default();
    if r == t {
        return c;
    }
    for y in r.y0..r.y1 {
        for x in r.x0..r.x1 {
            let i = r.index(x, y);
            if bufs.needed[i] && !t.contains(x, y) {
                c.halo_pixels += 1;
                c.halo_rays += bufs.rays[i] as u64;
            }
        }
    }
    c
}

/// Shades the samples of the tile's `pixels`, counts their queries and rays into `counts`,
/// and gathers each pixel's own — the mean of their radiance (in stratum order, so the sum
/// does not depend on the tile), the sum of their rays and wrong pairs, the mean of their
/// visible fractions and, with several samples, the fraction that hit; over a transparent
/// background the mean of their alphas (`crate::catcher`: 1 on the model, the shadow fraction
/// on a catcher, 0 on the background); for the compositor, the nearest depth, and the mean
/// normal and albedo (background samples counting 0). Validated, every query is traced
/// again to count the method's mistakes and shade the brute-force reference. With one sample
/// per pixel this is the pixel as it always was: adding to zero and dividing by one change no
/// bit.
///
/// At the pixel shading rate (`crate::shading_rate`, several samples per pixel) the samples
/// that hit the model are shaded in groups that share a surface, after the pixel's other
/// samples (background and catchers, shaded one by one); the reference is shaded the same
/// way from the traced bits, so the validated error is the method's alone.
///
/// With Cryptomatte (`ids`), each hit sample counts for its object's and its material's ID,
/// and the pixel's IDs are ranked by their share of its samples ([`Mattes`]).
fn shade(
    ctx: &FrameContext,
    (rate, ids): (ShadingRate, Option<&Ids>),
    bufs: &TileBuffers,
    pixels: Rect,
    holds: Holds,
    mut counts: Counts,
) -> TileResult {
    let k = ctx.samples.k;
    let spp = (k * k) as f32;
    let w = bufs.words;
    let n = pixels.area();
    let mut planes = Planes::new(n, holds);
    let mut p = 0;
    let (eye, forward) = (ctx.camera.position, ctx.camera.forward());
    let mut shader = Shader::new(ctx, rate, (k * k) as usize, w);
    let mut mattes = ids.map(|ids| Mattes::new(ids, (k * k) as usize));
    for py in pixels.y0..pixels.y1 {
        for px in pixels.x0..pixels.x1 {
            let mut lit = Vec3::ZERO;
            let mut traced = 0.0f32;
            let mut seen = 0.0f32;
            let mut mistakes = 0.0f32;
            let mut exact = Vec3::ZERO;
            let mut hits = 0u32;
            let mut opacity = 0.0f32;
            let mut nearest = f32::INFINITY;
            let mut n_sum = Vec3::ZERO;
            let mut a_sum = Vec3::ZERO;
            shader.members = 0;
            if let Some(m) = &mut mattes {
                m.clear();
            }
            for j in 0..k {
                for i in 0..k {
                    let (x, y) = (px * k + i, py * k + j);
                    let q = bufs.region.index(x, y);
                    debug_assert!(bufs.needed[q], "method left sample ({x}, {y}) unevaluated");
                    let s = &bufs.surf[q];
                    traced += bufs.rays[q] as f32;
                    counts.rays += bufs.rays[q] as u64;
                    let why = bufs.split[q];
                    counts.rays_every_light += why.every as u64;
                    counts.rays_flooded += why.flooded as u64;
                    counts.flood_fixes += why.fixes as u64;
                    if bufs.temporal[q] {
                        counts.temporal_pixels += 1;
                        counts.temporal_rays += bufs.rays[q] as u64;
                        counts.temporal_stale += u64::from(bufs.stale[q]);
                    }
                    if !s.hit {
                        let (r, a) = catcher::miss(ctx, s.dir);
                        lit += r;
                        exact += r;
                        opacity += a;
                        continue;
                    }
                    hits += 1;
                    if let Some(m) = &mut mattes {
                        m.add(s);
                    }
                    nearest = nearest.min((s.p - eye).dot(forward));
                    n_sum += s.n;
                    a_sum += s.albedo;
                    let above = bits::rows(&bufs.above, w).row(q);
                    let (c, a) = shader.sample(bufs, q);
                    lit += c;
                    opacity += a;
                    let n_above = bits::count(above);
                    counts.queries += n_above as u64;
                    if n_above > 0 {
                        seen +=
                            bits::count(bits::rows(&bufs.vis, w).row(q)) as f32 / n_above as f32;
                    }
                    if !holds.validated {
                        continue;
                    }
                    let (wrong_pairs, reference) = shader.validate(bufs, q, &mut counts);
                    mistakes += wrong_pairs as f32;
                    exact += reference;
                }
            }
            if shader.members > 0 {
                let members = &shader.member[..shader.members];
                let groups = group(&bufs.surf, members, &mut shader.group_of);
                lit += shader.groups(bufs, groups, false);
                if holds.validated {
                    exact += shader.groups(bufs, groups, true);
                }
            }
            // Each channel's value (those the tile does not hold are dropped).
            let (beauty, reference) = (lit / spp, exact / spp);
            let (normal, albedo) = (n_sum / spp, a_sum / spp);
            let depth = if hits > 0 { nearest } else { BACKGROUND_DEPTH };
            use Channel::*;
            for (c, v) in [
                (R, beauty.x),
                (G, beauty.y),
                (B, beauty.z),
                (A, opacity / spp),
                (Z, depth),
                (NX, normal.x),
                (NY, normal.y),
                (NZ, normal.z),
                (AlbedoR, albedo.x),
                (AlbedoG, albedo.y),
                (AlbedoB, albedo.z),
                (Rays, traced),
                (Visible, seen / spp),
                (Wrong, mistakes),
                (Coverage, hits as f32 / spp),
                (RefR, reference.x),
                (RefG, reference.y),
                (RefB, reference.z),
            ] {
                planes.set(c, p, v);
            }
            if let Some(m) = &mut mattes {
                m.write(&mut planes, p, spp);
            }
            p += 1;
        }
    }
    TileResult {
        rect: pixels,
        planes,
        counts,
    }
}

/// A pixel's Cryptomatte ranks, gathered sample by sample: its objects' and materials' IDs,
/// each counted once per sample that saw it (the filter placed the samples, so each weighs
/// the same), written as shares of the pixel's samples.
struct Mattes<'a> {
    ids: &'a Ids,
    objects: Ranking,
    materials: Ranking,
}

impl<'a> Mattes<'a> {
    fn new(ids: &'a Ids, spp: usize) -> Mattes<'a> {
        Mattes {
            ids,
            objects: Ranking::new(spp),
            materials: Ranking::new(spp),
        }
    }

    fn clear(&mut self) {
        self.objects.clear();
        self.materials.clear();
    }

    /// A sample that hit `s`.
    #[inline]
    fn add(&mut self, s: &Surface) {
        self.objects.add(self.ids.object_id(s.tri), 1.0);
        self.materials
            .add(self.ids.material_id(s.material_index), 1.0);
    }

    /// Writes the pixel's ranks into pixel `p` of `planes`, coverages as shares of `spp`.
    fn write(&mut self, planes: &mut Planes, p: usize, spp: f32) {
        for (ranking, channels) in [&mut self.objects, &mut self.materials]
            .into_iter()
            .zip(Channel::CRYPTOMATTE)
        {
            let ranks: [(f32, f32); RANKS] = ranking.ranks();
            for (r, (id, count)) in ranks.into_iter().enumerate() {
                planes.set(channels[2 * r], p, id);
                planes.set(channels[2 * r + 1], p, count / spp);
            }
        }
    }
}

/// One tile's shading of the model's samples: one by one, or at the pixel rate gathered per
/// pixel ([`Shader::sample`]) and shaded in groups at the pixel's end ([`Shader::groups`]).
struct Shader<'a> {
    ctx: &'a FrameContext<'a>,
    /// Groups of samples share their lobe (the pixel shading rate, several samples).
    shared: bool,
    words: usize,
    /// Lambertian samples with the normal and visible lights of the last one reuse its sum.
    cache: LambertCache,
    /// The reference has its own Lambertian cache and shares the catchers' (keyed on the
    /// normal).
    caches: (LambertCache, Catchers),
    /// The pixel's samples to shade in groups (region indices), and their traced bits
    /// (validated), a row each, then a spare row for the samples shaded alone.
    member: Vec<usize>,
    members: usize,
    truth: Vec<u64>,
    /// One group's rows of visible lights, back to back.
    group_vis: Vec<u64>,
    group_of: Vec<u8>,
    group_surf: Vec<Surface>,
}

impl<'a> Shader<'a> {
    fn new(ctx: &'a FrameContext<'a>, rate: ShadingRate, spp: usize, words: usize) -> Shader<'a> {
        Shader {
            ctx,
            shared: rate == ShadingRate::Pixel && spp > 1,
            words,
            cache: LambertCache::default(),
            caches: Default::default(),
            member: vec![0; spp],
            members: 0,
            truth: vec![0; (spp + 1) * words],
            group_vis: Vec::with_capacity(spp * words),
            group_of: vec![0; spp],
            group_surf: Vec::with_capacity(spp),
        }
    }

    /// Whether hit `s` is shaded with its pixel's group: at the pixel rate, a glTF-material
    /// sample of the model (not a catcher). [ours] Lambertian samples are shaded alone at
    /// either rate: their kernel costs about what counting their lights would (three products
    /// a light), and a flat surface's samples reuse one sum ([`LambertCache`]), which counting
    /// cannot.
    fn grouped(&self, s: &Surface) -> bool {
        self.shared && !s.catcher && !s.material.lambert
    }

    /// Sample `q` (a hit): its radiance and alpha, or — a sample [`Shader::grouped`] — nothing
    /// yet but its alpha, 1, its radiance left to [`Shader::groups`].
    fn sample(&mut self, bufs: &TileBuffers, q: usize) -> (Vec3, f32) {
        let (ctx, w) = (self.ctx, self.words);
        let s = &bufs.surf[q];
        let vis = bits::rows(&bufs.vis, w).row(q);
        let above = bits::rows(&bufs.above, w).row(q);
        if self.grouped(s) {
            self.member[self.members] = q;
            self.members += 1;
            (Vec3::ZERO, 1.0)
        } else if s.catcher {
            // [ours] A catcher's shadow is the map's lights' (its fraction is against the
            // map's unshadowed light); the file's point and spot lights do not darken it.
            let sum = self.cache.light_sum(&ctx.shade_lights, s.n, vis);
            self.caches.1.sample(ctx, s, above, sum)
        } else {
            (radiance_at(ctx, s, vis, &mut self.cache), 1.0)
        }
    }

    /// Validates sample `q` (a hit; `--validate`): traces every query again — those the
    /// method traced included, so a method that mis-records a trace shows up as
    /// `wrong_traced` —, counts the method's wrong pairs into `counts` and shades the
    /// brute-force reference (at the pixel rate, a model sample's waits for
    /// [`Shader::groups`], which reads its traced bits). Returns the sample's wrong pairs
    /// and its reference radiance.
    fn validate(&mut self, bufs: &TileBuffers, q: usize, counts: &mut Counts) -> (u64, Vec3) {
        let (ctx, w) = (self.ctx, self.words);
        let s = &bufs.surf[q];
        let grouped = self.grouped(s);
        // A grouped sample's row is its place among the members (it was just added); another
        // sample's is the spare row after them, which no member's traced bits occupy.
        let row = if grouped {
            self.members - 1
        } else {
            self.member.len()
        };
        let truth = bits::rows_mut(&mut self.truth, w).into_row(row);
        let vis = bits::rows(&bufs.vis, w).row(q);
        let above = bits::rows(&bufs.above, w).row(q);
        for m in 0..w {
            truth[m] = 0;
            let mut word = above[m];
            while word != 0 {
                let j = m * 64 + word.trailing_zeros() as usize;
                word &= word - 1;
                if ctx.trace(s, j) {
                    truth[m] |= 1 << (j & 63);
                }
            }
        }
        let traced_bits = bits::rows(&bufs.traced, w).row(q);
        let (mut wv, mut wb) = (0u64, 0u64);
        for m in 0..w {
            counts.wrong_traced +=
                ((vis[m] ^ truth[m]) & above[m] & traced_bits[m]).count_ones() as u64;
            wv += (vis[m] & !truth[m] & above[m]).count_ones() as u64;
            wb += (!vis[m] & truth[m] & above[m]).count_ones() as u64;
        }
        counts.wrong_visible += wv;
        counts.wrong_blocked += wb;
        counts.wrong_pixels += u64::from(wv + wb > 0);
        let (exact_cache, catchers) = &mut self.caches;
        let exact = if grouped {
            Vec3::ZERO
        } else if s.catcher {
            let sum = exact_cache.light_sum(&ctx.shade_lights, s.n, truth);
            catchers.sample(ctx, s, above, sum).0
        } else {
            radiance_at(ctx, s, truth, exact_cache)
        };
        (wv + wb, exact)
    }

    /// The summed radiance of the pixel's gathered samples, shaded in the `count` groups that
    /// share a surface (`group_of`, from `crate::shading_rate::group`), from their visible
    /// lights or, for the reference (`traced`), from the lights [`Shader::validate`] traced.
    fn groups(&mut self, bufs: &TileBuffers, count: usize, traced: bool) -> Vec3 {
        let (ctx, w) = (self.ctx, self.words);
        let members = &self.member[..self.members];
        let mut lit = Vec3::ZERO;
        let row = |i: usize, q: usize| {
            if traced {
                bits::rows(&self.truth, w).row(i)
            } else {
                bits::rows(&bufs.vis, w).row(q)
            }
        };
        for g in 0..count as u8 {
            let mut of = members
                .iter()
                .enumerate()
                .filter(|&(i, _)| self.group_of[i] == g);
            let (first, &q) = of.next().expect("a group has a first member");
            if of.next().is_none() {
                // A sample alone is shaded as at the sample rate: the same bits, no copies.
                let cache = if traced {
                    &mut self.caches.0
                } else {
                    &mut self.cache
                };
                lit += radiance_at(ctx, &bufs.surf[q], row(first, q), cache);
                continue;
            }
            self.group_vis.clear();
            self.group_surf.clear();
            for (i, &q) in members.iter().enumerate() {
                if self.group_of[i] != g {
                    continue;
                }
                self.group_surf.push(bufs.surf[q]);
                self.group_vis.extend_from_slice(row(i, q));
            }
            lit += group_radiance(ctx, &self.group_surf, bits::rows(&self.group_vis, w));
        }
        lit
    }
}
