//! Ray queries against the scene's triangles: our small interface over the obvhs CWBVH.
//!
//! Closest hit for camera rays ([`Accel::intersect`]), an occlusion test for shadow rays
//! ([`Accel::occluded`]; in packets from one origin, [`Accel::occluded_packet`], or from one
//! origin per ray, [`Accel::occluded_rays_within`]) and the same test reporting where the ray
//! was blocked ([`Accel::blocker`], for the warping predictors). obvhs's own naming is hidden
//! here (its `ray_traverse_miss` returns true when nothing is hit).
//!
//! Cut-out triangles (glTF's alpha-tested materials) are marked when the hierarchy is built
//! ([`Accel::build_with_cutouts`]); a hit on one counts only where a [`Cutout`] says the surface
//! stops the ray there. Every query has a form taking the cut-out test (`*_cut`, `*_within`);
//! shadow queries also take the ray's end (`tmax`: a point light's distance). Hits on other
//! triangles never call the test, so an opaque scene pays one predictable branch per hit group.

use std::sync::Arc;
use std::time::Duration;

use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};
use obvhs::ray::Ray;
use obvhs::triangle::Triangle;

/// The most rays [`Accel::occluded_packet`] traces at once (bits of its answer).
pub const PACKET: usize = 32;

/// A closest hit: distance along the ray, the scene's triangle index, and barycentrics (u, v)
/// such that the point is (1 − u − v)·p0 + u·p1 + v·p2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub tri: u32,
    pub u: f32,
    pub v: f32,
}

/// Whether a cut-out triangle stops a ray where the ray meets it: the alpha test of glTF's
/// `MASK` materials (and of `BLEND` ones, as a threshold). Asked only about hits on triangles
/// marked cut out ([`Accel::build_with_cutouts`]), and only for a hit nearer than any the
/// query has accepted so far; it must answer from its arguments alone (the same question, the
/// same answer), so every kernel and the packets find the same hits.
pub trait Cutout {
    /// Whether scene triangle `tri` stops the ray at barycentrics `(u, v)` (the point
    /// `(1 − u − v)·p0 + u·p1 + v·p2`, as the leaf kernels compute them).
    fn stops(&self, tri: u32, u: f32, v: f32) -> bool;
}

/// Every triangle stops every ray: the queries without a cut-out test.
pub struct Opaque;

impl Cutout for Opaque {
    #[inline(always)]
    fn stops(&self, _tri: u32, _u: f32, _v: f32) -> bool {
        true
    }
}

/// The scene's triangles for ray queries: one hierarchy over them all, or two when a file's
/// animation moves some of them (issue 41) — the still triangles' hierarchy, built once and
/// shared by every frame, and the moving ones', rebuilt per frame ([`Split`]). A
/// query walks each hierarchy in turn, still first: a closest hit keeps the nearer (the still
/// one among equals), a shadow ray is blocked by either. With one hierarchy the answers are
/// those of that hierarchy alone, bit for bit.
pub struct Accel {
    still: Arc<Hierarchy>,
    /// The moving triangles' hierarchy ([`Split`]), if any.
    moving: Option<Hierarchy>,
    /// How many triangles making this value built a hierarchy over (none shared).
    built: usize,
}

/// A scene's triangles split into those an animation moves and the others, with the others'
/// hierarchy built once: each pose's [`Accel`] shares it and builds only the moving ones'.
pub struct Split {
    still: Arc<Hierarchy>,
    /// The moving scene triangles, ascending; empty when none moves.
    moving: Vec<u32>,
}

impl Split {
    /// The split of the scene triangles that `moving[tri]` marks, the still ones' hierarchy
    /// built over `positions` (any pose: an animation leaves what it does not move as it was).
    pub fn new(
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        cut_out: &[bool],
        moving: &[bool],
    ) -> Split {
        let (moves, stays): (Vec<u32>, Vec<u32>) =
            (0..triangles.len() as u32).partition(|&t| moving.get(t as usize) == Some(&true));
        Split {
            still: Arc::new(Hierarchy::build(positions, triangles, &stays, cut_out)),
            moving: moves,
        }
    }

    /// The BVH of one pose (`positions` of the same triangles): the still triangles' hierarchy
    /// shared, the moving ones' built over their positions. The still triangles are checked to
    /// lie bit for bit where they lay; if one does not, the whole is built, so the answers are
    /// always this pose's.
    pub fn accel(&self, positions: &[Vec3], triangles: &[[u32; 3]], cut_out: &[bool]) -> Accel {
        if !self.still.lies_in(positions, triangles) {
            return Accel::build_with_cutouts(positions, triangles, cut_out);
        }
        Accel {
            still: Arc::clone(&self.still),
            moving: (!self.moving.is_empty())
                .then(|| Hierarchy::build(positions, triangles, &self.moving, cut_out)),
            built: self.moving.len(),
        }
    }
}

impl Accel {
    /// Builds the BVH. Deterministic: obvhs is used without its parallel builder.
    pub fn build(positions: &[Vec3], triangles: &[[u32; 3]]) -> Accel {
        Accel::build_with_cutouts(positions, triangles, &[])
    }

    /// [`build`](Self::build), with the scene triangles `tri` for which `cut_out[tri]` is true
    /// marked cut out: a hit on one counts only where the query's [`Cutout`] says so.
    /// `cut_out` may be shorter than `triangles` (the rest are opaque), or empty.
    pub fn build_with_cutouts(
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        cut_out: &[bool],
    ) -> Accel {
        let all: Vec<u32> = (0..triangles.len() as u32).collect();
        Accel {
            still: Arc::new(Hierarchy::build(positions, triangles, &all, cut_out)),
            moving: None,
            built: triangles.len(),
        }
    }

    /// How many triangles making this value built a hierarchy over: all for a whole build,
    /// the moving ones for [`Split::accel`] (none when nothing moves).
    pub fn built_triangles(&self) -> usize {
        self.built
    }

    /// The hierarchies, still first.
    #[inline(always)]
    fn parts(&self) -> impl Iterator<Item = &Hierarchy> {
        std::iter::once(&*self.still).chain(self.moving.as_ref())
    }

    /// Hierarchy `k` of [`parts`](Self::parts).
    #[inline]
    fn part(&self, k: usize) -> &Hierarchy {
        match (k, &self.moving) {
            (1, Some(m)) => m,
            _ => &self.still,
        }
    }

    /// Whether any triangle is cut out.
    pub fn has_cutouts(&self) -> bool {
        self.parts().any(|h| !h.cut.is_empty())
    }

    /// Number of triangles in the hierarchy.
    pub fn triangle_count(&self) -> usize {
        self.parts().map(|h| h.tris.len()).sum()
    }

    /// The closest hit along `origin + t·dir`, t in (0, ∞), every triangle opaque.
    pub fn intersect(&self, origin: Vec3, dir: Vec3) -> Option<Hit> {
        self.intersect_cut(origin, dir, &Opaque)
    }

    /// The closest hit along `origin + t·dir`, t in (0, ∞), that `cut` lets stop the ray
    /// (hits on cut-out triangles it refuses are passed through).
    pub fn intersect_cut<C: Cutout + ?Sized>(
        &self,
        origin: Vec3,
        dir: Vec3,
        cut: &C,
    ) -> Option<Hit> {
        let mut ray = ray(origin, dir, f32::INFINITY);
        let mut found = None;
        for h in self.parts() {
            if let Some((t, prim)) = h.closest(&ray, cut) {
                // A later hierarchy's hit must come nearer.
                ray.tmax = t;
                found = Some((h, t, prim));
            }
        }
        let (h, t, prim) = found?;
        Some(h.hit(prim, t, &ray))
    }

    /// [`intersect_cut`](Self::intersect_cut) for up to [`PACKET`] rays from one origin (a
    /// pixel's camera rays), ray r along `dirs[r]` with its own cut-out test `cuts[r]`:
    /// `hits[r]` is exactly what `intersect_cut(origin, dirs[r], &cuts[r])` returns (the same
    /// triangle, t and barycentrics bits), found faster. The rays of a pixel leave one point in
    /// nearly one direction, so they walk nearly the same nodes: the packet shares each node's
    /// load, its child planes and its traversal step, and gives the CPU the rays' tests to
    /// overlap where one ray waits on each node in turn.
    pub fn intersect_packet_cut<C: Cutout>(
        &self,
        origin: Vec3,
        dirs: &[Vec3],
        cuts: &[C],
        hits: &mut [Option<Hit>],
    ) {
        let n = dirs.len();
        assert!(n <= PACKET, "a packet holds at most {PACKET} rays");
        assert!(
            cuts.len() >= n && hits.len() >= n,
            "a test and an answer for every ray"
        );
        #[cfg(target_arch = "x86_64")]
        if crate::simd::has_avx2() && n > 0 {
            let rays: [Ray; PACKET] =
                std::array::from_fn(|r| ray(origin, dirs[r.min(n - 1)], f32::INFINITY));
            // Per ray: the nearest hit so far, and the hierarchy it lies in.
            let mut best = [(f32::INFINITY, usize::MAX); PACKET];
            let mut owner = [0usize; PACKET];
            for (k, h) in self.parts().enumerate() {
                // Each hierarchy starts from the nearest hit of those before it.
                let mut mine = best.map(|(t, _)| (t, usize::MAX));
                h.closest_packet(&rays, n, cuts, &mut mine);
                for r in 0..n {
                    if mine[r].1 != usize::MAX {
                        best[r] = mine[r];
                        owner[r] = k;
                    }
                }
            }
            for (r, h) in hits[..n].iter_mut().enumerate() {
                let (t, prim) = best[r];
                *h = (prim != usize::MAX).then(|| self.part(owner[r]).hit(prim, t, &rays[r]));
            }
            return;
        }
        // Without AVX2, one ray at a time: the same answers.
        for r in 0..n {
            hits[r] = self.intersect_cut(origin, dirs[r], &cuts[r]);
        }
    }

