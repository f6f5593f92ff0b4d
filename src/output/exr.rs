//! EXR frames: float RGB beauty plus AOV channels.
//!
//! Channels: `R`, `G`, `B` (linear radiance, premultiplied by alpha), `A` (alpha: coverage
//! over a transparent background, 1 over an opaque one; `crate::film::Film::alpha`), `rays` (shadow rays traced at the pixel),
//! `visible` (fraction of above-horizon lights visible), with samples per pixel `coverage`
//! (the filter-weighted fraction of the pixel's samples that hit the scene), with validation
//! `wrong` (wrong pairs, summed over the samples). ZIP compression in increasing scanline
//! order, written on one thread, so the same film always gives the same bytes.

use std::path::Path;

use anyhow::Context;
use exr::prelude::*;

use crate::error::Result;
use crate::film::Film;

/// Extra per-pixel channels written beside the beauty.
pub struct Aov<'a> {
    pub name: &'a str,
    pub values: &'a [f32],
}

/// The EXR file of the film's beauty and AOVs (plus `extra`).
pub fn encode_frame(film: &Film, extra: &[Aov]) -> Result<Vec<u8>> {
    let (w, h) = (film.width as usize, film.height as usize);
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let v: Vec<f32> = film.beauty.iter().map(|p| p[c]).collect();
        channels.push(AnyChannel::new(*name, FlatSamples::F32(v)));
    }
    let alpha = film.alpha.clone().unwrap_or_else(|| vec![1.0; w * h]);
    channels.push(AnyChannel::new("A", FlatSamples::F32(alpha)));
    channels.push(AnyChannel::new("rays", FlatSamples::F32(film.rays.clone())));
    channels.push(AnyChannel::new(
        "visible",
        FlatSamples::F32(film.visible.clone()),
    ));
    for aov in extra {
        channels.push(AnyChannel::new(
            aov.name,
            FlatSamples::F32(aov.values.to_vec()),
        ));
    }
    encode_channels((w, h), channels)
}

/// Writes float `channels` of a `size` image to `path` atomically ([`encode_channels`]).
pub fn write_channels(
    path: &Path,
    size: (usize, usize),
    channels: Vec<AnyChannel<FlatSamples>>,
) -> Result<()> {
    let bytes = encode_channels(size, channels)?;
    super::write_atomic(path, &bytes).with_context(|| format!("writing EXR {}", path.display()))
}

/// The EXR file of float `channels` of a `size` image: ZIP compression in increasing
/// scanline order on one thread, so the same samples always give the same bytes.
pub fn encode_channels(
    size: (usize, usize),
    channels: Vec<AnyChannel<FlatSamples>>,
) -> Result<Vec<u8>> {
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let image = Image::from_layer(layer);
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .context("encoding EXR")?;
    Ok(bytes.into_inner())
}

/// A frame read back: channel name → samples (row-major), and the size.
pub struct ReadFrame {
    pub width: usize,
    pub height: usize,
    pub channels: Vec<(String, Vec<f32>)>,
}

impl ReadFrame {
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
}

/// Reads every channel of the first layer of an EXR made by [`encode_frame`].
pub fn read_frame(path: &Path) -> Result<ReadFrame> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| crate::error::input_error(path, format!("not a readable EXR: {e}")))?;
    let layer = image.layer_data;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect();
    Ok(ReadFrame {
        width: layer.size.width(),
        height: layer.size.height(),
        channels,
    })
}
