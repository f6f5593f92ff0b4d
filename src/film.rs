//! The film: a frame's beauty and AOV buffers, assembled from finished tiles, and the counts
//! of the work that made them.

use std::ops::AddAssign;

use crate::tile::Rect;
use crate::view::View;

/// A finished tile: beauty and AOVs for the tile's pixels, and its counts.
#[derive(Clone, Debug)]
pub struct TileResult {
    pub rect: Rect,
    /// Linear RGB radiance: the mean of the pixel's samples.
    pub beauty: Vec<[f32; 3]>,
    /// Shadow rays traced per pixel (all its samples).
    pub rays: Vec<f32>,
    /// Fraction of the above-horizon lights that are visible, the mean over the pixel's
    /// samples (a background sample counts 0).
    pub visible: Vec<f32>,
    /// With validation: wrong (sample, light) pairs per pixel, and the brute-force beauty.
    pub wrong: Option<Vec<f32>>,
    pub reference: Option<Vec<[f32; 3]>>,
    /// With several samples per pixel: the fraction of them that hit the scene.
    pub coverage: Option<Vec<f32>>,
    /// Over a transparent background: each pixel's alpha (see [`Film::alpha`]).
    pub alpha: Option<Vec<f32>>,
    /// The compositor's passes ([`Film::depth`], [`Film::normal`], [`Film::albedo`]).
    pub depth: Vec<f32>,
    pub normal: Vec<[f32; 3]>,
    pub albedo: Vec<[f32; 3]>,
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

/// One frame's pixels: linear RGB beauty and the per-pixel AOVs, row-major, full frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub beauty: Vec<[f32; 3]>,
    /// Shadow rays traced per pixel.
    pub rays: Vec<f32>,
    /// Fraction of above-horizon lights visible.
    pub visible: Vec<f32>,
    /// With validation: wrong (sample, light) pairs per pixel, and the brute-force image.
    pub wrong: Option<Vec<f32>>,
    pub reference: Option<Vec<[f32; 3]>>,
    /// With several samples per pixel: the fraction of each pixel's samples that hit the
    /// scene (at one sample it would be the hit mask, and is not kept).
    pub coverage: Option<Vec<f32>>,
    /// Over a transparent background (`[render] background`): each pixel's alpha, the mean
    /// over its samples (placed by the pixel filter, so weighted as the beauty is) of 1 where a
    /// sample sees the model, the shadow fraction where it sees a shadow catcher and 0 where
    /// it sees the background; the beauty is premultiplied by it. `None`: alpha is 1
    /// everywhere (an opaque background).
    pub alpha: Option<Vec<f32>>,
    /// Camera depth: the distance along the view direction to the nearest surface any of
    /// the pixel's samples hit ([ours], as Arnold's "closest" filter: a mean across a
    /// silhouette would be a depth where nothing is); [`BACKGROUND_DEPTH`] where none hit.
    pub depth: Vec<f32>,
    /// World-space shading normal (turned towards the camera), the mean over the pixel's
    /// samples with background samples counting 0, not renormalised (as Cycles' Normal pass).
    pub normal: Vec<[f32; 3]>,
    /// Surface albedo (linear RGB base colour, textured), the mean over the pixel's samples
    /// with background samples counting 0.
    pub albedo: Vec<[f32; 3]>,
    /// Sum of the tiles' counts.
    pub counts: Counts,
}

