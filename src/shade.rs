//! Shading kernels: which lights are above a surface's horizon, and the Lambertian sum over
//! the visible ones (ALGORITHM.md §2), as SSE2/AVX2 kernels that give the same bits as the
//! scalar reference (the lane order is fixed, so neither thread nor tile changes a sum).

use glam::Vec3;

use crate::lights::{Light, LightSet, PointLight};

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
    /// The set's directional lights, then zero lights in the point and spot lights' places and
    /// up to a whole word (their light comes from [`point_lights`]).
    pub fn new(lights: &LightSet) -> ShadeLights {
        let n = lights.len().div_ceil(64) * 64;
        let pad = |f: &dyn Fn(&Light) -> f32| {
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
pub fn radiance(sl: &ShadeLights, n: Vec3, albedo: Vec3, bits: &[u64]) -> Vec3 {
    reflect(albedo, light_sum(sl, n, bits))
}

/// The radiance a Lambertian surface of `albedo` reflects from the cosine-weighted light
/// [`light_sum`]: [`radiance`] in two steps, so a sum can be shared by surfaces with the same
/// normal and visible lights (the samples of a pixel) for the very same bits.
#[inline]
pub fn reflect(albedo: Vec3, sum: Vec3) -> Vec3 {
    albedo * std::f32::consts::FRAC_1_PI * sum
}

/// The cosine-weighted irradiance at point `p` of normal `n` of the point and spot lights whose bits are
/// set in `bits` (light k of `points` has bit `first + k`): Σ E_k · max(0, N·ω_k), the
/// inverse-square, range and cone falloff in E_k ([`PointLight::at`]). What [`reflect`] turns
/// into Lambertian radiance, as [`light_sum`] is for the directional lights; in light order,
/// one light at a time (a scene file places a handful).
pub fn point_lights(points: &[PointLight], first: usize, p: Vec3, n: Vec3, bits: &[u64]) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for (k, l) in points.iter().enumerate() {
        if !crate::bits::get(bits, first + k) {
            continue;
        }
        if let Some(i) = l.at(p) {
            sum += i.irradiance * n.dot(i.dir).max(0.0);
        }
    }
    sum
}

/// Whether two normals are the same bits (so every kernel gives them the same answer).
#[inline]
pub fn same(a: Vec3, b: Vec3) -> bool {
    a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)
}

