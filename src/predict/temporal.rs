//! Predicting a pixel from the previous frame (ALGORITHM.md §8 [ours]).
//!
//! The current pixel's surface point is carried back into the previous frame (reprojected for a
//! moving camera; through the object's motion for a spinning object) and the up to four
//! previous pixels around it whose surface points lie on the same surface vote, exactly like
//! spatial voters: a light is predicted blocked when at least `min_voters` of them have it
//! above their horizon and all of those found it blocked, visible when none did, and traced
//! otherwise; the traces flood as in [`super::correct`] (uncertainty flooding, to the
//! neighbours `--flood-to` names).
//!
//! For a spinning object the lights turn relative to the object, so the votes are pulled
//! through the turn: light j reads the previous frame's light whose cell contains j's
//! direction as the object saw it then. A light at the edge of a voter's shadow in light space
//! (an adjacent light differs) is uncertain, since the turn may have carried the edge across it.
//! With fewer than `min_voters` valid previous pixels (the first frame of a chain, disoccluded
//! or newly visible surfaces) the driver falls back to the spatial method. The previous frame's
//! data and the reprojection are [`Prev`]'s; key frames and chains are decided above.

use super::correct::{At, correct};
use super::scratch::Scratch;
use super::turning::spatial_word;
use super::uncertainty::Uncertainty;
use crate::bits;
use crate::buffers::TileBuffers;
use crate::context::FrameContext;
use crate::history::Prev;

