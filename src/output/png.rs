//! PNG previews: exposure, then the sRGB transfer curve, 8 bits.

use std::path::Path;

use anyhow::Context;

use crate::error::Result;
use crate::film::srgb_encode;

/// Linear RGB → 8-bit sRGB with an exposure multiplier (clipped highlights).
pub fn tonemap(rgb: [f32; 3], exposure: f32) -> [u8; 3] {
    rgb.map(|c| (srgb_encode(c * exposure) * 255.0 + 0.5) as u8)
}

/// Writes an RGB8 image atomically.
pub fn write_rgb8(path: &Path, width: u32, height: u32, pixels: Vec<u8>) -> Result<()> {
    let img = image::RgbImage::from_raw(width, height, pixels)
        .context("pixel buffer does not match the image size")?;
    super::write_atomic_with(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .with_context(|| format!("encoding PNG {}", tmp.display()))
    })
}

/// Writes a tone-mapped preview of linear RGB pixels.
pub fn write_preview(
    path: &Path,
    width: u32,
    height: u32,
    beauty: &[[f32; 3]],
    exposure: f32,
) -> Result<()> {
    let mut bytes = Vec::with_capacity(beauty.len() * 3);
    for p in beauty {
        bytes.extend_from_slice(&tonemap(*p, exposure));
    }
    write_rgb8(path, width, height, bytes)
}
