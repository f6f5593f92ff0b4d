//! Rendering one tile of one frame: primary rays, shadow visibility (by the chosen
//! [`Predictor`]), optional validation against brute force, Lambertian shading
//! (ALGORITHM.md §2).

use glam::Vec3;

use crate::accel::{Accel, PACKET};
use crate::camera::Camera;
use crate::envmap::EnvMap;
use crate::film::{Counts, TileResult};
use crate::lights::LightSet;
use crate::predict::{Lattice, LatticePatch, Predictor, bits};
use crate::scene::Scene;
use crate::tile::Rect;

/// What a primary ray found at a pixel centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Surface {
    /// Hit point.
    pub p: Vec3,
    /// Unit shading normal, on the side facing the camera.
    pub n: Vec3,
    /// Unit geometric normal, on the side facing the camera: shadow rays start off it.
    pub ng: Vec3,
    /// Linear RGB albedo.
    pub albedo: Vec3,
    /// False for background pixels (the ray left the scene).
    pub hit: bool,
}

/// Everything a tile needs about its frame: shared, read-only, across threads.
pub struct FrameContext<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    pub camera: Camera,
    pub lights: &'a LightSet,
    pub env: &'a EnvMap,
    /// Light directions as a flat array, for shadow rays and warping.
    pub light_dir: Vec<Vec3>,
    /// The lights for the horizon test and shading, padded with zero lights to whole words
    /// (see [`above_horizon`] and [`radiance`]).
    pub shade_lights: ShadeLights,
    /// Shadow-ray origin offset along the geometric normal (scene units).
    pub shadow_eps: f32,
    pub predictor: &'a dyn Predictor,
    /// Also trace every query and count the predictor's mistakes (`--validate`).
    pub validate: bool,
    /// The previous frame, when this one is predicted temporally (`--temporal`).
    pub temporal: Option<&'a crate::temporal::Prev<'a>>,
}

impl<'a> FrameContext<'a> {
    pub fn new(
        scene: &'a Scene,
        accel: &'a Accel,
        camera: Camera,
        lights: &'a LightSet,
        env: &'a EnvMap,
        predictor: &'a dyn Predictor,
    ) -> FrameContext<'a> {
        FrameContext {
            scene,
            accel,
            camera,
            lights,
            env,
            light_dir: lights.lights.iter().map(|l| l.dir).collect(),
            shade_lights: ShadeLights::new(lights),
            shadow_eps: shadow_epsilon(scene),
            predictor,
            validate: false,
            temporal: None,
        }
    }

    /// Number of lights.
    pub fn light_count(&self) -> usize {
        self.light_dir.len()
    }

    /// Number of u64 words in one pixel's visibility bitset.
    pub fn words(&self) -> usize {
        self.light_count().div_ceil(64)
    }

    /// The surface seen through the centre of pixel (x, y).
    pub fn surface(&self, x: u32, y: u32) -> Surface {
        let dir = self.camera.ray_dir(x, y);
        let Some(hit) = self.accel.intersect(self.camera.position, dir) else {
            return Surface::default();
        };
        let tri = hit.tri as usize;
        let [p0, p1, p2] = self.scene.triangle(tri);
        let p = p0 * (1.0 - hit.u - hit.v) + p1 * hit.u + p2 * hit.v;
        let mut ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let mut n = self.scene.shading_normal(tri, (hit.u, hit.v));
        // Shade the side the camera sees: both normals turn towards the viewer.
        if ng.dot(dir) > 0.0 {
            ng = -ng;
            n = -n;
        }
        // An interpolated normal pointing away from the visible side (back-to-back faces in
        // scanned meshes) would light the surface from behind; the facet's own normal will not.
        if n.dot(ng) <= 0.0 || !n.is_finite() {
            n = ng;
        }
        Surface {
            p,
            n,
            ng,
            albedo: self.scene.albedo(tri, (hit.u, hit.v)),
            hit: true,
        }
    }

    /// Traces the shadow ray from `s` towards light `j`: true when the light is visible.
    #[inline]
    pub fn trace(&self, s: &Surface, j: usize) -> bool {
        !self
            .accel
            .occluded(s.p + s.ng * self.shadow_eps, self.light_dir[j])
    }

    /// [`trace`](Self::trace) for several lights at once (at most [`PACKET`]): bit k of the
    /// result is set when light `lights[k]` is blocked. One packet from the pixel's point,
    /// the same answers as tracing each light alone.
    #[inline]
    pub fn trace_packet(&self, s: &Surface, lights: &[u32]) -> u32 {
        let mut dirs = [Vec3::ZERO; PACKET];
        for (d, &j) in dirs.iter_mut().zip(lights) {
            *d = self.light_dir[j as usize];
        }
        self.accel
            .occluded_packet(s.p + s.ng * self.shadow_eps, &dirs[..lights.len()])
    }

    /// Like [`trace`](Self::trace), returning the distance from `s.p` to a blocker when the
    /// light is blocked (the blocker point is `s.p + t·ω_j`).
    #[inline]
    pub fn trace_blocker(&self, s: &Surface, j: usize) -> Option<f32> {
        self.accel
            .blocker_distance(s.p + s.ng * self.shadow_eps, self.light_dir[j])
    }
}

