//! A tile's working buffers: for every pixel of the tile and its halo, the surface its
//! primary ray found, its above-horizon, visible and traced lights as bitsets, its rays and
//! why they were traced, and its blockers. Flat arrays indexed by the pixel's place in the
//! region; no per-pixel heap vectors.

use crate::accel::PACKET;
use crate::bits;
use crate::blockers::Blockers;
use crate::context::{FrameContext, Surface};
use crate::tile::Rect;

/// Why a pixel's shadow rays were traced, for measuring where the work goes. The rays
/// neither counted here were queued by the pixel's own prediction (lights its voters disagree
/// on, see too few of, or that border a predicted shadow).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RaySplit {
    /// Rays of a pixel that traced every above-horizon light (the coarse grid, pixels without
    /// voters, brute force).
    pub every: u32,
    /// Rays queued by flooding.
    pub flooded: u32,
    /// Flooded rays whose answer differed from the prediction: wrong pairs flooding caught.
    pub fixes: u32,
}

/// A tile's pixels while its method decides them, reused across tiles by one thread. Flat arrays and bitsets only:
/// `words` u64 per pixel for each bitset (read with [`bits::rows`]), indexed by the pixel's
/// position in `region`.
#[derive(Default)]
pub struct TileBuffers {
    /// The pixels this tile outputs.
    pub tile: Rect,
    /// The pixels the buffers cover: the tile plus whatever halo its method reads.
    pub region: Rect,
    pub words: usize,
    /// Surfaces over `region` (valid where `needed`).
    pub surf: Vec<Surface>,
    /// Pixels the method evaluated (the tile's own pixels and its halo).
    pub needed: Vec<bool>,
    /// Pixels whose surface is already in `surf`, their primary rays traced together with
    /// their pixel's other samples' ([`FrameContext::surfaces`]) before the method begins
    /// them.
    pub primed: Vec<bool>,
    /// Pixels whose data is this tile's: evaluated here or copied from the frame's lattice.
    /// The other pixels' rows hold whatever an earlier tile left (see [`prepare`]).
    ///
    /// [`prepare`]: Self::prepare
    pub valid: Vec<bool>,
    /// Pixels that may vote: valid, and their primary ray hit the scene. Kept beside `surf`
    /// so a pixel's voters are checked without loading their surfaces (a cache miss each, a
    /// sixth of a pixel's bookkeeping at 4 spp).
    pub voter: Vec<bool>,
    /// Lights above each pixel's horizon: its shadow queries.
    pub above: Vec<u64>,
    /// Lights visible from each pixel (traced or predicted).
    pub vis: Vec<u64>,
    /// Lights traced at each pixel.
    pub traced: Vec<u64>,
    /// Shadow rays traced per pixel.
    pub rays: Vec<u32>,
    /// Why they were traced.
    pub split: Vec<RaySplit>,
    /// Pixels predicted from the previous frame (`--temporal`).
    pub temporal: Vec<bool>,
    /// Per pixel predicted from the previous frame, its lights whose previous visibility was
    /// dropped because what a file's animation moved may cross their rays.
    pub stale: Vec<u32>,
    /// Blockers, for the warping methods.
    pub blockers: Blockers,
    /// The last pixel begun on a surface: one with the same normal has the same lights above
    /// its horizon (samples of one pixel on a flat surface nearly always).
    pub(crate) last_begun: Option<usize>,
}

/// `v` at least `n` long, its contents left as they are (each pixel's are reset when used).
fn grow<T: Clone + Default>(v: &mut Vec<T>, n: usize) {
    if v.len() < n {
        v.resize(n, T::default());
    }
}

impl TileBuffers {
    /// Sizes the buffers for `tile` within `region` (⊇ tile); nothing is evaluated yet.
    ///
    /// Only the per-pixel flags are cleared: a pixel's rows are reset when it is begun
    /// ([`begin_pixel`](Self::begin_pixel)) or copied in from the lattice, and nothing reads
    /// a pixel that is not [`valid`](Self::valid). Clearing every row of a region of samples
    /// (16 spp, 400 lights: 20 MB a tile) cost more than a no-shadow frame's shading.
    pub fn prepare(&mut self, ctx: &FrameContext, tile: Rect, region: Rect) {
        self.tile = tile;
        self.region = region;
        self.words = ctx.words();
        let n = region.area();
        let nw = n * self.words;
        grow(&mut self.surf, n);
        self.needed.clear();
        self.needed.resize(n, false);
        self.primed.clear();
        self.primed.resize(n, false);
        self.valid.clear();
        self.valid.resize(n, false);
        self.voter.clear();
        self.voter.resize(n, false);
        for v in [&mut self.above, &mut self.vis, &mut self.traced] {
            grow(v, nw);
        }
        grow(&mut self.rays, n);
        grow(&mut self.split, n);
        grow(&mut self.temporal, n);
        grow(&mut self.stale, n);
        self.blockers.reserve(n);
        self.last_begun = None;
    }

