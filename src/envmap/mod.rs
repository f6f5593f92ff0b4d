//! Environment maps: equirectangular (lat-long) radiance over the sphere.
//!
//! Convention (OpenEXR's, ImfEnvmap.h), used for every map: +Y is up; the image centre
//! (u = 0.5) looks along +Z, u = 0.25 along +X, u = 0.75 along −X, the left/right edges along −Z;
//! row 0 is straight up. For a unit direction d: latitude = asin(d.y), longitude = atan2(d.x, d.z),
//! u = 0.5 − longitude / 2π, v = 0.5 − latitude / π. Texel (x, y) covers
//! u ∈ [x/w, (x+1)/w), v ∈ [y/h, (y+1)/h); its centre is at ((x+0.5)/w, (y+0.5)/h).
//!
//! The convention is pinned by a test against `OrientationLatLong.exr` (tests/it/envmap.rs).
//!
//! Rotation: a map rotated by θ degrees about +Y shows, along world direction d, what the
//! unrotated map shows along R_y(−θ)·d, where R_y is the right-handed rotation about +Y
//! (R_y(90°) takes +Z to +X). So +90° moves what was seen along +Z to be seen along +X.
//! The texels are never resampled; the rotation is applied on lookup.

mod exr;
mod hdr;
mod sky;

use glam::{Vec2, Vec3};
use std::f64::consts::PI;
use std::path::Path;

use crate::bail_input;
use crate::error::Result;
use crate::limits::{Budget, MAX_FILE_BYTES, read_regular};

/// Largest accepted map, in texels (2^28: 4 GiB of f32 RGB would follow).
pub const MAX_TEXELS: usize = 1 << 28;

/// Rec.709 / sRGB luminance weights, used for every luminance in the crate.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Luminance of a linear RGB value.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(LUMINANCE)
}

/// Lat-long coordinates (u, v) ∈ [0, 1]² of a unit direction, in the map's own frame
/// (no rotation). See the module comment for the convention.
#[inline]
pub fn dir_to_uv(dir: Vec3) -> Vec2 {
    let lat = libm::asinf(dir.y.clamp(-1.0, 1.0));
    let lon = libm::atan2f(dir.x, dir.z);
    Vec2::new(
        0.5 - lon / std::f32::consts::TAU,
        0.5 - lat / std::f32::consts::PI,
    )
}

/// The unit direction at lat-long coordinates `uv`, in the map's own frame (no rotation).
#[inline]
pub fn uv_to_dir(uv: Vec2) -> Vec3 {
    let lon = (0.5 - uv.x) * std::f32::consts::TAU;
    let lat = (0.5 - uv.y) * std::f32::consts::PI;
    let (sl, cl) = libm::sincosf(lat);
    let (so, co) = libm::sincosf(lon);
    Vec3::new(cl * so, sl, cl * co)
}

