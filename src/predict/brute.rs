//! `brute`'s rule: trace every shadow query (the "true" row of Table 1).

use super::correct::At;
use super::rule::Rule;
use super::scratch::Scratch;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;

/// Traces one shadow ray per (pixel, light) pair with N·ω > 0.
pub struct TraceAll;

impl Rule for TraceAll {
    fn parts(&self) -> (&'static str, &'static str) {
        ("", "")
    }

    fn solve(
        &self,
        ctx: &FrameContext,
        bufs: &mut TileBuffers,
        _sc: &mut Scratch,
        i: usize,
        _voters: &[usize],
        at: At,
    ) {
        bufs.trace_all(ctx, i, at.keep_blockers);
    }
}
