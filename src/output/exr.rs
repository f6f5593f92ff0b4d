//! EXR frames as Nuke, Blender and OpenImageIO read them: one part, the film's channels
//! ([`Channel`](crate::film::Channel): beauty `R G B A` (premultiplied; alpha 1 over an opaque background), depth `Z`, `N.X N.Y N.Z`, `albedo.R albedo.G albedo.B`, the
//! shadow method's `shadow.rays`, `shadow.visible`, `shadow.wrong`, `shadow.coverage`), and a
//! header with the standard attributes a compositor uses — `worldToCamera` and `worldToNDC`
//! (OpenEXR's conventions, see [`FrameHeader`]), `framesPerSecond`, `chromaticities`
//! (Rec.709 primaries, D65 white: the renderer's linear RGB), `software` — and ours as
//! `envshadow/…`: the frame number, the settings and the frame's counts.
//!
//! With Cryptomatte (`--cryptomatte`), the ID mattes' ranks `CryptoObject00.R` …
//! `CryptoMaterial02.A` and, per type, the specification's `cryptomatte/<key>/name`, `hash`,
//! `conversion` and `manifest` attributes (`crate::cryptomatte`).
//!
//! The layout ([`ExrLayout`], `--exr-layout`) names the channels: ours as above (the
//! default), or Blender's multilayer names (`ViewLayer.Combined.R`, `ViewLayer.Depth.Z`,
//! `ViewLayer.Normal.X`, `ViewLayer.DiffCol.R`, ours as `ViewLayer.ShadowRays.X`, …; see
//! [`Channel::blender_name`]) with the `BlenderMultiChannel` attribute Blender writes in its
//! own multilayer files, and the Cryptomatte types named `ViewLayer.CryptoObject`, as
//! Blender names its own.
//!
//! With `half`, every channel but those that need more ([`Channel::exact`]: counts and
//! depth) is stored as 16-bit half float. ZIP compression, chunks compressed in parallel and
//! written in increasing scanline order, attributes in name order (as OpenEXR's own library
//! writes them), so the same film always gives the same bytes.

use std::path::Path;

use anyhow::{Context, anyhow};
use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::image::write::layers::{LayersWriter, WritableLayers};
use exr::meta::attribute::{AttributeValue, Chromaticities, Text};
use exr::prelude::*;
use rayon::prelude::*;

use crate::cryptomatte;
use crate::error::Result;
use crate::film::{Channel, Film};
use crate::output::rate::FrameRate;
use crate::output::stats::{FrameStats, HEADER};
use crate::tile::Rect;

/// What a frame's EXR header says besides its channels.
#[derive(Clone, Debug)]
pub struct FrameHeader<'a> {
    /// OpenEXR's `worldToCamera` and `worldToNDC`, as OpenEXR stores an M44f: a matrix
    /// that multiplies row vectors on its left, flattened row by row (`crate::camera::Camera`
    /// makes them).
    pub world_to_camera: [f32; 16],
    pub world_to_ndc: [f32; 16],
    /// The frame's number (`envshadow/frame`): the start frame plus its index, as its file
    /// name has it.
    pub number: usize,
    /// The animation's frame rate (`framesPerSecond`, a rational: 29.97 is 30000/1001).
    pub fps: FrameRate,
    /// The settings the frame was rendered with: the lines of `settings.txt`
    /// (`[render] method` → `envshadow/render.method`).
    pub settings: &'a [(String, String)],
    /// The frame's row of `stats.csv`: every column that does not depend on the machine, the
    /// threads or the tiles (`envshadow/stats.rays_traced`, …; not `thread_seconds`, not the halo's
    /// work or the share traced that counts it).
    pub stats: &'a FrameStats,
}

/// How a frame's channels are named (`--exr-layout`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ExrLayout {
    /// Ours: `R G B A`, `Z`, `N.X`, `albedo.R`, `shadow.rays`, … (the default).
    #[default]
    Envshadow,
    /// Blender's multilayer EXR: `ViewLayer.Combined.R`, `ViewLayer.Depth.Z`, …
    Blender,
}

