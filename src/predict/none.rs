//! `none`'s rule: no shadows at all, every light visible. The baseline cost of a frame without
//! shadows, against which the shadow methods are timed.

use super::correct::At;
use super::rule::Rule;
use super::scratch::Scratch;
use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;

/// Marks every above-horizon light visible and traces nothing.
pub struct Unshadowed;

impl Rule for Unshadowed {
    fn parts(&self) -> (&'static str, &'static str) {
        ("", "")
    }

    fn solve(
        &self,
        _ctx: &FrameContext,
        bufs: &mut TileBuffers,
        _sc: &mut Scratch,
        i: usize,
        _voters: &[usize],
        _at: At,
    ) {
        let w = bufs.words;
        let above = bits::rows(&bufs.above, w).row(i);
        bits::rows_mut(&mut bufs.vis, w)
            .row_mut(i)
            .copy_from_slice(above);
    }
}