impl Film {
    /// An empty film; `validated` keeps the wrong pairs and the reference image, `coverage`
    /// the fraction of samples that hit.
    pub fn new(width: u32, height: u32, validated: bool, coverage: bool) -> Film {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            beauty: vec![[0.0; 3]; n],
            rays: vec![0.0; n],
            visible: vec![0.0; n],
            wrong: validated.then(|| vec![0.0; n]),
            reference: validated.then(|| vec![[0.0; 3]; n]),
            coverage: coverage.then(|| vec![0.0; n]),
            alpha: None,
            depth: vec![BACKGROUND_DEPTH; n],
            normal: vec![[0.0; 3]; n],
            albedo: vec![[0.0; 3]; n],
            counts: Counts::default(),
        }
    }

    /// This film with an alpha plane (a transparent background) when `alpha` is true; pixels
    /// no tile rendered stay at 0, transparent like the black around a region render.
    pub fn with_alpha(mut self, alpha: bool) -> Film {
        self.alpha = alpha.then(|| vec![0.0; self.beauty.len()]);
        self
    }

    /// Whether some pixel is less than opaque.
    pub fn has_transparency(&self) -> bool {
        self.alpha
            .as_ref()
            .is_some_and(|a| a.iter().any(|&v| v < 1.0))
    }

    /// Copies a finished tile into place and adds its counts.
    pub fn add(&mut self, tile: &TileResult) {
        let r = tile.rect;
        let w = r.width() as usize;
        for y in r.y0..r.y1 {
            let src = (y - r.y0) as usize * w;
            let dst = y as usize * self.width as usize + r.x0 as usize;
            self.beauty[dst..dst + w].copy_from_slice(&tile.beauty[src..src + w]);
            self.rays[dst..dst + w].copy_from_slice(&tile.rays[src..src + w]);
            self.visible[dst..dst + w].copy_from_slice(&tile.visible[src..src + w]);
            self.depth[dst..dst + w].copy_from_slice(&tile.depth[src..src + w]);
            self.normal[dst..dst + w].copy_from_slice(&tile.normal[src..src + w]);
            self.albedo[dst..dst + w].copy_from_slice(&tile.albedo[src..src + w]);
            if let (Some(d), Some(s)) = (&mut self.wrong, &tile.wrong) {
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
            if let (Some(d), Some(s)) = (&mut self.reference, &tile.reference) {
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
            if let (Some(d), Some(s)) = (&mut self.coverage, &tile.coverage) {
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
            if let (Some(d), Some(s)) = (&mut self.alpha, &tile.alpha) {
                d[dst..dst + w].copy_from_slice(&s[src..src + w]);
            }
        }
        self.counts += tile.counts;
    }

    /// The channels this film holds, in the order files list them: beauty, the compositor's
    /// passes, the shadow method's (alpha always: 1 over an opaque background); with `reference` also the brute-force image (farm tile
    /// images carry it, frames do not).
    pub fn channels(&self, reference: bool) -> Vec<Channel> {
        use Channel::*;
        let mut v = vec![
            R, G, B, A, Z, NX, NY, NZ, AlbedoR, AlbedoG, AlbedoB, Rays, Visible,
        ];
        if self.wrong.is_some() {
            v.push(Wrong);
        }
        if self.coverage.is_some() {
            v.push(Coverage);
        }
        if reference && self.reference.is_some() {
            v.extend([RefR, RefG, RefB]);
        }
        v
    }

    /// Channel `c` of pixel `i` (0 for a channel the film does not hold).
    #[inline]
    pub fn get(&self, c: Channel, i: usize) -> f32 {
        use Channel::*;
        let opt = |v: &Option<Vec<f32>>| v.as_ref().map_or(0.0, |v| v[i]);
        let opt3 = |v: &Option<Vec<[f32; 3]>>, k: usize| v.as_ref().map_or(0.0, |v| v[i][k]);
        match c {
            R => self.beauty[i][0],
            G => self.beauty[i][1],
            B => self.beauty[i][2],
            A => self.alpha.as_ref().map_or(1.0, |a| a[i]),
            Z => self.depth[i],
            NX => self.normal[i][0],
            NY => self.normal[i][1],
            NZ => self.normal[i][2],
            AlbedoR => self.albedo[i][0],
            AlbedoG => self.albedo[i][1],
            AlbedoB => self.albedo[i][2],
            Rays => self.rays[i],
            Visible => self.visible[i],
            Wrong => opt(&self.wrong),
            Coverage => opt(&self.coverage),
            RefR => opt3(&self.reference, 0),
            RefG => opt3(&self.reference, 1),
            RefB => opt3(&self.reference, 2),
        }
    }

    /// Sets channel `c` of pixel `i` (nothing for a channel the film does not hold).
    #[inline]
    pub fn set(&mut self, c: Channel, i: usize, v: f32) {
        use Channel::*;
        fn put(o: &mut Option<Vec<f32>>, i: usize, v: f32) {
            if let Some(o) = o {
                o[i] = v;
            }
        }
        fn put3(o: &mut Option<Vec<[f32; 3]>>, i: usize, k: usize, v: f32) {
            if let Some(o) = o {
                o[i][k] = v;
            }
        }
        match c {
            R => self.beauty[i][0] = v,
            G => self.beauty[i][1] = v,
            B => self.beauty[i][2] = v,
            A => put(&mut self.alpha, i, v),
            Z => self.depth[i] = v,
            NX => self.normal[i][0] = v,
            NY => self.normal[i][1] = v,
            NZ => self.normal[i][2] = v,
            AlbedoR => self.albedo[i][0] = v,
            AlbedoG => self.albedo[i][1] = v,
            AlbedoB => self.albedo[i][2] = v,
            Rays => self.rays[i] = v,
            Visible => self.visible[i] = v,
            Wrong => put(&mut self.wrong, i, v),
            Coverage => put(&mut self.coverage, i, v),
            RefR => put3(&mut self.reference, i, 0, v),
            RefG => put3(&mut self.reference, i, 1, v),
            RefB => put3(&mut self.reference, i, 2, v),
        }
    }

    /// With validation: the beauty against the brute-force image over `region` (the rendered
    /// pixels); the relative RMSE is relative to the brute-force image's mean.
    pub fn image_error(&self, region: Rect, exposure: f32, view: View) -> Option<ImageError> {
        let reference = self.reference.as_ref()?;
        let (mut se, mut sum_ref, mut n, mut se_ldr) = (0f64, 0f64, 0u64, 0f64);
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let i = y as usize * self.width as usize + x as usize;
                let (b, r) = (self.beauty[i], reference[i]);
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
    R,
    G,
    B,
    /// Alpha ([`Film::alpha`]; 1 over an opaque background).
    A,
    /// Camera depth ([`Film::depth`]).
    Z,
    /// World-space normal ([`Film::normal`]).
    NX,
    NY,
    NZ,
    /// Albedo ([`Film::albedo`]).
    AlbedoR,
    AlbedoG,
    AlbedoB,
    /// The shadow method's work and answers: rays traced at the pixel (all its samples),
    /// the fraction of above-horizon lights visible, wrong pairs (validation), the fraction
    /// of samples that hit the scene (several samples per pixel).
    Rays,
    Visible,
    Wrong,
    Coverage,
    /// The brute-force image (validation; farm tile images only).
    RefR,
    RefG,
    RefB,
}

impl Channel {
    /// The channel's name in an EXR file.
    pub fn name(self) -> &'static str {
        use Channel::*;
        match self {
            R => "R",
            G => "G",
            B => "B",
            A => "A",
            Z => "Z",
            NX => "N.X",
            NY => "N.Y",
            NZ => "N.Z",
            AlbedoR => "albedo.R",
            AlbedoG => "albedo.G",
            AlbedoB => "albedo.B",
            Rays => "shadow.rays",
            Visible => "shadow.visible",
            Wrong => "shadow.wrong",
            Coverage => "shadow.coverage",
            RefR => "reference.R",
            RefG => "reference.G",
            RefB => "reference.B",
        }
    }

    /// Whether the channel stays 32-bit float in a half-float EXR (`--half`) [ours]: counts
    /// (rays up to 4096 lights × 64 samples, wrong pairs) are whole numbers beyond half's
    /// 2048, and depth needs more than half's 11 bits (and its range: the background's 1e10).
    pub fn exact(self) -> bool {
        matches!(self, Channel::Z | Channel::Rays | Channel::Wrong)
    }
}
