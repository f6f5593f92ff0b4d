//! Texture decoding (sRGB → linear at load, or linear data as it is), the mip pyramid, and
//! sampling with a glTF sampler's wrap modes and filters.
//!
//! Determinism: the pyramid and the samplers use only + − × ÷, floor and `libm` (pure Rust),
//! never the host's libm, so every host gets the same bits.

use glam::{Vec2, Vec3, Vec4};
use image::ImageDecoder;

use super::Texture;

/// How a texture's colour channels are encoded: base colour and emissive textures are sRGB,
/// the others (metallic-roughness, normal, occlusion, specular) linear data (glTF 2.0 §3.9).
/// Alpha is linear in both.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Encoding {
    Srgb,
    Linear,
}

/// How a coordinate outside [0, 1] is brought back (glTF's `wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The texture tiles (GL `REPEAT`, glTF's default).
    #[default]
    Repeat,
    /// The edge texels extend (GL `CLAMP_TO_EDGE`).
    Clamp,
    /// Every other tile is mirrored (GL `MIRRORED_REPEAT`).
    Mirror,
}

/// A glTF sampler as the renderer uses it: the wrap mode per axis, whether magnification is
/// nearest-texel (else bilinear), and whether minification uses the mip pyramid (glTF's
/// `*_MIPMAP_*` minification filters, and no filter given: the default) or level 0 only.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    pub mag_nearest: bool,
    pub mipmaps: bool,
}

impl Default for Sampler {
    /// Repeat on both axes, bilinear, mip-mapped: what the renderer did before samplers, and
    /// glTF's default sampler.
    fn default() -> Sampler {
        Sampler {
            wrap_s: Wrap::Repeat,
            wrap_t: Wrap::Repeat,
            mag_nearest: false,
            mipmaps: true,
        }
    }
}

/// The sRGB electro-optical transfer function: an sRGB-encoded value in [0, 1] to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        libm::powf((c + 0.055) / 1.055, 2.4)
    }
}

