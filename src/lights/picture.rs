//! A PNG for eyes: the tone-mapped map with the light cells' borders and the lights on it.

use glam::Vec2;
use std::path::Path;

use super::LightSet;
use crate::envmap::{EnvMap, dir_to_uv, luminance, uv_to_dir};
use crate::error::Result;

/// Cell borders.
const BORDER: [u8; 3] = [255, 0, 255];

fn srgb(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * libm::powf(v, 1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// Writes a PNG of `env` in world orientation (lat-long, the crate's convention) at the map's
/// resolution, upscaled to at least 1024 wide: the map tone-mapped so its 99th-percentile
/// luminance shows as 1 (sRGB), cell borders in magenta (pixels whose right or lower neighbour
/// is in another cell), and each light as a cross with a black outline, yellow for the dimmest
/// to red for the most energetic, larger with more energy. Written atomically.
pub fn cells_png(env: &EnvMap, lights: &LightSet, path: &Path) -> Result<()> {
    let scale = 1024usize.div_ceil(env.width).max(1);
    let (w, h) = (env.width * scale, env.height * scale);
    let mut lum: Vec<f32> = env.texels.iter().map(|&t| luminance(t)).collect();
    lum.sort_unstable_by(f32::total_cmp);
    let p99 = lum[((lum.len() - 1) as f64 * 0.99) as usize];
    let exposure = if p99 > 0.0 {
        1.0 / p99
    } else if lum[lum.len() - 1] > 0.0 {
        1.0 / lum[lum.len() - 1]
    } else {
        1.0
    };
    let dir_at = |x: usize, y: usize| {
        uv_to_dir(Vec2::new(
            (x as f32 + 0.5) / w as f32,
            (y as f32 + 0.5) / h as f32,
        ))
    };
    let mut cells = vec![0u32; w * h];
    let mut rgb = vec![0u8; w * h * 3];
    for y in 0..h {
        for x in 0..w {
            let d = dir_at(x, y);
            cells[y * w + x] = if lights.is_empty() {
                0
            } else {
                lights.cell_of(d)
            };
            let c = env.radiance(d) * exposure;
            rgb[(y * w + x) * 3..][..3].copy_from_slice(&[srgb(c.x), srgb(c.y), srgb(c.z)]);
        }
    }
    for y in 0..h {
        for x in 0..w {
            let c = cells[y * w + x];
            let right = cells[y * w + (x + 1) % w];
            let down = if y + 1 < h { cells[(y + 1) * w + x] } else { c };
            if right != c || down != c {
                rgb[(y * w + x) * 3..][..3].copy_from_slice(&BORDER);
            }
        }
    }
    let max_energy = lights
        .lights
        .iter()
        .map(|l| luminance(l.energy))
        .fold(0.0f32, f32::max);
    let mut put = |x: i64, y: i64, c: [u8; 3]| {
        if y >= 0 && (y as usize) < h {
            let x = x.rem_euclid(w as i64) as usize;
            rgb[(y as usize * w + x) * 3..][..3].copy_from_slice(&c);
        }
    };
    for l in &lights.lights {
        let f = if max_energy > 0.0 {
            (luminance(l.energy) / max_energy).clamp(0.0, 1.0).sqrt()
        } else {
            0.0
        };
        let colour = [255, (255.0 * (1.0 - f)) as u8, 0];
        let arm = 2 + (4.0 * f).round() as i64;
        let uv = dir_to_uv(l.dir);
        let cx = (uv.x * w as f32) as i64;
        let cy = (uv.y * h as f32) as i64;
        for pass in 0..2 {
            for t in -arm..=arm {
                if pass == 0 {
                    // Outline first, so the cross reads on any background.
                    for o in [-1, 1] {
                        put(cx + t, cy + o, [0, 0, 0]);
                        put(cx + o, cy + t, [0, 0, 0]);
                    }
                } else {
                    put(cx + t, cy, colour);
                    put(cx, cy + t, colour);
                }
            }
        }
    }
    let mut bytes = Vec::new();
    image::RgbImage::from_raw(w as u32, h as u32, rgb)
        .expect("buffer matches the image size")
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )?;
    crate::output::write_atomic(path, &bytes)
}
