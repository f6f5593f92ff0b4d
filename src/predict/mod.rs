//! Shadow visibility: which (pixel, light) pairs are traced and which are predicted.
//!
//! Every method implements [`Predictor`]: given a frame and a tile, fill the tile's visibility
//! bitsets and count its work. A new method is one new file here plus one line in
//! [`Method::predictor`].

mod brute;
mod none;

use std::fmt;
use std::str::FromStr;

pub use brute::Brute;
pub use none::NoShadows;

use crate::frame::{FrameContext, TileWork};
use crate::tile::Rect;

/// A way of deciding shadow visibility for the pixels of a tile.
pub trait Predictor: Send + Sync {
    /// The method's name as the CLI and `stats.csv` spell it.
    fn name(&self) -> &'static str;
    /// The pixels, beyond `tile`, whose surfaces this method reads (its halo). `tile` itself
    /// for methods that need no neighbours.
    fn region(&self, ctx: &FrameContext, tile: Rect) -> Rect {
        let _ = ctx;
        tile
    }
    /// Fills `work.vis` (bit set = visible) and `work.rays` for every pixel of `tile`, and
    /// `work.counts`. Called with `work` prepared for `tile` and [`region`](Self::region).
    fn solve(&self, ctx: &FrameContext, tile: Rect, work: &mut TileWork);
}

/// The shadow methods, as named on the command line and in animation specs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// No shadows: every light counts as visible (the cost of rendering without shadows).
    None,
    /// Trace every query: the reference every other method is checked against.
    #[default]
    Brute,
}

impl Method {
    pub const ALL: [Method; 2] = [Method::None, Method::Brute];

    pub fn name(self) -> &'static str {
        match self {
            Method::None => "none",
            Method::Brute => "brute",
        }
    }

    /// The method's implementation.
    pub fn predictor(self) -> Box<dyn Predictor> {
        match self {
            Method::None => Box::new(NoShadows),
            Method::Brute => Box::new(Brute),
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
