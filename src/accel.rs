//! Ray queries against the scene's triangles: our small interface over the obvhs CWBVH.
//!
//! Closest hit for camera rays ([`Accel::intersect`]), an occlusion test for shadow rays
//! ([`Accel::occluded`]) and the same test reporting where the ray was blocked
//! ([`Accel::blocker`], for the warping predictors). obvhs's own naming is hidden here
//! (its `ray_traverse_miss` returns true when nothing is hit).

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;

/// A closest hit: distance along the ray, the scene's triangle index, and barycentrics (u, v)
/// such that the point is (1 − u − v)·p0 + u·p1 + v·p2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub tri: u32,
    pub u: f32,
    pub v: f32,
}

/// A bounding volume hierarchy over a triangle soup, built once per frame geometry.
pub struct Accel {
    bvh: CwBvh,
    /// Triangles in the BVH's primitive order, so a leaf indexes them directly.
    tris: Vec<Triangle>,
    /// BVH primitive order → the scene's triangle index.
    scene_index: Vec<u32>,
}

impl Accel {
    /// Builds the BVH. Deterministic: obvhs is used without its parallel builder.
    pub fn build(positions: &[Vec3], triangles: &[[u32; 3]]) -> Accel {
        let soup: Vec<Triangle> = triangles
            .iter()
            .map(|t| Triangle {
                v0: positions[t[0] as usize].into(),
                v1: positions[t[1] as usize].into(),
                v2: positions[t[2] as usize].into(),
            })
            .collect();
        if soup.is_empty() {
            return Accel {
                bvh: CwBvh::default(),
                tris: Vec::new(),
                scene_index: Vec::new(),
            };
        }
        let bvh = build_cwbvh_from_tris(
            &soup,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let tris = bvh
            .primitive_indices
            .iter()
            .map(|&i| soup[i as usize])
            .collect();
        let scene_index = bvh.primitive_indices.clone();
        Accel {
            bvh,
            tris,
            scene_index,
        }
    }

    /// Number of triangles in the hierarchy.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// The closest hit along `origin + t·dir`, t in (0, ∞).
    pub fn intersect(&self, origin: Vec3, dir: Vec3) -> Option<Hit> {
        if self.tris.is_empty() {
            return None;
        }
        let ray = Ray::new(origin.into(), dir.into(), 0.0, f32::INFINITY);
        let mut hit = RayHit::none();
        if !self
            .bvh
            .ray_traverse(ray, &mut hit, |r, id| self.tris[id].intersect(r))
        {
            return None;
        }
        let prim = hit.primitive_id as usize;
        let (u, v) = barycentrics(&self.tris[prim], ray.origin, ray.direction);
        Some(Hit {
            t: hit.t,
            tri: self.scene_index[prim],
            u,
            v,
        })
    }

    /// The triangles in the hierarchy's order (for ray dumps that other tracers replay).
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.tris
            .iter()
            .map(|t| [t.v0.into(), t.v1.into(), t.v2.into()])
    }

    /// True when anything lies along `origin + t·dir` for t in (0, ∞): the shadow-ray test.
    #[inline]
    pub fn occluded(&self, origin: Vec3, dir: Vec3) -> bool {
        record(origin, dir);
        self.occluded_unrecorded(origin, dir)
    }

    /// [`occluded`](Self::occluded) without the recording hook: what a replay measures.
    #[inline]
    pub fn occluded_unrecorded(&self, origin: Vec3, dir: Vec3) -> bool {
        if self.tris.is_empty() {
            return false;
        }
        let ray = Ray::new(origin.into(), dir.into(), 0.0, f32::INFINITY);
        !self
            .bvh
            .ray_traverse_miss(ray, |r, id| self.tris[id].intersect(r))
    }

    /// Like [`occluded`](Self::occluded) but returns the distance to a blocker along the ray
    /// (the first hit the traversal finds, not necessarily the nearest): the blocker point
    /// `origin + t·dir` is what the warping predictors re-aim.
    pub fn blocker_distance(&self, origin: Vec3, dir: Vec3) -> Option<f32> {
        record(origin, dir);
        if self.tris.is_empty() {
            return None;
        }
        let ray = Ray::new(origin.into(), dir.into(), 0.0, f32::INFINITY);
        let mut t_hit = f32::INFINITY;
        let missed = self.bvh.ray_traverse_miss(ray, |r, id| {
            let t = self.tris[id].intersect(r);
            if t < t_hit {
                t_hit = t;
            }
            t
        });
        (!missed).then_some(t_hit)
    }

    /// The blocking point of [`blocker_distance`](Self::blocker_distance).
    pub fn blocker(&self, origin: Vec3, dir: Vec3) -> Option<Vec3> {
        self.blocker_distance(origin, dir).map(|t| origin + dir * t)
    }
}

