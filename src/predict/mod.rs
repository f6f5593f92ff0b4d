//! Shadow visibility: which (pixel, light) pairs are traced and which are predicted
//! (ALGORITHM.md §3–6).
//!
//! Every method implements [`Predictor`]: given a frame and a tile, decide the visibility of
//! every light at every pixel of the tile, tracing some shadow rays and predicting the rest.
//! The paper's methods are combinations of three parts, one file each:
//! an evaluation order ([`grid`] coarse-to-fine, [`scanline`] row by row), a voting rule
//! (warped blockers or plain neighbour visibility, in [`correct`]) and a correction rule
//! (uncertainty or boundary flooding, in [`correct`]). A new method is one new file here plus
//! one line in [`Method::predictor`].

pub mod bits;
mod brute;
mod correct;
mod grid;
pub mod lattice;
mod none;
mod scanline;
pub mod temporal;

use std::fmt;
use std::str::FromStr;

pub use brute::Brute;
pub use correct::{Flood, FloodTo, Scratch, Vote};
pub use grid::Grid;
pub use lattice::{Lattice, LatticePatch};
pub use none::NoShadows;
pub use scanline::Scanline;

use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// A way of deciding shadow visibility for the pixels of a tile.
///
/// A frame is rendered in phases: first [`shared_phases`](Self::shared_phases) phases over all
/// tiles whose pixels go into a frame-wide [`Lattice`] (work every tile reads, done once), then
/// the final phase that decides every pixel of each tile and shades it.
pub trait Predictor: Send + Sync {
    /// The method's name as the CLI and `stats.csv` spell it.
    fn name(&self) -> &'static str;
    /// Phases whose results are shared through the lattice (0: none).
    fn shared_phases(&self) -> usize {
        0
    }
    /// Spacing of the lattice that holds the shared phases' pixels (0: none).
    fn lattice_step(&self) -> u32 {
        0
    }
    /// How far beyond a tile the shared phases' pixels it depends on reach (directly or
    /// through other shared pixels): a region render runs the shared phases that far out.
    fn shared_reach(&self) -> u32 {
        0
    }
    /// The pixels whose surfaces and visibility this method may read or evaluate for `tile`
    /// in `phase`: the tile plus its halo, inside the frame.
    fn region(&self, ctx: &FrameContext, tile: Rect, phase: usize) -> Rect {
        let _ = (ctx, phase);
        tile
    }
    /// Decides visibility for the pixels of `tile` that `phase` evaluates. `work` comes
    /// prepared for `tile` and [`region`](Self::region); the method copies what it reads from
    /// `lattice`, evaluates pixels with [`TileWork::begin_pixel`], sets their `vis`, `traced`
    /// and `rays`, and marks them `needed` (pixels outside the tile so marked are its halo).
    /// In a shared phase it records the pixels it evaluated into `patch`.
    fn solve(
        &self,
        ctx: &FrameContext,
        tile: Rect,
        work: &mut TileWork,
        phase: usize,
        lattice: &Lattice,
        patch: &mut LatticePatch,
    );
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
}

impl Default for Params {
    fn default() -> Self {
        Params {
            h0: 16,
            min_voters: 3,
            flood_to: FloodTo::ContraryFinest,
            scan_block: 64,
        }
    }
}

impl Params {
    /// Checks the ranges; the error names the parameter.
    pub fn check(&self) -> Result<(), String> {
        if !(2..=256).contains(&self.h0) || !self.h0.is_power_of_two() {
            return Err(format!(
                "h0 = {}: the coarse grid spacing must be a power of two from 2 to 256",
                self.h0
            ));
        }
        if !(1..=4).contains(&self.min_voters) {
            return Err(format!(
                "min_voters = {}: must be 1 to 4 (a pixel has at most 4 voters)",
                self.min_voters
            ));
        }
        if self.scan_block < 8 {
            return Err(format!(
                "scan_block = {}: must be at least 8",
                self.scan_block
            ));
        }
        Ok(())
    }
}

/// The shadow methods, as named on the command line and in animation specs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Method {
    /// No shadows: every light counts as visible (the cost of rendering without shadows).
    None,
    /// Trace every query: the reference every other method is checked against.
    Brute,
    /// Scanline order, warped blockers, boundary flooding.
    ScanWarpBoundary,
    /// Coarse-to-fine grid, warped blockers, boundary flooding.
    GridWarpBoundary,
    /// Coarse-to-fine grid, neighbours' visibility, boundary flooding.
    GridNowarpBoundary,
    /// Coarse-to-fine grid, warped blockers, uncertainty flooding.
    GridWarpUncertainty,
    /// Coarse-to-fine grid, neighbours' visibility, uncertainty flooding: the paper's best.
    #[default]
    GridNowarpUncertainty,
}

impl Method {
    pub const ALL: [Method; 7] = [
        Method::None,
        Method::Brute,
        Method::ScanWarpBoundary,
        Method::GridWarpBoundary,
        Method::GridNowarpBoundary,
        Method::GridWarpUncertainty,
        Method::GridNowarpUncertainty,
    ];

