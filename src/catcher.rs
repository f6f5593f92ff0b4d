//! What a pixel sample adds to its pixel beside the lit surfaces: the background where the
//! ray leaves the scene ([`miss`]), and shadow catchers ([`Catchers::sample`]).
//!
//! A shadow catcher (`[scene] shadow_catcher`, `catchers`, a glTF node's `extras`) receives
//! shadows and shows only them, as Cycles' shadow catcher does. Its shadow fraction is
//! `1 − E_vis / E_above`: the luminance of the cosine-weighted light of the visible lights over
//! that of every light above its horizon — from the very visibility bits the method decided
//! (traced or predicted, its rays counted like any other surface's).
//!
//! - Over a transparent background the sample is black with alpha = the shadow fraction
//!   (premultiplied: a compositor's `over` darkens the plate by it).
//! - Over an opaque background (environment, colour, blurred) it shows the background behind
//!   it darkened by the shadow: `background × (1 − shadow)`, alpha 1 — as if the background
//!   plate were photographed with the model's shadow on it.
//!
//! [ours] Catchers are geometry like any other for every other ray: they hide what is behind
//! them, and they block the model's shadow rays (a model on a catcher ground is not lit from
//! below the ground, as it would not be on a real floor). Nothing here reflects them (there is
//! no indirect light), so they never show up in reflections.

use glam::Vec3;

use crate::context::{FrameContext, Surface};
use crate::envmap::luminance;
use crate::shade::{light_sum, same};

/// A sample that saw the background along unit direction `dir`: its radiance (zero over a
/// transparent background) and alpha.
#[inline]
pub fn miss(ctx: &FrameContext, dir: Vec3) -> (Vec3, f32) {
    (ctx.background(dir), ctx.backdrop.alpha())
}

/// A thread's shading of catcher samples: the last catcher normal's unshadowed light, which
/// the samples of a flat catcher share (the lights above the horizon depend on the normal
/// alone).
#[derive(Default)]
pub struct Catchers {
    last: Option<(Vec3, f32)>,
}

impl Catchers {
    /// The catcher sample `s` whose visible lights give the cosine-weighted light `sum`
    /// ([`light_sum`] over its visibility bits; `above`: its lights above the horizon): its
    /// radiance and alpha (see the module comment).
    #[inline]
    pub fn sample(
        &mut self,
        ctx: &FrameContext,
        s: &Surface,
        above: &[u64],
        sum: Vec3,
    ) -> (Vec3, f32) {
        let shadow = self.shadow(ctx, s.n, above, sum);
        if ctx.backdrop.is_transparent() {
            (Vec3::ZERO, shadow)
        } else {
            (ctx.background(s.dir) * (1.0 - shadow), 1.0)
        }
    }

    /// The shadow fraction `1 − lum(sum) / lum(light of every light above)` at normal `n`, in
    /// [0, 1]; 0 where no light is above the horizon.
    pub fn shadow(&mut self, ctx: &FrameContext, n: Vec3, above: &[u64], sum: Vec3) -> f32 {
        let open = match self.last {
            Some((m, open)) if same(m, n) => open,
            _ => {
                let open = luminance(light_sum(&ctx.shade_lights, n, above));
                self.last = Some((n, open));
                open
            }
        };
        if open > 0.0 {
            (1.0 - luminance(sum) / open).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}
