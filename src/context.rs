//! A frame as its tiles see it: the posed scene and its BVH, the camera, the lights and the
//! map, shared read-only across threads; primary rays ([`FrameContext::surface`]) and shadow
//! rays ([`FrameContext::trace`] and its packet and blocker forms) from a surface point.

use glam::Vec3;

use crate::accel::{Accel, Hit, PACKET};
use crate::background::{Backdrop, ENVIRONMENT};
use crate::camera::Camera;
use crate::envmap::EnvMap;
use crate::glossy::Glossy;
use crate::lights::LightSet;
use crate::lights::punctual::SHADOW_END;
use crate::offset::{hit_point, offset_origin};
use crate::samples::Samples;
use crate::scene::{AlphaTest, MaterialSample, Scene, coverage_threshold, footprint_width};
use crate::shade::ShadeLights;

/// What a primary ray found at a pixel centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Surface {
    /// Hit point.
    pub p: Vec3,
    /// Unit shading normal (after the normal map), on the side facing the camera: it decides
    /// which lights are above the horizon, and shades.
    pub n: Vec3,
    /// Unit normal of the geometric horizon, on the side facing the camera: no light below it
    /// is received, whatever the shading normal. The facet's normal; with the terminator
    /// offset ([`FrameContext::terminator_offset`]) the smooth surface's, the interpolated
    /// vertex normal (before the normal map), whose lights past the facet's plane the lifted
    /// shadow rays then decide.
    pub ng: Vec3,
    /// Where shadow rays start: `p` moved along `ng` by a bound on its floating-point error
    /// ([`crate::offset`]), so no ray finds the surface it leaves, at any scale.
    pub origin: Vec3,
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
    /// A shadow catcher: it shows only the shadows it receives (see the `catcher` module).
    pub catcher: bool,
    /// The index of its material in the scene: at the pixel shading rate, samples of another
    /// material are shaded apart.
    pub material_index: u32,
    /// The triangle hit: its object's name for ID mattes (`crate::cryptomatte`).
    pub tri: u32,
}

