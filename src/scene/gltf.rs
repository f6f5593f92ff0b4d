//! glTF 2.0 loading (`.gltf` + external or `data:` resources, `.glb`).
//!
//! The `gltf` crate parses and validates the JSON (references in range, enums known); buffers,
//! images and accessors are read here rather than with `gltf::import` and its readers, because
//! those panic on some malformed files (a byteStride smaller than the element, an accessor type
//! that does not match its semantic, a bad percent-encoding in a URI) and give errors that do
//! not say which mesh or accessor is at fault.

use glam::{DMat4, DVec3, Vec2, Vec3, Vec4};
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::mesh::{Mode, Semantic};
use ::gltf::{Accessor, Document, Node, Primitive};

use super::material::{Material, TextureSlot, UvTransform};
use super::resource::{AllowedFolder, Confinement};
use super::texture::{Encoding, Sampler, Wrap};
use super::{
    AlphaMode, Part, Scene, SceneCamera, SceneLight, SceneLightKind, Texture, extend_optional,
    normal_matrix, tangents,
};
use super::{draco, extensions, meshopt};
use crate::bail_input;
use crate::error::{Result, escaped, escaped_path, input_error};
use crate::limits::{Budget, MAX_FILE_BYTES, NoMemory, SceneSize, read_regular, try_vec};

/// An accessor without a buffer view is all zeros; more elements than this is surely a broken
/// file, and refusing it avoids allocating whatever the count says from a few bytes of JSON.
const MAX_ZERO_ELEMENTS: usize = 1 << 24;
/// Most values (elements × components) read from one accessor: a triangle list at the scene's
/// triangle limit. Values are held as f64 while read, so this bounds that buffer to 1.6 GB.
const MAX_ACCESSOR_VALUES: usize = 3 * crate::limits::MAX_TRIANGLES;

/// Loads a glTF file into a world-space [`Scene`], counted against `budget` before anything
/// large is read or decoded.
pub(super) fn load(path: &Path, budget: &mut Budget, allowed: &AllowedFolder) -> Result<Scene> {
    let bytes = read_regular(path, MAX_FILE_BYTES).map_err(|e| e.into_error(path, "scene file"))?;
    load_bytes(&bytes, path, budget, allowed)
}

/// Loads a glTF file's bytes; `path` names it in errors and anchors relative URIs, which must
/// lead inside its folder or `allowed` ([`Confinement`]).
///
/// Memory: the JSON alone says how many vertices and triangles every mesh instance adds and
/// how long the buffers are, so that much is checked against `budget` before a buffer is read;
/// once the images' headers are read, their texels are counted too, before any is decoded.
pub(super) fn load_bytes(
    bytes: &[u8],
    path: &Path,
    budget: &mut Budget,
    allowed: &AllowedFolder,
) -> Result<Scene> {
    // Another format, named as what it is, before any parser reports a position in it.
    extensions::check_kind(path, bytes)?;
    // The gltf crate reports a short GLB as "could not completely read the object"; say more.
    if let (Some(b"glTF"), Some(declared)) = (bytes.get(..4), bytes.get(8..12)) {
        let declared = u32::from_le_bytes([declared[0], declared[1], declared[2], declared[3]]);
        // The gltf crate subtracts the 12-byte header from the declared length unchecked
        // (found by fuzzing: tests/data/fuzz/gltf/glb-length-below-header).
        if declared < 12 {
            bail_input!(
                path,
                "broken GLB header: declared length {declared} is less than the 12-byte header"
            );
        }
        if declared as usize > bytes.len() {
            bail_input!(
                path,
                "truncated GLB: the header says {declared} bytes, the file has {}",
                bytes.len()
            );
        }
    }
    let readable = extensions::check_json(path, bytes)?;
    let ::gltf::Gltf { document, blob } = ::gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| input_error(path, format!("not a valid glTF/GLB file: {e}")))?;
    let mut root = document.into_json();
    // Required extensions the loader reads, which the crate's validation does not know.
    root.extensions_required.retain(|e| !readable.contains(e));
    check_position_references(path, &root)?;
    let document = extensions::validated(root)
        .map_err(|e| input_error(path, format!("not a valid glTF/GLB file: {e}")))?;
    let confinement = Confinement::of_model(path, allowed)?;
    let (mut size, used, origin) = count(path, &document)?;
    // The file (and the GLB chunk's copy of it) and the buffers it declares are held while
    // loading.
    let blob_len = blob.as_ref().map_or(0, Vec::len) as u64;
    // Meshopt's fallback buffers are made here and filled by decoding: held as a file's.
    let declared: u64 = document
        .buffers()
        .filter(|b| matches!(b.source(), ::gltf::buffer::Source::Uri(_)) || meshopt::is_fallback(b))
        .map(|b| b.length() as u64)
        .sum();
    let held = bytes.len() as u64 + blob_len;
    size.file_bytes = held + declared;
    rig_budget(&document, &mut size, budget);
    budget.scene(path, size, held)?;
    let mut buffers = load_buffers(path, &confinement, &document, blob)?;
    meshopt::decode_all(path, &document, &mut buffers)?;
    let decoded = draco::decode_all(path, &document, &buffers)?;
    let read: u64 = buffers.iter().map(|b| b.len() as u64).sum();
    let images = Images::read(path, &confinement, &document, &buffers, &used)?;
    size.file_bytes = bytes.len() as u64 + read + images.owned_bytes();
    // An image read both as sRGB and as linear data is decoded once for each.
    let decodings = |d: &DistinctImage| d.encodings.iter().filter(|&&e| e).count() as u64;
    size.textures = images.distinct.iter().map(decodings).sum();
    size.texels = images
        .distinct
        .iter()
        .map(|d| d.texels * decodings(d))
        .sum();
    size.alpha_texels = images
        .distinct
        .iter()
        .filter(|d| d.alpha)
        .map(|d| d.texels * decodings(d))
        .sum();
    size.largest_texels = images.distinct.iter().map(|d| d.texels).max().unwrap_or(0);
    budget.scene(path, size, size.file_bytes)?;
    let mut loader = Loader {
        path,
        document: &document,
        buffers,
        scene: Scene {
            origin,
            ..reserved(path, &size)?
        },
        material_map: HashMap::new(),
        images,
        default_material: None,
        rig: super::rig_read::wanted(&document).then(Default::default),
        placing: (0, None),
        unsupported_extensions_seen: Default::default(),
        warned: Default::default(),
        decoded,
    };
    loader.start_rig()?;
    loader.walk()?;
    loader.warn_extensions();
    let scene = loader.finish_rig()?;
    if scene.triangles.is_empty() {
        // One line: what was skipped explains why nothing is left.
        let skipped: Vec<String> = scene
            .warnings
            .iter()
            .map(|w| {
                w.trim_start_matches(&format!("{}: ", escaped_path(path)))
                    .to_string()
            })
            .collect();
        if skipped.is_empty() {
            bail_input!(path, "no triangles in the default scene");
        }
        bail_input!(
            path,
            "no triangles in the default scene ({})",
            skipped.join("; ")
        );
    }
    Ok(scene)
}

/// `image.source()` where it cannot panic: the `gltf` crate unwraps an image's view index, its
/// `mimeType` when it has a view, and its `uri` when it has none, which its validation does
/// not all check (a fuzzed file panicked on the `mimeType`).
fn image_source<'a>(
    document: &'a Document,
    image: &::gltf::Image<'a>,
) -> std::result::Result<::gltf::image::Source<'a>, String> {
    let json = &document.as_json().images[image.index()];
    match (&json.buffer_view, &json.mime_type, &json.uri) {
        (Some(v), _, _) if v.value() >= document.views().len() => {
            Err(format!("bufferView {} does not exist", v.value()))
        }
        (Some(_), None, _) => Err("has a bufferView but no mimeType".into()),
        (None, _, None) => Err("has neither a uri nor a bufferView".into()),
        _ => Ok(image.source()),
    }
}

/// The files a glTF file's buffers and images name (`data:` URIs aside), resolved and checked
/// as loading reads them ([`Confinement::resolve`]), each once, in the file's order. A GLB
/// whose header is broken names none: loading it says what is wrong.
pub(super) fn external_files(path: &Path, allowed: &AllowedFolder) -> Result<Vec<PathBuf>> {
    let bytes = read_regular(path, MAX_FILE_BYTES).map_err(|e| e.into_error(path, "scene file"))?;
    if let (Some(b"glTF"), Some(d)) = (bytes.get(..4), bytes.get(8..12)) {
        let declared = u32::from_le_bytes([d[0], d[1], d[2], d[3]]) as usize;
        if declared < 12 || declared > bytes.len() {
            return Ok(Vec::new());
        }
    }
    let ::gltf::Gltf { document, .. } = ::gltf::Gltf::from_slice_without_validation(&bytes)
        .map_err(|e| input_error(path, format!("not a valid glTF/GLB file: {e}")))?;
    let confinement = Confinement::of_model(path, allowed)?;
    let buffers = document.buffers().filter_map(|b| match b.source() {
        ::gltf::buffer::Source::Uri(uri) => Some((format!("buffer {}", b.index()), uri)),
        ::gltf::buffer::Source::Bin => None,
    });
    let mut images = Vec::new();
    for i in document.images() {
        let what = format!("image {}", i.index());
        match image_source(&document, &i).map_err(|e| input_error(path, format!("{what}: {e}")))? {
            ::gltf::image::Source::Uri { uri, .. } => images.push((what, uri)),
            ::gltf::image::Source::View { .. } => {}
        }
    }
    let mut files: Vec<PathBuf> = Vec::new();
    for (what, uri) in buffers.chain(images) {
        if uri.starts_with("data:") {
            continue;
        }
        let file = confinement
            .resolve(uri)
            .map_err(|why| input_error(path, format!("{what}: {why}")))?;
        if !files.contains(&file) {
            files.push(file);
        }
    }
    Ok(files)
}

/// gltf-json's validation indexes the accessor list with each POSITION reference before checking
/// it is in range (a panic), so those references are checked first.
fn check_position_references(path: &Path, root: &::gltf::json::Root) -> Result<()> {
    use ::gltf::json::validation::Checked;
    let n = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(::gltf::json::mesh::Semantic::Positions));
            if let Some(a) = position
                && a.value() >= n
            {
                bail_input!(
                    path,
                    "mesh {m} primitive {p}: POSITION refers to accessor {}, but the file has {n} accessors",
                    a.value()
                );
            }
        }
    }
    Ok(())
}

