//! Shadow visibility: which (pixel, light) pairs are traced and which are predicted
//! (ALGORITHM.md §3–6).
//!
//! A method is an evaluation [`Order`] (which pixels are decided in which pass, and which
//! earlier pixels vote for each) and a [`Rule`] (how a pixel is decided from its voters). The
//! predicting rule, [`Predict`], is a voting rule ([`Vote`]: [`NoWarp`], [`Warp`]) and a flood
//! rule ([`Flood`]: [`Uncertainty`], [`Boundary`]). The tile driver (the driver's
//! `FrameWork`) walks an order's passes and does the per-pixel bookkeeping for every method;
//! the previous frame's voters ([`temporal`]) come first where a frame has one.
//!
//! The methods are the lines of [`METHODS`]: a new combination of existing parts is one line
//! there; a new order, vote or flood rule is one file here implementing its trait, plus its
//! `mod` line and the method lines that use it.

mod boundary;
mod brute;
mod correct;
mod every;
mod flood;
mod grid;
mod link;
mod none;
mod nowarp;
mod order;
mod rule;
mod scanline;
mod scratch;
pub mod temporal;
#[cfg(test)]
pub(crate) mod testkit;
pub mod turning;
mod uncertainty;
mod vote;
mod warp;

use std::fmt;
use std::str::FromStr;

pub use boundary::Boundary;
pub use brute::TraceAll;
pub use correct::{At, correct};
pub use every::EveryPixel;
pub use flood::{Flood, FloodTo};
pub use grid::Grid;
pub use link::{Link, Read};
pub use none::Unshadowed;
pub use nowarp::NoWarp;
pub use order::Order;
pub use rule::{Predict, Rule};
pub use scanline::Scanline;
pub use scratch::Scratch;
pub use uncertainty::Uncertainty;
pub use vote::Vote;
pub use warp::Warp;

/// One method: its name, what it does, and how to build its order and rule.
pub struct MethodDef {
    /// The name on the command line, in specs and in `stats.csv`.
    pub name: &'static str,
    /// One line for `--help` and the README.
    pub about: &'static str,
    order: fn(&Params) -> Box<dyn Order>,
    rule: fn(&Params) -> Box<dyn Rule>,
}

const fn method(
    name: &'static str,
    about: &'static str,
    order: fn(&Params) -> Box<dyn Order>,
    rule: fn(&Params) -> Box<dyn Rule>,
) -> MethodDef {
    MethodDef {
        name,
        about,
        order,
        rule,
    }
}

fn grid(p: &Params) -> Box<dyn Order> {
    Box::new(Grid::new(p))
}

fn scan(p: &Params) -> Box<dyn Order> {
    Box::new(Scanline::new(p))
}

fn every(_: &Params) -> Box<dyn Order> {
    Box::new(EveryPixel)
}

fn predict<V: Vote, F: Flood>(p: &Params) -> Box<dyn Rule> {
    Box::new(Predict::<V, F>::new(p))
}

fn trace_all(_: &Params) -> Box<dyn Rule> {
    Box::new(TraceAll)
}

fn unshadowed(_: &Params) -> Box<dyn Rule> {
    Box::new(Unshadowed)
}

