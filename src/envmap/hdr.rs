//! Radiance RGBE (`.hdr`) maps through the `image` crate's decoder.

use glam::Vec3;
use image::ImageDecoder;
use std::io::Cursor;
use std::path::Path;

use super::{check_plausible, check_size};
use crate::bail_input;
use crate::error::Result;

/// Decodes `bytes` (named `path` in errors) as (width, height, texels). Validation of the
/// values is the caller's.
pub(super) fn decode(bytes: &[u8], path: &Path) -> Result<(usize, usize, Vec<Vec3>)> {
    let decoder = match image::codecs::hdr::HdrDecoder::new(Cursor::new(bytes)) {
        Ok(d) => d,
        Err(e) => bail_input!(path, "not a valid Radiance HDR file: {e}"),
    };
    // The header's size is checked before the decoder allocates the pixels.
    let (w, h) = decoder.dimensions();
    check_size(path, w as usize, h as usize)?;
    check_plausible(path, w as usize, h as usize, bytes.len())?;
    let image = match image::DynamicImage::from_decoder(decoder) {
        Ok(i) => i.into_rgb32f(),
        Err(e) => bail_input!(path, "cannot decode Radiance HDR pixels: {e}"),
    };
    let texels = image
        .pixels()
        .map(|p| Vec3::new(p.0[0], p.0[1], p.0[2]))
        .collect();
    Ok((w as usize, h as usize, texels))
}
