//! The film: a frame's beauty and AOV buffers, assembled from finished tiles, and the counts
//! of the work that made them.
//!
//! The film holds one plane (row-major `f32`) per [`Channel`], those the frame keeps, and
//! every layer is a line of [`LAYERS`]. A new layer is its `Channel` variants with their
//! lines there (EXR names, ours and Blender's, precision, blank value, when held, where
//! listed), and the lines in the tile driver's `shade` that compute and write its per-pixel
//! value.

use std::ops::AddAssign;
use std::sync::Arc;

use crate::tile::Rect;
use crate::view::View;

/// A finished tile: its pixels' channels (row-major over `rect`) and its counts.
#[derive(Clone, Debug)]
pub struct TileResult {
    pub rect: Rect,
    pub planes: Planes,
    pub counts: Counts,
}

/// Work counted while deciding visibility. With samples per pixel every count is per sample:
/// a "pixel" below is one sample of the lattice the method works on (a pixel at `--spp 1`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counts {
    /// Shadow queries: (pixel, light) pairs with N·ω > 0 [paper].
    pub queries: u64,
    /// Shadow rays traced for the tile's own pixels.
    pub rays: u64,
    /// Pixels outside the tile that its method evaluated (its halo), and their rays.
    pub halo_pixels: u64,
    pub halo_rays: u64,
    /// With validation: pairs predicted visible that are blocked, and the reverse.
    pub wrong_visible: u64,
    pub wrong_blocked: u64,
    /// With validation: samples with any wrong pair.
    pub wrong_pixels: u64,
    /// With validation: wrong pairs among those the method traced (always 0 unless a method
    /// mis-records its own traces; checked by the tests).
    pub wrong_traced: u64,
    /// Pixels predicted from the previous frame (`--temporal`) and the rays they traced; the
    /// other pixels' rays are the spatially predicted ones.
    pub temporal_pixels: u64,
    pub temporal_rays: u64,
    /// Of those pixels' (pixel, light) pairs the previous frame was sure of, those dropped
    /// because what a file's animation moved may cross their rays. Not a `stats.csv` column
    /// (its columns are the farm's and the golden renders'); said by `-v`.
    #[serde(default)]
    pub temporal_stale: u64,
    /// Where the tile's rays went: at pixels tracing every light, and queued by flooding (the
    /// rest were queued by the prediction); flooded rays that caught a wrong prediction.
    #[serde(default)]
    pub rays_every_light: u64,
    #[serde(default)]
    pub rays_flooded: u64,
    #[serde(default)]
    pub flood_fixes: u64,
}

impl AddAssign for Counts {
    fn add_assign(&mut self, o: Counts) {
        self.queries += o.queries;
        self.rays += o.rays;
        self.halo_pixels += o.halo_pixels;
        self.halo_rays += o.halo_rays;
        self.wrong_visible += o.wrong_visible;
        self.wrong_blocked += o.wrong_blocked;
        self.wrong_pixels += o.wrong_pixels;
        self.wrong_traced += o.wrong_traced;
        self.temporal_pixels += o.temporal_pixels;
        self.temporal_rays += o.temporal_rays;
        self.temporal_stale += o.temporal_stale;
        self.rays_every_light += o.rays_every_light;
        self.rays_flooded += o.rays_flooded;
        self.flood_fixes += o.flood_fixes;
    }
}

impl Counts {
    /// Every shadow ray traced: at the pixels themselves and, again, at the halo pixels tiles
    /// evaluated for their neighbours (work a whole-frame render would not repeat).
    pub fn traced(&self) -> u64 {
        self.rays + self.halo_rays
    }

    /// [`traced`](Self::traced) as a percentage of queries (100 when there were no queries):
    /// every ray the frame cost, halo rays included [ours]; `rays` alone is what the pixels'
    /// `rays` layer sums to.
    pub fn percent_traced(&self) -> f64 {
        if self.queries == 0 {
            100.0
        } else {
            100.0 * self.traced() as f64 / self.queries as f64
        }
    }

    /// Rays queued by the prediction itself: neither at pixels tracing every light nor by
    /// flooding.
    pub fn rays_unsure(&self) -> u64 {
        self.rays - self.rays_every_light - self.rays_flooded
    }

    /// Wrong pairs / queries, in percent (validation only).
    pub fn error_percent(&self) -> f64 {
        if self.queries == 0 {
            0.0
        } else {
            100.0 * (self.wrong_visible + self.wrong_blocked) as f64 / self.queries as f64
        }
    }
}

