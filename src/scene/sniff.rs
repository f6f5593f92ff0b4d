//! What a file is, from its first bytes: so that a PLY, OBJ or Blender file given where a
//! model or a spec is expected, or a web page saved under a `.glb` name, is named as what it
//! is rather than reported at a parser's line and column.

/// What a file's content says it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A GLB container of `version` (2 is glTF 2.0).
    Glb { version: u32 },
    /// A JSON document (a `.gltf`, or some other JSON).
    Json,
    /// Another format we recognise: its name with an article ("a PLY file").
    Other(&'static str),
    /// Text we do not recognise (a TOML spec is one).
    Text,
    /// Bytes we do not recognise.
    Binary,
}

/// Magic numbers and what they mean, checked in order.
const MAGIC: &[(&[u8], &str)] = &[
    (b"ply\n", "a PLY file"),
    (b"ply\r\n", "a PLY file"),
    (b"BLENDER", "a Blender file (.blend)"),
    (b"Kaydara FBX Binary", "an FBX file"),
    (b"#usda", "a USD file"),
    (b"PXR-USDC", "a USD file"),
    (b"PK\x03\x04", "a ZIP archive (a .zip, .usdz or .3mf)"),
    (b"\x89PNG", "a PNG image"),
    (b"\xff\xd8\xff", "a JPEG image"),
    (b"#?RADIANCE", "a Radiance HDR image"),
    (b"#?RGBE", "a Radiance HDR image"),
    (b"\x76\x2f\x31\x01", "an OpenEXR image"),
    (b"\xabKTX 20", "a KTX2 texture"),
    (b"draco", "a Draco-compressed mesh (.drc)"),
    (b"\x1f\x8b", "a gzip-compressed file"),
    (b"%PDF", "a PDF document"),
];

/// What `bytes` (a file's start, or all of it) are.
pub fn kind(bytes: &[u8]) -> Kind {
    if bytes.starts_with(b"glTF") {
        let version = bytes
            .get(4..8)
            .map_or(0, |v| u32::from_le_bytes([v[0], v[1], v[2], v[3]]));
        return Kind::Glb { version };
    }
    for (magic, what) in MAGIC {
        if bytes.starts_with(magic) {
            return Kind::Other(what);
        }
    }
    let text = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let start = text.iter().position(|b| !b.is_ascii_whitespace());
    let text = &text[start.unwrap_or(text.len())..];
    if text.starts_with(b"{") {
        return Kind::Json;
    }
    let lower: Vec<u8> = text.iter().take(16).map(u8::to_ascii_lowercase).collect();
    if lower.starts_with(b"<!doctype") || lower.starts_with(b"<html") {
        return Kind::Other("an HTML page");
    }
    if lower.starts_with(b"<?xml") {
        return Kind::Other("an XML file (a COLLADA .dae or an X3D?)");
    }
    if text.starts_with(b"solid ") && contains(text, b"facet normal") {
        return Kind::Other("an STL file");
    }
    if is_obj(text) {
        return Kind::Other("a Wavefront OBJ file");
    }
    if std::str::from_utf8(&text[..text.len().min(4096)]).is_ok_and(|t| !t.contains('\0')) {
        Kind::Text
    } else {
        Kind::Binary
    }
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

/// Whether the first statement of `text` (past `#` comments and blank lines) is an OBJ
/// statement: a keyword and values, not `key = value` as TOML has it.
fn is_obj(text: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(&text[..text.len().min(4096)]) else {
        return false;
    };
    let Some(line) = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
    else {
        return false;
    };
    let mut words = line.split_whitespace();
    let first = words.next().unwrap_or("");
    let second = words.next().unwrap_or("=");
    ["v", "vn", "vt", "f", "o", "g", "s", "mtllib", "usemtl"].contains(&first) && second != "="
}

/// The file's first word as a message shows it: up to 16 characters, control characters
/// escaped.
pub fn opening(bytes: &[u8]) -> String {
    let text = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let start = text
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    let head: String = String::from_utf8_lossy(&text[start..text.len().min(start + 48)])
        .chars()
        .take_while(|c| !c.is_whitespace())
        .take(16)
        .collect();
    crate::error::escaped(&head).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_are_known_by_their_first_bytes() {
        assert_eq!(kind(b"glTF\x02\0\0\0"), Kind::Glb { version: 2 });
        assert_eq!(kind(b"glTF\x01\0\0\0"), Kind::Glb { version: 1 });
        assert_eq!(kind(b" \n{\"asset\":{}}"), Kind::Json);
        assert_eq!(kind(b"ply\nformat ascii 1.0\n"), Kind::Other("a PLY file"));
        assert_eq!(
            kind(b"# Blender 4.1\nmtllib x.mtl\no Cube\nv 1 1 1\n"),
            Kind::Other("a Wavefront OBJ file")
        );
        assert_eq!(
            kind(b"BLENDER-v402RENDH"),
            Kind::Other("a Blender file (.blend)")
        );
        assert_eq!(
            kind(b"\n<!DOCTYPE html>\n<html>"),
            Kind::Other("an HTML page")
        );
        assert_eq!(kind(b"# a spec\n[scene]\nfile = \"x.glb\"\n"), Kind::Text);
        assert_eq!(kind(b"v = 1\n"), Kind::Text, "TOML, not OBJ");
        assert_eq!(kind(b"\0\x01\x02"), Kind::Binary);
        assert_eq!(opening(b"\n<!DOCTYPE html>\n<html>"), "<!DOCTYPE");
    }
}