/// Reads every buffer: the GLB binary chunk, a `data:` URI, or a file beside the glTF (its
/// first `byteLength` bytes: the rest is never used).
fn load_buffers(
    path: &Path,
    confinement: &Confinement,
    document: &Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            // Filled by meshopt::decode_all; a fallback given a URI is read (and filled too).
            ::gltf::buffer::Source::Bin if meshopt::is_fallback(&buffer) => {
                vec![0; buffer.length()]
            }
            ::gltf::buffer::Source::Bin => match blob.take() {
                Some(data) => data,
                None => bail_input!(
                    path,
                    "buffer {i} refers to the GLB binary chunk, but the file has none"
                ),
            },
            ::gltf::buffer::Source::Uri(uri) => read_uri(
                path,
                confinement,
                uri,
                &format!("buffer {i}"),
                buffer.length() as u64,
            )?,
        };
        if data.len() < buffer.length() {
            bail_input!(
                path,
                "buffer {i}: declares {} bytes but holds only {}",
                buffer.length(),
                data.len()
            );
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// The bytes a URI names: `data:…;base64,…`, or a file inside the folders `confinement` opens
/// ([`Confinement::resolve`]), of which at most `limit` bytes are read. Only regular files are
/// read: a device (`/dev/zero`) would read until memory ran out, a FIFO block. Errors name the
/// glTF file `path` and `what` the URI is for (`buffer 0`, `material 1: image 2`).
fn read_uri(
    path: &Path,
    confinement: &Confinement,
    uri: &str,
    what: &str,
    limit: u64,
) -> Result<Vec<u8>> {
    let err = |msg: String| input_error(path, format!("{what}: {msg}"));
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_, payload)) = rest.split_once(";base64,") else {
            return Err(err("data: URI is not base64".to_string()));
        };
        return base64_decode(payload).ok_or_else(|| err("data: URI has invalid base64".into()));
    }
    let file = confinement.resolve(uri).map_err(err)?;
    let shown = escaped(uri);
    read_regular(&file, limit).map_err(|e| match e {
        crate::limits::ReadError::NoMemory(e) => anyhow::Error::new(e)
            .context(format!("{}: {what}: reading '{shown}'", escaped_path(path))),
        crate::limits::ReadError::Io(e) => err(format!("cannot read external file '{shown}': {e}")),
        e => err(format!("external file '{shown}' is {e}")),
    })
}

/// Standard base64 (padding optional, whitespace ignored); `None` on any other character.
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' | b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// Visits the default scene's nodes depth first (pre-order), composing transforms
/// parent × child in f64, and calls `visit` with each node and its world transform. A node reached
/// twice (a cycle, or two parents) and a transform that is not finite are refused.
fn walk(
    path: &Path,
    document: &Document,
    mut visit: impl FnMut(&Node, DMat4) -> Result<()>,
) -> Result<()> {
    let roots: Vec<Node> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            // No scenes: every node that is nobody's child is a root.
            let mut is_child = vec![false; document.nodes().len()];
            for node in document.nodes() {
                for child in node.children() {
                    is_child[child.index()] = true;
                }
            }
            document.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut visited = vec![false; document.nodes().len()];
    // Reversed so that popping visits nodes in file order.
    let mut stack: Vec<(Node, DMat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        let n = node.index();
        if visited[n] {
            bail_input!(
                path,
                "node {n} is reached twice in the node hierarchy (a cycle, or a node with two parents)"
            );
        }
        visited[n] = true;
        // In f64: a node far from the origin keeps its mesh's precision until the render
        // origin is taken off (super::origin).
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        if !local.is_finite() {
            bail_input!(path, "node {n}: transform is not finite");
        }
        let world = parent * local;
        visit(&node, world)?;
        let children: Vec<Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
    }
    Ok(())
}

/// Whether a node's or mesh's `extras` mark it a shadow catcher: `"shadow_catcher": true`, or
/// a non-zero number (Blender exports an object's custom properties as its node's extras, and
/// its boolean-looking properties as integers).
fn catcher_flag(extras: &::gltf::json::Extras) -> bool {
    let Some(raw) = extras else {
        return false;
    };
    let Ok(serde_json::Value::Object(map)) = serde_json::from_str(raw.get()) else {
        return false;
    };
    match map.get("shadow_catcher") {
        Some(serde_json::Value::Bool(b)) => *b,
        Some(serde_json::Value::Number(n)) => n.as_f64().is_some_and(|v| v != 0.0),
        _ => false,
    }
}

/// Whether a mesh placed by `world` is loaded: a singular transform (zero scale) flattens it.
fn placeable(world: DMat4) -> bool {
    let det = world.determinant();
    det != 0.0 && det.is_finite()
}

/// Whether a primitive's mode makes triangles (others are skipped with a warning).
fn is_triangles(mode: Mode) -> bool {
    matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    )
}

/// Most a `KHR_lights_punctual` light's colour times intensity may reach (candela or lux).
/// [ours] a thousand suns' illuminance; the most that keeps sums over lights finite in f32.
const MAX_LIGHT_INTENSITY: f32 = 1e9;

/// The extensions whose meaning the loader implements. A file that uses another gets one
/// warning naming it (and, for a material's, each material that uses it); one that
/// *requires* another is refused by the `gltf` crate's validation.
const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_unlit",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_mesh_quantization",
    draco::EXTENSION,
];

/// One texture a material uses: which slot, the texture, the `TEXCOORD` set its info names,
/// its `KHR_texture_transform` (and that one's `texCoord` override), how its texels are
/// encoded.
struct TextureRef<'a> {
    slot: &'static str,
    texture: ::gltf::Texture<'a>,
    tex_coord: u32,
    transform: Option<UvTransform>,
    transform_tex_coord: Option<u32>,
    encoding: Encoding,
}

impl TextureRef<'_> {
    /// The `TEXCOORD` set read: the transform's override, else the info's.
    fn set(&self) -> u32 {
        self.transform_tex_coord.unwrap_or(self.tex_coord)
    }
}

/// A `KHR_texture_transform` object read from JSON (the normal and occlusion texture infos,
/// whose transform the `gltf` crate does not parse): (transform, texCoord override).
fn transform_of_json(value: Option<&::gltf::json::Value>) -> (Option<UvTransform>, Option<u32>) {
    let Some(v) = value else {
        return (None, None);
    };
    let pair = |key: &str, default: [f32; 2]| {
        v.get(key)
            .and_then(|a| a.as_array())
            .and_then(|a| Some([a.first()?.as_f64()? as f32, a.get(1)?.as_f64()? as f32]))
            .unwrap_or(default)
    };
    let rotation = v.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0) as f32;
    let tex_coord = v
        .get("texCoord")
        .and_then(|t| t.as_u64())
        .map(|t| t.min(u64::from(u32::MAX)) as u32);
    let transform = UvTransform::new(
        pair("offset", [0.0, 0.0]),
        rotation,
        pair("scale", [1.0, 1.0]),
    );
    (Some(transform), tex_coord)
}

/// The textures a material uses, in slot order.
fn texture_refs<'a>(material: &::gltf::Material<'a>) -> Vec<TextureRef<'a>> {
    let mut refs = Vec::new();
    let mut info = |slot, info: Option<::gltf::texture::Info<'a>>, encoding| {
        if let Some(info) = info {
            let t = info.texture_transform();
            refs.push(TextureRef {
                slot,
                texture: info.texture(),
                tex_coord: info.tex_coord(),
                transform: t
                    .as_ref()
                    .map(|t| UvTransform::new(t.offset(), t.rotation(), t.scale())),
                transform_tex_coord: t.as_ref().and_then(|t| t.tex_coord()),
                encoding,
            });
        }
    };
    let pbr = material.pbr_metallic_roughness();
    info("baseColorTexture", pbr.base_color_texture(), Encoding::Srgb);
    info(
        "metallicRoughnessTexture",
        pbr.metallic_roughness_texture(),
        Encoding::Linear,
    );
    info(
        "emissiveTexture",
        material.emissive_texture(),
        Encoding::Srgb,
    );
    if let Some(spec) = material.specular() {
        info("specularTexture", spec.specular_texture(), Encoding::Linear);
        info(
            "specularColorTexture",
            spec.specular_color_texture(),
            Encoding::Srgb,
        );
    }
    if let Some(sg) = material.pbr_specular_glossiness() {
        info("diffuseTexture", sg.diffuse_texture(), Encoding::Srgb);
        info(
            "specularGlossinessTexture",
            sg.specular_glossiness_texture(),
            Encoding::Srgb,
        );
    }
    if let Some(n) = material.normal_texture() {
        let (transform, transform_tex_coord) =
            transform_of_json(n.extension_value("KHR_texture_transform"));
        refs.push(TextureRef {
            slot: "normalTexture",
            texture: n.texture(),
            tex_coord: n.tex_coord(),
            transform,
            transform_tex_coord,
            encoding: Encoding::Linear,
        });
    }
    if let Some(o) = material.occlusion_texture() {
        let (transform, transform_tex_coord) =
            transform_of_json(o.extension_value("KHR_texture_transform"));
        refs.push(TextureRef {
            slot: "occlusionTexture",
            texture: o.texture(),
            tex_coord: o.tex_coord(),
            transform,
            transform_tex_coord,
            encoding: Encoding::Linear,
        });
    }
    refs
}

