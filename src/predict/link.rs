//! A frame's link to its neighbours in time (`--temporal`, ALGORITHM.md §8 [ours]): what it
//! reads of its predecessor — the previous frame's view and the solver that predicts from it —
//! and what it keeps for its successor. Both are decided once per frame from the motion at that
//! frame (`temporal::link` builds the link); the driver asks it once per pixel
//! ([`Link::solve`]) and once per tile ([`Link::keep`]).
//!
//! [ours] Both solvers correct with uncertainty flooding: `--temporal` is offered with the
//! uncertainty methods only (the settings refuse it elsewhere; docs/temporal.md), and the
//! previous frame's voters are read as that rule reads spatial ones (agreeing voters are sure,
//! disagreeing ones uncertain). `--flood-to` (which neighbours a trace queues) is the method's.

use super::correct::At;
use super::scratch::Scratch;
use super::shadows::Shadows;
use super::temporal::solve_temporal;
use super::turning::solve_in_place;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;
use crate::history::{Carried, CarryPatch, Edges, Prev};

/// How a frame reads its predecessor: the previous frame's view, and which solver predicts a
/// pixel from it.
pub enum Read<'a> {
    /// The previous pixels around the surface point's reprojection vote, as spatial voters
    /// do (an orbiting camera, a spinning object: [`solve_temporal`]).
    Reproject(Prev<'a>),
    /// The pixel's own previous self saw the same point and only the lights turned (a turning
    /// environment: [`solve_in_place`]).
    InPlace(Prev<'a>),
}

/// A frame's link in time: what it reads of the previous frame and what it keeps for the next.
/// The default reads nothing and keeps nothing (a frame rendered alone, or a key frame that
/// ends its chain).
#[derive(Default)]
pub struct Link<'a> {
    read: Option<Read<'a>>,
    keep: Option<Edges>,
}

impl<'a> Link<'a> {
    /// A link that reads `read` (if any) and keeps the frame's visibility for the next frame,
    /// with the edge lights `keep` names (if any is kept).
    pub fn new(read: Option<Read<'a>>, keep: Option<Edges>) -> Link<'a> {
        Link { read, keep }
    }

    /// Empty carried data for `frame` (`width` × `height` pixels, `words` per bitset), if
    /// this frame keeps its visibility for the next; the tiles' [`Link::keep`] fill it.
    pub fn carried(&self, frame: usize, width: u32, height: u32, words: usize) -> Option<Carried> {
        let edges = self.keep.as_ref()?;
        Some(Carried::new(frame, width, height, words, edges.kept()))
    }

    /// Predicts and corrects region pixel `i` (already begun) from the previous frame, with
    /// `voters` its valid spatial voters. Returns false, touching nothing, where the spatial
    /// method decides: no previous frame, a sample inside a pixel, or too few previous pixels
    /// that saw the same surface point.
    pub fn solve(
        &self,
        ctx: &FrameContext,
        shadows: &Shadows,
        bufs: &mut TileBuffers,
        sc: &mut Scratch,
        (i, voters): (usize, &[usize]),
        at: At,
    ) -> bool {
        // [ours] With samples per pixel, the previous frame's pixels are a pixel apart: a
        // sample whose spatial voters are closer is left to them.
        if at.inside {
            return false;
        }
        match &self.read {
            None => false,
            Some(Read::Reproject(prev)) => {
                let min_voters = shadows.params.min_voters;
                solve_temporal(ctx, bufs, sc, prev, i, voters, min_voters, at)
            }
            Some(Read::InPlace(prev)) => {
                // [ours] The spatial voters count as the spatial rule counts them (busy voters).
                let spatial_min = shadows.rule.min_voters(bufs, voters);
                solve_in_place(ctx, bufs, sc, prev, i, voters, spatial_min, at)
            }
        }
    }

    /// What the tile in `bufs` (just rendered) carries forward for the next frame, if this
    /// frame keeps anything: each pixel's middle sample and, with edge lights kept, those.
    pub fn keep(&self, ctx: &FrameContext, bufs: &TileBuffers) -> Option<CarryPatch> {
        let edges = self.keep.as_ref()?;
        Some(CarryPatch::record(bufs, ctx.lights, edges, ctx.samples.k))
    }
}