/// One shadow ray as traced: origin and unit direction, t in (0, ∞).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowRay {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// Whether shadow queries are being recorded (`envshadow bench --split`/`--dump-rays`). Off in
/// renders: the hook costs one relaxed load and a predictable branch per ray.
static RECORDING: AtomicBool = AtomicBool::new(false);

thread_local! {
    /// The shadow rays this thread traced while recording, in order.
    static RECORDED: RefCell<Vec<ShadowRay>> = const { RefCell::new(Vec::new()) };
}

#[inline(always)]
fn record(origin: Vec3, dir: Vec3) {
    if RECORDING.load(Ordering::Relaxed) {
        RECORDED.with_borrow_mut(|v| v.push(ShadowRay { origin, dir }));
    }
}

/// Starts or stops recording every shadow query (occlusion and blocker) on every thread.
pub fn set_recording(on: bool) {
    RECORDING.store(on, Ordering::SeqCst);
}

/// Takes the shadow rays the calling thread recorded.
pub fn take_recorded() -> Vec<ShadowRay> {
    RECORDED.with_borrow_mut(std::mem::take)
}

/// Barycentrics with obvhs's (Möller–Trumbore) edge convention, unnormalised like its
/// `intersect` so that u weights v1 and v weights v2.
fn barycentrics(tri: &Triangle, origin: Vec3A, dir: Vec3A) -> (f32, f32) {
    let e1 = tri.v0 - tri.v1;
    let e2 = tri.v2 - tri.v0;
    let n = e1.cross(e2);
    let r = dir.cross(tri.v0 - origin);
    let inv_det = 1.0 / n.dot(dir);
    (r.dot(e2) * inv_det, r.dot(e1) * inv_det)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        // Unit square in the y = 0 plane plus a small square above it at y = 1.
        let p = vec![
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(-0.1, 1.0, -0.1),
            Vec3::new(0.1, 1.0, -0.1),
            Vec3::new(0.1, 1.0, 0.1),
            Vec3::new(-0.1, 1.0, 0.1),
        ];
        let t = vec![[0, 2, 1], [0, 3, 2], [4, 6, 5], [4, 7, 6]];
        (p, t)
    }

    #[test]
    fn closest_hit_and_barycentrics_reconstruct_the_point() {
        let (p, t) = quad();
        let accel = Accel::build(&p, &t);
        let o = Vec3::new(0.3, 5.0, 0.2);
        let d = Vec3::new(0.0, -1.0, 0.0);
        let hit = accel.intersect(o, d).expect("hits the ground");
        assert!((hit.t - 5.0).abs() < 1e-5, "{hit:?}");
        let tri = t[hit.tri as usize];
        let q = p[tri[0] as usize] * (1.0 - hit.u - hit.v)
            + p[tri[1] as usize] * hit.u
            + p[tri[2] as usize] * hit.v;
        assert!(
            (q - (o + d * hit.t)).length() < 1e-5,
            "{q} vs {}",
            o + d * hit.t
        );
        // Straight down through the small square: it is nearer.
        let hit = accel.intersect(Vec3::new(0.0, 5.0, 0.0), d).unwrap();
        assert!((hit.t - 4.0).abs() < 1e-5);
        assert!(hit.tri >= 2);
    }

    #[test]
    fn occlusion_and_blocker_point() {
        let (p, t) = quad();
        let accel = Accel::build(&p, &t);
        let up = Vec3::Y;
        assert!(accel.occluded(Vec3::new(0.03, 0.01, -0.02), up));
        assert!(!accel.occluded(Vec3::new(0.5, 0.01, 0.5), up));
        let b = accel.blocker(Vec3::new(0.05, 0.01, 0.0), up).unwrap();
        assert!((b - Vec3::new(0.05, 1.0, 0.0)).length() < 1e-5);
        assert!(accel.blocker(Vec3::new(0.5, 0.01, 0.5), up).is_none());
        let empty = Accel::build(&[], &[]);
        assert!(!empty.occluded(Vec3::ZERO, up));
        assert!(empty.intersect(Vec3::ZERO, up).is_none());
    }
}

impl Accel {
    /// TEMP experiment: nodes and triangles visited.
    pub fn stats(&self, origin: Vec3, dir: Vec3) -> (u32, u32, bool) {
        let ray = Ray::new(origin.into(), dir.into(), 0.0, f32::INFINITY);
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let (mut nn, mut nt, mut hit) = (0u32, 0u32, false);
        use glam::UVec2;
        'outer: {
            obvhs::traverse!(self.bvh, node, state, { nn += 1; node.intersect_ray(&ray, state.oct_inv4) }, {
                nt += 1;
                let t = self.tris[state.primitive_id as usize].intersect(&ray);
                if t < ray.tmax {
                    hit = true;
                    break 'outer;
                }
            });
        }
        (nn, nt, hit)
    }
}
