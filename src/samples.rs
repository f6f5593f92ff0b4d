//! Where a pixel's samples lie (`--spp`): a k×k stratified pattern, each stratum jittered by a
//! hash of (pixel, sample index) — never random state, so the same on every tile, thread,
//! process and host — then warped through the reconstruction filter's inverse CDF.
//!
//! The filter is importance-sampled, as pbrt-v4 and Cycles do: a sample's offset from its
//! pixel's centre follows the filter's distribution, so every sample of a pixel counts with
//! weight one and the pixel is their mean. The filter's support still crosses pixel (and tile)
//! borders — a sample may land in the neighbouring pixel's area — but no pixel reads another
//! pixel's samples, so tiled frames stay bit-identical to the whole frame. With one sample the
//! offset is zero: the pixel centre, whatever the filter.
//!
//! The filters are separable (a product of one 1D filter in x and one in y), non-negative, and
//! follow Cycles' definitions: `width` is the full support in pixels.

use std::fmt;
use std::str::FromStr;

/// A pixel reconstruction filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// Uniform over the pixel (width 1): the sharpest, and the most aliased.
    Box,
    /// A tent, `1 − |x| / (width/2)` (width 2).
    Triangle,
    /// Cycles' Gaussian, `exp(−2 (6x / width)²)` (width 1.5).
    Gaussian,
    /// Blackman-Harris (width 1.5), Cycles' default: smooth with negligible ringing, so edges
    /// are anti-aliased without the blur of a wide Gaussian or the jaggies of a box.
    #[default]
    BlackmanHarris,
}

impl Filter {
    pub const ALL: [Filter; 4] = [
        Filter::Box,
        Filter::Triangle,
        Filter::Gaussian,
        Filter::BlackmanHarris,
    ];

    /// The name on the command line and in specs.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Triangle => "triangle",
            Filter::Gaussian => "gaussian",
            Filter::BlackmanHarris => "blackman-harris",
        }
    }

    /// The width (full support, pixels) used when none is given.
    pub fn default_width(self) -> f32 {
        match self {
            Filter::Box => 1.0,
            Filter::Triangle => 2.0,
            Filter::Gaussian | Filter::BlackmanHarris => 1.5,
        }
    }

    /// The 1D filter at `x` pixels from the centre, for support `width` (not normalised).
    fn weight(self, x: f64, width: f64) -> f64 {
        let t = x / width; // in [-1/2, 1/2] on the support
        if t.abs() > 0.5 {
            return 0.0;
        }
        match self {
            Filter::Box => 1.0,
            Filter::Triangle => 1.0 - 2.0 * t.abs(),
            Filter::Gaussian => libm::exp(-2.0 * (6.0 * t) * (6.0 * t)),
            Filter::BlackmanHarris => {
                let v = 2.0 * std::f64::consts::PI * (t + 0.5);
                0.35875 - 0.48829 * libm::cos(v) + 0.14128 * libm::cos(2.0 * v)
                    - 0.01168 * libm::cos(3.0 * v)
            }
        }
    }
}

impl fmt::Display for Filter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Filter {
    type Err = String;
    fn from_str(s: &str) -> Result<Filter, String> {
        Filter::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                format!("unknown filter {s:?}; expected box, triangle, gaussian or blackman-harris")
            })
    }
}

/// Points of the tabulated inverse CDF: offsets are interpolated between them.
const TABLE: usize = 1024;

/// The sample pattern of a frame's pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct Samples {
    /// Samples per pixel side: `k × k` samples per pixel.
    pub k: u32,
    pub filter: Filter,
    /// Full support of the filter, pixels.
    pub width: f32,
    /// The 1D filter's inverse CDF at `TABLE + 1` evenly spaced probabilities from 0 to 1.
    inverse: Vec<f32>,
}

impl Samples {
    /// `spp` samples per pixel (a square) with `filter` of support `width` pixels (0: the
    /// filter's default).
    pub fn new(spp: u32, filter: Filter, width: f32) -> Samples {
        let k = (spp as f64).sqrt().round().max(1.0) as u32;
        let width = if width > 0.0 {
            width
        } else {
            filter.default_width()
        };
        Samples {
            k,
            filter,
            width,
            inverse: inverse_cdf(filter, f64::from(width)),
        }
    }

    /// One sample per pixel, at its centre.
    pub fn one() -> Samples {
        Samples::new(1, Filter::default(), 0.0)
    }

    /// Samples per pixel.
    pub fn spp(&self) -> u32 {
        self.k * self.k
    }

    /// The offset from pixel (x, y)'s centre, in pixels, of its sample in stratum (i, j)
    /// (column i, row j of the k × k strata, each below k): a pure function of its arguments.
    #[inline]
    pub fn offset(&self, x: u32, y: u32, i: u32, j: u32) -> (f32, f32) {
        if self.k == 1 {
            return (0.0, 0.0);
        }
        let index = j * self.k + i;
        let (jx, jy) = jitter(x, y, index);
        let k = self.k as f32;
        let u = (i as f32 + jx) / k;
        let v = (j as f32 + jy) / k;
        (self.warp(u), self.warp(v))
    }

    /// The filter's inverse CDF at probability `u` in [0, 1).
    #[inline]
    fn warp(&self, u: f32) -> f32 {
        let t = u * TABLE as f32;
        let m = (t as usize).min(TABLE - 1);
        let f = t - m as f32;
        self.inverse[m] + (self.inverse[m + 1] - self.inverse[m]) * f
    }
}