/// Every method, in the order `--help` lists them: an order and a rule each.
pub static METHODS: [MethodDef; 8] = [
    method(
        "none",
        "no shadows (every light visible): the cost of a frame without them",
        every,
        unshadowed,
    ),
    method(
        "brute",
        "traces every query: the reference",
        every,
        trace_all,
    ),
    method(
        "scan-warp-boundary",
        "row-by-row order from the left, upper-left and upper neighbours' warped blockers; \
         traces the predicted shadow's boundary",
        scan,
        predict::<Warp, Boundary>,
    ),
    method(
        "grid-warp-boundary",
        "grid order, warped blockers, binary prediction; traces the visible/blocked boundary",
        grid,
        predict::<Warp, Boundary>,
    ),
    method(
        "grid-nowarp-boundary",
        "grid order, neighbours' visibility, binary prediction; traces the visible/blocked \
         boundary",
        grid,
        predict::<NoWarp, Boundary>,
    ),
    method(
        "grid-warp-uncertainty",
        "grid order with the neighbours' blockers re-aimed from the pixel (warped); traces \
         what they disagree on and floods",
        grid,
        predict::<Warp, Uncertainty>,
    ),
    method(
        "grid-nowarp-uncertainty",
        "traces every light on a coarse grid (every 16th pixel), then predicts finer pixels \
         from four neighbours' visibility; traces lights the neighbours disagree on and floods \
         to adjacent lights until traces agree",
        grid,
        predict::<NoWarp, Uncertainty>,
    ),
    // [ours] not in the paper: its best rule on its simplest order.
    method(
        "scan-nowarp-uncertainty",
        "row-by-row order from the left, upper-left and upper neighbours' visibility; traces \
         what they disagree on and floods",
        scan,
        predict::<NoWarp, Uncertainty>,
    ),
];

/// A shadow method: one of [`METHODS`].
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Method(usize);

impl Method {
    /// No shadows.
    pub const NONE: Method = Method(0);
    /// Trace every query.
    pub const BRUTE: Method = Method(1);
    /// The default: `grid-nowarp-uncertainty`, the paper's best.
    pub const DEFAULT: Method = Method(6);

    /// Every method, in [`METHODS`]' order.
    pub fn all() -> impl Iterator<Item = Method> {
        (0..METHODS.len()).map(Method)
    }

    fn def(self) -> &'static MethodDef {
        &METHODS[self.0]
    }

    /// The method's name as the CLI and `stats.csv` spell it.
    pub fn name(self) -> &'static str {
        self.def().name
    }

    /// What the method does, in one line.
    pub fn about(self) -> &'static str {
        self.def().about
    }

    /// The method's order and rule for one frame, with `params`.
    pub fn build(self, params: Params) -> Shadows {
        let d = self.def();
        Shadows {
            order: (d.order)(&params),
            rule: (d.rule)(&params),
            params,
        }
    }

    /// Its parts' names: order, vote and flood rule (`""` for rules without them).
    pub fn parts(self) -> (&'static str, &'static str, &'static str) {
        let s = self.build(Params::default());
        let (vote, flood) = s.rule.parts();
        (s.order.name(), vote, flood)
    }

    /// Whether the method reads `setting` (`h0`, `min_voters`, `flood_to`, `scan_block`,
    /// `temporal`, `keyframe`): a setting it does not read cannot change what it does.
    pub fn reads(self, setting: &str) -> bool {
        let s = self.build(Params::default());
        s.order.reads().contains(&setting) || s.rule.reads().contains(&setting)
    }
}

impl Default for Method {
    fn default() -> Method {
        Method::DEFAULT
    }
}

/// A method built for one frame: its order and rule, and the parameters.
pub struct Shadows {
    pub order: Box<dyn Order>,
    pub rule: Box<dyn Rule>,
    pub params: Params,
}

