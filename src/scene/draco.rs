//! `KHR_draco_mesh_compression`: primitives whose geometry is a Draco stream in a buffer view,
//! decoded with the `draco-core` crate (pure Rust, no unsafe code) into the values of the
//! accessors the primitive names, which the loader then reads as it reads any accessor.

use std::collections::HashMap;
use std::path::Path;

use ::gltf::Document;
use ::gltf::accessor::DataType;
use ::gltf::mesh::Semantic;
use draco_core::{DecodeLimits, DecoderBuffer, FaceIndex, Mesh, MeshDecoder};

use crate::bail_input;
use crate::error::Result;

/// The extension's name, as files spell it.
pub(super) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// The decoded values (elements × components, as `f64`) of every accessor a Draco-compressed
/// primitive of `document` names, by accessor index. A stream that cannot be decoded, or that
/// decodes to other counts than the accessors declare, is refused naming the extension, the
/// mesh and the primitive.
pub(super) fn decode_all(
    path: &Path,
    document: &Document,
    buffers: &[Vec<u8>],
) -> Result<HashMap<usize, Vec<f64>>> {
    let mut decoded = HashMap::new();
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            let Some(ext) = primitive.extension_value(EXTENSION) else {
                continue;
            };
            let at = format!(
                "{EXTENSION}: mesh {} primitive {}",
                mesh.index(),
                primitive.index()
            );
            let stream = stream_of(path, &at, document, buffers, ext)?;
            let largest = primitive
                .attributes()
                .map(|(_, a)| a.count())
                .chain(primitive.indices().map(|a| a.count()))
                .max()
                .unwrap_or(0) as u64;
            let draco = decode(path, &at, stream, largest)?;
            if let Some(indices) = primitive.indices() {
                let faces = draco.num_faces();
                if faces * 3 != indices.count() {
                    bail_input!(
                        path,
                        "{at}: the stream has {faces} triangles, but accessor {} (indices) has {} indices",
                        indices.index(),
                        indices.count()
                    );
                }
                let mut values = Vec::with_capacity(faces * 3);
                for f in 0..faces {
                    let face = draco.face(FaceIndex(f as u32));
                    values.extend(face.iter().map(|p| f64::from(p.0)));
                }
                decoded.insert(indices.index(), values);
            }
            let ids = ext.get("attributes").and_then(|a| a.as_object());
            for (semantic, accessor) in primitive.attributes() {
                let name = semantic_name(&semantic);
                let Some(id) = ids.and_then(|a| a.get(&name)).and_then(|v| v.as_u64()) else {
                    // Not in the stream: the accessor's own data, read as usual.
                    continue;
                };
                let Some(attribute) = u32::try_from(id)
                    .ok()
                    .and_then(|id| draco.attribute_by_unique_id(id))
                else {
                    bail_input!(path, "{at}: {name}: the stream has no attribute {id}");
                };
                if draco.num_points() != accessor.count() {
                    bail_input!(
                        path,
                        "{at}: {name}: the stream has {} points, but accessor {} has {}",
                        draco.num_points(),
                        accessor.index(),
                        accessor.count()
                    );
                }
                let dims = accessor.dimensions().multiplicity();
                let scale = normalization(accessor.data_type(), accessor.normalized());
                let values = attribute
                    .read_f32s(draco.num_points(), dims)
                    .into_iter()
                    .map(|v| scale(f64::from(v)))
                    .collect();
                decoded.insert(accessor.index(), values);
            }
        }
    }
    Ok(decoded)
}

/// One Draco stream decoded as a primitive's is (at most `largest` points and faces, as its
/// accessors would declare), then its faces and every attribute's values read out as
/// [`decode_all`] reads them: the entry of the `draco` fuzz target, which reaches the decoder
/// with bytes that a glTF wrapper (base64 in JSON, a byte length to match) would rarely carry
/// intact. Returns the number of values read.
pub fn decode_stream(path: &Path, stream: &[u8], largest: u64) -> Result<usize> {
    let mesh = decode(path, EXTENSION, stream, largest)?;
    let mut values = 0;
    for f in 0..mesh.num_faces() {
        values += mesh.face(FaceIndex(f as u32)).len();
    }
    for id in 0..mesh.num_attributes() {
        let attribute = mesh.attribute(id);
        let dims = usize::from(attribute.num_components());
        values += attribute.read_f32s(mesh.num_points(), dims).len();
    }
    Ok(values)
}

/// The bytes of the extension's buffer view.
fn stream_of<'b>(
    path: &Path,
    at: &str,
    document: &Document,
    buffers: &'b [Vec<u8>],
    ext: &::gltf::json::Value,
) -> Result<&'b [u8]> {
    let view = ext
        .get("bufferView")
        .and_then(|v| v.as_u64())
        .and_then(|v| document.views().nth(usize::try_from(v).ok()?));
    let Some(view) = view else {
        bail_input!(path, "{at}: bufferView is missing or out of range");
    };
    let bytes = view
        .offset()
        .checked_add(view.length())
        .and_then(|end| buffers.get(view.buffer().index())?.get(view.offset()..end));
    match bytes {
        Some(b) => Ok(b),
        None => bail_input!(
            path,
            "{at}: buffer view {} lies outside its buffer",
            view.index()
        ),
    }
}

/// Decodes one stream, at most `largest` points and faces (what its accessors declare, and
/// so what the memory budget counted).
fn decode(path: &Path, at: &str, stream: &[u8], largest: u64) -> Result<Mesh> {
    // A face count is a third of the index count; the decoded values are counted in f32s of
    // at most 16 components (a MAT4) per point.
    let limits = DecodeLimits::default()
        .with_max_points(largest)
        .with_max_faces(largest)
        .with_max_decoded_bytes(largest.saturating_mul(64).max(1 << 16));
    let mut buffer = DecoderBuffer::new(stream).with_limits(limits);
    let mut mesh = Mesh::new();
    if let Err(e) = MeshDecoder::new().decode(&mut buffer, &mut mesh) {
        bail_input!(path, "{at}: cannot decode the Draco stream: {e}");
    }
    Ok(mesh)
}

/// A semantic as files spell it (`POSITION`, `TEXCOORD_0`).
fn semantic_name(s: &Semantic) -> String {
    match s {
        Semantic::Positions => "POSITION".into(),
        Semantic::Normals => "NORMAL".into(),
        Semantic::Tangents => "TANGENT".into(),
        Semantic::Colors(n) => format!("COLOR_{n}"),
        Semantic::TexCoords(n) => format!("TEXCOORD_{n}"),
        Semantic::Joints(n) => format!("JOINTS_{n}"),
        Semantic::Weights(n) => format!("WEIGHTS_{n}"),
        Semantic::Extras(name) => format!("_{name}"),
    }
}

/// How a decoded value maps to the accessor's: normalised integers to [0, 1] or [−1, 1] as
/// the glTF spec says (the stream holds the integers), others as they are.
fn normalization(ty: DataType, normalized: bool) -> impl Fn(f64) -> f64 {
    let most = match (ty, normalized) {
        (DataType::U8, true) => Some(255.0),
        (DataType::I8, true) => Some(127.0),
        (DataType::U16, true) => Some(65535.0),
        (DataType::I16, true) => Some(32767.0),
        _ => None,
    };
    move |v| most.map_or(v, |m| (v / m).max(-1.0))
}
