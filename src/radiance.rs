//! A sample's radiance (its background aside): its material — Lambertian, or glTF
//! metallic-roughness (`crate::brdf`) — over the visible lights of its bitset, with the glossy
//! environment (`crate::glossy`) where the lights are too few for the lobe, the scene file's
//! point and spot lights, occlusion and emission. The sums themselves are `crate::shade`'s
//! kernels.

use glam::Vec3;

use crate::bits::Rows;
use crate::brdf::{Lobe, MeanWeights, Reflectance, Sums, Weights};
use crate::context::{FrameContext, Surface};
use crate::shade::counted::counted_specular;
use crate::shade::{LambertCache, point_lights, point_sums, reflect, specular_sums};

/// A sample's radiance (its background aside): the visible lights in `vis` (those above its
/// horizon in `above`) reflected by its material — Lambertian, or glTF metallic-roughness
/// (`crate::brdf`) with, where `ctx.glossy` says the lights around the lobe are too sparse for
/// it, the prefiltered environment weighted by the lobe's visible fraction — times its occlusion,
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
    let mut lit = if m.lambert {
        let sum = cache.light_sum(sl, s.n, vis);
        if points && m.occlusion == 1.0 {
            // The Lambertian sum over every light, as main shades point lights.
            return reflect(
                s.albedo,
                sum + point_lights(&ctx.lights.points, ctx.light_dir.len(), s.p, s.n, vis),
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
        lit += point_radiance(ctx, s, vis);
    }
    if m.emission != Vec3::ZERO {
        lit += m.emission;
    }
    lit
}

/// The radiance of sample `s` from the scene file's point and spot lights in `vis`: its own
/// BRDF, exact, one light at a time.
fn point_radiance(ctx: &FrameContext, s: &Surface, vis: &[u64]) -> Vec3 {
    let (m, first) = (&s.material, ctx.light_dir.len());
    if m.lambert {
        reflect(
            s.albedo,
            point_lights(&ctx.lights.points, first, s.p, s.n, vis),
        )
    } else {
        let lobe = Lobe::new(s.n, -s.dir, m.roughness);
        let sums = point_sums(&ctx.lights.points, first, s.p, &lobe, vis);
        Weights::new(s.albedo, m).radiance(&sums)
    }
}

/// The summed radiance of `members`, samples of one pixel that share a glTF-material surface
/// (`crate::shading_rate`; Lambertian samples are shaded alone), with visible lights `vis` and lights above their horizons `above`
/// (a row each, in the members' order): [`radiance_at`] of each, added, but with the map's
/// lights evaluated once for the group — at the members' mean normal, view direction and
/// roughness, each light counted once per member that sees it — and reflected by the mean of
/// the members' weights (occlusion included). The scene file's point and spot lights, which
/// differ from point to point, and emission stay each member's own.
pub fn group_radiance(ctx: &FrameContext, members: &[Surface], vis: Rows, above: Rows) -> Vec3 {
    let sl = &ctx.shade_lights;
    let count = members.len() as f32;
    let lead = &members[0];
    debug_assert!(members.iter().all(|s| !s.material.lambert));
    let mut weights = MeanWeights::default();
    for s in members {
        weights.add(&Weights::new(s.albedo, &s.material), s.material.occlusion);
    }
    let n: Vec3 = members.iter().map(|s| s.n).sum();
    let dir: Vec3 = members.iter().map(|s| s.dir).sum();
    let roughness: f32 = members.iter().map(|s| s.material.roughness).sum();
    let shared = Shared {
        n: n.normalize_or(lead.n),
        v: (-dir).normalize_or(-lead.dir),
        roughness: roughness / count,
        members: count,
    };
    let mut lit = shared.radiance(ctx, &weights.mean(), |lobe, unshadowed| {
        counted_specular(sl, lobe, vis, unshadowed.then_some(above))
    });
    for (i, s) in members.iter().enumerate() {
        if ctx.has_points() {
            lit += point_radiance(ctx, s, vis.row(i));
        }
        if s.material.emission != Vec3::ZERO {
            lit += s.material.emission;
        }
    }
    lit
}

/// The glTF metallic-roughness radiance of sample `s` from the frame's directional lights (see
/// [`radiance_at`]).
fn metallic_roughness(ctx: &FrameContext, s: &Surface, vis: &[u64], above: &[u64]) -> Vec3 {
    let sl = &ctx.shade_lights;
    let m = &s.material;
    let lobe = Shared {
        n: s.n,
        v: -s.dir,
        roughness: m.roughness,
        members: 1.0,
    };
    let weights = Weights::new(s.albedo, m);
    lobe.radiance(ctx, &weights, |l, unshadowed| {
        specular_sums(sl, l, vis, above, unshadowed)
    })
}

/// What the samples shaded together share: their lobe's normal, view direction and roughness,
/// and how many they are (one for a sample shaded alone).
struct Shared {
    n: Vec3,
    v: Vec3,
    roughness: f32,
    members: f32,
}

impl Shared {
    /// The metallic-roughness radiance of the lights whose sums `sums` gives for a lobe (with
    /// `true`: also the unshadowed specular luminance), reflected by `weights`: the members'
    /// radiance summed.
    fn radiance(
        &self,
        ctx: &FrameContext,
        weights: &impl Reflectance,
        sums: impl Fn(&Lobe, bool) -> (Sums, f32),
    ) -> Vec3 {
        let Shared {
            n, v, roughness, ..
        } = *self;
        let lobe = Lobe::new(n, v, roughness);
        let Some(g) = ctx.glossy else {
            // The lights alone, exact over them, visibility included.
            let (sums, _) = sums(&lobe, false);
            return weights.diffuse(&sums) + weights.specular(sums.s2, sums.s3);
        };
        let mirror = n * (2.0 * lobe.n_dot_v) - v;
        // The map and its spacing field turned as this frame's lights are (`[motion] kind =
        // "environment"`).
        let mirror = match ctx.env_turn {
            None => mirror,
            Some((sin, cos)) => crate::envmap::rotate_y(mirror, (-sin, cos)),
        };
        let split = g.split(mirror, roughness);
        if split.lights >= 1.0 {
            // [ours] The lights resolve the lobe here: exact over them, visibility included.
            let (sums, _) = sums(&lobe, false);
            return weights.diffuse(&sums) + weights.specular(sums.s2, sums.s3);
        }
        // [ours] Too few lights around the lobe: the environment prefiltered for the
        // roughness, seen along the mirror direction, times the lobe's share of visible light
        // (measured with a lobe wide enough to hold a few of the lights there), blended with
        // the lights' own specular across the switch. The diffuse sums do not depend on the
        // roughness.
        let wide = Lobe::new(n, v, split.visibility_roughness);
        let (wide_sums, unshadowed) = sums(&wide, true);
        let visible = if unshadowed > 0.0 {
            (crate::envmap::luminance(wide_sums.s2) / unshadowed).min(1.0)
        } else {
            1.0
        };
        let (i2, i3) = g.dfg(lobe.n_dot_v, roughness);
        // Each member sees the visible share (the group's is the mean of its members').
        let env = g.radiance(mirror, roughness) * (visible * self.members);
        let from_env = weights.specular(env * i2, env * i3);
        if split.lights <= 0.0 {
            return weights.diffuse(&wide_sums) + from_env;
        }
        let (sums, _) = if wide == lobe {
            (wide_sums, unshadowed)
        } else {
            sums(&lobe, false)
        };
        weights.diffuse(&sums)
            + weights.specular(sums.s2, sums.s3) * split.lights
            + from_env * (1.0 - split.lights)
    }
}