/// Right-handed rotation about +Y by the angle with the given (sin, cos): +Z goes to +X at 90°.
#[inline]
pub fn rotate_y(d: Vec3, (s, c): (f32, f32)) -> Vec3 {
    Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

/// A lat-long HDR environment map, linear RGB radiance, row-major, row 0 at the top (+Y).
#[derive(Clone, Debug)]
pub struct EnvMap {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Vec3>,
    /// Where it came from: a path, or `builtin:sky`.
    pub source: String,
    /// Rotation about +Y in degrees (right-handed: +90 turns what was seen along +Z to be seen
    /// along +X; see the module comment and [`EnvMap::with_rotation`]).
    pub rotation_deg: f32,
    /// Intensity scale already applied to `texels`.
    pub intensity: f32,
    /// What loading changed (texels clamped to [`MAX_RADIANCE`]), for the run's warnings.
    pub warnings: Vec<String>,
}

/// Brightest texel a map may have. [ours] The sun's disc in absolute units is about 1.6e9;
/// a Radiance texel of exponent 255 is 1.7e38, whose sums overflow f32 into infinite pixels.
pub const MAX_RADIANCE: f32 = 1e12;

impl EnvMap {
    /// Loads `.exr` (full-resolution level of tiled/mip-mapped files too) or `.hdr`.
    /// NaN, Inf or negative texels are an `InputError` naming the file and the texel. Only a
    /// regular file is read; the size its header declares is checked against the memory budget
    /// ([`Budget`]) before its pixels are decoded.
    pub fn load(path: &Path) -> Result<EnvMap> {
        EnvMap::load_within(path, &mut Budget::default())
    }

    /// [`EnvMap::load`] against a render's `budget`, which then counts the map.
    pub fn load_within(path: &Path, budget: &mut Budget) -> Result<EnvMap> {
        format_of(path)?;
        check_readable(path)?;
        let bytes = read_regular(path, MAX_FILE_BYTES)
            .map_err(|e| e.into_error(path, "environment map"))?;
        EnvMap::decode_within(&bytes, path, budget)
    }

    /// Decodes a map file's bytes; `path` names it in errors and its extension gives the format.
    pub fn decode(bytes: &[u8], path: &Path) -> Result<EnvMap> {
        EnvMap::decode_within(bytes, path, &mut Budget::default())
    }

    /// [`EnvMap::decode`] against `budget`, which then counts the map.
    pub fn decode_within(bytes: &[u8], path: &Path, budget: &mut Budget) -> Result<EnvMap> {
        let (width, height, texels) = match format_of(path)? {
            Format::Exr => exr::decode(bytes, path, budget)?,
            Format::Hdr => hdr::decode(bytes, path, budget)?,
        };
        EnvMap::from_texels(width, height, texels, &path.display().to_string())
    }

    /// The texels a map file declares and the file's length, from its header alone (without
    /// reading its pixels); `None` if that cannot be read, which [`EnvMap::load`] then reports.
    pub fn declared_size(path: &Path) -> Option<(u64, u64)> {
        let format = format_of(path).ok()?;
        let m = std::fs::metadata(path).ok()?;
        // Not a device or a FIFO: reading one would not end, or block.
        if !m.is_file() {
            return None;
        }
        let file = std::io::BufReader::new(std::fs::File::open(path).ok()?);
        let texels = match format {
            Format::Hdr => {
                use image::ImageDecoder;
                let (w, h) = image::codecs::hdr::HdrDecoder::new(file).ok()?.dimensions();
                u64::from(w) * u64::from(h)
            }
            Format::Exr => ::exr::meta::MetaData::read_from_buffered(file, false)
                .ok()?
                .headers
                .iter()
                .map(|h| h.layer_size.0 as u64 * h.layer_size.1 as u64)
                .max()?,
        };
        Some((texels, m.len()))
    }

    /// A map from texels in memory (row-major, row 0 at the top), validated like a file:
    /// non-empty, `texels.len() == width * height`, every texel finite and ≥ 0.
    /// `source` names it in errors and in the lights JSON.
    pub fn from_texels(
        width: usize,
        height: usize,
        texels: Vec<Vec3>,
        source: &str,
    ) -> Result<EnvMap> {
        check_size(source, width, height)?;
        if texels.len() != width * height {
            bail_input!(
                source,
                "{} texels given for a {width}×{height} map",
                texels.len()
            );
        }
        for (i, t) in texels.iter().enumerate() {
            let bad = if t.is_nan() {
                Some("NaN")
            } else if !t.is_finite() {
                Some("infinite")
            } else if t.min_element() < 0.0 {
                Some("negative")
            } else {
                None
            };
            if let Some(what) = bad {
                bail_input!(
                    source,
                    "texel ({}, {}) has {what} radiance ({}, {}, {})",
                    i % width,
                    i / width,
                    t.x,
                    t.y,
                    t.z
                );
            }
        }
        let mut texels = texels;
        let mut warnings = Vec::new();
        let bright = clamp_radiance(&mut texels);
        if bright > 0 {
            warnings.push(format!(
                "{}: {bright} texel{} brighter than {MAX_RADIANCE:e} clamped to it",
                crate::error::escaped(source),
                if bright == 1 { "" } else { "s" }
            ));
        }
        Ok(EnvMap {
            width,
            height,
            texels,
            source: source.to_string(),
            rotation_deg: 0.0,
            intensity: 1.0,
            warnings,
        })
    }

    /// The built-in high-dynamic-range sky (sun plus sky), no files needed. See [`sky`] for
    /// what it contains: 512×256, a 0.75°-radius sun at 35° elevation towards (+X, +Z) carrying
    /// most of the energy, a blue-to-white sky and a dim brown-grey ground.
    pub fn builtin_sky() -> EnvMap {
        sky::builtin()
    }

    /// Rotates the map about the up axis by `degrees` (replacing any earlier rotation).
    /// +90 moves what was seen along +Z to be seen along +X. Texels are not resampled.
    pub fn with_rotation(mut self, degrees: f32) -> EnvMap {
        self.rotation_deg = degrees;
        self
    }

    /// Scales every texel by `scale` (must be finite and ≥ 0).
    pub fn with_intensity(mut self, scale: f32) -> Result<EnvMap> {
        if !scale.is_finite() || scale < 0.0 {
            bail_input!(
                "intensity",
                "must be a finite number ≥ 0, got {scale} (for {})",
                self.source
            );
        }
        for t in &mut self.texels {
            *t *= scale;
        }
        self.intensity *= scale;
        Ok(self)
    }

    /// (sin, cos) of the rotation.
    #[inline]
    fn rot(&self) -> (f32, f32) {
        libm::sincosf(self.rotation_deg.to_radians())
    }

    /// A direction in the map's own frame turned into world space (the rotation applied).
    #[inline]
    pub fn to_world(&self, map_dir: Vec3) -> Vec3 {
        rotate_y(map_dir, self.rot())
    }

    /// A world direction turned into the map's own frame (the rotation undone).
    #[inline]
    pub fn to_map(&self, world_dir: Vec3) -> Vec3 {
        let (s, c) = self.rot();
        rotate_y(world_dir, (-s, c))
    }

    /// World direction (rotation applied) of the centre of texel (x, y).
    pub fn texel_dir(&self, x: usize, y: usize) -> Vec3 {
        let uv = Vec2::new(
            (x as f32 + 0.5) / self.width as f32,
            (y as f32 + 0.5) / self.height as f32,
        );
        rotate_y(uv_to_dir(uv), self.rot())
    }

    /// Exact solid angle of a texel in row `y`: Δφ · (sin lat_top − sin lat_bottom).
    pub fn texel_solid_angle(&self, y: usize) -> f32 {
        self.texel_solid_angle_f64(y) as f32
    }

    /// [`EnvMap::texel_solid_angle`] in f64, for sums.
    pub fn texel_solid_angle_f64(&self, y: usize) -> f64 {
        let h = self.height as f64;
        let lat_top = PI * (0.5 - y as f64 / h);
        let lat_bottom = PI * (0.5 - (y as f64 + 1.0) / h);
        (2.0 * PI / self.width as f64) * (libm::sin(lat_top) - libm::sin(lat_bottom))
    }

    /// Texel (x, y).
    #[inline]
    pub fn texel(&self, x: usize, y: usize) -> Vec3 {
        self.texels[y * self.width + x]
    }

    /// Radiance seen looking along unit direction `dir` (rotation applied): bilinear between
    /// texel centres, wrapping in longitude and clamping at the poles.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let uv = dir_to_uv(self.to_map(dir));
        let fx = uv.x * self.width as f32 - 0.5;
        let fy = uv.y * self.height as f32 - 0.5;
        let x0f = fx.floor();
        let y0f = fy.floor();
        let tx = fx - x0f;
        let ty = fy - y0f;
        let w = self.width as i64;
        let h = self.height as i64;
        let x0 = (x0f as i64).rem_euclid(w) as usize;
        let x1 = (x0f as i64 + 1).rem_euclid(w) as usize;
        let y0 = (y0f as i64).clamp(0, h - 1) as usize;
        let y1 = (y0f as i64 + 1).clamp(0, h - 1) as usize;
        let top = self.texel(x0, y0).lerp(self.texel(x1, y0), tx);
        let bottom = self.texel(x0, y1).lerp(self.texel(x1, y1), tx);
        top.lerp(bottom, ty)
    }

    /// ∫ L(ω) dω over the sphere, RGB (f64 accumulation).
    pub fn integral(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for y in 0..self.height {
            let mut row = [0.0f64; 3];
            for t in &self.texels[y * self.width..(y + 1) * self.width] {
                row[0] += t.x as f64;
                row[1] += t.y as f64;
                row[2] += t.z as f64;
            }
            let dw = self.texel_solid_angle_f64(y);
            for k in 0..3 {
                sum[k] += row[k] * dw;
            }
        }
        sum
    }

    /// A one-line description for logs and JSON: source, rotation and intensity.
    pub fn describe(&self) -> String {
        format!(
            "{} (rotation {}°, intensity {})",
            self.source, self.rotation_deg, self.intensity
        )
    }
}