/// Converts a `KHR_materials_unlit` or `KHR_materials_pbrSpecularGlossiness` material (its
/// factors and texture slots already read into `m`) to what the renderer shades; returns what
/// the conversion approximates, for a warning.
///
/// Unlit: the base colour (factor, texture) is emitted and nothing is reflected, so lights and
/// shadows leave it as the file's viewer shows it. Spec-gloss: glTF-Transform's conversion —
/// diffuse as base colour, metallic 0, roughness 1 − glossiness (its factor times the
/// specularGlossinessTexture's A), the specular colour as `KHR_materials_specular`'s F0
/// colour at an infinite ior (F0 = the colour itself).
fn converted(material: &::gltf::Material, m: &mut Material) -> Option<String> {
    if material.unlit() {
        m.emissive = m.base_color;
        m.emissive_texture = m.base_color_texture;
        m.base_color = Vec3::ZERO;
        m.metallic = 0.0;
        m.specular = 0.0;
        m.specular_texture = None;
        m.specular_color_texture = None;
        m.metallic_roughness_texture = None;
        m.occlusion_texture = None;
        m.normal_texture = None;
        return None;
    }
    let sg = material.pbr_specular_glossiness()?;
    let [r, g, b, alpha] = sg.diffuse_factor();
    m.base_color = Vec3::new(r, g, b);
    m.base_alpha = alpha;
    m.metallic = 0.0;
    m.roughness = 1.0 - sg.glossiness_factor();
    m.metallic_roughness_texture = None;
    // The specularGlossinessTexture, read as the specular colour texture (RGB, sRGB), has
    // the glossiness in its A.
    m.glossiness_from_specular_texture = sg.specular_glossiness_texture().is_some();
    m.specular = 1.0;
    m.specular_color = Vec3::from_array(sg.specular_factor());
    m.ior = 1e6;
    Some(
        "KHR_materials_pbrSpecularGlossiness converted to metallic-roughness (diffuse as base \
         colour, roughness 1 − glossiness, the specular colour as F0)"
            .to_string(),
    )
}

/// The `TEXCOORD` sets a primitive's material reads (0 and 1; others read 0, with a warning).
fn tex_coord_sets(primitive: &Primitive) -> [bool; 2] {
    let mut sets = [true, false];
    for r in texture_refs(&primitive.material()) {
        if r.set() == 1 {
            sets[1] = true;
        }
    }
    sets
}

/// Whether a primitive's material has a normal map (its tangents are then read or made).
fn normal_mapped(primitive: &Primitive) -> bool {
    primitive.material().normal_texture().is_some()
}

/// The renderer's sampler for a glTF texture's.
fn sampler_of(texture: &::gltf::Texture) -> Sampler {
    use ::gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let s = texture.sampler();
    let wrap = |w| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
    };
    Sampler {
        wrap_s: wrap(s.wrap_s()),
        wrap_t: wrap(s.wrap_t()),
        mag_nearest: s.mag_filter() == Some(MagFilter::Nearest),
        // No filter given: the implementation's choice, which is the pyramid.
        mipmaps: !matches!(s.min_filter(), Some(MinFilter::Nearest | MinFilter::Linear)),
    }
}

/// [`count`]'s answer, in the order its comment gives, and the render origin
/// ([`super::render_origin`]) of the placed positions' bounds.
type Counted = (SceneSize, Vec<(usize, usize, Encoding)>, DVec3);

/// What the default scene will hold, from the JSON alone: the vertices and (at most) triangles
/// of every primitive the loader will read, once per node that places its mesh, and the
/// largest of them; and the images their materials use, as (material, image, encoding) in the
/// order the loader meets them. Accessors too large to read are refused here, as the loader
/// would.
fn count(path: &Path, document: &Document) -> Result<Counted> {
    let mut size = SceneSize::default();
    let mut used = Vec::new();
    let mut bounds = Some((DVec3::INFINITY, DVec3::NEG_INFINITY));
    // Whether any primitive has a second texture coordinate set, tangents, colours: then every
    // vertex of the scene gets them.
    let (mut uv1, mut tangents, mut colors) = (false, false, false);
    walk(path, document, |node, world| {
        size.lights += u64::from(node.light().is_some());
        let Some(mesh) = node.mesh() else {
            return Ok(());
        };
        if !placeable(world) {
            return Ok(());
        }
        size.instances += 1;
        for primitive in mesh.primitives() {
            if !is_triangles(primitive.mode()) {
                continue;
            }
            let at = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            // Without positions the loader refuses the primitive: nothing to count.
            let Some(positions) = primitive.get(&Semantic::Positions) else {
                continue;
            };
            let sets = tex_coord_sets(&primitive);
            let mapped = normal_mapped(&primitive);
            let attributes = [
                Some(positions.clone()),
                primitive.get(&Semantic::Normals),
                primitive.get(&Semantic::TexCoords(0)),
                primitive.get(&Semantic::TexCoords(1)).filter(|_| sets[1]),
                primitive.get(&Semantic::Tangents).filter(|_| mapped),
                primitive.get(&Semantic::Colors(0)),
                primitive.indices(),
            ];
            uv1 |= sets[1];
            tangents |= mapped;
            colors |= primitive.get(&Semantic::Colors(0)).is_some();
            for acc in attributes.iter().flatten() {
                check_values(path, &at, acc)?;
            }
            bounds = bounds.and_then(|b| grow(b, &positions, world));
            let vertices = positions.count() as u64;
            let indices = primitive.indices().map_or(vertices, |a| a.count() as u64);
            let triangles = match primitive.mode() {
                Mode::Triangles => indices / 3,
                _ => indices.saturating_sub(2),
            };
            size.vertices += vertices;
            size.triangles += triangles;
            size.largest_vertices = size.largest_vertices.max(vertices);
            size.largest_indices = size.largest_indices.max(indices);
            let material = primitive.material();
            if let Some(m) = material.index() {
                for r in texture_refs(&material) {
                    used.push((m, r.texture.source().index(), r.encoding));
                }
            }
        }
        Ok(())
    })?;
    // Tangents may split vertices (MikkTSpace at mirrored UV seams): counted as one more
    // vertex in four where any primitive is normal-mapped. [ours] a bound seen to hold on the
    // corpus, not a proof.
    if tangents {
        size.vertices += size.vertices / 4;
    }
    let per_vertex = 8 * u64::from(uv1) + 16 * u64::from(tangents) + 16 * u64::from(colors);
    size.extra_vertex_bytes = size.vertices * per_vertex;
    if let Some((lo, hi)) = bounds {
        check_not_too_far(path, lo, hi)?;
    }
    let origin = bounds.map_or(DVec3::ZERO, |(lo, hi)| super::render_origin(lo, hi));
    Ok((size, used, origin))
}

/// Refuses a model so far from the origin, for its size, that its coordinates cannot hold its
/// shape: at x = 1e20 doubles are 16,384 apart (the file's floats 8.8e12), so a model of a few
/// units would render as a sliver. [ours] 2^-30 of the distance: a model spanning less keeps
/// fewer than a float's bits across it once placed.
fn check_not_too_far(path: &Path, lo: DVec3, hi: DVec3) -> Result<()> {
    if !(lo.is_finite() && hi.is_finite() && lo.cmple(hi).all()) {
        return Ok(());
    }
    let far = lo.abs().max(hi.abs()).max_element();
    let span = (hi - lo).max_element();
    if far > 0.0 && span <= far * libm::ldexp(1.0, -30) {
        bail_input!(
            path,
            "the model lies {:e} units from the origin but spans only {:e}: at that \
             distance coordinates are too coarse to hold its shape (32-bit floats are \
             {:e} apart there); move it nearer the origin (its nodes' translation or its \
             positions)",
            far as f32,
            span as f32,
            libm::ldexpf(1.0, libm::ilogbf(far as f32) - 23)
        );
    }
    Ok(())
}

/// Refuses a vertex outside its POSITION accessor's declared `min`/`max` (by more than a
/// thousandth of their span: exporters round them): the specification requires them exact,
/// and the render origin, the memory estimate and the far-scene check are computed from them
/// before any vertex is read. A damaged file whose vertices lie 10³⁷ away from their declared
/// box made the camera not finite, and the BVH builder's own checks fail (found by fuzzing).
/// Normalised accessors declare their bounds in stored integers, and are left alone.
fn check_declared_bounds(
    path: &Path,
    at: &str,
    positions: &[[f32; 3]],
    acc: &Accessor,
) -> Result<()> {
    let bound = |v: Option<::gltf::json::Value>| -> Option<[f64; 3]> {
        let a = v?;
        let a = a.as_array()?;
        (a.len() == 3).then_some(())?;
        Some([a[0].as_f64()?, a[1].as_f64()?, a[2].as_f64()?])
    };
    let (Some(lo), Some(hi)) = (bound(acc.min()), bound(acc.max())) else {
        return Ok(());
    };
    if acc.normalized() {
        return Ok(());
    }
    let span = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let size = (0..3)
        .map(|k| lo[k].abs().max(hi[k].abs()))
        .fold(0.0, f64::max);
    let slack = 1e-3 * span + 1e-6 * size;
    for (i, p) in positions.iter().enumerate() {
        let outside = (0..3).any(|k| {
            let x = f64::from(p[k]);
            !(x >= lo[k] - slack && x <= hi[k] + slack)
        });
        if outside {
            bail_input!(
                path,
                "{at}: accessor {} (POSITION): vertex {i} at {:?} lies outside the accessor's \
                 declared bounds (min {lo:?}, max {hi:?}), which glTF requires exact: the file \
                 is damaged, or its exporter wrote wrong bounds",
                acc.index(),
                p
            );
        }
    }
    Ok(())
}

/// `bounds` grown by the corners of a POSITION accessor's declared `min`/`max` placed by
/// `world`; None when it declares none (the glTF spec requires them; without them the scene
/// keeps its world coordinates, losing only precision far from the origin).
fn grow(bounds: (DVec3, DVec3), positions: &Accessor, world: DMat4) -> Option<(DVec3, DVec3)> {
    let corner = |v: Option<::gltf::json::Value>| -> Option<DVec3> {
        let v = v?;
        let a = v.as_array()?;
        let c = |k: usize| a.get(k).and_then(|x| x.as_f64());
        Some(DVec3::new(c(0)?, c(1)?, c(2)?))
    };
    let (lo, hi) = (corner(positions.min())?, corner(positions.max())?);
    let (mut blo, mut bhi) = bounds;
    for k in 0..8 {
        let p = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let w = world.transform_point3(p);
        blo = blo.min(w);
        bhi = bhi.max(w);
    }
    Some((blo, bhi))
}

/// Refuses an accessor with more values (elements × components) than one read may hold.
fn check_values(path: &Path, at: &str, acc: &Accessor) -> Result<()> {
    let (count, dims) = (acc.count(), acc.dimensions().multiplicity());
    if count.saturating_mul(dims) > MAX_ACCESSOR_VALUES {
        bail_input!(
            path,
            "{at}: accessor {}: count {count} of {dims} components is more than the {MAX_ACCESSOR_VALUES} values allowed",
            acc.index()
        );
    }
    Ok(())
}

