//! Coverage: glTF's `alphaMode` and the base colour alpha it reads (factor × base colour
//! texture's alpha × `COLOR_0`'s alpha), and the alpha test the BVH asks at a hit on a cut-out
//! triangle ([`AlphaTest`]).
//!
//! - `OPAQUE`: alpha is ignored; the triangles are not cut out, and no alpha is looked up.
//! - `MASK`: the surface is there where alpha ≥ `alphaCutoff` (default 0.5), for camera rays and
//!   shadow rays alike: a cut-out leaf casts a leaf-shaped shadow.
//! - `BLEND` [ours]: for camera rays, coverage. Each sample sees the surface where its alpha
//!   exceeds the sample's threshold ([`coverage_threshold`]): the k × k samples of a pixel take
//!   thresholds evenly spaced over [0, 1), so a pixel shows a fraction alpha of the surface
//!   (to within 1/k²) and of what lies behind it, each lit and shadowed as itself. Shadow rays
//!   treat it as a mask at 0.5. The loader warns once per such material.
//!
//! Alpha is looked up bilinearly at the texture's full resolution for camera and shadow rays
//! alike (not filtered over a sample's footprint), so a camera ray and a shadow ray that meet
//! the same point agree on whether the surface is there.

use glam::Vec2;

use super::Scene;
use crate::accel::Cutout;

/// How a material's alpha covers its surface (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Fully there; alpha ignored.
    #[default]
    Opaque,
    /// There where alpha ≥ `cutoff`.
    Mask { cutoff: f32 },
    /// Coverage for camera rays, a mask at 0.5 for shadow rays.
    Blend,
}

impl AlphaMode {
    /// The alpha at or above which a shadow ray is stopped: the cutoff, 0.5 for `BLEND`, 0
    /// (always) for `OPAQUE`.
    pub fn shadow_cutoff(self) -> f32 {
        match self {
            AlphaMode::Opaque => 0.0,
            AlphaMode::Mask { cutoff } => cutoff,
            AlphaMode::Blend => 0.5,
        }
    }
}

/// A material's coverage: its alpha mode and the base colour alpha it reads.
#[derive(Clone, Debug, PartialEq)]
pub struct Alpha {
    pub mode: AlphaMode,
    /// The base colour factor's alpha.
    pub factor: f32,
    /// Index into [`Scene::alpha_maps`] of the base colour texture's alpha, if it has one and
    /// the material is not opaque.
    pub map: Option<usize>,
}

impl Alpha {
    /// Opaque, alpha 1, no map.
    pub const OPAQUE: Alpha = Alpha {
        mode: AlphaMode::Opaque,
        factor: 1.0,
        map: None,
    };
}

impl Default for Alpha {
    fn default() -> Alpha {
        Alpha::OPAQUE
    }
}

/// The alpha channel of a base colour texture, level 0 only, row 0 at the top, as stored in
/// the image (alpha is linear: no sRGB decoding).
#[derive(Clone, Debug)]
pub struct AlphaMap {
    width: usize,
    height: usize,
    /// Shared: the posed copies of a spinning scene keep the same texels.
    texels: std::sync::Arc<[f32]>,
}

impl AlphaMap {
    /// A map of `width × height` alphas; `None` if `texels` does not hold that many.
    pub fn new(width: usize, height: usize, texels: Vec<f32>) -> Option<AlphaMap> {
        if width.checked_mul(height)? != texels.len() {
            return None;
        }
        Some(AlphaMap {
            width,
            height,
            texels: texels.into(),
        })
    }

