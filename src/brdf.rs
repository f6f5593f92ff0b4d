//! The glTF 2.0 metallic-roughness BRDF (the specification's appendix B), one light at a time:
//! the scalar form every other evaluation is checked against, and what a light with its own
//! per-pixel direction (a point or spot light) is shaded with.
//!
//! `f = mix(dielectric, metal, metallic)` with
//! - `dielectric = (1 − max(F_d)) · base/π + F_d · D · Vis`, `F_d = f0 + (f90 − f0)(1 − v·h)⁵`
//!   (`f0 = ((ior − 1)/(ior + 1))²` times `KHR_materials_specular`'s colour and strength,
//!   `f90` its strength: 0.04 and 1 by default, where the `max` is the plain F);
//! - `metal = F_m · D · Vis`, `F_m = base + (1 − base)(1 − v·h)⁵`;
//! - `D` GGX / Trowbridge-Reitz with `α = roughness²`, `Vis` Smith's height-correlated
//!   masking-shadowing over `4 (n·l)(n·v)`.
//!
//! [ours] α is at least [`MIN_ALPHA`] (a mirror's D is a delta no sum over lights can hold;
//! Mitsuba 3 clamps the same), and `n·v` at least [`MIN_COS_VIEW`] (an interpolated or
//! normal-mapped normal can face away from the eye at silhouettes).
//!
//! Written so that a light's terms come from a few per-pixel constants and two dot products
//! ([`Lobe`], [`LightTerms`]): the SIMD kernels of the `shade` module do the same operations, in the
//! same order, eight lights at a time.

use glam::Vec3;

use crate::scene::MaterialSample;

/// The smallest GGX α (roughness² below 0.001 is taken as 0.001).
pub const MIN_ALPHA: f32 = 1e-3;
/// The smallest `n·v` the specular lobe is evaluated at.
pub const MIN_COS_VIEW: f32 = 1e-4;

/// GGX α of a perceptual roughness: `max(roughness², MIN_ALPHA)`.
#[inline]
pub fn alpha(roughness: f32) -> f32 {
    (roughness * roughness).max(MIN_ALPHA)
}

/// What the specular terms need of a pixel: normal, view direction and roughness, with the
/// parts of `D · Vis` that do not depend on the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobe {
    /// Unit shading normal.
    pub n: Vec3,
    /// Unit direction towards the eye.
    pub v: Vec3,
    /// `max(n·v, MIN_COS_VIEW)`.
    pub n_dot_v: f32,
    /// α².
    pub a2: f32,
    /// `1 − α²`.
    pub one_minus_a2: f32,
    /// `sqrt((n·v)² (1 − α²) + α²)`: the view's half of the height-correlated Smith term.
    pub kv: f32,
    /// `α²/2π`: D · Vis's constant factor.
    pub c: f32,
}

impl Lobe {
    pub fn new(n: Vec3, v: Vec3, roughness: f32) -> Lobe {
        let a = alpha(roughness);
        let a2 = a * a;
        let one_minus_a2 = 1.0 - a2;
        let n_dot_v = (n.x * v.x + n.y * v.y + n.z * v.z).max(MIN_COS_VIEW);
        let kv = (n_dot_v * n_dot_v * one_minus_a2 + a2).sqrt();
        Lobe {
            n,
            v,
            n_dot_v,
            a2,
            one_minus_a2,
            kv,
            c: a2 * 0.5 * std::f32::consts::FRAC_1_PI,
        }
    }
}

/// One light's terms for a pixel's [`Lobe`]: `n·l`, the Schlick weight `w = (1 − v·h)⁵`, and
/// `D · Vis` (the specular BRDF with F = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTerms {
    pub cos: f32,
    pub w: f32,
    pub dv: f32,
}