/// Clamps every channel to [`MAX_RADIANCE`]; returns how many texels it changed.
fn clamp_radiance(texels: &mut [Vec3]) -> usize {
    let mut changed = 0;
    for t in texels {
        if t.max_element() > MAX_RADIANCE {
            *t = t.min(Vec3::splat(MAX_RADIANCE));
            changed += 1;
        }
    }
    changed
}

/// Missing files and folders get a plain message instead of a decoder's.
enum Format {
    Exr,
    Hdr,
}

/// The map's format, from its file extension.
fn format_of(path: &Path) -> Result<Format> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("exr") => Ok(Format::Exr),
        Some("hdr") => Ok(Format::Hdr),
        Some(other) => bail_input!(
            path,
            "unsupported environment map format '.{other}' (expected .exr or .hdr)"
        ),
        None => bail_input!(
            path,
            "environment map has no file extension (expected .exr or .hdr)"
        ),
    }
}

/// A missing map gets a plain message; anything else that is not a regular file is refused by
/// the reader.
fn check_readable(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(_) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            bail_input!(path, "environment map not found")
        }
        Err(e) => bail_input!(path, "cannot read environment map: {e}"),
    }
}

/// The most decoded bytes one byte of a map file is taken to hold: above deflate's ~1032:1
/// and what RLE, PIZ or B44 reach on a constant image.
const MAX_EXPANSION: usize = 4096;

