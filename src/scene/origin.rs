//! The render origin: where a scene's f32 coordinates are counted from.
//!
//! A model placed far from the world's origin (a site 10⁶ m out in map coordinates, a part in
//! a large assembly) keeps its shape in its file — vertices near its nodes' origins, the large
//! offset in the node transforms — but f32 world coordinates round it away: at 10⁶ they are
//! 6 cm apart. [ours] As pbrt-v4 renders in a space centred on the camera rather than in world
//! space, and for the same reason, the loader composes node transforms in f64 and stores
//! every point relative to a render origin near the scene; positions in specs (camera target
//! and position, spin pivot) are moved the same way, and stats.csv reports world positions.
//!
//! The origin is zero unless the scene's centre is far from the world's origin for its size,
//! so scenes modelled around the origin keep their coordinates (and their renders) exactly;
//! otherwise it is the centre rounded to a multiple of a power of two at least the scene's
//! size, so that a scene moved by such a multiple (10⁶ is 2⁶ · 15625) keeps its f32
//! coordinates but for f64's rounding of the move (2⁻³³ at 10⁶).

use glam::DVec3;

/// How far (in scene sizes) the scene's centre may lie from the world's origin before its
/// coordinates are counted from a render origin near it: at 16 sizes away, f32 keeps 20 of
/// its 24 bits across the scene.
const FAR: f64 = 16.0;

/// The render origin of a scene whose world-space bounds are `lo`..`hi` (computed in f64);
/// zero for empty, non-finite or near-origin bounds.
pub fn render_origin(lo: DVec3, hi: DVec3) -> DVec3 {
    let size = (hi - lo).max_element();
    let centre = (lo + hi) * 0.5;
    if !(size > 0.0 && size.is_finite() && centre.is_finite())
        || centre.abs().max_element() <= FAR * size
    {
        return DVec3::ZERO;
    }
    let grid = power_of_two_at_least(size);
    DVec3::new(
        libm::round(centre.x / grid) * grid,
        libm::round(centre.y / grid) * grid,
        libm::round(centre.z / grid) * grid,
    )
}

/// The smallest power of two ≥ `x` (x positive, finite, normal).
fn power_of_two_at_least(x: f64) -> f64 {
    let bits = x.to_bits();
    let exponent = bits & (0x7ff << 52);
    let power = f64::from_bits(exponent);
    if power == x { power } else { power * 2.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_near_the_origin_keep_their_coordinates() {
        let o = render_origin(DVec3::new(-5.0, 0.0, -5.0), DVec3::new(5.0, 1.2, 5.0));
        assert_eq!(o, DVec3::ZERO);
        // A 15 cm model 2 m off the origin: still near.
        let o = render_origin(DVec3::new(2.0, 0.0, 0.0), DVec3::new(2.15, 0.15, 0.15));
        assert_eq!(o, DVec3::ZERO);
        assert_eq!(render_origin(DVec3::ONE, DVec3::ONE), DVec3::ZERO);
        let nan = DVec3::splat(f64::NAN);
        assert_eq!(render_origin(nan, nan), DVec3::ZERO);
    }

    #[test]
    fn far_scenes_count_from_a_grid_point_near_their_centre() {
        let lo = DVec3::new(1e6 - 5.0, 0.0, -5.0);
        let hi = DVec3::new(1e6 + 5.0, 1.2, 5.0);
        let o = render_origin(lo, hi);
        // A multiple of 16 (the power of two at least the size, 10): 10⁶ itself.
        assert_eq!(o, DVec3::new(1e6, 0.0, 0.0));
        for v in [lo, hi] {
            assert!((v - o).abs().max_element() <= 16.0);
        }
        assert_eq!(power_of_two_at_least(10.0), 16.0);
        assert_eq!(power_of_two_at_least(16.0), 16.0);
        assert_eq!(power_of_two_at_least(0.1), 0.125);
    }
}