/// How a validated frame's image compares with the brute-force image.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageError {
    /// Root mean square difference of linear RGB, over all pixels and channels.
    pub rmse: f64,
    /// `rmse` / the mean of the brute-force image over pixels that hit the scene.
    pub rel_rmse: f64,
    /// PSNR of the previews (the view transform's sRGB in [0, 1], peak 1), dB; infinite when
    /// equal.
    pub psnr_db: f64,
}

/// The depth (`Z`) of a pixel none of whose samples hit the scene: far beyond any scene,
/// finite so that a compositor's depth filters do not turn it into NaN.
pub const BACKGROUND_DEPTH: f32 = 1e10;

/// One frame's pixels: linear RGB beauty and the per-pixel AOVs, row-major, full frame, one
/// plane per channel the frame holds ([`Channel`] says what each is, [`LAYERS`] when it is
/// held).
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    planes: Planes,
    /// Sum of the tiles' counts.
    pub counts: Counts,
    /// With Cryptomatte (`--cryptomatte`): the manifests of its types
    /// ([`crate::cryptomatte::TYPES`]), which the EXR header carries.
    pub cryptomatte: Option<Arc<[String; 2]>>,
}

impl Film {
    /// An empty film holding the channels `holds` keeps, each at its blank value (pixels no
    /// tile rendered keep it: alpha 0, transparent like the black around a region render).
    pub fn new(width: u32, height: u32, holds: Holds) -> Film {
        Film {
            width,
            height,
            planes: Planes::new(width as usize * height as usize, holds),
            counts: Counts::default(),
            cryptomatte: None,
        }
    }

    /// The last guard before a frame is written: every value of every channel made finite
    /// (NaN to 0, ±∞ to the largest finite value its file stores: f32's, or half's 65504 with
    /// `half` where the channel is half), the beauty, alpha and albedo made ≥ 0. Returns how
    /// many values it changed, for a warning: a non-finite pixel breaks a comp (a blur
    /// spreads it as NaN), and the inputs that would make one are clamped at load.
    pub fn guard_finite(&mut self, half: bool) -> u64 {
        let mut changed = 0;
        for (c, plane) in self.planes.0.iter_mut().enumerate() {
            let Some(plane) = plane else {
                continue;
            };
            let layer = &LAYERS[c];
            let most = if half && layer.precision == Precision::Half {
                65504.0
            } else {
                f32::MAX
            };
            let least = if NON_NEGATIVE.contains(&layer.channel) {
                0.0
            } else {
                -most
            };
            for v in plane.iter_mut() {
                let g = if v.is_nan() {
                    0.0
                } else {
                    v.clamp(least, most)
                };
                if g.to_bits() != v.to_bits() && !(g == 0.0 && *v == 0.0) {
                    *v = g;
                    changed += 1;
                }
            }
        }
        changed
    }

    /// Whether some pixel is less than opaque.
    pub fn has_transparency(&self) -> bool {
        self.plane(Channel::A)
            .is_some_and(|a| a.iter().any(|&v| v < 1.0))
    }

