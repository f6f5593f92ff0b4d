//! The visible share of a glossy lobe, measured by rays traced into it.
//!
//! Where the lights are too sparse for a lobe, its specular is the prefiltered environment
//! ([`crate::glossy`]) times the share of the lobe's light that reaches the sample unblocked.
//! [ours] That share is measured by a few rays drawn from the lobe itself, from each sample's
//! own point, not by the light set's visibility bits: the bits hold a light every δ (0.25 rad
//! at 200 lights), so a lobe narrower than that sees its occluders — a neighbouring object, the
//! ground a mirror reflects — only as the blur of a lobe wide enough to hold a few lights, and a
//! mirror reflects the room around an object it should hide (BENCHMARKS.md, issue 42). The rays
//! are a fixed Hammersley set turned by a hash of the sample's point: the same bits whatever the
//! tiles, threads or hosts, and no pattern repeated between neighbouring samples.

use glam::Vec3;

use crate::accel::PACKET;
use crate::brdf::Lobe;
use crate::context::{FrameContext, Surface};
use crate::glossy::Glossy;
use crate::scene::AlphaTest;

/// [ours] Rays per sample into a lobe of α at least `WIDE_ALPHA`; one below it, where the lobe
/// is so narrow that its rays would all leave along the mirror direction. Measured against the
/// converged reference (BENCHMARKS.md, "Glossy reflections see their occluders"): 2 rays left
/// more error on rough metal, 8 no less than 4.
pub const RAYS: usize = 4;
pub const WIDE_ALPHA: f32 = 0.01;
/// [ours] Each ray looks the map up prefiltered at the lobe's roughness times `rays^-FILTER`:
/// the share of the lobe one ray stands for (Křivánek and Colbert's filtered importance
/// sampling), so that a bright lamp inside the lobe weighs the rays that pass near it, not only
/// the one that hits it.
const FILTER: f32 = 0.25;

/// The rays a group of samples sharing one lobe (a pixel's at the pixel shading rate, or one
/// sample alone) sends into it: [`RAYS`] in all (one for a mirror), shared out among the
/// members, at least one each — one Hammersley set over the group, turned by a hash of the
/// first member's point, member m taking its points `m·per .. (m + 1)·per`.
pub struct RaySet {
    /// Two unit vectors completing the lobe's normal to a basis.
    tangents: (Vec3, Vec3),
    per: usize,
    of: usize,
    turn: (f32, f32),
    looked_up: f32,
}

impl RaySet {
    /// The set for `members` samples (the first at `lead`) sharing `lobe` of `roughness`
    /// ([`lobe_light`] takes the same lobe).
    pub fn new(lobe: &Lobe, roughness: f32, members: usize, lead: Vec3) -> RaySet {
        let total = if lobe.a2 < WIDE_ALPHA * WIDE_ALPHA {
            1
        } else {
            RAYS
        };
        let members = members.max(1);
        let per = total.div_ceil(members).min(PACKET);
        let of = per * members;
        RaySet {
            tangents: basis(lobe.n),
            per,
            of,
            turn: rotation(lead),
            looked_up: roughness * libm::powf(of as f32, -FILTER),
        }
    }
}