/// The shadow-ray offset: large enough to leave the surface's own triangle at the scene's
/// float precision, small against any feature. Relative to the scene's size so the same
/// rule serves a 15 cm bunny and a 10 m shapes scene.
pub fn shadow_epsilon(scene: &Scene) -> f32 {
    if scene.positions.is_empty() {
        return 1e-4;
    }
    let (lo, hi) = scene.bounds();
    let diag = (hi - lo).length();
    let reach = lo.abs().max(hi.abs()).max_element();
    (diag * 2e-5).max(reach * 1e-6).max(1e-7)
}

/// Blockers of the evaluated pixels, for the warping predictors: per pixel a run of
/// (light, distance) entries in flat arrays, appended as pixels are evaluated.
#[derive(Default)]
pub struct Blockers {
    pub start: Vec<u32>,
    pub len: Vec<u32>,
    pub light: Vec<u16>,
    pub dist: Vec<f32>,
}

impl Blockers {
    pub(crate) fn reset(&mut self, pixels: usize) {
        self.start.clear();
        self.start.resize(pixels, 0);
        self.len.clear();
        self.len.resize(pixels, 0);
        self.light.clear();
        self.dist.clear();
    }

    /// The blockers of region pixel `i`: (light, distance from the pixel's point).
    #[inline]
    pub fn of(&self, i: usize) -> impl Iterator<Item = (usize, f32)> + '_ {
        let (s, n) = (self.start[i] as usize, self.len[i] as usize);
        self.light[s..s + n]
            .iter()
            .zip(&self.dist[s..s + n])
            .map(|(&j, &t)| (j as usize, t))
    }

    /// Starts pixel `i`'s run; push its entries next.
    #[inline]
    pub fn begin(&mut self, i: usize) {
        self.start[i] = self.light.len() as u32;
        self.len[i] = 0;
    }

    #[inline]
    pub fn push(&mut self, i: usize, light: usize, dist: f32) {
        self.light.push(light as u16);
        self.dist.push(dist);
        self.len[i] += 1;
    }
}

/// Why a pixel's shadow rays were traced, for measuring where the work goes. The rays
/// neither counted here were queued by the pixel's own prediction (lights its voters disagree
/// on, see too few of, or that border a predicted shadow).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RaySplit {
    /// Rays of a pixel that traced every above-horizon light (the coarse grid, pixels without
    /// voters, brute force).
    pub every: u32,
    /// Rays queued by flooding.
    pub flooded: u32,
    /// Flooded rays whose answer differed from the prediction: wrong pairs flooding caught.
    pub fixes: u32,
}

