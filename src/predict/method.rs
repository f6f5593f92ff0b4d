//! The methods: each a name, an evaluation order and a rule, one line of [`METHODS`] (a new
//! combination of existing parts is one line there).

use std::fmt;
use std::str::FromStr;

use super::boundary::Boundary;
use super::brute::TraceAll;
use super::every::EveryPixel;
use super::flood::Flood;
use super::grid::Grid;
use super::none::Unshadowed;
use super::nowarp::NoWarp;
use super::order::Order;
use super::params::Params;
use super::rule::{Predict, Rule};
use super::scanline::Scanline;
use super::shadows::Shadows;
use super::uncertainty::Uncertainty;
use super::vote::Vote;
use super::warp::Warp;
use crate::key::Key;

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

    /// Whether the method reads `setting` (its order's and its rule's `reads`): a setting it
    /// does not read cannot change what it does.
    pub fn reads(self, key: Key) -> bool {
        let s = self.build(Params::default());
        s.order.reads().contains(&key) || s.rule.reads().contains(&key)
    }
}

impl Default for Method {
    fn default() -> Method {
        Method::DEFAULT
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
}