    /// Marks region pixel `i` as holding this tile's data, with nothing yet traced, predicted
    /// or kept: its visible and traced lights, rays and blockers empty.
    #[inline]
    pub fn reset_pixel(&mut self, i: usize) {
        let w = self.words;
        self.valid[i] = true;
        self.voter[i] = self.surf[i].hit;
        bits::rows_mut(&mut self.vis, w).row_mut(i).fill(0);
        bits::rows_mut(&mut self.traced, w).row_mut(i).fill(0);
        self.rays[i] = 0;
        self.split[i] = RaySplit::default();
        self.temporal[i] = false;
        self.stale[i] = 0;
        self.blockers.begin(i);
    }

    /// Evaluates pixel (x, y) of the region: its surface (traced now unless
    /// [`primed`](Self::primed)) and above-horizon lights. Marks it needed and returns its
    /// region index.
    #[inline]
    pub fn begin_pixel(&mut self, ctx: &FrameContext, x: u32, y: u32) -> usize {
        let i = self.region.index(x, y);
        if !self.primed[i] {
            self.surf[i] = ctx.surface(x, y);
        }
        self.needed[i] = true;
        self.reset_pixel(i);
        let s = &self.surf[i];
        let mut above = bits::rows_mut(&mut self.above, self.words);
        if !s.hit {
            above.row_mut(i).fill(0);
        } else {
            match self.last_begun {
                Some(l)
                    if crate::shade::same(self.surf[l].n, s.n)
                        && crate::shade::same(self.surf[l].ng, s.ng) =>
                {
                    above.copy_row(l, i);
                }
                _ => crate::shade::above_both_horizons(
                    &ctx.shade_lights,
                    s.n,
                    s.ng,
                    above.row_mut(i),
                ),
            }
            if ctx.has_points() {
                // Point and spot lights: from this point, whatever the normal.
                ctx.point_lights_above(s, above.row_mut(i));
            }
            self.last_begun = Some(i);
        }
        i
    }

    /// Traces every above-horizon light of pixel `i` (the coarse pixels and pixels with no
    /// voters), keeping blockers when `keep_blockers`.
    pub fn trace_all(&mut self, ctx: &FrameContext, i: usize, keep_blockers: bool) {
        let w = self.words;
        let s = self.surf[i];
        if !s.hit {
            return;
        }
        self.blockers.begin(i);
        if keep_blockers {
            for k in 0..w {
                let mut m = self.above[i * w + k];
                while m != 0 {
                    let j = k * 64 + m.trailing_zeros() as usize;
                    m &= m - 1;
                    match ctx.trace_blocker(&s, j) {
                        Some(t) => self.blockers.push(i, j, t),
                        None => self.vis[i * w + k] |= 1 << (j & 63),
                    }
                }
            }
        } else {
            // Packets of up to PACKET lights from the pixel's point.
            let mut batch = [0u32; PACKET];
            let mut len = 0;
            let vis = bits::rows_mut(&mut self.vis, w).into_row(i);
            let mut flush = |batch: &[u32]| {
                let blocked = ctx.trace_packet(&s, batch);
                for (k, &j) in batch.iter().enumerate() {
                    if blocked & (1 << k) == 0 {
                        bits::set(vis, j as usize);
                    }
                }
            };
            bits::for_each(bits::rows(&self.above, w).row(i), |j| {
                batch[len] = j as u32;
                len += 1;
                if len == PACKET {
                    flush(&batch);
                    len = 0;
                }
            });
            if len > 0 {
                flush(&batch[..len]);
            }
        }
        let above = bits::rows(&self.above, w).row(i);
        bits::rows_mut(&mut self.traced, w)
            .row_mut(i)
            .copy_from_slice(above);
        self.rays[i] = bits::count(above);
        self.split[i] = RaySplit {
            every: self.rays[i],
            ..RaySplit::default()
        };
    }
}