/// Per-tile working buffers, reused across tiles by one thread. Flat arrays and bitsets only:
/// `words` u64 per pixel for each bitset, indexed by the pixel's position in `region`.
#[derive(Default)]
pub struct TileWork {
    /// The pixels this tile outputs.
    pub tile: Rect,
    /// The pixels the buffers cover: the tile plus whatever halo its method reads.
    pub region: Rect,
    pub words: usize,
    /// Surfaces over `region` (valid where `needed`).
    pub surf: Vec<Surface>,
    /// Pixels the method evaluated (the tile's own pixels and its halo).
    pub needed: Vec<bool>,
    /// Lights above each pixel's horizon: its shadow queries.
    pub above: Vec<u64>,
    /// Lights visible from each pixel (traced or predicted).
    pub vis: Vec<u64>,
    /// Lights traced at each pixel.
    pub traced: Vec<u64>,
    /// Shadow rays traced per pixel.
    pub rays: Vec<u32>,
    /// Why they were traced.
    pub split: Vec<RaySplit>,
    /// Pixels predicted from the previous frame (`--temporal`).
    pub temporal: Vec<bool>,
    /// Blockers, for the warping methods.
    pub blockers: Blockers,
    /// Counts for the tile (filled after the method ran).
    pub counts: Counts,
    /// Scratch of the per-pixel prediction, reused.
    pub scratch: crate::predict::Scratch,
}

impl TileWork {
    /// Sizes the buffers for `tile` within `region` (⊇ tile); nothing is evaluated yet.
    pub fn prepare(&mut self, ctx: &FrameContext, tile: Rect, region: Rect) {
        self.tile = tile;
        self.region = region;
        self.words = ctx.words();
        let n = region.area();
        let nw = n * self.words;
        self.surf.clear();
        self.surf.resize(n, Surface::default());
        self.needed.clear();
        self.needed.resize(n, false);
        for v in [&mut self.above, &mut self.vis, &mut self.traced] {
            v.clear();
            v.resize(nw, 0);
        }
        self.rays.clear();
        self.rays.resize(n, 0);
        self.split.clear();
        self.split.resize(n, RaySplit::default());
        self.temporal.clear();
        self.temporal.resize(n, false);
        self.blockers.reset(n);
        self.counts = Counts::default();
        self.scratch.prepare(ctx.light_count());
    }

    /// Evaluates pixel (x, y) of the region: its surface and above-horizon lights. Marks it
    /// needed and returns its region index.
    pub fn begin_pixel(&mut self, ctx: &FrameContext, x: u32, y: u32) -> usize {
        let i = self.region.index(x, y);
        let s = ctx.surface(x, y);
        self.surf[i] = s;
        self.needed[i] = true;
        if s.hit {
            let w = self.words;
            above_horizon(&ctx.shade_lights, s.n, &mut self.above[i * w..(i + 1) * w]);
        }
        i
    }

    /// Bitset `words` of pixel `i` in one of the per-pixel bitset arrays.
    #[inline]
    pub fn row(v: &[u64], i: usize, words: usize) -> &[u64] {
        &v[i * words..(i + 1) * words]
    }

    /// Traces every above-horizon light of pixel `i` (the coarse pixels and pixels with no
    /// voters), keeping blockers when `keep_blockers`.
    pub fn trace_all(&mut self, ctx: &FrameContext, i: usize, keep_blockers: bool) {
        let w = self.words;
        let s = self.surf[i];
        if !s.hit {
            return;
        }
        self.blockers.begin(i);
        if keep_blockers {
            for k in 0..w {
                let mut m = self.above[i * w + k];
                while m != 0 {
                    let j = k * 64 + m.trailing_zeros() as usize;
                    m &= m - 1;
                    match ctx.trace_blocker(&s, j) {
                        Some(t) => self.blockers.push(i, j, t),
                        None => self.vis[i * w + k] |= 1 << (j & 63),
                    }
                }
            }
        } else {
            // Packets of up to PACKET lights from the pixel's point.
            let mut batch = [0u32; PACKET];
            let mut len = 0;
            let vis = &mut self.vis[i * w..(i + 1) * w];
            let mut flush = |batch: &[u32]| {
                let blocked = ctx.trace_packet(&s, batch);
                for (k, &j) in batch.iter().enumerate() {
                    if blocked & (1 << k) == 0 {
                        bits::set(vis, j as usize);
                    }
                }
            };
            bits::for_each(&self.above[i * w..(i + 1) * w], |j| {
                batch[len] = j as u32;
                len += 1;
                if len == PACKET {
                    flush(&batch);
                    len = 0;
                }
            });
            if len > 0 {
                flush(&batch[..len]);
            }
        }
        let above = &self.above[i * w..(i + 1) * w];
        self.traced[i * w..(i + 1) * w].copy_from_slice(above);
        self.rays[i] = bits::count(above);
        self.split[i] = RaySplit {
            every: self.rays[i],
            ..RaySplit::default()
        };
    }
}

