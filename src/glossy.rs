//! Glossy reflection where the light set is too coarse for the lobe: the environment
//! prefiltered per roughness, and the GGX lobe's integrals for the split sum.
//!
//! Over N directional lights a narrow specular lobe sees a few lights or none — a low
//! roughness makes the lights into dots. [ours] Per shading point, the lobe's α is compared
//! with the lights' spacing around its mirror direction ([`Glossy::split`]: importance-sampled
//! lights crowd where the map is bright and thin out where it is dim, so the same roughness
//! may be resolved on one side of an object and not the other). Where they do not resolve it,
//! the specular is the split-sum estimate (Karis 2013): the map convolved with the GGX lobe
//! around the mirror direction ([`Glossy::radiance`]) times the lobe's integral for the
//! material's Fresnel ([`Glossy::dfg`]), then weighted by the share of the lobe's light that
//! reaches the point unblocked, measured by a few rays into the lobe (the reflection module: the
//! lights' bits would blur a narrow lobe's occluders over their spacing, and a mirror would
//! reflect what an object hides). Where they resolve it the lights alone are used;
//! between, the two are blended smoothly. docs/materials.md gives the measured errors.
//!
//! Everything here is computed once at load, deterministically (pure `libm`, fixed sample
//! sequences, each prefiltered texel a sum in a fixed order), so every host gets the same bits.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::brdf::alpha;
use crate::envmap::{EnvMap, dir_to_uv, uv_to_dir};
use crate::lights::LightSet;

/// Roughness step between prefiltered levels.
const STEP: f32 = 0.05;
/// Widest prefiltered level, texels (height half of it).
const MAX_WIDTH: usize = 256;
/// Narrowest prefiltered level.
const MIN_WIDTH: usize = 32;
/// Around its centre a lobe is summed over the level's own texels, out to where GGX's D falls
/// to this share of its peak but no further than `NEAR_RADIUS` or 4α; beyond, over a coarse copy
/// of the map (`FAR_WIDTH` texels wide). GGX's tails are long, and a small bright source far
/// from the centre (a studio light, the sun) can outweigh all of the lobe's core.
const CUTOFF: f32 = 1e-3;
const NEAR_RADIUS: f32 = 25.0 * std::f32::consts::PI / 180.0;
const FAR_WIDTH: usize = 32;
/// Resolution of the lobe-integral table, per axis (n·v and roughness).
const DFG_SIZE: usize = 32;
/// Samples per entry of that table (a Hammersley set).
const DFG_SAMPLES: u32 = 1024;

/// [ours] Per shading point, the lights give the specular of a lobe whose α is at least
/// `LIGHTS_EXACT × δ`, δ the lights' local spacing around the lobe's mirror direction (the
/// square root of their cells' solid angle there, see [`Spacing`]); below `LIGHTS_NONE × δ`
/// the lights' own specular is not used at all; between, a smoothstep. Chosen against
/// Mitsuba's converged render of the true map (docs/materials.md): wider switches leave more
/// to the split sum, whose error on rough lobes at grazing views is larger than the lights'.
const LIGHTS_EXACT: f32 = 0.5;
const LIGHTS_NONE: f32 = 0.25;
/// The spacing field's grid (lat-long, texels) and the angle its log solid angles are blurred
/// over (radians, a Gaussian's σ): a lobe on a cell's border sees both cells, and the share
/// must not jump there (a jump would draw the cells on a glossy surface).
const SPACING_WIDTH: usize = 128;
const SPACING_SIGMA: f32 = 4.0 * std::f32::consts::PI / 180.0;

/// One prefiltered lat-long map (the map's own frame, as [`EnvMap`]'s texels).
struct Level {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
}

/// The prefiltered environment, the lobe integrals, and the lights' local spacing that decides,
/// per shading point, where they stand in for the lights.
pub struct Glossy {
    /// The unfiltered map (roughness 0: a mirror sees it as it is).
    env: EnvMap,
    /// Roughness STEP, 2·STEP, … up to the first at or above the widest lobe the lights may
    /// leave to the environment (`Glossy::roughness_bound`).
    levels: Vec<Level>,
    /// `(∫ D Vis cos dω, ∫ D Vis cos (1 − v·h)⁵ dω)` over the hemisphere, by (roughness, n·v).
    dfg: Vec<[f32; 2]>,
    /// The lights' spacing around each direction.
    spacing: Spacing,
}

