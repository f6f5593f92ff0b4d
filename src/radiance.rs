//! A sample's radiance (its background aside): its material — Lambertian, or glTF
//! metallic-roughness (`crate::brdf`) — over the visible lights of its bitset, with the glossy
//! environment (`crate::glossy`) where the lights are too few for the lobe, the scene file's
//! point and spot lights, occlusion and emission. The sums themselves are `crate::shade`'s
//! kernels.

use glam::Vec3;

use crate::brdf::{Lobe, Weights};
use crate::context::{FrameContext, Surface};
use crate::shade::{LambertCache, point_lights, point_sums, reflect, specular_sums};

/// A sample's radiance (its background aside): the visible lights in `vis` (those above its
/// horizon in `above`) reflected by its material — Lambertian, or glTF metallic-roughness
/// (`crate::brdf`) with, where `ctx.glossy` says the lights are too few for the lobe, the
/// prefiltered environment weighted by the lobe's visible fraction — times its occlusion,
/// plus the scene file's point and spot lights in `vis` (the same BRDF, exact: one light at a
/// time; occlusion is the environment's only), plus its emission. Lambertian samples with the
/// normal and visible lights of the last one `cache` saw reuse its light sum (the same bits).
pub fn radiance_at(
    ctx: &FrameContext,
    s: &Surface,
    vis: &[u64],
    above: &[u64],
    cache: &mut LambertCache,
) -> Vec3 {
    let sl = &ctx.shade_lights;
    let m = &s.material;
    let points = ctx.has_points();
    let first = ctx.light_dir.len();
    let mut lit = if m.lambert {
        let sum = cache.light_sum(sl, s.n, vis);
        if points && m.occlusion == 1.0 {
            // The Lambertian sum over every light, as main shades point lights.
            return reflect(
                s.albedo,
                sum + point_lights(&ctx.lights.points, first, s.p, s.n, vis),
            ) + m.emission;
        }
        reflect(s.albedo, sum)
    } else {
        metallic_roughness(ctx, s, vis, above)
    };
    // Occlusion darkens the environment's light (all of the light set's); 1 and no emission
    // leave the bits alone.
    if m.occlusion != 1.0 {
        lit *= m.occlusion;
    }
    if points {
        lit += if m.lambert {
            reflect(
                s.albedo,
                point_lights(&ctx.lights.points, first, s.p, s.n, vis),
            )
        } else {
            let lobe = Lobe::new(s.n, -s.dir, m.roughness);
            let sums = point_sums(&ctx.lights.points, first, s.p, &lobe, vis);
            Weights::new(s.albedo, m).radiance(&sums)
        };
    }
    if m.emission != Vec3::ZERO {
        lit += m.emission;
    }
    lit
}

/// The glTF metallic-roughness radiance of sample `s` from the frame's directional lights (see
/// [`radiance_at`]).
fn metallic_roughness(ctx: &FrameContext, s: &Surface, vis: &[u64], above: &[u64]) -> Vec3 {
    let (sl, glossy) = (&ctx.shade_lights, ctx.glossy);
    let m = &s.material;
    let v = -s.dir;
    let weights = Weights::new(s.albedo, m);
    let share = glossy.map_or(1.0, |g| g.light_share(m.roughness));
    if share >= 1.0 {
        // [ours] The lights resolve the lobe: exact over them, visibility included.
        let lobe = Lobe::new(s.n, v, m.roughness);
        let (sums, _) = specular_sums(sl, &lobe, vis, above, false);
        return weights.radiance(&sums);
    }
    let Some(g) = glossy else {
        unreachable!("share < 1 comes from a glossy environment")
    };
    // [ours] Too few lights for the lobe: the environment prefiltered for the roughness, seen
    // along the mirror direction, times the lobe's share of visible light (measured with a
    // lobe wide enough to hold several lights), blended with the lights' own specular between
    // the two roughnesses `Glossy` names. The diffuse sums do not depend on the roughness.
    let wide = Lobe::new(s.n, v, g.visibility_roughness(m.roughness));
    let (wide_sums, unshadowed) = specular_sums(sl, &wide, vis, above, true);
    let visible = if unshadowed > 0.0 {
        (crate::envmap::luminance(wide_sums.s2) / unshadowed).min(1.0)
    } else {
        1.0
    };
    let lobe = Lobe::new(s.n, v, m.roughness);
    let (i2, i3) = g.dfg(lobe.n_dot_v, m.roughness);
    let mirror = s.n * (2.0 * lobe.n_dot_v) - v;
    // The map turned as this frame's lights are (`[motion] kind = "environment"`).
    let mirror = match ctx.env_turn {
        None => mirror,
        Some((sin, cos)) => crate::envmap::rotate_y(mirror, (-sin, cos)),
    };
    let env = g.radiance(mirror, m.roughness) * visible;
    let from_env = weights.specular(env * i2, env * i3);
    if share <= 0.0 {
        return weights.diffuse(&wide_sums) + from_env;
    }
    let (sums, _) = specular_sums(sl, &lobe, vis, above, false);
    weights.diffuse(&sums) + weights.specular(sums.s2, sums.s3) * share + from_env * (1.0 - share)
}