/// Predicts and corrects region pixel `i` (already begun) from the previous frame `prev`, with
/// `spatial` (its valid spatial voters) settling edge lights of a spinning object. Returns
/// false, touching nothing, when too few of the previous frame's pixels saw the same surface
/// point: the caller then predicts the pixel spatially.
// Word loops index several parallel bitsets at once; iterator chains would hide that.
#[allow(clippy::needless_range_loop)]
// The previous frame, the pixel and its spatial voters, the voter threshold, and the flooding.
#[allow(clippy::too_many_arguments)]
pub fn solve_temporal(
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
    // Nothing seen, or a point the file's animation moved (its every ray starts among the
    // moved triangles).
    let moved = prev.moved();
    if !s.hit || moved.is_some_and(|mv| mv.moved(s.tri)) {
        return false;
    }
    let mut q = [0usize; 4];
    let nv = prev.voters(&s, &mut q);
    if nv < min_voters as usize {
        return false;
    }
    let w = bufs.words;
    let carried = prev.carried();
    let (above, vis) = (&bufs.above, &bufs.vis);
    // Rows of the scratch: 0 = predicted blocked, 1 = sure (the voters agree), 2 = at an edge
    // that the turn may have carried across, indexed by the previous frame's lights; 3–5 the
    // same pulled to the current lights.
    let ext = &mut sc.ext;
    for m in 0..w {
        let mut above_words = [0u64; 4];
        let (mut all, mut any, mut edge) = (!0u64, 0u64, 0u64);
        for k in 0..nv {
            let (a, v, e) = carried.word(q[k], m);
            above_words[k] = a;
            let blocked = a & !v;
            all &= !a | blocked;
            any |= blocked;
            edge |= e;
        }
        let enough = bits::at_least(&above_words[..nv], min_voters);
        let blocked = enough & all & any;
        let visible = enough & !any;
        ext[m] = blocked;
        ext[w + m] = blocked | visible;
        ext[2 * w + m] = edge;
    }
    let remap = prev.remap();
    let spin = carried.has_edges();
    let (blocked, sure, edge) = if remap.is_empty() {
        (0, w, 2 * w)
    } else {
        ext.copy_within(0..3 * w, 3 * w);
        for &(j, from) in remap {
            let (j, from) = (j as usize, from as usize);
            for row in 0..3 {
                let mut rows = bits::rows_mut(ext, w);
                let v = bits::get(rows.row(row), from);
                let dst = rows.row_mut(3 + row);
                if v {
                    bits::set(dst, j);
                } else {
                    bits::clear(dst, j);
                }
            }
        }
        (3 * w, 4 * w, 5 * w)
    };
    // Spin: the grazing lights (above the horizon by less than the pull's largest error) are
    // at the edge the horizon makes: a surface's own horizon is a shadow edge the previous
    // frame's edge lights never mark (the lights below it are no queries), and grazing
    // shadows (trim, seams, parts standing proud of a flat panel) lie right above it.
    let graze = 6 * w;
    if spin {
        let band = &mut ext[graze..graze + w];
        crate::shade::above_plane(&ctx.shade_lights, s.n, prev.grazing(), band);
    }
    let mine = bits::rows(above, w).row(i);
    let stale = 7 * w;
    if let Some(mv) = moved {
        stale_lights(ctx, &s, (mv, prev, &q[..nv]), mine, ext, (w, sure, stale));
    }
    let mut stale_pairs = 0;
    for m in 0..w {
        let my = mine[m];
        // Edge lights take the spatial voters' word where those agree (they surround the
        // pixel, so they bracket an edge the turn moved); otherwise they are traced, and
        // unlike uncertain lights flood only when the trace disagrees: the turn moves an edge
        // by a fraction of a cell, so a trace that confirms the prediction confirms its side.
        let (s_blocked, s_sure, _) = spatial_word(above, vis, spatial, w, m, min_voters);
        let e = if spin {
            my & (ext[edge + m] | !ext[graze + m])
        } else {
            my & ext[edge + m]
        };
        if !spin && moved.is_none() {
            sc.pred_vis[m] = my & !ext[blocked + m];
            sc.uncertain[m] = my & !ext[sure + m];
            sc.queued[m] = sc.uncertain[m];
            continue;
        }
        if !spin {
            // [ours] Lights whose rays may cross what moved (stale): the spatial voters decide
            // them where they agree; the others are traced, predicted as the previous frame
            // saw them and flooding only where the trace says otherwise (a moving shadow edge
            // crosses few of them from one frame to the next: flooding every one traced 10 %
            // more on the walking fox, docs/temporal.md).
            let st = ext[stale + m];
            stale_pairs += st.count_ones();
            let t_sure = ext[sure + m] & !st;
            let (s_settled, open) = (st & s_sure, st & !s_sure);
            let blocked_now = (ext[blocked + m] & (t_sure | open)) | (s_settled & s_blocked);
            sc.pred_vis[m] = my & !blocked_now;
            sc.queued[m] = my & !(t_sure | s_settled);
            sc.uncertain[m] = sc.queued[m] & !open;
            continue;
        }
        // Spin: the temporal voters settle what the spatial ones leave uncertain, and the
        // reverse; where both are sure they must agree.
        let t_sure = ext[sure + m] & !e;
        let t_blocked = ext[blocked + m] & t_sure;
        let conflict = t_sure & s_sure & (t_blocked ^ s_blocked);
        let settled = (t_sure | s_sure) & !conflict;
        let blocked_now = (t_blocked & t_sure) | (s_blocked & s_sure);
        sc.pred_vis[m] = my & !(blocked_now & settled);
        // An edge light neither settles is traced, flooding only on a surprise; lights the
        // voters disagree on are uncertain and flood.
        sc.uncertain[m] = my & !settled & !(e & ext[sure + m]);
        sc.queued[m] = my & !settled;
    }
    // The voters' agreement is uncertainty flooding's, and predicted blockers are kept
    // ([ours], docs/methods.md) whatever the spatial order does.
    let at = At {
        keep_predicted: true,
        flood_to: at.for_voters(bufs, spatial).flood_to,
        majority: false,
        inside: false,
        ..at
    };
    correct::<Uncertainty>(ctx, bufs, sc, i, at);
    bufs.temporal[i] = true;
    bufs.stale[i] = stale_pairs;
    true
}