/// How one shading point's specular is split between the lights and the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// 1: the lights alone (exact over them); 0: the environment alone; between, a blend.
    pub lights: f32,
}

impl Glossy {
    /// The roughness below which some lobe of `lights` may take its specular from the
    /// environment: where the largest cell's spacing no longer resolves it. Nothing is
    /// prefiltered: enough to ask whether a material needs the rest.
    pub fn roughness_bound(lights: &LightSet) -> f32 {
        let largest = lights
            .lights
            .iter()
            .map(|l| l.solid_angle)
            .fold(0.0f32, f32::max);
        let spacing = if lights.lights.is_empty() {
            2.0 * std::f32::consts::PI
        } else {
            largest.max(0.0).sqrt()
        };
        (LIGHTS_EXACT * spacing).sqrt().min(1.0)
    }

    /// Prefilters `env` for the light set `lights` (the frame's lights before any turn of
    /// the environment). Parallel over texel rows, each texel summed alone: the same bits
    /// whatever the threads.
    pub fn build(env: &EnvMap, lights: &LightSet) -> Glossy {
        let bound = Glossy::roughness_bound(lights);
        let far_width = FAR_WIDTH.min(env.width.max(2));
        let far = (
            downsample(env, far_width, (far_width / 2).max(1)),
            Source::new(far_width, (far_width / 2).max(1)),
        );
        let mut levels = Vec::new();
        let mut k = 1;
        loop {
            let roughness = STEP * k as f32;
            levels.push(prefilter(env, roughness, &far));
            if roughness >= bound || roughness >= 1.0 {
                break;
            }
            k += 1;
        }
        Glossy {
            env: env.clone(),
            levels,
            dfg: dfg_table(),
            spacing: Spacing::build(lights),
        }
    }

    /// The split of a lobe of `roughness` reflected along world direction `mirror` (in the
    /// frame of the lights the prefilter was built for): by its α against the lights' local
    /// spacing δ there, the lights alone at α ≥ `LIGHTS_EXACT·δ`, the environment alone at
    /// α ≤ `LIGHTS_NONE·δ`, a smoothstep between.
    pub fn split(&self, mirror: Vec3, roughness: f32) -> Split {
        let delta = self.spacing.at(mirror);
        let a = alpha(roughness);
        let t = ((a / delta - LIGHTS_NONE) / (LIGHTS_EXACT - LIGHTS_NONE)).clamp(0.0, 1.0);
        Split {
            lights: t * t * (3.0 - 2.0 * t),
        }
    }

    /// The lights' local spacing δ (radians) around world direction `dir`.
    pub fn spacing(&self, dir: Vec3) -> f32 {
        self.spacing.at(dir)
    }

    /// The environment's radiance along world direction `dir`, averaged over the GGX lobe of
    /// `roughness` (with n = v = `dir`, the split sum's assumption): the map itself at 0,
    /// linear between levels.
    pub fn radiance(&self, dir: Vec3, roughness: f32) -> Vec3 {
        let uv = dir_to_uv(self.env.to_map(dir));
        let r = roughness.max(0.0);
        let k = (r / STEP).floor() as usize;
        let t = r / STEP - k as f32;
        let at = |k: usize| -> Vec3 {
            if k == 0 {
                self.env.radiance(dir)
            } else {
                let level = &self.levels[(k - 1).min(self.levels.len() - 1)];
                level.bilinear(uv)
            }
        };
        let fine = at(k);
        if t == 0.0 || k >= self.levels.len() {
            fine
        } else {
            fine * (1.0 - t) + at(k + 1) * t
        }
    }