/// One level of a texture's pyramid: linear RGB texels, row-major, row 0 at the top, and the
/// alpha of each texel when the image had an alpha channel (empty when it had none: opaque).
#[derive(Clone, Debug)]
pub(super) struct Level {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
    alpha: Vec<f32>,
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
        Texture::from_linear(width, height, texels)
    }

    /// A texture from linear RGB texels (row-major, row 0 at the top), used as given.
    /// `None` if `texels` does not hold `width × height` texels.
    pub fn from_linear(width: usize, height: usize, texels: Vec<Vec3>) -> Option<Texture> {
        if width.checked_mul(height)? != texels.len() {
            return None;
        }
        // Small textures made in memory: a refused pyramid level would be a bug's, not an
        // input's; decoded ones go through `try_from_linear`.
        Texture::try_from_linear(width, height, texels, Vec::new()).ok()
    }

    /// A texture from linear RGB texels and their alpha (row-major, row 0 at the top), used
    /// as given. `None` if either does not hold `width × height` values.
    pub fn from_linear_alpha(
        width: usize,
        height: usize,
        texels: Vec<Vec3>,
        alpha: Vec<f32>,
    ) -> Option<Texture> {
        let n = width.checked_mul(height)?;
        if n != texels.len() || n != alpha.len() {
            return None;
        }
        Texture::try_from_linear(width, height, texels, alpha).ok()
    }

    /// [`Texture::from_linear`] for a size already checked, with each pyramid level asked of
    /// the system before it is filled.
    fn try_from_linear(
        width: usize,
        height: usize,
        texels: Vec<Vec3>,
        alpha: Vec<f32>,
    ) -> Result<Texture, crate::limits::NoMemory> {
        debug_assert_eq!(width * height, texels.len());
        debug_assert!(alpha.is_empty() || alpha.len() == texels.len());
        let mut levels = vec![Level {
            width,
            height,
            texels,
            alpha,
        }];
        if width > 0 && height > 0 {
            while let Some(next) = levels.last().and_then(Level::half).transpose()? {
                levels.push(next);
            }
        }
        Ok(Texture {
            levels: levels.into(),
        })
    }

    /// The size an encoded image (PNG or JPEG) declares, read from its header without decoding
    /// it. Images over [`crate::limits::MAX_TEXTURE_TEXELS`] or 16384 on a side are refused.
    pub fn dimensions(bytes: &[u8]) -> Result<(u32, u32), image::ImageError> {
        let (w, h) = reader(bytes)?.into_dimensions()?;
        if u64::from(w) * u64::from(h) > crate::limits::MAX_TEXTURE_TEXELS {
            return Err(image::ImageError::Limits(
                image::error::LimitError::from_kind(image::error::LimitErrorKind::DimensionError),
            ));
        }
        Ok((w, h))
    }

    /// [`dimensions`](Self::dimensions), and whether the image has an alpha channel (which the
    /// texture keeps), from the header alone: no pixel is decoded or allocated.
    pub fn header(bytes: &[u8]) -> Result<(u32, u32, bool), image::ImageError> {
        let (w, h) = Texture::dimensions(bytes)?;
        let alpha = reader(bytes)?.into_decoder()?.color_type().has_alpha();
        Ok((w, h, alpha))
    }

    /// Decodes an encoded image (PNG or JPEG) to a linear texture, treating it as sRGB:
    /// [`decode_as`](Self::decode_as) with [`Encoding::Srgb`].
    pub fn decode(bytes: &[u8]) -> crate::error::Result<Texture> {
        Texture::decode_as(bytes, Encoding::Srgb)
    }

    /// Decodes an encoded image (PNG or JPEG) to a linear texture: its colour channels sRGB
    /// decoded, or taken as they are for [`Encoding::Linear`] data; its alpha, if it has one,
    /// kept (linear). 16-bit images are decoded from their full precision.
    /// Images over [`crate::limits::MAX_TEXTURE_TEXELS`] or 16384 on a side are refused before
    /// their pixels are allocated ([`Texture::dimensions`]).
    ///
    /// Errors: the decoder's [`image::ImageError`], or [`crate::limits::NoMemory`] when the
    /// system refuses a buffer (the decoder's pixels, the texels, a pyramid level): each is
    /// asked for before it is filled, so a refusal is an error rather than an abort.
    pub fn decode_as(bytes: &[u8], encoding: Encoding) -> crate::error::Result<Texture> {
        let (w, h) = Texture::dimensions(bytes)?;
        let decoder = reader(bytes)?.into_decoder()?;
        let color = decoder.color_type();
        let total = decoder.total_bytes();
        if total > crate::limits::MAX_TEXTURE_TEXELS * 8 {
            return Err(
                image::ImageError::Limits(image::error::LimitError::from_kind(
                    image::error::LimitErrorKind::InsufficientMemory,
                ))
                .into(),
            );
        }
        let mut pixels = crate::limits::try_zeroed(total as usize, "an image's pixels")?;
        decoder.read_image(&mut pixels)?;
        let n = w as usize * h as usize;
        let mut texels = crate::limits::try_vec(n, "a texture's texels")?;
        let mut alpha = if color.has_alpha() {
            crate::limits::try_vec(n, "a texture's alpha")?
        } else {
            Vec::new()
        };
        if !linear_texels(color, encoding, &pixels, &mut texels, &mut alpha)
            || texels.len() != n
            || !(alpha.is_empty() || alpha.len() == n)
        {
            return Err(
                image::ImageError::Parameter(image::error::ParameterError::from_kind(
                    image::error::ParameterErrorKind::DimensionMismatch,
                ))
                .into(),
            );
        }
        // The decoder's pixels are gone before the pyramid is built: a lower peak.
        drop(pixels);
        Ok(Texture::try_from_linear(
            w as usize, h as usize, texels, alpha,
        )?)
    }

    /// Width in texels (of level 0).
    pub fn width(&self) -> usize {
        self.levels[0].width
    }

    /// Height in texels (of level 0).
    pub fn height(&self) -> usize {
        self.levels[0].height
    }

    /// The `width × height` linear RGB texels of level 0, row 0 first.
    pub fn texels(&self) -> &[Vec3] {
        &self.levels[0].texels
    }

    /// The alpha of level 0's texels, row 0 first; empty for an image without alpha.
    pub fn alpha(&self) -> &[f32] {
        &self.levels[0].alpha
    }

    /// Whether the image had an alpha channel (else every texel is opaque: alpha 1).
    pub fn has_alpha(&self) -> bool {
        !self.levels[0].alpha.is_empty()
    }

    /// Number of pyramid levels: 1 + ⌊log2(max(width, height))⌋, or 1 for an empty texture.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// `(width, height)` of pyramid level `k` (level 0 is the texture itself).
    ///
    /// # Panics
    /// If `k >= level_count()`.
    pub fn level_size(&self, k: usize) -> (usize, usize) {
        (self.levels[k].width, self.levels[k].height)
    }

    /// Bilinear sample at `uv` with repeat wrap: texel `(i, j)` covers
    /// `u ∈ [i/w, (i+1)/w)`, `v ∈ [j/h, (j+1)/h)` (v down, row 0 at the top), and its exact
    /// colour is returned at its centre. Returns white for an empty texture and texel (0, 0)'s
    /// neighbourhood for non-finite `uv`.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        self.levels[0].bilinear(uv, REPEAT)
    }

    /// The texture filtered over a footprint `footprint` wide in UV units (1 = the whole
    /// texture), centred at `uv`: trilinear, i.e. [`sample`](Self::sample)'s bilinear lookup in
    /// the two pyramid levels nearest to level `log2(footprint × max(width, height))`, blended
    /// by its fraction. The level is clamped to the last (1 × 1, the texture's mean).
    ///
    /// A footprint of at most one texel (`footprint × max(width, height) ≤ 1`), zero, negative
    /// or NaN gives exactly [`sample`](Self::sample)`(uv)`, bit for bit; an infinite one the
    /// last level. Wrapping and non-finite `uv` as in `sample`.
    pub fn sample_footprint(&self, uv: Vec2, footprint: f32) -> Vec3 {
        let base = &self.levels[0];
        let texels = footprint * base.width.max(base.height) as f32;
        if texels.is_nan() || texels <= 1.0 || self.levels.len() == 1 {
            return self.sample(uv);
        }
        let last = (self.levels.len() - 1) as f32;
        let level = libm::log2f(texels).max(0.0).min(last);
        let n = level.floor();
        let t = level - n;
        let n = n as usize;
        let fine = self.levels[n].bilinear(uv, REPEAT);
        if t == 0.0 {
            fine
        } else {
            fine.lerp(self.levels[n + 1].bilinear(uv, REPEAT), t)
        }
    }

    /// The texture as a glTF `sampler` reads it at `uv`, filtered over a footprint
    /// `footprint` wide in UV units: RGB and alpha (1 without an alpha channel).
    ///
    /// With the default sampler (repeat, bilinear, mip-mapped) the colour is exactly
    /// [`sample_footprint`](Self::sample_footprint)'s, bit for bit. A footprint of at most one
    /// texel magnifies: bilinear at level 0, or the nearest texel for a `NEAREST` magnification
    /// filter. A larger one minifies: trilinear over the pyramid, or bilinear at level 0 for a
    /// minification filter without mipmaps. Wrapping per axis as the sampler says.
    pub fn lookup(&self, uv: Vec2, footprint: f32, sampler: &Sampler) -> Vec4 {
        let wrap = (sampler.wrap_s, sampler.wrap_t);
        let base = &self.levels[0];
        let texels = footprint * base.width.max(base.height) as f32;
        let magnified = texels.is_nan() || texels <= 1.0 || self.levels.len() == 1;
        if magnified && sampler.mag_nearest {
            return base.nearest(uv, wrap);
        }
        if magnified || !sampler.mipmaps {
            return base.bilinear4(uv, wrap);
        }
        let last = (self.levels.len() - 1) as f32;
        let level = libm::log2f(texels).max(0.0).min(last);
        let n = level.floor();
        let t = level - n;
        let n = n as usize;
        let fine = self.levels[n].bilinear4(uv, wrap);
        if t == 0.0 {
            fine
        } else {
            fine.lerp(self.levels[n + 1].bilinear4(uv, wrap), t)
        }
    }
}