impl ExrLayout {
    /// The name on the command line and in specs.
    pub fn name(self) -> &'static str {
        match self {
            ExrLayout::Envshadow => "envshadow",
            ExrLayout::Blender => "blender",
        }
    }

    /// Channel `c`'s name in this layout.
    pub fn channel_name(self, c: Channel) -> &'static str {
        match self {
            ExrLayout::Envshadow => c.name(),
            ExrLayout::Blender => c.blender_name(),
        }
    }

    /// A Cryptomatte type's name (`CryptoObject`) in this layout: Blender prefixes its view
    /// layer, as its channels are.
    pub fn cryptomatte_name(self, type_name: &str) -> String {
        match self {
            ExrLayout::Envshadow => type_name.to_string(),
            ExrLayout::Blender => format!("{BLENDER_VIEW_LAYER}.{type_name}"),
        }
    }
}

/// The view layer Blender names in its multilayer files by default.
pub const BLENDER_VIEW_LAYER: &str = "ViewLayer";

/// The `BlenderMultiChannel` attribute's value in Blender's multilayer files.
pub const BLENDER_MULTI_CHANNEL: &str = "Blender V2.55.1 and newer";

impl std::fmt::Display for ExrLayout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ExrLayout {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<ExrLayout, String> {
        match s {
            "envshadow" => Ok(ExrLayout::Envshadow),
            "blender" => Ok(ExrLayout::Blender),
            _ => Err(format!(
                "unknown EXR layout {s:?} (expected envshadow or blender)"
            )),
        }
    }
}

