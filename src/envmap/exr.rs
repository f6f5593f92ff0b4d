//! OpenEXR lat-long maps through the `exr` crate: the first layer with R, G, B (A optional),
//! half or float, scanline or tiled; of a mip-mapped file only the full-resolution level 0.

use ::exr::prelude::{ReadChannels, ReadLayers};
use glam::Vec3;
use std::io::Cursor;
use std::path::Path;

use super::{check_plausible, check_size};
use crate::bail_input;
use crate::error::Result;
use crate::limits::{Budget, NoMemory, try_vec};

/// Decodes `bytes` (named `path` in errors) as (width, height, texels), once `budget` has
/// counted the largest size the headers declare. Validation of the values is the caller's.
pub(super) fn decode(
    bytes: &[u8],
    path: &Path,
    budget: &mut Budget,
) -> Result<(usize, usize, Vec<Vec3>)> {
    // Headers first, so an absurd declared size is refused before pixels are allocated.
    let meta = match ::exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false) {
        Ok(m) => m,
        Err(e) => bail_input!(path, "not a readable OpenEXR file: {e}"),
    };
    let mut largest = 0;
    for header in &meta.headers {
        let (w, h) = (header.layer_size.0, header.layer_size.1);
        check_size(path, w, h)?;
        check_plausible(path, w, h, bytes.len())?;
        largest = largest.max(w as u64 * h as u64);
    }
    check_channels(path, &meta)?;
    budget.map(path, largest, bytes.len() as u64)?;
    // The texels are asked of the system inside the reader's callback, which cannot fail: a
    // refusal leaves them empty, the pixel callback writes nowhere, and it is reported below.
    let image = ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size: ::exr::math::Vec2<usize>, _channels: &::exr::prelude::RgbaChannels| {
                let n = size.0 * size.1;
                let mut texels = try_vec(n, "").unwrap_or_default();
                if texels.capacity() >= n {
                    texels.resize(n, Vec3::ZERO);
                }
                (size.0, texels)
            },
            |(w, texels): &mut (usize, Vec<Vec3>),
             pos: ::exr::math::Vec2<usize>,
             (r, g, b, _a): (f32, f32, f32, f32)| {
                if let Some(t) = texels.get_mut(pos.1 * *w + pos.0) {
                    *t = Vec3::new(r, g, b);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes));
    let image = match image {
        Ok(i) => i,
        Err(e) => bail_input!(path, "cannot decode OpenEXR RGB layer: {e}"),
    };
    let size = image.layer_data.size;
    let (_, texels) = image.layer_data.channel_data.pixels;
    if texels.len() != size.0 * size.1 {
        let e = NoMemory {
            bytes: (size.0 * size.1 * size_of::<Vec3>()) as u128,
            what: "the map's texels".to_string(),
        };
        return Err(anyhow::Error::new(e).context(path.display().to_string()));
    }
    Ok((size.0, size.1, texels))
}

/// Refuses a file none of whose layers has R, G and B channels, listing the channels it has
/// (a luminance-only `Y` map, a render's `diffuse.R`-style layers) rather than the reader's
/// "no valid layer".
fn check_channels(path: &Path, meta: &::exr::meta::MetaData) -> Result<()> {
    let mut found = Vec::new();
    for header in &meta.headers {
        let layer = header
            .own_attributes
            .layer_name
            .as_ref()
            .map(|n| format!("{n}."))
            .unwrap_or_default();
        let names: Vec<String> = header
            .channels
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        if ["R", "G", "B"].iter().all(|k| names.iter().any(|n| n == k)) {
            return Ok(());
        }
        found.extend(names.into_iter().map(|n| format!("{layer}{n}")));
    }
    let found: Vec<String> = found
        .iter()
        .map(|n| crate::error::escaped(n).into_owned())
        .collect();
    bail_input!(
        path,
        "no layer with R, G and B channels, which an environment map needs (found: {}); \
         save the map as RGB (a luminance-only or multi-layer EXR is not read)",
        if found.is_empty() {
            "no channels".to_string()
        } else {
            found.join(", ")
        }
    )
}