    /// `(width, height)` in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    fn texel(&self, x: i64, y: i64) -> f32 {
        let x = x.rem_euclid(self.width as i64) as usize;
        let y = y.rem_euclid(self.height as i64) as usize;
        self.texels[y * self.width + x]
    }

    /// Bilinear lookup at `uv` with repeat wrap, texel centres and rows as
    /// [`super::Texture::sample`] has them; 1 for an empty map, texel (0, 0)'s neighbourhood
    /// for a non-finite `uv`.
    pub fn sample(&self, uv: Vec2) -> f32 {
        if self.width == 0 || self.height == 0 {
            return 1.0;
        }
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        let x = uv.x.rem_euclid(1.0) * self.width as f32 - 0.5;
        let y = uv.y.rem_euclid(1.0) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let top = lerp(self.texel(x0, y0), self.texel(x0 + 1, y0), fx);
        let bottom = lerp(self.texel(x0, y0 + 1), self.texel(x0 + 1, y0 + 1), fx);
        lerp(top, bottom, fy)
    }
}

impl Scene {
    /// The base colour alpha at barycentric `(u, v)` of triangle `tri`: the material's factor ×
    /// its texture's alpha at the interpolated UV × the interpolated `COLOR_0` alpha (each 1
    /// where absent). Looked up whatever the alpha mode; opaque materials ignore it.
    pub fn alpha(&self, tri: usize, bary: (f32, f32)) -> f32 {
        let alpha = &self.materials[self.tri_material[tri] as usize].alpha;
        let mut a = alpha.factor;
        if let Some(map) = alpha.map.and_then(|m| self.alpha_maps.get(m)) {
            a *= map.sample(self.uv(tri, bary));
        }
        if !self.vertex_alpha.is_empty() {
            let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
            let (u, v) = bary;
            let va = &self.vertex_alpha;
            a *= va[i0] * (1.0 - u - v) + va[i1] * u + va[i2] * v;
        }
        a
    }

    /// Which triangles the BVH must treat as cut out ([`crate::accel::Accel::build_with_cutouts`]):
    /// those of `MASK` and `BLEND` materials, but for a constant alpha (no texture alpha, no
    /// vertex alpha) that covers the whole surface anyway. Empty when none is.
    pub fn cut_out_triangles(&self) -> Vec<bool> {
        let cut: Vec<bool> = self
            .materials
            .iter()
            .map(|m| {
                let varies = m.alpha.map.is_some() || !self.vertex_alpha.is_empty();
                match m.alpha.mode {
                    AlphaMode::Opaque => false,
                    AlphaMode::Mask { cutoff } => varies || m.alpha.factor < cutoff,
                    AlphaMode::Blend => varies || m.alpha.factor < 1.0,
                }
            })
            .collect();
        if !cut.iter().any(|&c| c) {
            return Vec::new();
        }
        self.tri_material.iter().map(|&m| cut[m as usize]).collect()
    }

    /// The BVH over this scene's triangles, its cut-out triangles marked.
    pub fn accel(&self) -> crate::accel::Accel {
        crate::accel::Accel::build_with_cutouts(
            &self.positions,
            &self.triangles,
            &self.cut_out_triangles(),
        )
    }
}

/// The alpha test of one query: where a cut-out triangle stops the ray.
pub struct AlphaTest<'a> {
    scene: &'a Scene,
    /// A camera ray's coverage threshold for `BLEND` surfaces; `None` for shadow rays.
    coverage: Option<f32>,
}

