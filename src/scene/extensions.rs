//! What a glTF file is and which extensions it needs, checked before the `gltf` crate parses
//! it: a file of another format, glTF 1.0, and an extension the renderer cannot do are refused
//! with the cause first ("KHR_texture_basisu without a fallback …, re-export …") rather than
//! a parser's position or a validation path; the extensions it can do are let through the
//! crate's own check of `extensionsRequired`.

use std::collections::HashSet;
use std::path::Path;

use ::gltf::Document;
use serde::Deserialize;
use serde_json::Value;

use super::sniff::{Kind, kind, opening};
use crate::bail_input;
use crate::error::{Result, escaped};

/// Extensions a file may require that the loader reads: quantized attributes are read as the
/// normalised or plain integers they are; Draco and meshopt streams are decoded (`draco.rs`,
/// `meshopt.rs`); KTX2 and WebP textures with a PNG/JPEG fallback use
/// the fallback (one without is refused by [`check_json`]); unlit and spec-gloss materials
/// are converted (`gltf.rs`).
const READ_WHEN_REQUIRED: &[&str] = &[
    "KHR_mesh_quantization",
    super::draco::EXTENSION,
    super::meshopt::EXTENSION,
    "KHR_texture_basisu",
    "EXT_texture_webp",
    "KHR_materials_unlit",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_texture_transform",
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
];

/// Texture extensions whose image the renderer cannot decode: the texture's `source` (the
/// PNG or JPEG fallback) is read instead.
const TEXTURE_FORMATS: &[(&str, &str)] = &[
    ("KHR_texture_basisu", "a KTX2/Basis Universal texture"),
    ("EXT_texture_webp", "a WebP texture"),
    ("MSFT_texture_dds", "a DDS texture"),
];

/// How to get a file the renderer reads, per unsupported extension.
fn how_to_convert(_ext: &str) -> &'static str {
    "re-export it without it (Blender's glTF exporter, or `gltf-transform`)"
}

/// Refuses what is not a glTF 2.0 file, by its first bytes: another format named as what it
/// is, a GLB of another version.
pub(super) fn check_kind(path: &Path, bytes: &[u8]) -> Result<()> {
    match kind(bytes) {
        Kind::Glb { version: 2 } | Kind::Json => Ok(()),
        Kind::Glb { version: 1 } => bail_input!(
            path,
            "glTF 1.0 is not supported (a GLB of version 1): envshadow reads glTF 2.0; convert \
             it, e.g. with `gltf-pipeline -i in.glb -o out.glb`"
        ),
        // No glTF of another version exists: a damaged header, which the GLB reader names
        // more exactly (a length below the header, a chunk past the end, …).
        Kind::Glb { .. } => Ok(()),
        Kind::Other(what) => bail_input!(
            path,
            "not a glTF file (starts with '{}'): {what}; envshadow reads glTF 2.0 (.gltf/.glb)",
            opening(bytes)
        ),
        Kind::Text | Kind::Binary => bail_input!(
            path,
            "not a glTF file (starts with '{}'); envshadow reads glTF 2.0 (.gltf/.glb)",
            opening(bytes)
        ),
    }
}

/// The JSON of a `.gltf`, or of a GLB's first chunk; `None` where it cannot be found.
fn json_of(bytes: &[u8]) -> Option<&[u8]> {
    if bytes.starts_with(b"glTF") {
        let len = u32::from_le_bytes(bytes.get(12..16)?.try_into().ok()?) as usize;
        bytes.get(20..20usize.checked_add(len)?)
    } else {
        Some(bytes)
    }
}

/// What [`check_json`] reads of the document. Everything else (buffers, their `data:` URIs)
/// is skipped by the parser without being copied; `images` keep only their names.
#[derive(Default, Deserialize)]
#[serde(default)]
struct Head {
    #[serde(rename = "extensionsRequired")]
    extensions_required: Vec<String>,
    textures: Vec<Value>,
    images: Vec<ImageHead>,
}

#[derive(Default, Deserialize)]
#[serde(default)]
struct ImageHead {
    name: Option<String>,
}

/// glTF 1.0 kept its objects in dictionaries; its `meshes` tells it apart.
#[derive(Default, Deserialize)]
#[serde(default)]
struct OldHead {
    asset: Option<Value>,
    meshes: Option<Value>,
}