/// A header may declare a size its file cannot hold: a few hundred bytes claiming 2^28 texels
/// would make us allocate gigabytes before the decoder finds the data missing (found by fuzzing:
/// tests/data/fuzz/envmap_exr/). Refused unless the file could hold that many texels at
/// `MAX_EXPANSION`:1 (at least half-float RGB, 6 bytes a texel); small maps always pass.
fn check_plausible(path: &Path, width: usize, height: usize, file_bytes: usize) -> Result<()> {
    let decoded = width.saturating_mul(height).saturating_mul(6);
    let room = file_bytes.saturating_mul(MAX_EXPANSION).max(16 << 20);
    if decoded > room {
        bail_input!(
            path,
            "the header declares {width}×{height} texels (about {} of memory to load), more than a {file_bytes}-byte file can hold (truncated or broken header)",
            crate::limits::human_bytes_u128(crate::limits::map_bytes(width as u64 * height as u64))
        );
    }
    Ok(())
}

/// Zero and absurd sizes are refused before anything is allocated.
fn check_size(source: impl AsRef<Path>, width: usize, height: usize) -> Result<()> {
    if width == 0 || height == 0 {
        bail_input!(source, "environment map has zero size ({width}×{height})");
    }
    if width.checked_mul(height).is_none_or(|n| n > MAX_TEXELS) {
        bail_input!(
            source,
            "environment map is too large ({width}×{height}; at most {MAX_TEXELS} texels)"
        );
    }
    Ok(())
}
