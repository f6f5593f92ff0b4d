//! The film: a frame's beauty and AOV buffers, assembled from finished tiles.

use crate::frame::TileResult;
use crate::output::png::srgb_encode;
use crate::output::stats::{Counts, ImageError};
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
    /// With validation: wrong (pixel, light) pairs per pixel, and the brute-force image.
    pub wrong: Option<Vec<f32>>,
    pub reference: Option<Vec<[f32; 3]>>,
    /// Sum of the tiles' counts.
    pub counts: Counts,
}

impl Film {
    pub fn new(width: u32, height: u32, validated: bool) -> Film {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            beauty: vec![[0.0; 3]; n],
            rays: vec![0.0; n],
            visible: vec![0.0; n],
            wrong: validated.then(|| vec![0.0; n]),
            reference: validated.then(|| vec![[0.0; 3]; n]),
            counts: Counts::default(),
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
            if let (Some(d), Some(s)) = (&mut self.wrong, &tile.wrong) {
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
            if let (Some(d), Some(s)) = (&mut self.reference, &tile.reference) {
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
        }
        self.counts += tile.counts;
    }

    /// With validation: the beauty against the brute-force image over `region` (the rendered
    /// pixels); the relative RMSE is relative to the brute-force image's mean.
    pub fn image_error(&self, region: Rect, exposure: f32) -> Option<ImageError> {
        let reference = self.reference.as_ref()?;
        let (mut se, mut sum_ref, mut n, mut se_ldr) = (0f64, 0f64, 0u64, 0f64);
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let i = y as usize * self.width as usize + x as usize;
                let (b, r) = (self.beauty[i], reference[i]);
                for c in 0..3 {
                    let d = (b[c] - r[c]) as f64;
                    se += d * d;
                    let dl = (srgb_encode(b[c] * exposure) - srgb_encode(r[c] * exposure)) as f64;
                    se_ldr += dl * dl;
                }
                n += 3;
                sum_ref += (r[0] + r[1] + r[2]) as f64;
            }
        }
        let rmse = (se / n.max(1) as f64).sqrt();
        let mean = sum_ref / n.max(1) as f64;
        let mse_ldr = se_ldr / n.max(1) as f64;
        Some(ImageError {
            rmse,
            rel_rmse: if mean > 0.0 { rmse / mean } else { 0.0 },
            psnr_db: if mse_ldr > 0.0 {
                -10.0 * mse_ldr.log10()
            } else {
                f64::INFINITY
            },
        })
    }
}
