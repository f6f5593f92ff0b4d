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
//! Alpha is looked up at the base colour texture's full resolution (bilinear, or the nearest
//! texel for a `NEAREST` magnification filter, wrapped as its sampler says) for camera and
//! shadow rays alike (not filtered over a sample's footprint), so a camera ray and a shadow ray
//! that meet the same point agree on whether the surface is there.

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

impl Scene {
    /// The base colour alpha at barycentric `(u, v)` of triangle `tri`: the material's factor ×
    /// its base colour texture's alpha (level 0, through the texture's slot: its coordinate set,
    /// `KHR_texture_transform` and sampler) × the interpolated `COLOR_0` alpha (each 1 where
    /// absent). Looked up whatever the alpha mode; opaque materials ignore it.
    pub fn alpha(&self, tri: usize, bary: (f32, f32)) -> f32 {
        let m = &self.materials[self.tri_material[tri] as usize];
        let mut a = m.base_alpha;
        if let Some(slot) = &m.base_color_texture
            && let Some(texture) = self.textures.get(slot.texture)
            && texture.has_alpha()
        {
            a *= texture.alpha_at(self.slot_uv(slot, tri, bary), &slot.sampler);
        }
        if !self.colors.is_empty() {
            a *= self.vertex_color(tri, bary).w;
        }
        a
    }

    /// Which triangles the BVH must treat as cut out ([`crate::accel::Accel::build_with_cutouts`]):
    /// those of `MASK` and `BLEND` materials, but for a constant alpha (no texture alpha, no
    /// vertex colours) that covers the whole surface anyway. Empty when none is.
    pub fn cut_out_triangles(&self) -> Vec<bool> {
        let cut: Vec<bool> = self
            .materials
            .iter()
            .map(|m| {
                let texture_alpha = m
                    .base_color_texture
                    .and_then(|s| self.textures.get(s.texture))
                    .is_some_and(|t| t.has_alpha());
                let varies = texture_alpha || !self.colors.is_empty();
                match m.alpha_mode {
                    AlphaMode::Opaque => false,
                    AlphaMode::Mask { cutoff } => varies || m.base_alpha < cutoff,
                    AlphaMode::Blend => varies || m.base_alpha < 1.0,
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
        let mode = self.scene.materials[self.scene.tri_material[tri] as usize].alpha_mode;
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
}
