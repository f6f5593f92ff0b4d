//! How voters vote (ALGORITHM.md §4): each valid neighbour (evaluated, not background) votes
//! for the lights it believes blocked at the current pixel. A rule answers, word by word of
//! the light bitset, which lights got *some* vote and which got *every* vote they could — one
//! from each voter with the light above its horizon ([ours]: K_j such voters, votes_j ≥ K_j
//! read as "all agree"). The flood rule turns that into a prediction.
//!
//! Rules: [`NoWarp`](super::nowarp::NoWarp) (a voter's blocked light votes for itself) and
//! [`Warp`](super::warp::Warp) (a voter's blockers, re-aimed from the current point, vote for
//! the cell they land in).

use super::scratch::Scratch;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;

/// A voting rule.
pub trait Vote: Send + Sync + 'static {
    /// The rule's name, as method names spell it (`warp`, `nowarp`).
    const NAME: &'static str;
    /// Whether the votes read the voters' blockers (which voters then keep).
    const READS_BLOCKERS: bool;

    /// Before the words: gathers what the votes for region pixel `i` need from its `voters`.
    fn gather(
        ctx: &FrameContext,
        bufs: &TileBuffers,
        sc: &mut Scratch,
        i: usize,
        voters: &[usize],
    ) {
        let _ = (ctx, bufs, sc, i, voters);
    }

    /// Word `m` of the votes: `(any, all)` — lights some voter votes blocked, and lights every
    /// voter with them above its horizon votes blocked (meaningful where `any`). `above`
    /// holds word `m` of each voter's above-horizon lights, in `voters`' order.
    fn word(
        bufs: &TileBuffers,
        sc: &Scratch,
        voters: &[usize],
        m: usize,
        above: &[u64],
    ) -> (u64, u64);
}
