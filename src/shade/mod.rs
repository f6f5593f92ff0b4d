//! Shading kernels: which lights are above a surface's horizon, the Lambertian sum over the
//! visible ones (ALGORITHM.md §2), and the glTF metallic-roughness sums (the `brdf` module's),
//! as SSE2/AVX2 kernels that give the same bits as the scalar reference (the lane order is
//! fixed, so neither thread nor tile changes a sum); the point and spot lights' sums, one light
//! at a time. A sample's radiance from them is the `radiance` module's.

pub mod counted;

use glam::Vec3;

use crate::brdf::{Lobe, MAX_DV, Sums, light_terms};
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

/// For each byte value, its eight bits as all-ones / zero lane masks, lowest bit first: a lane
/// outside the set is cleared by a bitwise and, whatever (NaN, infinite) it held.
const BYTE_BITS: [[u32; 8]; 256] = {
    let mut t = [[0u32; 8]; 256];
    let mut v = 0;
    while v < 256 {
        let mut l = 0;
        while l < 8 {
            t[v][l] = if (v >> l) & 1 == 1 { u32::MAX } else { 0 };
            l += 1;
        }
        v += 1;
    }
    t
};

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

/// The metallic-roughness light sums ([`Sums`]) of the point and spot lights whose bits are set
/// in `bits` (light k of `points` has bit `first + k`) at point `p` for `lobe`: each light's
/// irradiance (falloff included, [`PointLight::at`]) in its own direction, one light at a time
/// in light order, as [`point_lights`] sums them for Lambert.
pub fn point_sums(points: &[PointLight], first: usize, p: Vec3, lobe: &Lobe, bits: &[u64]) -> Sums {
    let mut sums = Sums::default();
    for (k, l) in points.iter().enumerate() {
        if !crate::bits::get(bits, first + k) {
            continue;
        }
        let Some(i) = l.at(p) else {
            continue;
        };
        let t = light_terms(lobe, i.dir);
        if t.cos <= 0.0 {
            continue;
        }
        let e = i.irradiance * t.cos;
        sums.s0 += e;
        sums.s1 += e * t.w;
        sums.s2 += e * t.dv;
        sums.s3 += e * (t.dv * t.w);
    }
    sums
}

/// The Lambertian light sum of the last sample shaded with it, so that a sample with the same
/// normal and visible lights — neighbouring samples of a flat or finely tessellated surface
/// mostly have them — is shaded without the per-light loop, to the same bits. One per tile.
#[derive(Clone, Debug, Default)]
pub struct LambertCache {
    n: Vec3,
    bits: Vec<u64>,
    sum: Vec3,
    valid: bool,
}

impl LambertCache {
    /// [`light_sum`] of `n` and `vis`, or the last one's when they are the same.
    pub fn light_sum(&mut self, sl: &ShadeLights, n: Vec3, vis: &[u64]) -> Vec3 {
        if self.valid && same(n, self.n) && self.bits == vis {
            return self.sum;
        }
        self.sum = light_sum(sl, n, vis);
        self.n = n;
        self.bits.clear();
        self.bits.extend_from_slice(vis);
        self.valid = true;
        self.sum
    }
}

/// Clears a lane whose mask bits are zero.
#[inline]
fn and(x: f32, mask: u32) -> f32 {
    f32::from_bits(x.to_bits() & mask)
}

/// The light sums of the metallic-roughness BRDF (`crate::brdf::Sums`) over the lights of
/// `vis` for `lobe`. Eight lights at a time into eight lanes, added in a fixed order, as
/// [`light_sum`].
pub fn specular_sums(sl: &ShadeLights, lobe: &Lobe, vis: &[u64]) -> Sums {
    assert!(vis.len() * 64 <= sl.x.len());
    #[cfg(target_arch = "x86_64")]
    // SAFETY: the light planes hold every light of the bitset (asserted); AVX2 where detected.
    let lanes = unsafe {
        if crate::simd::has_avx2() {
            specular_avx2(sl, lobe, vis)
        } else {
            specular_sse2(sl, lobe, vis)
        }
    };
    #[cfg(not(target_arch = "x86_64"))]
    let lanes = specular_lanes(sl, lobe, vis);
    specular_totals(&lanes)
}