/// Runs shared phase `phase` of the frame's method on one tile: returns the pixels it
/// evaluated, for the frame's lattice.
pub fn render_shared(
    ctx: &FrameContext,
    tile: Rect,
    work: &mut TileWork,
    phase: usize,
    lattice: &Lattice,
) -> LatticePatch {
    let region = ctx.predictor.region(ctx, tile, phase);
    work.prepare(ctx, tile, region);
    let mut patch = LatticePatch::default();
    ctx.predictor
        .solve(ctx, tile, work, phase, lattice, &mut patch);
    patch
}

/// Renders one tile (the final phase): the method decides visibility, then (with validation)
/// every query is traced to count mistakes, then the tile is shaded.
pub fn render_tile(
    ctx: &FrameContext,
    tile: Rect,
    work: &mut TileWork,
    lattice: &Lattice,
) -> TileResult {
    let phase = ctx.predictor.shared_phases();
    let region = ctx.predictor.region(ctx, tile, phase);
    debug_assert!(region.intersect(&tile) == tile);
    work.prepare(ctx, tile, region);
    let mut unused = LatticePatch::default();
    ctx.predictor
        .solve(ctx, tile, work, phase, lattice, &mut unused);
    count_work(work);
    shade(ctx, work)
}

/// Queries and rays of the tile's pixels, and the halo's work apart.
fn count_work(work: &mut TileWork) {
    let (r, t, w) = (work.region, work.tile, work.words);
    let mut c = Counts::default();
    for y in r.y0..r.y1 {
        for x in r.x0..r.x1 {
            let i = r.index(x, y);
            if t.contains(x, y) {
                debug_assert!(work.needed[i], "method left pixel ({x}, {y}) unevaluated");
                c.queries += bits::count(TileWork::row(&work.above, i, w)) as u64;
                c.rays += work.rays[i] as u64;
                let why = work.split[i];
                c.rays_every_light += why.every as u64;
                c.rays_flooded += why.flooded as u64;
                c.flood_fixes += why.fixes as u64;
                if work.temporal[i] {
                    c.temporal_pixels += 1;
                    c.temporal_rays += work.rays[i] as u64;
                }
            } else if work.needed[i] {
                c.halo_pixels += 1;
                c.halo_rays += work.rays[i] as u64;
            }
        }
    }
    work.counts = c;
}

/// Light directions and energies as padded flat arrays (length a multiple of 64, zero lights at
/// the end), so shading runs over 8 lights at a time without bounds checks.
#[derive(Clone, Debug, Default)]
pub struct ShadeLights {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    r: Vec<f32>,
    g: Vec<f32>,
    b: Vec<f32>,
}

impl ShadeLights {
    fn new(lights: &LightSet) -> ShadeLights {
        let n = lights.lights.len().div_ceil(64) * 64;
        let pad = |f: &dyn Fn(&crate::lights::Light) -> f32| {
            let mut v: Vec<f32> = lights.lights.iter().map(f).collect();
            v.resize(n, 0.0);
            v
        };
        ShadeLights {
            x: pad(&|l| l.dir.x),
            y: pad(&|l| l.dir.y),
            z: pad(&|l| l.dir.z),
            r: pad(&|l| l.energy.x),
            g: pad(&|l| l.energy.y),
            b: pad(&|l| l.energy.z),
        }
    }
}