/// The cosine-weighted radiance of the lights in `bits` on a surface with normal `n`.
#[inline]
pub fn light_sum(sl: &ShadeLights, n: Vec3, bits: &[u64]) -> Vec3 {
    assert!(bits.len() * 64 <= sl.x.len());
    #[cfg(target_arch = "x86_64")]
    // SAFETY: the light planes hold every light of `bits` (asserted); AVX2 where detected.
    let lanes = unsafe {
        if crate::simd::has_avx2() {
            radiance_avx2(sl, n, bits)
        } else {
            radiance_sse2(sl, n, bits)
        }
    };
    #[cfg(not(target_arch = "x86_64"))]
    let lanes = radiance_lanes(sl, n, bits);
    let sum = |a: [f32; 8]| ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
    Vec3::new(sum(lanes[0]), sum(lanes[1]), sum(lanes[2]))
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
pub fn above_horizon(sl: &ShadeLights, n: Vec3, out: &mut [u64]) {
    above_plane(sl, n, 0.0, out);
}

/// Sets `out`'s bits for the lights with `n·ω > h`: [`above_horizon`] raised to the sine `h`
/// of an elevation above the tangent plane (the lights between are grazing).
#[inline]
pub fn above_plane(sl: &ShadeLights, n: Vec3, h: f32, out: &mut [u64]) {
    let lights = out.len() * 64;
    let (x, y, z) = (&sl.x[..lights], &sl.y[..lights], &sl.z[..lights]);
    #[cfg(target_arch = "x86_64")]
    {
        if crate::simd::has_avx2() {
            // SAFETY: AVX2 was detected; the slices hold `out.len() * 64` lights.
            unsafe { above_horizon_avx2(x, y, z, n, h, out) };
        } else {
            // SAFETY: as above (SSE2 is part of x86_64).
            unsafe { above_horizon_sse2(x, y, z, n, h, out) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    for (k, word) in out.iter_mut().enumerate() {
        let mut bits = 0u64;
        for l in 0..64 {
            let j = k * 64 + l;
            let d = n.x * x[j] + n.y * y[j] + n.z * z[j];
            bits |= u64::from(d > h) << l;
        }
        *word = bits;
    }
}

/// The lights a surface point can receive: above the horizon of its shading normal `n` (the
/// cosine that shades them is positive) and of its facet's normal `ng`. [ours] A light below
/// the facet's plane reaches only the facet's other side: tracing it from this side finds the
/// facet itself (or the closed mesh behind it), so it is blocked by definition, not a query.
/// Where interpolated normals tilt past the facet (the shading terminator of coarse meshes)
/// those lights were grazing queries on which neighbouring facets' votes disagreed.
#[inline]
pub fn above_both_horizons(sl: &ShadeLights, n: Vec3, ng: Vec3, out: &mut [u64]) {
    above_horizon(sl, n, out);
    if !same(n, ng) {
        let mut g = [0u64; crate::limits::MAX_LIGHTS / 64];
        let g = &mut g[..out.len()];
        above_horizon(sl, ng, g);
        for (o, g) in out.iter_mut().zip(g.iter()) {
            *o &= g;
        }
    }
}

/// # Safety
/// `x`, `y`, `z` hold at least `out.len() * 64` values.
#[cfg(target_arch = "x86_64")]
unsafe fn above_horizon_sse2(x: &[f32], y: &[f32], z: &[f32], n: Vec3, h: f32, out: &mut [u64]) {
    use std::arch::x86_64::*;
    unsafe {
        let (nx, ny, nz) = (_mm_set1_ps(n.x), _mm_set1_ps(n.y), _mm_set1_ps(n.z));
        let zero = _mm_set1_ps(h);
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
unsafe fn above_horizon_avx2(x: &[f32], y: &[f32], z: &[f32], n: Vec3, h: f32, out: &mut [u64]) {
    use std::arch::x86_64::*;
    unsafe {
        let (nx, ny, nz) = (
            _mm256_set1_ps(n.x),
            _mm256_set1_ps(n.y),
            _mm256_set1_ps(n.z),
        );
        let zero = _mm256_set1_ps(h);
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
                unsafe { above_horizon_sse2(x, y, z, *n, 0.0, &mut out) };
                assert_eq!(out, reference);
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: as above, and AVX2 was detected.
                    unsafe { above_horizon_avx2(x, y, z, *n, 0.0, &mut out) };
                    assert_eq!(out, reference);
                }
            }
        }
    }

    #[test]
    fn lights_below_the_facet_are_not_received_whatever_the_shading_normal() {
        let (sl, _) = setup();
        // A shading normal tilted 30° past its facet's (the terminator of a coarse mesh).
        let ng = Vec3::Z;
        let n = Vec3::new(0.5, 0.0, 0.866).normalize();
        let mut out = [0u64; 4];
        above_both_horizons(&sl, n, ng, &mut out);
        let (mut received, mut tilted) = (0, 0);
        for j in 0..256 {
            let d = Vec3::new(sl.x[j], sl.y[j], sl.z[j]);
            let want = n.dot(d) > 0.0 && ng.dot(d) > 0.0;
            assert_eq!(out[j / 64] >> (j % 64) & 1 == 1, want, "light {j}");
            received += u32::from(want);
            tilted += u32::from(n.dot(d) > 0.0 && ng.dot(d) <= 0.0);
        }
        assert!(
            received > 0 && tilted > 0,
            "the case must have both kinds of light"
        );
        // The same normal for both: the shading normal's horizon alone.
        let mut alone = [0u64; 4];
        above_horizon(&sl, n, &mut alone);
        above_both_horizons(&sl, n, n, &mut out);
        assert_eq!(out, alone);
    }
}
