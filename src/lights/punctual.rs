//! Lights placed by the scene file (glTF's `KHR_lights_punctual`), in the map's units.
//!
//! Units [ours]: the extension gives lux for directional lights and candela for point and spot
//! lights; the map's lights are radiometric (E_j = ∫ L dω over a cell, in the map's radiance
//! units). A photometric value becomes radiometric divided by 683 lm/W, the convention of
//! Blender's glTF exporter and importer ("Standard" lighting mode): a Blender sun of strength
//! 10 W/m² is written as 6830 lux and lights here as a map light of energy 10 would, and a
//! point light of P watts (written as P/4π × 683 cd) has radiant intensity P/4π. So:
//!
//! - a directional light is a light of the set like the map's ([`super::Light`]), with energy
//!   E = colour × lux / 683 (its irradiance on a surface facing it);
//! - a point light at distance d along unit direction ω from a surface of normal n gives
//!   irradiance colour × cd / 683 × max(0, n·ω) / d² × window(d), with the extension's
//!   recommended range window `clamp(1 − (d / range)⁴, 0, 1)²` (1 without a range);
//! - a spot light multiplies that by the extension's smooth cone falloff: with
//!   `scale = 1 / max(0.001, cos inner − cos outer)`, `offset = −cos outer × scale` and `c` the
//!   cosine between its axis and −ω, `clamp(c × scale + offset, 0, 1)²`.

use glam::Vec3;

use crate::scene::{SceneLight, SceneLightKind};

/// Lumens per watt: photometric units to the map's radiometric ones.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Shadow rays to a point or spot light end this fraction short of it (pbrt-v4's
/// `ShadowEpsilon`), so a light placed on a surface is not blocked by that surface.
pub const SHADOW_END: f32 = 1e-4;

/// A point or spot light of the scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    /// World-space position.
    pub position: Vec3,
    /// Radiant intensity, RGB in the map's units per steradian: colour × cd / 683.
    pub intensity: Vec3,
    /// Where its influence ends (∞ without a range).
    pub range: f32,
    /// The cone of a spot light.
    pub spot: Option<Cone>,
}

/// A spot light's cone, as the falloff uses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Unit direction the light shines along.
    pub axis: Vec3,
    /// Cosine of the outer angle: no light at or beyond it.
    pub cos_outer: f32,
    /// The falloff's `scale` and `offset` (module doc).
    pub scale: f32,
    pub offset: f32,
}

impl Cone {
    /// The cone of a spot light shining along `axis` with the given angles (radians).
    pub fn new(axis: Vec3, inner: f32, outer: f32) -> Cone {
        let (ci, co) = (libm::cosf(inner), libm::cosf(outer));
        let scale = 1.0 / (ci - co).max(0.001);
        Cone {
            axis,
            cos_outer: co,
            scale,
            offset: -co * scale,
        }
    }

    /// The falloff towards unit direction `out` (from the light): 1 inside the inner cone, 0
    /// at and beyond the outer one, smooth between.
    #[inline]
    pub fn falloff(&self, out: Vec3) -> f32 {
        let c = self.axis.dot(out);
        if c <= self.cos_outer {
            return 0.0;
        }
        let t = (c * self.scale + self.offset).clamp(0.0, 1.0);
        t * t
    }
}

/// What a point or spot light gives a surface point: the unit direction towards the light, its
/// distance, and the irradiance it would give a surface facing it (0 where the range or the
/// cone leaves it none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incidence {
    pub dir: Vec3,
    pub dist: f32,
    pub irradiance: Vec3,
}

impl PointLight {
    /// How the light reaches point `p`. `None` when it cannot: `p` at the light, beyond its
    /// range, outside its cone, or the light black.
    #[inline]
    pub fn at(&self, p: Vec3) -> Option<Incidence> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        let dist = dist2.sqrt();
        if !(dist > 0.0 && dist < self.range && dist.is_finite()) {
            return None;
        }
        let dir = d / dist;
        let mut k = 1.0 / dist2;
        if self.range < f32::INFINITY {
            let q = dist / self.range;
            let q2 = q * q;
            let w = (1.0 - q2 * q2).clamp(0.0, 1.0);
            k *= w * w;
        }
        if let Some(cone) = &self.spot {
            k *= cone.falloff(-dir);
        }
        let irradiance = self.intensity * k;
        if k > 0.0 && irradiance.max_element() > 0.0 {
            Some(Incidence {
                dir,
                dist,
                irradiance,
            })
        } else {
            None
        }
    }
}