    /// The triangles in the hierarchy's order (for ray dumps that other tracers replay).
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.parts().flat_map(|h| h.triangles())
    }

    /// True when anything lies along `origin + t·dir` for t in (0, ∞), every triangle opaque:
    /// the shadow-ray test.
    #[inline]
    pub fn occluded(&self, origin: Vec3, dir: Vec3) -> bool {
        self.occluded_within(origin, dir, f32::INFINITY, &Opaque)
    }

    /// True when something `cut` lets stop the ray lies along `origin + t·dir` for t in
    /// (0, `tmax`): the shadow-ray test towards a light `tmax` away (∞ for a directional one).
    #[inline]
    pub fn occluded_within<C: Cutout + ?Sized>(
        &self,
        origin: Vec3,
        dir: Vec3,
        tmax: f32,
        cut: &C,
    ) -> bool {
        self.parts()
            .any(|h| h.occluded_within(origin, dir, tmax, cut))
    }

    /// [`occluded`](Self::occluded) for up to [`PACKET`] rays from one origin (a pixel's rays
    /// to several lights), traced together: bit r is set when `dirs[r]` is occluded. The same
    /// answers as one ray at a time, found faster: rays from one point share much of their
    /// walk through the hierarchy (on the bunny at 400 lights, 1.7× on the default method's
    /// rays and 1.9–2.3× on brute force's; BENCHMARKS.md).
    pub fn occluded_packet(&self, origin: Vec3, dirs: &[Vec3]) -> u32 {
        self.occluded_packet_within(origin, dirs, &[f32::INFINITY; PACKET], &Opaque)
    }

    /// [`occluded_packet`](Self::occluded_packet) with each ray's end (`tmax[r]` for
    /// `dirs[r]`; `tmax` at least as long as `dirs`) and the cut-out test: the answers of
    /// [`occluded_within`](Self::occluded_within), one ray at a time.
    pub fn occluded_packet_within<C: Cutout + ?Sized>(
        &self,
        origin: Vec3,
        dirs: &[Vec3],
        tmax: &[f32],
        cut: &C,
    ) -> u32 {
        self.trace_packet::<true, C>(&[origin], dirs, tmax, cut)
    }

    /// Up to [`PACKET`] shadow rays, each from its own origin, traced together: bit r is set
    /// when the ray from `origins[r]` along `dirs[r]` is blocked before `tmax[r]`. The same
    /// answers as [`occluded_within`](Self::occluded_within) one ray at a time. Built for the
    /// parallel rays of one directional light from nearby points (a tile's queries of that
    /// light), which walk nearly the same nodes; rays from one origin are the other case.
    pub fn occluded_rays_within<C: Cutout + ?Sized>(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        tmax: &[f32],
        cut: &C,
    ) -> u32 {
        assert!(origins.len() == dirs.len(), "an origin for every ray");
        self.trace_packet::<false, C>(origins, dirs, tmax, cut)
    }

    /// The packet query through every hierarchy: the still one's blocked rays are answered,
    /// the others go on, gathered into a packet of their own, to the moving one.
    fn trace_packet<const SHARED: bool, C: Cutout + ?Sized>(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        tmax: &[f32],
        cut: &C,
    ) -> u32 {
        let blocked = self
            .still
            .trace_packet::<SHARED, C>(origins, dirs, tmax, cut);
        let Some(m) = &self.moving else {
            return blocked;
        };
        let n = dirs.len();
        let open = !blocked & if n == PACKET { u32::MAX } else { (1 << n) - 1 };
        if open == 0 {
            return blocked;
        }
        let (mut o, mut d, mut t) = ([Vec3::ZERO; PACKET], [Vec3::ZERO; PACKET], [0f32; PACKET]);
        let mut from = [0usize; PACKET];
        let mut k = 0;
        for r in (0..n).filter(|r| open & (1 << r) != 0) {
            (o[k], d[k], t[k], from[k]) =
                (origins[if SHARED { 0 } else { r }], dirs[r], tmax[r], r);
            k += 1;
        }
        let more =
            m.trace_packet::<SHARED, C>(&o[..if SHARED { 1 } else { k }], &d[..k], &t[..k], cut);
        (0..k)
            .filter(|j| more & (1 << j) != 0)
            .fold(blocked, |b, j| b | 1 << from[j])
    }

    /// Like [`occluded`](Self::occluded) but returns the distance to a blocker along the ray
    /// (the nearest hit among the first leaf triangles the traversal finds hit, not
    /// necessarily the nearest of all): the blocker point `origin + t·dir` is what the warping
    /// predictors re-aim.
    pub fn blocker_distance(&self, origin: Vec3, dir: Vec3) -> Option<f32> {
        self.blocker_distance_within(origin, dir, f32::INFINITY, &Opaque)
    }

    /// [`blocker_distance`](Self::blocker_distance) for t in (0, `tmax`) with the cut-out
    /// test: blocked exactly when [`occluded_within`](Self::occluded_within) says so.
    pub fn blocker_distance_within<C: Cutout + ?Sized>(
        &self,
        origin: Vec3,
        dir: Vec3,
        tmax: f32,
        cut: &C,
    ) -> Option<f32> {
        self.parts()
            .find_map(|h| h.blocker_distance_within(origin, dir, tmax, cut))
    }

    /// The blocking point of [`blocker_distance`](Self::blocker_distance).
    pub fn blocker(&self, origin: Vec3, dir: Vec3) -> Option<Vec3> {
        self.blocker_distance(origin, dir).map(|t| origin + dir * t)
    }

    /// The one hierarchy of a scene built whole (the tests' view of its internals).
    #[cfg(test)]
    fn single(&self) -> &Hierarchy {
        assert!(self.moving.is_none(), "one hierarchy");
        &self.still
    }
}

/// The scene triangles `which` as obvhs's triangles.
fn soup_of(positions: &[Vec3], triangles: &[[u32; 3]], which: &[u32]) -> Vec<Triangle> {
    which
        .iter()
        .map(|&i| {
            let t = triangles[i as usize];
            Triangle {
                v0: positions[t[0] as usize].into(),
                v1: positions[t[1] as usize].into(),
                v2: positions[t[2] as usize].into(),
            }
        })
        .collect()
}

/// A bounding volume hierarchy over some of a scene's triangles, built once per frame geometry.
struct Hierarchy {
    bvh: CwBvh,
    /// Triangles in the BVH's primitive order, so a leaf indexes them directly.
    tris: Vec<Triangle>,
    /// BVH primitive order → the scene's triangle index.
    scene_index: Vec<u32>,
    /// The same triangles as precomputed planes for the shadow-ray leaf kernels.
    planes: TriPlanes,
    /// Cut-out triangles as a bitset in the BVH's primitive order, padded like the planes;
    /// empty when there are none.
    cut: Vec<u64>,
}

impl Hierarchy {
    /// The hierarchy over the scene triangles `which`, those marked in `cut_out` cut out.
    fn build(
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        which: &[u32],
        cut_out: &[bool],
    ) -> Hierarchy {
        let soup = soup_of(positions, triangles, which);
        if soup.is_empty() {
            return Hierarchy {
                bvh: CwBvh::default(),
                tris: Vec::new(),
                scene_index: Vec::new(),
                planes: TriPlanes::new(&[]),
                cut: Vec::new(),
            };
        }
        let bvh = build_cwbvh_from_tris(
            &soup,
            // Measured on the default method's rays (callgrind, bunny, 400 lights): slower presets
            // and smaller leaves change traversal work by under 4 % for 1.2–3× the build time.
            // Rebuilt, not refitted, per pose: refitting a walk cycle's hierarchy cost more in
            // its frames' rays than it saved in building (BENCHMARKS.md, issue 41).
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        Hierarchy::from_cwbvh(bvh, &soup, which, cut_out)
    }

    /// The hierarchy of `bvh`, built over `soup` (the scene triangles `which`).
    fn from_cwbvh(bvh: CwBvh, soup: &[Triangle], which: &[u32], cut_out: &[bool]) -> Hierarchy {
        let tris: Vec<Triangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| soup[i as usize])
            .collect();
        let scene_index: Vec<u32> = bvh
            .primitive_indices
            .iter()
            .map(|&i| which[i as usize])
            .collect();
        let planes = TriPlanes::new(&tris);
        let mut cut = Vec::new();
        if cut_out.iter().any(|&c| c) {
            cut = vec![0u64; planes.stride.div_ceil(64) + 1];
            for (i, &t) in scene_index.iter().enumerate() {
                if cut_out.get(t as usize) == Some(&true) {
                    cut[i / 64] |= 1 << (i % 64);
                }
            }
            if !cut.iter().any(|&w| w != 0) {
                cut.clear();
            }
        }
        Hierarchy {
            bvh,
            tris,
            scene_index,
            planes,
            cut,
        }
    }

    /// Whether each triangle of this hierarchy lies where `positions` and `triangles` put it,
    /// bit for bit.
    fn lies_in(&self, positions: &[Vec3], triangles: &[[u32; 3]]) -> bool {
        self.tris.iter().zip(&self.scene_index).all(|(held, &t)| {
            let v = triangles
                .get(t as usize)
                .map(|t| t.map(|i| positions.get(i as usize)));
            let bits = |p: Vec3A| p.to_array().map(f32::to_bits);
            matches!(v, Some([Some(a), Some(b), Some(c)])
                if [a, b, c].map(|p| bits((*p).into())) == [held.v0, held.v1, held.v2].map(bits))
        })
    }

    /// The nearest hit (t, primitive) before `ray.tmax` that `cut` lets stop the ray.
    #[inline]
    fn closest<C: Cutout + ?Sized>(&self, ray: &Ray, cut: &C) -> Option<(f32, usize)> {
        if self.tris.is_empty() {
            return None;
        }
        let cut = self.cut_with(cut);
        #[cfg(target_arch = "x86_64")]
        let found = if crate::simd::has_avx2() {
            // SAFETY: AVX2 was detected on this CPU.
            unsafe { self.closest_avx2(ray, &cut) }
        } else {
            self.closest_with(ray, node_hits, |p, base, mask, ray| {
                // SAFETY: the group's lanes lie within the padded planes.
                unsafe { leaf::hit_sse2(p, base, mask, ray, &cut) }
            })
        };
        #[cfg(not(target_arch = "x86_64"))]
        let found = self.closest_with(ray, node_hits, |p, base, mask, ray| {
            leaf::hit_scalar(p, base, mask, ray, &cut)
        });
        found
    }

    /// The hit at distance `t` of `ray` on primitive `prim`, with its scene triangle and
    /// barycentrics.
    fn hit(&self, prim: usize, t: f32, ray: &Ray) -> Hit {
        let (u, v) = barycentrics(&self.tris[prim], ray.origin, ray.direction);
        Hit {
            t,
            tri: self.scene_index[prim],
            u,
            v,
        }
    }

    /// The closest hits of the first `n` of `rays` (all from one origin), ray r with the
    /// cut-out test `cuts[r]`: where this hierarchy holds a hit nearer than `best[r].0`,
    /// `best[r]` becomes it (t, primitive); otherwise it is left as it was.
    #[cfg(target_arch = "x86_64")]
    fn closest_packet<C: Cutout>(
        &self,
        rays: &[Ray; PACKET],
        n: usize,
        cuts: &[C],
        best: &mut [(f32, usize); PACKET],
    ) {
        if self.tris.is_empty() {
            return;
        }
        // obvhs orders a node's children by the ray's octant; rays of one octant walk in
        // one order, so each packet holds one octant's rays (a pixel's rays nearly always
        // share theirs).
        let octant = |r: usize| octant_inv4(rays[r].direction);
        let mut left = if n == 32 { u32::MAX } else { (1u32 << n) - 1 };
        while left != 0 {
            let oct = octant(left.trailing_zeros() as usize);
            let mut group = 0u32;
            let mut m = left;
            while m != 0 {
                let r = m.trailing_zeros() as usize;
                m &= m - 1;
                if octant(r) == oct {
                    group |= 1 << r;
                }
            }
            left &= !group;
            // SAFETY: AVX2 was detected on this CPU (the caller checked).
            unsafe { avx2::closest_packet(self, rays, group, oct, cuts, best) };
        }
    }

    /// The cut-out test of one query, with this hierarchy's cut-out triangles.
    #[inline(always)]
    fn cut_with<'a, C: Cutout + ?Sized>(&'a self, test: &'a C) -> Cut<'a, C> {
        Cut {
            bits: &self.cut,
            scene_index: &self.scene_index,
            test,
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn closest_avx2<C: Cutout + ?Sized>(&self, ray: &Ray, cut: &Cut<C>) -> Option<(f32, usize)> {
        self.closest_with(
            ray,
            |node, ray, oct| avx2::node_hits_avx2(node, ray, oct),
            // SAFETY: as for the SSE2 kernel.
            |p, base, mask, ray| unsafe { leaf::hit_avx2(p, base, mask, ray, cut) },
        )
    }

    /// obvhs's closest-hit traversal (`ray_traverse`) with our kernels: each hit group's
    /// nearest triangle shortens the ray, so later nodes and groups must come nearer.
    #[inline(always)]
    fn closest_with(
        &self,
        ray: &Ray,
        node_test: impl Fn(&CwBvhNode, &Ray, u32) -> u32,
        leaf_test: impl Fn(&TriPlanes, usize, u32, &Ray) -> (f32, usize),
    ) -> Option<(f32, usize)> {
        use glam::UVec2;
        let mut ray = *ray;
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let mut found = None;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            node_test(node, &ray, state.oct_inv4),
            {
                let base = state.primitive_group.x;
                let mask = state.primitive_group.y | 1 << (state.primitive_id - base);
                state.primitive_group.y = 0;
                let (t, i) = leaf_test(&self.planes, base as usize, mask, &ray);
                if t < ray.tmax {
                    ray.tmax = t;
                    found = Some((t, i));
                }
            }
        );
        found
    }

    /// The triangles in the hierarchy's order (for ray dumps that other tracers replay).
    fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.tris
            .iter()
            .map(|t| [t.v0.into(), t.v1.into(), t.v2.into()])
    }