impl Texture {
    /// The alpha [`lookup`](Self::lookup) gives at `uv` with a zero footprint (level 0:
    /// bilinear, or the nearest texel for a `NEAREST` magnification filter), without the
    /// colour: what the alpha test reads ([`super::Scene::alpha`]). 1 without an alpha channel.
    pub fn alpha_at(&self, uv: Vec2, sampler: &Sampler) -> f32 {
        let base = &self.levels[0];
        if base.alpha.is_empty() || !base.readable() {
            return 1.0;
        }
        let wrap = (sampler.wrap_s, sampler.wrap_t);
        if sampler.mag_nearest {
            return base.alpha[base.nearest_index(uv, wrap)];
        }
        let Taps4 { at, fx, fy } = base.taps(uv, wrap);
        base.bilinear_alpha(at, fx, fy)
    }
}

/// Repeat on both axes.
const REPEAT: (Wrap, Wrap) = (Wrap::Repeat, Wrap::Repeat);

impl Wrap {
    /// A texture coordinate brought into [0, 1] (repeat: its fraction, first, so that large
    /// coordinates keep their precision; clamp: clamped; mirror: folded over a period of 2).
    #[inline]
    fn coordinate(self, u: f32) -> f32 {
        match self {
            Wrap::Repeat => u.rem_euclid(1.0),
            Wrap::Clamp => u.clamp(0.0, 1.0),
            Wrap::Mirror => {
                let t = u.rem_euclid(2.0);
                if t > 1.0 { 2.0 - t } else { t }
            }
        }
    }

    /// A texel index `i` (one beyond either edge at most, as a bilinear footprint reaches)
    /// brought into `0..n`.
    #[inline]
    fn index(self, i: i64, n: usize) -> usize {
        let n = n as i64;
        let i = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            // Period 2n: the mirrored copy reads n−1 … 0.
            Wrap::Mirror => {
                let t = i.rem_euclid(2 * n);
                if t >= n { 2 * n - 1 - t } else { t }
            }
        };
        i as usize
    }
}

/// An image reader for `bytes`, its format guessed from them, with the texture limits: at most
/// 16384 a side, and the decoder's own buffers at most 8 bytes (RGBA16) per allowed texel.
fn reader(bytes: &[u8]) -> image::ImageResult<image::ImageReader<std::io::Cursor<&[u8]>>> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(crate::limits::MAX_DIM);
    limits.max_image_height = Some(crate::limits::MAX_DIM);
    limits.max_alloc = Some(crate::limits::MAX_TEXTURE_TEXELS * 8);
    reader.limits(limits);
    Ok(reader)
}

/// Appends the linear RGB texels of decoded `pixels` of colour type `color` (native-endian
/// samples, as the decoder wrote them) to `out`: samples scaled to [0, 1] exactly as the
/// `image` crate's `to_rgb32f` does (the textures are then the same bits as when it decoded
/// them, without its second copy of every pixel), grey copied to R, G and B; then sRGB
/// decoded, unless `encoding` is linear. The alpha channel, if the colour type has one, goes
/// to `alpha` as it is (scaled to [0, 1]). `false` for a colour type it does not know.
fn linear_texels(
    color: image::ColorType,
    encoding: Encoding,
    pixels: &[u8],
    out: &mut Vec<Vec3>,
    alpha: &mut Vec<f32>,
) -> bool {
    use image::ColorType as C;
    let (size, channels) = match color {
        C::L8 | C::La8 | C::Rgb8 | C::Rgba8 => (1, color.channel_count() as usize),
        C::L16 | C::La16 | C::Rgb16 | C::Rgba16 => (2, color.channel_count() as usize),
        C::Rgb32F | C::Rgba32F => (4, color.channel_count() as usize),
        _ => return false,
    };
    // RGB(A) samples are divided by the largest value and clamped; grey ones multiplied by its
    // reciprocal (the crate's colour-space path), which rounds differently for some values.
    let sample = |b: &[u8]| match size {
        1 => (f32::from(b[0]) / 255.0).clamp(0.0, 1.0),
        2 => (f32::from(u16::from_ne_bytes([b[0], b[1]])) / 65535.0).clamp(0.0, 1.0),
        _ => f32::from_ne_bytes([b[0], b[1], b[2], b[3]]),
    };
    let grey = |b: &[u8]| match size {
        1 => f32::from(b[0]) * (1.0 / 255.0),
        2 => f32::from(u16::from_ne_bytes([b[0], b[1]])) * (1.0 / 65535.0),
        _ => f32::from_ne_bytes([b[0], b[1], b[2], b[3]]),
    };
    // sRGB decoding of integer samples by table: one `powf` per possible value rather than per
    // sample (a 4096 × 4096 texture has 50 million; under the fuzzer's sanitizer that took
    // 46 s), the same bits as decoding each sample. Only where the image has more samples than
    // the table has entries.
    let values = if size <= 2 { 1usize << (8 * size) } else { 0 };
    let index = |b: &[u8]| match size {
        1 => usize::from(b[0]),
        _ => usize::from(u16::from_ne_bytes([b[0], b[1]])),
    };
    let table: Vec<f32> =
        if encoding == Encoding::Srgb && values > 0 && pixels.len() / size > values {
            (0..values)
                .map(|v| {
                    let b = if size == 1 {
                        [v as u8, 0]
                    } else {
                        (v as u16).to_ne_bytes()
                    };
                    srgb_to_linear(if channels < 3 { grey(&b) } else { sample(&b) })
                })
                .collect()
        } else {
            Vec::new()
        };
    let has_alpha = color.has_alpha();
    for p in pixels.chunks_exact(size * channels) {
        let linear = match (table.is_empty(), channels < 3) {
            (false, true) => Vec3::splat(table[index(p)]),
            (false, false) => Vec3::new(
                table[index(p)],
                table[index(&p[size..])],
                table[index(&p[2 * size..])],
            ),
            (true, true) => Vec3::splat(grey(p)),
            (true, false) => Vec3::new(sample(p), sample(&p[size..]), sample(&p[2 * size..])),
        };
        out.push(match (encoding, table.is_empty()) {
            (Encoding::Srgb, true) => linear.map(srgb_to_linear),
            _ => linear,
        });
        if has_alpha {
            // Coverage: [0, 1] (a float image may hold more).
            alpha.push(sample(&p[(channels - 1) * size..]).clamp(0.0, 1.0));
        }
    }
    true
}

