//! Rendering one tile of one frame: primary rays, shadow visibility (by the chosen
//! [`Predictor`]), Lambertian shading (ALGORITHM.md §2).

use glam::Vec3;

use crate::accel::Accel;
use crate::camera::Camera;
use crate::envmap::EnvMap;
use crate::lights::LightSet;
use crate::output::stats::Counts;
use crate::predict::Predictor;
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
    /// Light directions and energies as flat arrays for the per-pixel loops.
    pub light_dir: Vec<Vec3>,
    pub light_energy: Vec<Vec3>,
    /// Shadow-ray origin offset along the geometric normal (scene units).
    pub shadow_eps: f32,
    pub predictor: &'a dyn Predictor,
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
            light_energy: lights.lights.iter().map(|l| l.energy).collect(),
            shadow_eps: shadow_epsilon(scene),
            predictor,
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
        let [i0, i1, i2] = self.scene.triangles[tri];
        let (p0, p1, p2) = (
            self.scene.positions[i0 as usize],
            self.scene.positions[i1 as usize],
            self.scene.positions[i2 as usize],
        );
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

    /// Like [`trace`](Self::trace), returning the blocker point when the light is blocked.
    #[inline]
    pub fn trace_blocker(&self, s: &Surface, j: usize) -> Option<Vec3> {
        self.accel
            .blocker(s.p + s.ng * self.shadow_eps, self.light_dir[j])
    }

    /// Is light `j` above the horizon of `s`? Only such pairs are shadow queries [paper].
    #[inline]
    pub fn above(&self, s: &Surface, j: usize) -> bool {
        s.n.dot(self.light_dir[j]) > 0.0
    }
}

/// The shadow-ray offset: large enough to leave the surface's own triangle at the scene's
/// float precision, small against any feature. Relative to the scene's size so the same
/// rule serves a 15 cm bunny and a 6 m shapes scene.
fn shadow_epsilon(scene: &Scene) -> f32 {
    if scene.positions.is_empty() {
        return 1e-4;
    }
    let (lo, hi) = scene.bounds();
    let diag = (hi - lo).length();
    let reach = lo.abs().max(hi.abs()).max_element();
    (diag * 2e-5).max(reach * 1e-6).max(1e-7)
}

/// Per-tile working buffers, reused across tiles by one thread. Flat arrays only.
#[derive(Default)]
pub struct TileWork {
    /// The pixels this tile outputs.
    pub tile: Rect,
    /// The pixels the buffers cover: the tile plus whatever halo its method reads.
    pub region: Rect,
    /// Surfaces over `region`.
    pub surf: Vec<Surface>,
    /// Visibility bitsets over `region`, `words` u64 per pixel, bit j set = light j visible.
    pub vis: Vec<u64>,
    pub words: usize,
    /// Shadow rays traced per pixel over `region`.
    pub rays: Vec<u32>,
    /// Counts for the tile's own pixels (halo work counted apart).
    pub counts: Counts,
}

impl TileWork {
    /// Prepares the buffers for `tile` reading `region` (⊇ tile) and computes its surfaces.
    pub fn prepare(&mut self, ctx: &FrameContext, tile: Rect, region: Rect) {
        self.tile = tile;
        self.region = region;
        self.words = ctx.words();
        let n = region.area();
        self.surf.clear();
        self.surf.reserve(n);
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                self.surf.push(ctx.surface(x, y));
            }
        }
        self.vis.clear();
        self.vis.resize(n * self.words, 0);
        self.rays.clear();
        self.rays.resize(n, 0);
        self.counts = Counts::default();
    }

    /// The bitset of pixel `i` (index into `region`).
    #[inline]
    pub fn vis_of(&self, i: usize) -> &[u64] {
        &self.vis[i * self.words..(i + 1) * self.words]
    }

    #[inline]
    pub fn vis_of_mut(&mut self, i: usize) -> &mut [u64] {
        &mut self.vis[i * self.words..(i + 1) * self.words]
    }
}

/// A finished tile: beauty and AOVs for the tile's pixels, and its counts.
#[derive(Clone, Debug)]
pub struct TileResult {
    pub rect: Rect,
    /// Linear RGB radiance.
    pub beauty: Vec<[f32; 3]>,
    /// Shadow rays traced per pixel.
    pub rays: Vec<f32>,
    /// Fraction of the above-horizon lights that are visible (0 for background pixels).
    pub visible: Vec<f32>,
    pub counts: Counts,
}

/// Renders one tile: surfaces, visibility by the context's predictor, shading.
pub fn render_tile(ctx: &FrameContext, tile: Rect, work: &mut TileWork) -> TileResult {
    let region = ctx.predictor.region(ctx, tile);
    work.prepare(ctx, tile, region);
    ctx.predictor.solve(ctx, tile, work);
    shade(ctx, work)
}

/// Lambertian shading from the visibility bits:
/// `B = Σ_j V_j · ρ/π · E_j · max(0, N·ω_j)`, summed in light order (deterministic).
fn shade(ctx: &FrameContext, work: &TileWork) -> TileResult {
    let tile = work.tile;
    let n = tile.area();
    let mut beauty = Vec::with_capacity(n);
    let mut rays = Vec::with_capacity(n);
    let mut visible = Vec::with_capacity(n);
    let inv_pi = std::f32::consts::FRAC_1_PI;
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let i = work.region.index(x, y);
            let s = &work.surf[i];
            rays.push(work.rays[i] as f32);
            if !s.hit {
                let r = ctx.env.radiance(ctx.camera.ray_dir(x, y));
                beauty.push(r.to_array());
                visible.push(0.0);
                continue;
            }
            let bits = work.vis_of(i);
            let mut e = Vec3::ZERO;
            let (mut above, mut lit) = (0u32, 0u32);
            for j in 0..ctx.light_count() {
                let c = s.n.dot(ctx.light_dir[j]);
                if c > 0.0 {
                    above += 1;
                    if bits[j >> 6] >> (j & 63) & 1 == 1 {
                        lit += 1;
                        e += ctx.light_energy[j] * c;
                    }
                }
            }
            beauty.push((s.albedo * inv_pi * e).to_array());
            visible.push(if above > 0 {
                lit as f32 / above as f32
            } else {
                0.0
            });
        }
    }
    TileResult {
        rect: tile,
        beauty,
        rays,
        visible,
        counts: work.counts,
    }
}