/// The 12 × 8 lane sums of the specular kernels (s0, s1, s2, s3 as r, g, b each) added up:
/// each sum's eight lanes in a fixed order.
fn specular_totals(lanes: &[[f32; 8]; 12]) -> Sums {
    let sum = |a: &[f32; 8]| ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
    let rgb = |k: usize| Vec3::new(sum(&lanes[k]), sum(&lanes[k + 1]), sum(&lanes[k + 2]));
    Sums {
        s0: rgb(0),
        s1: rgb(3),
        s2: rgb(6),
        s3: rgb(9),
    }
}

/// The 12 × 8 lane sums of [`specular_sums`] (s0, s1, s2, s3 as r, g, b each), one light at
/// a time: the reference the SIMD kernels follow operation for operation.
#[cfg_attr(all(target_arch = "x86_64", not(test)), allow(dead_code))]
fn specular_lanes(sl: &ShadeLights, lobe: &Lobe, vis: &[u64]) -> [[f32; 8]; 12] {
    let mut acc = [[0.0f32; 8]; 12];
    for (k, &word) in vis.iter().enumerate() {
        let mut wv = word;
        let mut base = k * 64;
        while wv != 0 {
            let bv = (wv & 0xff) as usize;
            if bv != 0 {
                for l in 0..8 {
                    let j = base + l;
                    let t = light_terms(lobe, Vec3::new(sl.x[j], sl.y[j], sl.z[j]));
                    let mv = BYTE_BITS[bv][l];
                    let (cos, w, dv) = (and(t.cos, mv), and(t.w, mv), and(t.dv, mv));
                    for (c, e) in [&sl.r, &sl.g, &sl.b].into_iter().enumerate() {
                        let ec = e[j] * cos;
                        acc[c][l] += ec;
                        acc[3 + c][l] += ec * w;
                        let ecd = ec * dv;
                        acc[6 + c][l] += ecd;
                        acc[9 + c][l] += ecd * w;
                    }
                }
            }
            wv >>= 8;
            base += 8;
        }
    }
    acc
}

