//! The tunable parameters of the prediction methods and their defaults.

use super::flood::FloodTo;

/// The tunable parameters of the prediction methods (ALGORITHM.md §4–5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Params {
    /// Coarse grid spacing h0 (a power of two, 2..=256): coarse pixels trace every light [paper].
    /// Default 16 [ours].
    pub h0: u32,
    /// Uncertainty rule: a light is predicted only when at least this many valid neighbours
    /// have it above their horizon; otherwise it is traced. [ours] ALGORITHM.md says K_j < 2 →
    /// trace; we trace below 3: on the paper scenes at 200 lights, 2 traced 5.6 % with 0.064 %
    /// wrong pairs (bunny), 3 traces 7.8 % with 0.016 % (BENCHMARKS.md).
    pub min_voters: u32,
    /// Which neighbour lights a flooding trace queues: all untraced ones, or [ours] only those
    /// predicted opposite to the traced answer — at the grid's finest level only, or
    /// everywhere; by default ([`FloodTo::Auto`]) all where the frame has cut-outs, the
    /// finest level's contrary ones elsewhere.
    pub flood_to: FloodTo,
    /// Scanline order restarts at frame-anchored blocks of this many pixels, so a tile's
    /// halo is bounded (the paper scans the whole frame) [ours].
    pub scan_block: u32,
    /// [ours] With samples per pixel, at the grid's finest level (voters one sample apart,
    /// inside a pixel), a light on which three of four voters agree is taken from them rather
    /// than traced: a straight shadow edge that leaves three of the four corners of a square on
    /// one side leaves its centre there too. A mistake misleads only samples of the same
    /// pixel (the finest level's diagonal pass votes for its axis pass). Off by default: on
    /// the corpus at 4 spp it saved a sixth of the rays for five times the wrong pairs, 0.27 %
    /// on the cut-out panels (BENCHMARKS.md, "Three voters of four inside a pixel").
    pub pixel_majority: bool,
    /// [ours] Voters must share the pixel's surface: a neighbour whose normal turns more than
    /// about 37° from the pixel's, or whose point lies more than about 17° off the pixel's
    /// tangent plane, does not vote. Measured on the corpus and not the default
    /// (BENCHMARKS.md, "Issue 23").
    pub surface_voters: bool,
    /// [ours] A light is predicted only if every valid voter (at least `min_voters`) has it
    /// above its horizon. Measured on the corpus (BENCHMARKS.md, "Issue 23").
    pub all_voters: bool,
    /// [ours] Where a voter's own flooding caught a wrong prediction, `min_voters` is at
    /// least this (0: off; default 4): the neighbourhood's shadows are finer than the voters'
    /// spacing, so a light only some voters see is traced. On the corpus it kept every frame
    /// under 0.05 % wrong pairs for 6 % more rays (BENCHMARKS.md, "Issue 23").
    pub busy_voters: u32,
    /// [ours] A pixel whose prediction leaves at least this share (percent) of its
    /// above-horizon lights uncertain traces every one of them in full packets instead of
    /// correcting the prediction light by light (0: off; default 40). Such a pixel's voters
    /// know little of it (they straddle a crease or a cut-out's holes), so the lights they
    /// agree on are the ones they mislead it on; past some share, flooding traces most of the
    /// rest anyway, in short waves, and a full packet's rays cost a quarter as much each. On
    /// the corpus it halved the cut-out panels' wrong pairs for about the same rays
    /// (BENCHMARKS.md, "Tracing every light where the voters know little").
    pub trace_all_share: u32,
}

impl Params {
    /// The parameters' defaults: what a spec or command line that leaves a method setting out
    /// gets (the `[render]` settings' list reads them from here).
    pub const DEFAULT: Params = Params {
        h0: 16,
        min_voters: 3,
        flood_to: FloodTo::Auto,
        scan_block: 64,
        pixel_majority: false,
        surface_voters: false,
        all_voters: false,
        busy_voters: 4,
        trace_all_share: 40,
    };

    /// The parameters on a lattice of k × k samples per pixel: the coarse grid and the scan's
    /// blocks keep their size in pixels (the grid's spacing rounded up to a power of two), so
    /// the coarse grid's share of the queries falls as the samples grow denser.
    pub fn for_samples(self, k: u32) -> Params {
        Params {
            h0: (self.h0 * k).next_power_of_two(),
            scan_block: self.scan_block * k,
            ..self
        }
    }

    /// The parameters for a frame whose geometry has cut-out triangles (`cutouts`) or not:
    /// the flood rule [`FloodTo::Auto`] decided.
    pub fn for_cutouts(self, cutouts: bool) -> Params {
        Params {
            flood_to: self.flood_to.resolved(cutouts),
            ..self
        }
    }
}

impl Default for Params {
    fn default() -> Params {
        Params::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_floods_to_all_lights_only_where_the_frame_has_cut_outs() {
        let auto = Params {
            flood_to: FloodTo::Auto,
            ..Params::default()
        };
        assert_eq!(auto.for_cutouts(true).flood_to, FloodTo::All);
        assert_eq!(auto.for_cutouts(false).flood_to, FloodTo::ContraryFinest);
        for f in [
            FloodTo::All,
            FloodTo::ContraryFinest,
            FloodTo::Contrary,
            FloodTo::Adaptive,
        ] {
            for cutouts in [false, true] {
                assert_eq!(f.resolved(cutouts), f, "a rule the user chose is kept");
            }
        }
        assert_eq!("auto".parse::<FloodTo>(), Ok(FloodTo::Auto));
    }
}