/// Marks in row `stale` of `ext` the above-horizon lights of `s` (`mine`) that the previous
/// frame is sure of (row `sure`) whose shadow rays may cross what moved since (`mv`), the moved
/// boxes grown by how far the previous frame's `voters` lie from the point, so the voters'
/// rays, parallel and that near, miss what the pixel's miss. The others' previous visibility
/// is still the truth at the voters (their rays meet only still triangles, the same bits in
/// both frames).
fn stale_lights(
    ctx: &FrameContext,
    s: &crate::context::Surface,
    (mv, prev, voters): (&crate::moved::Moved, &Prev, &[usize]),
    mine: &[u64],
    ext: &mut [u64],
    (w, sure, stale): (usize, usize, usize),
) {
    // A deforming frame has no object motion: the voters' points are in this frame's world.
    let reach = voters
        .iter()
        .map(|&v| (prev.carried().point(v) - s.p).length())
        .fold(0.0f32, f32::max);
    for m in 0..w {
        let mut candidates = mine[m] & ext[sure + m];
        let mut word = 0u64;
        while candidates != 0 {
            let b = candidates.trailing_zeros();
            candidates &= candidates - 1;
            let (origin, dir, end) = ctx.shadow_ray(s, m * 64 + b as usize);
            if mv.crosses(origin, dir, end, reach) {
                word |= 1 << b;
            }
        }
        ext[stale + m] = word;
    }
}

#[cfg(test)]
mod tests {
    use super::super::testkit::{
        CONTRARY, DOWN, Frame, at, buffers, carried_ground, ground_point, list, set_of, star,
    };
    use super::*;
    use crate::history::Edges;
    use glam::Mat4;

    const AT: At = CONTRARY;

    /// Solves a ground point a quarter pixel past pixel (3, 3)'s centre from a previous frame
    /// whose pixel (x, y) kept `vis(x, y)` visible of the lights above the horizon (`None`:
    /// saw nothing). Returns whether it was solved, its traced and visible lights, the truth
    /// and whether it is marked temporal.
    fn solve(
        vis: impl Fn(u32, u32) -> Option<Vec<usize>>,
    ) -> (bool, Vec<usize>, Vec<usize>, Vec<usize>, bool) {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let up: Vec<usize> = (0..DOWN).collect();
        let carried = carried_ground(&ctx, &Edges::None, |x, y| {
            vis(x, y).map(|v| (up.clone(), v))
        });
        let s = at(ground_point(&ctx, 3, 3, (0.25, 0.25)));
        let truth: Vec<usize> = up.iter().copied().filter(|&j| ctx.trace(&s, j)).collect();
        let (mut bufs, mut sc) = buffers(&ctx, &[s]);
        bufs.above[..w].copy_from_slice(&set_of(w, &up));
        let cam = ctx.camera;
        let prev = Prev::new(&carried, Mat4::IDENTITY, cam, &cam, Vec::new());
        let solved = solve_temporal(&ctx, &mut bufs, &mut sc, &prev, 0, &[], 3, AT);
        let traced = list(&bufs.traced[..w]);
        (
            solved,
            traced,
            list(&bufs.vis[..w]),
            truth,
            bufs.temporal[0],
        )
    }

    /// Solves the test's ground point, whose four previous pixels saw every light lit, with
    /// `moved` the previous frame's view of what moved. Returns whether it was solved, its
    /// traced and visible lights, and how many of its pairs were stale.
    fn solve_moved(moved: &crate::moved::Moved) -> (bool, Vec<usize>, Vec<usize>, u32) {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        let up: Vec<usize> = (0..DOWN).collect();
        let carried = carried_ground(&ctx, &Edges::None, |_, _| Some((up.clone(), up.clone())));
        let s = at(ground_point(&ctx, 3, 3, (0.25, 0.25)));
        let (mut bufs, mut sc) = buffers(&ctx, &[s]);
        bufs.above[..w].copy_from_slice(&set_of(w, &up));
        let cam = ctx.camera;
        let prev =
            Prev::new(&carried, Mat4::IDENTITY, cam, &cam, Vec::new()).with_moved(Some(moved));
        let solved = solve_temporal(&ctx, &mut bufs, &mut sc, &prev, 0, &[], 3, AT);
        let (traced, vis) = (list(&bufs.traced[..w]), list(&bufs.vis[..w]));
        (solved, traced, vis, bufs.stale[0])
    }

