//! The geometry a file's animation moved between two consecutive frames (`--temporal` on a
//! deforming animation, issue 41): which triangles, and boxes that hold them in both frames.
//!
//! A previous frame's (point, light) visibility still holds where its shadow ray misses every
//! moved triangle in both frames: the still triangles it may meet are the same bits in both
//! frames, and no moved one can have entered or left it. So a pair whose ray misses the boxes
//! (grown by how far the previous frame's voters lie from the point, so their rays miss them
//! too) keeps its prediction as on a rigid frame; the others are left to the frame itself
//! (the temporal predictor's spatial voters, or a trace). A point on a moved triangle is never predicted from the
//! previous frame: its own rays start inside the boxes.
//!
//! The boxes are a few groups of the moved triangles, split at the median along their widest
//! axis ([`LEAVES`]): a walking character's legs and head are apart, and a light seen past the
//! body from the ground need not be lost to a box round the whole of it.

use std::ops::Range;

use glam::Vec3;

use crate::bits;
use crate::scene::Scene;

/// Most boxes the moved triangles are grouped into (a power of two).
pub const LEAVES: usize = 16;

/// What moved between two frames: triangles, and boxes over both frames' positions.
pub struct Moved {
    /// Per scene triangle, one bit: whether any of its vertices moved.
    tris: Vec<u64>,
    /// How many triangles moved.
    count: usize,
    /// The union of the boxes, tested first.
    all: (Vec3, Vec3),
    /// Each group's box over both frames.
    boxes: Vec<(Vec3, Vec3)>,
    /// Slack added to every box: rounding of the ray and the box (a thousandth of a percent of
    /// the boxes' extent).
    pad: f32,
}

impl Moved {
    /// What moved from `before` (the previous frame's vertex positions) to `now` among the
    /// triangles of `parts` (the only ones the animation may move); None when nothing did
    /// (the pose held): the previous frame then predicts everywhere, as for a still scene.
    pub fn between(before: &[Vec3], now: &Scene, parts: &[Range<usize>]) -> Option<Moved> {
        let mut tris = vec![0u64; now.triangle_count().div_ceil(64)];
        let mut swept: Vec<(Vec3, Vec3)> = Vec::new();
        let same_count = before.len() == now.positions.len();
        for part in parts {
            for t in part.clone() {
                let idx = now.triangles[t];
                let moved = !same_count
                    || idx
                        .iter()
                        .any(|&i| before[i as usize] != now.positions[i as usize]);
                if !moved {
                    continue;
                }
                bits::set(&mut tris, t);
                let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
                for &i in &idx {
                    let p = now.positions[i as usize];
                    lo = lo.min(p);
                    hi = hi.max(p);
                    if same_count {
                        let q = before[i as usize];
                        lo = lo.min(q);
                        hi = hi.max(q);
                    }
                }
                swept.push((lo, hi));
            }
        }
        if swept.is_empty() {
            return None;
        }
        let count = swept.len();
        let all = union(&swept);
        let pad = (all.1 - all.0).length() * 1e-5;
        let mut boxes = Vec::with_capacity(LEAVES);
        group(&mut swept, LEAVES, &mut boxes);
        Some(Moved {
            tris,
            count,
            all,
            boxes,
            pad,
        })
    }

    /// Triangles `tris` moved (of `count`), within `boxes`: for the predictors' tests.
    #[cfg(test)]
    pub(crate) fn from_boxes(tris: &[u32], count: usize, boxes: Vec<(Vec3, Vec3)>) -> Moved {
        let mut bitset = vec![0u64; count.div_ceil(64)];
        for &t in tris {
            bits::set(&mut bitset, t as usize);
        }
        Moved {
            tris: bitset,
            count: tris.len(),
            all: union(&boxes),
            boxes,
            pad: 0.0,
        }
    }

    /// How many triangles moved.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The groups' boxes (over both frames).
    pub fn boxes(&self) -> &[(Vec3, Vec3)] {
        &self.boxes
    }

    /// Whether triangle `tri` moved.
    #[inline]
    pub fn moved(&self, tri: u32) -> bool {
        bits::get(&self.tris, tri as usize)
    }

    /// Whether the ray `origin + t·dir`, 0 ≤ t ≤ `end`, passes within `grow` of a box: of the
    /// moved triangles in either frame, for any ray parallel to it and starting within `grow`
    /// of `origin` (a point light's ray towards the same light stays as near). False is sure;
    /// true may be a near miss.
    #[inline]
    pub fn crosses(&self, origin: Vec3, dir: Vec3, end: f32, grow: f32) -> bool {
        let grow = grow + self.pad;
        let g = Vec3::splat(grow);
        // The sphere round a box first: no division, and most rays pass far from what moved.
        let hit = |(lo, hi): (Vec3, Vec3)| {
            near_sphere((lo + hi) * 0.5, ((hi - lo) * 0.5 + g).length(), origin, dir)
                && slab(lo - g, hi + g, origin, dir, end)
        };
        hit(self.all) && self.boxes.iter().any(|&b| hit(b))
    }
}

/// The box around `boxes`.
fn union(boxes: &[(Vec3, Vec3)]) -> (Vec3, Vec3) {
    boxes
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &(a, b)| {
            (lo.min(a), hi.max(b))
        })
}