/// The four texels a bilinear lookup reads (row-major indices: top left, top right, bottom
/// left, bottom right) and the blend weights across and down.
struct Taps4 {
    at: [usize; 4],
    fx: f32,
    fy: f32,
}

impl Level {
    /// Whether the level has texels to read (an empty texture reads as white).
    fn readable(&self) -> bool {
        self.width > 0 && self.height > 0 && self.texels.len() >= self.width * self.height
    }

    /// The taps of a bilinear lookup at `uv`: texel `(i, j)` covers `u ∈ [i/w, (i+1)/w)`,
    /// `v ∈ [j/h, (j+1)/h)` and is exact at its centre. Non-finite `uv` reads at (0, 0).
    #[inline]
    fn taps(&self, uv: Vec2, (ws, wt): (Wrap, Wrap)) -> Taps4 {
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        // Wrap first so large coordinates keep their precision in the fraction.
        let x = ws.coordinate(uv.x) * self.width as f32 - 0.5;
        let y = wt.coordinate(uv.y) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let (xa, xb) = (ws.index(x0, self.width), ws.index(x0 + 1, self.width));
        let (ya, yb) = (wt.index(y0, self.height), wt.index(y0 + 1, self.height));
        let w = self.width;
        Taps4 {
            at: [ya * w + xa, ya * w + xb, yb * w + xa, yb * w + xb],
            fx,
            fy,
        }
    }

    /// [`Texture::sample`] on this level, wrapped by `wrap`.
    fn bilinear(&self, uv: Vec2, wrap: (Wrap, Wrap)) -> Vec3 {
        if !self.readable() {
            return Vec3::ONE;
        }
        let Taps4 { at, fx, fy } = self.taps(uv, wrap);
        let t = |k: usize| self.texels[at[k]];
        let top = t(0).lerp(t(1), fx);
        let bottom = t(2).lerp(t(3), fx);
        top.lerp(bottom, fy)
    }

    /// [`bilinear`](Self::bilinear) with the alpha beside it (1 where there is none): the
    /// colour is the same bits.
    fn bilinear4(&self, uv: Vec2, wrap: (Wrap, Wrap)) -> Vec4 {
        if !self.readable() {
            return Vec4::ONE;
        }
        let Taps4 { at, fx, fy } = self.taps(uv, wrap);
        let t = |k: usize| self.texels[at[k]];
        let rgb = t(0).lerp(t(1), fx).lerp(t(2).lerp(t(3), fx), fy);
        let alpha = if self.alpha.is_empty() {
            1.0
        } else {
            self.bilinear_alpha(at, fx, fy)
        };
        rgb.extend(alpha)
    }

    /// The alpha of a bilinear lookup's taps (the level has alpha).
    #[inline]
    fn bilinear_alpha(&self, at: [usize; 4], fx: f32, fy: f32) -> f32 {
        let a = |k: usize| self.alpha[at[k]];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        lerp(lerp(a(0), a(1), fx), lerp(a(2), a(3), fx), fy)
    }

    /// The index of the texel whose area holds `uv` (GL `NEAREST`); the level is readable.
    #[inline]
    fn nearest_index(&self, uv: Vec2, (ws, wt): (Wrap, Wrap)) -> usize {
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        let x = (ws.coordinate(uv.x) * self.width as f32).floor() as i64;
        let y = (wt.coordinate(uv.y) * self.height as f32).floor() as i64;
        // u = 1 exactly (clamped or mirrored) is the last texel's edge: it stays in range.
        wt.index(y.min(self.height as i64 - 1), self.height) * self.width
            + ws.index(x.min(self.width as i64 - 1), self.width)
    }

    /// The texel whose area holds `uv` (GL `NEAREST`), with its alpha.
    fn nearest(&self, uv: Vec2, (ws, wt): (Wrap, Wrap)) -> Vec4 {
        if !self.readable() {
            return Vec4::ONE;
        }
        let i = self.nearest_index(uv, (ws, wt));
        let alpha = self.alpha.get(i).copied().unwrap_or(1.0);
        self.texels[i].extend(alpha)
    }