    /// True when something `cut` lets stop the ray lies along `origin + t·dir` for t in
    /// (0, `tmax`): the shadow-ray test towards a light `tmax` away (∞ for a directional one).
    #[inline]
    fn occluded_within<C: Cutout + ?Sized>(
        &self,
        origin: Vec3,
        dir: Vec3,
        tmax: f32,
        cut: &C,
    ) -> bool {
        if self.tris.is_empty() {
            return false;
        }
        let ray = ray(origin, dir, tmax);
        self.any_hit(&ray, &self.cut_with(cut)).is_some()
    }

    /// The packet query behind both forms: `origins` holds one origin for every ray or, with
    /// `SHARED`, the one origin they all leave from (whose offset to each node is then
    /// computed once per node, not once per ray).
    fn trace_packet<const SHARED: bool, C: Cutout + ?Sized>(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        tmax: &[f32],
        cut: &C,
    ) -> u32 {
        assert!(dirs.len() <= PACKET, "a packet holds at most {PACKET} rays");
        assert!(tmax.len() >= dirs.len(), "a ray end for every ray");
        if self.tris.is_empty() || dirs.is_empty() {
            return 0;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::simd::has_avx2() {
            let cut = self.cut_with(cut);
            // SAFETY: AVX2 was detected on this CPU.
            return unsafe { avx2::occluded_packet::<SHARED, C>(self, origins, dirs, tmax, &cut) };
        }
        // Without AVX2, one ray at a time: the same answers.
        let mut blocked = 0;
        for (r, d) in dirs.iter().enumerate() {
            let o = origins[if SHARED { 0 } else { r }];
            if self.occluded_within(o, *d, tmax[r], cut) {
                blocked |= 1 << r;
            }
        }
        blocked
    }

    /// obvhs's any-hit traversal (`ray_traverse_miss`) with our node and leaf kernels: the
    /// distance of the nearest accepted hit before `ray.tmax` among the first leaf triangles
    /// found hit, or None. With AVX2 (checked once at run time) a node's eight children and up
    /// to eight leaf triangles are tested per instruction, otherwise four with SSE2; both
    /// kernels perform the same float operations per child and per triangle, so every host
    /// finds the same children, the same hits and the same bits (farm hosts may differ in CPU).
    #[inline(always)]
    fn any_hit<C: Cutout + ?Sized>(&self, ray: &Ray, cut: &Cut<C>) -> Option<f32> {
        #[cfg(target_arch = "x86_64")]
        {
            if crate::simd::has_avx2() {
                // SAFETY: AVX2 was detected on this CPU.
                return unsafe { self.any_hit_avx2(ray, cut) };
            }
            self.any_hit_with(ray, node_hits, |p, base, mask, ray| {
                // SAFETY: `base..` + the mask's bits lie within the padded planes.
                unsafe { leaf::hit_sse2(p, base, mask, ray, cut) }
            })
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.any_hit_with(ray, node_hits, |p, base, mask, ray| {
            leaf::hit_scalar(p, base, mask, ray, cut)
        })
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn any_hit_avx2<C: Cutout + ?Sized>(&self, ray: &Ray, cut: &Cut<C>) -> Option<f32> {
        self.any_hit_with(
            ray,
            |node, ray, oct| avx2::node_hits_avx2(node, ray, oct),
            // SAFETY: as for the SSE2 kernel.
            |p, base, mask, ray| unsafe { leaf::hit_avx2(p, base, mask, ray, cut) },
        )
    }

    #[inline(always)]
    fn any_hit_with(
        &self,
        ray: &Ray,
        node_test: impl Fn(&CwBvhNode, &Ray, u32) -> u32,
        leaf_test: impl Fn(&TriPlanes, usize, u32, &Ray) -> (f32, usize),
    ) -> Option<f32> {
        use glam::UVec2;
        let mut state = self.bvh.new_traversal(ray.direction);
        let mut node;
        let mut found = None;
        'outer: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                node_test(node, ray, state.oct_inv4),
                {
                    // The macro hands out one triangle of the node's hit leaves at a time; take
                    // them all (the group's base and its remaining bits) and test them at once.
                    let base = state.primitive_group.x;
                    let mask = state.primitive_group.y | 1 << (state.primitive_id - base);
                    state.primitive_group.y = 0;
                    let (t, _) = leaf_test(&self.planes, base as usize, mask, ray);
                    if t < ray.tmax {
                        found = Some(t);
                        break 'outer;
                    }
                }
            );
        }
        found
    }

    /// [`blocker_distance`](Self::blocker_distance) for t in (0, `tmax`) with the cut-out
    /// test: blocked exactly when [`occluded_within`](Self::occluded_within) says so.
    fn blocker_distance_within<C: Cutout + ?Sized>(
        &self,
        origin: Vec3,
        dir: Vec3,
        tmax: f32,
        cut: &C,
    ) -> Option<f32> {
        if self.tris.is_empty() {
            return None;
        }
        let ray = ray(origin, dir, tmax);
        self.any_hit(&ray, &self.cut_with(cut))
    }
}

/// Triangles in the BVH's primitive order as twelve planes of floats (v0, v1, v2, and
/// n = e1 × e2 with obvhs's Möller–Trumbore edges e1 = v0 − v1, e2 = v2 − v0), precomputed
/// once so a leaf test loads what it needs with one load per plane. Each plane is padded so that a kernel
/// may read a whole chunk of lanes past the last triangle.
struct TriPlanes {
    stride: usize,
    data: Vec<f32>,
}

/// Planes, in order: v0, v1, v2, n (x, y, z each).
const PLANES: usize = 12;
/// Bits in a primitive group (obvhs's hit mask holds 24), so the padding a chunk may read.
const GROUP_BITS: usize = 24;

impl TriPlanes {
    fn new(tris: &[Triangle]) -> TriPlanes {
        let stride = tris.len() + GROUP_BITS + 8;
        let mut data = vec![0.0f32; PLANES * stride];
        for (i, t) in tris.iter().enumerate() {
            let e1 = t.v0 - t.v1;
            let e2 = t.v2 - t.v0;
            let n = e1.cross(e2);
            for (k, v) in [t.v0, t.v1, t.v2, n].iter().enumerate() {
                data[(3 * k) * stride + i] = v.x;
                data[(3 * k + 1) * stride + i] = v.y;
                data[(3 * k + 2) * stride + i] = v.z;
            }
        }
        TriPlanes { stride, data }
    }

    /// Plane `k` from triangle `i` on.
    #[inline(always)]
    fn at(&self, k: usize, i: usize) -> *const f32 {
        debug_assert!(i + 8 <= self.stride);
        // SAFETY (of later reads): callers read at most 8 lanes, within the padding.
        unsafe { self.data.as_ptr().add(k * self.stride + i) }
    }
}

/// The cut-out triangles and the test a query applies to them, for the leaf kernels.
struct Cut<'a, C: ?Sized> {
    /// [`Accel::cut`]: empty when no triangle is cut out.
    bits: &'a [u64],
    scene_index: &'a [u32],
    test: &'a C,
}

impl<C: Cutout + ?Sized> Cut<'_, C> {
    /// Bits `i..i + 8` of the cut-out set (primitive order), lowest first; `i + 8` lies within
    /// the planes' padding.
    #[inline(always)]
    fn lanes(&self, i: usize) -> u32 {
        if self.bits.is_empty() {
            return 0;
        }
        let (w, s) = (i / 64, i % 64);
        let mut v = self.bits[w] >> s;
        if s > 56 {
            v |= self.bits[w + 1] << (64 - s);
        }
        (v & 0xff) as u32
    }

    /// Whether the hit at barycentrics (u, v) on primitive `i` stops the ray.
    #[inline(always)]
    fn stops(&self, i: usize, u: f32, v: f32) -> bool {
        self.test.stops(self.scene_index[i], u, v)
    }
}

/// Leaf kernels: which of a primitive group's triangles a ray hits, as the nearest such t
/// before `ray.tmax` and that triangle's index (the first of equals; (`ray.tmax`, 0) when
/// none).
///
/// Watertight, after Woop, Benthin & Wald (2013): each vertex is taken relative to the ray's
/// origin and sheared into the ray's own frame ([`Shear`]: the axes permuted so `d`'s largest
/// component is the third, then `x = p[kx] − sx·p[kz]`, `y = p[ky] − sy·p[kz]`), where the
/// ray is the point (0, 0). The 2-D edge functions `e0 = c.x·b.y − c.y·b.x`,
/// `e1 = a.x·c.y − a.y·c.x`, `e2 = b.x·a.y − b.y·a.x` (weights of v0, v1, v2) are a hit when
/// none is negative while another is positive, and their sum `det = (e0 + e1) + e2` is not
/// zero. A vertex's sheared coordinates depend on the vertex and the ray only, and two
/// triangles sharing an edge form its function from the same two products in the opposite
/// order, which gives exactly the negated value: a ray cannot pass between them, one of the
/// two (or both) takes it (Möller–Trumbore's `u`, `v` and `1 − u − v`, from different
/// products, let 61 of 6,912 camera rays through a closed cube's face diagonals; issue 39).
/// The shear keeps the coordinates at the triangle's own size, so the edge functions round
/// relative to it, not to the distance from the origin: 3-D edge functions `d·(b × c)` of the
/// origin-relative vertices round at that distance squared and made a scene's edges differ
/// with its scale (tests/it/scale.rs).
///
/// `t = (n·a)·inv` with `a = v0 − o`, `inv = 1 / n·d` (a hit when `inv ≠ 0` and
/// 0 ≤ t < ∞) is Möller–Trumbore's, bit for bit, so a hit point and its rounding bound
/// (src/offset.rs) are what they were; the barycentrics a cut-out test reads are
/// `u = e1 / det` (weighting v1), `v = e2 / det` (v2), obvhs's convention.
///
/// Every kernel evaluates, per triangle, exactly these operations in this order, never
/// fused; lanes are independent, so four or eight at a time give the same bits. Hits are
/// taken in triangle order, each only if nearer than the best so far; a hit on a cut-out
/// triangle must then also pass the query's [`Cutout`] at the kernel's own (u, v), so every
/// kernel asks the same questions and keeps the same hit.
mod leaf {
    use super::*;

    /// A ray's frame for the edge functions: `kz` its direction's largest axis (the first of
    /// equals), `kx`, `ky` the next two in cyclic order, and the shear `sx = d[kx] / d[kz]`,
    /// `sy = d[ky] / d[kz]` that moves the ray onto the `kz` axis.
    pub(super) struct Shear {
        pub kx: usize,
        pub ky: usize,
        pub kz: usize,
        pub sx: f32,
        pub sy: f32,
    }

    impl Shear {
        #[inline(always)]
        pub(super) fn of(d: Vec3A) -> Shear {
            let a = d.abs();
            let kz = if a.x >= a.y && a.x >= a.z {
                0
            } else if a.y >= a.z {
                1
            } else {
                2
            };
            let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
            let d = d.to_array();
            Shear {
                kx,
                ky,
                kz,
                sx: d[kx] / d[kz],
                sy: d[ky] / d[kz],
            }
        }
    }

    /// Whether a hit on primitive `i` stops the ray: always, unless the triangle is cut out;
    /// then where the query's test says so at `u = e1 / det`, `v = e2 / det` (the weights of
    /// v1 and v2), computed only here, where they are read. Every kernel decides through it.
    #[inline(always)]
    fn stops<C: Cutout + ?Sized>(cut: &Cut<C>, cut_out: bool, i: usize, e: [f32; 3]) -> bool {
        let [e1, e2, det] = e;
        !cut_out || {
            let inv_det = 1.0 / det;
            cut.stops(i, e1 * inv_det, e2 * inv_det)
        }
    }