    /// Copies a finished tile into place (every channel both hold) and adds its counts.
    pub fn add(&mut self, tile: &TileResult) {
        let r = tile.rect;
        let w = r.width() as usize;
        for (d, s) in self.planes.0.iter_mut().zip(&tile.planes.0) {
            let (Some(d), Some(s)) = (d, s) else {
                continue;
            };
            for y in r.y0..r.y1 {
                let src = (y - r.y0) as usize * w;
                let dst = y as usize * self.width as usize + r.x0 as usize;
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
        }
        self.counts += tile.counts;
    }

    /// The channels this film holds, in the order files list them ([`LAYERS`]' order):
    /// beauty, the compositor's passes, the shadow method's (alpha always: 1 over an opaque
    /// background); with `reference` also the brute-force image (farm tile images carry it,
    /// frames do not).
    pub fn channels(&self, reference: bool) -> Vec<Channel> {
        LAYERS
            .iter()
            .filter(|l| {
                let held = self.planes.0[l.channel as usize].is_some();
                match l.listed {
                    Listed::Held => held,
                    Listed::Always(_) => true,
                    Listed::TileImages => reference && held,
                }
            })
            .map(|l| l.channel)
            .collect()
    }

    /// Whether the film holds channel `c`.
    pub fn holds(&self, c: Channel) -> bool {
        self.planes.0[c as usize].is_some()
    }

    /// Channel `c`'s plane, row-major; `None` where the film does not hold it.
    pub fn plane(&self, c: Channel) -> Option<&[f32]> {
        self.planes.plane(c)
    }

    /// Channel `c` of pixel `i` (for a channel the film does not hold, the value files list,
    /// else 0).
    #[inline]
    pub fn get(&self, c: Channel, i: usize) -> f32 {
        self.planes.get(c, i)
    }

    /// Sets channel `c` of pixel `i` (nothing for a channel the film does not hold).
    #[inline]
    pub fn set(&mut self, c: Channel, i: usize, v: f32) {
        self.planes.set(c, i, v);
    }

    /// Pixel `i` of an RGB layer ([`Channel::BEAUTY`], [`Channel::NORMAL`], ...).
    #[inline]
    pub fn rgb(&self, layer: [Channel; 3], i: usize) -> [f32; 3] {
        layer.map(|c| self.get(c, i))
    }

    /// Pixel `i` of the beauty: linear RGB radiance, the mean of the pixel's samples.
    #[inline]
    pub fn beauty(&self, i: usize) -> [f32; 3] {
        self.rgb(Channel::BEAUTY, i)
    }

    /// Every pixel of an RGB layer, row-major; `None` where the film does not hold it.
    pub fn layer(&self, layer: [Channel; 3]) -> Option<Vec<[f32; 3]>> {
        let [r, g, b] = layer.map(|c| self.plane(c));
        let (r, g, b) = (r?, g?, b?);
        Some((0..r.len()).map(|i| [r[i], g[i], b[i]]).collect())
    }

    /// With validation: the beauty against the brute-force image over `region` (the rendered
    /// pixels); the relative RMSE is relative to the brute-force image's mean.
    pub fn image_error(&self, region: Rect, exposure: f32, view: View) -> Option<ImageError> {
        if !self.holds(Channel::RefR) {
            return None;
        }
        let (mut se, mut sum_ref, mut n, mut se_ldr) = (0f64, 0f64, 0u64, 0f64);
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let i = y as usize * self.width as usize + x as usize;
                let (b, r) = (self.beauty(i), self.rgb(Channel::REFERENCE, i));
                let (bl, rl) = (
                    view.display(b.map(|c| c * exposure)),
                    view.display(r.map(|c| c * exposure)),
                );
                for c in 0..3 {
                    let d = (b[c] - r[c]) as f64;
                    se += d * d;
                    let dl = (bl[c] - rl[c]) as f64;
                    se_ldr += dl * dl;
                }
                n += 3;
                sum_ref += (r[0] + r[1] + r[2]) as f64;
            }
        }
        let rmse = (se / n.max(1) as f64).sqrt();
        let mean = sum_ref / n.max(1) as f64;
        let mse_ldr = se_ldr / n.max(1) as f64;
        Some(ImageError {
            rmse,
            rel_rmse: if mean > 0.0 { rmse / mean } else { 0.0 },
            psnr_db: if mse_ldr > 0.0 {
                -10.0 * libm::log10(mse_ldr)
            } else {
                f64::INFINITY
            },
        })
    }
}