/// For each byte value, its eight bits as 0.0 / 1.0 multipliers, lowest bit first.
const BYTE_MASK: [[f32; 8]; 256] = {
    let mut t = [[0.0f32; 8]; 256];
    let mut v = 0;
    while v < 256 {
        let mut l = 0;
        while l < 8 {
            t[v][l] = ((v >> l) & 1) as f32;
            l += 1;
        }
        v += 1;
    }
    t
};

/// Lambertian shading of `bits`: `B = Σ_j V_j · ρ/π · E_j · (N·ω_j)` over the visible lights
/// (all above the horizon). Eight lights at a time, branch-free within a byte of the bitset
/// (a visibility bit becomes a 0/1 multiplier), into eight partial sums — lane l sums the
/// lights j ≡ l (mod 8) in increasing order — added in a fixed order at the end: the same bits
/// whatever the thread or tile, and several times faster than one light at a time.
#[inline]
fn radiance(ctx: &FrameContext, s: &Surface, bits: &[u64]) -> Vec3 {
    let sl = &ctx.shade_lights;
    assert!(bits.len() * 64 <= sl.x.len());
    #[cfg(target_arch = "x86_64")]
    // SAFETY: the light planes hold every light of `bits` (asserted); AVX2 where detected.
    let lanes = unsafe {
        if crate::simd::has_avx2() {
            radiance_avx2(sl, s.n, bits)
        } else {
            radiance_sse2(sl, s.n, bits)
        }
    };
    #[cfg(not(target_arch = "x86_64"))]
    let lanes = radiance_lanes(sl, s.n, bits);
    let sum = |a: [f32; 8]| ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
    let e = Vec3::new(sum(lanes[0]), sum(lanes[1]), sum(lanes[2]));
    s.albedo * std::f32::consts::FRAC_1_PI * e
}

/// The eight per-lane partial sums (r, g, b) of [`radiance`], one light at a time: the
/// reference the SIMD kernels follow operation for operation.
#[cfg_attr(all(target_arch = "x86_64", not(test)), allow(dead_code))]
fn radiance_lanes(sl: &ShadeLights, n: Vec3, bits: &[u64]) -> [[f32; 8]; 3] {
    let mut acc = [[0.0f32; 8]; 3];
    for (k, &word) in bits.iter().enumerate() {
        let mut w = word;
        let mut base = k * 64;
        while w != 0 {
            let byte = (w & 0xff) as usize;
            if byte != 0 {
                let m = &BYTE_MASK[byte];
                for l in 0..8 {
                    let j = base + l;
                    let c = (n.x * sl.x[j] + n.y * sl.y[j] + n.z * sl.z[j]) * m[l];
                    acc[0][l] += sl.r[j] * c;
                    acc[1][l] += sl.g[j] * c;
                    acc[2][l] += sl.b[j] * c;
                }
            }
            w >>= 8;
            base += 8;
        }
    }
    acc
}

