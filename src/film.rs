//! The film: a frame's beauty and AOV buffers, assembled from finished tiles.

use crate::frame::TileResult;
use crate::output::stats::Counts;
use crate::tile::Rect;

/// One frame's pixels: linear RGB beauty and the per-pixel AOVs, row-major, full frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub beauty: Vec<[f32; 3]>,
    /// Shadow rays traced per pixel.
    pub rays: Vec<f32>,
    /// Fraction of above-horizon lights visible.
    pub visible: Vec<f32>,
    /// Sum of the tiles' counts.
    pub counts: Counts,
    /// Tiles added so far.
    pub tiles: usize,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Film {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            beauty: vec![[0.0; 3]; n],
            rays: vec![0.0; n],
            visible: vec![0.0; n],
            counts: Counts::default(),
            tiles: 0,
        }
    }

    /// Copies a finished tile into place and adds its counts.
    pub fn add(&mut self, tile: &TileResult) {
        let r = tile.rect;
        let w = r.width() as usize;
        for y in r.y0..r.y1 {
            let src = (y - r.y0) as usize * w;
            let dst = y as usize * self.width as usize + r.x0 as usize;
            self.beauty[dst..dst + w].copy_from_slice(&tile.beauty[src..src + w]);
            self.rays[dst..dst + w].copy_from_slice(&tile.rays[src..src + w]);
            self.visible[dst..dst + w].copy_from_slice(&tile.visible[src..src + w]);
        }
        self.counts += tile.counts;
        self.tiles += 1;
    }

    /// The full frame's rectangle.
    pub fn rect(&self) -> Rect {
        Rect::frame(self.width, self.height)
    }
}