/// Splits `boxes` into at most `leaves` groups at the median of their centres along the
/// widest axis, pushing each group's box onto `out` (the same order whatever the run).
fn group(boxes: &mut [(Vec3, Vec3)], leaves: usize, out: &mut Vec<(Vec3, Vec3)>) {
    if leaves <= 1 || boxes.len() <= 1 {
        out.push(union(boxes));
        return;
    }
    let centre = |b: &(Vec3, Vec3)| b.0 + b.1;
    let (lo, hi) = boxes
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), b| {
            (lo.min(centre(b)), hi.max(centre(b)))
        });
    let axis = (hi - lo).max_position();
    let mid = boxes.len() / 2;
    boxes.select_nth_unstable_by(mid, |a, b| centre(a)[axis].total_cmp(&centre(b)[axis]));
    let (left, right) = boxes.split_at_mut(mid);
    group(left, leaves / 2, out);
    group(right, leaves / 2, out);
}

/// Whether the ray `origin + t·dir`, t ≥ 0 (`dir` a unit vector), may meet the sphere of
/// `centre` and `radius`: false only when it surely does not (it starts outside, and points
/// away or passes farther than the radius; a tenth of a percent of slack for rounding).
#[inline]
fn near_sphere(centre: Vec3, radius: f32, origin: Vec3, dir: Vec3) -> bool {
    let to = centre - origin;
    let r2 = radius * radius * 1.002;
    let d2 = to.length_squared();
    if d2 <= r2 {
        return true;
    }
    let along = to.dot(dir);
    along > 0.0 && d2 - along * along <= r2
}

/// Whether the segment `origin + t·dir`, 0 ≤ t ≤ `end`, meets the box `lo`..`hi` (slabs; an
/// axis the ray runs along meets it only if the origin lies within its slab).
#[inline]
fn slab(lo: Vec3, hi: Vec3, origin: Vec3, dir: Vec3, end: f32) -> bool {
    let (mut t0, mut t1) = (0.0f32, end);
    for a in 0..3 {
        let (o, d) = (origin[a], dir[a]);
        if d == 0.0 {
            if o < lo[a] || o > hi[a] {
                return false;
            }
            continue;
        }
        let (mut near, mut far) = ((lo[a] - o) / d, (hi[a] - o) / d);
        if near > far {
            std::mem::swap(&mut near, &mut far);
        }
        t0 = t0.max(near);
        t1 = t1.min(far);
        if t0 > t1 {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_meets_a_box_only_where_its_segment_does() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let o = Vec3::new(-3.0, 0.0, 0.0);
        assert!(slab(lo, hi, o, Vec3::X, f32::INFINITY));
        assert!(!slab(lo, hi, o, -Vec3::X, f32::INFINITY));
        // Short of the box, and along an axis beside it.
        assert!(!slab(lo, hi, o, Vec3::X, 1.5));
        assert!(!slab(
            lo,
            hi,
            Vec3::new(-3.0, 2.0, 0.0),
            Vec3::X,
            f32::INFINITY
        ));
        // From inside, any way.
        assert!(slab(lo, hi, Vec3::ZERO, Vec3::Y, f32::INFINITY));
        let d = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!(slab(lo, hi, Vec3::new(-1.5, -1.5, 0.0), d, f32::INFINITY));
        assert!(!slab(lo, hi, Vec3::new(-1.5, 0.0, 5.0), d, f32::INFINITY));
    }

    #[test]
    fn a_ray_passing_beside_a_sphere_misses_it_and_one_through_it_does_not() {
        let c = Vec3::new(5.0, 0.0, 0.0);
        assert!(near_sphere(c, 1.0, Vec3::ZERO, Vec3::X));
        assert!(!near_sphere(c, 1.0, Vec3::ZERO, -Vec3::X));
        assert!(!near_sphere(c, 1.0, Vec3::ZERO, Vec3::Y));
        assert!(near_sphere(c, 1.0, Vec3::new(5.0, 0.5, 0.0), Vec3::Y));
        let grazing = Vec3::new(5.0, 0.99, 0.0).normalize();
        assert!(near_sphere(c, 1.0, Vec3::ZERO, grazing));
    }

    #[test]
    fn groups_split_far_apart_triangles_into_their_own_boxes() {
        // Two clusters, at x = 0 and x = 10: the ray between them (x = 5) meets no group,
        // although it crosses the union.
        let mut boxes: Vec<(Vec3, Vec3)> = (0..8)
            .map(|k| {
                let x = if k % 2 == 0 { 0.0 } else { 10.0 };
                let p = Vec3::new(x, k as f32 * 0.1, 0.0);
                (p - 0.5, p + 0.5)
            })
            .collect();
        let mut out = Vec::new();
        group(&mut boxes, LEAVES, &mut out);
        assert!(out.len() <= LEAVES && out.len() >= 2);
        let m = Moved {
            tris: vec![0],
            count: 8,
            all: union(&out),
            boxes: out,
            pad: 0.0,
        };
        let down = -Vec3::Y;
        let above = |x: f32| Vec3::new(x, 10.0, 0.0);
        assert!(!m.crosses(above(5.0), down, f32::INFINITY, 0.0));
        assert!(m.crosses(above(0.0), down, f32::INFINITY, 0.0));
        assert!(m.crosses(above(10.2), down, f32::INFINITY, 0.0));
        // Grown by the voters' reach, a ray beside a group meets it.
        assert!(!m.crosses(above(1.0), down, f32::INFINITY, 0.25));
        assert!(m.crosses(above(1.0), down, f32::INFINITY, 0.75));
    }
}
