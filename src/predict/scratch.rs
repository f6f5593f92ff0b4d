//! A thread's per-pixel scratch for the prediction, reused from pixel to pixel: the prediction
//! as bitsets, the flood queue, and the warped-blocker tallies. The tile driver keeps one
//! beside each thread's tile buffers.

/// Reused per-pixel scratch: bitsets, the flood queue, warped-blocker bookkeeping.
#[derive(Default)]
pub struct Scratch {
    words: usize,
    /// The prediction: visible lights, lights the voters are unsure of, lights queued to trace.
    pub(super) pred_vis: Vec<u64>,
    pub(super) uncertain: Vec<u64>,
    pub(super) queued: Vec<u64>,
    pub(super) queue: Vec<u32>,
    /// Warped blockers per cell, and the cells that got any (set bits: some vote; every
    /// above-horizon voter's worth of votes).
    pub(super) votes: Vec<u8>,
    pub(super) vote_any: Vec<u64>,
    pub(super) vote_all: Vec<u64>,
    /// Best warped blocker per cell: alignment with the light and distance along it.
    pub(super) best_dot: Vec<f32>,
    pub(super) best_dist: Vec<f32>,
    pub(super) touched: Vec<u32>,
    /// Distance to the traced blocker per light (valid where traced and blocked).
    pub(super) hit_dist: Vec<f32>,
    /// Bitset rows for the temporal predictor ([`EXT_ROWS`] × words).
    pub(super) ext: Vec<u64>,
}

/// Rows of `Scratch::ext`: the temporal prediction (blocked, sure, edge), before and after
/// pulling it through a spinning object's turn, the pixel's grazing lights, and the lights
/// whose rays may cross what a file's animation moved.
pub(super) const EXT_ROWS: usize = 8;

impl Scratch {
    /// Sizes the scratch for `lights` lights.
    pub fn prepare(&mut self, lights: usize) {
        let w = lights.div_ceil(64);
        if self.words == w && self.best_dot.len() == lights {
            return;
        }
        self.words = w;
        self.ext = vec![0; EXT_ROWS * w];
        self.pred_vis = vec![0; w];
        self.uncertain = vec![0; w];
        self.queued = vec![0; w];
        self.queue = Vec::with_capacity(lights);
        self.votes = vec![0; lights];
        self.vote_any = vec![0; w];
        self.vote_all = vec![0; w];
        self.best_dot = vec![f32::NEG_INFINITY; lights];
        self.best_dist = vec![0.0; lights];
        self.touched = Vec::with_capacity(lights);
        self.hit_dist = vec![0.0; lights];
    }
}