impl Shadows {
    /// How the pixels of `pass` are decided: the flood rule at their level, and which
    /// blockers they keep.
    pub fn at(&self, pass: usize) -> At {
        // Voters closer than a pixel apart (spp > 1) [ours]: see `FloodTo::ContraryFinest`
        // and `Params::pixel_majority`.
        let spacing = self.order.spacing(pass);
        let inside = spacing.is_some_and(|s| s < self.params.k);
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

/// The tunable parameters of the prediction methods (ALGORITHM.md §4–5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Params {
    /// Coarse grid spacing h0 (a power of two, 2..=256): coarse pixels trace every light [paper].
    /// Default 16 [ours].
    pub h0: u32,
    /// Uncertainty rule: a light is predicted only when at least this many valid neighbours
    /// have it above their horizon; otherwise it is traced. [ours] ALGORITHM.md says K_j < 2 →
    /// trace; we trace below 3: on the paper scenes at 200 lights, 2 traced 5.6 % with 0.064 %
    /// wrong pairs (bunny), 3 traces 7.8 % with 0.016 % (BENCHMARKS.md).
    pub min_voters: u32,
    /// Which neighbour lights a flooding trace queues: all untraced ones, or [ours] only those
    /// predicted opposite to the traced answer — at the grid's finest level only (the
    /// default), or everywhere.
    pub flood_to: FloodTo,
    /// Scanline order restarts at frame-anchored blocks of this many pixels, so a tile's
    /// halo is bounded (the paper scans the whole frame) [ours].
    pub scan_block: u32,
    /// [ours] With samples per pixel, at the grid's finest level (voters one sample apart,
    /// inside a pixel), a light on which three of four voters agree is taken from them rather
    /// than traced: a straight shadow edge that leaves three of the four corners of a square on
    /// one side leaves its centre there too. A mistake misleads only samples of the same
    /// pixel (the finest level's diagonal pass votes for its axis pass). Off by default: on
    /// the corpus at 4 spp it saved a sixth of the rays for five times the wrong pairs, 0.27 %
    /// on the cut-out panels (BENCHMARKS.md, "Three voters of four inside a pixel").
    pub pixel_majority: bool,
    /// [ours] Voters must share the pixel's surface: a neighbour whose normal turns more than
    /// about 37° from the pixel's, or whose point lies more than about 17° off the pixel's
    /// tangent plane, does not vote. Measured on the corpus and not the default
    /// (BENCHMARKS.md, "Issue 23").
    pub surface_voters: bool,
    /// [ours] A light is predicted only if every valid voter (at least `min_voters`) has it
    /// above its horizon. Measured on the corpus (BENCHMARKS.md, "Issue 23").
    pub all_voters: bool,
    /// [ours] Where a voter's own flooding caught a wrong prediction, `min_voters` is at
    /// least this (0: off; default 4): the neighbourhood's shadows are finer than the voters'
    /// spacing, so a light only some voters see is traced. On the corpus it kept every frame
    /// under 0.05 % wrong pairs for 6 % more rays (BENCHMARKS.md, "Issue 23").
    pub busy_voters: u32,
    /// [ours] A pixel whose prediction leaves at least this share (percent) of its
    /// above-horizon lights uncertain traces every one of them in full packets instead of
    /// correcting the prediction light by light (0: off; default 40). Such a pixel's voters
    /// know little of it (they straddle a crease or a cut-out's holes), so the lights they
    /// agree on are the ones they mislead it on; past some share, flooding traces most of the
    /// rest anyway, in short waves, and a full packet's rays cost a quarter as much each. On
    /// the corpus it halved the cut-out panels' wrong pairs for about the same rays
    /// (BENCHMARKS.md, "Tracing every light where the voters know little").
    pub trace_all_share: u32,
    /// Samples per pixel side: the lattice the method works on holds k × k samples per pixel
    /// (1: one sample at the pixel centre). Set by [`for_samples`](Self::for_samples).
    pub k: u32,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            h0: 16,
            min_voters: 3,
            flood_to: FloodTo::ContraryFinest,
            scan_block: 64,
            pixel_majority: false,
            surface_voters: false,
            all_voters: false,
            busy_voters: 4,
            trace_all_share: 40,
            k: 1,
        }
    }
}

impl Params {
    /// The parameters on a lattice of k × k samples per pixel: the coarse grid and the scan's
    /// blocks keep their size in pixels (the grid's spacing rounded up to a power of two), so
    /// the coarse grid's share of the queries falls as the samples grow denser.
    pub fn for_samples(self, k: u32) -> Params {
        Params {
            h0: (self.h0 * k).next_power_of_two(),
            scan_block: self.scan_block * k,
            k,
            ..self
        }
    }

