//! A frame as its tiles see it: the posed scene and its BVH, the camera, the lights and the
//! map, shared read-only across threads; primary rays ([`FrameContext::surface`]) and shadow
//! rays ([`FrameContext::trace`] and its packet and blocker forms) from a surface point.

use glam::Vec3;

use crate::accel::{Accel, PACKET};
use crate::camera::Camera;
use crate::envmap::EnvMap;
use crate::glossy::Glossy;
use crate::lights::LightSet;
use crate::samples::Samples;
use crate::scene::{MaterialSample, Scene, footprint_width};
use crate::shade::ShadeLights;

/// What a primary ray found at a pixel centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Surface {
    /// Hit point.
    pub p: Vec3,
    /// Unit shading normal (after the normal map), on the side facing the camera: it decides
    /// which lights are above the horizon, and shades.
    pub n: Vec3,
    /// Unit geometric normal, on the side facing the camera: shadow rays start off it.
    pub ng: Vec3,
    /// Linear RGB albedo: the material's base colour there (texture and vertex colour
    /// included).
    pub albedo: Vec3,
    /// The primary ray's unit direction: where a background sample looks up the map, and the
    /// view direction (its opposite) for specular.
    pub dir: Vec3,
    /// False for background pixels (the ray left the scene).
    pub hit: bool,
    /// The rest of the material there: metallic, roughness, occlusion, emission, specular.
    pub material: MaterialSample,
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
    /// (see [`crate::shade`]).
    pub shade_lights: ShadeLights,
    /// Shadow-ray origin offset along the geometric normal (scene units).
    pub shadow_eps: f32,
    /// Where the pixels' samples lie. The tiles and the methods address samples: sample
    /// (x, y) is stratum (x mod k, y mod k) of pixel (x div k, y div k); with one sample per
    /// pixel, samples are pixels.
    pub samples: Samples,
    /// Texture filtering: the share of its pixel's width one sample stands for, or 0 for
    /// point-sampled textures (level-0 bilinear lookups). Set by
    /// [`with_samples`](Self::with_samples), see [`texture_footprint`].
    pub texture_footprint: f32,
    /// The prefiltered environment for lobes too narrow for the lights (none: the lights
    /// alone); see [`with_glossy`](Self::with_glossy).
    pub glossy: Option<&'a Glossy>,
}

impl<'a> FrameContext<'a> {
    pub fn new(
        scene: &'a Scene,
        accel: &'a Accel,
        camera: Camera,
        lights: &'a LightSet,
        env: &'a EnvMap,
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
            samples: Samples::one(),
            texture_footprint: 0.0,
            glossy: None,
        }
    }

    /// This context with glossy lobes too narrow for the lights shaded from `glossy`.
    pub fn with_glossy(self, glossy: Option<&'a Glossy>) -> FrameContext<'a> {
        FrameContext { glossy, ..self }
    }

    /// This context with the pixels' samples at `samples`, and textures filtered to what one
    /// of them covers ([`texture_footprint`]).
    pub fn with_samples(self, samples: Samples) -> FrameContext<'a> {
        FrameContext {
            texture_footprint: texture_footprint(&samples),
            samples,
            ..self
        }
    }

    /// The unit direction of the primary ray of sample (x, y).
    #[inline]
    pub fn sample_dir(&self, x: u32, y: u32) -> Vec3 {
        let k = self.samples.k;
        let (px, py) = (x / k, y / k);
        let (dx, dy) = self.samples.offset(px, py, x % k, y % k);
        self.camera.ray_dir_at(px, py, dx, dy)
    }

    /// Number of lights.
    pub fn light_count(&self) -> usize {
        self.light_dir.len()
    }

    /// Number of u64 words in one pixel's visibility bitset.
    pub fn words(&self) -> usize {
        self.light_count().div_ceil(64)
    }

    /// The surface seen by sample (x, y) (with one sample per pixel: through the centre of
    /// pixel (x, y)).
    #[inline]
    pub fn surface(&self, x: u32, y: u32) -> Surface {
        let dir = self.sample_dir(x, y);
        let Some(hit) = self.accel.intersect(self.camera.position, dir) else {
            return Surface {
                dir,
                ..Surface::default()
            };
        };
        let tri = hit.tri as usize;
        let [p0, p1, p2] = self.scene.triangle(tri);
        let p = p0 * (1.0 - hit.u - hit.v) + p1 * hit.u + p2 * hit.v;
        let mut ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let bary = (hit.u, hit.v);
        let footprint = if self.texture_footprint > 0.0 {
            let angle = self.camera.pixel_angle(dir) * self.texture_footprint;
            footprint_width(hit.t, angle, ng.dot(dir))
        } else {
            0.0
        };
        // The material there, and the interpolated normal bent by its normal map (in the
        // mesh's own orientation, before either normal turns to the camera).
        let at = self
            .scene
            .material_at(tri, bary, footprint, self.scene.shading_normal(tri, bary));
        let mut n = at.normal;
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
            albedo: at.base_color,
            dir,
            hit: true,
            material: at.sample,
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

/// The share of its pixel's width that one sample's texture lookup filters over, as pbrt-v4
/// scales its camera rays' differentials: `max(1/8, 1/k)` for `k × k` samples per pixel (the
/// samples together cover the pixel; past 64 of them, a sample's own filter stops shrinking
/// and the samples' mean does the rest).
///
/// One sample per pixel gives 0: textures stay point-sampled (level-0 bilinear, as before mip
/// pyramids existed), so every frame rendered with one sample per pixel — every frame before
/// `--spp`, textured or not — stays bit for bit what it was. That is a choice, not a
/// necessity: the golden renders have no textured surface, so they would not have caught a
/// change; filtering at one sample too would remove aliasing there as well, at the price of
/// changing existing textured frames. Filtering is what more samples per pixel call for: a
/// point-sampled texture keeps aliasing until the samples alone resolve every texel.
pub fn texture_footprint(samples: &Samples) -> f32 {
    if samples.k <= 1 {
        0.0
    } else {
        (1.0 / samples.k as f32).max(1.0 / 8.0)
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