/// [`radiance_lanes`] with SSE2, lanes 0–3 and 4–7 in two registers per channel.
///
/// # Safety
/// The light planes hold at least `bits.len() * 64` lights.
#[cfg(target_arch = "x86_64")]
unsafe fn radiance_sse2(sl: &ShadeLights, n: Vec3, bits: &[u64]) -> [[f32; 8]; 3] {
    use std::arch::x86_64::*;
    let mut out = [[0.0f32; 8]; 3];
    unsafe {
        let (nx, ny, nz) = (_mm_set1_ps(n.x), _mm_set1_ps(n.y), _mm_set1_ps(n.z));
        let mut acc = [_mm_setzero_ps(); 6];
        for (k, &word) in bits.iter().enumerate() {
            let mut w = word;
            let mut base = k * 64;
            while w != 0 {
                let byte = (w & 0xff) as usize;
                if byte != 0 {
                    for h in 0..2 {
                        let j = base + 4 * h;
                        let ld = |v: &[f32]| _mm_loadu_ps(v.as_ptr().add(j));
                        let m = _mm_loadu_ps(BYTE_MASK[byte].as_ptr().add(4 * h));
                        let d = _mm_add_ps(
                            _mm_add_ps(_mm_mul_ps(nx, ld(&sl.x)), _mm_mul_ps(ny, ld(&sl.y))),
                            _mm_mul_ps(nz, ld(&sl.z)),
                        );
                        let c = _mm_mul_ps(d, m);
                        acc[h] = _mm_add_ps(acc[h], _mm_mul_ps(ld(&sl.r), c));
                        acc[2 + h] = _mm_add_ps(acc[2 + h], _mm_mul_ps(ld(&sl.g), c));
                        acc[4 + h] = _mm_add_ps(acc[4 + h], _mm_mul_ps(ld(&sl.b), c));
                    }
                }
                w >>= 8;
                base += 8;
            }
        }
        for ch in 0..3 {
            _mm_storeu_ps(out[ch].as_mut_ptr(), acc[2 * ch]);
            _mm_storeu_ps(out[ch].as_mut_ptr().add(4), acc[2 * ch + 1]);
        }
    }
    out
}

/// [`radiance_lanes`] with AVX2 (no FMA), eight lanes in one register per channel.
///
/// # Safety
/// As [`radiance_sse2`], on a CPU with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn radiance_avx2(sl: &ShadeLights, n: Vec3, bits: &[u64]) -> [[f32; 8]; 3] {
    use std::arch::x86_64::*;
    let mut out = [[0.0f32; 8]; 3];
    unsafe {
        let (nx, ny, nz) = (
            _mm256_set1_ps(n.x),
            _mm256_set1_ps(n.y),
            _mm256_set1_ps(n.z),
        );
        let mut acc = [_mm256_setzero_ps(); 3];
        for (k, &word) in bits.iter().enumerate() {
            let mut w = word;
            let mut base = k * 64;
            while w != 0 {
                let byte = (w & 0xff) as usize;
                if byte != 0 {
                    let ld = |v: &[f32]| _mm256_loadu_ps(v.as_ptr().add(base));
                    let m = _mm256_loadu_ps(BYTE_MASK[byte].as_ptr());
                    let d = _mm256_add_ps(
                        _mm256_add_ps(_mm256_mul_ps(nx, ld(&sl.x)), _mm256_mul_ps(ny, ld(&sl.y))),
                        _mm256_mul_ps(nz, ld(&sl.z)),
                    );
                    let c = _mm256_mul_ps(d, m);
                    acc[0] = _mm256_add_ps(acc[0], _mm256_mul_ps(ld(&sl.r), c));
                    acc[1] = _mm256_add_ps(acc[1], _mm256_mul_ps(ld(&sl.g), c));
                    acc[2] = _mm256_add_ps(acc[2], _mm256_mul_ps(ld(&sl.b), c));
                }
                w >>= 8;
                base += 8;
            }
        }
        for ch in 0..3 {
            _mm256_storeu_ps(out[ch].as_mut_ptr(), acc[ch]);
        }
    }
    out
}

