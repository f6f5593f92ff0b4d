//! Uncertainty flooding (ALGORITHM.md §6) [paper idea, ours exact rule]: a light is predicted
//! only when at least `min_voters` voters have it above their horizon and they agree — every
//! such voter votes blocked → blocked, none does → visible; otherwise it is uncertain and
//! traced, and its trace floods to its neighbour lights.

use super::Flood;

/// Trace what the voters disagree on (or see too little of), and flood from it.
pub struct Uncertainty;

impl Flood for Uncertainty {
    const NAME: &'static str = "uncertainty";
    const READS: &'static [&'static str] = &["min_voters", "flood_to", "temporal", "keyframe"];

    fn min_voters(setting: u32) -> u32 {
        setting
    }

    #[inline]
    fn predict(my: u64, enough: u64, any: u64, all: u64) -> (u64, u64) {
        (my & enough & all, my & (!enough | (any & !all)))
    }

    #[inline]
    fn floods(uncertain: bool, disagrees: bool) -> bool {
        uncertain || disagrees
    }
}