/// The terms of light direction `l` (unit) for `lobe`, computed without normalising the half
/// vector `h = v + l`: with `|h|²` its squared length, `v·h = |h|/2`, and
/// `(n·h)²(α² − 1) + 1 = q / |h|²` where `q = (n·h)² α² + |n × h|²` — a sum of two squares,
/// so a sharp lobe's peak loses no precision to cancellation (`|h|² − (n·h)²` would). Then
/// `D · Vis = (α²/2π) |h|⁴ / (q² · (n·l · kv + n·v · sqrt((n·l)²(1 − α²) + α²)))`, at most
/// [`MAX_DV`]; `n·h` is taken as `n·v + n·l` with the clamped `n·v`. Every product and sum in
/// the order the kernels use. For `n·l ≤ 0` the caller must not use the result.
#[inline]
pub fn light_terms(lobe: &Lobe, l: Vec3) -> LightTerms {
    let (n, v) = (lobe.n, lobe.v);
    let cos = n.x * l.x + n.y * l.y + n.z * l.z;
    let (hx, hy, hz) = (v.x + l.x, v.y + l.y, v.z + l.z);
    let hh = hx * hx + hy * hy + hz * hz;
    let vh = (hh * 0.25).sqrt();
    let t = 1.0 - vh;
    let t2 = t * t;
    let w = t2 * t2 * t;
    let (cx, cy, cz) = (
        n.y * hz - n.z * hy,
        n.z * hx - n.x * hz,
        n.x * hy - n.y * hx,
    );
    let cross = cx * cx + cy * cy + cz * cz;
    let sum = lobe.n_dot_v + cos;
    let q = sum * sum * lobe.a2 + cross;
    let kl = (cos * cos * lobe.one_minus_a2 + lobe.a2).sqrt();
    let den = q * q * (cos * lobe.kv + lobe.n_dot_v * kl);
    let dv = lobe.c * (hh * hh) / den;
    // As `_mm_min_ps(dv, MAX_DV)`: NaN becomes MAX_DV too.
    let dv = if dv < MAX_DV { dv } else { MAX_DV };
    LightTerms { cos, w, dv }
}

/// The largest `D · Vis` a light contributes: [ours] finite where the formula's denominator
/// meets zero (a view below the normal's horizon, at float precision), far beyond any value
/// a lit pixel can reach (α ≥ 0.001 bounds D by 3.2·10⁵).
pub const MAX_DV: f32 = 1e7;

/// The four light sums a pixel's shading is made of, over a set of lights `j` with energies
/// `E_j`: `s0 = Σ E cos`, `s1 = Σ E cos w`, `s2 = Σ E cos D Vis`, `s3 = Σ E cos D Vis w`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sums {
    pub s0: Vec3,
    pub s1: Vec3,
    pub s2: Vec3,
    pub s3: Vec3,
}

/// The material's colours that turn [`Sums`] into radiance: `L = kd · (s0·a − s1·b) + ks2 · s2
/// + ks3 · s3`, the BRDF above rewritten as linear in `w` (so the sums need no material).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights {
    /// `base · (1 − metallic) / π`.
    pub kd: Vec3,
    /// `1 − max(f0)`.
    pub a: f32,
    /// `f90 − max(f0)`.
    pub b: f32,
    /// `(1 − metallic) f0 + metallic · base`: the specular colour at normal incidence.
    pub ks2: Vec3,
    /// `(1 − metallic)(f90 − f0) + metallic (1 − base)`: what the Schlick weight adds.
    pub ks3: Vec3,
}

impl Weights {
    pub fn new(base: Vec3, m: &MaterialSample) -> Weights {
        let metal = m.metallic;
        let dielectric = 1.0 - metal;
        let f0_max = m.f0.max_element();
        Weights {
            kd: base * (dielectric * std::f32::consts::FRAC_1_PI),
            a: 1.0 - f0_max,
            b: m.f90 - f0_max,
            ks2: m.f0 * dielectric + base * metal,
            ks3: (Vec3::splat(m.f90) - m.f0) * dielectric + (Vec3::ONE - base) * metal,
        }
    }

    /// The radiance of `sums` (see [`Weights`]).
    #[inline]
    pub fn radiance(&self, sums: &Sums) -> Vec3 {
        self.diffuse(sums) + self.specular(sums.s2, sums.s3)
    }

    /// The diffuse part.
    #[inline]
    pub fn diffuse(&self, sums: &Sums) -> Vec3 {
        self.kd * (sums.s0 * self.a - sums.s1 * self.b)
    }

    /// The specular part of the sums `s2`, `s3`.
    #[inline]
    pub fn specular(&self, s2: Vec3, s3: Vec3) -> Vec3 {
        self.ks2 * s2 + self.ks3 * s3
    }
}