/// A channel of the film, named as Nuke, Blender and OpenImageIO read them: the beauty as
/// `R G B`, the depth as `Z`, the other passes as `layer.channel` (`N.X`, `albedo.R`,
/// `shadow.rays`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    /// Linear RGB radiance: the mean of the pixel's samples.
    R,
    G,
    B,
    /// Alpha: over a transparent background (`[render] background`), each pixel's mean over
    /// its samples (placed by the pixel filter, so weighted as the beauty is) of 1 where a
    /// sample sees the model, the shadow fraction where it sees a shadow catcher and 0 where
    /// it sees the background; the beauty is premultiplied by it. Not held: 1 everywhere (an
    /// opaque background).
    A,
    /// Camera depth: the distance along the view direction to the nearest surface any of the
    /// pixel's samples hit ([ours], as Arnold's "closest" filter: a mean across a silhouette
    /// would be a depth where nothing is); [`BACKGROUND_DEPTH`] where none hit.
    Z,
    /// World-space shading normal (turned towards the camera), the mean over the pixel's
    /// samples with background samples counting 0, not renormalised (as Cycles' Normal pass).
    NX,
    NY,
    NZ,
    /// Surface albedo (linear RGB base colour, textured), the mean over the pixel's samples
    /// with background samples counting 0.
    AlbedoR,
    AlbedoG,
    AlbedoB,
    /// The shadow method's work and answers: rays traced at the pixel (all its samples),
    /// the fraction of above-horizon lights visible, wrong pairs (validation), the fraction
    /// of samples that hit the scene (several samples per pixel; at one sample it would be
    /// the hit mask, and is not kept).
    Rays,
    Visible,
    Wrong,
    Coverage,
    /// The brute-force image (validation; farm tile images only).
    RefR,
    RefG,
    RefB,
    /// Cryptomatte (`--cryptomatte`, see `crate::cryptomatte`): per type, three layers of two
    /// ranks, each an ID (the hash of an object's or a material's name as a float) and its
    /// coverage, the share of the pixel's samples that saw it (the samples are placed by the
    /// filter, so each weighs the same); a pixel's coverages add up to the share of its
    /// samples that hit the scene ([`Channel::Coverage`], 1 at one sample on a hit), the
    /// background's having no ID.
    Object00R,
    Object00G,
    Object00B,
    Object00A,
    Object01R,
    Object01G,
    Object01B,
    Object01A,
    Object02R,
    Object02G,
    Object02B,
    Object02A,
    Material00R,
    Material00G,
    Material00B,
    Material00A,
    Material01R,
    Material01G,
    Material01B,
    Material01A,
    Material02R,
    Material02G,
    Material02B,
    Material02A,
}

impl Channel {
    /// How many channels there are.
    pub const COUNT: usize = LAYERS.len();
    /// The RGB layers: the beauty, the normal, the albedo, the brute-force image.
    pub const BEAUTY: [Channel; 3] = [Channel::R, Channel::G, Channel::B];
    pub const NORMAL: [Channel; 3] = [Channel::NX, Channel::NY, Channel::NZ];
    pub const ALBEDO: [Channel; 3] = [Channel::AlbedoR, Channel::AlbedoG, Channel::AlbedoB];
    pub const REFERENCE: [Channel; 3] = [Channel::RefR, Channel::RefG, Channel::RefB];
    /// Cryptomatte's channels per type ([`crate::cryptomatte::TYPES`]' order): rank 0's ID
    /// and coverage, rank 1's, … (`CryptoObject00.R`, `.G`, `.B`, `.A`, `CryptoObject01.R`, …).
    pub const CRYPTOMATTE: [[Channel; 2 * crate::cryptomatte::RANKS]; 2] = {
        use Channel::*;
        [
            [
                Object00R, Object00G, Object00B, Object00A, Object01R, Object01G, Object01B,
                Object01A, Object02R, Object02G, Object02B, Object02A,
            ],
            [
                Material00R,
                Material00G,
                Material00B,
                Material00A,
                Material01R,
                Material01G,
                Material01B,
                Material01A,
                Material02R,
                Material02G,
                Material02B,
                Material02A,
            ],
        ]
    };

    fn layer(self) -> &'static Layer {
        &LAYERS[self as usize]
    }

    /// The channel's name in an EXR file.
    pub fn name(self) -> &'static str {
        self.layer().name
    }

    /// The channel's name in Blender's multilayer layout (`ViewLayer.Combined.R`, …).
    pub fn blender_name(self) -> &'static str {
        self.layer().blender
    }

    /// Whether the channel stays 32-bit float in a half-float EXR (`--half`).
    pub fn exact(self) -> bool {
        self.layer().precision == Precision::Full
    }
}

/// What the frame keeps beyond the layers every film holds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Holds {
    /// `--validate`: the wrong pairs and the brute-force image.
    pub validated: bool,
    /// Several samples per pixel: the coverage.
    pub samples: bool,
    /// A transparent background: the alpha.
    pub transparent: bool,
    /// `--cryptomatte`: the ID mattes.
    pub cryptomatte: bool,
}

impl Holds {
    fn held(self, when: Held) -> bool {
        match when {
            Held::Always => true,
            Held::Validated => self.validated,
            Held::Samples => self.samples,
            Held::Transparent => self.transparent,
            Held::Cryptomatte => self.cryptomatte,
        }
    }
}

/// When the film holds a channel (see [`Holds`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Held {
    Always,
    Validated,
    Samples,
    Transparent,
    Cryptomatte,
}

