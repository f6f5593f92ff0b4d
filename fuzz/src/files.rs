//! Small files shared by the glTF target (its folder of external resources) and the seed
//! generator: one triangle's buffer and a 2×2 PNG texture.

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
