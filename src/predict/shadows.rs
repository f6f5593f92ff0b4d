//! A method built for one frame: its order, its rule and parameters, and what each pass of
//! the order needs to know ([`Shadows::at`]).

use super::correct::At;
use super::order::Order;
use super::params::Params;
use super::rule::Rule;
use crate::context::FrameContext;

/// A method built for one frame: its order and rule, and the parameters.
pub struct Shadows {
    pub order: Box<dyn Order>,
    pub rule: Box<dyn Rule>,
    pub params: Params,
}

impl Shadows {
    /// How the pixels of `pass` are decided in the frame of `ctx`: the flood rule at their
    /// level, and which blockers they keep.
    pub fn at(&self, ctx: &FrameContext, pass: usize) -> At {
        // Voters closer than a pixel apart (spp > 1: the frame's samples per pixel side)
        // [ours]: see `FloodTo::ContraryFinest` and `Params::pixel_majority`.
        let spacing = self.order.spacing(pass);
        let inside = spacing.is_some_and(|s| s < ctx.samples.k);
        At {
            flood_to: self
                .params
                .flood_to
                .at_level(self.order.finest(pass) || inside),
            majority: self.params.pixel_majority && inside && spacing == Some(1),
            inside,
            keep_blockers: self.rule.reads_blockers() && self.order.read_later(pass),
            keep_predicted: self.order.keeps_predicted(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::flood::FloodTo;
    use super::super::method::Method;
    use super::super::testkit::{Frame, star};
    use super::*;
    use crate::samples::{Filter, Samples};

    /// What `Shadows::at` must give for every method, flood rule and pass at h0 = 16 (grid
    /// passes 0..=8, the finest level being passes 7 and 8): `contrary-finest` is contrary
    /// there and all elsewhere, and never contrary on the scanline (no levels); the other
    /// rules stand at every level. Warping methods keep blockers on every pass something reads
    /// later (not the grid's last); the grid keeps predicted blockers, the scanline does not.
    #[test]
    fn each_pass_gets_its_levels_flood_rule_and_blockers() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let mut failures = Vec::new();
        for m in Method::all() {
            let (order, vote, _) = m.parts();
            let warp = vote == "warp";
            for flood_to in FloodTo::ALL {
                let params = Params {
                    flood_to,
                    ..Params::default()
                };
                let shadows = m.build(params);
                let passes = shadows.order.passes();
                let want_passes = if order == "grid" { 9 } else { 1 };
                if passes != want_passes {
                    failures.push(format!("{m}: {passes} passes, want {want_passes}"));
                }
                for pass in 0..passes {
                    let finest = order == "grid" && pass >= 7;
                    let want = At {
                        flood_to: match flood_to {
                            // `Auto` not resolved for cut-outs reads as contrary-finest.
                            FloodTo::ContraryFinest | FloodTo::Auto if finest => FloodTo::Contrary,
                            FloodTo::ContraryFinest | FloodTo::Auto => FloodTo::All,
                            f => f,
                        },
                        keep_blockers: warp && !(order == "grid" && pass == 8),
                        keep_predicted: order == "grid",
                        majority: false,
                        inside: false,
                    };
                    let got = shadows.at(&ctx, pass);
                    if got != want {
                        failures.push(format!(
                            "{m} {flood_to} pass {pass}: {got:?}, want {want:?}"
                        ));
                    }
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    /// With 4 × 4 samples per pixel (k = 4, h0 = 16 → 64 on the lattice: passes 0..=12, the
    /// levels of spacing 2 and 1 being passes 9–12): the passes whose voters lie inside a
    /// pixel flood to contrary lights and leave `--temporal` to their voters; the majority
    /// decides at the finest level only, and not at all with `--pixel-majority=false`.
    #[test]
    fn passes_inside_a_pixel_flood_contrary_and_the_finest_takes_the_majority() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx().with_samples(Samples::new(16, Filter::Box, 0.0));
        assert_eq!(ctx.samples.k, 4);
        for pixel_majority in [true, false] {
            let params = Params {
                pixel_majority,
                ..Params::default()
            }
            .for_samples(4);
            let shadows = Method::DEFAULT.build(params);
            assert_eq!(shadows.order.passes(), 13);
            for pass in 0..13 {
                let at = shadows.at(&ctx, pass);
                let inside = pass >= 9;
                assert_eq!(at.inside, inside, "pass {pass}");
                let contrary = if inside {
                    FloodTo::Contrary
                } else {
                    FloodTo::All
                };
                assert_eq!(at.flood_to, contrary, "pass {pass}");
                assert_eq!(at.majority, pixel_majority && pass >= 11, "pass {pass}");
            }
        }
        // The scanline has no levels: nothing is inside.
        let scan = "scan-warp-boundary".parse::<Method>().unwrap();
        let shadows = scan.build(Params::default().for_samples(4));
        assert!(!shadows.at(&ctx, 0).inside && !shadows.at(&ctx, 0).majority);
    }
}
