//! Uncertainty flooding (ALGORITHM.md §6) [paper idea, ours exact rule]: a light is predicted
//! only when at least `min_voters` voters have it above their horizon and they agree — every
//! such voter votes blocked → blocked, none does → visible; otherwise it is uncertain and
//! traced, and its trace floods to its neighbour lights.

use super::flood::Flood;
use crate::key::Key;

/// Trace what the voters disagree on (or see too little of), and flood from it.
pub struct Uncertainty;

impl Flood for Uncertainty {
    const NAME: &'static str = "uncertainty";
    const READS: &'static [Key] = &[
        Key::MinVoters,
        Key::FloodTo,
        Key::Temporal,
        Key::Keyframe,
        Key::SurfaceVoters,
        Key::AllVoters,
        Key::BusyVoters,
        Key::TraceAllShare,
    ];

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

#[cfg(test)]
mod tests {
    use super::super::flood::table;
    use super::*;

    #[test]
    fn predicts_only_what_enough_voters_agree_on() {
        let (t, f) = (true, false);
        let rows = [
            // Below this pixel's horizon: neither, whatever the votes.
            ((f, f, f, f), (f, f)),
            ((f, t, f, f), (f, f)),
            ((f, t, t, f), (f, f)),
            ((f, t, t, t), (f, f)),
            ((f, f, t, t), (f, f)),
            // Too few voters see it: traced, whatever they say.
            ((t, f, f, f), (f, t)),
            ((t, f, t, f), (f, t)),
            ((t, f, t, t), (f, t)),
            // Enough voters: none votes → visible, some → unsure, all → blocked.
            ((t, t, f, f), (f, f)),
            ((t, t, t, f), (f, t)),
            ((t, t, t, t), (t, f)),
        ];
        let failures = table::predict_failures(Uncertainty::predict, &rows);
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    #[test]
    fn floods_when_uncertain_or_mistaken() {
        let (t, f) = (true, false);
        let want = [((f, f), f), ((f, t), t), ((t, f), t), ((t, t), t)];
        let failures = table::floods_failures(Uncertainty::floods, want);
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    #[test]
    fn min_voters_is_the_setting() {
        for s in 1..=4 {
            assert_eq!(Uncertainty::min_voters(s), s);
        }
    }
}
