//! PNG previews: exposure, then the sRGB transfer curve, 8 bits.

use anyhow::Context;

use crate::error::Result;
use crate::film::srgb_encode;

/// Linear RGB → 8-bit sRGB with an exposure multiplier (clipped highlights).
pub fn tonemap(rgb: [f32; 3], exposure: f32) -> [u8; 3] {
    rgb.map(|c| (srgb_encode(c * exposure) * 255.0 + 0.5) as u8)
}

/// The PNG file of an RGB8 image.
fn encode_rgb8(width: u32, height: u32, pixels: Vec<u8>) -> Result<Vec<u8>> {
    let img = image::RgbImage::from_raw(width, height, pixels)
        .context("pixel buffer does not match the image size")?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .context("encoding PNG")?;
    Ok(bytes.into_inner())
}

/// The PNG file of a tone-mapped preview of linear RGB pixels.
pub fn encode_preview(
    width: u32,
    height: u32,
    beauty: &[[f32; 3]],
    exposure: f32,
) -> Result<Vec<u8>> {
    let mut bytes = Vec::with_capacity(beauty.len() * 3);
    for p in beauty {
        bytes.extend_from_slice(&tonemap(*p, exposure));
    }
    encode_rgb8(width, height, bytes)
}
