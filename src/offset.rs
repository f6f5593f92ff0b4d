//! Where a shadow ray starts: the hit point moved off its surface by a bound on the point's own
//! floating-point error, as pbrt-v4 does (`Triangle::InteractionFromIntersection`,
//! `OffsetRayOrigin`), so the ray cannot find the surface it leaves at any scale or distance
//! from the origin — a constant or a fraction of the scene's size leaks light through thin
//! parts of large scenes and hides whole objects of small ones.
//!
//! [`hit_point`] interpolates the point from the triangle's corners and bounds its error;
//! [`offset_origin`] moves it along the geometric normal by that bound projected on the normal,
//! `dot(|n|, err)`, and rounds each moved coordinate one float further away from the surface.
//!
//! [ours] Two departures from pbrt-v4, both because our triangle test is obvhs's
//! Möller–Trumbore (`t ≥ 0`), not pbrt's watertight test with its conservative `t > δt`:
//! - the bound also covers the triangle test's own rounding of the surface it leaves: that test
//!   evaluates the plane through the corner `p0` with the edges' cross products, so its error
//!   grows with the triangle's size as well as with the coordinates, and with every axis's
//!   (the products mix them): `err = γ7 · max(|p0| + |e1| + |e2|)` on each axis, where pbrt's
//!   per-axis `γ7 · Σ|bᵢ pᵢ|` would let a large triangle near the origin find itself again
//!   (`tests::no_ray_finds_the_triangle_it_leaves`) and gives a panel lying in a coordinate
//!   plane through the origin no offset at all: every ray found the panel
//!   (`tests::a_panel_in_a_coordinate_plane_through_the_origin_does_not_shadow_itself`);
//! - every ray of a point starts from one origin on the viewer's side (pbrt flips the offset to
//!   the side each ray leaves towards): a pixel's rays are traced as one packet from one point,
//!   and a light below the geometric surface is blocked by it, as it should be.

use glam::Vec3;

/// pbrt's γ(n) = nε / (1 − nε), ε = 2⁻²⁴ (half an ulp of 1): a bound on the relative error of
/// n chained f32 operations.
#[inline]
pub fn gamma(n: u32) -> f32 {
    let e = n as f32 * (f32::EPSILON * 0.5);
    e / (1.0 - e)
}

/// The point at barycentrics `(u, v)` of triangle `p` — `p0 + u·(p1 − p0) + v·(p2 − p0)`, which
/// lies on the triangle's plane for any `u, v` — and a per-axis bound on how far the computed
/// point, and the triangle test's idea of the plane, are from exact (see the module doc).
#[inline]
pub fn hit_point(p: [Vec3; 3], u: f32, v: f32) -> (Vec3, Vec3) {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let point = p[0] + e1 * u + e2 * v;
    // The same bound on every axis: the triangle test's cross products mix the axes, so a
    // triangle whose coordinates are exact on its normal's axis (a panel in the plane z = 0)
    // still finds itself through the rounding of the others.
    let err = Vec3::splat((p[0].abs() + e1.abs() + e2.abs()).max_element() * gamma(7));
    (point, err)
}

/// The origin of a ray leaving `p` (error bound `err`, from [`hit_point`]) on the side of the
/// unit geometric normal `ng`: `p + dot(|ng|, err)·ng`, each coordinate then rounded one float
/// further along `ng` (pbrt-v4's `OffsetRayOrigin`).
#[inline]
pub fn offset_origin(p: Vec3, err: Vec3, ng: Vec3) -> Vec3 {
    let d = ng.abs().dot(err);
    let o = p + ng * d;
    let away = |o: f32, n: f32| {
        if n > 0.0 {
            o.next_up()
        } else if n < 0.0 {
            o.next_down()
        } else {
            o
        }
    };
    Vec3::new(away(o.x, ng.x), away(o.y, ng.y), away(o.z, ng.z))
}