impl serde::Serialize for ExrLayout {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// This build's name and version, for the `software` attribute.
pub const SOFTWARE: &str = concat!("envshadow ", env!("CARGO_PKG_VERSION"));

/// The stats columns left out of the header: they depend on the machine or on how the frame
/// was split (tiles, jobs), and the same frame must be the same bytes. `percent_traced` counts
/// the halos' rays, so it depends on the tiles (`rays_traced` and `queries` stay).
fn run_dependent(column: &str) -> bool {
    column.starts_with("halo_")
        || column == "percent_traced"
        || column.contains("second")
        || column.contains("time")
}

/// The EXR file of a frame's film, half-float where `half` allows, with `header`, its
/// channels named as `layout` says.
pub fn encode_frame(
    film: &Film,
    header: &FrameHeader,
    half: bool,
    layout: ExrLayout,
) -> Result<Vec<u8>> {
    let rect = Rect::frame(film.width, film.height);
    let channels = channels_in(film, rect, false, half, layout);
    let mut attrs = LayerAttributes {
        software_name: Some(text(SOFTWARE)),
        world_to_camera: Some(header.world_to_camera),
        world_to_normalized_device: Some(header.world_to_ndc),
        frames_per_second: Some((header.fps.num as i32, header.fps.den)),
        ..LayerAttributes::default()
    };
    let mut put = |name: String, value: AttributeValue| {
        attrs.other.insert(text(&name), value);
    };
    let stats = header.stats;
    put(
        "envshadow/frame".into(),
        AttributeValue::I32(header.number as i32),
    );
    for (key, value) in header.settings {
        put(
            format!("envshadow/{}", setting_name(key)),
            text_value(value),
        );
    }
    for (column, value) in HEADER.split(',').zip(stats.csv_row().split(',')) {
        if column != "frame" && !value.is_empty() && !run_dependent(column) {
            put(format!("envshadow/stats.{column}"), text_value(value));
        }
    }
    if layout == ExrLayout::Blender {
        put(
            "BlenderMultiChannel".into(),
            text_value(BLENDER_MULTI_CHANNEL),
        );
    }
    if let Some(manifests) = &film.cryptomatte {
        for (type_name, manifest) in cryptomatte::TYPES.iter().zip(manifests.iter()) {
            let name = layout.cryptomatte_name(type_name);
            let key = cryptomatte::key(&name);
            for (attr, value) in [
                ("name", name.as_str()),
                ("hash", "MurmurHash3_32"),
                ("conversion", "uint32_to_float32"),
                ("manifest", manifest),
            ] {
                put(format!("cryptomatte/{key}/{attr}"), text_value(value));
            }
        }
    }
    let image_attrs = ImageAttributes {
        chromaticities: Some(REC709),
        ..ImageAttributes::new(IntegerBounds::from_dimensions((
            film.width as usize,
            film.height as usize,
        )))
    };
    encode(
        (film.width as usize, film.height as usize),
        channels,
        attrs,
        image_attrs,
    )
}

/// A settings line's key as an attribute name: `[render] method` → `render.method`,
/// `--region` → `region`.
fn setting_name(key: &str) -> String {
    match key.strip_prefix('[').and_then(|k| k.split_once("] ")) {
        Some((table, key)) => format!("{table}.{key}"),
        None => key.trim_start_matches('-').to_string(),
    }
}

/// Rec.709 primaries and D65 white: what the renderer's linear RGB is.
const REC709: Chromaticities = Chromaticities {
    red: Vec2(0.64, 0.33),
    green: Vec2(0.30, 0.60),
    blue: Vec2(0.15, 0.06),
    white: Vec2(0.3127, 0.3290),
};

/// A text attribute's bytes: UTF-8, as OpenEXR's library and OpenImageIO read strings.
fn text(s: &str) -> Text {
    Text::from_slice_unchecked(s.as_bytes())
}

fn text_value(s: &str) -> AttributeValue {
    AttributeValue::Text(text(s))
}

/// The film's channels over `rect` (frame pixels), in [`Film::channels`] order (with
/// `reference`, the validation's brute-force image too); half-float where `half` allows.
/// Copied a channel per task on the current rayon pool.
pub fn film_channels(
    film: &Film,
    rect: Rect,
    reference: bool,
    half: bool,
) -> Vec<AnyChannel<FlatSamples>> {
    channels_in(film, rect, reference, half, ExrLayout::Envshadow)
}

/// [`film_channels`] named as `layout` says.
fn channels_in(
    film: &Film,
    rect: Rect,
    reference: bool,
    half: bool,
    layout: ExrLayout,
) -> Vec<AnyChannel<FlatSamples>> {
    let fw = film.width as usize;
    film.channels(reference)
        .into_par_iter()
        .map(|c| {
            let mut v = Vec::with_capacity(rect.area());
            for y in rect.y0..rect.y1 {
                for x in rect.x0..rect.x1 {
                    v.push(film.get(c, y as usize * fw + x as usize));
                }
            }
            let samples = if half && !c.exact() {
                FlatSamples::F16(v.into_iter().map(f16::from_f32).collect())
            } else {
                FlatSamples::F32(v)
            };
            AnyChannel::new(layout.channel_name(c), samples)
        })
        .collect()
}

/// Writes `channels` of a `size` image to `path` atomically, with no attributes beyond the
/// required ones (farm tile images).
pub fn write_channels(
    path: &Path,
    size: (usize, usize),
    channels: Vec<AnyChannel<FlatSamples>>,
) -> Result<()> {
    let image_attrs = ImageAttributes::new(IntegerBounds::from_dimensions(size));
    let bytes = encode(size, channels, LayerAttributes::default(), image_attrs)?;
    super::write_atomic(path, &bytes).with_context(|| format!("writing EXR {}", path.display()))
}

/// The EXR file of `channels` of a `size` image with the given attributes: ZIP compression,
/// chunk by chunk in parallel on the current rayon pool, the chunks written in increasing
/// scanline order whatever order they finish in, and attributes in name order, so the same
/// samples and attributes always give the same bytes, on any number of threads.
fn encode(
    size: (usize, usize),
    channels: Vec<AnyChannel<FlatSamples>>,
    layer_attrs: LayerAttributes,
    image_attrs: ImageAttributes,
) -> Result<Vec<u8>> {
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        size,
        layer_attrs,
        encoding,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let headers = layer.infer_headers(&image_attrs);
    let layers = layer.create_writer(&headers);
    let mut bytes = std::io::Cursor::new(Vec::new());
    // What the exr crate's own writer does, but on our pool: its parallel writer builds a
    // thread pool of every core for each file, whatever `--threads` says.
    exr::block::write(&mut bytes, headers, true, |meta, chunks| {
        let blocks: Vec<(usize, BlockIndex)> =
            meta.enumerate_ordered_header_block_indices().collect();
        let compressed = blocks
            .into_par_iter()
            .map(|(index, block)| {
                let data = layers.extract_uncompressed_block(&meta.headers, block);
                let chunk =
                    UncompressedBlock { index: block, data }.compress_to_chunk(&meta.headers)?;
                Ok((index, chunk))
            })
            .collect::<exr::error::Result<Vec<_>>>()?;
        // `collect` keeps the blocks' order: the file's chunks increase in y.
        for (index, chunk) in compressed {
            chunks.write_chunk(index, chunk)?;
        }
        Ok(())
    })
    .context("encoding EXR")?;
    let mut bytes = bytes.into_inner();
    sort_attributes(&mut bytes)?;
    Ok(bytes)
}

/// Puts the attributes of a single-part EXR's header in name order, in place. The exr crate
/// keeps custom attributes in a `HashMap` and writes them in its iteration order, which
/// changes from one run to the next; OpenEXR's own library writes them sorted by name. The
/// header keeps its length, so the offset table after it stays right.
fn sort_attributes(bytes: &mut [u8]) -> Result<()> {
    let bad = || anyhow!("encoding EXR: malformed header");
    let nul = |from: usize| -> Result<usize> {
        bytes
            .get(from..)
            .and_then(|b| b.iter().position(|&c| c == 0))
            .map(|k| from + k)
            .ok_or_else(bad)
    };
    const START: usize = 8; // magic number and version field
    let mut pos = START;
    let mut attrs: Vec<(Vec<u8>, std::ops::Range<usize>)> = Vec::new();
    while *bytes.get(pos).ok_or_else(bad)? != 0 {
        let name_end = nul(pos)?;
        let type_end = nul(name_end + 1)?;
        let size = bytes.get(type_end + 1..type_end + 5).ok_or_else(bad)?;
        let size = u32::from_le_bytes(size.try_into().map_err(|_| bad())?) as usize;
        let end = type_end + 5 + size;
        if end > bytes.len() {
            return Err(bad());
        }
        attrs.push((bytes[pos..name_end].to_vec(), pos..end));
        pos = end;
    }
    attrs.sort_by(|a, b| a.0.cmp(&b.0));
    let mut sorted = Vec::with_capacity(pos - START);
    for (_, r) in &attrs {
        sorted.extend_from_slice(&bytes[r.clone()]);
    }
    bytes[START..pos].copy_from_slice(&sorted);
    Ok(())
}

/// A frame read back: channel name → samples (row-major), the size and the header's
/// attributes.
pub struct ReadFrame {
    pub width: usize,
    pub height: usize,
    pub channels: Vec<(String, Vec<f32>)>,
    pub attributes: LayerAttributes,
}

impl ReadFrame {
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
}

/// Reads every channel of the first layer of an EXR made by [`encode_frame`] (half-float
/// channels widened to f32).
pub fn read_frame(path: &Path) -> Result<ReadFrame> {
    read_frame_with(path, true)
}

/// [`read_frame`] decompressing on the calling thread: for callers that read many frames at
/// once, a frame per thread, where the exr crate's parallel reading (a thread pool of every
/// core for each file) only costs.
pub fn read_frame_here(path: &Path) -> Result<ReadFrame> {
    read_frame_with(path, false)
}

fn read_frame_with(path: &Path, parallel: bool) -> Result<ReadFrame> {
    let file = std::fs::File::open(path)
        .map_err(|e| crate::error::input_error(path, format!("cannot open: {e}")))?;
    read_frame_from(std::io::BufReader::new(file), parallel)
        .map_err(|e| crate::error::input_error(path, format!("not a readable EXR: {e}")))
}

/// [`read_frame`] from any seekable reader.
fn read_frame_from(
    reader: impl std::io::Read + std::io::Seek + Send,
    parallel: bool,
) -> std::result::Result<ReadFrame, exr::error::Error> {
    let read = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes();
    let image = if parallel {
        read.from_buffered(reader)?
    } else {
        read.non_parallel().from_buffered(reader)?
    };
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
        attributes: layer.attributes,
    })
}

