//! No warp (ALGORITHM.md §4) [paper]: a voter's blocked light votes for that same light at the
//! current pixel. Word operations only.

use super::scratch::Scratch;
use super::vote::Vote;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Three voters; each light is a bit with its own story. `above` and `vis` are the voters'
    /// words, `any` and `all` what the votes must be.
    #[test]
    fn a_voter_votes_for_the_lights_it_found_blocked_above_its_horizon() {
        // bit 0: above at every voter, blocked at every voter     → any, all
        // bit 1: above at voters 0 and 1 only, blocked at both     → any, all (voter 2 has no say)
        // bit 2: above at every voter, blocked at voter 1 only     → any, not all
        // bit 3: above at every voter, blocked at none             → neither
        // bit 4: above at no voter (and so not visible there)      → neither
        // bit 5: above at voter 2 only, blocked there              → any, all
        // bit 6: above at voters 0 and 2, blocked at 2 only        → any, not all
        let above = [0b100_1111u64, 0b000_1111, 0b110_1101];
        let vis = [0b100_1100u64, 0b000_1000, 0b000_1100];
        let (want_any, want_all) = (0b110_0111u64, 0b010_0011u64);
        let bufs = TileBuffers {
            words: 1,
            vis: vis.to_vec(),
            ..TileBuffers::default()
        };
        let (any, all) = NoWarp::word(&bufs, &Scratch::default(), &[0, 1, 2], 0, &above);
        assert_eq!(
            (any, all),
            (want_any, want_all),
            "(any, all) = ({any:#b}, {all:#b}), want ({want_any:#b}, {want_all:#b})"
        );
    }

    /// Voters are read at their own place in the buffers and at word `m` of it.
    #[test]
    fn votes_read_each_voters_own_word() {
        // Two words per pixel; voters are pixels 2 and 0, word 1 is asked for. Word 0 of every
        // pixel is all blocked, pixel 1 (no voter) too: neither may vote.
        let bufs = TileBuffers {
            words: 2,
            vis: vec![0, 0b01, 0, 0, 0, 0b10],
            ..TileBuffers::default()
        };
        let above = [0b11u64, 0b11];
        let (any, all) = NoWarp::word(&bufs, &Scratch::default(), &[2, 0], 1, &above);
        // Light 64: pixel 2 blocked, pixel 0 visible; light 65: pixel 2 visible, pixel 0
        // blocked. Both got a vote, neither every vote.
        assert_eq!((any, all), (0b11, 0b00));
    }
}