/// Two numbers in [0, 1) for sample `index` of pixel (x, y): the stratum's jitter.
#[inline]
fn jitter(x: u32, y: u32, index: u32) -> (f32, f32) {
    let h = mix(mix((u64::from(y) << 32) | u64::from(x)) ^ u64::from(index));
    // 24 bits each: exactly representable as f32 fractions below 1.
    let a = (h >> 40) as f32 / (1u32 << 24) as f32;
    let b = ((h >> 8) & 0xff_ffff) as f32 / (1u32 << 24) as f32;
    (a, b)
}

/// splitmix64's finaliser: a well-mixed 64-bit hash of `z`.
#[inline]
fn mix(z: u64) -> u64 {
    let mut z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The inverse CDF of the 1D filter over its support, at `TABLE + 1` probabilities: the CDF
/// integrated (trapezoids, f64) on a grid eight times finer, then inverted by linear
/// interpolation. Every operation is IEEE arithmetic or the pure-Rust `libm`, so the table is
/// the same on every host.
fn inverse_cdf(filter: Filter, width: f64) -> Vec<f32> {
    let n = 8 * TABLE;
    let r = width / 2.0;
    let xs: Vec<f64> = (0..=n).map(|s| -r + width * s as f64 / n as f64).collect();
    let mut cdf = vec![0.0f64; n + 1];
    for s in 1..=n {
        let (a, b) = (filter.weight(xs[s - 1], width), filter.weight(xs[s], width));
        cdf[s] = cdf[s - 1] + 0.5 * (a + b) * (xs[s] - xs[s - 1]);
    }
    let total = cdf[n];
    let mut out = Vec::with_capacity(TABLE + 1);
    let mut s = 0;
    for m in 0..=TABLE {
        let u = m as f64 / TABLE as f64 * total;
        while s < n && cdf[s + 1] < u {
            s += 1;
        }
        let x = if s >= n {
            r
        } else {
            let span = cdf[s + 1] - cdf[s];
            let f = if span > 0.0 { (u - cdf[s]) / span } else { 0.0 };
            xs[s] + f * (xs[s + 1] - xs[s])
        };
        out.push(x as f32);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_is_the_pixel_centre_whatever_the_filter() {
        for f in Filter::ALL {
            let s = Samples::new(1, f, 0.0);
            assert_eq!(s.offset(3, 7, 0, 0), (0.0, 0.0), "{f}");
        }
    }

    #[test]
    fn the_pattern_is_a_pure_function_of_pixel_and_index() {
        let a = Samples::new(16, Filter::BlackmanHarris, 0.0);
        let b = Samples::new(16, Filter::BlackmanHarris, 0.0);
        // Any order of asking gives the same offsets.
        let mut forward = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                forward.push(a.offset(5, 9, i, j));
            }
        }
        let mut backward = Vec::new();
        for j in (0..4).rev() {
            for i in (0..4).rev() {
                backward.push(b.offset(5, 9, i, j));
            }
        }
        backward.reverse();
        assert_eq!(forward, backward);
        // Different pixels and indices give different jitter.
        assert_ne!(a.offset(5, 9, 1, 1), a.offset(6, 9, 1, 1));
        assert_ne!(jitter(5, 9, 0), jitter(5, 9, 1));
    }

    #[test]
    fn box_strata_cover_the_pixel_one_sample_each() {
        let s = Samples::new(16, Filter::Box, 0.0);
        for (x, y) in [(0, 0), (17, 3), (640, 480)] {
            for j in 0..4 {
                for i in 0..4 {
                    let (dx, dy) = s.offset(x, y, i, j);
                    // Stratum (i, j) of the pixel [-1/2, 1/2)², within interpolation error.
                    let (lx, ly) = (i as f32 / 4.0 - 0.5, j as f32 / 4.0 - 0.5);
                    assert!(dx >= lx - 1e-5 && dx < lx + 0.25 + 1e-5, "{i} {dx}");
                    assert!(dy >= ly - 1e-5 && dy < ly + 0.25 + 1e-5, "{j} {dy}");
                }
            }
        }
    }

    #[test]
    fn offsets_follow_the_filter_within_its_support() {
        for f in Filter::ALL {
            let s = Samples::new(64, f, 0.0);
            let r = s.width / 2.0;
            let (mut sum, mut sum2, mut n) = (0.0f64, 0.0f64, 0usize);
            for y in 0..40 {
                for x in 0..40 {
                    for j in 0..8 {
                        for i in 0..8 {
                            let (dx, dy) = s.offset(x, y, i, j);
                            assert!(dx.abs() <= r + 1e-6 && dy.abs() <= r + 1e-6, "{f}");
                            sum += f64::from(dx);
                            sum2 += f64::from(dx) * f64::from(dx);
                            n += 1;
                        }
                    }
                }
            }
            let mean = sum / n as f64;
            let var = sum2 / n as f64;
            // The filter's own variance, by numerical integration.
            let (mut w, mut wx2) = (0.0f64, 0.0f64);
            for m in 0..10_000 {
                let x = -f64::from(r) + f64::from(s.width) * (m as f64 + 0.5) / 10_000.0;
                let v = f.weight(x, f64::from(s.width));
                w += v;
                wx2 += v * x * x;
            }
            let want = wx2 / w;
            assert!(mean.abs() < 0.01, "{f}: mean {mean}");
            assert!(
                (var - want).abs() < 0.05 * want,
                "{f}: variance {var} vs {want}"
            );
        }
    }

    #[test]
    fn filters_parse_by_name() {
        for f in Filter::ALL {
            assert_eq!(f.name().parse::<Filter>(), Ok(f));
        }
        assert!(
            "lanczos"
                .parse::<Filter>()
                .unwrap_err()
                .contains("blackman-harris")
        );
    }
}