/// Checks the file's version and the extensions it requires, and returns the required
/// extensions the loader reads (which the `gltf` crate's validation would refuse: it knows
/// only those it parses). glTF 1.0, an unsupported required extension, and a texture in a
/// format the renderer cannot decode that has no PNG/JPEG fallback are refused, the cause
/// first. A document this cannot parse is left to the `gltf` crate, which says why.
pub(super) fn check_json(path: &Path, bytes: &[u8]) -> Result<HashSet<String>> {
    let Some(json) = json_of(bytes) else {
        return Ok(HashSet::new());
    };
    let Ok(old) = serde_json::from_slice::<OldHead>(json) else {
        return Ok(HashSet::new());
    };
    let version = old
        .asset
        .as_ref()
        .and_then(|a| a.get("version"))
        .and_then(Value::as_str);
    match version {
        Some(v) if v.starts_with("2.") => {}
        Some(v) => bail_input!(
            path,
            "glTF {} is not supported (asset.version \"{}\"): envshadow reads glTF 2.0; \
             convert it, e.g. with `gltf-pipeline -i in.gltf -o out.gltf`",
            escaped(v),
            escaped(v)
        ),
        None if old.meshes.as_ref().is_some_and(Value::is_object) => bail_input!(
            path,
            "glTF 1.0 is not supported (asset.version missing, objects in dictionaries): \
             envshadow reads glTF 2.0; convert it, e.g. with `gltf-pipeline -i in.gltf -o out.gltf`"
        ),
        None => {}
    }
    let Ok(head) = serde_json::from_slice::<Head>(json) else {
        return Ok(HashSet::new());
    };
    for ext in &head.extensions_required {
        let ext = ext.as_str();
        if !READ_WHEN_REQUIRED.contains(&ext) && !TEXTURE_FORMATS.iter().any(|(e, _)| *e == ext) {
            bail_input!(
                path,
                "{} is required by the file and not supported: {}",
                escaped(ext),
                how_to_convert(ext)
            );
        }
    }
    check_texture_fallbacks(path, &head)?;
    Ok(head.extensions_required.into_iter().collect())
}

/// Refuses a texture whose only image is in a format the renderer cannot decode (KTX2/Basis,
/// WebP, DDS: no `source` fallback), naming the texture, its image and the extension.
fn check_texture_fallbacks(path: &Path, head: &Head) -> Result<()> {
    for (t, texture) in head.textures.iter().enumerate() {
        if texture.get("source").is_some() {
            continue;
        }
        for (ext, what) in TEXTURE_FORMATS {
            let Some(image) = texture
                .pointer(&format!("/extensions/{ext}/source"))
                .and_then(Value::as_u64)
            else {
                continue;
            };
            let name = usize::try_from(image)
                .ok()
                .and_then(|i| head.images.get(i))
                .and_then(|i| i.name.as_deref())
                .map_or_else(String::new, |n| format!(" '{}'", escaped(n)));
            bail_input!(
                path,
                "{ext}: texture {t}'s image {image}{name} is {what} with no PNG or JPEG \
                 fallback, which envshadow cannot decode; re-export the model with PNG or JPEG \
                 textures (e.g. `gltf-transform png in.glb out.glb`)"
            );
        }
    }
    Ok(())
}

/// The document, once the `gltf` crate's validation passes it, but for one rule the crate
/// adds to glTF 2.0: an accessor without a buffer view is valid (its values are zeros, or a
/// Draco stream's), and the loader reads it so.
pub(super) fn validated(root: ::gltf::json::Root) -> std::result::Result<Document, String> {
    use ::gltf::json::validation::{Error, Validate};
    let mut errors = Vec::new();
    root.validate(&root, ::gltf::json::Path::new, &mut |path, error| {
        errors.push((path(), error))
    });
    errors.retain(|(path, error)| {
        let p = path.as_str();
        !(*error == Error::Missing && p.starts_with("accessors[") && p.ends_with("].bufferView"))
    });
    if errors.is_empty() {
        return Ok(Document::from_json_without_validation(root));
    }
    let mut message = String::from("invalid glTF:");
    for (path, error) in errors {
        message.push_str(&format!(" {path}: {error};"));
    }
    Err(message)
}
