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
//! The methods are the lines of [`METHODS`] (`method.rs`): a new combination of existing parts
//! is one line there; a new order, vote or flood rule is one file here implementing its trait,
//! plus its `mod` line and the method lines that use it. This file only declares the modules
//! and re-exports their public names; the files import from each other, never from here.

mod boundary;
mod brute;
mod correct;
mod every;
mod flood;
mod grid;
mod link;
mod method;
mod none;
mod nowarp;
mod order;
mod params;
mod rule;
mod scanline;
mod scratch;
mod shadows;
pub mod temporal;
#[cfg(test)]
pub(crate) mod testkit;
pub mod turning;
mod uncertainty;
mod vote;
mod warp;

pub use boundary::Boundary;
pub use brute::TraceAll;
pub use correct::{At, correct};
pub use every::EveryPixel;
pub use flood::{Flood, FloodTo};
pub use grid::Grid;
pub use link::{Link, Read};
pub use method::{METHODS, Method, MethodDef};
pub use none::Unshadowed;
pub use nowarp::NoWarp;
pub use order::Order;
pub use params::Params;
pub use rule::{Predict, Rule};
pub use scanline::Scanline;
pub use scratch::Scratch;
pub use shadows::Shadows;
pub use uncertainty::Uncertainty;
pub use vote::Vote;
pub use warp::Warp;