/// A channel's precision in a half-float EXR (`--half`) [ours]: counts (rays up to 4096
/// lights × 64 samples, wrong pairs) are whole numbers beyond half's 2048, and depth needs
/// more than half's 11 bits (and its range: the background's 1e10), so they stay `Full`, as
/// do Cryptomatte's IDs (a float's every bit is the hash) and coverages (as Blender writes
/// them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    Half,
    Full,
}

/// Which files list a channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Listed {
    /// Every file, where the film holds it.
    Held,
    /// Every file: where the film does not hold it, as this value (alpha: 1, opaque).
    Always(f32),
    /// Farm tile images only, where the film holds it (the brute-force image).
    TileImages,
}

/// One channel's line of [`LAYERS`].
#[derive(Clone, Copy, Debug)]
pub struct Layer {
    pub channel: Channel,
    /// Its name in an EXR file, and in Blender's multilayer layout (`--exr-layout blender`):
    /// `ViewLayer.<pass>.<channel>`, Blender's pass where it has one (`Combined`, `Depth`,
    /// `Normal`, `DiffCol` for the albedo), ours under our pass names otherwise.
    pub name: &'static str,
    pub blender: &'static str,
    pub precision: Precision,
    /// Its value where no sample wrote one (a pixel no tile rendered).
    pub blank: f32,
    pub held: Held,
    pub listed: Listed,
}