/// How far to move a shadow ray's point `p` (at barycentrics `(u, v)` of the triangle with
/// `corners`) onto the smooth surface its vertex `normals` describe, seen from `side` (1 on
/// the normals' side, −1 behind them): Hanika's shadow-terminator fix ("Hacking the Shadow
/// Terminator", Ray Tracing Gems II, 2021), `Σ bᵢ · max(0, −(p − cᵢ)·nᵢ) · nᵢ` — the point
/// projected onto each corner's tangent plane where it lies below it, blended by the
/// barycentrics. Zero on flat parts (every normal the face's) and on concave ones (the point
/// above every tangent plane); on a coarse convex mesh it lifts the point out of the shadow
/// of its own neighbouring facets, which is what draws a faceted terminator. [ours] Zero
/// where the blend would point below the triangle (normals bent past its plane), so a ray
/// never leaves from under the surface it starts on.
#[inline]
pub fn terminator_lift(
    p: Vec3,
    corners: [Vec3; 3],
    normals: [Vec3; 3],
    (u, v): (f32, f32),
    side: f32,
    ng: Vec3,
) -> Vec3 {
    let w = [1.0 - u - v, u, v];
    let mut lift = Vec3::ZERO;
    for i in 0..3 {
        let n = normals[i] * side;
        let below = (p - corners[i]).dot(n);
        if below < 0.0 {
            lift -= n * (below * w[i]);
        }
    }
    if lift.dot(ng) > 0.0 && lift.is_finite() {
        lift
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Accel;

    /// A deterministic generator of floats in [0, 1).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }

        fn vec(&mut self) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0
        }
    }

    /// Signed distance of `o` from the exact plane of `p`, along the normal `ng` points to,
    /// in f64 (so the rounding under test does not decide it).
    fn height(p: [Vec3; 3], ng: Vec3, o: Vec3) -> f64 {
        let d = |v: Vec3| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
        let n = (d(p[1]) - d(p[0])).cross(d(p[2]) - d(p[0])).normalize();
        let n = if n.dot(d(ng)) < 0.0 { -n } else { n };
        n.dot(d(o) - d(p[0]))
    }

    #[test]
    fn gamma_bounds_grow_with_the_operations() {
        assert!(gamma(1) > f32::EPSILON * 0.5 && gamma(1) < f32::EPSILON);
        assert!(gamma(7) > 7.0 * f32::EPSILON * 0.5 && gamma(7) < 4.0 * f32::EPSILON);
    }

    #[test]
    fn the_origin_lies_off_the_exact_plane_at_every_scale_and_place() {
        // Triangles of every size from 1e-15 to 1e15, near the origin and far from it, long
        // and thin or even: the offset origin is strictly on the normal's side of the exact
        // plane, and not further than a few thousand ulps of the point's coordinates.
        let mut rng = Lcg(7);
        let mut checked = 0;
        for scale in [1e-15f32, 1e-9, 1e-6, 1e-4, 1.0, 1e4, 1e6, 1e9, 1e15] {
            for shift in [0.0f32, 1e3, 1e6] {
                for k in 0..300 {
                    let centre = rng.vec() * scale * shift;
                    let thin = if k % 3 == 0 { 1e-3 } else { 1.0 };
                    let a = rng.vec() * scale;
                    let p = [
                        centre + a,
                        centre + a + rng.vec() * scale,
                        centre + a * thin,
                    ];
                    let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                    if ng == Vec3::ZERO || !ng.is_finite() {
                        continue;
                    }
                    let (mut u, mut v) = (rng.next(), rng.next());
                    if u + v > 1.0 {
                        (u, v) = (1.0 - u, 1.0 - v);
                    }
                    let (point, err) = hit_point(p, u, v);
                    for side in [ng, -ng] {
                        let o = offset_origin(point, err, side);
                        let h = height(p, side, o);
                        assert!(h > 0.0, "scale {scale} shift {shift} case {k}: {h}");
                        let reach = (point.abs().max_element() as f64).max(scale as f64);
                        assert!(h < reach * 1e-3, "scale {scale}: offset {h} too far");
                        checked += 1;
                    }
                }
            }
        }
        // Scales whose cross products leave f32's range (1e±15) have no normal to test.
        assert!(checked > 4_000, "{checked}");
    }

    #[test]
    fn no_ray_finds_the_triangle_it_leaves() {
        // One triangle at a time, large and small, at the origin and far off it (and a thin
        // sliver): every ray from the offset origin into the normal's half space misses it,
        // the closest-hit and both occlusion forms alike.
        let mut rng = Lcg(99);
        let mut rays = 0;
        for scale in [1e-6f32, 1e-2, 1.0, 1e2, 1e5] {
            for shift in [0.0f32, 0.5, 1e3] {
                for k in 0..40 {
                    let centre = rng.vec() * scale * shift;
                    let p = [
                        centre + rng.vec() * scale,
                        centre + rng.vec() * scale,
                        centre + rng.vec() * scale * if k % 4 == 0 { 1e-3 } else { 1.0 },
                    ];
                    let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                    if ng == Vec3::ZERO {
                        continue;
                    }
                    let accel = Accel::build(&p, &[[0, 1, 2]]);
                    for _ in 0..20 {
                        let (mut u, mut v) = (rng.next(), rng.next());
                        if u + v > 1.0 {
                            (u, v) = (1.0 - u, 1.0 - v);
                        }
                        let (point, err) = hit_point(p, u, v);
                        for side in [ng, -ng] {
                            let o = offset_origin(point, err, side);
                            let mut dirs = Vec::new();
                            while dirs.len() < 8 {
                                let d = rng.vec().normalize_or_zero();
                                // Grazing rays too: any direction strictly above the plane.
                                if d.dot(side) > 0.0 {
                                    dirs.push(d);
                                }
                            }
                            for d in &dirs {
                                assert!(
                                    !accel.occluded(o, *d),
                                    "scale {scale} shift {shift}: {o} {d}"
                                );
                                assert!(accel.intersect(o, *d).is_none());
                            }
                            assert_eq!(accel.occluded_packet(o, &dirs), 0);
                            rays += dirs.len();
                        }
                    }
                }
            }
        }
        assert!(rays > 10_000, "{rays}");
    }

    #[test]
    fn a_panel_in_a_coordinate_plane_through_the_origin_does_not_shadow_itself() {
        // A quad whose coordinate on its normal's axis is exactly 0 (the corpus's
        // alpha_mask_panels lattice, frame 0: x from -0.6 to -5.6e-17, y to 0.8, z = 0): a
        // per-axis bound is 0 there, the origin moved by one subnormal, and rays leaving one
        // triangle found the other, coplanar one at t = 0.
        let mut rng = Lcg(5);
        let mut rays = 0;
        for scale in [1e-4f32, 1.0, 1e3] {
            for axis in 0..3 {
                let flat = |x: f32, y: f32| {
                    let mut v = [x, y, 0.0];
                    v.rotate_right(axis);
                    Vec3::from_array(v) * scale
                };
                // A post standing off the panel's plane, as the rest of a scene does: a flat
                // bounding box alone would turn the rays away before the triangle test.
                let post = |x: f32, y: f32, z: f32| {
                    let mut v = [x, y, z];
                    v.rotate_right(axis);
                    Vec3::from_array(v) * scale
                };
                let p = [
                    flat(-0.6, 0.0),
                    flat(-5.551115e-17, 0.0),
                    flat(-5.551115e-17, 0.8),
                    flat(-0.6, 0.8),
                    post(3.0, 0.0, -1.0),
                    post(3.0, 0.1, 1.0),
                    post(3.1, 0.0, 1.0),
                ];
                let quad = [[0, 1, 2], [0, 2, 3]];
                let accel = Accel::build(&p, &[quad[0], quad[1], [4, 5, 6]]);
                let post_only = Accel::build(&p, &[[4, 5, 6]]);
                for k in 0..400 {
                    let t = quad[k % 2];
                    let tri = [p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]];
                    let ng = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
                    let (mut u, mut v) = (rng.next(), rng.next());
                    if u + v > 1.0 {
                        (u, v) = (1.0 - u, 1.0 - v);
                    }
                    let (point, err) = hit_point(tri, u, v);
                    for side in [ng, -ng] {
                        let o = offset_origin(point, err, side);
                        let mut dirs = Vec::new();
                        while dirs.len() < 8 {
                            let d = rng.vec().normalize_or_zero();
                            if d.dot(side) > 0.0 {
                                dirs.push(d);
                            }
                        }
                        for d in &dirs {
                            assert_eq!(
                                accel.occluded(o, *d),
                                post_only.occluded(o, *d),
                                "{scale} {axis}: {o} {d}"
                            );
                        }
                        assert_eq!(
                            accel.occluded_packet(o, &dirs),
                            post_only.occluded_packet(o, &dirs)
                        );
                        rays += dirs.len();
                    }
                }
            }
        }
        assert!(rays > 10_000, "{rays}");
    }

    /// Hanika's lift: zero on a flat patch (every corner normal the face's) and on a concave
    /// one; on a convex one it moves the point outwards, onto the tangent planes it lies
    /// below — and seen from behind (`side` −1) the same patch is concave.
    #[test]
    fn the_terminator_lift_raises_points_of_convex_patches_only() {
        let c = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let p = Vec3::new(0.25, 0.25, 0.0);
        let bary = (0.25, 0.25);
        let up = Vec3::Z;
        assert_eq!(terminator_lift(p, c, [up; 3], bary, 1.0, up), Vec3::ZERO);
        // Corner normals leaning away from the centroid: a cap (convex).
        let centre = Vec3::new(1.0 / 3.0, 1.0 / 3.0, 0.0);
        let cap = c.map(|v| (v - centre + up * 4.0).normalize());
        let lift = terminator_lift(p, c, cap, bary, 1.0, up);
        assert!(lift.z > 0.0 && lift.z < 0.1, "{lift}");
        // The same cap seen from below is a bowl: no lift.
        assert_eq!(terminator_lift(p, c, cap, bary, -1.0, -up), Vec3::ZERO);
        // Normals leaning towards the centroid: a bowl from above, a cap from below.
        let bowl = c.map(|v| (centre - v + up * 4.0).normalize());
        assert_eq!(terminator_lift(p, c, bowl, bary, 1.0, up), Vec3::ZERO);
        let under = terminator_lift(p, c, bowl, bary, -1.0, -up);
        assert!(under.z < 0.0, "{under}");
        // At a corner the point lies on that corner's tangent plane: nothing to lift.
        assert_eq!(
            terminator_lift(c[0], c, cap, (0.0, 0.0), 1.0, up),
            Vec3::ZERO
        );
    }
}