/// Sets `out`'s bits for the lights above the horizon of normal `n` (`n·ω > 0`, the products
/// summed in glam's dot order `(x + y) + z`), four or eight lights per instruction.
#[inline]
fn above_horizon(sl: &ShadeLights, n: Vec3, out: &mut [u64]) {
    let lights = out.len() * 64;
    let (x, y, z) = (&sl.x[..lights], &sl.y[..lights], &sl.z[..lights]);
    #[cfg(target_arch = "x86_64")]
    {
        if crate::simd::has_avx2() {
            // SAFETY: AVX2 was detected; the slices hold `out.len() * 64` lights.
            unsafe { above_horizon_avx2(x, y, z, n, out) };
        } else {
            // SAFETY: as above (SSE2 is part of x86_64).
            unsafe { above_horizon_sse2(x, y, z, n, out) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    for (k, word) in out.iter_mut().enumerate() {
        let mut bits = 0u64;
        for l in 0..64 {
            let j = k * 64 + l;
            let d = n.x * x[j] + n.y * y[j] + n.z * z[j];
            bits |= u64::from(d > 0.0) << l;
        }
        *word = bits;
    }
}

/// # Safety
/// `x`, `y`, `z` hold at least `out.len() * 64` values.
#[cfg(target_arch = "x86_64")]
unsafe fn above_horizon_sse2(x: &[f32], y: &[f32], z: &[f32], n: Vec3, out: &mut [u64]) {
    use std::arch::x86_64::*;
    unsafe {
        let (nx, ny, nz) = (_mm_set1_ps(n.x), _mm_set1_ps(n.y), _mm_set1_ps(n.z));
        let zero = _mm_setzero_ps();
        for (k, word) in out.iter_mut().enumerate() {
            let mut bits = 0u64;
            for g in 0..16 {
                let j = k * 64 + g * 4;
                let d = _mm_add_ps(
                    _mm_add_ps(
                        _mm_mul_ps(nx, _mm_loadu_ps(x.as_ptr().add(j))),
                        _mm_mul_ps(ny, _mm_loadu_ps(y.as_ptr().add(j))),
                    ),
                    _mm_mul_ps(nz, _mm_loadu_ps(z.as_ptr().add(j))),
                );
                bits |= (_mm_movemask_ps(_mm_cmpgt_ps(d, zero)) as u64) << (g * 4);
            }
            *word = bits;
        }
    }
}

/// # Safety
/// As [`above_horizon_sse2`], on a CPU with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn above_horizon_avx2(x: &[f32], y: &[f32], z: &[f32], n: Vec3, out: &mut [u64]) {
    use std::arch::x86_64::*;
    unsafe {
        let (nx, ny, nz) = (
            _mm256_set1_ps(n.x),
            _mm256_set1_ps(n.y),
            _mm256_set1_ps(n.z),
        );
        let zero = _mm256_setzero_ps();
        for (k, word) in out.iter_mut().enumerate() {
            let mut bits = 0u64;
            for g in 0..8 {
                let j = k * 64 + g * 8;
                let d = _mm256_add_ps(
                    _mm256_add_ps(
                        _mm256_mul_ps(nx, _mm256_loadu_ps(x.as_ptr().add(j))),
                        _mm256_mul_ps(ny, _mm256_loadu_ps(y.as_ptr().add(j))),
                    ),
                    _mm256_mul_ps(nz, _mm256_loadu_ps(z.as_ptr().add(j))),
                );
                let m = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(d, zero)) as u64;
                bits |= m << (g * 8);
            }
            *word = bits;
        }
    }
}

fn shade(ctx: &FrameContext, work: &mut TileWork) -> TileResult {
    let tile = work.tile;
    let w = work.words;
    let n = tile.area();
    let mut beauty = Vec::with_capacity(n);
    let mut rays = Vec::with_capacity(n);
    let mut visible = Vec::with_capacity(n);
    let mut wrong = ctx.validate.then(|| Vec::with_capacity(n));
    let mut reference = ctx.validate.then(|| Vec::with_capacity(n));
    let mut truth = vec![0u64; w];
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let i = work.region.index(x, y);
            let s = work.surf[i];
            rays.push(work.rays[i] as f32);
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
            let vis = TileWork::row(&work.vis, i, w);
            let above = TileWork::row(&work.above, i, w);
            let lit = radiance(ctx, &s, vis);
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
                let traced = TileWork::row(&work.traced, i, w);
                for k in 0..w {
                    work.counts.wrong_traced +=
                        ((vis[k] ^ truth[k]) & above[k] & traced[k]).count_ones() as u64;
                }
                let (mut wv, mut wb) = (0u64, 0u64);
                for k in 0..w {
                    wv += (vis[k] & !truth[k] & above[k]).count_ones() as u64;
                    wb += (!vis[k] & truth[k] & above[k]).count_ones() as u64;
                }
                work.counts.wrong_visible += wv;
                work.counts.wrong_blocked += wb;
                work.counts.wrong_pixels += u64::from(wv + wb > 0);
                wr.push((wv + wb) as f32);
                rf.push(radiance(ctx, &s, &truth).to_array());
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
        counts: work.counts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 200 pseudo-random lights (some below any horizon, unequal energies), padded as for a
    /// frame, and random normals and visibility words.
    fn setup() -> (ShadeLights, Vec<(Vec3, [u64; 4])>) {
        let mut seed = 99u32;
        let mut rnd = move || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let n = 200;
        let pad = |v: Vec<f32>| {
            let mut v = v;
            v.resize(256, 0.0);
            v
        };
        let dirs: Vec<Vec3> = (0..n)
            .map(|_| (Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0).normalize_or(Vec3::Y))
            .collect();
        let energy: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rnd(), rnd(), rnd()) * 3.0)
            .collect();
        let sl = ShadeLights {
            x: pad(dirs.iter().map(|d| d.x).collect()),
            y: pad(dirs.iter().map(|d| d.y).collect()),
            z: pad(dirs.iter().map(|d| d.z).collect()),
            r: pad(energy.iter().map(|e| e.x).collect()),
            g: pad(energy.iter().map(|e| e.y).collect()),
            b: pad(energy.iter().map(|e| e.z).collect()),
        };
        let mut cases = Vec::new();
        for _ in 0..300 {
            let nrm = (Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0).normalize_or(Vec3::Z);
            let mut bits = [0u64; 4];
            for (j, d) in dirs.iter().enumerate() {
                if nrm.dot(*d) > 0.0 && rnd() < 0.7 {
                    bits[j / 64] |= 1 << (j % 64);
                }
            }
            cases.push((nrm, bits));
        }
        (sl, cases)
    }

    #[test]
    fn shading_kernels_give_the_reference_lanes_bit_for_bit() {
        let (sl, cases) = setup();
        for (n, bits) in &cases {
            let reference = radiance_lanes(&sl, *n, bits);
            assert!(reference[0].iter().any(|&v| v != 0.0));
            #[cfg(target_arch = "x86_64")]
            {
                let bitwise = |a: [[f32; 8]; 3]| a.map(|c| c.map(f32::to_bits));
                // SAFETY: the planes hold 256 lights, `bits` covers 256.
                let sse = unsafe { radiance_sse2(&sl, *n, bits) };
                assert_eq!(bitwise(sse), bitwise(reference));
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: as above, and AVX2 was detected.
                    let avx = unsafe { radiance_avx2(&sl, *n, bits) };
                    assert_eq!(bitwise(avx), bitwise(reference));
                }
            }
        }
    }

    #[test]
    fn horizon_kernels_agree_with_the_dot_product() {
        let (sl, cases) = setup();
        for (n, _) in &cases {
            let mut reference = [0u64; 4];
            for j in 0..256 {
                let d = Vec3::new(sl.x[j], sl.y[j], sl.z[j]);
                if n.dot(d) > 0.0 {
                    reference[j / 64] |= 1 << (j % 64);
                }
            }
            let mut out = [0u64; 4];
            above_horizon(&sl, *n, &mut out);
            assert_eq!(out, reference);
            #[cfg(target_arch = "x86_64")]
            {
                let (x, y, z) = (&sl.x[..], &sl.y[..], &sl.z[..]);
                // SAFETY: the planes hold 256 lights.
                unsafe { above_horizon_sse2(x, y, z, *n, &mut out) };
                assert_eq!(out, reference);
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: as above, and AVX2 was detected.
                    unsafe { above_horizon_avx2(x, y, z, *n, &mut out) };
                    assert_eq!(out, reference);
                }
            }
        }
    }
}
