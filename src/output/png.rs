//! PNG previews: exposure, then the view transform ([`View`]: AgX, Hable's curve or the clipped
//! sRGB curve), 8 bits, tagged sRGB (an `sRGB` chunk with its `gAMA` and `cHRM` fallbacks),
//! so colour-managed viewers show them as written; RGBA with straight (unpremultiplied)
//! alpha, as PNG defines it, where the frame has transparent pixels.

use anyhow::Context;
use rayon::prelude::*;

use crate::error::Result;
use crate::view::View;

/// The PNG file of an 8-bit RGB or RGBA image, tagged sRGB.
fn encode8(width: u32, height: u32, color: png::ColorType, pixels: &[u8]) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, width, height);
    enc.set_color(color);
    enc.set_depth(png::BitDepth::Eight);
    // The image crate's defaults, which wrote every preview before the colour tag.
    enc.set_compression(png::Compression::Fast);
    enc.set_filter(png::Filter::Adaptive);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut w = enc.write_header().context("encoding PNG")?;
    w.write_image_data(pixels).context("encoding PNG")?;
    w.finish().context("encoding PNG")?;
    Ok(bytes)
}

/// The PNG file of a preview of linear RGB pixels, premultiplied by `alpha` where given:
/// `exposure`, then `view`; RGBA with the colour unpremultiplied before the view when some
/// pixel is less than opaque, else RGB. Rows go through the view in parallel on the current
/// rayon pool (each pixel's bytes depend on it alone); the compression is one stream.
pub fn encode_preview(
    width: u32,
    height: u32,
    beauty: &[[f32; 3]],
    alpha: Option<&[f32]>,
    exposure: f32,
    view: View,
) -> Result<Vec<u8>> {
    let row = (width as usize).max(1);
    let Some(alpha) = alpha.filter(|a| a.iter().any(|&v| v < 1.0)) else {
        let mut bytes = vec![0u8; beauty.len() * 3];
        bytes
            .par_chunks_mut(row * 3)
            .zip(beauty.par_chunks(row))
            .for_each(|(out, px)| {
                for (o, p) in out.chunks_exact_mut(3).zip(px) {
                    o.copy_from_slice(&view.to_8bit(*p, exposure));
                }
            });
        return encode8(width, height, png::ColorType::Rgb, &bytes);
    };
    let mut bytes = vec![0u8; beauty.len() * 4];
    bytes
        .par_chunks_mut(row * 4)
        .zip(beauty.par_chunks(row).zip(alpha.par_chunks(row)))
        .for_each(|(out, (px, al))| {
            for (o, (p, &a)) in out.chunks_exact_mut(4).zip(px.iter().zip(al)) {
                let a = a.clamp(0.0, 1.0);
                let straight = if a > 0.0 { p.map(|c| c / a) } else { [0.0; 3] };
                o[..3].copy_from_slice(&view.to_8bit(straight, exposure));
                o[3] = (a * 255.0 + 0.5) as u8;
            }
        });
    encode8(width, height, png::ColorType::Rgba, &bytes)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The chunks of a PNG file, by type.
    fn chunk_types(png: &[u8]) -> Vec<String> {
        let mut types = Vec::new();
        let mut pos = 8;
        while pos + 8 <= png.len() {
            let len = u32::from_be_bytes(png[pos..pos + 4].try_into().unwrap()) as usize;
            types.push(String::from_utf8_lossy(&png[pos + 4..pos + 8]).into_owned());
            pos += 12 + len;
        }
        types
    }

    #[test]
    fn previews_are_tagged_srgb_and_decode_to_the_view() {
        let beauty = [
            [0.0, 0.0, 0.0],
            [0.18, 0.18, 0.18],
            [1.0, 0.5, 0.25],
            [9.0, 9.0, 9.0],
        ];
        for view in View::ALL {
            let png = encode_preview(2, 2, &beauty, None, 1.0, view).unwrap();
            let types = chunk_types(&png);
            let srgb = types.iter().position(|t| t == "sRGB");
            let idat = types.iter().position(|t| t == "IDAT");
            assert!(
                srgb.is_some() && srgb < idat,
                "{view}: no sRGB chunk before the pixels: {types:?}"
            );
            let img = image::load_from_memory(&png).unwrap().to_rgb8();
            for (k, p) in img.pixels().enumerate() {
                assert_eq!(p.0, view.to_8bit(beauty[k], 1.0), "{view}: pixel {k}");
            }
        }
    }
}
