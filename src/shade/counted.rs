//! Shading kernels for a group of samples that share one surface (decoupled shading: the
//! pixel shading rate). Each light's unshadowed terms are evaluated
//! once, for the group's lobe, and weighted by how many of the group's samples see the light
//! — counts over the samples' bit rows — instead of once per sample: `Σ_j f_j · c_j` rather
//! than `Σ_s Σ_j f_j(s) · V_sj`.
//!
//! The lanes are those of the per-sample kernels (lane l sums the lights j ≡ l mod 8 in
//! increasing order, the lanes added in a fixed order at the end), and one member's counts
//! are its bits, so a group of one sample gets the per-sample kernels' very bits. The body is
//! written once over eight-lane arrays and compiled twice, for baseline x86-64 and with AVX2
//! (the same operations in the same order, never fused multiply-adds): either copy gives the
//! same bits, whatever the host.

use glam::Vec3;

use super::{BYTE_MASK, ShadeLights, specular_totals};
use crate::bits::Rows;
use crate::brdf::{Lobe, Sums, light_terms};

/// The lights (one byte of word `k`, at `shift`) any row has.
#[inline(always)]
fn any(rows: Rows, k: usize) -> u64 {
    let mut any = 0;
    for m in 0..rows.len() {
        any |= rows.word(m, k);
    }
    any
}

/// How many rows have each of the eight lights of word `k`'s byte at `shift`.
#[inline(always)]
fn counts(rows: Rows, k: usize, shift: u32) -> [f32; 8] {
    let mut c = [0.0f32; 8];
    for m in 0..rows.len() {
        let mask = &BYTE_MASK[((rows.word(m, k) >> shift) & 0xff) as usize];
        for l in 0..8 {
            c[l] += mask[l];
        }
    }
    c
}

/// Eight consecutive lights from `base` of one of [`ShadeLights`]' planes.
#[inline(always)]
fn lanes(plane: &[f32], base: usize) -> &[f32; 8] {
    plane[base..base + 8].try_into().unwrap()
}

/// The metallic-roughness light sums ([`Sums`]) of the group's visible lights for `lobe`, each
/// light's terms counted once per member that sees it. Lights below the lobe's own horizon
/// add nothing, whatever the members' horizons.
pub fn counted_specular(sl: &ShadeLights, lobe: &Lobe, vis: Rows) -> Sums {
    assert!(vis.words() * 64 <= sl.x.len());
    #[cfg(target_arch = "x86_64")]
    // SAFETY: AVX2 where detected.
    let lanes = unsafe {
        if crate::simd::has_avx2() {
            specular_avx2(sl, lobe, vis)
        } else {
            specular_body(sl, lobe, vis)
        }
    };
    #[cfg(not(target_arch = "x86_64"))]
    let lanes = specular_body(sl, lobe, vis);
    specular_totals(&lanes)
}

/// The light terms of eight lights for `lobe` ([`light_terms`]), with `cos` and `D · Vis` set
/// to 0 where the light is below the lobe's horizon (so a count times them is 0, never 0 · ∞).
#[inline(always)]
fn terms(sl: &ShadeLights, lobe: &Lobe, base: usize) -> ([f32; 8], [f32; 8], [f32; 8]) {
    let (x, y, z) = (lanes(&sl.x, base), lanes(&sl.y, base), lanes(&sl.z, base));
    let (mut cos, mut w, mut dv) = ([0.0f32; 8], [0.0f32; 8], [0.0f32; 8]);
    for l in 0..8 {
        let t = light_terms(lobe, Vec3::new(x[l], y[l], z[l]));
        let up = t.cos > 0.0;
        cos[l] = if up { t.cos } else { 0.0 };
        w[l] = t.w;
        dv[l] = if up { t.dv } else { 0.0 };
    }
    (cos, w, dv)
}