/// What turns a lobe's light [`Sums`] into radiance: one sample's [`Weights`], or the mean
/// of a group's ([`MeanWeights`]).
pub trait Reflectance {
    /// The diffuse part of `sums`.
    fn diffuse(&self, sums: &Sums) -> Vec3;
    /// The specular part of the sums `s2`, `s3`.
    fn specular(&self, s2: Vec3, s3: Vec3) -> Vec3;
}

impl Reflectance for Weights {
    #[inline]
    fn diffuse(&self, sums: &Sums) -> Vec3 {
        Weights::diffuse(self, sums)
    }
    #[inline]
    fn specular(&self, s2: Vec3, s3: Vec3) -> Vec3 {
        Weights::specular(self, s2, s3)
    }
}

/// The mean of several samples' [`Weights`], each scaled by its own factor (its occlusion):
/// radiance is linear in each of the four products `kd·a`, `kd·b`, `ks2`, `ks3`, so the mean
/// of theirs reflects a group's summed light as the samples' own weights would on average —
/// exactly where the samples' light is the same. (The mean of `kd`, `a` and `b` apart would
/// not: `kd·a` is a product.)
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeanWeights {
    d0: Vec3,
    d1: Vec3,
    ks2: Vec3,
    ks3: Vec3,
    n: f32,
}

impl MeanWeights {
    /// Adds one sample's weights, scaled by `scale`.
    pub fn add(&mut self, w: &Weights, scale: f32) {
        self.d0 += w.kd * (w.a * scale);
        self.d1 += w.kd * (w.b * scale);
        self.ks2 += w.ks2 * scale;
        self.ks3 += w.ks3 * scale;
        self.n += 1.0;
    }

    /// The mean of the weights added.
    pub fn mean(self) -> MeanWeights {
        let k = 1.0 / self.n.max(1.0);
        MeanWeights {
            d0: self.d0 * k,
            d1: self.d1 * k,
            ks2: self.ks2 * k,
            ks3: self.ks3 * k,
            n: 1.0,
        }
    }
}

impl Reflectance for MeanWeights {
    #[inline]
    fn diffuse(&self, sums: &Sums) -> Vec3 {
        self.d0 * sums.s0 - self.d1 * sums.s1
    }
    #[inline]
    fn specular(&self, s2: Vec3, s3: Vec3) -> Vec3 {
        self.ks2 * s2 + self.ks3 * s3
    }
}

