//! `EXT_meshopt_compression`: buffer views whose bytes are meshoptimizer streams (gltfpack's
//! `-c`/`-cc` output), decoded with the `meshoptimizer-rs` crate (pure Rust, its SIMD
//! feature off so no unsafe code; the filters' arithmetic is its own, IEEE and `libm`, never
//! the host's) into the view's place in its buffer, which the loader then reads as it reads
//! any view. A buffer the extension marks as a fallback and gives no URI is that place: it
//! is made of zeros, then filled.

use std::path::Path;

use ::gltf::Document;
use meshoptimizer_rs::codec::{Filter, Mode, decode_buffer_view_into};
use meshoptimizer_rs::{Limits, Workspace};
use serde_json::Value;

use crate::bail_input;
use crate::error::Result;

/// The extension's name, as files spell it.
pub(super) const EXTENSION: &str = "EXT_meshopt_compression";

/// Whether `buffer` is a fallback the extension fills: its bytes are not in the file.
pub(super) fn is_fallback(buffer: &::gltf::Buffer) -> bool {
    buffer
        .extension_value(EXTENSION)
        .and_then(|e| e.get("fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// What a compressed view's extension object says, checked to lie within the buffers.
struct Stream {
    source: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

/// Decodes every compressed view of `document` into its place in `buffers`. A stream that
/// cannot be decoded, or whose declared layout does not fit its view or its buffers, is
/// refused naming the extension and the view.
pub(super) fn decode_all(path: &Path, document: &Document, buffers: &mut [Vec<u8>]) -> Result<()> {
    // Each view's decoding is bounded by what it declares (count × stride, checked against
    // its view's byteLength below), so the crate's own limits only guard its scratch.
    let mut workspace = Workspace::new(Limits::default());
    for view in document.views() {
        let Some(ext) = view.extension_value(EXTENSION) else {
            continue;
        };
        let at = format!("{EXTENSION}: bufferView {}", view.index());
        let s = stream(path, &at, ext, buffers)?;
        let bytes = s.count.saturating_mul(s.stride);
        if bytes > view.length() {
            bail_input!(
                path,
                "{at}: {} elements of {} bytes do not fit the view's {} bytes",
                s.count,
                s.stride,
                view.length()
            );
        }
        let start = view.offset();
        let target = view.buffer().index();
        if start
            .checked_add(bytes)
            .is_none_or(|end| buffers[target].len() < end)
        {
            bail_input!(
                path,
                "{at}: the view ends past its buffer {target} ({} bytes)",
                buffers[target].len()
            );
        }
        // The source may be the same buffer: copied out first (it is the small side).
        let source = buffers[s.source][s.offset..s.offset + s.length].to_vec();
        let destination = &mut buffers[target][start..start + bytes];
        decode_buffer_view_into(
            destination,
            s.mode,
            s.filter,
            s.count,
            s.stride,
            &source,
            &mut workspace,
        )
        .map_err(|e| {
            crate::error::input_error(
                path,
                format!(
                    "{at}: cannot decode the stream ({e}); the file may be damaged, or written \
                     by a newer encoder: re-export it without meshopt compression \
                     (`gltfpack -i in.glb -o out.glb`, no `-c`)"
                ),
            )
        })?;
    }
    Ok(())
}

/// The extension object of a view, read and checked against the buffers.
fn stream(path: &Path, at: &str, ext: &Value, buffers: &[Vec<u8>]) -> Result<Stream> {
    let number = |key: &str, default: Option<u64>| -> Result<usize> {
        match ext.get(key).map(Value::as_u64) {
            Some(Some(n)) => usize::try_from(n).map_err(|_| {
                crate::error::input_error(path, format!("{at}: {key} {n} is too large"))
            }),
            Some(None) => bail_input!(path, "{at}: {key} is not a non-negative integer"),
            None => match default {
                Some(n) => Ok(n as usize),
                None => bail_input!(path, "{at}: {key} is missing"),
            },
        }
    };
    let name = |key: &str, default: Option<&'static str>| -> Result<String> {
        match ext.get(key) {
            Some(Value::String(s)) => Ok(s.clone()),
            Some(_) => bail_input!(path, "{at}: {key} is not a string"),
            None => match default {
                Some(s) => Ok(s.to_string()),
                None => bail_input!(path, "{at}: {key} is missing"),
            },
        }
    };
    let source = number("buffer", None)?;
    let offset = number("byteOffset", Some(0))?;
    let length = number("byteLength", None)?;
    let stride = number("byteStride", None)?;
    let count = number("count", None)?;
    let mode_name = name("mode", None)?;
    let filter_name = name("filter", Some("NONE"))?;
    let shown = crate::error::escaped;
    let Ok(mode) = Mode::parse(&mode_name) else {
        bail_input!(
            path,
            "{at}: unknown mode '{}' (ATTRIBUTES, TRIANGLES or INDICES)",
            shown(&mode_name)
        );
    };
    let Ok(filter) = Filter::parse(&filter_name) else {
        bail_input!(
            path,
            "{at}: unknown filter '{}' (NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)",
            shown(&filter_name)
        );
    };
    let Some(held) = buffers.get(source).map(Vec::len) else {
        bail_input!(
            path,
            "{at}: buffer {source} does not exist (the file has {})",
            buffers.len()
        );
    };
    if offset.checked_add(length).is_none_or(|end| end > held) {
        bail_input!(
            path,
            "{at}: bytes {offset}..+{length} lie past the end of buffer {source} ({held} bytes)"
        );
    }
    Ok(Stream {
        source,
        offset,
        length,
        stride,
        count,
        mode,
        filter,
    })
}