/// [`counted_specular`]'s 12 × 8 lanes (s0, s1, s2, s3 as r, g, b each).
#[inline(always)]
fn specular_body(sl: &ShadeLights, lobe: &Lobe, vis: Rows) -> [[f32; 8]; 12] {
    let mut acc = [[0.0f32; 8]; 12];
    for k in 0..vis.words() {
        let any = any(vis, k);
        for b in 0..8u32 {
            let shift = 8 * b;
            if (any >> shift) & 0xff == 0 {
                continue;
            }
            let base = k * 64 + 8 * b as usize;
            let cv = counts(vis, k, shift);
            let (cos, w, dv) = terms(sl, lobe, base);
            for (ch, e) in [&sl.r, &sl.g, &sl.b].into_iter().enumerate() {
                let e = lanes(e, base);
                for l in 0..8 {
                    let ec = e[l] * (cos[l] * cv[l]);
                    acc[ch][l] += ec;
                    acc[3 + ch][l] += ec * w[l];
                    let ecd = ec * dv[l];
                    acc[6 + ch][l] += ecd;
                    acc[9 + ch][l] += ecd * w[l];
                }
            }
        }
    }
    acc
}

/// [`specular_body`] compiled with AVX2.
///
/// # Safety
/// The CPU has AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn specular_avx2(sl: &ShadeLights, lobe: &Lobe, vis: Rows) -> [[f32; 8]; 12] {
    specular_body(sl, lobe, vis)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(bits: &[[u64; 4]]) -> Vec<u64> {
        bits.iter().flatten().copied().collect()
    }

    fn bitwise(s: &Sums) -> [u32; 12] {
        let v = [s.s0, s.s1, s.s2, s.s3];
        std::array::from_fn(|i| v[i / 3].to_array()[i % 3].to_bits())
    }

    #[test]
    fn a_group_of_one_sample_gets_the_per_sample_kernels_bits() {
        let (sl, cases) = crate::shade::tests::setup();
        for (i, (n, bits)) in cases.iter().enumerate() {
            let v = Vec3::new(0.2, 0.5, 0.8).normalize();
            let lobe = Lobe::new(*n, v, 0.1 + (i % 9) as f32 * 0.1);
            let one = crate::bits::rows(bits, 4);
            let want = crate::shade::specular_sums(&sl, &lobe, bits);
            let got = counted_specular(&sl, &lobe, one);
            assert_eq!(bitwise(&got), bitwise(&want), "case {i}");
        }
    }

    #[test]
    fn counts_sum_the_members_lights_and_skip_those_below_the_lobes_horizon() {
        let (sl, cases) = crate::shade::tests::setup();
        let lobe = Lobe::new(cases[0].0, Vec3::new(0.3, 0.3, 0.9).normalize(), 0.4);
        // Every member's own bits, cut to the lobe's horizon: the group's sums are the sum of
        // the members' sums (to rounding).
        let mut up = [0u64; 4];
        crate::shade::above_horizon(&sl, lobe.n, &mut up);
        let members: Vec<[u64; 4]> = cases[..16]
            .iter()
            .map(|(_, b)| std::array::from_fn(|k| b[k] & up[k]))
            .collect();
        let flat = rows(&members);
        let got = counted_specular(&sl, &lobe, crate::bits::rows(&flat, 4));
        let mut want = Sums::default();
        for m in &members {
            let s = crate::shade::specular_sums(&sl, &lobe, m);
            want.s0 += s.s0;
            want.s1 += s.s1;
            want.s2 += s.s2;
            want.s3 += s.s3;
        }
        for (g, w) in [(got.s0, want.s0), (got.s2, want.s2), (got.s3, want.s3)] {
            assert!(
                (g - w).abs().max_element() <= 1e-5 * w.max_element(),
                "{g} {w}"
            );
        }
        // The members' own bits, lights below the lobe's horizon included: those add nothing.
        let raw = rows(&cases[..16].iter().map(|c| c.1).collect::<Vec<_>>());
        let all = counted_specular(&sl, &lobe, crate::bits::rows(&raw, 4));
        assert_eq!(bitwise(&all), bitwise(&got));
    }

    #[test]
    fn both_copies_of_the_counted_kernels_give_the_same_bits() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let (sl, cases) = crate::shade::tests::setup();
            let members: Vec<[u64; 4]> = cases.iter().map(|c| c.1).collect();
            for (i, group) in members.chunks(7).enumerate() {
                let flat = rows(group);
                let r = crate::bits::rows(&flat, 4);
                let lobe = Lobe::new(cases[i].0, Vec3::Z, 0.05 + (i % 7) as f32 * 0.15);
                let base = specular_body(&sl, &lobe, r);
                // SAFETY: AVX2 was detected.
                let avx = unsafe { specular_avx2(&sl, &lobe, r) };
                assert_eq!(
                    base.map(|l| l.map(f32::to_bits)),
                    avx.map(|l| l.map(f32::to_bits))
                );
            }
        }
    }
}