    /// The methods of the paper's Table 1, in its row order ("true" = brute first).
    pub const TABLE1: [Method; 6] = [
        Method::Brute,
        Method::ScanWarpBoundary,
        Method::GridWarpBoundary,
        Method::GridNowarpBoundary,
        Method::GridWarpUncertainty,
        Method::GridNowarpUncertainty,
    ];

    /// Whether `--flood-to` can change what the method traces: only uncertainty flooding.
    /// Boundary flooding already queues every light whose prediction differs from an adjacent
    /// light's, so the neighbours `contrary` leaves out of a flood (predicted unlike the
    /// mispredicted light) are queued anyway: both rules trace the same set.
    pub fn floods_by_rule(self) -> bool {
        matches!(
            self,
            Method::GridWarpUncertainty | Method::GridNowarpUncertainty
        )
    }

    pub fn name(self) -> &'static str {
        match self {
            Method::None => "none",
            Method::Brute => "brute",
            Method::ScanWarpBoundary => "scan-warp-boundary",
            Method::GridWarpBoundary => "grid-warp-boundary",
            Method::GridNowarpBoundary => "grid-nowarp-boundary",
            Method::GridWarpUncertainty => "grid-warp-uncertainty",
            Method::GridNowarpUncertainty => "grid-nowarp-uncertainty",
        }
    }

    /// The method's implementation with `params`.
    pub fn predictor(self, params: Params) -> Box<dyn Predictor> {
        use Flood::*;
        use Vote::*;
        match self {
            Method::None => Box::new(NoShadows),
            Method::Brute => Box::new(Brute),
            Method::ScanWarpBoundary => Box::new(Scanline::new(self.name(), params)),
            Method::GridWarpBoundary => Box::new(Grid::new(self.name(), Warp, Boundary, params)),
            Method::GridNowarpBoundary => {
                Box::new(Grid::new(self.name(), NoWarp, Boundary, params))
            }
            Method::GridWarpUncertainty => {
                Box::new(Grid::new(self.name(), Warp, Uncertainty, params))
            }
            Method::GridNowarpUncertainty => {
                Box::new(Grid::new(self.name(), NoWarp, Uncertainty, params))
            }
        }
    }

    /// The paper's Table 1 figure (% of N·L > 0 shadow rays traced) for this method, scene
    /// (`shapes` or `bunny`) and light count, where the paper gives one.
    pub fn paper_percent(self, scene: &str, lights: usize) -> Option<f64> {
        let col = match lights {
            50 => 0,
            100 => 1,
            200 => 2,
            400 => 3,
            _ => return None,
        };
        let row: [f64; 8] = match self {
            Method::Brute => [100.0; 8],
            Method::ScanWarpBoundary => [40.5, 34.3, 26.3, 22.4, 52.4, 42.6, 33.6, 25.9],
            Method::GridWarpBoundary => [22.0, 17.9, 15.1, 12.4, 21.5, 16.6, 13.5, 11.6],
            Method::GridNowarpBoundary => [21.7, 17.1, 13.8, 10.6, 21.2, 15.8, 12.0, 9.3],
            Method::GridWarpUncertainty => [10.4, 10.7, 11.0, 11.3, 9.1, 9.4, 10.2, 11.5],
            Method::GridNowarpUncertainty => [9.4, 8.8, 8.3, 7.5, 8.1, 7.7, 7.2, 6.7],
            Method::None => return None,
        };
        match scene {
            "shapes" => Some(row[col]),
            "bunny" => Some(row[4 + col]),
            _ => None,
        }
    }
}

/// A method with its flood rule: what the measuring commands (`bench`, `table`) sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    pub method: Method,
    pub flood_to: FloodTo,
}

impl Variant {
    /// Every method with every flood rule, in that order; methods the rule cannot change
    /// ([`Method::floods_by_rule`]) once, with the default rule.
    pub fn sweep(methods: &[Method], floods: &[FloodTo]) -> Vec<Variant> {
        let mut v = Vec::new();
        for &method in methods {
            for &flood_to in floods {
                let flood_to = if method.floods_by_rule() {
                    flood_to
                } else {
                    FloodTo::default()
                };
                let variant = Variant { method, flood_to };
                if !v.contains(&variant) {
                    v.push(variant);
                }
            }
        }
        v
    }

    /// The variant's parameters: `params` with its flood rule.
    pub fn params(self, params: Params) -> Params {
        Params {
            flood_to: self.flood_to,
            ..params
        }
    }
}

impl From<Method> for Variant {
    /// The method with the default flood rule.
    fn from(method: Method) -> Variant {
        Variant {
            method,
            flood_to: FloodTo::default(),
        }
    }
}

/// The method's name, followed by the flag that selects a flood rule other than the default.
impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.flood_to == FloodTo::default() {
            write!(f, "{}", self.method)
        } else {
            write!(f, "{} --flood-to {}", self.method, self.flood_to)
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Method, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
                format!(
                    "unknown shadow method {s:?}; expected one of {}",
                    names.join(", ")
                )
            })
    }
}
