//! Splitting a frame into tiles.
//!
//! A tile is a half-open pixel rectangle. The tiles of a frame are listed in row-major order and
//! numbered from 0; that number is the tile's identity in progress reports and job plans.

use std::fmt;

/// A half-open pixel rectangle [x0, x1) × [y0, y1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Rect {
    pub fn new(x0: u32, y0: u32, x1: u32, y1: u32) -> Rect {
        Rect { x0, y0, x1, y1 }
    }
    /// The whole `width`×`height` frame.
    pub fn frame(width: u32, height: u32) -> Rect {
        Rect::new(0, 0, width, height)
    }
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }
    pub fn area(&self) -> usize {
        self.width() as usize * self.height() as usize
    }
    pub fn is_empty(&self) -> bool {
        self.area() == 0
    }
    pub fn contains(&self, x: u32, y: u32) -> bool {
        x >= self.x0 && x < self.x1 && y >= self.y0 && y < self.y1
    }
    /// This rectangle grown by `d` pixels on every side (not below 0; clip with `intersect`).
    pub fn grow(&self, d: u32) -> Rect {
        Rect::new(
            self.x0.saturating_sub(d),
            self.y0.saturating_sub(d),
            self.x1 + d,
            self.y1 + d,
        )
    }
    /// The overlap of two rectangles (empty if they do not meet).
    pub fn intersect(&self, other: &Rect) -> Rect {
        let x0 = self.x0.max(other.x0);
        let y0 = self.y0.max(other.y0);
        Rect::new(
            x0,
            y0,
            self.x1.min(other.x1).max(x0),
            self.y1.min(other.y1).max(y0),
        )
    }
    /// Index of pixel (x, y) in a row-major buffer covering this rectangle.
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y - self.y0) as usize * self.width() as usize + (x - self.x0) as usize
    }
}

impl fmt::Display for Rect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

/// One tile of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Position in the frame's row-major tile list.
    pub index: usize,
    pub rect: Rect,
}

/// The tiles of a `width`×`height` frame of `size`×`size` pixels (`size == 0`: one tile for the
/// whole frame), clipped to `region` when given. Tiles keep their frame-wide numbering and
/// grid alignment when a region clips them, so a region render reuses the same tile ids.
pub fn tiles(width: u32, height: u32, size: u32, region: Option<Rect>) -> Vec<Tile> {
    let frame = Rect::frame(width, height);
    let region = region.map_or(frame, |r| r.intersect(&frame));
    let (tw, th) = if size == 0 {
        (width.max(1), height.max(1))
    } else {
        (size, size)
    };
    let cols = width.div_ceil(tw);
    let rows = height.div_ceil(th);
    let mut out = Vec::new();
    for ty in 0..rows {
        for tx in 0..cols {
            let full = Rect::new(
                tx * tw,
                ty * th,
                ((tx + 1) * tw).min(width),
                ((ty + 1) * th).min(height),
            );
            let rect = full.intersect(&region);
            if !rect.is_empty() {
                out.push(Tile {
                    index: (ty * cols + tx) as usize,
                    rect,
                });
            }
        }
    }
    out
}

/// The bounding rectangle of some tiles.
pub fn bounding(tiles: &[Tile]) -> Rect {
    let mut r = tiles.first().map(|t| t.rect).unwrap_or_default();
    for t in tiles {
        r = Rect::new(
            r.x0.min(t.rect.x0),
            r.y0.min(t.rect.y0),
            r.x1.max(t.rect.x1),
            r.y1.max(t.rect.y1),
        );
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_frame_exactly_once() {
        for (w, h, s) in [
            (64, 48, 16),
            (65, 47, 16),
            (10, 10, 0),
            (7, 3, 8),
            (640, 480, 64),
        ] {
            let mut seen = vec![0u8; (w * h) as usize];
            for t in tiles(w, h, s, None) {
                for y in t.rect.y0..t.rect.y1 {
                    for x in t.rect.x0..t.rect.x1 {
                        seen[(y * w + x) as usize] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "{w}x{h} tile {s}");
        }
    }

    #[test]
    fn region_clips_and_keeps_tile_numbers() {
        let all = tiles(64, 64, 16, None);
        let part = tiles(64, 64, 16, Some(Rect::new(10, 10, 20, 20)));
        assert_eq!(part.len(), 4);
        for t in &part {
            let whole = all.iter().find(|a| a.index == t.index).unwrap();
            assert_eq!(whole.rect.intersect(&t.rect), t.rect);
        }
        assert_eq!(part.iter().map(|t| t.rect.area()).sum::<usize>(), 100);
    }
}
