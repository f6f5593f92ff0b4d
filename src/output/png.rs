//! PNG previews: exposure, then the sRGB transfer curve, 8 bits; RGBA with straight
//! (unpremultiplied) alpha, as PNG defines it, where the frame has transparent pixels.

use anyhow::Context;

use crate::error::Result;
use crate::film::srgb_encode;

/// Linear RGB → 8-bit sRGB with an exposure multiplier (clipped highlights).
pub fn tonemap(rgb: [f32; 3], exposure: f32) -> [u8; 3] {
    rgb.map(|c| (srgb_encode(c * exposure) * 255.0 + 0.5) as u8)
}

/// The PNG file of 8-bit `pixels`, RGB or RGBA as `P` says.
fn encode<P>(width: u32, height: u32, pixels: Vec<u8>) -> Result<Vec<u8>>
where
    P: image::Pixel<Subpixel = u8> + image::PixelWithColorType,
{
    let img = image::ImageBuffer::<P, Vec<u8>>::from_raw(width, height, pixels)
        .context("pixel buffer does not match the image size")?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .context("encoding PNG")?;
    Ok(bytes.into_inner())
}

/// The PNG file of a tone-mapped preview of linear RGB pixels, premultiplied by `alpha` where
/// given: RGBA with the colour unpremultiplied before tone mapping when some pixel is less
/// than opaque, else RGB.
pub fn encode_preview(
    width: u32,
    height: u32,
    beauty: &[[f32; 3]],
    alpha: Option<&[f32]>,
    exposure: f32,
) -> Result<Vec<u8>> {
    let Some(alpha) = alpha.filter(|a| a.iter().any(|&v| v < 1.0)) else {
        let mut bytes = Vec::with_capacity(beauty.len() * 3);
        for p in beauty {
            bytes.extend_from_slice(&tonemap(*p, exposure));
        }
        return encode::<image::Rgb<u8>>(width, height, bytes);
    };
    let mut bytes = Vec::with_capacity(beauty.len() * 4);
    for (p, &a) in beauty.iter().zip(alpha) {
        let a = a.clamp(0.0, 1.0);
        let straight = if a > 0.0 { p.map(|c| c / a) } else { [0.0; 3] };
        bytes.extend_from_slice(&tonemap(straight, exposure));
        bytes.push((a * 255.0 + 0.5) as u8);
    }
    encode::<image::Rgba<u8>>(width, height, bytes)
}

/// An RGBA preview over a light and dark grey checkerboard of `square`-pixel squares (the
/// usual picture of transparency), as RGB; an opaque image is unchanged.
pub fn over_checkerboard(img: &image::RgbaImage, square: u32) -> image::RgbImage {
    image::RgbImage::from_fn(img.width(), img.height(), |x, y| {
        let p = img.get_pixel(x, y).0;
        let back = if (x / square + y / square).is_multiple_of(2) {
            204.0
        } else {
            153.0
        };
        let a = p[3] as f32 / 255.0;
        image::Rgb([0, 1, 2].map(|c| (p[c] as f32 * a + back * (1.0 - a) + 0.5) as u8))
    })
}