    /// The SIMD kernels' lanes `hits` of the group from primitive `i`, in order: each taken
    /// into `best` when nearer and it [`stops`] the ray. `cuts` are the cut-out lanes, for
    /// which `e` holds e1, e2 and det.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn take_lanes<C: Cutout + ?Sized, const N: usize>(
        cut: &Cut<C>,
        i: usize,
        mut hits: u32,
        cuts: u32,
        ts: &[f32; N],
        e: &[[f32; N]; 3],
        best: &mut (f32, usize),
    ) {
        while hits != 0 {
            let l = hits.trailing_zeros() as usize;
            let lane = [e[0][l], e[1][l], e[2][l]];
            if ts[l] < best.0 && stops(cut, cuts >> l & 1 != 0, i + l, lane) {
                *best = (ts[l], i + l);
            }
            hits &= hits - 1;
        }
    }

    /// One triangle, in plain f32 (the reference the SIMD lanes follow; non-x86 hosts).
    #[cfg_attr(all(target_arch = "x86_64", not(test)), allow(dead_code))]
    pub(super) fn hit_scalar<C: Cutout + ?Sized>(
        p: &TriPlanes,
        base: usize,
        mask: u32,
        ray: &Ray,
        cut: &Cut<C>,
    ) -> (f32, usize) {
        let (o, d) = (ray.origin, ray.direction);
        let s = Shear::of(d);
        let o3 = o.to_array();
        let (mut best, mut index) = (ray.tmax, 0);
        let mut m = mask;
        while m != 0 {
            let i = base + m.trailing_zeros() as usize;
            m &= m - 1;
            // SAFETY: i lies within the planes (the group's triangles exist).
            let g = |k: usize| unsafe { *p.at(k, i) };
            // Vertex j relative to the origin, sheared: (x, y) in the ray's frame.
            let sheared = |j: usize| {
                let r = |k: usize| g(3 * j + k) - o3[k];
                let z = r(s.kz);
                (r(s.kx) - s.sx * z, r(s.ky) - s.sy * z)
            };
            let (a, b, c) = (sheared(0), sheared(1), sheared(2));
            let e0 = c.0 * b.1 - c.1 * b.0;
            let e1 = a.0 * c.1 - a.1 * c.0;
            let e2 = b.0 * a.1 - b.1 * a.0;
            let det = (e0 + e1) + e2;
            let negative = e0 < 0.0 || e1 < 0.0 || e2 < 0.0;
            let positive = e0 > 0.0 || e1 > 0.0 || e2 > 0.0;
            let inv = 1.0 / ((g(9) * d.x + g(10) * d.y) + g(11) * d.z);
            let t = ((g(9) * (g(0) - o.x) + g(10) * (g(1) - o.y)) + g(11) * (g(2) - o.z)) * inv;
            if inv != 0.0
                && !(negative && positive)
                && det.abs() > 0.0
                && (0.0..f32::INFINITY).contains(&t)
                && t < best
                && stops(cut, cut.lanes(i) & 1 != 0, i, [e1, e2, det])
            {
                (best, index) = (t, i);
            }
        }
        (best, index)
    }

    /// Four triangles per step with SSE2.
    ///
    /// # Safety
    /// `base` + 24 lanes lie within the padded planes.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) unsafe fn hit_sse2<C: Cutout + ?Sized>(
        p: &TriPlanes,
        base: usize,
        mask: u32,
        ray: &Ray,
        cut: &Cut<C>,
    ) -> (f32, usize) {
        use std::arch::x86_64::*;
        let (o, d) = (ray.origin, ray.direction);
        let s = Shear::of(d);
        let mut best = (ray.tmax, 0);
        let mut m = mask;
        let mut i = base;
        unsafe {
            let (dx, dy, dz) = (_mm_set1_ps(d.x), _mm_set1_ps(d.y), _mm_set1_ps(d.z));
            let o4 = [_mm_set1_ps(o.x), _mm_set1_ps(o.y), _mm_set1_ps(o.z)];
            let (sx, sy) = (_mm_set1_ps(s.sx), _mm_set1_ps(s.sy));
            while m != 0 {
                let lanes = m & 0xf;
                if lanes != 0 {
                    let g = |k: usize| _mm_loadu_ps(p.at(k, i));
                    let r = |j: usize, k: usize| _mm_sub_ps(g(3 * j + k), o4[k]);
                    let sheared = |j: usize| {
                        let z = r(j, s.kz);
                        (
                            _mm_sub_ps(r(j, s.kx), _mm_mul_ps(sx, z)),
                            _mm_sub_ps(r(j, s.ky), _mm_mul_ps(sy, z)),
                        )
                    };
                    let (a, b, c) = (sheared(0), sheared(1), sheared(2));
                    let edge = |p: (__m128, __m128), q: (__m128, __m128)| {
                        _mm_sub_ps(_mm_mul_ps(p.0, q.1), _mm_mul_ps(p.1, q.0))
                    };
                    let (e0, e1, e2) = (edge(c, b), edge(a, c), edge(b, a));
                    let det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
                    let zero = _mm_setzero_ps();
                    let negative = _mm_movemask_ps(_mm_or_ps(
                        _mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)),
                        _mm_cmplt_ps(e2, zero),
                    ));
                    let positive = _mm_movemask_ps(_mm_or_ps(
                        _mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)),
                        _mm_cmpgt_ps(e2, zero),
                    ));
                    let nonzero = _mm_movemask_ps(_mm_or_ps(
                        _mm_cmplt_ps(det, zero),
                        _mm_cmpgt_ps(det, zero),
                    ));
                    let dot = |ax, ay, az, bx, by, bz| {
                        _mm_add_ps(
                            _mm_add_ps(_mm_mul_ps(ax, bx), _mm_mul_ps(ay, by)),
                            _mm_mul_ps(az, bz),
                        )
                    };
                    let (nx, ny, nz) = (g(9), g(10), g(11));
                    let inv = _mm_div_ps(_mm_set1_ps(1.0), dot(nx, ny, nz, dx, dy, dz));
                    let t = _mm_mul_ps(dot(nx, ny, nz, r(0, 0), r(0, 1), r(0, 2)), inv);
                    let ok = _mm_movemask_ps(_mm_cmpneq_ps(inv, zero))
                        & _mm_movemask_ps(_mm_cmpge_ps(t, zero))
                        & _mm_movemask_ps(_mm_cmplt_ps(t, _mm_set1_ps(f32::INFINITY)))
                        & nonzero
                        & !(negative & positive);
                    let hits = ok as u32 & lanes;
                    if hits != 0 {
                        let mut ts = [0.0f32; 4];
                        _mm_storeu_ps(ts.as_mut_ptr(), t);
                        let cuts = cut.lanes(i) & hits;
                        // The edge functions only where a cut-out test reads them.
                        let mut e = [[0.0f32; 4]; 3];
                        if cuts != 0 {
                            for (out, v) in e.iter_mut().zip([e1, e2, det]) {
                                _mm_storeu_ps(out.as_mut_ptr(), v);
                            }
                        }
                        take_lanes(cut, i, hits, cuts, &ts, &e, &mut best);
                    }
                }
                m >>= 4;
                i += 4;
            }
        }
        best
    }

    /// Eight triangles per step with AVX2 (no FMA: the same roundings as SSE2).
    ///
    /// # Safety
    /// As [`hit_sse2`], on a CPU with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn hit_avx2<C: Cutout + ?Sized>(
        p: &TriPlanes,
        base: usize,
        mask: u32,
        ray: &Ray,
        cut: &Cut<C>,
    ) -> (f32, usize) {
        use std::arch::x86_64::*;
        let (o, d) = (ray.origin, ray.direction);
        let s = Shear::of(d);
        let mut best = (ray.tmax, 0);
        let mut m = mask;
        let mut i = base;
        unsafe {
            let (dx, dy, dz) = (
                _mm256_set1_ps(d.x),
                _mm256_set1_ps(d.y),
                _mm256_set1_ps(d.z),
            );
            let o8 = [
                _mm256_set1_ps(o.x),
                _mm256_set1_ps(o.y),
                _mm256_set1_ps(o.z),
            ];
            let (sx, sy) = (_mm256_set1_ps(s.sx), _mm256_set1_ps(s.sy));
            while m != 0 {
                let lanes = m & 0xff;
                if lanes != 0 {
                    let g = |k: usize| _mm256_loadu_ps(p.at(k, i));
                    let r = |j: usize, k: usize| _mm256_sub_ps(g(3 * j + k), o8[k]);
                    let sheared = |j: usize| {
                        let z = r(j, s.kz);
                        (
                            _mm256_sub_ps(r(j, s.kx), _mm256_mul_ps(sx, z)),
                            _mm256_sub_ps(r(j, s.ky), _mm256_mul_ps(sy, z)),
                        )
                    };
                    let (a, b, c) = (sheared(0), sheared(1), sheared(2));
                    let edge = |p: (__m256, __m256), q: (__m256, __m256)| {
                        _mm256_sub_ps(_mm256_mul_ps(p.0, q.1), _mm256_mul_ps(p.1, q.0))
                    };
                    let (e0, e1, e2) = (edge(c, b), edge(a, c), edge(b, a));
                    let det = _mm256_add_ps(_mm256_add_ps(e0, e1), e2);
                    let zero = _mm256_setzero_ps();
                    let lt = |x| _mm256_cmp_ps::<_CMP_LT_OQ>(x, zero);
                    let gt = |x| _mm256_cmp_ps::<_CMP_GT_OQ>(x, zero);
                    let negative =
                        _mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(lt(e0), lt(e1)), lt(e2)));
                    let positive =
                        _mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(gt(e0), gt(e1)), gt(e2)));
                    let nonzero = _mm256_movemask_ps(_mm256_or_ps(lt(det), gt(det)));
                    let dot = |ax, ay, az, bx, by, bz| {
                        _mm256_add_ps(
                            _mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)),
                            _mm256_mul_ps(az, bz),
                        )
                    };
                    let (nx, ny, nz) = (g(9), g(10), g(11));
                    let inv = _mm256_div_ps(_mm256_set1_ps(1.0), dot(nx, ny, nz, dx, dy, dz));
                    let t = _mm256_mul_ps(dot(nx, ny, nz, r(0, 0), r(0, 1), r(0, 2)), inv);
                    let ok = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_NEQ_UQ>(inv, zero))
                        & _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GE_OQ>(t, zero))
                        & _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(
                            t,
                            _mm256_set1_ps(f32::INFINITY),
                        ))
                        & nonzero
                        & !(negative & positive);
                    let hits = ok as u32 & lanes;
                    if hits != 0 {
                        let mut ts = [0.0f32; 8];
                        _mm256_storeu_ps(ts.as_mut_ptr(), t);
                        let cuts = cut.lanes(i) & hits;
                        // The edge functions only where a cut-out test reads them.
                        let mut e = [[0.0f32; 8]; 3];
                        if cuts != 0 {
                            for (out, v) in e.iter_mut().zip([e1, e2, det]) {
                                _mm256_storeu_ps(out.as_mut_ptr(), v);
                            }
                        }
                        take_lanes(cut, i, hits, cuts, &ts, &e, &mut best);
                    }
                }
                m >>= 8;
                i += 8;
            }
        }
        best
    }
}

/// obvhs's octant code of a ray direction (`ray_get_octant_inv4`, which orders a node's
/// children for the ray's walk).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn octant_inv4(dir: Vec3A) -> u32 {
    (if dir.x < 0.0 { 0 } else { 0x0404_0404 })
        | (if dir.y < 0.0 { 0 } else { 0x0202_0202 })
        | (if dir.z < 0.0 { 0 } else { 0x0101_0101 })
}