const fn line(
    channel: Channel,
    [name, blender]: [&'static str; 2],
    precision: Precision,
    blank: f32,
    held: Held,
    listed: Listed,
) -> Layer {
    Layer {
        channel,
        name,
        blender,
        precision,
        blank,
        held,
        listed,
    }
}

/// Every channel, in [`Channel`]'s order (which files list them in). Blender's single-value
/// passes have one channel named `X` (its AOVs') or `Z` (depth); ours follow the former.
#[rustfmt::skip]
pub const LAYERS: &[Layer] = {
    use Channel::*;
    use Held::*;
    use Precision::*;
    &[
        line(R, ["R", "ViewLayer.Combined.R"], Half, 0.0, Always, Listed::Held),
        line(G, ["G", "ViewLayer.Combined.G"], Half, 0.0, Always, Listed::Held),
        line(B, ["B", "ViewLayer.Combined.B"], Half, 0.0, Always, Listed::Held),
        line(A, ["A", "ViewLayer.Combined.A"], Half, 0.0, Transparent, Listed::Always(1.0)),
        line(Z, ["Z", "ViewLayer.Depth.Z"], Full, BACKGROUND_DEPTH, Always, Listed::Held),
        line(NX, ["N.X", "ViewLayer.Normal.X"], Half, 0.0, Always, Listed::Held),
        line(NY, ["N.Y", "ViewLayer.Normal.Y"], Half, 0.0, Always, Listed::Held),
        line(NZ, ["N.Z", "ViewLayer.Normal.Z"], Half, 0.0, Always, Listed::Held),
        line(AlbedoR, ["albedo.R", "ViewLayer.DiffCol.R"], Half, 0.0, Always, Listed::Held),
        line(AlbedoG, ["albedo.G", "ViewLayer.DiffCol.G"], Half, 0.0, Always, Listed::Held),
        line(AlbedoB, ["albedo.B", "ViewLayer.DiffCol.B"], Half, 0.0, Always, Listed::Held),
        line(Rays, ["shadow.rays", "ViewLayer.ShadowRays.X"], Full, 0.0, Always, Listed::Held),
        line(Visible, ["shadow.visible", "ViewLayer.ShadowVisible.X"], Half, 0.0, Always, Listed::Held),
        line(Wrong, ["shadow.wrong", "ViewLayer.ShadowWrong.X"], Full, 0.0, Validated, Listed::Held),
        line(Coverage, ["shadow.coverage", "ViewLayer.ShadowCoverage.X"], Half, 0.0, Samples, Listed::Held),
        line(RefR, ["reference.R", "ViewLayer.Reference.R"], Half, 0.0, Validated, Listed::TileImages),
        line(RefG, ["reference.G", "ViewLayer.Reference.G"], Half, 0.0, Validated, Listed::TileImages),
        line(RefB, ["reference.B", "ViewLayer.Reference.B"], Half, 0.0, Validated, Listed::TileImages),
        line(Object00R, ["CryptoObject00.R", "ViewLayer.CryptoObject00.R"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object00G, ["CryptoObject00.G", "ViewLayer.CryptoObject00.G"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object00B, ["CryptoObject00.B", "ViewLayer.CryptoObject00.B"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object00A, ["CryptoObject00.A", "ViewLayer.CryptoObject00.A"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object01R, ["CryptoObject01.R", "ViewLayer.CryptoObject01.R"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object01G, ["CryptoObject01.G", "ViewLayer.CryptoObject01.G"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object01B, ["CryptoObject01.B", "ViewLayer.CryptoObject01.B"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object01A, ["CryptoObject01.A", "ViewLayer.CryptoObject01.A"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object02R, ["CryptoObject02.R", "ViewLayer.CryptoObject02.R"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object02G, ["CryptoObject02.G", "ViewLayer.CryptoObject02.G"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object02B, ["CryptoObject02.B", "ViewLayer.CryptoObject02.B"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Object02A, ["CryptoObject02.A", "ViewLayer.CryptoObject02.A"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material00R, ["CryptoMaterial00.R", "ViewLayer.CryptoMaterial00.R"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material00G, ["CryptoMaterial00.G", "ViewLayer.CryptoMaterial00.G"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material00B, ["CryptoMaterial00.B", "ViewLayer.CryptoMaterial00.B"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material00A, ["CryptoMaterial00.A", "ViewLayer.CryptoMaterial00.A"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material01R, ["CryptoMaterial01.R", "ViewLayer.CryptoMaterial01.R"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material01G, ["CryptoMaterial01.G", "ViewLayer.CryptoMaterial01.G"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material01B, ["CryptoMaterial01.B", "ViewLayer.CryptoMaterial01.B"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material01A, ["CryptoMaterial01.A", "ViewLayer.CryptoMaterial01.A"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material02R, ["CryptoMaterial02.R", "ViewLayer.CryptoMaterial02.R"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material02G, ["CryptoMaterial02.G", "ViewLayer.CryptoMaterial02.G"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material02B, ["CryptoMaterial02.B", "ViewLayer.CryptoMaterial02.B"], Full, 0.0, Cryptomatte, Listed::Held),
        line(Material02A, ["CryptoMaterial02.A", "ViewLayer.CryptoMaterial02.A"], Full, 0.0, Cryptomatte, Listed::Held),
    ]
};

// Each channel's line is at its index.
const _: () = {
    let mut i = 0;
    while i < LAYERS.len() {
        assert!(
            LAYERS[i].channel as usize == i,
            "LAYERS out of Channel's order"
        );
        i += 1;
    }
};

/// The channels no pixel may hold a negative value in ([`Film::guard_finite`]).
const NON_NEGATIVE: [Channel; 10] = [
    Channel::R,
    Channel::G,
    Channel::B,
    Channel::A,
    Channel::AlbedoR,
    Channel::AlbedoG,
    Channel::AlbedoB,
    Channel::RefR,
    Channel::RefG,
    Channel::RefB,
];

/// Pixels' channels: one row-major plane per channel held, indexed by [`Channel`].
#[derive(Clone, Debug, PartialEq)]
pub struct Planes([Option<Vec<f32>>; Channel::COUNT]);

impl Planes {
    /// `n` pixels of the channels `holds` keeps, at their blank values.
    pub fn new(n: usize, holds: Holds) -> Planes {
        Planes(std::array::from_fn(|c| {
            let l = &LAYERS[c];
            holds.held(l.held).then(|| vec![l.blank; n])
        }))
    }

    /// Channel `c`'s plane; `None` where not held.
    #[inline]
    pub fn plane(&self, c: Channel) -> Option<&[f32]> {
        self.0[c as usize].as_deref()
    }

    /// Channel `c` of pixel `i` (for a channel not held, the value files list, else 0).
    #[inline]
    pub fn get(&self, c: Channel, i: usize) -> f32 {
        match &self.0[c as usize] {
            Some(p) => p[i],
            None => match c.layer().listed {
                Listed::Always(v) => v,
                _ => 0.0,
            },
        }
    }

    /// Sets channel `c` of pixel `i` (nothing for a channel not held).
    #[inline]
    pub fn set(&mut self, c: Channel, i: usize, v: f32) {
        if let Some(p) = &mut self.0[c as usize] {
            p[i] = v;
        }
    }
}
