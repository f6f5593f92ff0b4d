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
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};
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
            // Measured on the default method's rays (callgrind, bunny, 400 lights): slower presets
            // and smaller leaves change traversal work by under 4 % for 1.2–3× the build time,
            // and the BVH is rebuilt every frame.
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
        self.any_hit(&ray, |t| t < ray.tmax)
    }

    /// obvhs's any-hit traversal (`ray_traverse_miss`) with our node test: true as soon as a
    /// triangle hit at t passes `accept(t)`. With AVX2 (checked once at run time) all eight
    /// children are tested in one 256-bit lane set, otherwise with SSE2 in two halves; both
    /// kernels perform the same float operations per child, so every host finds the same
    /// children, the same hits and the same bits (farm hosts may differ in CPU).
    #[inline(always)]
    fn any_hit(&self, ray: &Ray, accept: impl FnMut(f32) -> bool) -> bool {
        #[cfg(target_arch = "x86_64")]
        if simd::has_avx2() {
            // SAFETY: AVX2 was detected on this CPU.
            return unsafe { self.any_hit_avx2(ray, accept) };
        }
        self.any_hit_with(ray, accept, node_hits)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn any_hit_avx2(&self, ray: &Ray, accept: impl FnMut(f32) -> bool) -> bool {
        self.any_hit_with(ray, accept, |node, ray, oct| {
            simd::node_hits_avx2(node, ray, oct)
        })
    }

    #[inline(always)]
    fn any_hit_with(
        &self,
        ray: &Ray,
        mut accept: impl FnMut(f32) -> bool,
        node_test: impl Fn(&CwBvhNode, &Ray, u32) -> u32,
    ) -> bool {
        use glam::UVec2;
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let mut hit = false;
        'outer: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                node_test(node, ray, state.oct_inv4),
                {
                    let t = self.tris[state.primitive_id as usize].intersect(ray);
                    if accept(t) {
                        hit = true;
                        break 'outer;
                    }
                }
            );
        }
        hit
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
        let hit = self.any_hit(&ray, |t| {
            if t < t_hit {
                t_hit = t;
            }
            t < ray.tmax
        });
        hit.then_some(t_hit)
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

/// Which children of `node` the ray's segment meets, in obvhs's hit-mask layout: obvhs's
/// `CwBvhNode::intersect_ray_simd` with the same float operations in the same order (so the
/// same children, and the same traversal), but the 8-bit child planes widened to floats eight
/// at a time with SSE2 unpacks instead of one at a time, and all eight children tested at once.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn node_hits(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
    use std::arch::x86_64::*;
    // obvhs's node-test epsilon (`cwbvh::node::EPSILON`, crate-private): the near clip.
    const EPSILON: f32 = 0.0001;
    let inv = node.compute_extent() * ray.inv_direction;
    let org = (Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
    let d = ray.direction;
    let (lo_x, hi_x) = if d.x < 0.0 {
        (&node.child_max_x, &node.child_min_x)
    } else {
        (&node.child_min_x, &node.child_max_x)
    };
    let (lo_y, hi_y) = if d.y < 0.0 {
        (&node.child_max_y, &node.child_min_y)
    } else {
        (&node.child_min_y, &node.child_max_y)
    };
    let (lo_z, hi_z) = if d.z < 0.0 {
        (&node.child_max_z, &node.child_min_z)
    } else {
        (&node.child_min_z, &node.child_max_z)
    };
    // SAFETY: SSE2 is part of x86_64; the loads read exactly the 8 bytes of each array.
    let mask = unsafe {
        let zero = _mm_setzero_si128();
        // Eight u8 planes as two vectors of four f32 (children 0–3, 4–7).
        let widen = |v: &[u8; 8]| {
            let b = _mm_loadl_epi64(v.as_ptr() as *const __m128i);
            let w = _mm_unpacklo_epi8(b, zero);
            (
                _mm_cvtepi32_ps(_mm_unpacklo_epi16(w, zero)),
                _mm_cvtepi32_ps(_mm_unpackhi_epi16(w, zero)),
            )
        };
        let (lx, hx, ly, hy, lz, hz) = (
            widen(lo_x),
            widen(hi_x),
            widen(lo_y),
            widen(hi_y),
            widen(lo_z),
            widen(hi_z),
        );
        let (ix, iy, iz) = (_mm_set1_ps(inv.x), _mm_set1_ps(inv.y), _mm_set1_ps(inv.z));
        let (ox, oy, oz) = (_mm_set1_ps(org.x), _mm_set1_ps(org.y), _mm_set1_ps(org.z));
        let eps = _mm_set1_ps(EPSILON);
        let tmax_ray = _mm_set1_ps(ray.tmax);
        let half = |lx: __m128, hx: __m128, ly: __m128, hy: __m128, lz: __m128, hz: __m128| {
            let tmin_x = _mm_add_ps(_mm_mul_ps(lx, ix), ox);
            let tmax_x = _mm_add_ps(_mm_mul_ps(hx, ix), ox);
            let tmin_y = _mm_add_ps(_mm_mul_ps(ly, iy), oy);
            let tmax_y = _mm_add_ps(_mm_mul_ps(hy, iy), oy);
            let tmin_z = _mm_add_ps(_mm_mul_ps(lz, iz), oz);
            let tmax_z = _mm_add_ps(_mm_mul_ps(hz, iz), oz);
            let tmin = _mm_max_ps(tmin_x, _mm_max_ps(tmin_y, tmin_z));
            let tmax = _mm_min_ps(tmax_x, _mm_min_ps(tmax_y, tmax_z));
            let tmin = _mm_max_ps(tmin, eps);
            let tmax = _mm_min_ps(tmax, tmax_ray);
            _mm_movemask_ps(_mm_cmple_ps(tmin, tmax)) as u32
        };
        half(lx.0, hx.0, ly.0, hy.0, lz.0, hz.0) | half(lx.1, hx.1, ly.1, hy.1, lz.1, hz.1) << 4
    };
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut hit_mask = 0;
    let mut m = mask;
    while m != 0 {
        let c = m.trailing_zeros() as usize;
        m &= m - 1;
        hit_mask |= extract_byte64(child_bits8, c) << extract_byte64(bit_index8, c);
    }
    hit_mask
}