    /// The parameters for a frame whose geometry has cut-out triangles (`cutouts`) or not:
    /// the flood rule [`FloodTo::Auto`] decided.
    pub fn for_cutouts(self, cutouts: bool) -> Params {
        Params {
            flood_to: self.flood_to.resolved(cutouts),
            ..self
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Debug for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Method, String> {
        Method::all().find(|m| m.name() == s).ok_or_else(|| {
            let names: Vec<_> = Method::all().map(|m| m.name()).collect();
            format!(
                "unknown shadow method {s:?}; expected one of {}",
                names.join(", ")
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_methods_are_the_registered_ones() {
        assert_eq!(Method::NONE.name(), "none");
        assert_eq!(Method::BRUTE.name(), "brute");
        assert_eq!(Method::DEFAULT.name(), "grid-nowarp-uncertainty");
        assert_eq!(Method::DEFAULT.parts(), ("grid", "nowarp", "uncertainty"));
        for m in Method::all() {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
        }
        assert!(
            "magic"
                .parse::<Method>()
                .unwrap_err()
                .contains("grid-nowarp-uncertainty")
        );
    }

    /// What `Shadows::at` must give for every method, flood rule and pass at h0 = 16 (grid
    /// passes 0..=8, the finest level being passes 7 and 8): `contrary-finest` is contrary
    /// there and all elsewhere, and never contrary on the scanline (no levels); the other
    /// rules stand at every level. Warping methods keep blockers on every pass something reads
    /// later (not the grid's last); the grid keeps predicted blockers, the scanline does not.
    #[test]
    fn each_pass_gets_its_levels_flood_rule_and_blockers() {
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
                    let got = shadows.at(pass);
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

    #[test]
    fn auto_floods_to_all_lights_only_where_the_frame_has_cut_outs() {
        let auto = Params {
            flood_to: FloodTo::Auto,
            ..Params::default()
        };
        assert_eq!(auto.for_cutouts(true).flood_to, FloodTo::All);
        assert_eq!(auto.for_cutouts(false).flood_to, FloodTo::ContraryFinest);
        for f in [
            FloodTo::All,
            FloodTo::ContraryFinest,
            FloodTo::Contrary,
            FloodTo::Adaptive,
        ] {
            for cutouts in [false, true] {
                assert_eq!(f.resolved(cutouts), f, "a rule the user chose is kept");
            }
        }
        assert_eq!("auto".parse::<FloodTo>(), Ok(FloodTo::Auto));
    }

    /// With 4 × 4 samples per pixel (k = 4, h0 = 16 → 64 on the lattice: passes 0..=12, the
    /// levels of spacing 2 and 1 being passes 9–12): the passes whose voters lie inside a
    /// pixel flood to contrary lights and leave `--temporal` to their voters; the majority
    /// decides at the finest level only, and not at all with `--pixel-majority=false`.
    #[test]
    fn passes_inside_a_pixel_flood_contrary_and_the_finest_takes_the_majority() {
        for pixel_majority in [true, false] {
            let params = Params {
                pixel_majority,
                ..Params::default()
            }
            .for_samples(4);
            let shadows = Method::DEFAULT.build(params);
            assert_eq!(shadows.order.passes(), 13);
            for pass in 0..13 {
                let at = shadows.at(pass);
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
        assert!(!shadows.at(0).inside && !shadows.at(0).majority);
    }

    /// `at_level` resolves `contrary-finest` alone.
    #[test]
    fn only_contrary_finest_depends_on_the_level() {
        let want = [
            (FloodTo::All, [FloodTo::All, FloodTo::All]),
            (FloodTo::ContraryFinest, [FloodTo::All, FloodTo::Contrary]),
            (FloodTo::Contrary, [FloodTo::Contrary, FloodTo::Contrary]),
        ];
        for (f, [coarse, finest]) in want {
            assert_eq!(
                (f.at_level(false), f.at_level(true)),
                (coarse, finest),
                "{f}"
            );
        }
    }
}