/// Copies the pixels of `copy` from `img`, an EXR of the frame pixels of `rect` (which holds
/// `copy`), into `film`: every channel `film` holds must be there (`reference`: the
/// validation's brute-force image too). Errors name the missing channel.
pub fn fill_film(
    img: &ReadFrame,
    rect: Rect,
    copy: Rect,
    film: &mut Film,
    reference: bool,
) -> std::result::Result<(), String> {
    let fw = film.width as usize;
    let rw = rect.width() as usize;
    for c in film.channels(reference) {
        let v = img
            .channel(c.name())
            .ok_or_else(|| format!("no channel {}", c.name()))?;
        for y in copy.y0..copy.y1 {
            for x in copy.x0..copy.x1 {
                let src = v[(y - rect.y0) as usize * rw + (x - rect.x0) as usize];
                film.set(c, y as usize * fw + x as usize, src);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats() -> FrameStats {
        FrameStats {
            frame: 7,
            method: "brute".into(),
            lights: 3,
            width: 4,
            height: 2,
            spp: 1,
            counts: Default::default(),
            image_error: None,
            thread_seconds: 0.25,
            camera_position: glam::Vec3::new(0.0, 1.0, 5.0),
            camera_target: glam::Vec3::ZERO,
            camera_up: glam::Vec3::Y,
            vfov_deg: 40.0,
        }
    }

    /// The exr crate writes custom attributes in a HashMap's order, which changes with every
    /// map; the header is sorted, so a frame is the same bytes every time.
    #[test]
    fn the_same_frame_is_the_same_bytes() {
        let film = Film::new(4, 2, Default::default());
        let settings: Vec<(String, String)> = (0..20)
            .map(|k| (format!("[render] key{k}"), k.to_string()))
            .collect();
        let stats = stats();
        let header = FrameHeader {
            world_to_camera: [0.0; 16],
            world_to_ndc: [1.0; 16],
            number: stats.frame,
            fps: FrameRate::whole(24),
            settings: &settings,
            stats: &stats,
        };
        let first = encode_frame(&film, &header, false, ExrLayout::Envshadow).unwrap();
        for _ in 0..10 {
            assert!(encode_frame(&film, &header, false, ExrLayout::Envshadow).unwrap() == first);
        }
        // Sorted by name, the header reads back.
        let back = read_frame_from(std::io::Cursor::new(first), false).unwrap();
        let attrs = &back.attributes;
        assert_eq!(attrs.world_to_normalized_device, Some([1.0; 16]));
        assert_eq!(
            attrs.other.get(&text("envshadow/frame")),
            Some(&AttributeValue::I32(7))
        );
        assert!(attrs.other.contains_key(&text("envshadow/render.key19")));
        assert!(
            !attrs
                .other
                .contains_key(&text("envshadow/stats.thread_seconds"))
        );
    }

    /// Chunks compressed in parallel are the file the exr crate's own sequential writer
    /// makes, byte for byte, on any number of threads: the chunks stay in increasing y.
    #[test]
    fn parallel_compression_writes_the_sequential_writers_bytes() {
        let (w, h) = (37, 101); // seven 16-line chunks, the last one short
        let mut film = Film::new(w, h, Default::default());
        for c in film.channels(false) {
            for i in 0..(w * h) as usize {
                // Smooth with some noise, so chunks compress to different sizes.
                let v = libm::sinf(i as f32 * 0.013) + ((i * 7919) % 13) as f32 * 0.01;
                film.set(c, i, v);
            }
        }
        let stats = stats();
        let header = FrameHeader {
            world_to_camera: [0.0; 16],
            world_to_ndc: [1.0; 16],
            number: stats.frame,
            fps: FrameRate::whole(24),
            settings: &[],
            stats: &stats,
        };
        for half in [false, true] {
            let channels = film_channels(&film, Rect::frame(w, h), false, half);
            let size = (w as usize, h as usize);
            let layer = Layer::new(
                size,
                LayerAttributes::default(),
                Encoding {
                    compression: Compression::ZIP16,
                    blocks: Blocks::ScanLines,
                    line_order: LineOrder::Increasing,
                },
                AnyChannels::sort(SmallVec::from_vec(channels.clone())),
            );
            let image = Image {
                attributes: ImageAttributes::new(IntegerBounds::from_dimensions(size)),
                layer_data: layer,
            };
            let mut sequential = std::io::Cursor::new(Vec::new());
            image
                .write()
                .non_parallel()
                .to_buffered(&mut sequential)
                .unwrap();
            let mut sequential = sequential.into_inner();
            sort_attributes(&mut sequential).unwrap();
            for threads in [1, 3, 8] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let attrs = ImageAttributes::new(IntegerBounds::from_dimensions(size));
                let ours = pool
                    .install(|| encode(size, channels.clone(), LayerAttributes::default(), attrs))
                    .unwrap();
                assert!(
                    ours == sequential,
                    "half {half}, {threads} threads: other bytes"
                );
            }
            // The frame writer's own path too: the same bytes on any pool.
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let many = rayon::ThreadPoolBuilder::new()
                .num_threads(6)
                .build()
                .unwrap();
            let a = one
                .install(|| encode_frame(&film, &header, half, ExrLayout::Envshadow))
                .unwrap();
            let b = many
                .install(|| encode_frame(&film, &header, half, ExrLayout::Envshadow))
                .unwrap();
            assert!(a == b, "half {half}: a frame's bytes depend on the threads");
        }
    }

    #[test]
    fn settings_lines_become_attribute_names() {
        assert_eq!(setting_name("[render] method"), "render.method");
        assert_eq!(setting_name("--region"), "region");
    }
}