    /// The GGX lobe's integrals at `n_dot_v` and `roughness`: `(∫ D Vis cos dω,
    /// ∫ D Vis cos (1 − v·h)⁵ dω)` (bilinear in the table).
    pub fn dfg(&self, n_dot_v: f32, roughness: f32) -> (f32, f32) {
        let last = (DFG_SIZE - 1) as f32;
        let x = (n_dot_v.clamp(0.0, 1.0) * last).min(last);
        let y = (roughness.clamp(0.0, 1.0) * last).min(last);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(DFG_SIZE - 1), (y0 + 1).min(DFG_SIZE - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let e = |xi: usize, yi: usize| self.dfg[yi * DFG_SIZE + xi];
        let mut out = [0.0f32; 2];
        for (c, o) in out.iter_mut().enumerate() {
            let top = e(x0, y0)[c] * (1.0 - fx) + e(x1, y0)[c] * fx;
            let bottom = e(x0, y1)[c] * (1.0 - fx) + e(x1, y1)[c] * fx;
            *o = top * (1.0 - fy) + bottom * fy;
        }
        (out[0], out[1])
    }
}

/// The four texels around `uv` on a `width`×`height` lat-long grid and the weights between
/// them: bilinear between texel centres, wrapping in longitude, clamped at the poles (as
/// [`EnvMap::radiance`]). `([x0, x1, y0, y1], tx, ty)`.
fn taps(uv: Vec2, width: usize, height: usize) -> ([usize; 4], f32, f32) {
    let fx = uv.x * width as f32 - 0.5;
    let fy = uv.y * height as f32 - 0.5;
    let (x0f, y0f) = (fx.floor(), fy.floor());
    let (w, h) = (width as i64, height as i64);
    let x0 = (x0f as i64).rem_euclid(w) as usize;
    let x1 = (x0f as i64 + 1).rem_euclid(w) as usize;
    let y0 = (y0f as i64).clamp(0, h - 1) as usize;
    let y1 = (y0f as i64 + 1).clamp(0, h - 1) as usize;
    ([x0, x1, y0, y1], fx - x0f, fy - y0f)
}

impl Level {
    /// Bilinear between texel centres, wrapping in longitude, clamped at the poles (as
    /// [`EnvMap::radiance`]).
    fn bilinear(&self, uv: Vec2) -> Vec3 {
        let ([x0, x1, y0, y1], tx, ty) = taps(uv, self.width, self.height);
        let t = |x: usize, y: usize| self.texels[y * self.width + x];
        let top = t(x0, y0).lerp(t(x1, y0), tx);
        let bottom = t(x0, y1).lerp(t(x1, y1), tx);
        top.lerp(bottom, ty)
    }
}

/// `env`'s texels (its own frame) box-averaged down to `width × height` (each at most the
/// map's), each source texel weighted by its solid angle.
fn downsample(env: &EnvMap, width: usize, height: usize) -> Vec<Vec3> {
    let (sw, sh) = (env.width, env.height);
    let mut out = Vec::with_capacity(width * height);
    for y in 0..height {
        let (r0, r1) = (
            y * sh / height,
            ((y + 1) * sh / height).max(y * sh / height + 1),
        );
        for x in 0..width {
            let (c0, c1) = (
                x * sw / width,
                ((x + 1) * sw / width).max(x * sw / width + 1),
            );
            let mut sum = Vec3::ZERO;
            let mut weight = 0.0f32;
            for r in r0..r1 {
                let dw = env.texel_solid_angle(r);
                for c in c0..c1 {
                    sum += env.texel(c, r) * dw;
                    weight += dw;
                }
            }
            out.push(if weight > 0.0 {
                sum / weight
            } else {
                Vec3::ZERO
            });
        }
    }
    out
}

/// The map convolved with the GGX lobe of `roughness` around each texel's direction R, with
/// n = v = R: each source texel ω weighted by `D(h) (R·ω) dω`, `(n·h)² = (1 + R·ω)/2`,
/// normalised by the weights' sum, over the whole hemisphere around R: the level's own texels
/// near R (see [`CUTOFF`]), the coarse `far` copy of the map beyond.
fn prefilter(env: &EnvMap, roughness: f32, far: &(Vec<Vec3>, Source)) -> Level {
    let a = alpha(roughness);
    let a2 = a * a;
    // Texels about α/2 wide (the lobe's half-vector spread), within the bounds, a power of
    // two: coarser texels move a small bright source by a good part of the lobe.
    let want = (2.0 * std::f32::consts::TAU / a).ceil() as usize;
    let width = want
        .next_power_of_two()
        .clamp(MIN_WIDTH, MAX_WIDTH)
        .min(env.width.max(2));
    let height = (width / 2).max(1);
    let source = downsample(env, width, height);
    let src = Source::new(width, height);
    // Where D falls to CUTOFF of its peak: (n·h)²(α² − 1) + 1 = α² / √CUTOFF.
    let limit = a2 / libm::sqrtf(CUTOFF);
    let cutoff_cos = if limit >= 1.0 {
        0.0
    } else {
        // (n·h)² = (1 − limit)/(1 − α²), and R·ω = 2(n·h)² − 1.
        (2.0 * (1.0 - limit) / (1.0 - a2) - 1.0).max(0.0)
    };
    // A rough lobe keeps much of its weight well past NEAR_RADIUS (a third of its peak at 25°
    // for α = 0.25): its own texels out to 4α.
    let near = NEAR_RADIUS.max(4.0 * a).min(std::f32::consts::FRAC_PI_2);
    let near_cos = cutoff_cos.max(libm::cosf(near));
    let radius = libm::acosf(near_cos);
    let weight = |cos: f32, dw: f32| {
        let nh2 = (1.0 + cos) * 0.5;
        let q = nh2 * (a2 - 1.0) + 1.0;
        cos * dw / (q * q)
    };
    let (far_texels, far_src) = far;
    let texels: Vec<Vec3> = (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let (source, src) = (&source, &src);
            (0..width).map(move |x| {
                let r = src.dir[y * width + x];
                let mut sum = Vec3::ZERO;
                let mut total = 0.0f32;
                let lat = std::f32::consts::FRAC_PI_2
                    - (y as f32 + 0.5) / height as f32 * std::f32::consts::PI;
                let (rows, cols) = src.window(lat, radius, x);
                for row in rows {
                    let dw = src.solid_angle[row];
                    for c in cols.clone() {
                        let col = c.rem_euclid(width as i64) as usize;
                        let cos = r.dot(src.dir[row * width + col]);
                        if cos > near_cos {
                            let w = weight(cos, dw);
                            sum += source[row * width + col] * w;
                            total += w;
                        }
                    }
                }
                for (i, d) in far_src.dir.iter().enumerate() {
                    let cos = r.dot(*d);
                    if cos > 0.0 && cos <= near_cos {
                        let w = weight(cos, far_src.solid_angle[i / far_src.width]);
                        sum += far_texels[i] * w;
                        total += w;
                    }
                }
                if total > 0.0 {
                    sum / total
                } else {
                    source[y * width + x]
                }
            })
        })
        .collect();
    Level {
        width,
        height,
        texels,
    }
}