/// An empty scene with room for `size`'s vertices and triangles, asked of the system at once:
/// a refusal is an error now, and the arrays never grow by doubling (a copy of each, briefly
/// twice its size).
fn reserved(path: &Path, size: &SceneSize) -> Result<Scene> {
    let refused = |e: NoMemory| anyhow::Error::new(e).context(path.display().to_string());
    let (v, t) = (size.vertices as usize, size.triangles as usize);
    Ok(Scene {
        source: path.display().to_string(),
        positions: try_vec(v, "the scene's positions").map_err(refused)?,
        normals: try_vec(v, "the scene's normals").map_err(refused)?,
        uvs: try_vec(v, "the scene's texture coordinates").map_err(refused)?,
        triangles: try_vec(t, "the scene's triangles").map_err(refused)?,
        tri_material: try_vec(t, "the scene's triangle materials").map_err(refused)?,
        ..Scene::default()
    })
}

/// Where an image's encoded bytes are.
enum Encoded {
    /// Read from a file or a `data:` URI.
    Owned(Vec<u8>),
    /// A range of a buffer.
    View { buffer: usize, range: Range<usize> },
    /// Decoded: the bytes are no longer needed.
    Gone,
}

/// One distinct image: its bytes until decoded, its texels, its scene textures once decoded
/// (one per encoding a material reads it with: sRGB, linear).
struct DistinctImage {
    encoded: Encoded,
    texels: u64,
    /// The image has an alpha channel: each decoding keeps it.
    alpha: bool,
    texture: [Option<usize>; 2],
    /// Which encodings the materials read it with.
    encodings: [bool; 2],
}

/// Index of an encoding in [`DistinctImage::texture`].
fn encoding_index(e: Encoding) -> usize {
    match e {
        Encoding::Srgb => 0,
        Encoding::Linear => 1,
    }
}

/// The images the materials use, read and identified before any is decoded. Images with the
/// same bytes (one file under several image indices, or copies of it) are one image, decoded
/// once and shared by every material that uses any of them.
struct Images {
    /// glTF image index → index into `distinct`.
    of_index: HashMap<usize, usize>,
    distinct: Vec<DistinctImage>,
}

impl Images {
    /// Reads the `used` images and their sizes from their headers; errors name the first
    /// material that uses an image.
    fn read(
        path: &Path,
        confinement: &Confinement,
        document: &Document,
        buffers: &[Vec<u8>],
        used: &[(usize, usize, Encoding)],
    ) -> Result<Images> {
        let mut images = Images {
            of_index: HashMap::new(),
            distinct: Vec::new(),
        };
        let mut by_digest: HashMap<[u8; 32], usize> = HashMap::new();
        for &(material, index, encoding) in used {
            if let Some(&d) = images.of_index.get(&index) {
                images.distinct[d].encodings[encoding_index(encoding)] = true;
                continue;
            }
            let at = format!("material {material}: image {index}");
            let Some(image) = document.images().nth(index) else {
                bail_input!(path, "{at}: no such image");
            };
            let source = image_source(document, &image)
                .map_err(|e| input_error(path, format!("{at}: {e}")))?;
            let encoded = match source {
                ::gltf::image::Source::Uri { uri, .. } => {
                    Encoded::Owned(read_uri(path, confinement, uri, &at, MAX_FILE_BYTES)?)
                }
                ::gltf::image::Source::View { view, .. } => {
                    let range = view.offset()..view.offset().saturating_add(view.length());
                    let buffer = view.buffer().index();
                    if buffers
                        .get(buffer)
                        .and_then(|b| b.get(range.clone()))
                        .is_none()
                    {
                        bail_input!(
                            path,
                            "{at}: buffer view {} lies outside its buffer",
                            view.index()
                        );
                    }
                    Encoded::View { buffer, range }
                }
            };
            let bytes = bytes_of(&encoded, buffers);
            let digest: [u8; 32] = Sha256::digest(bytes).into();
            if let Some(&d) = by_digest.get(&digest) {
                images.of_index.insert(index, d);
                images.distinct[d].encodings[encoding_index(encoding)] = true;
                continue;
            }
            let (w, h, alpha) = Texture::header(bytes)
                .map_err(|e| input_error(path, format!("{at}: cannot decode: {e}")))?;
            by_digest.insert(digest, images.distinct.len());
            images.of_index.insert(index, images.distinct.len());
            let mut encodings = [false; 2];
            encodings[encoding_index(encoding)] = true;
            images.distinct.push(DistinctImage {
                encoded,
                texels: u64::from(w) * u64::from(h),
                alpha,
                texture: [None; 2],
                encodings,
            });
        }
        Ok(images)
    }

    /// Bytes of encoded images held beside the buffers.
    fn owned_bytes(&self) -> u64 {
        self.distinct
            .iter()
            .map(|d| match &d.encoded {
                Encoded::Owned(b) => b.len() as u64,
                _ => 0,
            })
            .sum()
    }
}

/// The bytes of an image not yet decoded (empty once it is).
fn bytes_of<'a>(encoded: &'a Encoded, buffers: &'a [Vec<u8>]) -> &'a [u8] {
    match encoded {
        Encoded::Owned(bytes) => bytes,
        Encoded::View { buffer, range } => &buffers[*buffer][range.clone()],
        Encoded::Gone => &[],
    }
}

/// A primitive's attributes that its material reads, as the file gives them.
struct MaterialAttributes {
    /// `TEXCOORD_0`, if the primitive has it.
    uvs: Option<Vec<[f32; 2]>>,
    /// `TEXCOORD_1` when the material reads it (zeros where the primitive lacks it).
    uvs1: Option<Vec<[f32; 2]>>,
    /// `COLOR_0` as linear RGBA.
    colors: Option<Vec<Vec4>>,
    /// The file's tangents, read only for a normal-mapped material.
    tangents: Option<Vec<[f32; 4]>>,
}

/// A primitive's vertices placed in the scene (world space, counted from the render origin):
/// every attribute, one entry per vertex.
struct Vertices {
    /// The vertex each copy the tangent generator made was copied from, in order.
    copied: Vec<u32>,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    uvs1: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec4>>,
    tangents: Option<Vec<Vec4>>,
}

impl Vertices {
    /// Appends a copy of vertex `v` (a vertex the tangent generator split), every attribute
    /// but the tangents, which the generator returns for the copies too.
    fn copy_vertex(&mut self, v: usize) {
        self.copied.push(v as u32);
        self.positions.push(self.positions[v]);
        self.normals.push(self.normals[v]);
        self.uvs.push(self.uvs[v]);
        if let Some(u1) = &mut self.uvs1 {
            u1.push(u1[v]);
        }
        if let Some(c) = &mut self.colors {
            c.push(c[v]);
        }
    }
}

/// The file's normals moved to world space by `world`'s normal matrix; where one is zero or
/// not finite, or the file has none, the `smooth` normal computed from the triangles.
fn place_normals(normals: Option<&[[f32; 3]]>, smooth: Vec<Vec3>, world: DMat4) -> Vec<Vec3> {
    let nm = normal_matrix(world.as_mat4());
    match normals {
        Some(normals) => normals
            .iter()
            .zip(&smooth)
            .map(|(&n, &fallback)| {
                let n = (nm * Vec3::from_array(n)).normalize_or_zero();
                // Zero or non-finite file normals: use the computed one instead.
                if n != Vec3::ZERO && n.is_finite() {
                    n
                } else {
                    fallback
                }
            })
            .collect(),
        None => smooth,
    }
}

/// The file's tangents moved to world space like any surface direction, their handedness
/// flipped by a mirroring `world`; zero where the transformed direction is.
fn world_tangents(t: &[[f32; 4]], world: DMat4) -> Vec<Vec4> {
    let handedness = if world.determinant() < 0.0 { -1.0 } else { 1.0 };
    let world_f32 = world.as_mat4();
    t.iter()
        .map(|t| {
            let v = world_f32
                .transform_vector3(Vec3::new(t[0], t[1], t[2]))
                .normalize_or_zero();
            let w = if t[3] < 0.0 { -1.0 } else { 1.0 };
            if v.is_finite() && v != Vec3::ZERO {
                v.extend(w * handedness)
            } else {
                Vec4::ZERO
            }
        })
        .collect()
}

/// State while walking the node hierarchy.
struct Loader<'a> {
    path: &'a Path,
    document: &'a Document,
    buffers: Vec<Vec<u8>>,
    scene: Scene,
    /// glTF material index → scene material index.
    material_map: HashMap<usize, u32>,
    /// The images the materials use, each decoded once.
    images: Images,
    /// Scene index of the default grey material, once some primitive needed it.
    default_material: Option<u32>,
    /// What posing will need, when the file animates, skins or morphs anything.
    rig: Option<super::rig::RigData>,
    /// The node whose meshes are being read, and its skin.
    placing: (usize, Option<usize>),
    /// Material extensions some material's warning already named.
    unsupported_extensions_seen: std::collections::HashSet<String>,
    /// Materials already warned about for a primitive attribute they lack or the renderer
    /// ignores (one warning per material and kind).
    warned: std::collections::HashSet<(u32, &'static str)>,
    /// Accessors whose values a Draco stream holds ([`draco::decode_all`]), decoded.
    decoded: HashMap<usize, Vec<f64>>,
}