    #[test]
    fn a_light_whose_ray_crosses_what_moved_is_not_taken_from_the_previous_frame() {
        use super::super::testkit::R;
        use glam::Vec3;
        // Something moved in a box on R[0]'s way (+x, 45° up) from the point, away from every
        // other light's: R[0] is traced (and found under the roof, which floods to its
        // neighbours); R[3], on the other side, is read as the previous frame saw it, untraced.
        let on_r0 = (Vec3::new(2.0, 1.8, -0.5), Vec3::new(3.0, 2.8, 0.5));
        let moved = crate::moved::Moved::from_boxes(&[5], 8, vec![on_r0]);
        let (solved, traced, vis, stale) = solve_moved(&moved);
        assert!(solved);
        assert_eq!(stale, 1);
        assert!(traced.contains(&R[0]), "traced {traced:?}");
        assert!(vis.contains(&R[3]) && !traced.contains(&R[3]), "{traced:?}");
        // Every traced light is the truth: the roof blocks R[0], R[1] and R[5].
        for j in traced {
            let under_roof = [R[0], R[1], R[5]].contains(&j);
            assert_eq!(vis.contains(&j), !under_roof, "light {j}");
        }
        // Nothing on any light's way: the previous frame decides every light.
        let far = (Vec3::new(0.0, -9.0, 0.0), Vec3::new(1.0, -8.0, 1.0));
        let (solved, traced, _, stale) =
            solve_moved(&crate::moved::Moved::from_boxes(&[5], 8, vec![far]));
        assert!(solved && traced.is_empty() && stale == 0);
        // The point's own triangle (the test surfaces say triangle 0) moved: left to the
        // spatial method, untouched.
        let own = crate::moved::Moved::from_boxes(&[0], 8, vec![far]);
        let (solved, traced, vis, _) = solve_moved(&own);
        assert!(!solved && traced.is_empty() && vis.is_empty());
    }

    /// The truth at the test's point, from the ground under the roof.
    fn truth() -> Vec<usize> {
        solve(|_, _| None).3
    }

    #[test]
    fn previous_pixels_that_agree_decide_every_light_without_a_ray() {
        let t = truth();
        assert!(
            t.len() > 1 && t.len() < DOWN,
            "the roof shades part of the sky: {t:?}"
        );
        let (solved, traced, vis, truth, temporal) = solve(|_, _| Some(t.clone()));
        assert!(solved && temporal);
        assert_eq!(traced, Vec::<usize>::new());
        assert_eq!(vis, truth);
    }

    #[test]
    fn a_light_the_previous_pixels_disagree_on_is_traced() {
        let t = truth();
        let blocked = (0..DOWN).find(|j| !t.contains(j)).expect("a blocked light");
        // Pixel (4, 3), one of the four voters, saw the blocked light lit.
        let (solved, traced, vis, truth, _) = solve(|x, y| {
            let mut v = t.clone();
            if (x, y) == (4, 3) {
                v.push(blocked);
            }
            Some(v)
        });
        assert!(solved);
        assert!(traced.contains(&blocked), "traced {traced:?}");
        assert_eq!(vis, truth);
    }

    #[test]
    fn the_previous_frame_predicts_what_it_saw_not_the_truth() {
        // Every voter saw every light lit (the roof was elsewhere then): all sure, none traced.
        let (solved, traced, vis, truth, _) = solve(|_, _| Some((0..DOWN).collect()));
        assert!(solved);
        assert_eq!(traced, Vec::<usize>::new());
        assert_eq!(vis, (0..DOWN).collect::<Vec<_>>());
        assert_ne!(vis, truth);
    }

    #[test]
    fn too_few_previous_pixels_leave_the_pixel_to_the_spatial_method_untouched() {
        // Only (3, 3) and (3, 4) of the four saw the point: below three voters.
        let (solved, traced, vis, _, temporal) =
            solve(|x, _| (x == 3).then(|| (0..DOWN).collect()));
        assert!(!solved && !temporal);
        assert!(traced.is_empty() && vis.is_empty());
    }
}