/// The directions and solid angles of a `width × height` lat-long grid, and the windows of
/// texels within an angle of a texel.
struct Source {
    width: usize,
    height: usize,
    dir: Vec<Vec3>,
    solid_angle: Vec<f32>,
}

impl Source {
    fn new(width: usize, height: usize) -> Source {
        let dir = (0..height)
            .flat_map(|y| {
                (0..width).map(move |x| {
                    uv_to_dir(Vec2::new(
                        (x as f32 + 0.5) / width as f32,
                        (y as f32 + 0.5) / height as f32,
                    ))
                })
            })
            .collect();
        let solid_angle = (0..height)
            .map(|y| {
                let pi = std::f64::consts::PI;
                let top = pi * (0.5 - y as f64 / height as f64);
                let bottom = pi * (0.5 - (y as f64 + 1.0) / height as f64);
                ((2.0 * pi / width as f64) * (libm::sin(top) - libm::sin(bottom))) as f32
            })
            .collect();
        Source {
            width,
            height,
            dir,
            solid_angle,
        }
    }

    /// The rows, and the columns (unwrapped: may run past either edge), of the texels that
    /// may lie within `radius` of the texel at latitude `lat`, column `x`.
    fn window(
        &self,
        lat: f32,
        radius: f32,
        x: usize,
    ) -> (std::ops::Range<usize>, std::ops::Range<i64>) {
        let (w, h) = (self.width as f32, self.height as f32);
        let half_pi = std::f32::consts::FRAC_PI_2;
        let row_of = |l: f32| ((half_pi - l) / std::f32::consts::PI * h).floor();
        let top = row_of((lat + radius).min(half_pi)).max(0.0) as usize;
        let bottom = (row_of((lat - radius).max(-half_pi)) as usize + 1).min(self.height);
        // Past a pole every longitude is near; else the widest row of the window decides.
        let widest = lat.abs() + radius;
        let cols = if widest >= half_pi || radius >= half_pi {
            0..self.width as i64
        } else {
            let span = libm::asinf((libm::sinf(radius) / libm::cosf(widest)).min(1.0));
            let n = (span / std::f32::consts::TAU * w).ceil() as i64 + 1;
            if 2 * n + 1 >= self.width as i64 {
                0..self.width as i64
            } else {
                x as i64 - n..x as i64 + n + 1
            }
        };
        (top..bottom, cols)
    }
}