    /// The next pyramid level: each side halved, rounded down, at least 1; `None` at 1 × 1.
    ///
    /// Both levels span the whole texture, so texel `i` of the new level covers the span
    /// `[i·n/n′, (i+1)·n/n′)` of this level's `n` texels along each axis (`n′` the new size): two
    /// texels when `n` is even, between two and three when it is odd, one when that side is
    /// already 1. The new texel is the average over that rectangle, each texel below weighted
    /// by the area it shares with it (a box filter, separable: rows, then columns). Every texel
    /// below gives away its whole area, so the mean is kept (exactly, but for rounding).
    /// `None` at 1 × 1; an error if the system refuses the new level's memory.
    fn half(&self) -> Option<Result<Level, crate::limits::NoMemory>> {
        let (w, h) = (self.width, self.height);
        if w <= 1 && h <= 1 {
            return None;
        }
        let (w2, h2) = ((w / 2).max(1), (h / 2).max(1));
        let buffers = crate::limits::try_vec(w2 * h, "a texture's pyramid").and_then(|rows| {
            Ok((
                rows,
                crate::limits::try_vec(w2 * h2, "a texture's pyramid")?,
            ))
        });
        let (mut rows, mut texels) = match buffers {
            Ok(b) => b,
            Err(e) => return Some(Err(e)),
        };
        let taps_x = axis_taps(w, w2);
        for y in 0..h {
            let row = &self.texels[y * w..(y + 1) * w];
            rows.extend(taps_x.iter().map(|t| t.apply(|j| row[j])));
        }
        let taps_y = axis_taps(h, h2);
        for t in &taps_y {
            texels.extend((0..w2).map(|x| t.apply(|j| rows[j * w2 + x])));
        }
        // Alpha the same way, as the fourth channel it is.
        let mut alpha = Vec::new();
        if !self.alpha.is_empty() {
            let buffers = crate::limits::try_vec(w2 * h, "a texture's pyramid")
                .and_then(|r| Ok((r, crate::limits::try_vec(w2 * h2, "a texture's pyramid")?)));
            let (mut rows, out) = match buffers {
                Ok(b) => b,
                Err(e) => return Some(Err(e)),
            };
            alpha = out;
            for y in 0..h {
                let row = &self.alpha[y * w..(y + 1) * w];
                rows.extend(taps_x.iter().map(|t| t.apply_scalar(|j| row[j])));
            }
            for t in &taps_y {
                alpha.extend((0..w2).map(|x| t.apply_scalar(|j| rows[j * w2 + x])));
            }
        }
        Some(Ok(Level {
            width: w2,
            height: h2,
            texels,
            alpha,
        }))
    }
}

/// The source texels one texel of a shrunk axis averages: at most four, since its span is at
/// most three texels long.
struct Taps {
    first: usize,
    weights: [f32; 4],
    len: usize,
}

impl Taps {
    /// `Σ weight_k · texel(first + k)`, in order.
    fn apply(&self, texel: impl Fn(usize) -> Vec3) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for (k, &w) in self.weights[..self.len].iter().enumerate() {
            sum += texel(self.first + k) * w;
        }
        sum
    }

    /// [`apply`](Self::apply) for one channel.
    fn apply_scalar(&self, texel: impl Fn(usize) -> f32) -> f32 {
        let mut sum = 0.0;
        for (k, &w) in self.weights[..self.len].iter().enumerate() {
            sum += texel(self.first + k) * w;
        }
        sum
    }
}

