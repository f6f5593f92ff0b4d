//! Environment maps: equirectangular (lat-long) radiance over the sphere.
//!
//! Convention (OpenEXR's, ImfEnvmap.h), used for every map: +Y is up; the image centre
//! (u = 0.5) looks along +Z, u = 0.25 along +X, u = 0.75 along −X, the left/right edges along −Z;
//! row 0 is straight up. For a unit direction d: latitude = asin(d.y), longitude = atan2(d.x, d.z),
//! u = 0.5 − longitude / 2π, v = 0.5 − latitude / π. Texel (x, y) covers
//! u ∈ [x/w, (x+1)/w), v ∈ [y/h, (y+1)/h); its centre is at ((x+0.5)/w, (y+0.5)/h).
//!
//! STUB: filled in by the envmap helper.

use glam::Vec3;
use std::path::Path;

use crate::error::Result;

/// A lat-long HDR environment map, linear RGB radiance, row-major, row 0 at the top (+Y).
#[derive(Clone, Debug)]
pub struct EnvMap {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Vec3>,
    /// Where it came from: a path, or `builtin:sky`.
    pub source: String,
    /// Rotation about +Y in degrees (right-handed: +90 turns what was at +Z to +X... see `with_rotation`).
    pub rotation_deg: f32,
    /// Intensity scale already applied to `texels`.
    pub intensity: f32,
}

impl EnvMap {
    /// Loads `.exr` (full-resolution level of tiled/mip-mapped files too) or `.hdr`.
    /// NaN, Inf or negative texels are an `InputError` naming the file and the texel.
    pub fn load(_path: &Path) -> Result<EnvMap> {
        unimplemented!()
    }
    /// The built-in high-dynamic-range sky (sun plus sky), no files needed.
    pub fn builtin_sky() -> EnvMap {
        unimplemented!()
    }
    /// Rotates the map about the up axis by `degrees`.
    pub fn with_rotation(self, _degrees: f32) -> EnvMap {
        unimplemented!()
    }
    /// Scales every texel by `scale` (must be finite and ≥ 0).
    pub fn with_intensity(self, _scale: f32) -> Result<EnvMap> {
        unimplemented!()
    }
    /// Radiance seen looking along unit direction `dir` (rotation applied).
    pub fn radiance(&self, _dir: Vec3) -> Vec3 {
        unimplemented!()
    }
    /// ∫ L(ω) dω over the sphere, RGB (f64 accumulation).
    pub fn integral(&self) -> [f64; 3] {
        unimplemented!()
    }
}
