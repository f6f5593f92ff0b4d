//! Which lights are traced beyond what the votes settle, and where a trace floods to
//! (ALGORITHM.md §6). A flood rule turns the votes into a prediction (blocked, and unsure:
//! traced), may queue more lights (the boundary rule queues the prediction's edges), and says
//! which traces flood: queue their untraced above-horizon neighbour lights too, until no trace
//! disagrees. Which neighbours a flooding trace queues is [`FloodTo`] (`--flood-to`).
//!
//! Rules: [`Uncertainty`](super::uncertainty::Uncertainty) and
//! [`Boundary`](super::boundary::Boundary).

use super::scratch::Scratch;
use crate::context::FrameContext;
use crate::key::Key;

/// A flood rule.
pub trait Flood: Send + Sync + 'static {
    /// The rule's name, as method names spell it (`uncertainty`, `boundary`).
    const NAME: &'static str;
    /// The settings the rule reads.
    const READS: &'static [Key];

    /// How many voters must have a light above their horizon for it to be predicted, given
    /// the `min_voters` setting.
    fn min_voters(setting: u32) -> u32;

    /// Word of the prediction: `(blocked, unsure)` among `my` above-horizon lights, from the
    /// lights with `enough` voters, `any` vote and `all` votes.
    fn predict(my: u64, enough: u64, any: u64, all: u64) -> (u64, u64);

    /// Queues lights beyond the unsure ones (`sc.queued`), given the prediction in
    /// `sc.pred_vis` and the pixel's above-horizon lights `mine`.
    fn queue_more(ctx: &FrameContext, mine: &[u64], sc: &mut Scratch) {
        let _ = (ctx, mine, sc);
    }

    /// Whether a traced light floods: it was `uncertain`, or its trace `disagrees` with the
    /// prediction.
    fn floods(uncertain: bool, disagrees: bool) -> bool;
}

/// Which neighbours a flooding trace queues (`--flood-to`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloodTo {
    /// Every untraced above-horizon neighbour light: a ring around each uncertain or
    /// mispredicted light [ALGORITHM.md §6].
    All,
    /// [ours; what [`Auto`](Self::Auto), the default, takes without cut-outs]
    /// [`Contrary`](Self::Contrary) at the pixels of the grid's finest
    /// level (spacing 1: three pixels in four), [`All`](Self::All) at the coarser levels. A
    /// wrong pair at a coarse pixel is a wrong vote for every finer pixel it predicts; at the
    /// finest level it reaches at most the last pass's pixels, and those vote for nobody. On
    /// the paper's scenes it traces about a fifth fewer rays than `all` for 0–3.5 % more wrong
    /// pairs (BENCHMARKS.md, "Where the default method's rays go"). With samples per pixel
    /// the levels whose voters lie inside a pixel (closer than k samples) count as finest
    /// too: a wrong pair there misleads only samples of the same pixel (about 10 % fewer
    /// rays at 16 spp for 1–2 % more wrong pairs). Orders without levels (the scanline)
    /// flood to all.
    ContraryFinest,
    /// [ours] Only the untraced above-horizon neighbours whose prediction is the opposite of
    /// the traced answer: the border between the two lights is where the prediction and the
    /// truth disagree. A neighbour predicted like the traced answer is taken as predicted.
    /// On the paper's scenes it traces about a third fewer rays for 1.1–1.9× the wrong pairs
    /// (BENCHMARKS.md, "Flooding only to contrary neighbours").
    Contrary,
    /// [ours] Decided at each pixel from its voters: [`All`](Self::All) where some voter's own
    /// flooding caught a wrong prediction (the shadows there are finer than the voters'
    /// spacing), [`Contrary`](Self::Contrary) where none did. Measured on the corpus and not
    /// the default (BENCHMARKS.md, "Issue 23").
    Adaptive,
    /// [ours, the default: [`Params::DEFAULT`](super::params::Params::DEFAULT)]
    /// [`All`](Self::All) where the frame's geometry has cut-out (alpha
    /// MASK or BLEND) triangles, [`ContraryFinest`](Self::ContraryFinest) elsewhere
    /// ([`resolved`](Self::resolved)). A hole in a mask flips one light without flipping its
    /// neighbours the way an edge does, so contrary flooding misses the lights beside it: on
    /// the corpus's masked panels `contrary-finest` left 0.11–0.17 % wrong pairs, `all`
    /// 0.049–0.053 % for 13–20 % more rays (BENCHMARKS.md, "Cut-out panels").
    Auto,
}