/// The AVX2 node kernel.
#[cfg(target_arch = "x86_64")]
mod simd {
    use super::*;
    pub use crate::simd::has_avx2;
    use std::arch::x86_64::*;

    /// [`node_hits`](super::node_hits) with eight children per instruction: each child's
    /// slab distances are `plane · inv + org` (a multiply then an add, never fused, as in
    /// obvhs), clipped by obvhs's epsilon and the ray's tmax, compared `tmin ≤ tmax`.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub fn node_hits_avx2(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
        const EPSILON: f32 = 0.0001;
        let inv = node.compute_extent() * ray.inv_direction;
        let org = (Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
        let d = ray.direction;
        let (lo_x, hi_x) = if d.x < 0.0 {
            (&node.child_max_x, &node.child_min_x)
        } else {
            (&node.child_min_x, &node.child_max_x)
        };
        let (lo_y, hi_y) = if d.y < 0.0 {
            (&node.child_max_y, &node.child_min_y)
        } else {
            (&node.child_min_y, &node.child_max_y)
        };
        let (lo_z, hi_z) = if d.z < 0.0 {
            (&node.child_max_z, &node.child_min_z)
        } else {
            (&node.child_min_z, &node.child_max_z)
        };
        // SAFETY: each load reads exactly the 8 bytes of one plane array.
        let widen = |v: &[u8; 8]| unsafe {
            _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(
                v.as_ptr() as *const __m128i
            )))
        };
        let slab = |q: &[u8; 8], inv: f32, org: f32| {
            _mm256_add_ps(
                _mm256_mul_ps(widen(q), _mm256_set1_ps(inv)),
                _mm256_set1_ps(org),
            )
        };
        let tmin = _mm256_max_ps(
            slab(lo_x, inv.x, org.x),
            _mm256_max_ps(slab(lo_y, inv.y, org.y), slab(lo_z, inv.z, org.z)),
        );
        let tmax = _mm256_min_ps(
            slab(hi_x, inv.x, org.x),
            _mm256_min_ps(slab(hi_y, inv.y, org.y), slab(hi_z, inv.z, org.z)),
        );
        let tmin = _mm256_max_ps(tmin, _mm256_set1_ps(EPSILON));
        let tmax = _mm256_min_ps(tmax, _mm256_set1_ps(ray.tmax));
        let hit = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(tmin, tmax));
        // obvhs's hit mask, branch-free: each hit child's bits (one for an inner node, the
        // leaf's unary triangle count) shifted to its slot, OR-ed over the eight lanes. A loop
        // over the hit children mispredicted on about every node.
        let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
        let bytes = |v: u64| _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(v as i64));
        let bits = _mm256_and_si256(
            _mm256_sllv_epi32(bytes(child_bits8), bytes(bit_index8)),
            hit,
        );
        let x = _mm_or_si128(
            _mm256_castsi256_si128(bits),
            _mm256_extracti128_si256::<1>(bits),
        );
        let x = _mm_or_si128(x, _mm_shuffle_epi32::<0b00_00_11_10>(x));
        let x = _mm_or_si128(x, _mm_shuffle_epi32::<0b00_00_00_01>(x));
        _mm_cvtsi128_si32(x) as u32
    }
}

#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn node_hits(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
    node.intersect_ray(ray, oct_inv4)
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

    #[test]
    fn our_node_test_agrees_with_obvhs_on_every_node() {
        // A random soup, rays from points inside and outside it in all octants: the children
        // our kernel reports must be exactly obvhs's, or traversal (and hits) could differ.
        let mut seed = 12345u32;
        let mut rnd = move || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut p = Vec::new();
        let mut t = Vec::new();
        for i in 0..2000u32 {
            let c = Vec3::new(rnd(), rnd(), rnd()) * 4.0 - 2.0;
            for _ in 0..3 {
                p.push(c + Vec3::new(rnd(), rnd(), rnd()) * 0.2);
            }
            t.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        let accel = Accel::build(&p, &t);
        let mut checked = 0;
        for _ in 0..300 {
            let o = Vec3::new(rnd(), rnd(), rnd()) * 6.0 - 3.0;
            let d = (Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0).normalize_or(Vec3::Y);
            let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
            let oct = accel.bvh.new_traversal(ray.direction).oct_inv4;
            for node in &accel.bvh.nodes {
                let reference = node.intersect_ray(&ray, oct);
                assert_eq!(node_hits(node, &ray, oct), reference);
                #[cfg(target_arch = "x86_64")]
                if is_x86_feature_detected!("avx2") {
                    // SAFETY: AVX2 was detected.
                    assert_eq!(unsafe { simd::node_hits_avx2(node, &ray, oct) }, reference);
                }
                checked += 1;
            }
            let reference = !accel
                .bvh
                .ray_traverse_miss(ray, |r, id| accel.tris[id].intersect(r));
            assert_eq!(accel.occluded(o, d), reference);
        }
        assert!(checked > 1000);
    }
}
