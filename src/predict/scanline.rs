//! Scanline order (ALGORITHM.md §5) [paper]: pixels in row-major order, each predicted from its
//! left, upper-left and upper neighbours; a pixel with no voters is traced in full.
//!
//! Tiles [ours]: in the paper the scan runs over the whole frame, so a pixel depends on every
//! pixel above and to the left of it. Here the scan restarts at frame-anchored blocks of
//! `scan_block` pixels (default 64): a pixel reads only neighbours in its own block. A tile's
//! halo is then the part of its blocks above and to the left of it; tiles that are multiples
//! of the block (the default 64) have none.

use super::order::Order;
use super::params::Params;
use crate::key::Key;
use crate::tile::Rect;

/// Row-major order restarting at blocks of `block` pixels.
pub struct Scanline {
    block: u32,
}

impl Scanline {
    pub fn new(params: &Params) -> Scanline {
        Scanline {
            block: params.scan_block,
        }
    }
}

impl Order for Scanline {
    fn name(&self) -> &'static str {
        "scan"
    }

    /// Left, upper-left and upper, inside the pixel's block.
    fn voters(
        &self,
        x: u32,
        y: u32,
        _pass: usize,
        frame: Rect,
        out: &mut [(u32, u32); 4],
    ) -> usize {
        let b = self.block;
        let (bx, by) = (x / b * b, y / b * b);
        let mut n = 0;
        for (ok, vx, vy) in [
            (x > bx, x.wrapping_sub(1), y),
            (x > bx && y > by, x.wrapping_sub(1), y.wrapping_sub(1)),
            (y > by, x, y.wrapping_sub(1)),
        ] {
            if ok && frame.contains(vx, vy) {
                out[n] = (vx, vy);
                n += 1;
            }
        }
        n
    }

    /// Every pixel may be read by the next ones along its row and column.
    fn read_later(&self, _pass: usize) -> bool {
        true
    }

    /// [paper] §3: only traced hits are blockers. Keeping predicted ones too lets a
    /// misprediction travel along the row: fewer rays, up to 3× the wrong pairs at 400 lights
    /// (docs/methods.md).
    fn keeps_predicted(&self) -> bool {
        false
    }

    fn region(&self, _frame: Rect, tile: Rect, _phase: usize) -> Rect {
        let b = self.block;
        Rect::new(tile.x0 / b * b, tile.y0 / b * b, tile.x1, tile.y1)
    }

    fn reads(&self) -> &'static [Key] {
        &[Key::ScanBlock]
    }
}