/// [`specular_lanes`] with SSE2, lanes 0–3 and 4–7 in two registers per sum.
///
/// # Safety
/// The light planes hold at least `vis.len() * 64` lights.
#[cfg(target_arch = "x86_64")]
unsafe fn specular_sse2(sl: &ShadeLights, lobe: &Lobe, vis: &[u64]) -> [[f32; 8]; 12] {
    use std::arch::x86_64::*;
    let mut out = [[0.0f32; 8]; 12];
    unsafe {
        let set = _mm_set1_ps;
        let (nx, ny, nz) = (set(lobe.n.x), set(lobe.n.y), set(lobe.n.z));
        let (vx, vy, vz) = (set(lobe.v.x), set(lobe.v.y), set(lobe.v.z));
        let (nv, a2, oma2) = (set(lobe.n_dot_v), set(lobe.a2), set(lobe.one_minus_a2));
        let (kv, c, quarter, one, max_dv) =
            (set(lobe.kv), set(lobe.c), set(0.25), set(1.0), set(MAX_DV));
        let mut acc = [_mm_setzero_ps(); 24];
        for (k, &word) in vis.iter().enumerate() {
            let mut wv = word;
            let mut base = k * 64;
            while wv != 0 {
                let bv = (wv & 0xff) as usize;
                if bv != 0 {
                    for h in 0..2 {
                        let j = base + 4 * h;
                        let ld = |v: &[f32]| _mm_loadu_ps(v.as_ptr().add(j));
                        let mask = |b: usize| {
                            _mm_castsi128_ps(_mm_loadu_si128(
                                BYTE_BITS[b].as_ptr().add(4 * h) as *const __m128i
                            ))
                        };
                        let (lx, ly, lz) = (ld(&sl.x), ld(&sl.y), ld(&sl.z));
                        let (add, sub, mul) = (
                            |a, b| _mm_add_ps(a, b),
                            |a, b| _mm_sub_ps(a, b),
                            |a, b| _mm_mul_ps(a, b),
                        );
                        let cos = add(add(mul(nx, lx), mul(ny, ly)), mul(nz, lz));
                        let (hx, hy, hz) = (add(vx, lx), add(vy, ly), add(vz, lz));
                        let hh = add(add(mul(hx, hx), mul(hy, hy)), mul(hz, hz));
                        let vh = _mm_sqrt_ps(mul(hh, quarter));
                        let t = sub(one, vh);
                        let t2 = mul(t, t);
                        let w = mul(mul(t2, t2), t);
                        let cx = sub(mul(ny, hz), mul(nz, hy));
                        let cy = sub(mul(nz, hx), mul(nx, hz));
                        let cz = sub(mul(nx, hy), mul(ny, hx));
                        let cross = add(add(mul(cx, cx), mul(cy, cy)), mul(cz, cz));
                        let sum = add(nv, cos);
                        let q = add(mul(mul(sum, sum), a2), cross);
                        let kl = _mm_sqrt_ps(add(mul(mul(cos, cos), oma2), a2));
                        let den = mul(mul(q, q), add(mul(cos, kv), mul(nv, kl)));
                        let dv = _mm_div_ps(mul(c, mul(hh, hh)), den);
                        let dv = _mm_min_ps(dv, max_dv);
                        let mv = mask(bv);
                        let (cm, wm, dm) =
                            (_mm_and_ps(cos, mv), _mm_and_ps(w, mv), _mm_and_ps(dv, mv));
                        for (ch, e) in [&sl.r, &sl.g, &sl.b].into_iter().enumerate() {
                            let ec = _mm_mul_ps(ld(e), cm);
                            let a = |k: usize| 2 * k + h;
                            acc[a(ch)] = _mm_add_ps(acc[a(ch)], ec);
                            acc[a(3 + ch)] = _mm_add_ps(acc[a(3 + ch)], _mm_mul_ps(ec, wm));
                            let ecd = _mm_mul_ps(ec, dm);
                            acc[a(6 + ch)] = _mm_add_ps(acc[a(6 + ch)], ecd);
                            acc[a(9 + ch)] = _mm_add_ps(acc[a(9 + ch)], _mm_mul_ps(ecd, wm));
                        }
                    }
                }
                wv >>= 8;
                base += 8;
            }
        }
        for k in 0..12 {
            _mm_storeu_ps(out[k].as_mut_ptr(), acc[2 * k]);
            _mm_storeu_ps(out[k].as_mut_ptr().add(4), acc[2 * k + 1]);
        }
    }
    out
}