/// The BRDF `f(l, v)` of a material of base colour `base` with shading normal `n`, times
/// nothing (no cosine): for one light, radiance = `f · E · (n·l)`. Zero where `l` is below the
/// horizon. Lambertian materials give `base/π`.
pub fn brdf(n: Vec3, v: Vec3, l: Vec3, base: Vec3, m: &MaterialSample) -> Vec3 {
    let cos = n.dot(l);
    if cos <= 0.0 {
        return Vec3::ZERO;
    }
    if m.lambert {
        return base * std::f32::consts::FRAC_1_PI;
    }
    let lobe = Lobe::new(n, v, m.roughness);
    let t = light_terms(&lobe, l);
    let w = Weights::new(base, m);
    w.kd * (w.a - w.b * t.w) + (w.ks2 + w.ks3 * t.w) * t.dv
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(metallic: f32, roughness: f32) -> MaterialSample {
        MaterialSample {
            lambert: false,
            metallic,
            roughness,
            ..MaterialSample::default()
        }
    }

    /// The spec's formulas written the plain way, in f64: h normalised, D and Vis apart.
    fn reference(n: Vec3, v: Vec3, l: Vec3, base: Vec3, m: &MaterialSample) -> [f64; 3] {
        let d = |a: Vec3, b: Vec3| {
            f64::from(a.x) * f64::from(b.x)
                + f64::from(a.y) * f64::from(b.y)
                + f64::from(a.z) * f64::from(b.z)
        };
        let (nl, nv) = (d(n, l), d(n, v).max(f64::from(MIN_COS_VIEW)));
        // h in f64 too: an f32 half vector's rounding moves a sharp peak's D by more than
        // the tolerance.
        let hs = [
            f64::from(v.x) + f64::from(l.x),
            f64::from(v.y) + f64::from(l.y),
            f64::from(v.z) + f64::from(l.z),
        ];
        let len = (hs[0] * hs[0] + hs[1] * hs[1] + hs[2] * hs[2]).sqrt();
        let dh = |a: Vec3| {
            (f64::from(a.x) * hs[0] + f64::from(a.y) * hs[1] + f64::from(a.z) * hs[2]) / len
        };
        let (nh, vh) = (dh(n), dh(v));
        let a = f64::from(alpha(m.roughness));
        let a2 = a * a;
        let dd = a2 / (std::f64::consts::PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
        let vis = 0.5
            / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt());
        let w = (1.0 - vh).powi(5);
        let mut out = [0.0; 3];
        for c in 0..3 {
            let b = f64::from(base[c]);
            let f0 = f64::from(m.f0[c]);
            let fd = f0 + (f64::from(m.f90) - f0) * w;
            let fd_max = f64::from(m.f0.max_element())
                + (f64::from(m.f90) - f64::from(m.f0.max_element())) * w;
            let dielectric = (1.0 - fd_max) * b / std::f64::consts::PI + fd * dd * vis;
            let metal = (b + (1.0 - b) * w) * dd * vis;
            let mt = f64::from(m.metallic);
            out[c] = dielectric * (1.0 - mt) + metal * mt;
        }
        out
    }

    fn dirs() -> Vec<Vec3> {
        let mut seed = 7u32;
        let mut rnd = move || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        (0..200)
            .map(|_| (Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0).normalize_or(Vec3::Y))
            .collect()
    }

    #[test]
    fn the_rewritten_brdf_is_the_specifications() {
        let n = Vec3::new(0.1, 0.9, 0.2).normalize();
        let base = Vec3::new(0.9, 0.6, 0.2);
        let ds = dirs();
        // A near-mirror too: its peak must not lose precision.
        let cases = [
            (0.0, 0.3),
            (0.0, 1.0),
            (1.0, 0.5),
            (0.5, 0.7),
            (0.25, 0.15),
            (1.0, 0.02),
        ];
        for &(metallic, roughness) in &cases {
            let m = material(metallic, roughness);
            let tol = if roughness < 0.1 { 0.05 } else { 1e-3 };
            for v in ds.iter().filter(|v| n.dot(**v) > 0.05) {
                for l in ds.iter().filter(|l| n.dot(**l) > 0.05) {
                    let got = brdf(n, *v, *l, base, &m);
                    let want = reference(n, *v, *l, base, &m);
                    for c in 0..3 {
                        let err = (f64::from(got[c]) - want[c]).abs();
                        assert!(
                            // f32: near a sharp peak `n × h` is a difference of nearly
                            // equal products, and its rounding moves D by up to ~3·10⁻⁴
                            // (r 0.15); a wrong term moves it by percents.
                            // The near-mirror (α clamped to 0.001): a normal whose f32
                            // length is 1 within 10⁻⁷ moves that peak's D by ~2 %.
                            err <= tol * want[c].abs().max(1.0),
                            "m {metallic} r {roughness} v {v} l {l}: {got} vs {want:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_brdf_is_reciprocal() {
        let n = Vec3::Y;
        let base = Vec3::new(0.8, 0.5, 0.3);
        let ds = dirs();
        for &(metallic, roughness) in &[(0.0, 0.2), (0.0, 0.8), (1.0, 0.4), (0.6, 1.0)] {
            let m = material(metallic, roughness);
            for a in ds.iter().filter(|d| n.dot(**d) > 0.05) {
                for b in ds.iter().filter(|d| n.dot(**d) > 0.05) {
                    let (ab, ba) = (brdf(n, *a, *b, base, &m), brdf(n, *b, *a, base, &m));
                    let err = ((ab - ba) / ab.max(Vec3::splat(1e-3))).abs().max_element();
                    assert!(err < 1e-4, "{a} {b}: {ab} vs {ba}");
                }
            }
        }
    }

    #[test]
    fn below_the_horizon_reflects_nothing_and_lambert_is_albedo_over_pi() {
        let m = material(0.0, 0.5);
        let base = Vec3::splat(0.5);
        assert_eq!(brdf(Vec3::Y, Vec3::Y, Vec3::NEG_Y, base, &m), Vec3::ZERO);
        let lambert = MaterialSample::default();
        assert_eq!(
            brdf(Vec3::Y, Vec3::X, Vec3::Y, base, &lambert),
            base * std::f32::consts::FRAC_1_PI
        );
    }
}
