//! The shading rate: how often a pixel's samples evaluate their material's light (REYES's
//! shading rate, MSAA's decoupled shading). Visibility is always decided per sample — each
//! sample keeps its own bits and coverage — but at the pixel rate the samples of a pixel that
//! see the same surface share one evaluation of every light's unshadowed term, at their mean
//! normal and view direction, weighted by how many of them see the light
//! (`crate::shade::counted`); samples on different surfaces (silhouettes, creases, another
//! material, sharp normal-map detail) are shaded apart.

use std::fmt;
use std::str::FromStr;

use crate::context::Surface;

/// How often a pixel's samples are shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadingRate {
    /// Once per pixel surface: the samples of a pixel that see the same surface share their
    /// lobe's evaluation (the default: see BENCHMARKS.md, "Shading once per pixel surface").
    #[default]
    Pixel,
    /// Once per sample: every sample evaluates every visible light, as before the pixel rate.
    Sample,
}

impl ShadingRate {
    pub const ALL: [ShadingRate; 2] = [ShadingRate::Pixel, ShadingRate::Sample];

    /// The name on the command line and in specs.
    pub fn name(self) -> &'static str {
        match self {
            ShadingRate::Pixel => "pixel",
            ShadingRate::Sample => "sample",
        }
    }
}

impl fmt::Display for ShadingRate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ShadingRate {
    type Err = String;
    fn from_str(s: &str) -> Result<ShadingRate, String> {
        ShadingRate::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| format!("unknown shading rate {s:?}; expected pixel or sample"))
    }
}

/// The cosine of the largest angle between two samples' shading normals that share a lobe
/// (about 2.6°), on a rough surface. [ours] Chosen by measurement against
/// per-sample shading (BENCHMARKS.md): the lobe's normal is the members' mean.
pub const SAME_NORMAL: f32 = 0.999;

/// The cosine of the largest angle between the shading normals of two samples of roughness
/// `roughness` that share a lobe: [`SAME_NORMAL`], or closer for a sharp lobe, whose
/// highlight moves with the normal — `1 − cos θ ≤ GLOSSY_TURN · α²`, θ a fixed fraction of the
/// lobe's width α.
#[inline]
pub fn same_normal(roughness: f32) -> f32 {
    let a = crate::brdf::alpha(roughness);
    1.0 - (GLOSSY_TURN * a * a).min(1.0 - SAME_NORMAL)
}

/// See [`same_normal`]: `θ ≈ sqrt(2 · GLOSSY_TURN) · α`, about α/22. [ours] Measured on the
/// corpus against per-sample shading: 0.005 left 0.35 % relative RMSE on the golf ball's sun
/// highlight, 0.001 0.02 % (BENCHMARKS.md).
pub const GLOSSY_TURN: f32 = 0.001;

/// The largest difference between two samples' perceptual roughness that share a lobe
/// (textured roughness): the lobe takes their mean.
pub const SAME_ROUGHNESS: f32 = 0.02;

/// Whether sample `b` may share the lobe of sample `a`: both hit the same material with the
/// same model, their shading normals (normal maps included) within [`same_normal`] and their
/// roughness within [`SAME_ROUGHNESS`]. Base colour, metallic, occlusion and emission may
/// differ: they weigh the shared sums linearly, each sample's own averaged.
#[inline]
pub fn same_surface(a: &Surface, b: &Surface) -> bool {
    let (ma, mb) = (&a.material, &b.material);
    a.material_index == b.material_index
        && ma.lambert == mb.lambert
        && a.n.dot(b.n)
            >= if ma.lambert {
                SAME_NORMAL
            } else {
                same_normal(ma.roughness)
            }
        && (ma.roughness - mb.roughness).abs() <= SAME_ROUGHNESS
}

/// Splits a pixel's hit samples (`members`, indices into `surf`, in stratum order) into
/// groups that share a surface: each sample joins the first group whose first sample it
/// matches ([`same_surface`]), else starts one. Writes each member's group into `group` and
/// returns the number of groups, numbered in order of their first sample.
pub fn group(surf: &[Surface], members: &[usize], group: &mut [u8]) -> usize {
    debug_assert!(members.len() <= group.len() && members.len() <= 256);
    let mut leaders = [0usize; 256];
    let mut groups = 0;
    for (i, &q) in members.iter().enumerate() {
        let s = &surf[q];
        let found = leaders[..groups]
            .iter()
            .position(|&l| same_surface(&surf[l], s));
        group[i] = match found {
            Some(g) => g as u8,
            None => {
                leaders[groups] = q;
                groups += 1;
                (groups - 1) as u8
            }
        };
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn at(n: Vec3, material: u32, roughness: f32) -> Surface {
        let mut s = Surface {
            n: n.normalize(),
            hit: true,
            material_index: material,
            ..Surface::default()
        };
        s.material.roughness = roughness;
        s
    }

    #[test]
    fn samples_on_one_surface_share_and_a_crease_a_material_or_a_roughness_split_them() {
        let flat = at(Vec3::Y, 0, 0.5);
        let near = at(Vec3::new(0.01, 1.0, 0.0), 0, 0.51);
        let crease = at(Vec3::new(0.2, 1.0, 0.0), 0, 0.5);
        let other = at(Vec3::Y, 1, 0.5);
        let rough = at(Vec3::Y, 0, 0.6);
        let surf = [flat, near, crease, other, rough];
        let mut g = [0u8; 7];
        assert_eq!(group(&surf, &[0, 1, 2, 3, 4, 1, 2], &mut g), 4);
        assert_eq!(g, [0, 0, 1, 2, 3, 0, 1]);
        // A Lambertian sample and a glTF one never share, whatever their normals.
        let mut lambert = flat;
        lambert.material.lambert = !flat.material.lambert;
        assert!(!same_surface(&flat, &lambert));
    }

    #[test]
    fn shading_rates_parse_from_their_names() {
        for r in ShadingRate::ALL {
            assert_eq!(r.name().parse::<ShadingRate>(), Ok(r));
        }
        let e = "quad".parse::<ShadingRate>().unwrap_err();
        assert!(e.contains("pixel or sample"), "{e}");
    }
}