/// Everything a tile needs about its frame: shared, read-only, across threads.
pub struct FrameContext<'a> {
    pub scene: &'a Scene,
    pub accel: &'a Accel,
    pub camera: Camera,
    pub lights: &'a LightSet,
    pub env: &'a EnvMap,
    /// What rays that leave the scene see (`[render] background`; the environment unless
    /// [`with_backdrop`](Self::with_backdrop) says otherwise).
    pub backdrop: &'a Backdrop,
    /// The directional lights' directions as a flat array, for shadow rays and warping (light
    /// j < `light_dir.len()`; the point and spot lights come after them, see
    /// [`shadow_ray`](Self::shadow_ray)).
    pub light_dir: Vec<Vec3>,
    /// The point and spot lights' bits (every light's bitset width): lights whose direction
    /// differs per pixel.
    pub point_bits: Vec<u64>,
    /// The lights for the horizon test and shading, padded with zero lights to whole words
    /// (see [`crate::shade`]).
    pub shade_lights: ShadeLights,
    /// Where the pixels' samples lie. The tiles and the methods address samples: sample
    /// (x, y) is stratum (x mod k, y mod k) of pixel (x div k, y div k); with one sample per
    /// pixel, samples are pixels.
    pub samples: Samples,
    /// Texture filtering: the share of its pixel's width one sample stands for, or 0 for
    /// point-sampled textures (level-0 bilinear lookups). Set by
    /// [`with_samples`](Self::with_samples), see [`texture_footprint`].
    pub texture_footprint: f32,
    /// Whether shadow rays leave from their point lifted onto the smooth surface of the vertex
    /// normals ([`crate::offset::terminator_lift`]); see
    /// [`with_terminator_offset`](Self::with_terminator_offset).
    pub terminator_offset: bool,
    /// The prefiltered environment for lobes too narrow for the lights (none: the lights
    /// alone); see [`with_glossy`](Self::with_glossy).
    pub glossy: Option<&'a Glossy>,
    /// The environment's turn this frame beyond the map's own rotation (`[motion] kind =
    /// "environment"`), as (sin, cos): the background turns with the lights.
    pub env_turn: Option<(f32, f32)>,
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
            backdrop: &ENVIRONMENT,
            light_dir: lights.lights.iter().map(|l| l.dir).collect(),
            point_bits: {
                let mut b = vec![0u64; lights.len().div_ceil(64)];
                for j in lights.lights.len()..lights.len() {
                    crate::bits::set(&mut b, j);
                }
                b
            },
            shade_lights: ShadeLights::new(lights),
            samples: Samples::one(),
            texture_footprint: 0.0,
            terminator_offset: false,
            glossy: None,
            env_turn: None,
        }
    }

    /// This context with shadow rays leaving from the flat triangles (`false`, the default) or
    /// from the smooth surface of the vertex normals (`true`).
    pub fn with_terminator_offset(self, terminator_offset: bool) -> FrameContext<'a> {
        FrameContext {
            terminator_offset,
            ..self
        }
    }

    /// This context with glossy lobes too narrow for the lights shaded from `glossy`.
    pub fn with_glossy(self, glossy: Option<&'a Glossy>) -> FrameContext<'a> {
        FrameContext { glossy, ..self }
    }

    /// This context with the environment turned by `degrees` about the up axis beyond the
    /// map's rotation, as its lights are ([`LightSet::turned`](crate::lights::LightSet::turned)).
    pub fn with_environment_turn(self, degrees: Option<f32>) -> FrameContext<'a> {
        FrameContext {
            env_turn: degrees.map(|d| libm::sincosf(d.to_radians())),
            ..self
        }
    }

    /// World direction `dir` in the frame of the map before this frame's turn
    /// ([`with_environment_turn`](Self::with_environment_turn)): where to look the map up.
    #[inline]
    pub fn unturned(&self, dir: Vec3) -> Vec3 {
        match self.env_turn {
            None => dir,
            Some((s, c)) => crate::envmap::rotate_y(dir, (-s, c)),
        }
    }

    /// The environment's radiance seen along unit direction `dir` (a background sample):
    /// the map turned as this frame's lights are.
    #[inline]
    pub fn background(&self, dir: Vec3) -> Vec3 {
        self.backdrop.radiance(self.env, self.unturned(dir))
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

    /// This context with rays that leave the scene seeing `backdrop`.
    pub fn with_backdrop(self, backdrop: &'a Backdrop) -> FrameContext<'a> {
        FrameContext { backdrop, ..self }
    }

    /// The unit direction of the primary ray of sample (x, y).
    #[inline]
    pub fn sample_dir(&self, x: u32, y: u32) -> Vec3 {
        let k = self.samples.k;
        let (px, py) = (x / k, y / k);
        let (dx, dy) = self.samples.offset(px, py, x % k, y % k);
        self.camera.ray_dir_at(px, py, dx, dy)
    }

    /// Number of lights: directional, point and spot.
    pub fn light_count(&self) -> usize {
        self.lights.len()
    }

    /// Whether the scene file placed point or spot lights.
    #[inline]
    pub fn has_points(&self) -> bool {
        !self.lights.points.is_empty()
    }

    /// The shadow ray from `s` towards light `j`: origin (off the surface along its geometric
    /// normal), unit direction, and end — ∞ for a directional light, just short of a point or
    /// spot light ([`crate::lights::punctual::SHADOW_END`]).
    #[inline]
    pub fn shadow_ray(&self, s: &Surface, j: usize) -> (Vec3, Vec3, f32) {
        let origin = s.origin;
        match self.light_dir.get(j) {
            Some(&dir) => (origin, dir, f32::INFINITY),
            None => {
                let to = self.lights.points[j - self.light_dir.len()].position - origin;
                let dist = to.length();
                (origin, to / dist, dist * (1.0 - SHADOW_END))
            }
        }
    }

    /// Sets the bits of the point and spot lights that reach surface `s` from above its
    /// horizon (within range and cone; [`crate::lights::PointLight::at`]) in `row` (one pixel's bitset),
    /// clearing the others' bits.
    #[inline]
    pub fn point_lights_above(&self, s: &Surface, row: &mut [u64]) {
        let first = self.light_dir.len();
        for (k, l) in self.lights.points.iter().enumerate() {
            let up = l.at(s.p).is_some_and(|i| s.n.dot(i.dir) > 0.0);
            if up {
                crate::bits::set(row, first + k);
            } else {
                crate::bits::clear(row, first + k);
            }
        }
    }

    /// Number of u64 words in one pixel's visibility bitset.
    pub fn words(&self) -> usize {
        self.light_count().div_ceil(64)
    }

    /// The surface seen by sample (x, y) (with one sample per pixel: through the centre of
    /// pixel (x, y)).
    #[inline]
    pub fn surface(&self, x: u32, y: u32) -> Surface {
        let (dir, cut) = self.camera_ray(x, y);
        let hit = self.accel.intersect_cut(self.camera.position, dir, &cut);
        self.surface_hit(dir, hit)
    }

    /// The surfaces seen by the samples of pixel (px, py) in strata `strata` (at most
    /// [`PACKET`]; stratum s is column s mod k, row s div k), written to `surf[index[r]]` for
    /// `strata[r]`: each what [`surface`](Self::surface) gives, bit for bit, their primary rays
    /// traced together ([`Accel::intersect_packet_cut`]). Written in place: a surface copied
    /// on its way cost a twentieth of a frame without shadows.
    #[inline]
    pub fn surfaces(
        &self,
        (px, py): (u32, u32),
        strata: &[u32],
        surf: &mut [Surface],
        index: &[usize],
    ) {
        let (n, k) = (strata.len(), self.samples.k);
        let mut dirs = [Vec3::ZERO; PACKET];
        let mut cuts: [AlphaTest; PACKET] =
            std::array::from_fn(|_| AlphaTest::camera(self.scene, 0.0));
        for (r, &s) in strata.iter().enumerate() {
            let (i, j) = (s % k, s / k);
            let (dx, dy) = self.samples.offset(px, py, i, j);
            dirs[r] = self.camera.ray_dir_at(px, py, dx, dy);
            cuts[r] = AlphaTest::camera(self.scene, coverage_threshold(px, py, i, j, k));
        }
        let mut hits = [None; PACKET];
        self.accel.intersect_packet_cut(
            self.camera.position,
            &dirs[..n],
            &cuts[..n],
            &mut hits[..n],
        );
        for r in 0..n {
            self.surface_into(dirs[r], hits[r], &mut surf[index[r]]);
        }
    }

    /// The primary ray of sample (x, y): its unit direction, and the cut-out test of its
    /// coverage threshold.
    #[inline]
    fn camera_ray(&self, x: u32, y: u32) -> (Vec3, AlphaTest<'a>) {
        let dir = self.sample_dir(x, y);
        let k = self.samples.k;
        let coverage = coverage_threshold(x / k, y / k, x % k, y % k, k);
        (dir, AlphaTest::camera(self.scene, coverage))
    }

    /// The surface a primary ray along `dir` found at `hit` (none: the background).
    #[inline]
    fn surface_hit(&self, dir: Vec3, hit: Option<Hit>) -> Surface {
        let mut s = Surface::default();
        self.surface_into(dir, hit, &mut s);
        s
    }

    /// [`surface_hit`](Self::surface_hit) written into `out`, field by field.
    #[inline(always)]
    fn surface_into(&self, dir: Vec3, hit: Option<Hit>, out: &mut Surface) {
        let Some(hit) = hit else {
            *out = Surface {
                dir,
                ..Surface::default()
            };
            return;
        };
        let tri = hit.tri as usize;
        let [p0, p1, p2] = self.scene.triangle(tri);
        let (p, err) = hit_point([p0, p1, p2], hit.u, hit.v);
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
        let smooth = self.scene.shading_normal(tri, bary);
        let at = self.scene.material_at(tri, bary, footprint, smooth);
        let mut n = at.normal;
        // Shade the side the camera sees: both normals turn towards the viewer.
        let side = if ng.dot(dir) > 0.0 {
            ng = -ng;
            n = -n;
            -1.0
        } else {
            1.0
        };
        // The terminator offset: shadow rays leave from the smooth surface, and lights are
        // received down to its horizon, not the facet's (whose steps draw a faceted
        // terminator on a coarse mesh) — where it leans less than 90° from the facet.
        let (from, horizon) = if self.terminator_offset {
            let normals = self.scene.corner_normals(tri);
            let lift = crate::offset::terminator_lift(p, [p0, p1, p2], normals, bary, side, ng);
            let smooth = smooth * side;
            (p + lift, if smooth.dot(ng) > 0.0 { smooth } else { ng })
        } else {
            (p, ng)
        };
        // An interpolated normal pointing away from the visible side (back-to-back faces in
        // scanned meshes) would light the surface from behind; the facet's own normal will not.
        if n.dot(ng) <= 0.0 || !n.is_finite() {
            n = ng;
        }
        *out = Surface {
            p,
            n,
            ng: horizon,
            origin: offset_origin(from, err, ng),
            albedo: at.base_color,
            dir,
            hit: true,
            material: at.sample,
            catcher: self.scene.is_catcher(tri),
            material_index: self.scene.tri_material[tri],
            tri: hit.tri,
        };
    }

    /// Traces the shadow ray from `s` towards light `j`: true when the light is visible.
    #[inline]
    pub fn trace(&self, s: &Surface, j: usize) -> bool {
        let (origin, dir, end) = self.shadow_ray(s, j);
        crate::raydump::record(origin, dir);
        !self
            .accel
            .occluded_within(origin, dir, end, &AlphaTest::shadow(self.scene))
    }

    /// [`trace`](Self::trace) for several lights at once (at most [`PACKET`]): bit k of the
    /// result is set when light `lights[k]` is blocked. One packet from the pixel's point,
    /// the same answers as tracing each light alone.
    #[inline]
    pub fn trace_packet(&self, s: &Surface, lights: &[u32]) -> u32 {
        let mut dirs = [Vec3::ZERO; PACKET];
        let mut ends = [f32::INFINITY; PACKET];
        for ((d, e), &j) in dirs.iter_mut().zip(&mut ends).zip(lights) {
            (_, *d, *e) = self.shadow_ray(s, j as usize);
        }
        crate::raydump::record_packet(s.origin, &dirs[..lights.len()]);
        self.accel.occluded_packet_within(
            s.origin,
            &dirs[..lights.len()],
            &ends,
            &AlphaTest::shadow(self.scene),
        )
    }

    /// Like [`trace`](Self::trace), returning the distance from the ray's origin to a blocker
    /// when the light is blocked (the blocker point is `s.origin + t·ω_j`).
    #[inline]
    pub fn trace_blocker(&self, s: &Surface, j: usize) -> Option<f32> {
        let (origin, dir, end) = self.shadow_ray(s, j);
        crate::raydump::record(origin, dir);
        self.accel
            .blocker_distance_within(origin, dir, end, &AlphaTest::shadow(self.scene))
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
