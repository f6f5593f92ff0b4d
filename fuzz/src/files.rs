//! Small files shared by the glTF target (its folder of external resources), its replay in
//! tests/it/fuzz_regressions.rs and the seed generator: one triangle's buffer, a 2×2 PNG
//! texture, and the folder a fuzzed model lies in.

// Each user includes this file and calls some of its functions.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// Writes the folder a fuzzed model lies in, `root/model/`, and returns it: `buffer.bin` and
/// `texture.png` (the names the seed files use), `inside-link.bin` (a link to `buffer.bin`)
/// and `outside-link.bin` (a link to `root/outside.bin`, a triangle buffer outside the folder,
/// which `../outside.bin` also names). The `uri-*` seeds name each of them, so the target reaches
/// URI resolution's acceptances and its refusals of files that exist.
pub fn model_folder(root: &Path) -> PathBuf {
    let dir = root.join("model");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("buffer.bin"), triangle_buffer()).unwrap();
    std::fs::write(dir.join("texture.png"), texture_png()).unwrap();
    std::fs::write(root.join("outside.bin"), triangle_buffer()).unwrap();
    for (link, to) in [
        ("inside-link.bin", "buffer.bin"),
        ("outside-link.bin", "../outside.bin"),
    ] {
        let _ = std::fs::remove_file(dir.join(link));
        std::os::unix::fs::symlink(to, dir.join(link)).unwrap();
    }
    dir
}

/// Three VEC3 f32 positions (36 bytes), three u16 indices (6 bytes), two bytes of padding, then
/// three VEC2 f32 texture coordinates (24 bytes): 68 bytes.
pub fn triangle_buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in v {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b.extend_from_slice(&[0, 0]);
    for v in [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]] {
        for c in v {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    b
}

/// A 2×2 RGB PNG.
pub fn texture_png() -> Vec<u8> {
    let img = image::RgbImage::from_raw(2, 2, vec![255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128])
        .expect("2x2x3 bytes");
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("PNG encodes");
    out.into_inner()
}