/// [`specular_lanes`] with AVX2 (no FMA), eight lanes in one register per sum.
///
/// # Safety
/// As [`specular_sse2`], on a CPU with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn specular_avx2(sl: &ShadeLights, lobe: &Lobe, vis: &[u64]) -> [[f32; 8]; 12] {
    use std::arch::x86_64::*;
    let mut out = [[0.0f32; 8]; 12];
    unsafe {
        let set = |x: f32| _mm256_set1_ps(x);
        let (nx, ny, nz) = (set(lobe.n.x), set(lobe.n.y), set(lobe.n.z));
        let (vx, vy, vz) = (set(lobe.v.x), set(lobe.v.y), set(lobe.v.z));
        let (nv, a2, oma2) = (set(lobe.n_dot_v), set(lobe.a2), set(lobe.one_minus_a2));
        let (kv, c, quarter, one, max_dv) =
            (set(lobe.kv), set(lobe.c), set(0.25), set(1.0), set(MAX_DV));
        let mut acc = [_mm256_setzero_ps(); 12];
        for (k, &word) in vis.iter().enumerate() {
            let mut wv = word;
            let mut base = k * 64;
            while wv != 0 {
                let bv = (wv & 0xff) as usize;
                if bv != 0 {
                    let ld = |v: &[f32]| _mm256_loadu_ps(v.as_ptr().add(base));
                    let mask = |b: usize| {
                        _mm256_castsi256_ps(_mm256_loadu_si256(
                            BYTE_BITS[b].as_ptr() as *const __m256i
                        ))
                    };
                    let (lx, ly, lz) = (ld(&sl.x), ld(&sl.y), ld(&sl.z));
                    let (add, sub, mul) = (
                        |a, b| _mm256_add_ps(a, b),
                        |a, b| _mm256_sub_ps(a, b),
                        |a, b| _mm256_mul_ps(a, b),
                    );
                    let cos = add(add(mul(nx, lx), mul(ny, ly)), mul(nz, lz));
                    let (hx, hy, hz) = (add(vx, lx), add(vy, ly), add(vz, lz));
                    let hh = add(add(mul(hx, hx), mul(hy, hy)), mul(hz, hz));
                    let vh = _mm256_sqrt_ps(mul(hh, quarter));
                    let t = sub(one, vh);
                    let t2 = mul(t, t);
                    let w = mul(mul(t2, t2), t);
                    let cx = sub(mul(ny, hz), mul(nz, hy));
                    let cy = sub(mul(nz, hx), mul(nx, hz));
                    let cz = sub(mul(nx, hy), mul(ny, hx));
                    let cross = add(add(mul(cx, cx), mul(cy, cy)), mul(cz, cz));
                    let sum = add(nv, cos);
                    let q = add(mul(mul(sum, sum), a2), cross);
                    let kl = _mm256_sqrt_ps(add(mul(mul(cos, cos), oma2), a2));
                    let den = mul(mul(q, q), add(mul(cos, kv), mul(nv, kl)));
                    let dv = _mm256_div_ps(mul(c, mul(hh, hh)), den);
                    let dv = _mm256_min_ps(dv, max_dv);
                    let mv = mask(bv);
                    let (cm, wm, dm) = (
                        _mm256_and_ps(cos, mv),
                        _mm256_and_ps(w, mv),
                        _mm256_and_ps(dv, mv),
                    );
                    for (ch, e) in [&sl.r, &sl.g, &sl.b].into_iter().enumerate() {
                        let ec = _mm256_mul_ps(ld(e), cm);
                        acc[ch] = _mm256_add_ps(acc[ch], ec);
                        acc[3 + ch] = _mm256_add_ps(acc[3 + ch], _mm256_mul_ps(ec, wm));
                        let ecd = _mm256_mul_ps(ec, dm);
                        acc[6 + ch] = _mm256_add_ps(acc[6 + ch], ecd);
                        acc[9 + ch] = _mm256_add_ps(acc[9 + ch], _mm256_mul_ps(ecd, wm));
                    }
                }
                wv >>= 8;
                base += 8;
            }
        }
        for k in 0..12 {
            _mm256_storeu_ps(out[k].as_mut_ptr(), acc[k]);
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
    use crate::brdf::Weights;

    #[test]
    fn point_sums_are_the_brdf_of_each_visible_point_light() {
        // Two point lights, the second's bit clear: the sums' radiance is the first light's
        // BRDF × irradiance × cosine (brdf::brdf, the scalar reference), the second adds nothing.
        let m = crate::scene::MaterialSample {
            lambert: false,
            metallic: 0.4,
            roughness: 0.35,
            ..crate::scene::MaterialSample::default()
        };
        let (n, base) = (
            Vec3::new(0.1, 1.0, 0.2).normalize(),
            Vec3::new(0.7, 0.4, 0.2),
        );
        let v = Vec3::new(-0.3, 0.8, 0.5).normalize();
        let p = Vec3::new(0.2, 0.0, -0.1);
        let light = |at: Vec3| PointLight {
            position: at,
            intensity: Vec3::new(2.0, 1.5, 1.0),
            range: f32::INFINITY,
            spot: None,
        };
        let points = [
            light(Vec3::new(1.0, 2.0, 0.5)),
            light(Vec3::new(-1.0, 1.0, 0.0)),
        ];
        let lobe = Lobe::new(n, v, m.roughness);
        let bits = [1u64 << 3];
        let got = Weights::new(base, &m).radiance(&point_sums(&points, 3, p, &lobe, &bits));
        let i = points[0].at(p).unwrap();
        let want = crate::brdf::brdf(n, v, i.dir, base, &m) * i.irradiance * n.dot(i.dir);
        assert!(
            (got - want).abs().max_element() <= 1e-4 * want.max_element(),
            "{got} against {want}"
        );
        let none = point_sums(&points, 3, p, &lobe, &[0]);
        assert_eq!(none, Sums::default());
    }

    /// 200 pseudo-random lights (some below any horizon, unequal energies), padded as for a
    /// frame, and random normals and visibility words.
    pub(super) fn setup() -> (ShadeLights, Vec<(Vec3, [u64; 4])>) {
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

    /// Views from every side of the normal (below its horizon too, as normal maps make them),
    /// roughness from a mirror's to 1.
    fn lobes(n: Vec3, k: usize) -> Vec<Lobe> {
        let views = [
            Vec3::new(0.3, 0.8, 0.5),
            Vec3::new(-0.9, 0.1, 0.2),
            Vec3::new(0.0, -0.3, 1.0),
            n,
            -n,
        ];
        let rough = [0.0, 0.05, 0.3, 0.7, 1.0];
        views
            .iter()
            .map(|v| {
                Lobe::new(
                    n,
                    ((*v + n * 0.5).normalize_or(n)).normalize(),
                    rough[k % 5],
                )
            })
            .collect()
    }

    #[test]
    fn specular_kernels_give_the_reference_lanes_bit_for_bit() {
        let (sl, cases) = setup();
        let bitwise = |a: [[f32; 8]; 12]| a.map(|c| c.map(f32::to_bits));
        for (k, (n, vis)) in cases.iter().enumerate() {
            for lobe in lobes(*n, k) {
                let plain = specular_lanes(&sl, &lobe, vis);
                assert!(plain.iter().flatten().all(|v| v.is_finite()));
                #[cfg(target_arch = "x86_64")]
                {
                    // SAFETY: the planes hold 256 lights, the bitsets cover 256.
                    unsafe {
                        let sse = specular_sse2(&sl, &lobe, vis);
                        assert_eq!(bitwise(sse), bitwise(plain), "case {k}");
                        if std::arch::is_x86_feature_detected!("avx2") {
                            let avx = specular_avx2(&sl, &lobe, vis);
                            assert_eq!(bitwise(avx), bitwise(plain), "case {k}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn the_specular_sums_are_the_brdf_summed_light_by_light() {
        // Against `brdf::brdf` one light at a time (another order of the same products: close,
        // not the same bits).
        let (sl, cases) = setup();
        let base = Vec3::new(0.7, 0.5, 0.2);
        for (k, (n, vis)) in cases.iter().enumerate().take(60) {
            for lobe in lobes(*n, k).into_iter().take(3) {
                let roughness = [0.0, 0.05, 0.3, 0.7, 1.0][k % 5];
                let m = crate::scene::MaterialSample {
                    lambert: false,
                    metallic: [0.0, 1.0, 0.3][k % 3],
                    roughness,
                    ..Default::default()
                };
                let sums = specular_sums(&sl, &lobe, vis);
                let got = Weights::new(base, &m).radiance(&sums);
                let mut want = Vec3::ZERO;
                for j in 0..200 {
                    if vis[j / 64] >> (j % 64) & 1 == 1 {
                        let l = Vec3::new(sl.x[j], sl.y[j], sl.z[j]);
                        let e = Vec3::new(sl.r[j], sl.g[j], sl.b[j]);
                        want += crate::brdf::brdf(*n, lobe.v, l, base, &m) * e * n.dot(l);
                    }
                }
                let err = ((got - want).abs() / want.abs().max(Vec3::splat(1e-3))).max_element();
                assert!(err < 1e-3, "case {k}: {got} vs {want}");
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
