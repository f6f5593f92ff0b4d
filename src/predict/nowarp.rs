//! No warp (ALGORITHM.md §4) [paper]: a voter's blocked light votes for that same light at the
//! current pixel. Word operations only.

use super::{Scratch, Vote};
use crate::buffers::TileBuffers;

/// Neighbours' own visibility votes.
pub struct NoWarp;

impl Vote for NoWarp {
    const NAME: &'static str = "nowarp";
    const READS_BLOCKERS: bool = false;

    #[inline]
    fn word(
        bufs: &TileBuffers,
        _sc: &Scratch,
        voters: &[usize],
        m: usize,
        above: &[u64],
    ) -> (u64, u64) {
        let w = bufs.words;
        let (mut all, mut any) = (!0u64, 0u64);
        for (k, &q) in voters.iter().enumerate() {
            let blocked = above[k] & !bufs.vis[q * w + m];
            all &= !above[k] | blocked;
            any |= blocked;
        }
        (any, all & any)
    }
}
