//! Predicting a pixel while the environment turns (`[motion] kind = "environment"`,
//! ALGORITHM.md §8 [ours]; docs/temporal.md, "Environment rotation").
//!
//! Scene and camera are still, so the pixel's previous self saw the same surface point, whose
//! visibility over the sphere of directions has not changed; only the lights moved, each
//! along its circle of latitude by the frame's turn. Light j keeps its previous visibility
//! unless the previous frame marked it an edge light: its way (the cells a corridor around
//! its path meets, [`crate::lights::Tracks`]) held both visible and blocked or below-horizon
//! lights ([`crate::history::Edges::Track`]). A light that rose above the pixel's horizon has
//! no previous visibility.
//!
//! The spatial voters then decide with it, measured on the bunny (docs/temporal.md):
//! - lights the previous frame is sure of are taken from it unless the spatial voters
//!   disagree among themselves (a shadow edge passes the pixel: 15 % of such lights had
//!   changed) or are sure of the opposite (traced, flooding);
//! - the other lights take the spatial voters' word where they agree, and are traced where
//!   they do not;
//! - the spatial voters are counted as the spatial rule counts them (`--busy-voters`);
//! - every traced light floods, as the spatial rule's uncertain lights do, but never into
//!   lights both the previous frame and the spatial voters are sure of (a thin occluder, a
//!   trunk between two of the previous frame's lights, is found only by flooding into lights
//!   the previous frame alone vouched for);
//! - pixels without spatial voters (the coarse grid, which traces every light in the spatial
//!   method) are left to the spatial method: their fresh traces, checked against by the
//!   pixels predicted from them, keep errors from building up along a chain.

use super::correct::{At, correct_closed};
use super::scratch::Scratch;
use super::uncertainty::Uncertainty;
use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;
use crate::history::Prev;

/// Predicts and corrects region pixel `i` (already begun) from its own previous self in `prev`
/// (an in-place view) and `spatial`, its valid spatial voters. Returns false, touching
/// nothing, where the spatial method decides: no spatial voters, or the previous frame's
/// pixel did not see the same point (a sample other than its pixel's middle one).
// Word loops index several parallel bitsets at once; iterator chains would hide that.
#[allow(clippy::needless_range_loop)]
// The previous frame, the pixel and its spatial voters, the voter threshold, and the flooding.
#[allow(clippy::too_many_arguments)]
pub fn solve_in_place(
    ctx: &FrameContext,
    bufs: &mut TileBuffers,
    sc: &mut Scratch,
    prev: &Prev,
    i: usize,
    spatial: &[usize],
    min_voters: u32,
    at: At,
) -> bool {
    let s = bufs.surf[i];
    if !s.hit || spatial.is_empty() {
        return false;
    }
    let (r, k) = (bufs.region, ctx.samples.k);
    let rw = r.width() as usize;
    let (x, y) = (r.x0 + (i % rw) as u32, r.y0 + (i / rw) as u32);
    let Some(q) = prev.same_point(x / k, y / k, s.p) else {
        return false;
    };
    let w = bufs.words;
    let carried = prev.carried();
    let (above, vis) = (&bufs.above, &bufs.vis);
    let mine = bits::rows(above, w).row(i);
    // Scratch row 0: the lights flooding may not reach.
    let closed = &mut sc.ext;
    for m in 0..w {
        let my = mine[m];
        let (a, v, edge) = carried.word(q, m);
        let (s_blocked, s_sure, s_contested) = spatial_word(above, vis, spatial, w, m, min_voters);
        // Sure from the previous frame: above the horizon then, no edge on its way, and no
        // shadow edge passing the pixel now.
        let t_sure = a & !edge & !s_contested;
        let t_blocked = t_sure & !v;
        let conflict = t_sure & s_sure & (t_blocked ^ s_blocked);
        let settled = (t_sure | s_sure) & !conflict;
        let blocked = t_blocked | (s_blocked & !t_sure);
        // A traced light is expected to be what it was (where it was above the horizon).
        let expect_blocked = a & !v & !settled;
        sc.pred_vis[m] = my & !((blocked & settled) | expect_blocked);
        // [ours] Every traced light floods, as the spatial rule's uncertain lights do; only
        // lights both the previous frame and the spatial voters are sure of are closed to it
        // (closing those only the previous frame vouched for left a thin occluder between two
        // of its lights, a palm's trunk, untraced: 0.12 % wrong pairs instead of 0.044 %).
        sc.uncertain[m] = my & !settled;
        sc.queued[m] = my & !settled;
        closed[m] = my & t_sure & s_sure & settled;
    }
    // Predicted blockers are kept ([ours], docs/methods.md) whatever the spatial order does;
    // flooding follows the spatial voters as the spatial rule's does.
    let at = At {
        keep_predicted: true,
        majority: false,
        inside: false,
        ..at.for_voters(bufs, spatial)
    };
    let closed = std::mem::take(&mut sc.ext);
    correct_closed::<Uncertainty>(ctx, bufs, sc, i, at, &closed[..w]);
    sc.ext = closed;
    bufs.temporal[i] = true;
    true
}