impl<'a> AlphaTest<'a> {
    /// The test of shadow rays: `MASK` at its cutoff, `BLEND` at 0.5.
    pub fn shadow(scene: &'a Scene) -> AlphaTest<'a> {
        AlphaTest {
            scene,
            coverage: None,
        }
    }

    /// The test of a camera ray whose sample has coverage threshold `threshold` in [0, 1)
    /// ([`coverage_threshold`]): `MASK` at its cutoff, `BLEND` where alpha > `threshold`.
    pub fn camera(scene: &'a Scene, threshold: f32) -> AlphaTest<'a> {
        AlphaTest {
            scene,
            coverage: Some(threshold),
        }
    }
}

impl Cutout for AlphaTest<'_> {
    #[inline]
    fn stops(&self, tri: u32, u: f32, v: f32) -> bool {
        let tri = tri as usize;
        let mode = self.scene.materials[self.scene.tri_material[tri] as usize]
            .alpha
            .mode;
        let alpha = || self.scene.alpha(tri, (u, v));
        match (mode, self.coverage) {
            (AlphaMode::Opaque, _) => true,
            (AlphaMode::Blend, Some(threshold)) => alpha() > threshold,
            (mode, _) => alpha() >= mode.shadow_cutoff(),
        }
    }
}

/// The coverage threshold of sample `(sx, sy)` (its stratum, each in `0..k`) of pixel
/// `(px, py)`, in [0, 1) [ours]: the pixel's k² samples take thresholds `(r + o) / k²` for
/// r = 0 … k² − 1 (r = the stratum's row-major rank), so a `BLEND` surface of alpha a covers
/// ⌊a·k² + 1 − o⌋ of them — a fraction a within 1/k² — whichever strata they are; the offset
/// o ∈ [0, 1) is interleaved gradient noise over the pixels (Jimenez 2014), so neighbouring
/// pixels round alphas differently and a flat alpha dithers finely rather than banding.
/// A pure function of its arguments: tiles and threads see the same thresholds.
pub fn coverage_threshold(px: u32, py: u32, sx: u32, sy: u32, k: u32) -> f32 {
    let ign = |x: f32, y: f32| {
        let f = |v: f32| v - v.floor();
        f(52.982_918 * f(0.067_110_56 * x + 0.005_837_15 * y))
    };
    let o = ign(px as f32, py as f32);
    let n = (k * k) as f32;
    let r = (sy * k + sx) as f32;
    ((r + o) / n).min(1.0 - f32::EPSILON / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixels_thresholds_cover_each_alpha_to_within_one_sample() {
        for k in 1..=8u32 {
            for (px, py) in [(0, 0), (17, 3), (640, 479), (12345, 999)] {
                let t: Vec<f32> = (0..k * k)
                    .map(|s| coverage_threshold(px, py, s % k, s / k, k))
                    .collect();
                assert!(t.iter().all(|&t| (0.0..1.0).contains(&t)), "{t:?}");
                for a in [0.0f32, 0.1, 0.25, 0.5, 0.77, 0.999, 1.0] {
                    let covered = t.iter().filter(|&&t| a > t).count() as f32;
                    let n = (k * k) as f32;
                    assert!(
                        (covered / n - a).abs() <= 1.0 / n,
                        "k {k} pixel ({px}, {py}) alpha {a}: {covered} of {n}"
                    );
                }
            }
        }
        // One sample per pixel: the thresholds of neighbouring pixels spread over [0, 1).
        let t: Vec<f32> = (0..64).map(|x| coverage_threshold(x, 7, 0, 0, 1)).collect();
        let mean = t.iter().sum::<f32>() / 64.0;
        assert!((mean - 0.5).abs() < 0.1, "{mean}");
        assert!(t.iter().any(|&t| t < 0.2) && t.iter().any(|&t| t > 0.8));
    }

    #[test]
    fn alpha_maps_sample_bilinearly_with_repeat_wrap() {
        let m = AlphaMap::new(2, 1, vec![0.0, 1.0]).unwrap();
        assert_eq!(m.sample(Vec2::new(0.25, 0.5)), 0.0);
        assert_eq!(m.sample(Vec2::new(0.75, 0.5)), 1.0);
        assert_eq!(m.sample(Vec2::new(0.5, 0.5)), 0.5);
        // Across the wrap, halfway between the last texel and the first.
        assert_eq!(m.sample(Vec2::new(1.0, 0.5)), 0.5);
        assert_eq!(m.sample(Vec2::new(-0.25, 0.5)), 1.0);
        assert_eq!(m.sample(Vec2::new(f32::NAN, 0.5)), 0.5);
        assert_eq!(AlphaMap::new(0, 0, vec![]).unwrap().sample(Vec2::ZERO), 1.0);
        assert!(AlphaMap::new(2, 2, vec![1.0]).is_none());
    }
}