impl FloodTo {
    pub const ALL: [FloodTo; 5] = [
        FloodTo::All,
        FloodTo::ContraryFinest,
        FloodTo::Contrary,
        FloodTo::Adaptive,
        FloodTo::Auto,
    ];

    /// The name on the command line and in animation specs.
    pub fn name(self) -> &'static str {
        match self {
            FloodTo::All => "all",
            FloodTo::ContraryFinest => "contrary-finest",
            FloodTo::Contrary => "contrary",
            FloodTo::Adaptive => "adaptive",
            FloodTo::Auto => "auto",
        }
    }

    /// [`Auto`](Self::Auto) decided for a frame whose geometry has cut-out triangles
    /// (`cutouts`) or not; every other rule as it is.
    pub fn resolved(self, cutouts: bool) -> FloodTo {
        match self {
            FloodTo::Auto if cutouts => FloodTo::All,
            FloodTo::Auto => FloodTo::ContraryFinest,
            f => f,
        }
    }

    /// The rule at a pixel of the order's finest levels (`finest`) or a coarser one:
    /// [`ContraryFinest`](Self::ContraryFinest) resolved to what the flooding applies there.
    /// [`Auto`](Self::Auto), if not [`resolved`](Self::resolved) yet, as `contrary-finest`.
    pub fn at_level(self, finest: bool) -> FloodTo {
        match self {
            FloodTo::ContraryFinest | FloodTo::Auto if finest => FloodTo::Contrary,
            FloodTo::ContraryFinest | FloodTo::Auto => FloodTo::All,
            f => f,
        }
    }
}

impl std::fmt::Display for FloodTo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FloodTo {
    type Err = String;
    fn from_str(s: &str) -> Result<FloodTo, String> {
        FloodTo::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = FloodTo::ALL.iter().map(|f| f.name()).collect();
                let (last, rest) = names.split_last().expect("flood rules");
                format!(
                    "unknown flood rule {s:?}; expected {} or {last}",
                    rest.join(", ")
                )
            })
    }
}

/// Truth tables shared by the flood rules' tests.
#[cfg(test)]
pub(super) mod table {
    /// One combination of `predict`'s inputs at one light, and the `(blocked, unsure)` the rule
    /// must give: `(my, enough, any, all)`. `all` implies `any` (the votes guarantee it).
    pub type Row = ((bool, bool, bool, bool), (bool, bool));

    /// Calls `predict` once on words holding row r at bit r and lists every row it gets wrong.
    pub fn predict_failures(
        predict: fn(u64, u64, u64, u64) -> (u64, u64),
        rows: &[Row],
    ) -> Vec<String> {
        let word = |f: fn(&Row) -> bool| {
            rows.iter()
                .enumerate()
                .fold(0u64, |w, (r, row)| w | u64::from(f(row)) << r)
        };
        let (blocked, unsure) = predict(
            word(|r| r.0.0),
            word(|r| r.0.1),
            word(|r| r.0.2),
            word(|r| r.0.3),
        );
        let mut failures = Vec::new();
        for (r, &(inputs, want)) in rows.iter().enumerate() {
            let got = (blocked >> r & 1 == 1, unsure >> r & 1 == 1);
            if got != want {
                failures.push(format!(
                    "(my, enough, any, all) = {inputs:?}: (blocked, unsure) {got:?}, want {want:?}"
                ));
            }
        }
        failures
    }

    /// Lists the `(uncertain, disagrees)` combinations where `floods` is not `want`.
    pub fn floods_failures(
        floods: fn(bool, bool) -> bool,
        want: [((bool, bool), bool); 4],
    ) -> Vec<String> {
        want.iter()
            .filter(|&&((u, d), w)| floods(u, d) != w)
            .map(|((u, d), w)| format!("floods(uncertain {u}, disagrees {d}) should be {w}"))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `at_level` resolves `contrary-finest` alone.
    #[test]
    fn only_contrary_finest_depends_on_the_level() {
        let want = [
            (FloodTo::All, [FloodTo::All, FloodTo::All]),
            (FloodTo::ContraryFinest, [FloodTo::All, FloodTo::Contrary]),
            (FloodTo::Contrary, [FloodTo::Contrary, FloodTo::Contrary]),
        ];
        for (f, [coarse, finest]) in want {
            assert_eq!(
                (f.at_level(false), f.at_level(true)),
                (coarse, finest),
                "{f}"
            );
        }
    }
}
