//! The built-in procedural sky (`builtin:sky`), so a render needs no map file.
//!
//! 512×256 lat-long, in the crate's convention:
//! - a sun disc of 0.75° angular radius at 35° elevation, azimuth 40° from +Z towards +X, so a
//!   camera looking towards −Z sees shadows falling back and to the left; it carries 80 % of the
//!   map's energy (its radiance is set from the sky's integral), warm white;
//! - a sky from white-blue at the horizon to deeper blue at the zenith, a little brighter
//!   around the sun;
//! - a dim brown-grey ground below the horizon (non-zero, so upward-facing shading is not black).
//!
//! The sun covers about two texels, so texels near it are supersampled (16×16, weighted by
//! cos latitude) to give the disc its exact energy.

use glam::{Vec2, Vec3};

use super::{EnvMap, luminance, uv_to_dir};

const WIDTH: usize = 512;
const HEIGHT: usize = 256;
const SUN_RADIUS_DEG: f32 = 0.75;
const SUN_ELEVATION_DEG: f32 = 35.0;
const SUN_AZIMUTH_DEG: f32 = 40.0;
/// Share of the whole map's luminance energy carried by the sun disc.
const SUN_SHARE: f64 = 0.8;
const SUN_COLOR: Vec3 = Vec3::new(1.0, 0.95, 0.86);

/// Unit direction towards the built-in sun.
pub fn sun_direction() -> Vec3 {
    let (se, ce) = libm::sincosf(SUN_ELEVATION_DEG.to_radians());
    let (sa, ca) = libm::sincosf(SUN_AZIMUTH_DEG.to_radians());
    Vec3::new(ce * sa, se, ce * ca)
}

fn sky_radiance(d: Vec3, sun: Vec3) -> Vec3 {
    if d.y >= 0.0 {
        let horizon = Vec3::new(0.95, 0.97, 1.0) * 1.1;
        let zenith = Vec3::new(0.2, 0.38, 0.9) * 0.8;
        let base = horizon.lerp(zenith, d.y.sqrt());
        // A broad glow around the sun, as real skies have.
        let glow = 1.0 + 1.5 * d.dot(sun).max(0.0).powi(16);
        base * glow
    } else {
        // Ground: dim brown-grey, a little lighter right at the horizon.
        let ground = Vec3::new(0.16, 0.13, 0.10);
        ground * (1.0 + 0.5 * (1.0 + d.y).powi(8))
    }
}

pub(super) fn builtin() -> EnvMap {
    let sun = sun_direction();
    let mut texels = vec![Vec3::ZERO; WIDTH * HEIGHT];
    let mut map = EnvMap {
        width: WIDTH,
        height: HEIGHT,
        texels: Vec::new(),
        source: "builtin:sky".to_string(),
        rotation_deg: 0.0,
        intensity: 1.0,
        warnings: Vec::new(),
    };
    let mut sky_energy = 0.0f64;
    for y in 0..HEIGHT {
        let dw = map.texel_solid_angle_f64(y);
        for x in 0..WIDTH {
            let c = sky_radiance(map.texel_dir(x, y), sun);
            sky_energy += luminance(c) as f64 * dw;
            texels[y * WIDTH + x] = c;
        }
    }
    // The sun's coverage of each texel near it, then its radiance from the energy it must carry.
    let cos_r = libm::cosf(SUN_RADIUS_DEG.to_radians());
    let texel_deg = 360.0 / WIDTH as f32;
    let near = libm::cosf((SUN_RADIUS_DEG + 3.0 * texel_deg).to_radians());
    const SUB: usize = 16;
    let mut coverage = Vec::new();
    let mut covered_solid_angle = 0.0f64;
    for y in 0..HEIGHT {
        let dw = map.texel_solid_angle_f64(y);
        for x in 0..WIDTH {
            if map.texel_dir(x, y).dot(sun) < near {
                continue;
            }
            let (mut inside, mut total) = (0.0f64, 0.0f64);
            for sy in 0..SUB {
                for sx in 0..SUB {
                    let uv = Vec2::new(
                        (x as f32 + (sx as f32 + 0.5) / SUB as f32) / WIDTH as f32,
                        (y as f32 + (sy as f32 + 0.5) / SUB as f32) / HEIGHT as f32,
                    );
                    let d = uv_to_dir(uv);
                    let w = libm::cosf(libm::asinf(d.y.clamp(-1.0, 1.0))) as f64;
                    total += w;
                    if d.dot(sun) >= cos_r {
                        inside += w;
                    }
                }
            }
            if inside > 0.0 {
                let f = inside / total;
                coverage.push((y * WIDTH + x, f));
                covered_solid_angle += f * dw;
            }
        }
    }
    let sun_energy = sky_energy * SUN_SHARE / (1.0 - SUN_SHARE);
    let sun_luminance = sun_energy / (covered_solid_angle * luminance(SUN_COLOR) as f64);
    for (i, f) in coverage {
        texels[i] += SUN_COLOR * (sun_luminance * f) as f32;
    }
    map.texels = texels;
    map
}