/// The lights' local spacing δ over the sphere: on a lat-long grid in the lights' frame, the
/// square root of the geometric mean of the solid angles of the cells around each texel (each
/// texel's cell by `cell_of`, blurred with a Gaussian of σ `SPACING_SIGMA` over the sphere),
/// looked up bilinearly, so it varies smoothly across the cells' borders.
struct Spacing {
    width: usize,
    height: usize,
    delta: Vec<f32>,
}

impl Spacing {
    fn build(lights: &LightSet) -> Spacing {
        let (width, height) = (SPACING_WIDTH, SPACING_WIDTH / 2);
        if lights.lights.is_empty() {
            // No light resolves anything: the environment everywhere.
            let all = 2.0 * std::f32::consts::PI;
            return Spacing {
                width,
                height,
                delta: vec![all; width * height],
            };
        }
        let src = Source::new(width, height);
        let log_solid: Vec<f32> = src
            .dir
            .iter()
            .map(|&d| {
                let j = lights.cell_of(d) as usize;
                libm::logf(lights.lights[j].solid_angle.max(1e-12))
            })
            .collect();
        let radius = 3.0 * SPACING_SIGMA;
        let cos_radius = libm::cosf(radius);
        let delta = (0..height)
            .into_par_iter()
            .flat_map_iter(|y| {
                let (src, log_solid) = (&src, &log_solid);
                (0..width).map(move |x| {
                    let r = src.dir[y * width + x];
                    let lat = std::f32::consts::FRAC_PI_2
                        - (y as f32 + 0.5) / height as f32 * std::f32::consts::PI;
                    let (rows, cols) = src.window(lat, radius, x);
                    let (mut sum, mut total) = (0.0f32, 0.0f32);
                    for row in rows {
                        for c in cols.clone() {
                            let i = row * width + c.rem_euclid(width as i64) as usize;
                            let cos = r.dot(src.dir[i]);
                            if cos >= cos_radius {
                                let theta = libm::acosf(cos.min(1.0));
                                let g = theta / SPACING_SIGMA;
                                let w = libm::expf(-0.5 * g * g) * src.solid_angle[row];
                                sum += log_solid[i] * w;
                                total += w;
                            }
                        }
                    }
                    let mean = if total > 0.0 {
                        sum / total
                    } else {
                        log_solid[y * width + x]
                    };
                    libm::expf(0.5 * mean)
                })
            })
            .collect();
        Spacing {
            width,
            height,
            delta,
        }
    }

    /// δ along unit direction `dir`: bilinear between texel centres, wrapping in longitude,
    /// clamped at the poles.
    fn at(&self, dir: Vec3) -> f32 {
        let ([x0, x1, y0, y1], tx, ty) = taps(dir_to_uv(dir), self.width, self.height);
        let t = |x: usize, y: usize| self.delta[y * self.width + x];
        let top = t(x0, y0) + (t(x1, y0) - t(x0, y0)) * tx;
        let bottom = t(x0, y1) + (t(x1, y1) - t(x0, y1)) * tx;
        top + (bottom - top) * ty
    }
}