impl Loader<'_> {
    fn warn(&mut self, message: String) {
        // Escaped: names from the file reach the terminal, the report and the settings record.
        let message = escaped(&format!("{}: {message}", self.path.display())).into_owned();
        self.scene.warnings.push(message);
    }

    /// Reads the nodes of the default scene ([`walk`]): cameras, and the meshes of nodes whose
    /// transform is not singular.
    fn walk(&mut self) -> Result<()> {
        let (path, document) = (self.path, self.document);
        walk(path, document, |node, world| {
            let n = node.index();
            if let Some(rig) = &mut self.rig {
                rig.order.push(n);
                self.placing = (n, node.skin().map(|s| s.index()));
            }
            if let Some(camera) = node.camera() {
                self.camera(n, &camera, world);
            }
            if let Some(light) = node.light() {
                self.light(n, &light, world)?;
            }
            if let Some(mesh) = node.mesh() {
                if !placeable(world) {
                    self.warn(format!(
                        "node {n}: world transform is singular (zero scale), mesh {} skipped",
                        mesh.index()
                    ));
                } else {
                    let first = self.scene.triangles.len();
                    for primitive in mesh.primitives() {
                        self.primitive(mesh.index(), &primitive, world)?;
                    }
                    let triangles = first..self.scene.triangles.len();
                    if catcher_flag(node.extras()) || catcher_flag(mesh.extras()) {
                        self.scene.set_catcher(triangles.clone());
                    }
                    self.scene.parts.push(Part {
                        node: node.name().map(str::to_string),
                        mesh: mesh.name().map(str::to_string),
                        triangles,
                    });
                }
            }
            Ok(())
        })
    }

    /// Keeps the first perspective camera: eye at the node's origin looking down its −Z, +Y up.
    fn camera(&mut self, node: usize, camera: &::gltf::Camera, world: DMat4) {
        if self.scene.camera.is_some() {
            return;
        }
        let ::gltf::camera::Projection::Perspective(p) = camera.projection() else {
            self.warn(format!(
                "node {node}: camera {} is orthographic, which envshadow does not render \
                 (perspective cameras only), ignored",
                camera.index()
            ));
            return;
        };
        let position = (world.transform_point3(DVec3::ZERO) - self.scene.origin).as_vec3();
        let world = world.as_mat4();
        let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y);
        // Orthogonalise: a sheared node would otherwise give an up tilted toward forward.
        let up = (up - forward * up.dot(forward)).normalize_or_zero();
        let vfov_deg = p.yfov().to_degrees();
        let why = if !(vfov_deg > 0.0 && vfov_deg < 180.0) {
            Some(format!("its yfov {} rad is not between 0 and π", p.yfov()))
        } else if forward == Vec3::ZERO || up == Vec3::ZERO || !position.is_finite() {
            Some("its node's transform leaves it no position or direction (zero scale)".into())
        } else {
            None
        };
        if let Some(why) = why {
            self.warn(format!(
                "node {node}: camera {}: {why}, ignored",
                camera.index()
            ));
            return;
        }
        self.scene.camera = Some(SceneCamera {
            position,
            forward,
            up,
            vfov_deg,
        });
    }

    /// Keeps a `KHR_lights_punctual` light placed by node `node`: at the node's origin,
    /// shining along its −Z. Values the extension forbids (negative or non-finite intensity or
    /// colour, a range ≤ 0, cone angles outside 0 ≤ inner < outer ≤ π/2) are refused; a light
    /// whose node flattens its direction (zero scale) is skipped with a warning.
    fn light(
        &mut self,
        node: usize,
        light: &::gltf::khr_lights_punctual::Light,
        world: DMat4,
    ) -> Result<()> {
        use ::gltf::khr_lights_punctual::Kind;
        let index = light.index();
        let name = light
            .name()
            .map_or_else(|| format!("light {index}"), str::to_string);
        let at = format!("node {node}: light {index} ('{name}')");
        let color = Vec3::from_array(light.color());
        if !color.is_finite() || color.min_element() < 0.0 {
            bail_input!(self.path, "{at}: color {color} is not finite and ≥ 0");
        }
        let mut intensity = light.intensity();
        if !(intensity.is_finite() && intensity >= 0.0) {
            bail_input!(
                self.path,
                "{at}: intensity {intensity} is not finite and ≥ 0"
            );
        }
        if intensity * color.max_element() > MAX_LIGHT_INTENSITY {
            let most = MAX_LIGHT_INTENSITY / color.max_element();
            self.warn(format!(
                "{at}: intensity {intensity} × color {color} clamped to intensity {most} \
                 (at most {MAX_LIGHT_INTENSITY} in any channel, so that pixels stay finite)"
            ));
            intensity = most;
        }
        let range = light.range();
        if let Some(r) = range
            && !(r.is_finite() && r > 0.0)
        {
            bail_input!(self.path, "{at}: range {r} is not a finite number > 0");
        }
        let kind = match light.kind() {
            Kind::Directional => SceneLightKind::Directional,
            Kind::Point => SceneLightKind::Point,
            Kind::Spot {
                inner_cone_angle: inner,
                outer_cone_angle: outer,
            } => {
                let right = std::f32::consts::FRAC_PI_2;
                if !(inner >= 0.0 && inner < outer && outer <= right) {
                    bail_input!(
                        self.path,
                        "{at}: spot cone angles inner {inner}, outer {outer}: they must be 0 ≤ inner < outer ≤ π/2"
                    );
                }
                SceneLightKind::Spot { inner, outer }
            }
        };
        // Counted from the render origin, as the positions are.
        let position = (world.transform_point3(DVec3::ZERO) - self.scene.origin).as_vec3();
        let direction = world
            .as_mat4()
            .transform_vector3(Vec3::NEG_Z)
            .normalize_or_zero();
        let needs_direction = kind != SceneLightKind::Point;
        if !position.is_finite() || (needs_direction && direction == Vec3::ZERO) {
            self.warn(format!(
                "{at}: its node's transform leaves it no position or direction (zero scale), ignored"
            ));
            return Ok(());
        }
        self.scene.lights.push(SceneLight {
            name,
            kind,
            position,
            direction,
            color,
            intensity,
            range,
        });
        Ok(())
    }

    /// Appends one primitive, transformed by `world`, to the scene.
    fn primitive(&mut self, m: usize, primitive: &Primitive, world: DMat4) -> Result<()> {
        let p = primitive.index();
        let at = format!("mesh {m} primitive {p}");
        let mode = primitive.mode();
        if !is_triangles(mode) {
            let message =
                format!("mesh {m} primitive {p}: mode {mode:?} is not triangles, skipped");
            self.warn(message);
            return Ok(());
        }
        let Some(pos_acc) = primitive.get(&Semantic::Positions) else {
            bail_input!(self.path, "{at}: no POSITION attribute");
        };
        let positions = self.read_positions(&at, &pos_acc)?;
        let count = positions.len();
        let normals = match primitive.get(&Semantic::Normals) {
            Some(acc) => {
                let normals = self.read_floats::<3>(&at, &acc)?;
                self.check_count(&at, &acc, "NORMAL", normals.len(), &pos_acc, count)?;
                Some(normals)
            }
            None => None,
        };
        let material = self.material(primitive.material())?;
        let file = self.read_material_attributes(&at, primitive, material, &pos_acc, count)?;
        let mut tris = self.read_triangles(&at, primitive, mode, count)?;

        let world_pos = self.place_positions(&at, &positions, world, &pos_acc)?;
        self.keep_front_faces(&at, world, &world_pos, &mut tris);
        let smooth = smooth_normals(&world_pos, &tris);
        let mut vertices = Vertices {
            copied: Vec::new(),
            normals: place_normals(normals.as_deref(), smooth, world),
            positions: world_pos,
            uvs: match file.uvs {
                Some(uvs) => uvs.into_iter().map(Vec2::from_array).collect(),
                None => vec![Vec2::ZERO; count],
            },
            uvs1: file
                .uvs1
                .map(|u| u.into_iter().map(Vec2::from_array).collect()),
            colors: file.colors,
            tangents: None,
        };
        vertices.tangents = self.tangents(
            &at,
            material,
            file.tangents,
            world,
            &mut vertices,
            &mut tris,
        );
        self.keep_for_rig(
            &at,
            primitive,
            &positions,
            normals.as_deref(),
            world,
            &vertices,
            &tris,
        )?;
        self.append(&at, material, vertices, tris)
    }

    /// The primitive's POSITION attribute, checked finite.
    fn read_positions(&self, at: &str, pos_acc: &Accessor) -> Result<Vec<[f32; 3]>> {
        let positions = self.read_floats::<3>(at, pos_acc)?;
        if let Some(i) = positions
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            bail_input!(
                self.path,
                "{at}: accessor {} (POSITION): vertex {i} is not finite ({:?})",
                pos_acc.index(),
                positions[i]
            );
        }
        check_declared_bounds(self.path, at, &positions, pos_acc)?;
        Ok(positions)
    }

    /// The attributes `material` reads (texture coordinates, vertex colours, the file's
    /// tangents for a normal map), checked against the vertex count; what the primitive lacks or
    /// the renderer ignores is warned about once per material.
    fn read_material_attributes(
        &mut self,
        at: &str,
        primitive: &Primitive,
        material: u32,
        pos_acc: &Accessor,
        count: usize,
    ) -> Result<MaterialAttributes> {
        let sets = tex_coord_sets(primitive);
        let textured = self.scene.materials[material as usize]
            .slots()
            .iter()
            .any(|(_, s)| s.is_some());
        let uvs = self.read_uvs(at, primitive, 0, pos_acc, count)?;
        if uvs.is_none() && textured {
            self.warn_material(
                material,
                "no_uv",
                format!("{at}: the material's textures use TEXCOORD_0, which the primitive lacks; sampled at (0, 0)"),
            );
        }
        let uvs1 = if sets[1] {
            let uvs1 = self.read_uvs(at, primitive, 1, pos_acc, count)?;
            if uvs1.is_none() {
                self.warn_material(
                    material,
                    "no_uv1",
                    format!("{at}: the material's textures use TEXCOORD_1, which the primitive lacks; sampled at (0, 0)"),
                );
            }
            Some(uvs1.unwrap_or_else(|| vec![[0.0; 2]; count]))
        } else {
            None
        };
        let colors = match primitive.get(&Semantic::Colors(0)) {
            Some(acc) => Some(self.read_colors(at, &acc, pos_acc, count)?),
            None => None,
        };
        if primitive.get(&Semantic::Colors(1)).is_some() {
            self.warn_material(
                material,
                "color1",
                format!(
                    "{at}: COLOR_1 and later vertex colours are not supported (COLOR_0 is read)"
                ),
            );
        }
        let normal_slot = self.scene.materials[material as usize].normal_texture;
        let tangents = match (&normal_slot, primitive.get(&Semantic::Tangents)) {
            (Some(_), Some(acc)) => {
                let t = self.read_floats::<4>(at, &acc)?;
                self.check_count(at, &acc, "TANGENT", t.len(), pos_acc, count)?;
                Some(t)
            }
            _ => None,
        };
        Ok(MaterialAttributes {
            uvs,
            uvs1,
            colors,
            tangents,
        })
    }

    /// The primitive's triangles as vertex indices (its index accessor, checked against the
    /// `count` vertices, or the vertices in order), assembled from its `mode`.
    fn read_triangles(
        &mut self,
        at: &str,
        primitive: &Primitive,
        mode: Mode,
        count: usize,
    ) -> Result<Vec<[u32; 3]>> {
        let indices: Vec<u32> = match primitive.indices() {
            Some(acc) => {
                let indices = self.read_indices(at, &acc)?;
                if let Some(&bad) = indices.iter().find(|&&i| i as usize >= count) {
                    bail_input!(
                        self.path,
                        "{at}: accessor {}: index {bad} out of range ({count} vertices)",
                        acc.index()
                    );
                }
                indices
            }
            None => match u32::try_from(count) {
                Ok(n) => (0..n).collect(),
                Err(_) => bail_input!(self.path, "{at}: too many vertices ({count})"),
            },
        };
        let tris = assemble(mode, &indices);
        if mode == Mode::Triangles && !indices.len().is_multiple_of(3) {
            self.warn(format!(
                "{at}: {} indices is not a multiple of 3, the last {} ignored",
                indices.len(),
                indices.len() % 3
            ));
        }
        Ok(tris)
    }

    /// The positions placed by `world`, counted from the render origin.
    fn place_positions(
        &self,
        at: &str,
        positions: &[[f32; 3]],
        world: DMat4,
        pos_acc: &Accessor,
    ) -> Result<Vec<Vec3>> {
        // Placed in f64, then counted from the render origin: one rounding to f32.
        let origin = self.scene.origin;
        let world_pos: Vec<Vec3> = positions
            .iter()
            .map(|&v| (world.transform_point3(Vec3::from_array(v).as_dvec3()) - origin).as_vec3())
            .collect();
        if world_pos.iter().any(|p| !p.is_finite()) {
            bail_input!(
                self.path,
                "{at}: accessor {} (POSITION): a vertex is not finite once transformed by its node",
                pos_acc.index()
            );
        }
        Ok(world_pos)
    }

    /// Keeps the front side of `tris` under a mirroring `world`, and drops the zero-area
    /// triangles among them (warned about).
    fn keep_front_faces(
        &mut self,
        at: &str,
        world: DMat4,
        world_pos: &[Vec3],
        tris: &mut Vec<[u32; 3]>,
    ) {
        if world.determinant() < 0.0 {
            // A mirror turns counter-clockwise into clockwise; swap to keep the front side.
            for t in tris.iter_mut() {
                t.swap(1, 2);
            }
        }
        // Zero-area triangles have no normal and cannot be hit; drop them. So are triangles
        // so large that their normal overflows f32: named apart, the cause is the scale.
        let (before, mut huge) = (tris.len(), 0);
        tris.retain(|t| {
            let [a, b, c] = t.map(|i| world_pos[i as usize]);
            let n = (b - a).cross(c - a);
            huge += usize::from(!n.is_finite());
            n != Vec3::ZERO && n.is_finite()
        });
        let zero = before - tris.len() - huge;
        if huge > 0 {
            self.warn(format!(
                "{at}: {huge} triangles skipped as too large to render (edges over about 1e19 \
                 units once placed, whose normal overflows 32-bit floats): the model or its \
                 node's scale is far too large; scale it down"
            ));
        }
        if zero > 0 {
            self.warn(format!("{at}: {zero} zero-area triangles skipped"));
        }
    }

    /// Tangents for a normal map: the file's, moved to world space like any surface
    /// direction, else MikkTSpace's over the normal map's own (transformed) coordinates, which
    /// may split vertices (every attribute of `v` follows). Zero where none can be had: the
    /// normal map is then not applied there. None without a normal map.
    fn tangents(
        &mut self,
        at: &str,
        material: u32,
        file_tangents: Option<Vec<[f32; 4]>>,
        world: DMat4,
        v: &mut Vertices,
        tris: &mut [[u32; 3]],
    ) -> Option<Vec<Vec4>> {
        let slot = self.scene.materials[material as usize].normal_texture?;
        if let Some(t) = file_tangents {
            return Some(world_tangents(&t, world));
        }
        let source = match (slot.tex_coord, &v.uvs1) {
            (1, Some(u1)) => u1,
            _ => &v.uvs,
        };
        let mapped: Vec<Vec2> = match &slot.transform {
            Some(t) => source.iter().map(|&uv| t.apply(uv)).collect(),
            None => source.clone(),
        };
        let mut split = Vec::new();
        match tangents::generate(&v.positions, &v.normals, &mapped, tris, &mut split) {
            Some(t) => {
                // Copies of split vertices: every attribute follows.
                for &s in &split {
                    v.copy_vertex(s as usize);
                }
                Some(t)
            }
            None => {
                self.warn_material(
                    material,
                    "tangents",
                    format!("{at}: no tangents can be made (no texture coordinate area); the normal map is not applied"),
                );
                Some(vec![Vec4::ZERO; v.positions.len()])
            }
        }
    }

    /// Appends the placed vertices and their triangles to the scene, within the scene's
    /// limits.
    fn append(&mut self, at: &str, material: u32, v: Vertices, tris: Vec<[u32; 3]>) -> Result<()> {
        let count = v.positions.len();
        let vertex_base = self.scene.positions.len();
        if vertex_base + count > crate::limits::MAX_VERTICES {
            bail_input!(
                self.path,
                "{at}: the scene would have {} vertices; at most {} are allowed",
                vertex_base + count,
                crate::limits::MAX_VERTICES
            );
        }
        if self.scene.triangles.len() + tris.len() > crate::limits::MAX_TRIANGLES {
            bail_input!(
                self.path,
                "{at}: the scene would have {} triangles; at most {} are allowed",
                self.scene.triangles.len() + tris.len(),
                crate::limits::MAX_TRIANGLES
            );
        }
        let scene = &mut self.scene;
        extend_optional(
            &mut scene.uvs1,
            vertex_base,
            v.uvs1.unwrap_or_default(),
            count,
            Vec2::ZERO,
        );
        extend_optional(
            &mut scene.tangents,
            vertex_base,
            v.tangents.unwrap_or_default(),
            count,
            Vec4::ZERO,
        );
        extend_optional(
            &mut scene.colors,
            vertex_base,
            v.colors.unwrap_or_default(),
            count,
            Vec4::ONE,
        );
        let vertex_base = vertex_base as u32;
        self.scene.positions.extend(v.positions);
        self.scene.normals.extend(v.normals);
        self.scene.uvs.extend(v.uvs);
        self.scene
            .tri_material
            .extend(std::iter::repeat_n(material, tris.len()));
        self.scene
            .triangles
            .extend(tris.into_iter().map(|t| t.map(|i| i + vertex_base)));
        Ok(())
    }

    /// One warning per material and `kind` (a primitive attribute it lacks or that is
    /// ignored), however many primitives use the material.
    fn warn_material(&mut self, material: u32, kind: &'static str, message: String) {
        if self.warned.insert((material, kind)) {
            let name = self.scene.materials[material as usize].name.clone();
            self.warn(format!("{message} (material {name:?})"));
        }
    }

    /// `TEXCOORD_<set>` of a primitive, checked (count, finite), if it has one.
    fn read_uvs(
        &self,
        at: &str,
        primitive: &Primitive,
        set: u32,
        pos_acc: &Accessor,
        count: usize,
    ) -> Result<Option<Vec<[f32; 2]>>> {
        let Some(acc) = primitive.get(&Semantic::TexCoords(set)) else {
            return Ok(None);
        };
        let uvs = self.read_floats::<2>(at, &acc)?;
        let name = format!("TEXCOORD_{set}");
        self.check_count(at, &acc, &name, uvs.len(), pos_acc, count)?;
        if let Some(i) = uvs.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
            bail_input!(
                self.path,
                "{at}: accessor {} ({name}): element {i} is not finite",
                acc.index()
            );
        }
        Ok(Some(uvs))
    }

    /// `COLOR_0` (VEC3 or VEC4; floats or normalised integers) as linear RGBA, alpha 1 for
    /// VEC3; checked (count, finite).
    fn read_colors(
        &self,
        at: &str,
        acc: &Accessor,
        pos_acc: &Accessor,
        count: usize,
    ) -> Result<Vec<Vec4>> {
        let colors: Vec<Vec4> = match acc.dimensions() {
            Dimensions::Vec3 => self
                .read_floats::<3>(at, acc)?
                .into_iter()
                .map(|c| Vec3::from_array(c).extend(1.0))
                .collect(),
            _ => self
                .read_floats::<4>(at, acc)?
                .into_iter()
                .map(Vec4::from_array)
                .collect(),
        };
        self.check_count(at, acc, "COLOR_0", colors.len(), pos_acc, count)?;
        if let Some(i) = colors.iter().position(|c| !c.is_finite()) {
            bail_input!(
                self.path,
                "{at}: accessor {} (COLOR_0): element {i} is not finite",
                acc.index()
            );
        }
        // Alpha is coverage: clamped to [0, 1] (the alpha test compares it with cutoffs).
        Ok(colors
            .into_iter()
            .map(|c| c.truncate().extend(c.w.clamp(0.0, 1.0)))
            .collect())
    }

    fn check_count(
        &self,
        at: &str,
        acc: &Accessor,
        name: &str,
        n: usize,
        pos_acc: &Accessor,
        count: usize,
    ) -> Result<()> {
        if n != count {
            bail_input!(
                self.path,
                "{at}: accessor {} ({name}) has {n} elements but accessor {} (POSITION) has {count}",
                acc.index(),
                pos_acc.index()
            );
        }
        Ok(())
    }

    /// The scene material for a glTF material (converted once), or the default grey. What the
    /// material uses that the renderer does not do is named in one warning per material.
    fn material(&mut self, material: ::gltf::Material) -> Result<u32> {
        let Some(index) = material.index() else {
            return Ok(self.default_material());
        };
        if let Some(&i) = self.material_map.get(&index) {
            return Ok(i);
        }
        let name = material
            .name()
            .map_or_else(|| format!("material {index}"), str::to_string);
        let alpha_mode = self.alpha_mode(index, &name, &material)?;
        let mut m = self.factors(index, &name, &material, alpha_mode)?;
        let mut unsupported = self.texture_slots(index, &material, &mut m)?;
        if let Some(note) = converted(&material, &mut m) {
            self.warn(format!("material {index} ({name:?}): {note}"));
        }
        let clamped = m.clamp_factors();
        if !clamped.is_empty() {
            self.warn(format!(
                "material {index} ({name:?}): outside glTF's ranges: {}",
                clamped.join("; ")
            ));
        }
        unsupported.extend(self.unsupported_material_extensions(&material));
        if !unsupported.is_empty() {
            self.warn(format!(
                "material {index} ({name:?}): {}",
                unsupported.join("; ")
            ));
        }
        let i = self.scene.materials.len() as u32;
        self.scene.materials.push(m);
        self.material_map.insert(index, i);
        Ok(i)
    }

    /// The scene index of the default grey material, added the first time a primitive needs
    /// it.
    fn default_material(&mut self) -> u32 {
        if let Some(i) = self.default_material {
            return i;
        }
        let i = self.scene.materials.len() as u32;
        self.scene.materials.push(Material::default_grey());
        self.default_material = Some(i);
        i
    }

    /// The material's alpha mode: a mask's cutoff checked, blending warned about (it is
    /// rendered as coverage).
    fn alpha_mode(
        &mut self,
        index: usize,
        name: &str,
        material: &::gltf::Material,
    ) -> Result<AlphaMode> {
        Ok(match material.alpha_mode() {
            ::gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            ::gltf::material::AlphaMode::Mask => {
                let cutoff = material.alpha_cutoff().unwrap_or(0.5);
                if !(cutoff.is_finite() && cutoff >= 0.0) {
                    bail_input!(
                        self.path,
                        "material {index}: alphaCutoff {cutoff} is not a finite number ≥ 0"
                    );
                }
                AlphaMode::Mask { cutoff }
            }
            ::gltf::material::AlphaMode::Blend => {
                self.warn(format!(
                    "material {index} ('{name}'): alphaMode BLEND is rendered as coverage (each \
                     camera sample sees the surface where its alpha exceeds the sample's \
                     threshold: use --spp 4 or more for smooth transparency) and as a mask at \
                     alpha 0.5 for shadows"
                ));
                AlphaMode::Blend
            }
        })
    }

    /// The material's factors (base colour, metallic-roughness, emission, ior, specular, the
    /// normal and occlusion textures' scales), each checked finite; no textures yet.
    fn factors(
        &self,
        index: usize,
        name: &str,
        material: &::gltf::Material,
        alpha_mode: AlphaMode,
    ) -> Result<Material> {
        let at = format!("material {index} ({name:?})");
        let finite = |what: &str, values: &[f32]| -> Result<()> {
            if values.iter().all(|v| v.is_finite()) {
                Ok(())
            } else {
                bail_input!(self.path, "{at}: {what} is not finite ({values:?})")
            }
        };
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, alpha] = pbr.base_color_factor();
        finite("baseColorFactor", &[r, g, b, alpha])?;
        let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
        finite("metallicFactor", &[metallic])?;
        finite("roughnessFactor", &[roughness])?;
        let emissive = material.emissive_factor();
        finite("emissiveFactor", &emissive)?;
        let strength = material.emissive_strength().unwrap_or(1.0);
        finite("KHR_materials_emissive_strength", &[strength])?;
        let ior = material.ior().unwrap_or(1.5);
        finite("KHR_materials_ior", &[ior])?;
        let (mut specular, mut specular_color) = (1.0, Vec3::ONE);
        if let Some(spec) = material.specular() {
            specular = spec.specular_factor();
            let c = spec.specular_color_factor();
            finite("KHR_materials_specular", &[specular, c[0], c[1], c[2]])?;
            specular_color = Vec3::from_array(c);
        }
        let mut m = Material {
            name: name.to_string(),
            base_color: Vec3::new(r, g, b),
            base_alpha: alpha,
            alpha_mode,
            metallic,
            roughness,
            emissive: Vec3::from_array(emissive) * strength,
            // [ours] An ior of 0 stands for an infinite one in the extension (F0 = 1); so does
            // the formula's limit, which `ior_f0` reaches from 1e6.
            ior: if ior == 0.0 { 1e6 } else { ior },
            specular,
            specular_color,
            ..Material::default()
        };
        if let Some(n) = material.normal_texture() {
            m.normal_scale = n.scale();
            finite("normalTexture.scale", &[m.normal_scale])?;
        }
        if let Some(o) = material.occlusion_texture() {
            m.occlusion_strength = o.strength();
            finite("occlusionTexture.strength", &[m.occlusion_strength])?;
        }
        Ok(m)
    }

    /// Sets `m`'s texture slots from the material's textures (each image decoded once);
    /// returns what of them the renderer does not do, for the material's warning.
    fn texture_slots(
        &mut self,
        index: usize,
        material: &::gltf::Material,
        m: &mut Material,
    ) -> Result<Vec<String>> {
        let mut unsupported: Vec<String> = Vec::new();
        for r in texture_refs(material) {
            let set = match r.set() {
                s @ (0 | 1) => s as u8,
                s => {
                    unsupported.push(format!(
                        "{} reads TEXCOORD_{s} (sets 0 and 1 are read; it reads TEXCOORD_0)",
                        r.slot
                    ));
                    0
                }
            };
            let texture = self.texture(index, r.texture.source(), r.encoding)?;
            let slot = Some(TextureSlot {
                texture,
                tex_coord: set,
                transform: r.transform,
                sampler: sampler_of(&r.texture),
            });
            match r.slot {
                "baseColorTexture" => m.base_color_texture = slot,
                "metallicRoughnessTexture" => m.metallic_roughness_texture = slot,
                "emissiveTexture" => m.emissive_texture = slot,
                "specularTexture" => m.specular_texture = slot,
                "specularColorTexture" | "specularGlossinessTexture" => {
                    m.specular_color_texture = slot
                }
                "diffuseTexture" => m.base_color_texture = slot,
                "normalTexture" => m.normal_texture = slot,
                _ => m.occlusion_texture = slot,
            }
        }
        Ok(unsupported)
    }

    /// The material's extensions that the renderer does not implement, for its warning (and
    /// noted, so the file's own warning does not name them again).
    fn unsupported_material_extensions(&mut self, material: &::gltf::Material) -> Vec<String> {
        let mut unsupported = Vec::new();
        // Material extensions the `gltf` crate does not parse (or we did not enable) come back
        // as JSON: every one of them is one we do not implement.
        if let Some(others) = material.extensions() {
            let mut names: Vec<&String> = others.keys().collect();
            names.sort();
            for ext in names {
                self.unsupported_extensions_seen.insert(ext.clone());
                unsupported.push(format!("{ext} is not supported (ignored)"));
            }
        }
        unsupported
    }

    /// Warns once about the extensions the file uses that are not implemented, beyond the
    /// material extensions each material's warning already named.
    fn warn_extensions(&mut self) {
        let mut others: Vec<String> = self
            .document
            .extensions_used()
            .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
            .filter(|e| !self.unsupported_extensions_seen.contains(*e))
            .map(str::to_string)
            .collect();
        others.sort();
        others.dedup();
        if !others.is_empty() {
            self.warn(format!(
                "extensions not supported (ignored): {}",
                others.join(", ")
            ));
        }
    }

    /// Decodes an image once per encoding and returns its scene texture index; an image with
    /// the same bytes as one already decoded returns that one's.
    fn texture(
        &mut self,
        material: usize,
        image: ::gltf::Image,
        encoding: Encoding,
    ) -> Result<usize> {
        let index = image.index();
        let Some(&d) = self.images.of_index.get(&index) else {
            // `count` saw every primitive the loader reads, and with it every image.
            anyhow::bail!("{}: image {index} was not counted", self.path.display());
        };
        let e = encoding_index(encoding);
        let distinct = &mut self.images.distinct[d];
        if let Some(t) = distinct.texture[e] {
            return Ok(t);
        }
        let at = format!("material {material}: image {index}");
        let texture = Texture::decode_as(bytes_of(&distinct.encoded, &self.buffers), encoding)
            .map_err(|e| match e.downcast::<NoMemory>() {
                Ok(e) => anyhow::Error::new(e).context(format!("{}: {at}", self.path.display())),
                Err(e) => input_error(self.path, format!("{at}: cannot decode: {e}")),
            })?;
        let t = self.scene.textures.len();
        self.scene.textures.push(texture);
        distinct.texture[e] = Some(t);
        // Its bytes go once every decoding the materials ask for is done.
        let wanted = distinct.encodings;
        if (0..2).all(|k| !wanted[k] || distinct.texture[k].is_some()) {
            distinct.encoded = Encoded::Gone;
        }
        Ok(t)
    }

    /// Reads a float attribute of `N` components (VEC2/VEC3); integer components are converted,
    /// normalised where the accessor says so.
    fn read_floats<const N: usize>(&self, at: &str, acc: &Accessor) -> Result<Vec<[f32; N]>> {
        let dims = acc.dimensions().multiplicity();
        if dims != N {
            bail_input!(
                self.path,
                "{at}: accessor {}: type {:?}, expected {N} components",
                acc.index(),
                acc.dimensions()
            );
        }
        let values = self.read_accessor(at, acc)?;
        Ok(values
            .chunks_exact(N)
            .map(|c| std::array::from_fn(|k| c[k] as f32))
            .collect())
    }

    /// Reads an index accessor (SCALAR of unsigned bytes, shorts or ints).
    fn read_indices(&self, at: &str, acc: &Accessor) -> Result<Vec<u32>> {
        if acc.dimensions() != Dimensions::Scalar
            || !matches!(
                acc.data_type(),
                DataType::U8 | DataType::U16 | DataType::U32
            )
        {
            bail_input!(
                self.path,
                "{at}: accessor {} (indices): {:?} {:?}, expected unsigned integer SCALAR",
                acc.index(),
                acc.data_type(),
                acc.dimensions()
            );
        }
        Ok(self
            .read_accessor(at, acc)?
            .into_iter()
            .map(|v| v as u32)
            .collect())
    }

    /// Reads all `count × components` values of an accessor (dense, sparse, or zeros), with every
    /// byte range checked against its view and buffer.
    fn read_accessor(&self, at: &str, acc: &Accessor) -> Result<Vec<f64>> {
        let a = acc.index();
        let count = acc.count();
        let dims = acc.dimensions().multiplicity();
        let ty = acc.data_type();
        let normalized = acc.normalized();
        let err = |msg: String| input_error(self.path, format!("{at}: accessor {a}: {msg}"));
        check_values(self.path, at, acc)?;
        if let Some(values) = self.decoded.get(&a) {
            return Ok(values.clone());
        }

        let mut values = match acc.view() {
            Some(view) => {
                let bytes = self.view_bytes(&view).ok_or_else(|| {
                    err(format!(
                        "buffer view {} lies outside its buffer",
                        view.index()
                    ))
                })?;
                read_elements(
                    bytes,
                    acc.offset(),
                    view.stride(),
                    count,
                    dims,
                    ty,
                    normalized,
                )
                .map_err(err)?
            }
            None => {
                if count.saturating_mul(dims) > MAX_ZERO_ELEMENTS {
                    return Err(err(format!("count {count} without a buffer view")));
                }
                vec![0.0; count * dims]
            }
        };

        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            let indices = sparse.indices();
            let index_type = match indices.index_type() {
                ::gltf::accessor::sparse::IndexType::U8 => DataType::U8,
                ::gltf::accessor::sparse::IndexType::U16 => DataType::U16,
                ::gltf::accessor::sparse::IndexType::U32 => DataType::U32,
            };
            let index_bytes = self.view_bytes(&indices.view()).ok_or_else(|| {
                err("sparse indices' buffer view lies outside its buffer".to_string())
            })?;
            let targets =
                read_elements(index_bytes, indices.offset(), None, n, 1, index_type, false)
                    .map_err(|e| err(format!("sparse indices: {e}")))?;
            let value_view = sparse.values().view();
            let value_bytes = self.view_bytes(&value_view).ok_or_else(|| {
                err("sparse values' buffer view lies outside its buffer".to_string())
            })?;
            let replacements = read_elements(
                value_bytes,
                sparse.values().offset(),
                None,
                n,
                dims,
                ty,
                normalized,
            )
            .map_err(|e| err(format!("sparse values: {e}")))?;
            for (k, &target) in targets.iter().enumerate() {
                let target = target as usize;
                if target >= count {
                    return Err(err(format!(
                        "sparse index {target} out of range ({count} elements)"
                    )));
                }
                values[target * dims..(target + 1) * dims]
                    .copy_from_slice(&replacements[k * dims..(k + 1) * dims]);
            }
        }
        Ok(values)
    }

    /// The bytes of a buffer view, if it lies inside its buffer.
    fn view_bytes(&self, view: &::gltf::buffer::View) -> Option<&[u8]> {
        let start = view.offset();
        let end = start.checked_add(view.length())?;
        self.buffers.get(view.buffer().index())?.get(start..end)
    }
}

