//! Where shadow rays were blocked, per pixel, for the warping votes (ALGORITHM.md §3): a
//! voter's blockers, re-aimed from the pixel being predicted, vote for the lights they land on.

/// Blockers of the evaluated pixels, for the warping predictors: per pixel a run of
/// (light, distance) entries in flat arrays, appended as pixels are evaluated.
#[derive(Default)]
pub struct Blockers {
    pub start: Vec<u32>,
    pub len: Vec<u32>,
    pub light: Vec<u16>,
    pub dist: Vec<f32>,
}

impl Blockers {
    pub(crate) fn reset(&mut self, pixels: usize) {
        self.start.clear();
        self.start.resize(pixels, 0);
        self.len.clear();
        self.len.resize(pixels, 0);
        self.light.clear();
        self.dist.clear();
    }

    /// The blockers of region pixel `i`: (light, distance from the pixel's point).
    #[inline]
    pub fn of(&self, i: usize) -> impl Iterator<Item = (usize, f32)> + '_ {
        let (s, n) = (self.start[i] as usize, self.len[i] as usize);
        self.light[s..s + n]
            .iter()
            .zip(&self.dist[s..s + n])
            .map(|(&j, &t)| (j as usize, t))
    }

    /// Room for `pixels` pixels' runs and no entries; a pixel's run is empty once
    /// [`begin`](Self::begin) starts it (runs of pixels not begun since are stale).
    pub(crate) fn reserve(&mut self, pixels: usize) {
        if self.start.len() < pixels {
            self.start.resize(pixels, 0);
            self.len.resize(pixels, 0);
        }
        self.light.clear();
        self.dist.clear();
    }

    /// Starts pixel `i`'s run; push its entries next.
    #[inline]
    pub fn begin(&mut self, i: usize) {
        self.start[i] = self.light.len() as u32;
        self.len[i] = 0;
    }

    #[inline]
    pub fn push(&mut self, i: usize, light: usize, dist: f32) {
        self.light.push(light as u16);
        self.dist.push(dist);
        self.len[i] += 1;
    }
}