/// obvhs's ray from `origin` along `dir` over t in [0, tmax), with negative zeros in the direction
/// made positive: obvhs takes the inverse of −0 as −1/ε but picks a box's near and far planes by
/// `d < 0`, false for −0, so a ray along an axis written with −0 (`-Vec3::Y`) missed every box.
#[inline(always)]
fn ray(origin: Vec3, dir: Vec3, tmax: f32) -> Ray {
    Ray::new(origin.into(), (dir + Vec3::ZERO).into(), 0.0, tmax)
}

/// One shadow ray as traced: origin and unit direction, t in (0, ∞).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowRay {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// Which children of `node` the ray's segment meets, in obvhs's hit-mask layout: obvhs's
/// `CwBvhNode::intersect_ray_simd` with the same float operations in the same order, but the
/// 8-bit child planes widened to floats eight at a time with SSE2 unpacks instead of one at a
/// time, all eight children tested at once, and the segment clipped to the ray's own
/// `[tmin, tmax]` where obvhs clips its near end at an absolute 1e-4 (`cwbvh::node::EPSILON`):
/// that constant culled every box within 1e-4 scene units of the ray's origin, so a model
/// authored in millimetres lost its shadows and one a thousand times smaller rendered nothing.
/// [`node_hits_reference`] is the same test one child at a time.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn node_hits(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
    use std::arch::x86_64::*;
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
        let tmin_ray = _mm_set1_ps(ray.tmin);
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
            let tmin = _mm_max_ps(tmin, tmin_ray);
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
mod avx2 {
    use super::*;
    use std::arch::x86_64::*;

    /// Up to [`PACKET`] shadow rays traversed together, ray r along `dirs[r]` from
    /// `origins[r]`, or with `SHARED` from `origins[0]` (one origin and many directions: a
    /// pixel's lights; many origins and one direction: a light's pixels): bit r of the result
    /// is set when ray r is occluded. Each ray meets a node's children through exactly
    /// the operations of [`node_hits_avx2`] (its slab ends chosen by its direction's signs, by
    /// a blend instead of a branch), so it reaches exactly the leaves it would reach alone, and
    /// tests them with [`leaf::hit_avx2`]: the answers are the single-ray answers. What the
    /// rays share is the walk — one stack, one pop and one widening of the child planes per
    /// node for all the rays that entered it, and independent work for the CPU to overlap.
    #[target_feature(enable = "avx2")]
    pub(super) fn occluded_packet<const SHARED: bool, C: Cutout + ?Sized>(
        accel: &Hierarchy,
        origins: &[Vec3],
        dirs: &[Vec3],
        tmax: &[f32],
        cut: &Cut<C>,
    ) -> u32 {
        use std::mem::MaybeUninit;
        const STACK: usize = 256;
        let n = dirs.len();
        debug_assert!((1..=PACKET).contains(&n));
        let bvh = &accel.bvh;
        let mut inv = [Vec3A::ZERO; PACKET];
        let mut sign = [0u8; PACKET];
        let mut dir = [Vec3A::ZERO; PACKET];
        let mut org = [Vec3A::ZERO; PACKET];
        // Ray r's origin in `org`.
        let at = |r: usize| if SHARED { 0 } else { r };
        for (r, d) in dirs.iter().enumerate() {
            let o = origins[at(r)];
            org[at(r)] = o.into();
            let single = ray(o, *d, f32::INFINITY);
            (dir[r], inv[r]) = (single.direction, single.inv_direction);
            let d = single.direction;
            sign[r] = (d.x < 0.0) as u8 | ((d.y < 0.0) as u8) << 1 | ((d.z < 0.0) as u8) << 2;
        }
        // Per sign pattern, the blend masks that swap an axis's slab ends.
        let mask = |on: bool| _mm256_castsi256_ps(_mm256_set1_epi32(-(on as i32)));
        let swaps: [[__m256; 3]; 8] =
            std::array::from_fn(|s| [mask(s & 1 != 0), mask(s & 2 != 0), mask(s & 4 != 0)]);
        // Near-first order for the first ray's octant (obvhs's slot order XOR the octant).
        let oct = 7 ^ sign[0] as u32;
        let oct = (oct & 1) << 2 | (oct & 2) | (oct & 4) >> 2;
        let all = if n == 32 { u32::MAX } else { (1u32 << n) - 1 };
        let mut done = 0u32;
        let mut stack = [MaybeUninit::<(u32, u32)>::uninit(); STACK];
        stack[0].write((0, all));
        let mut top = 1;
        // The rays' own range, (0, tmax), as `occluded` gives each ray alone.
        let tmin_ray = _mm256_setzero_ps();
        while top > 0 {
            top -= 1;
            // SAFETY: entries below `top` were written.
            let (ni, m0) = unsafe { stack[top].assume_init() };
            let m = m0 & !done;
            if m == 0 {
                continue;
            }
            let node = &bvh.nodes[ni as usize];
            // SAFETY: each load reads exactly the 8 bytes of one plane array.
            let widen = |v: &[u8; 8]| unsafe {
                _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(
                    v.as_ptr() as *const __m128i
                )))
            };
            let (lx, hx, ly, hy, lz, hz) = (
                widen(&node.child_min_x),
                widen(&node.child_max_x),
                widen(&node.child_min_y),
                widen(&node.child_max_y),
                widen(&node.child_min_z),
                widen(&node.child_max_z),
            );
            let extent = node.compute_extent();
            let p = Vec3A::from(node.p);
            let shared = p - org[0];
            let mut acc = _mm256_setzero_si256();
            let mut mm = m;
            while mm != 0 {
                let r = mm.trailing_zeros() as usize;
                mm &= mm - 1;
                // node_hits_avx2's `inv` and `org`, the same products.
                let ri = extent * inv[r];
                let ro = (if SHARED { shared } else { p - org[r] }) * inv[r];
                let slab = |lo: __m256, hi: __m256, i: f32, o: f32, sw: __m256| {
                    let (i, o) = (_mm256_set1_ps(i), _mm256_set1_ps(o));
                    let a = _mm256_add_ps(_mm256_mul_ps(lo, i), o);
                    let b = _mm256_add_ps(_mm256_mul_ps(hi, i), o);
                    (_mm256_blendv_ps(a, b, sw), _mm256_blendv_ps(b, a, sw))
                };
                let [sx, sy, sz] = swaps[sign[r] as usize];
                let (nx, fx) = slab(lx, hx, ri.x, ro.x, sx);
                let (ny, fy) = slab(ly, hy, ri.y, ro.y, sy);
                let (nz, fz) = slab(lz, hz, ri.z, ro.z, sz);
                let tmin = _mm256_max_ps(nx, _mm256_max_ps(ny, nz));
                let far = _mm256_min_ps(fx, _mm256_min_ps(fy, fz));
                let tmin = _mm256_max_ps(tmin, tmin_ray);
                let far = _mm256_min_ps(far, _mm256_set1_ps(tmax[r]));
                let hit = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(tmin, far));
                acc = _mm256_or_si256(acc, _mm256_and_si256(hit, _mm256_set1_epi32(1 << r)));
            }
            // Lane c: the rays that entered child c.
            let mut child_rays = [0u32; 8];
            // SAFETY: writes exactly the 32 bytes of the array.
            unsafe { _mm256_storeu_si256(child_rays.as_mut_ptr() as *mut __m256i, acc) };
            // Leaves: the rays their triangles block are done.
            done |= leaf_hits(
                accel,
                node,
                &child_rays,
                |r| org[at(r)],
                &dir,
                &inv,
                tmax,
                cut,
            );
            if done == all {
                break;
            }
            if top + 8 > STACK {
                // Deeper than any hierarchy we build; finish the open rays one at a time.
                for (r, d) in dirs.iter().enumerate() {
                    if done & (1 << r) == 0
                        && accel.occluded_within(origins[at(r)], *d, tmax[r], cut.test)
                    {
                        done |= 1 << r;
                    }
                }
                break;
            }
            // Inner children, pushed so the nearest (for the first ray's octant) pops first.
            for i in 0..8u32 {
                let c = i ^ oct;
                let rr = child_rays[c as usize] & !done;
                if node.imask & (1 << c) != 0 && rr != 0 {
                    let rel = (node.imask as u32 & ((1 << c) - 1)).count_ones();
                    stack[top].write((node.child_base_idx + rel, rr));
                    top += 1;
                }
            }
        }
        done
    }

    /// The rays of `child_rays` (lane c: the rays that entered child c of `node`) that its
    /// leaf children block: each ray tests the triangles of all the leaf children it entered
    /// at once (obvhs's primitive group: a unary count shifted to the leaf's offset), ray r
    /// from `origin(r)` along `dir[r]` up to `tmax[r]`.
    #[allow(clippy::too_many_arguments)]
    #[target_feature(enable = "avx2")]
    #[inline]
    fn leaf_hits<C: Cutout + ?Sized>(
        accel: &Hierarchy,
        node: &CwBvhNode,
        child_rays: &[u32; 8],
        origin: impl Fn(usize) -> Vec3A,
        dir: &[Vec3A; PACKET],
        inv: &[Vec3A; PACKET],
        tmax: &[f32],
        cut: &Cut<C>,
    ) -> u32 {
        let mut prim = [0u32; PACKET];
        let mut leaf_rays = 0u32;
        for (c, (&meta, &rr)) in node.child_meta.iter().zip(child_rays).enumerate() {
            if node.imask & (1 << c) != 0 || meta == 0 || rr == 0 {
                continue;
            }
            let bits = (meta >> 5) as u32 & 7;
            let bits = bits << (meta & 0x1f);
            leaf_rays |= rr;
            let mut rr = rr;
            while rr != 0 {
                let r = rr.trailing_zeros() as usize;
                rr &= rr - 1;
                prim[r] |= bits;
            }
        }
        let mut blocked = 0;
        while leaf_rays != 0 {
            let r = leaf_rays.trailing_zeros() as usize;
            leaf_rays &= leaf_rays - 1;
            let ray = Ray {
                origin: origin(r),
                direction: dir[r],
                inv_direction: inv[r],
                tmin: 0.0,
                tmax: tmax[r],
            };
            // SAFETY: the node's primitive group lies within the padded planes.
            let (t, _) = unsafe {
                leaf::hit_avx2(
                    &accel.planes,
                    node.primitive_base_idx as usize,
                    prim[r],
                    &ray,
                    cut,
                )
            };
            if t < ray.tmax {
                blocked |= 1 << r;
            }
        }
        blocked
    }

    /// Closest hits of the rays of `group` (bits of `rays`, all of octant `oct_inv4`), one
    /// walk for all: ray r's nearest hit (t, primitive) lands in `best[r]` (untouched when it
    /// hits nothing). The walk is obvhs's `traverse!` order for that octant — a node's leaf
    /// triangles tested as it is entered, then its inner children entered highest hit-mask bit
    /// first — with ray r carried into a child exactly when its own test hit that child. So
    /// the events that concern ray r are those of its walk alone, in the same order: the same
    /// node tests (those of [`node_hits_avx2`], against its nearest hit so far), the same leaf
    /// calls ([`leaf::hit_avx2`]), the same hit kept among equals.
    #[target_feature(enable = "avx2")]
    pub(super) fn closest_packet<C: Cutout>(
        accel: &Hierarchy,
        rays: &[Ray; PACKET],
        group: u32,
        oct_inv4: u32,
        cuts: &[C],
        best: &mut [(f32, usize); PACKET],
    ) {
        use std::mem::MaybeUninit;
        const STACK: usize = 256;
        let bvh = &accel.bvh;
        let first = &rays[group.trailing_zeros() as usize];
        let (origin, d) = (first.origin, first.direction);
        let mut stack = [MaybeUninit::<(u32, u32)>::uninit(); STACK];
        stack[0].write((0, group));
        let mut top = 1;
        let mut gone = 0u32;
        // SAFETY: each load reads exactly the 8 bytes of one plane array.
        let widen = |v: &[u8; 8]| unsafe {
            _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(
                v.as_ptr() as *const __m128i
            )))
        };
        let bytes = |v: u64| _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(v as i64));
        while top > 0 {
            top -= 1;
            // SAFETY: entries below `top` were written.
            let (ni, m) = unsafe { stack[top].assume_init() };
            let m = m & !gone;
            if m == 0 {
                continue;
            }
            let node = &bvh.nodes[ni as usize];
            // node_hits_avx2's slab ends, chosen once for the octant's signs.
            let ends = |neg: bool, lo: &[u8; 8], hi: &[u8; 8]| {
                if neg {
                    (widen(hi), widen(lo))
                } else {
                    (widen(lo), widen(hi))
                }
            };
            let (lo_x, hi_x) = ends(d.x < 0.0, &node.child_min_x, &node.child_max_x);
            let (lo_y, hi_y) = ends(d.y < 0.0, &node.child_min_y, &node.child_max_y);
            let (lo_z, hi_z) = ends(d.z < 0.0, &node.child_min_z, &node.child_max_z);
            let extent = node.compute_extent();
            let offset = Vec3A::from(node.p) - origin;
            let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
            let child_bits = _mm256_sllv_epi32(bytes(child_bits8), bytes(bit_index8));
            // Bit b: the rays that entered the inner child at hit-mask bit 24 + b.
            let mut entered = [0u32; 8];
            let mut mm = m;
            while mm != 0 {
                let r = mm.trailing_zeros() as usize;
                mm &= mm - 1;
                let ray = &rays[r];
                let inv = extent * ray.inv_direction;
                let org = offset * ray.inv_direction;
                let slab = |q: __m256, inv: f32, org: f32| {
                    _mm256_add_ps(_mm256_mul_ps(q, _mm256_set1_ps(inv)), _mm256_set1_ps(org))
                };
                let tmin = _mm256_max_ps(
                    slab(lo_x, inv.x, org.x),
                    _mm256_max_ps(slab(lo_y, inv.y, org.y), slab(lo_z, inv.z, org.z)),
                );
                let tmax = _mm256_min_ps(
                    slab(hi_x, inv.x, org.x),
                    _mm256_min_ps(slab(hi_y, inv.y, org.y), slab(hi_z, inv.z, org.z)),
                );
                let tmin = _mm256_max_ps(tmin, _mm256_set1_ps(ray.tmin));
                let tmax = _mm256_min_ps(tmax, _mm256_set1_ps(best[r].0));
                let hit = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(tmin, tmax));
                let bits = _mm256_and_si256(child_bits, hit);
                let x = _mm_or_si128(
                    _mm256_castsi256_si128(bits),
                    _mm256_extracti128_si256::<1>(bits),
                );
                let x = _mm_or_si128(x, _mm_shuffle_epi32::<0b00_00_11_10>(x));
                let x = _mm_or_si128(x, _mm_shuffle_epi32::<0b00_00_00_01>(x));
                let hitmask = _mm_cvtsi128_si32(x) as u32;
                let prims = hitmask & 0x00ff_ffff;
                if prims != 0 {
                    let ray = Ray {
                        tmax: best[r].0,
                        ..*ray
                    };
                    let cut = accel.cut_with(&cuts[r]);
                    // SAFETY: the node's primitive group lies within the padded planes.
                    let (t, i) = unsafe {
                        leaf::hit_avx2(
                            &accel.planes,
                            node.primitive_base_idx as usize,
                            prims,
                            &ray,
                            &cut,
                        )
                    };
                    if t < ray.tmax {
                        best[r] = (t, i);
                    }
                }
                let mut inner = hitmask >> 24;
                while inner != 0 {
                    let b = inner.trailing_zeros() as usize;
                    inner &= inner - 1;
                    entered[b] |= 1 << r;
                }
            }
            if top + 8 > STACK {
                // Deeper than any hierarchy we build: these rays walk alone from the root
                // instead (the same answers), and leave the packet.
                let mut mm = m;
                while mm != 0 {
                    let r = mm.trailing_zeros() as usize;
                    mm &= mm - 1;
                    let cut = accel.cut_with(&cuts[r]);
                    best[r] = accel
                        .closest_avx2(&rays[r], &cut)
                        .unwrap_or((f32::INFINITY, usize::MAX));
                }
                gone |= m;
                continue;
            }
            // Highest bit entered first: pushed last.
            for (b, &rr) in entered.iter().enumerate() {
                if rr != 0 {
                    let slot = b as u32 ^ (oct_inv4 & 0xff);
                    let rel = (node.imask as u32 & ((1 << slot) - 1)).count_ones();
                    stack[top].write((node.child_base_idx + rel, rr));
                    top += 1;
                }
            }
        }
    }

    /// [`node_hits`](super::node_hits) with eight children per instruction: each child's
    /// slab distances are `plane · inv + org` (a multiply then an add, never fused, as in
    /// obvhs), clipped to the ray's `[tmin, tmax]`, compared `tmin ≤ tmax`.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub fn node_hits_avx2(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
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
        let tmin = _mm256_max_ps(tmin, _mm256_set1_ps(ray.tmin));
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
    node_hits_reference(node, ray, oct_inv4)
}