/// Of the environment's light in `lobe`, the part member `member` of `set` finds reaching it
/// unblocked, and the part its rays stand for, `(open, all)`: rays from `s.origin` along
/// directions drawn from the lobe, each weighted by its part of the lobe's integral and by the
/// map's (filtered) radiance along it. The group's share is Σ open ÷ Σ all — the split sum's
/// environment light times it then darkens where a bright part of the map is hidden, not where
/// a dim one is. Directions below the surface's own horizon count as blocked (the surface
/// itself is in the way).
pub fn lobe_light(
    ctx: &FrameContext,
    g: &Glossy,
    s: &Surface,
    lobe: &Lobe,
    set: &RaySet,
    member: usize,
) -> (f32, f32) {
    let a2 = lobe.a2;
    let (t, b) = set.tangents;
    let (r1, r2) = set.turn;
    let mut dirs = [Vec3::ZERO; PACKET];
    let mut light = [0.0f32; PACKET];
    let (mut k, mut below) = (0, 0.0f32);
    for i in member * set.per..(member + 1) * set.per {
        // The Hammersley point i of the set, turned (Cranley–Patterson).
        let u1 = fract((i as f32 + 0.5) / set.of as f32 + r1);
        let u2 = fract(radical_inverse(i as u32) + r2);
        // A GGX half vector (tan²θ = α² u / (1 − u)) and the reflection of v about it.
        let cos_h = libm::sqrtf((1.0 - u1) / (1.0 + (a2 - 1.0) * u1));
        let sin_h = libm::sqrtf((1.0 - cos_h * cos_h).max(0.0));
        let phi = std::f32::consts::TAU * u2;
        let h = t * (sin_h * libm::cosf(phi)) + b * (sin_h * libm::sinf(phi)) + lobe.n * cos_h;
        let vh = lobe.v.dot(h);
        let l = h * (2.0 * vh) - lobe.v;
        let nl = lobe.n.dot(l);
        if nl <= 0.0 || vh <= 0.0 {
            // Outside the lobe's hemisphere: no part of its integral.
            continue;
        }
        // Its part of the lobe's integral, D Vis cos over the half vectors' density
        // (4 Vis (n·l)(v·h)/(n·h), as `crate::glossy`'s table sums), times the light there.
        let w = 2.0 * nl * vh / (cos_h * (nl * lobe.kv + lobe.n_dot_v * kl(nl, a2)));
        let y = w * crate::envmap::luminance(g.radiance(ctx.unturned(l), set.looked_up));
        if s.ng.dot(l) <= 0.0 {
            below += y;
            continue;
        }
        dirs[k] = l;
        light[k] = y;
        k += 1;
    }
    let all = light[..k].iter().sum::<f32>() + below;
    if k == 0 {
        return (0.0, all);
    }
    crate::raydump::record_packet(s.origin, &dirs[..k]);
    let blocked = ctx.accel.occluded_packet_within(
        s.origin,
        &dirs[..k],
        &[f32::INFINITY; PACKET],
        &AlphaTest::shadow(ctx.scene),
    );
    let open: f32 = (0..k)
        .filter(|&r| blocked & (1 << r) == 0)
        .map(|r| light[r])
        .sum();
    (open, all)
}

/// `sqrt((n·l)² (1 − α²) + α²)`: the light's half of the height-correlated Smith term.
#[inline]
fn kl(nl: f32, a2: f32) -> f32 {
    libm::sqrtf(nl * nl * (1.0 - a2) + a2)
}

#[inline]
fn fract(x: f32) -> f32 {
    x - libm::floorf(x)
}

/// Van der Corput's radical inverse in base 2, in [0, 1).
#[inline]
fn radical_inverse(i: u32) -> f32 {
    (i.reverse_bits() >> 8) as f32 / (1u32 << 24) as f32
}

/// Two numbers in [0, 1) from the bits of point `p`: the turn of a sample's Hammersley set.
fn rotation(p: Vec3) -> (f32, f32) {
    let mut h = (u64::from(p.x.to_bits()) << 32 | u64::from(p.y.to_bits()))
        ^ u64::from(p.z.to_bits()).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    // splitmix64's finaliser.
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^= h >> 31;
    let unit = |bits: u64| (bits >> 40) as f32 / (1u64 << 24) as f32;
    (unit(h), unit(h << 24))
}

/// Two unit vectors completing unit `n` to an orthonormal basis (Duff et al. 2017).
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_basis_is_orthonormal_for_every_normal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, 0.866).normalize(),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
        ] {
            let (t, b) = basis(n);
            for (u, w) in [(t, b), (t, n), (b, n)] {
                assert!(u.dot(w).abs() < 1e-5, "{n}: {u} · {w}");
            }
            for u in [t, b] {
                assert!((u.length() - 1.0).abs() < 1e-5, "{n}: |{u}|");
            }
        }
    }

    #[test]
    fn the_turn_of_the_sample_set_covers_the_unit_square_and_is_the_points_own() {
        let mut cells = [0u32; 16];
        for i in 0..4096 {
            let p = Vec3::new(i as f32 * 0.013, 1.0 - i as f32 * 0.007, 0.5);
            let (a, b) = rotation(p);
            assert!((0.0..1.0).contains(&a) && (0.0..1.0).contains(&b));
            assert_eq!(rotation(p), (a, b));
            cells[(a * 4.0) as usize * 4 + (b * 4.0) as usize] += 1;
        }
        // 256 expected per cell; a hash that ignored a coordinate or a bit half would not fill them.
        assert!(cells.iter().all(|&c| (180..340).contains(&c)), "{cells:?}");
    }
}
