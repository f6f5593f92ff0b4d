//! Texture decoding (sRGB → linear at load) and sampling.

use glam::{Vec2, Vec3};

use super::Texture;

/// The sRGB electro-optical transfer function: an sRGB-encoded value in [0, 1] to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

impl Texture {
    /// A texture from sRGB-encoded RGB bytes (row-major, row 0 at the top), decoded to linear.
    /// `None` if `rgb` does not hold `width × height × 3` bytes.
    pub fn from_srgb8(width: usize, height: usize, rgb: &[u8]) -> Option<Texture> {
        if width.checked_mul(height)?.checked_mul(3)? != rgb.len() {
            return None;
        }
        // 256 entries: decode each byte value once.
        let table: Vec<f32> = (0..=255u8)
            .map(|b| srgb_to_linear(f32::from(b) / 255.0))
            .collect();
        let texels = rgb
            .chunks_exact(3)
            .map(|c| {
                Vec3::new(
                    table[c[0] as usize],
                    table[c[1] as usize],
                    table[c[2] as usize],
                )
            })
            .collect();
        Some(Texture {
            width,
            height,
            texels,
        })
    }

    /// Decodes an encoded image (PNG or JPEG) to a linear texture, treating it as sRGB and
    /// ignoring alpha. 16-bit images are decoded from their full precision.
    /// Images over [`crate::limits::MAX_TEXTURE_TEXELS`] or 16384 on a side are refused before
    /// their pixels are allocated.
    pub fn decode(bytes: &[u8]) -> Result<Texture, image::ImageError> {
        let mut reader =
            image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(crate::limits::MAX_DIM);
        limits.max_image_height = Some(crate::limits::MAX_DIM);
        // The decoder's own buffer: at most 8 bytes (RGBA16) per allowed texel.
        limits.max_alloc = Some(crate::limits::MAX_TEXTURE_TEXELS * 8);
        reader.limits(limits.clone());
        let (w, h) = reader.into_dimensions()?;
        if u64::from(w) * u64::from(h) > crate::limits::MAX_TEXTURE_TEXELS {
            return Err(image::ImageError::Limits(
                image::error::LimitError::from_kind(image::error::LimitErrorKind::DimensionError),
            ));
        }
        let mut reader =
            image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format()?;
        reader.limits(limits);
        let img = reader.decode()?;
        let rgb = img.to_rgb32f();
        let (w, h) = (rgb.width() as usize, rgb.height() as usize);
        let texels = rgb
            .pixels()
            .map(|p| Vec3::new(p[0], p[1], p[2]).map(srgb_to_linear))
            .collect();
        Ok(Texture {
            width: w,
            height: h,
            texels,
        })
    }

    /// The texel at integer coordinates, wrapped (repeat) into range.
    fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.rem_euclid(self.width as i64) as usize;
        let y = y.rem_euclid(self.height as i64) as usize;
        self.texels[y * self.width + x]
    }

    /// Bilinear sample at `uv` with repeat wrap: texel `(i, j)` covers
    /// `u ∈ [i/w, (i+1)/w)`, `v ∈ [j/h, (j+1)/h)` (v down, row 0 at the top), and its exact
    /// colour is returned at its centre. Returns white for an empty texture and texel (0, 0)'s
    /// neighbourhood for non-finite `uv`.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        if self.width == 0 || self.height == 0 || self.texels.len() < self.width * self.height {
            return Vec3::ONE;
        }
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        // Wrap first so large coordinates keep their precision in the fraction.
        let x = uv.x.rem_euclid(1.0) * self.width as f32 - 0.5;
        let y = uv.y.rem_euclid(1.0) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self.texel(x0, y0).lerp(self.texel(x0 + 1, y0), fx);
        let bottom = self.texel(x0, y0 + 1).lerp(self.texel(x0 + 1, y0 + 1), fx);
        top.lerp(bottom, fy)
    }
}