/// Word `m` of what the spatial voters say, as the uncertainty rule reads them: (blocked,
/// sure, contested) — at least `min_voters` of them see the light and all of those agree it
/// is blocked; agree either way; disagree. Shared with the spin rule
/// ([`super::temporal::solve_temporal`]).
#[inline]
pub(super) fn spatial_word(
    above: &[u64],
    vis: &[u64],
    spatial: &[usize],
    w: usize,
    m: usize,
    min_voters: u32,
) -> (u64, u64, u64) {
    let (mut all, mut any, mut seen) = (!0u64, 0u64, [0u64; 4]);
    for (k, &q) in spatial.iter().enumerate() {
        let a = above[q * w + m];
        let b = a & !vis[q * w + m];
        seen[k] = a;
        all &= !a | b;
        any |= b;
    }
    let enough = bits::at_least(&seen[..spatial.len()], min_voters);
    let blocked = enough & all & any;
    (blocked, blocked | (enough & !any), enough & any & !all)
}

#[cfg(test)]
mod tests {
    use super::super::testkit::{
        CONTRARY, DOWN, Frame, R, UP, at, buffers, carried_ground, ground_point, list, set_of, star,
    };
    use super::*;
    use crate::history::Edges;
    use glam::{Mat4, Vec3};

    const AT: At = CONTRARY;
    const LIT: [usize; 4] = [UP, R[2], R[3], R[4]];

    /// Solves ground pixel (0, 0) in place (region pixel 0, its own previous self at
    /// `offset` from the point it saw) with four spatial voters beside it whose visible lights
    /// are `spatial[k]`; the previous frame saw `LIT`. Returns whether it was solved, its
    /// traced and visible lights, and whether it is marked temporal.
    fn solve(offset: Vec3, spatial: [&[usize]; 4]) -> (bool, Vec<usize>, Vec<usize>, bool) {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let up: Vec<usize> = (0..DOWN).collect();
        let carried = carried_ground(&ctx, &Edges::None, |_, _| Some((up.clone(), LIT.to_vec())));
        let p = ground_point(&ctx, 0, 0, (0.0, 0.0));
        let mut surfaces = vec![at(p + offset)];
        surfaces.extend([0.01f32, 0.02, 0.03, 0.04].map(|d| at(p + Vec3::new(d, 0.0, 0.0))));
        let (mut bufs, mut sc) = buffers(&ctx, &surfaces);
        for q in 0..5 {
            bits::rows_mut(&mut bufs.above, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &up));
            if q > 0 {
                bits::rows_mut(&mut bufs.vis, w)
                    .row_mut(q)
                    .copy_from_slice(&set_of(w, spatial[q - 1]));
            }
        }
        let cam = ctx.camera;
        let prev = Prev::new(&carried, Mat4::IDENTITY, cam, &cam, Vec::new());
        let solved = solve_in_place(&ctx, &mut bufs, &mut sc, &prev, 0, &[1, 2, 3, 4], 3, AT);
        let (traced, vis) = (list(&bufs.traced[..w]), list(&bufs.vis[..w]));
        (solved, traced, vis, bufs.temporal[0])
    }

    #[test]
    fn a_pixel_keeps_what_its_previous_self_and_its_neighbours_agree_on() {
        let (solved, traced, vis, temporal) = solve(Vec3::ZERO, [&LIT; 4]);
        assert!(solved && temporal);
        assert!(traced.is_empty(), "traced {traced:?}");
        assert_eq!(vis, LIT);
    }

    #[test]
    fn a_light_whose_shadow_edge_passes_the_pixel_is_traced() {
        // One spatial voter sees R[0] lit: the neighbours are contested on it, so the previous
        // frame's word (blocked) is not taken and R[0] is traced.
        let mut one = LIT.to_vec();
        one.push(R[0]);
        let (solved, traced, vis, _) = solve(Vec3::ZERO, [&LIT, &LIT, &one, &LIT]);
        assert!(solved);
        assert!(traced.contains(&R[0]), "traced {traced:?}");
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let truth = ctx.trace(&at(ground_point(&ctx, 0, 0, (0.0, 0.0))), R[0]);
        assert_eq!(vis.contains(&R[0]), truth, "the trace decides R[0]");
    }

    #[test]
    fn where_the_previous_pixel_saw_another_point_the_spatial_method_decides() {
        let (solved, traced, vis, temporal) = solve(Vec3::new(0.0, 0.0, 1e-3), [&LIT; 4]);
        assert!(!solved && !temporal);
        assert!(traced.is_empty() && vis.is_empty());
    }
}
