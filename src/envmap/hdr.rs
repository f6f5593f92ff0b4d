//! Radiance RGBE (`.hdr`) maps through the `image` crate's decoder.

use glam::Vec3;
use image::ImageDecoder;
use std::io::Cursor;
use std::path::Path;

use super::{check_plausible, check_size};
use crate::bail_input;
use crate::error::Result;
use crate::limits::{Budget, NoMemory, try_vec, try_zeroed};

/// Decodes `bytes` (named `path` in errors) as (width, height, texels), once `budget` has
/// counted the size the header declares. Validation of the values is the caller's.
pub(super) fn decode(
    bytes: &[u8],
    path: &Path,
    budget: &mut Budget,
) -> Result<(usize, usize, Vec<Vec3>)> {
    let decoder = match image::codecs::hdr::HdrDecoder::new(Cursor::new(bytes)) {
        Ok(d) => d,
        Err(e) => bail_input!(path, "not a valid Radiance HDR file: {e}"),
    };
    // The header's size is checked before the pixels are allocated.
    let (w, h) = decoder.dimensions();
    check_size(path, w as usize, h as usize)?;
    check_plausible(path, w as usize, h as usize, bytes.len())?;
    budget.map(path, u64::from(w) * u64::from(h), bytes.len() as u64)?;
    let refused = |e: NoMemory| anyhow::Error::new(e).context(path.display().to_string());
    // The decoder's RGB f32 samples; untouched pages cost nothing if the file ends early.
    let mut rgb =
        try_zeroed(decoder.total_bytes() as usize, "the map's pixels").map_err(refused)?;
    if let Err(e) = decoder.read_image(&mut rgb) {
        bail_input!(path, "cannot decode Radiance HDR pixels: {e}");
    }
    let mut texels = try_vec(w as usize * h as usize, "the map's texels").map_err(refused)?;
    texels.extend(rgb.chunks_exact(12).map(|p| {
        let c = |k: usize| f32::from_ne_bytes([p[k], p[k + 1], p[k + 2], p[k + 3]]);
        Vec3::new(c(0), c(4), c(8))
    }));
    Ok((w as usize, h as usize, texels))
}