/// The taps of each texel of an axis of `n` texels shrunk to `n2` (see [`Level::half`]).
/// Positions are counted in `1/n2` of a source texel, so every boundary is an integer and the
/// weights are the exact fractions `overlap / n`, rounded once.
fn axis_taps(n: usize, n2: usize) -> Vec<Taps> {
    (0..n2)
        .map(|i| {
            let (lo, hi) = (i * n, (i + 1) * n);
            let first = lo / n2;
            let mut taps = Taps {
                first,
                weights: [0.0; 4],
                len: 0,
            };
            for j in first..hi.div_ceil(n2) {
                let overlap = hi.min((j + 1) * n2) - lo.max(j * n2);
                taps.weights[taps.len] = overlap as f32 / n as f32;
                taps.len += 1;
            }
            taps
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integer sRGB samples decoded by table (images with more samples than the table has
    /// entries) give the very bits decoding each sample gives: every 8- and 16-bit value, grey
    /// and RGB, twice over.
    #[test]
    fn srgb_decoding_by_table_gives_the_bits_of_decoding_each_sample() {
        use image::ColorType as C;
        for (color, size, channels) in [
            (C::L8, 1, 1),
            (C::Rgb8, 1, 3),
            (C::L16, 2, 1),
            (C::Rgb16, 2, 3),
        ] {
            let values = 1usize << (8 * size);
            let mut pixels = Vec::new();
            let mut want = Vec::new();
            for v in (0..values).chain(0..values) {
                let unit = if size == 1 {
                    v as f32 / 255.0
                } else {
                    v as f32 / 65535.0
                };
                let grey = if size == 1 {
                    v as f32 * (1.0 / 255.0)
                } else {
                    v as f32 * (1.0 / 65535.0)
                };
                let linear = srgb_to_linear(if channels == 1 {
                    grey
                } else {
                    unit.clamp(0.0, 1.0)
                });
                want.push(Vec3::splat(linear));
                for _ in 0..channels {
                    if size == 1 {
                        pixels.push(v as u8);
                    } else {
                        pixels.extend_from_slice(&(v as u16).to_ne_bytes());
                    }
                }
            }
            let (mut out, mut alpha) = (Vec::new(), Vec::new());
            assert!(linear_texels(
                color,
                Encoding::Srgb,
                &pixels,
                &mut out,
                &mut alpha
            ));
            let bits = |v: &[Vec3]| -> Vec<[u32; 3]> {
                v.iter().map(|t| t.to_array().map(f32::to_bits)).collect()
            };
            assert!(bits(&out) == bits(&want), "{color:?}");
        }
    }

    /// Deterministic texels in [0, 1).
    fn noise(width: usize, height: usize, seed: u64) -> Texture {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        let texels = (0..width * height)
            .map(|_| Vec3::new(next(), next(), next()))
            .collect();
        Texture::from_linear(width, height, texels).unwrap()
    }

    /// A checkerboard of 1-texel squares, black and white (sRGB 0 and 255: linear 0 and 1).
    fn checker(width: usize, height: usize) -> Texture {
        let rgb: Vec<u8> = (0..width * height)
            .flat_map(|i| {
                [if (i % width + i / width).is_multiple_of(2) {
                    255
                } else {
                    0
                }; 3]
            })
            .collect();
        Texture::from_srgb8(width, height, &rgb).unwrap()
    }

    fn mean(level: &Level) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for t in &level.texels {
            for c in 0..3 {
                sum[c] += f64::from(t[c]);
            }
        }
        sum.map(|s| s / level.texels.len() as f64)
    }

    const SIZES: [(usize, usize); 12] = [
        (1, 1),
        (2, 2),
        (16, 16),
        (64, 8),
        (1, 32),
        (3, 3),
        (5, 7),
        (13, 1),
        (99, 57),
        (255, 3),
        (2, 9),
        (100, 100),
    ];

    #[test]
    fn pyramid_sizes_halve_down_to_one_within_the_memory_bound() {
        for (w, h) in SIZES {
            let t = noise(w, h, 1);
            assert_eq!(t.level_count(), 1 + w.max(h).ilog2() as usize, "{w}×{h}");
            assert_eq!(t.level_size(0), (w, h));
            let mut all = 0;
            for k in 0..t.level_count() {
                let (lw, lh) = t.level_size(k);
                assert_eq!(
                    (lw, lh),
                    ((w >> k).max(1), (h >> k).max(1)),
                    "{w}×{h} level {k}"
                );
                assert_eq!(t.levels[k].texels.len(), lw * lh);
                all += lw * lh;
            }
            assert_eq!(t.level_size(t.level_count() - 1), (1, 1));
            // 4/3 of level 0, plus a few texels where the short side reaches 1 first (a
            // 1-texel strip doubles: its levels are strips too).
            let bound = w * h + w * h / 3 + w.max(h).div_ceil(w.min(h));
            assert!(all <= bound, "{w}×{h}: {all} texels > {bound}");
        }
        let empty = Texture::from_linear(0, 0, Vec::new()).unwrap();
        assert_eq!(empty.level_count(), 1);
        assert_eq!(
            Texture::from_linear(0, 5, Vec::new())
                .unwrap()
                .level_count(),
            1
        );
        assert!(Texture::from_linear(2, 2, vec![Vec3::ONE; 3]).is_none());
    }

    #[test]
    fn every_level_keeps_the_mean() {
        for (w, h) in SIZES {
            let t = noise(w, h, 2);
            let m0 = mean(&t.levels[0]);
            // Powers of two: halves of halves, only float rounding. Odd sizes: weights such as
            // 1/3 and 2/5 round too (one f32 rounding each), still well under 1e-5.
            let tol = if w.is_power_of_two() && h.is_power_of_two() {
                1e-6
            } else {
                1e-5
            };
            for (k, level) in t.levels.iter().enumerate() {
                let m = mean(level);
                for c in 0..3 {
                    assert!(
                        (m[c] - m0[c]).abs() <= tol * m0[c],
                        "{w}×{h} level {k} channel {c}: mean {} vs {}",
                        m[c],
                        m0[c]
                    );
                }
            }
        }
    }

    #[test]
    fn a_constant_texture_is_constant_at_every_level() {
        let c = Vec3::new(0.2, 0.55, 0.9);
        for (w, h) in SIZES {
            let t = Texture::from_linear(w, h, vec![c; w * h]).unwrap();
            for (k, level) in t.levels.iter().enumerate() {
                for &texel in &level.texels {
                    // Halving an even side averages pairs with weights 1/2: exact. Odd sides
                    // weigh by thirds and fifths, which round once each.
                    if w.is_power_of_two() && h.is_power_of_two() {
                        assert_eq!(texel, c, "{w}×{h} level {k}");
                    } else {
                        let err = ((texel - c) / c).abs().max_element();
                        assert!(err < 1e-6, "{w}×{h} level {k}: {texel} vs {c}");
                    }
                }
            }
            // And so is every footprint lookup, anywhere.
            for footprint in [0.0, 0.01, 0.1, 0.3, 1.0, 5.0] {
                let got = t.sample_footprint(Vec2::new(0.37, 0.81), footprint);
                assert!(((got - c) / c).abs().max_element() < 1e-6, "{w}×{h}: {got}");
            }
        }
    }

    #[test]
    fn a_checkerboards_coarse_levels_are_its_mean() {
        for (w, h) in [(64, 64), (16, 4), (8, 32)] {
            let t = checker(w, h);
            // Level 1 averages 2 × 2 squares: two black, two white. So does every level after.
            for k in 1..t.level_count() {
                for &texel in &t.levels[k].texels {
                    assert_eq!(texel, Vec3::splat(0.5), "{w}×{h} level {k}");
                }
            }
        }
        // Odd sides: a 5 × 5 checker has 13 white squares; its last level is their share.
        let t = checker(5, 5);
        let last = t.levels[t.level_count() - 1].texels[0];
        assert!(
            (last - Vec3::splat(13.0 / 25.0)).abs().max_element() < 1e-6,
            "{last}"
        );
    }

    #[test]
    fn a_footprint_covering_the_texture_is_its_mean() {
        for (w, h) in SIZES {
            let t = noise(w, h, 7);
            let m = mean(&t.levels[0]);
            for footprint in [1.0, 1.5, 1e3] {
                for uv in [Vec2::new(0.1, 0.9), Vec2::new(-3.3, 7.25), Vec2::ZERO] {
                    let got = t.sample_footprint(uv, footprint);
                    for c in 0..3 {
                        let err = (f64::from(got[c]) - m[c]).abs();
                        assert!(err < 1e-5 * m[c], "{w}×{h} footprint {footprint}: {got}");
                    }
                }
            }
        }
    }

    #[test]
    fn odd_sizes_average_the_area_each_texel_covers() {
        // 3 texels to 1 and 5 to 2: spans of 3 and 2.5 texels.
        let t = Texture::from_linear(5, 3, (0..15).map(|i| Vec3::splat(i as f32)).collect());
        let t = t.unwrap();
        let l1 = &t.levels[1];
        assert_eq!((l1.width, l1.height), (2, 1));
        // Column weights 2/5, 2/5, 1/5 | 1/5, 2/5, 2/5; each row the mean of its 3 rows
        // (column x's mean is x + 5).
        let left = (0.4 * 5.0 + 0.4 * 6.0 + 0.2 * 7.0) as f32;
        let right = (0.2 * 7.0 + 0.4 * 8.0 + 0.4 * 9.0) as f32;
        assert!((l1.texels[0].x - left).abs() < 1e-5, "{}", l1.texels[0].x);
        assert!((l1.texels[1].x - right).abs() < 1e-5, "{}", l1.texels[1].x);
    }

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    #[test]
    fn footprints_of_at_most_one_texel_are_sample_bit_for_bit() {
        let uvs = [
            Vec2::new(0.3, 0.7),
            Vec2::new(0.0, 0.0),
            Vec2::new(-2.37, 5.11),
            Vec2::new(1e6 + 0.25, -1e5),
            Vec2::new(0.999_999, 0.5),
            Vec2::new(f32::NAN, 0.5),
            Vec2::new(0.5, f32::INFINITY),
        ];
        for (w, h) in SIZES {
            let t = noise(w, h, 3);
            let one = 1.0 / w.max(h) as f32;
            for footprint in [
                0.0,
                -0.0,
                -1.0,
                f32::NAN,
                1e-30,
                0.5 * one,
                0.999 * one,
                one,
            ] {
                assert!(footprint.is_nan() || footprint * w.max(h) as f32 <= 1.0);
                for &uv in &uvs {
                    assert_eq!(
                        bits(t.sample_footprint(uv, footprint)),
                        bits(t.sample(uv)),
                        "{w}×{h} uv {uv} footprint {footprint}"
                    );
                }
            }
        }
    }

    #[test]
    fn checkerboard_at_eight_texels_is_its_mean_grey() {
        let t = checker(64, 64);
        for i in 0..64 {
            for j in 0..64 {
                // Texel centres: point sampling gives exactly black or white.
                let uv = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                let point = t.sample(uv);
                assert!(point == Vec3::ZERO || point == Vec3::ONE, "{point}");
                let filtered = t.sample_footprint(uv, 8.0 / 64.0);
                assert!((filtered - Vec3::splat(0.5)).abs().max_element() < 1e-6);
                // Off the centres too, and over the wrap.
                let uv = uv * 1.37 - Vec2::splat(0.61);
                let filtered = t.sample_footprint(uv, 8.0 / 64.0);
                assert!((filtered - Vec3::splat(0.5)).abs().max_element() < 1e-6);
            }
        }
    }

    #[test]
    fn levels_blend_continuously_as_the_footprint_grows() {
        let t = noise(32, 32, 4);
        let last = (t.level_count() - 1) as f32;
        let steps_per_level = 256;
        let step = 1.0 / steps_per_level as f32;
        let mut biggest_level_change = 0.0f32;
        for uv in [
            Vec2::new(0.31, 0.62),
            Vec2::new(0.05, 0.93),
            Vec2::new(0.5, 0.5),
        ] {
            let at = |level: f32| t.sample_footprint(uv, libm::exp2f(level) / 32.0);
            for n in 0..last as usize {
                let (a, b) = (at(n as f32), at(n as f32 + 1.0));
                biggest_level_change = biggest_level_change.max((a - b).abs().max_element());
            }
            let mut prev = t.sample(uv);
            for s in 1..=(last as usize + 1) * steps_per_level {
                let value = at(s as f32 * step);
                // The blend moves by at most |level n+1 − level n| ≤ 1 per level.
                let jump = (value - prev).abs().max_element();
                assert!(
                    jump <= 1.01 * step + 1e-6,
                    "uv {uv}: jump {jump} at step {s}"
                );
                prev = value;
            }
        }
        // Adjacent levels differ, so a jump between them would have shown.
        assert!(biggest_level_change > 0.1, "{biggest_level_change}");
    }

    /// The old decoding: the `image` crate's `DynamicImage::to_rgb32f`, then sRGB decoded.
    fn through_dynamic_image(bytes: &[u8]) -> Vec<Vec3> {
        let rgb = reader(bytes).unwrap().decode().unwrap().to_rgb32f();
        rgb.pixels()
            .map(|p| Vec3::new(p[0], p[1], p[2]).map(srgb_to_linear))
            .collect()
    }

    #[test]
    fn decoding_gives_the_texels_of_the_image_crates_conversion_bit_for_bit() {
        use image::{DynamicImage, ImageBuffer, ImageFormat};
        // Every 8- and 16-bit sample value, in every channel layout PNG has; JPEG's two; RGB
        // floats through Radiance HDR.
        let v8 = |n: usize, k: usize| ((n * 7 + k * 91) % 256) as u8;
        let v16 = |n: usize, k: usize| ((n * 7 + k * 9091) % 65536) as u16;
        let (w, h) = (256, 256);
        let l8 = DynamicImage::ImageLuma8(ImageBuffer::from_fn(w, h, |x, y| {
            image::Luma([v8((y * w + x) as usize, 0)])
        }));
        let rgb8 = DynamicImage::ImageRgb8(ImageBuffer::from_fn(w, h, |x, y| {
            let n = (y * w + x) as usize;
            image::Rgb([v8(n, 0), v8(n, 1), v8(n, 2)])
        }));
        let images: Vec<(&str, DynamicImage, ImageFormat)> = vec![
            ("L8", l8.clone(), ImageFormat::Png),
            (
                "La8",
                DynamicImage::ImageLumaA8(ImageBuffer::from_fn(w, h, |x, y| {
                    let n = (y * w + x) as usize;
                    image::LumaA([v8(n, 0), v8(n, 1)])
                })),
                ImageFormat::Png,
            ),
            ("Rgb8", rgb8.clone(), ImageFormat::Png),
            (
                "Rgba8",
                DynamicImage::ImageRgba8(ImageBuffer::from_fn(w, h, |x, y| {
                    let n = (y * w + x) as usize;
                    image::Rgba([v8(n, 0), v8(n, 1), v8(n, 2), v8(n, 3)])
                })),
                ImageFormat::Png,
            ),
            (
                "L16",
                DynamicImage::ImageLuma16(ImageBuffer::from_fn(w, h, |x, y| {
                    image::Luma([v16((y * w + x) as usize, 0)])
                })),
                ImageFormat::Png,
            ),
            (
                "La16",
                DynamicImage::ImageLumaA16(ImageBuffer::from_fn(w, h, |x, y| {
                    let n = (y * w + x) as usize;
                    image::LumaA([v16(n, 0), v16(n, 1)])
                })),
                ImageFormat::Png,
            ),
            (
                "Rgb16",
                DynamicImage::ImageRgb16(ImageBuffer::from_fn(w, h, |x, y| {
                    let n = (y * w + x) as usize;
                    image::Rgb([v16(n, 0), v16(n, 1), v16(n, 2)])
                })),
                ImageFormat::Png,
            ),
            (
                "Rgba16",
                DynamicImage::ImageRgba16(ImageBuffer::from_fn(w, h, |x, y| {
                    let n = (y * w + x) as usize;
                    image::Rgba([v16(n, 0), v16(n, 1), v16(n, 2), v16(n, 3)])
                })),
                ImageFormat::Png,
            ),
            ("JPEG L8", l8, ImageFormat::Jpeg),
            ("JPEG Rgb8", rgb8, ImageFormat::Jpeg),
            (
                "HDR Rgb32F",
                DynamicImage::ImageRgb32F(ImageBuffer::from_fn(w, h, |x, y| {
                    let n = (y * w + x) as f32;
                    image::Rgb([n / 1000.0, 0.5, n * 3.0])
                })),
                ImageFormat::Hdr,
            ),
        ];
        for (name, img, format) in images {
            let mut bytes = std::io::Cursor::new(Vec::new());
            img.write_to(&mut bytes, format).unwrap();
            let bytes = bytes.into_inner();
            let t = Texture::decode(&bytes).unwrap();
            assert_eq!((t.width(), t.height()), (w as usize, h as usize), "{name}");
            let old = through_dynamic_image(&bytes);
            let same = t
                .texels()
                .iter()
                .zip(&old)
                .all(|(a, b)| bits(*a) == bits(*b));
            assert!(same, "{name}: texels differ from to_rgb32f's");
        }
    }

    #[test]
    fn alpha_is_kept_as_stored_and_leaves_the_colour_alone() {
        use image::{DynamicImage, ImageBuffer, ImageFormat};
        let (w, h) = (16u32, 8u32);
        let a8 = |n: u32| (n * 37 % 256) as u8;
        let a16 = |n: u32| (n * 9091 % 65536) as u16;
        let images: Vec<(&str, DynamicImage, Vec<f32>)> = vec![
            (
                "Rgba8",
                DynamicImage::ImageRgba8(ImageBuffer::from_fn(w, h, |x, y| {
                    image::Rgba([10, 20, 30, a8(y * w + x)])
                })),
                (0..w * h).map(|n| f32::from(a8(n)) / 255.0).collect(),
            ),
            (
                "La8",
                DynamicImage::ImageLumaA8(ImageBuffer::from_fn(w, h, |x, y| {
                    image::LumaA([90, a8(y * w + x)])
                })),
                (0..w * h).map(|n| f32::from(a8(n)) / 255.0).collect(),
            ),
            (
                "Rgba16",
                DynamicImage::ImageRgba16(ImageBuffer::from_fn(w, h, |x, y| {
                    image::Rgba([1000, 2000, 3000, a16(y * w + x)])
                })),
                (0..w * h).map(|n| f32::from(a16(n)) / 65535.0).collect(),
            ),
        ];
        for (name, img, want) in images {
            let mut bytes = std::io::Cursor::new(Vec::new());
            img.write_to(&mut bytes, ImageFormat::Png).unwrap();
            let bytes = bytes.into_inner();
            let t = Texture::decode(&bytes).unwrap();
            assert!(t.has_alpha(), "{name}");
            assert_eq!(t.alpha().len(), (w * h) as usize, "{name}");
            for (n, want) in want.iter().enumerate() {
                let (x, y) = (n % w as usize, n / w as usize);
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                assert_eq!(
                    t.alpha_at(uv, &Sampler::default()),
                    *want,
                    "{name} texel {n}"
                );
                // The sampler's lookup at level 0 reads the same alpha.
                assert_eq!(
                    t.lookup(uv, 0.0, &Sampler::default()).w,
                    *want,
                    "{name} {n}"
                );
            }
            let same = t
                .texels()
                .iter()
                .zip(&through_dynamic_image(&bytes))
                .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits));
            assert!(same, "{name}: colour changed");
        }
        // No alpha channel: opaque.
        let rgb = DynamicImage::ImageRgb8(ImageBuffer::from_fn(4, 4, |_, _| image::Rgb([1, 2, 3])));
        let mut bytes = std::io::Cursor::new(Vec::new());
        rgb.write_to(&mut bytes, ImageFormat::Png).unwrap();
        let bytes = bytes.into_inner();
        let t = Texture::decode(&bytes).unwrap();
        assert!(!t.has_alpha());
        assert_eq!(t.alpha_at(Vec2::splat(0.3), &Sampler::default()), 1.0);
    }

    #[test]
    fn odd_inputs_do_not_panic() {
        let textures = [
            noise(1, 1, 5),
            noise(1, 7, 5),
            noise(5, 3, 5),
            Texture::from_linear(0, 0, Vec::new()).unwrap(),
            Texture::from_linear(0, 4, Vec::new()).unwrap(),
        ];
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN_POSITIVE,
            1e30,
        ];
        for t in &textures {
            for &u in &values {
                for &footprint in &values {
                    let got = t.sample_footprint(Vec2::new(u, 0.25), footprint);
                    assert!(got.is_finite(), "{u} {footprint}: {got}");
                }
            }
        }
        // An empty texture is white, as `sample` makes it.
        assert_eq!(textures[3].sample_footprint(Vec2::ZERO, 0.5), Vec3::ONE);
        // An infinite footprint is the last level: the mean.
        let t = noise(8, 8, 6);
        let m = mean(&t.levels[0]);
        let got = t.sample_footprint(Vec2::new(0.1, 0.2), f32::INFINITY);
        for c in 0..3 {
            assert!((f64::from(got[c]) - m[c]).abs() < 1e-6);
        }
    }
}