/// `(∫ D Vis cos dω, ∫ D Vis cos w dω)` for every (roughness, n·v) of the table: GGX
/// importance-sampled with a Hammersley set, `l` the reflection of `v` about the sampled
/// half vector, each sample `Vis · 4 (n·l)(v·h)/(n·h)` (D cancels with the density).
fn dfg_table() -> Vec<[f32; 2]> {
    let mut table = Vec::with_capacity(DFG_SIZE * DFG_SIZE);
    for yi in 0..DFG_SIZE {
        let roughness = yi as f32 / (DFG_SIZE - 1) as f32;
        let a = f64::from(alpha(roughness));
        let a2 = a * a;
        for xi in 0..DFG_SIZE {
            let nv = (xi as f64 / (DFG_SIZE - 1) as f64).max(f64::from(crate::brdf::MIN_COS_VIEW));
            let v = [libm::sqrt(1.0 - nv * nv), 0.0, nv];
            let (mut i2, mut i3) = (0.0f64, 0.0f64);
            for k in 0..DFG_SAMPLES {
                let u1 = (f64::from(k) + 0.5) / f64::from(DFG_SAMPLES);
                let u2 = f64::from(k.reverse_bits()) / 4294967296.0;
                // GGX half vectors: tan²θ = α² u / (1 − u).
                let cos_h = libm::sqrt((1.0 - u1) / (1.0 + (a2 - 1.0) * u1));
                let sin_h = libm::sqrt((1.0 - cos_h * cos_h).max(0.0));
                let phi = std::f64::consts::TAU * u2;
                let h = [sin_h * libm::cos(phi), sin_h * libm::sin(phi), cos_h];
                let vh = v[0] * h[0] + v[1] * h[1] + v[2] * h[2];
                let nl = 2.0 * vh * h[2] - v[2];
                if nl <= 0.0 || vh <= 0.0 {
                    continue;
                }
                let vis = 0.5
                    / (nl * libm::sqrt(nv * nv * (1.0 - a2) + a2)
                        + nv * libm::sqrt(nl * nl * (1.0 - a2) + a2));
                let value = vis * 4.0 * nl * vh / cos_h;
                let w = (1.0 - vh).powi(5);
                i2 += value;
                i3 += value * w;
            }
            let n = f64::from(DFG_SAMPLES);
            table.push([(i2 / n) as f32, (i3 / n) as f32]);
        }
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lobe_integrals_of_a_rough_lobe_match_a_quadrature() {
        let table = dfg_table();
        // Brute force over the hemisphere, f64, for a few entries.
        for &(xi, yi) in &[(31usize, 31usize), (16, 20), (8, 12), (24, 31)] {
            let roughness = yi as f32 / 31.0;
            let nv = xi as f64 / 31.0;
            let a = f64::from(alpha(roughness));
            let a2 = a * a;
            let v = [libm::sqrt(1.0 - nv * nv), 0.0, nv];
            let (mut i2, mut i3) = (0.0, 0.0);
            let (nt, np) = (800, 1600);
            for i in 0..nt {
                let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
                for j in 0..np {
                    let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                    let l = [
                        libm::sin(theta) * libm::cos(phi),
                        libm::sin(theta) * libm::sin(phi),
                        libm::cos(theta),
                    ];
                    let dw = libm::sin(theta)
                        * (std::f64::consts::FRAC_PI_2 / nt as f64)
                        * (std::f64::consts::TAU / np as f64);
                    let hs = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
                    let len = libm::sqrt(hs[0] * hs[0] + hs[1] * hs[1] + hs[2] * hs[2]);
                    let h = [hs[0] / len, hs[1] / len, hs[2] / len];
                    let nh = h[2];
                    let vh = v[0] * h[0] + v[1] * h[1] + v[2] * h[2];
                    let nl = l[2];
                    let d = a2 / (std::f64::consts::PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
                    let vis = 0.5
                        / (nl * libm::sqrt(nv * nv * (1.0 - a2) + a2)
                            + nv * libm::sqrt(nl * nl * (1.0 - a2) + a2));
                    i2 += d * vis * nl * dw;
                    i3 += d * vis * nl * dw * (1.0 - vh).powi(5);
                }
            }
            let got = table[yi * DFG_SIZE + xi];
            assert!(
                (f64::from(got[0]) - i2).abs() < 0.01 * i2.max(0.05),
                "({xi}, {yi}): {} vs {i2}",
                got[0]
            );
            assert!(
                (f64::from(got[1]) - i3).abs() < 0.01 * i2.max(0.05),
                "({xi}, {yi}): {} vs {i3}",
                got[1]
            );
        }
    }

    #[test]
    fn a_uniform_map_stays_uniform_at_every_roughness() {
        let env = EnvMap::from_texels(64, 32, vec![Vec3::splat(2.0); 64 * 32], "uniform").unwrap();
        let lights = crate::lights::LightSet::build(&env, 50, crate::lights::Sampler::Sis).unwrap();
        let g = Glossy::build(&env, &lights);
        for r in [0.0, 0.1, 0.2, 0.3, 0.55, 0.8] {
            for d in [Vec3::Y, Vec3::X, Vec3::new(0.3, -0.8, 0.5).normalize()] {
                let got = g.radiance(d, r);
                assert!(
                    (got - Vec3::splat(2.0)).abs().max_element() < 1e-4,
                    "{r} {d}: {got}"
                );
            }
        }
    }

    /// A map of radiance 0.1 with a bright patch around +Z: importance-sampled lights crowd
    /// there.
    fn patch_map() -> EnvMap {
        let (w, h) = (128, 64);
        let texels = (0..w * h)
            .map(|i| {
                let d = uv_to_dir(Vec2::new(
                    ((i % w) as f32 + 0.5) / w as f32,
                    ((i / w) as f32 + 0.5) / h as f32,
                ));
                Vec3::splat(if d.z > 0.9 { 50.0 } else { 0.1 })
            })
            .collect();
        EnvMap::from_texels(w, h, texels, "patch").unwrap()
    }

    #[test]
    fn the_lights_share_rises_with_roughness_and_with_the_lights_density() {
        let env = patch_map();
        let few = crate::lights::LightSet::build(&env, 50, crate::lights::Sampler::Sis).unwrap();
        let many = crate::lights::LightSet::build(&env, 400, crate::lights::Sampler::Sis).unwrap();
        let (g50, g400) = (Glossy::build(&env, &few), Glossy::build(&env, &many));
        let (bright, dim) = (Vec3::Z, Vec3::NEG_Z);
        assert!(
            g400.spacing(bright) < g400.spacing(dim) * 0.5,
            "the lights crowd at the patch: {} vs {}",
            g400.spacing(bright),
            g400.spacing(dim)
        );
        assert!(g400.spacing(dim) < g50.spacing(dim), "more lights, closer");
        for g in [&g50, &g400] {
            for d in [bright, dim] {
                let shares: Vec<f32> = (0..=20)
                    .map(|k| g.split(d, k as f32 / 20.0).lights)
                    .collect();
                assert!(shares.windows(2).all(|p| p[0] <= p[1]), "{shares:?}");
                assert_eq!(shares[0], 0.0, "a mirror takes the environment");
            }
        }
        // A roughness the crowded lights resolve and the sparse ones do not: α just above
        // half the crowded lights' spacing.
        let r = libm::sqrtf(0.5 * g400.spacing(bright) * 1.01);
        assert_eq!(g400.split(bright, r).lights, 1.0);
        assert!(g400.split(dim, r).lights < 0.1, "{:?}", g400.split(dim, r));
        assert_eq!(
            g400.split(dim, 1.0).lights,
            1.0,
            "roughness 1 over 400 lights"
        );
        assert!(Glossy::roughness_bound(&many) < Glossy::roughness_bound(&few));
    }

    #[test]
    fn the_lights_share_has_no_step_at_the_cells_borders() {
        // Along a great circle through the patch and the dim side, in steps of 0.05°: the
        // share moves by a small amount per step wherever it moves (a jump would draw the
        // cells on a glossy surface).
        let env = patch_map();
        let lights =
            crate::lights::LightSet::build(&env, 200, crate::lights::Sampler::Sis).unwrap();
        let g = Glossy::build(&env, &lights);
        for r in [0.2f32, 0.3, 0.4] {
            let mut last = None;
            for k in 0..7200 {
                let a = k as f32 * 0.05f32.to_radians();
                let d = Vec3::new(libm::sinf(a), 0.3, libm::cosf(a)).normalize();
                let s = g.split(d, r).lights;
                if let Some(p) = last {
                    let step: f32 = s - p;
                    assert!(step.abs() < 0.02, "roughness {r}, {k}: {p} → {s}");
                }
                last = Some(s);
            }
        }
    }
}