/// Where a light of the scene file went in the light set, and what the file said of it (for
/// the lights JSON and messages).
#[derive(Clone, Debug, PartialEq)]
pub struct FileLight {
    pub name: String,
    /// `directional`, `point` or `spot`.
    pub kind: &'static str,
    /// Its bit in the visibility bitsets: an index into the set's directional lights, or past
    /// them into its point lights.
    pub index: usize,
    pub color: Vec3,
    /// As in the file: lux or candela.
    pub intensity: f32,
    /// Spot cone angles, radians, as in the file.
    pub cone: Option<(f32, f32)>,
}

/// A file light as it joins the set: a directional light's unit direction towards it and its
/// energy, or a point or spot light.
pub(super) enum Joined {
    Directional { dir: Vec3, energy: Vec3 },
    Point(PointLight),
}

/// The light a [`SceneLight`] becomes, in the map's units (module doc).
pub(super) fn convert(l: &SceneLight) -> Joined {
    let scale = l.color * (l.intensity / LUMENS_PER_WATT);
    match l.kind {
        SceneLightKind::Directional => Joined::Directional {
            dir: -l.direction,
            energy: scale,
        },
        SceneLightKind::Point => Joined::Point(PointLight {
            position: l.position,
            intensity: scale,
            range: l.range.unwrap_or(f32::INFINITY),
            spot: None,
        }),
        SceneLightKind::Spot { inner, outer } => Joined::Point(PointLight {
            position: l.position,
            intensity: scale,
            range: l.range.unwrap_or(f32::INFINITY),
            spot: Some(Cone::new(l.direction, inner, outer)),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(range: f32, spot: Option<Cone>) -> PointLight {
        PointLight {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: Vec3::splat(683.0 / LUMENS_PER_WATT * 4.0),
            range,
            spot,
        }
    }

    #[test]
    fn inverse_square_range_window_and_cone() {
        let free = point(f32::INFINITY, None);
        let at = free.at(Vec3::ZERO).unwrap();
        assert_eq!((at.dir, at.dist), (Vec3::Y, 2.0));
        assert!((at.irradiance.x - 1.0).abs() < 1e-6, "4 / 2² = 1");
        let side = free.at(Vec3::new(2.0, 0.0, 0.0)).unwrap();
        assert!((side.irradiance.x - 0.5).abs() < 1e-6, "4 / 8");
        assert!(free.at(free.position).is_none());
        // Range 4: at d = 2 the window is (1 − 1/16)²; at or past 4 nothing.
        let ranged = point(4.0, None);
        let w = (1.0f32 - 1.0 / 16.0).powi(2);
        assert!((ranged.at(Vec3::ZERO).unwrap().irradiance.x - w).abs() < 1e-6);
        assert!(ranged.at(Vec3::new(0.0, -2.0, 0.0)).is_none());
        // A spot straight down, inner 20°, outer 40°.
        let (inner, outer) = (20f32.to_radians(), 40f32.to_radians());
        let spot = point(f32::INFINITY, Some(Cone::new(-Vec3::Y, inner, outer)));
        let off_axis = |deg: f32| {
            let r = 2.0 * libm::tanf(deg.to_radians());
            spot.at(Vec3::new(r, 0.0, 0.0))
                .map_or(0.0, |i| i.irradiance.x * i.dist * i.dist / 4.0)
        };
        assert!((off_axis(0.0) - 1.0).abs() < 1e-6);
        assert!((off_axis(19.9) - 1.0).abs() < 1e-6);
        assert_eq!(off_axis(40.1), 0.0);
        let mid = off_axis(30.0);
        let cos = libm::cosf;
        let t = (cos(30f32.to_radians()) - cos(outer)) / (cos(inner) - cos(outer));
        assert!((mid - t * t).abs() < 1e-5, "{mid} vs {}", t * t);
        // Monotone from the inner to the outer edge.
        let mut last = 1.0;
        for k in 0..=40 {
            let v = off_axis(20.0 + k as f32 * 0.5);
            assert!(v <= last + 1e-6, "{k}: {v} after {last}");
            last = v;
        }
    }
}