/// Reads `count` elements of `dims` components of type `ty` from `bytes` (a buffer view),
/// starting at `offset` with `stride` bytes between elements (tightly packed if `None`).
fn read_elements(
    bytes: &[u8],
    offset: usize,
    stride: Option<usize>,
    count: usize,
    dims: usize,
    ty: DataType,
    normalized: bool,
) -> std::result::Result<Vec<f64>, String> {
    let size = ty.size();
    let element = size * dims;
    let stride = stride.unwrap_or(element);
    if stride < element {
        return Err(format!(
            "byteStride {stride} is smaller than the element size {element}"
        ));
    }
    if count == 0 {
        return Ok(Vec::new());
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(element));
    match end {
        Some(end) if end <= bytes.len() => {}
        _ => {
            return Err(format!(
                "{count} elements of {element} bytes (stride {stride}, offset {offset}) do not fit in the {}-byte buffer view",
                bytes.len()
            ));
        }
    }
    let mut out = Vec::with_capacity(count * dims);
    for e in 0..count {
        let start = offset + e * stride;
        for k in 0..dims {
            let b = &bytes[start + k * size..start + (k + 1) * size];
            out.push(component(b, ty, normalized));
        }
    }
    Ok(out)
}

/// One little-endian component as f64; normalised integers map to [0, 1] or [−1, 1] as the glTF
/// spec says.
fn component(b: &[u8], ty: DataType, normalized: bool) -> f64 {
    match ty {
        DataType::I8 => {
            let v = f64::from(b[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = f64::from(b[0]);
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let v = f64::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = f64::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
    }
}

/// Triangles from an index list: lists as is, strips and fans unrolled per the glTF spec.
/// Triangles that repeat a vertex (strip restarts) are dropped.
fn assemble(mode: Mode, idx: &[u32]) -> Vec<[u32; 3]> {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::Triangles => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [idx[i], idx[i + 1], idx[i + 2]]
                } else {
                    [idx[i], idx[i + 2], idx[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..idx.len().saturating_sub(1))
            .map(|i| [idx[i], idx[i + 1], idx[0]])
            .collect(),
        _ => Vec::new(),
    };
    tris.into_iter()
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect()
}

/// Area-weighted vertex normals (the sum of unnormalised face normals), normalised. A vertex
/// whose sum cancels (back-to-back faces) takes its largest incident face's normal; a vertex no
/// triangle uses gets +Y, which nothing will see.
pub(super) fn smooth_normals(positions: &[Vec3], tris: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    let mut largest = vec![Vec3::ZERO; positions.len()];
    for t in tris {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            let i = i as usize;
            sum[i] += n;
            if n.length_squared() > largest[i].length_squared() {
                largest[i] = n;
            }
        }
    }
    sum.iter()
        .zip(&largest)
        .map(|(s, l)| {
            let n = s.normalize_or_zero();
            if n != Vec3::ZERO {
                n
            } else {
                let l = l.normalize_or_zero();
                if l != Vec3::ZERO { l } else { Vec3::Y }
            }
        })
        .collect()
}

/// What posing adds to the scene's memory: the rig's own copy of the vertices, and, when the
/// file has animations, a posed copy of the scene and its BVH per frame in flight.
fn rig_budget(document: &Document, size: &mut SceneSize, budget: &mut Budget) {
    if super::rig_read::wanted(document) {
        size.extra_vertex_bytes += size.vertices * crate::limits::RIG_VERTEX;
    }
    if document.animations().next().is_some() {
        budget.animated();
    }
}

/// Posing (super::rig): what the loader keeps of the nodes, skins, animations and moving
/// primitives, and the rest pose it leaves in the scene.
impl Loader<'_> {
    /// Reads the nodes, skins and animations, before the meshes: a primitive is kept for
    /// posing only if something can move it.
    fn start_rig(&mut self) -> Result<()> {
        if self.rig.is_none() {
            return Ok(());
        }
        let read = |at: &str, acc: &Accessor| self.read_accessor(at, acc);
        let data = super::rig::RigData {
            nodes: super::rig_read::nodes(self.document),
            skins: super::rig_read::skins(self.path, self.document, &read)?,
            clips: super::rig_read::clips(self.path, self.document, &read)?,
            origin: self.scene.origin,
            ..Default::default()
        };
        self.rig = Some(data);
        Ok(())
    }

    /// Keeps a primitive just placed by `world` (its vertices `v`, triangles `tris`) for
    /// posing, in its mesh's space, when a skin, a morph target or an animation can move it.
    #[allow(clippy::too_many_arguments)]
    fn keep_for_rig(
        &mut self,
        at: &str,
        primitive: &Primitive,
        positions: &[[f32; 3]],
        file_normals: Option<&[[f32; 3]]>,
        world: DMat4,
        v: &Vertices,
        tris: &[[u32; 3]],
    ) -> Result<()> {
        let Some(rig) = &self.rig else {
            return Ok(());
        };
        let (node, skin) = self.placing;
        let count = positions.len();
        let read = |at: &str, acc: &Accessor| self.read_accessor(at, acc);
        let mut influences = match skin {
            Some(s) => {
                let joints = rig.skins[s].joints.len();
                super::rig_read::influences(self.path, at, primitive, count, joints, &read)?
            }
            None => Default::default(),
        };
        let mut targets = super::rig_read::targets(self.path, at, primitive, count, &read)?;
        // A channel on the node or on one of its ancestors moves it.
        let mut animated = false;
        let mut up = Some(node);
        while let Some(k) = up {
            animated |= rig
                .clips
                .iter()
                .flat_map(|c| &c.channels)
                .any(|ch| ch.node == k);
            up = rig.nodes[k].parent;
        }
        if influences.is_empty() && targets.is_empty() && !animated {
            return Ok(());
        }
        let mut local: Vec<Vec3> = positions.iter().map(|&p| Vec3::from_array(p)).collect();
        for &c in &v.copied {
            let c = c as usize;
            local.push(local[c]);
            if !influences.is_empty() {
                let m = super::skin::Influences::MAX;
                influences.joints.extend_from_within(c * m..(c + 1) * m);
                influences.weights.extend_from_within(c * m..(c + 1) * m);
            }
            for t in &mut targets.0 {
                for a in [&mut t.positions, &mut t.normals, &mut t.tangents] {
                    if !a.is_empty() {
                        a.push(a[c]);
                    }
                }
            }
        }
        // The placed normals carried back (by the transpose of the normal matrix's inverse):
        // the file's, or the loader's fallback where it had none or a broken one.
        let back = world.as_mat4();
        let back = glam::Mat3::from_mat4(back).transpose();
        let normals = v
            .normals
            .iter()
            .map(|&n| (back * n).normalize_or_zero())
            .collect();
        let first_vertex = self.scene.positions.len();
        let first_triangle = self.scene.triangles.len();
        let primitive = super::rig::RigPrimitive {
            node,
            skin: skin.filter(|_| !influences.is_empty()),
            first_vertex,
            triangles: first_triangle..first_triangle + tris.len(),
            mirrored: world.determinant() < 0.0,
            positions: local,
            normals,
            smooth: file_normals.is_none(),
            tangents: v
                .tangents
                .as_deref()
                .map(|t| super::rig_read::local_tangents(t, world))
                .unwrap_or_default(),
            influences,
            targets,
        };
        if let Some(rig) = &mut self.rig {
            rig.primitives.push(primitive);
        }
        Ok(())
    }

    /// The scene, with its rig when the file has one, in its rest pose: skins bent by their
    /// joints at rest, morph targets at their default weights.
    fn finish_rig(self) -> Result<Scene> {
        let mut scene = self.scene;
        let Some(data) = self.rig else {
            return Ok(scene);
        };
        let rig = super::rig::Rig {
            data: std::sync::Arc::new(data),
            up: super::Up::Y,
        };
        let bent = rig.data.bent_at_rest();
        if bent.iter().any(|&b| b) {
            rig.pose(&mut scene, None, &bent);
        }
        scene.rig = Some(rig);
        Ok(scene)
    }
}