/// [`node_hits`] one child at a time in plain f32: obvhs's `intersect_ray_basic` with the
/// segment clipped to the ray's own `[tmin, tmax]` (the kernels' reference; non-x86 hosts).
#[cfg_attr(all(target_arch = "x86_64", not(test)), allow(dead_code))]
fn node_hits_reference(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
    let inv = node.compute_extent() * ray.inv_direction;
    let org = (Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
    let d = ray.direction;
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut hit_mask = 0;
    for c in 0..8 {
        let ends = |lo: u8, hi: u8, neg: bool| {
            let (a, b) = if neg { (hi, lo) } else { (lo, hi) };
            (a as f32, b as f32)
        };
        let (nx, fx) = ends(node.child_min_x[c], node.child_max_x[c], d.x < 0.0);
        let (ny, fy) = ends(node.child_min_y[c], node.child_max_y[c], d.y < 0.0);
        let (nz, fz) = ends(node.child_min_z[c], node.child_max_z[c], d.z < 0.0);
        let near = (nx * inv.x + org.x)
            .max((ny * inv.y + org.y).max(nz * inv.z + org.z))
            .max(ray.tmin);
        let far = (fx * inv.x + org.x)
            .min((fy * inv.y + org.y).min(fz * inv.z + org.z))
            .min(ray.tmax);
        if near <= far {
            hit_mask |= extract_byte64(child_bits8, c) << extract_byte64(bit_index8, c);
        }
    }
    hit_mask
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

    /// A deterministic generator of floats in [0, 1) for the random-soup tests.
    struct Lcg(u32);

    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_mul(1664525).wrapping_add(1013904223);
            (self.0 >> 8) as f32 / (1u32 << 24) as f32
        }

        fn vec(&mut self) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next())
        }
    }

    /// `n` random triangles of size up to `size`, their corners within `half` (plus `size`)
    /// of the origin.
    fn soup(rng: &mut Lcg, n: u32, half: f32, size: f32) -> Accel {
        soup_cut(rng, n, half, size, &[])
    }

    /// [`soup`] with triangle `i` cut out where `cut_out[i]`.
    fn soup_cut(rng: &mut Lcg, n: u32, half: f32, size: f32, cut_out: &[bool]) -> Accel {
        let (p, t) = soup_triangles(rng, n, half, size);
        Accel::build_with_cutouts(&p, &t, cut_out)
    }

    /// The positions and triangles of [`soup`].
    fn soup_triangles(rng: &mut Lcg, n: u32, half: f32, size: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        let mut t = Vec::new();
        for i in 0..n {
            let c = rng.vec() * (2.0 * half) - half;
            for _ in 0..3 {
                p.push(c + rng.vec() * size);
            }
            t.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        (p, t)
    }

    /// Every query of `split` against `whole` (the same triangles in one hierarchy) on random
    /// rays through the soup's box, with the cut-out test `Stripes`: the same answers, bit for
    /// bit (random triangles never tie).
    fn same_answers(split: &Accel, whole: &Accel, rng: &mut Lcg) {
        for k in 0..400 {
            let o = rng.vec() * 8.0 - 4.0;
            let dirs: Vec<Vec3> = (0..PACKET)
                .map(|_| (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y))
                .collect();
            let tmax: Vec<f32> = (0..PACKET)
                .map(|r| if r % 3 == 0 { 2.0 } else { f32::INFINITY })
                .collect();
            let d = dirs[0];
            assert_eq!(
                split.intersect_cut(o, d, &Stripes),
                whole.intersect_cut(o, d, &Stripes),
                "ray {k}"
            );
            assert_eq!(
                split
                    .blocker_distance_within(o, d, tmax[0], &Stripes)
                    .is_some(),
                whole.occluded_within(o, d, tmax[0], &Stripes),
                "ray {k}"
            );
            assert_eq!(
                split.occluded_packet_within(o, &dirs, &tmax, &Stripes),
                whole.occluded_packet_within(o, &dirs, &tmax, &Stripes),
                "packet {k}"
            );
            let origins: Vec<Vec3> = dirs.iter().map(|&d| o + d * 0.5).collect();
            let along = vec![d; PACKET];
            assert_eq!(
                split.occluded_rays_within(&origins, &along, &tmax, &Stripes),
                whole.occluded_rays_within(&origins, &along, &tmax, &Stripes),
                "parallel packet {k}"
            );
            let cuts: Vec<Stripes> = (0..PACKET).map(|_| Stripes).collect();
            let (mut a, mut b) = ([None; PACKET], [None; PACKET]);
            split.intersect_packet_cut(o, &dirs, &cuts, &mut a);
            whole.intersect_packet_cut(o, &dirs, &cuts, &mut b);
            assert_eq!(a, b, "camera packet {k}");
        }
    }

    #[test]
    fn a_split_hierarchy_answers_as_one_over_every_triangle_in_every_pose() {
        let mut rng = Lcg(17);
        let n = 600;
        let (mut p, t) = soup_triangles(&mut rng, n, 3.0, 0.8);
        let cut_out = two_in_three(n);
        let moving: Vec<bool> = (0..n).map(|i| i % 4 == 1).collect();
        let split = Split::new(&p, &t, &cut_out, &moving);
        let first = split.accel(&p, &t, &cut_out);
        assert!(first.moving.is_some(), "two hierarchies");
        same_answers(
            &first,
            &Accel::build_with_cutouts(&p, &t, &cut_out),
            &mut rng,
        );
        // Another pose: the moving triangles shift, the still hierarchy is shared.
        for (i, tri) in t.iter().enumerate() {
            if moving[i] {
                for &v in tri {
                    p[v as usize] += Vec3::new(0.7, -0.3, 0.2);
                }
            }
        }
        let posed = split.accel(&p, &t, &cut_out);
        assert!(
            Arc::ptr_eq(&posed.still, &split.still),
            "the still part is shared"
        );
        same_answers(
            &posed,
            &Accel::build_with_cutouts(&p, &t, &cut_out),
            &mut rng,
        );
        // A still triangle that moved after all: the whole is rebuilt, and still right.
        p[0] += Vec3::X;
        let rebuilt = split.accel(&p, &t, &cut_out);
        assert!(rebuilt.moving.is_none(), "rebuilt whole");
        same_answers(
            &rebuilt,
            &Accel::build_with_cutouts(&p, &t, &cut_out),
            &mut rng,
        );
    }

    /// A cut-out test with holes in every triangle: stripes across (u, v), shifted per
    /// triangle; a little over half of each triangle stops rays.
    struct Stripes;

    impl Cutout for Stripes {
        fn stops(&self, tri: u32, u: f32, v: f32) -> bool {
            let x = u * 5.0 + v * 3.0 + tri as f32 * 0.37;
            x - x.floor() < 0.55
        }
    }

    /// Two triangles of three cut out (those with `i % 3 != 0`).
    fn two_in_three(n: u32) -> Vec<bool> {
        (0..n).map(|i| i % 3 != 0).collect()
    }

    /// The nearest hit of the ray on any one triangle that `cut` lets stop it, t < tmax, by
    /// testing every triangle alone with the scalar kernel (the reference for the traversals).
    fn brute_force<C: Cutout>(accel: &Accel, ray: &Ray, cut: &C) -> Option<(f32, u32)> {
        let cut = accel.single().cut_with(cut);
        let mut best: Option<(f32, u32)> = None;
        for i in 0..accel.single().tris.len() {
            let (t, _) = leaf::hit_scalar(&accel.single().planes, i, 1, ray, &cut);
            if t < ray.tmax && best.is_none_or(|(b, _)| t < b) {
                best = Some((t, accel.single().scene_index[i]));
            }
        }
        best
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
    fn our_node_test_agrees_with_the_reference_on_every_node() {
        // A random soup, rays from points inside and outside it in all octants: the children
        // our kernels report must be exactly the reference's, or traversal (and hits) could
        // differ; and the traversal must find what testing every triangle finds.
        let mut rng = Lcg(12345);
        let accel = soup(&mut rng, 2000, 2.0, 0.2);
        let mut checked = 0;
        for _ in 0..300 {
            let o = rng.vec() * 6.0 - 3.0;
            let d = (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y);
            let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
            let oct = accel.single().bvh.new_traversal(ray.direction).oct_inv4;
            for node in &accel.single().bvh.nodes {
                let reference = node_hits_reference(node, &ray, oct);
                assert_eq!(node_hits(node, &ray, oct), reference);
                #[cfg(target_arch = "x86_64")]
                if is_x86_feature_detected!("avx2") {
                    // SAFETY: AVX2 was detected.
                    assert_eq!(unsafe { avx2::node_hits_avx2(node, &ray, oct) }, reference);
                }
                checked += 1;
            }
            // Every triangle tested alone (obvhs's own triangle test): the nearest hit, and
            // whether there is any.
            let nearest = (0..accel.single().tris.len())
                .map(|i| {
                    (
                        accel.single().tris[i].intersect(&ray),
                        accel.single().scene_index[i],
                    )
                })
                .filter(|h| h.0 < f32::INFINITY)
                .min_by(|a, b| a.0.total_cmp(&b.0));
            assert_eq!(accel.occluded(o, d), nearest.is_some());
            assert_eq!(accel.intersect(o, d).map(|h| h.t), nearest.map(|h| h.0));
        }
        assert!(checked > 1000);
    }

    #[test]
    fn boxes_right_at_the_origin_are_not_culled() {
        // obvhs clips a node's segment at 1e-4 from the origin: a blocker nearer than that was
        // missed. The same two triangles at scales from 1e-8 to 1e4: a ray from just below the
        // upper one is blocked, and a camera ray just above it hits it, at every scale.
        for scale in [1e-8f32, 1e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4] {
            let (p, t) = quad();
            let p: Vec<Vec3> = p.iter().map(|v| *v * scale).collect();
            let accel = Accel::build(&p, &t);
            // Off the squares' diagonals, where both triangles' edge tests could refuse a ray.
            let below = Vec3::new(0.03, 0.999, -0.02) * scale;
            assert!(accel.occluded(below, Vec3::Y), "scale {scale}");
            assert_eq!(accel.occluded_packet(below, &[Vec3::Y, Vec3::X]), 1);
            let above = Vec3::new(0.03, 1.001, -0.02) * scale;
            let hit = accel
                .intersect(above, -Vec3::Y)
                .expect("hits the small square");
            assert!(
                (hit.t / scale - 0.001).abs() < 1e-5,
                "scale {scale}: {}",
                hit.t
            );
        }
    }

    #[test]
    fn packets_answer_exactly_as_single_rays() {
        // A soup dense enough that about half the rays are blocked; origins inside and outside
        // it, every packet size from 1 to PACKET, directions in all octants mixed in a packet.
        let mut rng = Lcg(4242);
        let accel = soup(&mut rng, 3000, 2.0, 0.3);
        let (mut rays, mut blocked) = (0, 0);
        for k in 0..400 {
            let o = rng.vec() * 5.0 - 2.5;
            let n = 1 + k % PACKET;
            let dirs: Vec<Vec3> = (0..n)
                .map(|_| (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y))
                .collect();
            let single: u32 = dirs
                .iter()
                .enumerate()
                .map(|(r, d)| u32::from(accel.occluded(o, *d)) << r)
                .sum();
            assert_eq!(accel.occluded_packet(o, &dirs), single, "packet {k}");
            rays += n;
            blocked += single.count_ones() as usize;
        }
        // Both answers occur often, or agreement would prove little.
        assert!(
            blocked > rays / 5 && blocked < rays * 4 / 5,
            "{blocked} of {rays}"
        );
        assert_eq!(
            Accel::build(&[], &[]).occluded_packet(Vec3::ZERO, &[Vec3::Y]),
            0
        );
    }

    /// Stripes shifted by a per-ray amount: each camera ray has its own cut-out test (its
    /// sample's coverage threshold).
    struct Shifted(f32);

    impl Cutout for Shifted {
        fn stops(&self, tri: u32, u: f32, v: f32) -> bool {
            let x = u * 5.0 + v * 3.0 + tri as f32 * 0.37 + self.0;
            x - x.floor() < 0.55
        }
    }

    #[test]
    fn closest_hit_packets_find_exactly_the_single_rays_hits() {
        // A random soup with two triangles in three cut out (each ray its own test), then a
        // grid of quads whose shared edges and corners the rays aim at (hits tied between
        // triangles, where the walk's order decides). Packets of every size: a pixel's
        // nearly parallel rays, and rays in every octant mixed (axis-aligned ones with −0).
        let mut rng = Lcg(2718);
        let n = 4000;
        let soup = soup_cut(&mut rng, n, 2.0, 0.3, &two_in_three(n));
        let (mut p, mut t) = (Vec::new(), Vec::new());
        let side = 24u32;
        for j in 0..=side {
            for i in 0..=side {
                p.push(Vec3::new(
                    i as f32 / side as f32,
                    0.0,
                    j as f32 / side as f32,
                ));
            }
        }
        for j in 0..side {
            for i in 0..side {
                let c = j * (side + 1) + i;
                t.push([c, c + side + 1, c + 1]);
                t.push([c + 1, c + side + 1, c + side + 2]);
            }
        }
        let grid = Accel::build(&p, &t);
        let (mut rays, mut hits) = (0, 0);
        for (accel, targets) in [(&soup, false), (&grid, true)] {
            for k in 0..300 {
                let o = if targets {
                    Vec3::new(0.5, 1.0 + rng.next(), 0.5)
                } else {
                    rng.vec() * 5.0 - 2.5
                };
                let n = 1 + k % PACKET;
                let base = (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y);
                let dirs: Vec<Vec3> = (0..n)
                    .map(|r| match (targets, k % 3) {
                        // At grid corners and edge midpoints.
                        (true, _) => {
                            let a = (rng.next() * side as f32).floor() / side as f32;
                            let b = (rng.next() * 2.0 * side as f32).floor() / (2 * side) as f32;
                            (Vec3::new(a, 0.0, b) - o).normalize()
                        }
                        (false, 0) => (base + (rng.vec() - 0.5) * 0.002).normalize(),
                        (false, 1) => [Vec3::X, -Vec3::Y, -Vec3::Z, Vec3::Y][r % 4],
                        _ => (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y),
                    })
                    .collect();
                let cuts: Vec<Shifted> = (0..n).map(|_| Shifted(rng.next())).collect();
                let mut packet = vec![None; n];
                accel.intersect_packet_cut(o, &dirs, &cuts, &mut packet);
                for (r, d) in dirs.iter().enumerate() {
                    let single = accel.intersect_cut(o, *d, &cuts[r]);
                    let bits = |h: Option<Hit>| {
                        h.map(|h| (h.t.to_bits(), h.tri, h.u.to_bits(), h.v.to_bits()))
                    };
                    assert_eq!(bits(packet[r]), bits(single), "packet {k}, ray {r}");
                    hits += usize::from(single.is_some());
                }
                rays += n;
            }
        }
        // Both answers occur often, or agreement would prove little.
        assert!(hits > rays / 5 && hits < rays * 4 / 5, "{hits} of {rays}");
        let mut none = [Some(Hit {
            t: 0.0,
            tri: 0,
            u: 0.0,
            v: 0.0,
        })];
        Accel::build(&[], &[]).intersect_packet_cut(Vec3::ZERO, &[Vec3::Y], &[Opaque], &mut none);
        assert_eq!(none, [None]);
    }

    /// Parallel rays from many origins (a light's queries from a patch of points): the
    /// single-ray answers, ray for ray.
    #[test]
    fn parallel_packets_answer_exactly_as_single_rays() {
        let mut rng = Lcg(77);
        let accel = soup(&mut rng, 3000, 2.0, 0.3);
        let (mut rays, mut blocked) = (0, 0);
        let inf = [f32::INFINITY; PACKET];
        for k in 0..400 {
            let n = 1 + k % PACKET;
            let dir = (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y);
            let centre = rng.vec() * 5.0 - 2.5;
            let origins: Vec<Vec3> = (0..n).map(|_| centre + rng.vec() * 0.05).collect();
            let dirs = vec![dir; n];
            let single: u32 = origins
                .iter()
                .enumerate()
                .map(|(r, o)| u32::from(accel.occluded(*o, dir)) << r)
                .sum();
            let packed = accel.occluded_rays_within(&origins, &dirs, &inf, &Opaque);
            assert_eq!(packed, single, "parallel packet {k}");
            rays += n;
            blocked += single.count_ones() as usize;
        }
        assert!(
            blocked > rays / 5 && blocked < rays * 4 / 5,
            "{blocked} of {rays}"
        );
    }

    /// The scalar leaf kernel's hit for `mask` of the group at `base`, after checking that
    /// the SSE2 and (where the CPU has it) AVX2 kernels give the same bits.
    fn leaf_kernels<C: Cutout>(
        accel: &Accel,
        base: usize,
        mask: u32,
        ray: &Ray,
        test: &C,
        k: usize,
    ) -> (f32, usize) {
        let cut = accel.single().cut_with(test);
        let scalar = leaf::hit_scalar(&accel.single().planes, base, mask, ray, &cut);
        #[cfg(target_arch = "x86_64")]
        {
            let bitwise = |(t, i): (f32, usize)| (t.to_bits(), i);
            // SAFETY: base + 24 lies within the padded planes.
            let sse = unsafe { leaf::hit_sse2(&accel.single().planes, base, mask, ray, &cut) };
            assert_eq!(bitwise(sse), bitwise(scalar), "ray {k}");
            if is_x86_feature_detected!("avx2") {
                // SAFETY: as above, and AVX2 was detected.
                let avx = unsafe { leaf::hit_avx2(&accel.single().planes, base, mask, ray, &cut) };
                assert_eq!(bitwise(avx), bitwise(scalar), "ray {k}");
            }
        }
        scalar
    }

    /// The edge functions round at the triangle's size, not at its distance from the ray's
    /// origin: rays from 10⁴ away decide inside and outside as a near ray does, wherever
    /// they pass farther from an edge than a vertex's own rounding there (a ulp of 10⁴:
    /// 10⁻³; 10⁻² asked). 3-D edge functions `d·(b × c)` of the origin-relative vertices
    /// round at that distance squared, took rays 5 % of a triangle outside its edges and
    /// left holes 5 % inside, so a scene rendered differently at another scale.
    #[test]
    fn edges_are_decided_at_the_triangles_size_however_far_the_origin() {
        let mut rng = Lcg(4242);
        let mut asked = 0;
        for k in 0..3000 {
            let v: [Vec3; 3] = std::array::from_fn(|_| rng.vec() - 0.5);
            let accel = Accel::build(&v, &[[0, 1, 2]]);
            let far = (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Z) * 1e4;
            // Aim 2 % of the way inside or outside the nearest edge, in barycentrics.
            let (mut a, mut b) = (rng.next(), rng.next());
            if a + b > 1.0 {
                (a, b) = (1.0 - a, 1.0 - b);
            }
            let w = [1.0 - a - b, a, b];
            let low = (0..3).min_by(|&i, &j| w[i].total_cmp(&w[j])).unwrap();
            let mut w = w.map(|x| x.max(0.04));
            w[low] = if k % 2 == 0 { 0.02 } else { -0.02 };
            let sum: f32 = w.iter().sum();
            let target = (v[0] * w[0] + v[1] * w[1] + v[2] * w[2]) / sum;
            let d = (target - far).normalize();
            let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
            if n.dot(d).abs() < 0.2 {
                continue; // grazing: the edge's margin is a sliver of the view
            }
            let ray = Ray::new(far.into(), d.into(), 0.0, f32::INFINITY);
            let by = inside_distance(&accel.single().tris[0], &ray);
            if by.abs() < 1e-2 {
                continue;
            }
            let (t, _) = leaf_kernels(&accel, 0, 1, &ray, &Opaque, k);
            assert_eq!(
                t < f32::INFINITY,
                by > 0.0,
                "ray {k} from {far}: {by} inside"
            );
            asked += 1;
        }
        assert!(asked > 1000, "{asked}");
    }

    /// How far inside triangle `tri` the ray passes through its plane, in f64: the signed
    /// distance to its nearest edge's line (negative outside).
    fn inside_distance(tri: &Triangle, ray: &Ray) -> f64 {
        let f = |v: Vec3A| glam::DVec3::new(v.x.into(), v.y.into(), v.z.into());
        let (o, d) = (f(ray.origin), f(ray.direction));
        let v = [f(tri.v0), f(tri.v1), f(tri.v2)];
        let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        let p = o + d * (n.dot(v[0] - o) / n.dot(d));
        (0..3)
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % 3]);
                n.cross(b - a).normalize().dot(p - a)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// How far inside triangle `tri` the ray passes: the least of its three barycentrics,
    /// in f64 (negative outside).
    fn inside_by(tri: &Triangle, ray: &Ray) -> f64 {
        let f = |v: Vec3A| glam::DVec3::new(v.x.into(), v.y.into(), v.z.into());
        let (o, d) = (f(ray.origin), f(ray.direction));
        let (a, b, c) = (f(tri.v0) - o, f(tri.v1) - o, f(tri.v2) - o);
        let (e0, e1, e2) = (d.dot(b.cross(c)), d.dot(c.cross(a)), d.dot(a.cross(b)));
        let det = e0 + e1 + e2;
        (e0 / det).min(e1 / det).min(e2 / det)
    }

    #[test]
    fn leaf_kernels_agree_with_obvhs_and_each_other_bit_for_bit() {
        // Rays aimed at points of a dense soup (so many hit, some on edges), each leaf group of
        // up to 24 triangles at random offsets: scalar, SSE2 and AVX2 give the same nearest t,
        // and that t is the nearest of obvhs's own triangle test over the same triangles —
        // except where the two tests see a ray through an edge or a vertex differently
        // (obvhs's Möller–Trumbore is not watertight), which the triangle they disagree on
        // must then show: the ray passes within 1e-4 of its edge (f32 rounding).
        let mut rng = Lcg(777);
        let accel = soup(&mut rng, 600, 1.0, 0.5);
        let n = accel.single().tris.len();
        let mut hits = 0;
        for k in 0..4000 {
            let o = rng.vec() * 8.0 - 4.0;
            let base = (rng.next() * (n - 24) as f32) as usize;
            let mask = (rng.next() * (1 << 24) as f32) as u32 | 1;
            // Aim at one of the group's triangles: inside it, or (every fourth ray) through a
            // vertex, where the edge rules decide.
            let aim = &accel.single().tris[base + (rng.next() * 23.0) as usize];
            let (a, b) = (rng.next(), rng.next());
            let target: Vec3 = if k % 4 == 0 {
                aim.v1.into()
            } else {
                let (a, b) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                (aim.v0 + (aim.v1 - aim.v0) * a + (aim.v2 - aim.v0) * b).into()
            };
            let d = (target - o).normalize_or(Vec3::Y);
            let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
            let (mut reference, mut reference_index) = (f32::INFINITY, 0);
            for b in 0..24 {
                if mask >> b & 1 == 1 {
                    let t = accel.single().tris[base + b].intersect(&ray);
                    if t < reference {
                        (reference, reference_index) = (t, base + b);
                    }
                }
            }
            let scalar = leaf_kernels(&accel, base, mask, &ray, &Opaque, k);
            if scalar.0.to_bits() != reference.to_bits() {
                // The nearer of the two answers is the triangle one test took and the other
                // refused: on its edge.
                let disputed = if scalar.0 < reference {
                    scalar.1
                } else {
                    reference_index
                };
                let inside = inside_by(&accel.single().tris[disputed], &ray);
                assert!(
                    inside.abs() < 1e-4,
                    "ray {k}: t {} against obvhs's {reference}, {inside} inside triangle {disputed}",
                    scalar.0
                );
                continue;
            }
            if scalar.0 < f32::INFINITY {
                assert_eq!(accel.single().tris[scalar.1].intersect(&ray), scalar.0);
            }
            hits += usize::from(scalar.0 < f32::INFINITY);
        }
        assert!(
            hits > 1000,
            "only {hits} rays hit: the test would prove little"
        );
    }

    #[test]
    fn cut_out_triangles_stop_rays_only_where_the_test_says() {
        // A cut-out soup traced with the stripes, and with finite ray ends: every query
        // agrees with testing each triangle alone (closest hit: the same triangle and t;
        // occlusion and blocker: whether any accepted hit lies before the end). The same soup
        // without the test (Opaque) is blocked more often, or the holes would prove nothing.
        let mut rng = Lcg(9001);
        let n = 3000;
        let accel = soup_cut(&mut rng, n, 2.0, 0.5, &two_in_three(n));
        assert!(accel.has_cutouts());
        let (mut blocked, mut blocked_opaque, mut cut_hits, mut ends) = (0, 0, 0, 0);
        for k in 0..600 {
            let o = rng.vec() * 5.0 - 2.5;
            let d = (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y);
            let tmax = if k % 2 == 0 {
                f32::INFINITY
            } else {
                rng.next() * 3.0
            };
            let ray = Ray::new(o.into(), d.into(), 0.0, tmax);
            let want = brute_force(&accel, &ray, &Stripes);
            let occluded = accel.occluded_within(o, d, tmax, &Stripes);
            assert_eq!(occluded, want.is_some(), "ray {k}");
            let blocker = accel.blocker_distance_within(o, d, tmax, &Stripes);
            assert_eq!(blocker.is_some(), occluded, "ray {k}");
            if let Some(t) = blocker {
                assert!(t < tmax && t >= want.unwrap().0, "ray {k}: {t} vs {want:?}");
            }
            if tmax == f32::INFINITY {
                let hit = accel.intersect_cut(o, d, &Stripes).map(|h| (h.t, h.tri));
                assert_eq!(hit, want, "ray {k}");
                cut_hits += usize::from(hit.is_some_and(|(_, tri)| tri % 3 != 0));
            } else {
                ends += usize::from(
                    brute_force(
                        &accel,
                        &Ray::new(o.into(), d.into(), 0.0, f32::INFINITY),
                        &Stripes,
                    )
                    .is_some_and(|(t, _)| t >= tmax),
                );
            }
            blocked += usize::from(occluded);
            blocked_opaque += usize::from(accel.occluded_within(o, d, tmax, &Opaque));
        }
        assert!(
            blocked > 100 && blocked + 30 < blocked_opaque,
            "{blocked} vs {blocked_opaque}"
        );
        assert!(
            cut_hits > 50,
            "only {cut_hits} closest hits on cut-out triangles"
        );
        assert!(ends > 20, "only {ends} rays ended before their hit");
    }

    #[test]
    fn cut_out_packets_answer_exactly_as_single_rays() {
        // As `packets_answer_exactly_as_single_rays`, with two triangles in three cut out and
        // each ray its own end (some infinite, some short).
        let mut rng = Lcg(31337);
        let n = 5000;
        let accel = soup_cut(&mut rng, n, 2.0, 0.4, &two_in_three(n));
        let (mut rays, mut blocked) = (0, 0);
        for k in 0..400 {
            let o = rng.vec() * 5.0 - 2.5;
            let n = 1 + k % PACKET;
            let dirs: Vec<Vec3> = (0..n)
                .map(|_| (rng.vec() * 2.0 - 1.0).normalize_or(Vec3::Y))
                .collect();
            let tmax: Vec<f32> = (0..n)
                .map(|r| {
                    if r % 3 == 0 {
                        f32::INFINITY
                    } else {
                        rng.next() * 4.0
                    }
                })
                .collect();
            let single: u32 = dirs
                .iter()
                .zip(&tmax)
                .enumerate()
                .map(|(r, (d, &t))| u32::from(accel.occluded_within(o, *d, t, &Stripes)) << r)
                .sum();
            assert_eq!(
                accel.occluded_packet_within(o, &dirs, &tmax, &Stripes),
                single,
                "packet {k}"
            );
            rays += n;
            blocked += single.count_ones() as usize;
        }
        assert!(
            blocked > rays / 5 && blocked < rays * 4 / 5,
            "{blocked} of {rays}"
        );
    }

    #[test]
    fn cut_out_leaf_kernels_agree_bit_for_bit() {
        // Leaf groups of a cut-out soup: scalar, SSE2 and AVX2 keep the same hit, and it is
        // the nearest of the group's triangles tested one at a time.
        let mut rng = Lcg(4711);
        let n = 600;
        let accel = soup_cut(&mut rng, n, 1.0, 0.5, &two_in_three(n));
        let cut = accel.single().cut_with(&Stripes);
        let count = accel.single().tris.len();
        let (mut hits, mut passed) = (0, 0);
        for k in 0..4000 {
            let o = rng.vec() * 8.0 - 4.0;
            let base = (rng.next() * (count - 24) as f32) as usize;
            let mask = (rng.next() * (1 << 24) as f32) as u32 | 1;
            let aim = &accel.single().tris[base + (rng.next() * 23.0) as usize];
            let (a, b) = (rng.next() * 0.5, rng.next() * 0.5);
            let target: Vec3 = (aim.v0 + (aim.v1 - aim.v0) * a + (aim.v2 - aim.v0) * b).into();
            let d = (target - o).normalize_or(Vec3::Y);
            let ray = Ray::new(o.into(), d.into(), 0.0, f32::INFINITY);
            let mut reference = (f32::INFINITY, 0);
            let mut any_hit = false;
            for b in 0..24 {
                if mask >> b & 1 == 1 {
                    let alone = leaf::hit_scalar(&accel.single().planes, base + b, 1, &ray, &cut);
                    if alone.0 < reference.0 {
                        reference = alone;
                    }
                    any_hit |= accel.single().tris[base + b].intersect(&ray) < f32::INFINITY;
                }
            }
            let scalar = leaf_kernels(&accel, base, mask, &ray, &Stripes, k);
            assert_eq!(
                (scalar.0.to_bits(), scalar.1),
                (reference.0.to_bits(), reference.1),
                "ray {k}"
            );
            hits += usize::from(scalar.0 < f32::INFINITY);
            passed += usize::from(any_hit && scalar.0 == f32::INFINITY);
        }
        assert!(hits > 1000, "only {hits} rays hit");
        assert!(passed > 100, "only {passed} rays passed through holes");
    }
}
