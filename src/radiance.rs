//! A sample's radiance (its background aside): its material — Lambertian, or glTF
//! metallic-roughness (`crate::brdf`) — over the visible lights of its bitset, with the glossy
//! environment (`crate::glossy`) where the lights are too few for the lobe, the scene file's
//! point and spot lights, occlusion and emission. The sums themselves are `crate::shade`'s
//! kernels.

use glam::Vec3;

use crate::bits::Rows;
use crate::brdf::{Lobe, MeanWeights, Reflectance, Sums, Weights};
use crate::context::{FrameContext, Surface};
use crate::reflection::{RaySet, lobe_light};
use crate::shade::counted::counted_specular;
use crate::shade::{LambertCache, point_lights, point_sums, reflect, specular_sums};

/// A sample's radiance (its background aside): the visible lights in `vis` reflected by its material — Lambertian, or glTF metallic-roughness
/// (`crate::brdf`) with, where `ctx.glossy` says the lights around the lobe are too sparse for
/// it, the prefiltered environment weighted by the lobe's visible fraction — times its occlusion,
/// plus the scene file's point and spot lights in `vis` (the same BRDF, exact: one light at a
/// time; occlusion is the environment's only), plus its emission. Lambertian samples with the
/// normal and visible lights of the last one `cache` saw reuse its light sum (the same bits).
pub fn radiance_at(ctx: &FrameContext, s: &Surface, vis: &[u64], cache: &mut LambertCache) -> Vec3 {
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
        metallic_roughness(ctx, s, vis)
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
/// (`crate::shading_rate`; Lambertian samples are shaded alone), with visible lights `vis`
/// (a row each, in the members' order): [`radiance_at`] of each, added, but with the map's
/// lights evaluated once for the group — at the members' mean normal, view direction and
/// roughness, each light counted once per member that sees it — and reflected by the mean of
/// the members' weights (occlusion included). The scene file's point and spot lights, which
/// differ from point to point, and emission stay each member's own.
pub fn group_radiance(ctx: &FrameContext, members: &[Surface], vis: Rows) -> Vec3 {
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
        members,
    };
    let mut lit = shared.radiance(ctx, &weights.mean(), |lobe| counted_specular(sl, lobe, vis));
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
fn metallic_roughness(ctx: &FrameContext, s: &Surface, vis: &[u64]) -> Vec3 {
    let sl = &ctx.shade_lights;
    let m = &s.material;
    let lobe = Shared {
        n: s.n,
        v: -s.dir,
        roughness: m.roughness,
        members: std::slice::from_ref(s),
    };
    let weights = Weights::new(s.albedo, m);
    lobe.radiance(ctx, &weights, |l| specular_sums(sl, l, vis))
}

/// What the samples shaded together share: their lobe's normal, view direction and roughness;
/// and the samples (one for a sample shaded alone), whose own points the lobe's reflection
/// rays leave from.
struct Shared<'a> {
    n: Vec3,
    v: Vec3,
    roughness: f32,
    members: &'a [Surface],
}

impl Shared<'_> {
    /// The metallic-roughness radiance of the lights whose sums `sums` gives for a lobe,
    /// reflected by `weights`, with the glossy environment where the lights are too sparse for
    /// the lobe: the members' radiance summed.
    fn radiance(
        &self,
        ctx: &FrameContext,
        weights: &impl Reflectance,
        sums: impl Fn(&Lobe) -> Sums,
    ) -> Vec3 {
        let Shared {
            n, v, roughness, ..
        } = *self;
        let lobe = Lobe::new(n, v, roughness);
        let sums = sums(&lobe);
        let Some(g) = ctx.glossy else {
            // The lights alone, exact over them, visibility included.
            return weights.diffuse(&sums) + weights.specular(sums.s2, sums.s3);
        };
        // The map and its spacing field turned as this frame's lights are (`[motion] kind =
        // "environment"`).
        let mirror = ctx.unturned(n * (2.0 * lobe.n_dot_v) - v);
        let split = g.split(mirror, roughness);
        if split.lights >= 1.0 {
            // [ours] The lights resolve the lobe here: exact over them, visibility included.
            return weights.diffuse(&sums) + weights.specular(sums.s2, sums.s3);
        }
        // [ours] Too few lights around the lobe: the environment prefiltered for the
        // roughness, seen along the mirror direction, times the share of the lobe's light that
        // reaches each member unblocked — measured by rays into the lobe from the member's own
        // point (`crate::reflection`), not by the lights' bits, which blur a narrow lobe's
        // occluders over the lights' spacing — blended with the lights' own specular across
        // the switch.
        let members = self.members;
        let set = RaySet::new(&lobe, roughness, members.len(), members[0].p);
        let (open, all) = members
            .iter()
            .enumerate()
            .map(|(m, s)| lobe_light(ctx, g, s, &lobe, &set, m))
            .fold((0.0, 0.0), |(a, b), (o, l)| (a + o, b + l));
        let share = if all > 0.0 {
            (open / all).min(1.0)
        } else {
            1.0
        };
        let visible = share * members.len() as f32;
        let (i2, i3) = g.dfg(lobe.n_dot_v, roughness);
        let env = g.radiance(mirror, roughness) * visible;
        let from_env = weights.specular(env * i2, env * i3);
        weights.diffuse(&sums)
            + weights.specular(sums.s2, sums.s3) * split.lights
            + from_env * (1.0 - split.lights)
    }
}
