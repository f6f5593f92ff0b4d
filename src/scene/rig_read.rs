//! Reading a [`RigData`] from a glTF document: the node hierarchy and rest transforms, the
//! skins, the animations (checked: key times finite and increasing, as many values as keys
//! say, targets that exist), and each moving primitive's joints, weights and morph targets.
//! Accessors are read by the loader's reader (`read`), which checks every byte range.

use glam::{DMat4, DQuat, DVec3, Vec3, Vec4};
use std::path::Path;

use ::gltf::animation::{Interpolation as FileInterpolation, Property};
use ::gltf::mesh::Semantic;
use ::gltf::{Accessor, Document, Primitive};

use super::clip::{Channel, Clip, Interpolation, Path as Target};
use super::morph::{Target as MorphTarget, Targets};
use super::rig::{Rest, RigNode};
use super::skin::{Influences, Skin};
use crate::bail_input;
use crate::error::Result;

/// Reads an accessor's values (elements × components, as f64), checked.
pub type Read<'r> = dyn Fn(&str, &Accessor) -> Result<Vec<f64>> + 'r;

/// Whether a document has anything to pose: an animation, a skin, or a morph target.
pub fn wanted(document: &Document) -> bool {
    document.animations().next().is_some()
        || document.skins().next().is_some()
        || document
            .meshes()
            .flat_map(|m| m.primitives())
            .any(|p| p.morph_targets().next().is_some())
}

/// Every node: its parent, its rest transform and its mesh's default weights.
pub fn nodes(document: &Document) -> Vec<RigNode> {
    let mut nodes: Vec<RigNode> = document
        .nodes()
        .map(|n| {
            let rest = match n.transform() {
                ::gltf::scene::Transform::Matrix { matrix } => {
                    Rest::Matrix(DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from))))
                }
                ::gltf::scene::Transform::Decomposed {
                    translation,
                    rotation,
                    scale,
                } => Rest::Trs {
                    translation: Vec3::from_array(translation).as_dvec3(),
                    rotation: DQuat::from_xyzw(
                        rotation[0].into(),
                        rotation[1].into(),
                        rotation[2].into(),
                        rotation[3].into(),
                    )
                    .normalize(),
                    scale: Vec3::from_array(scale).as_dvec3(),
                },
            };
            let weights = n
                .weights()
                .or_else(|| n.mesh().and_then(|m| m.weights()))
                .unwrap_or_default()
                .iter()
                .map(|&w| f64::from(w))
                .collect();
            RigNode {
                parent: None,
                rest,
                weights,
            }
        })
        .collect();
    for n in document.nodes() {
        for c in n.children() {
            nodes[c.index()].parent = Some(n.index());
        }
    }
    nodes
}

/// The skins: joints and inverse bind matrices (identity where the file gives none).
pub fn skins(path: &Path, document: &Document, read: &Read) -> Result<Vec<Skin>> {
    document
        .skins()
        .map(|s| {
            let at = format!("skin {}", s.index());
            let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
            let inverse_bind = match s.inverse_bind_matrices() {
                Some(acc) => {
                    if acc.dimensions().multiplicity() != 16 || acc.count() < joints.len() {
                        bail_input!(
                            path,
                            "{at}: inverse bind matrices (accessor {}) are not one MAT4 per joint ({} joints)",
                            acc.index(),
                            joints.len()
                        );
                    }
                    let values = read(&at, &acc)?;
                    finite(path, &at, &values)?;
                    values
                        .chunks_exact(16)
                        .take(joints.len())
                        .map(DMat4::from_cols_slice)
                        .collect()
                }
                None => vec![DMat4::IDENTITY; joints.len()],
            };
            Ok(Skin {
                joints,
                inverse_bind,
            })
        })
        .collect()
}

fn finite(path: &Path, at: &str, values: &[f64]) -> Result<()> {
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        bail_input!(path, "{at}: value {i} is not finite");
    }
    Ok(())
}

/// The animations, each channel checked against its node (weights need a mesh with targets).
pub fn clips(path: &Path, document: &Document, read: &Read) -> Result<Vec<Clip>> {
    let mut clips = Vec::new();
    for a in document.animations() {
        let mut channels = Vec::new();
        let mut duration = 0.0f64;
        for ch in a.channels() {
            let at = format!("animation {} channel {}", a.index(), ch.index());
            let node = ch.target().node();
            let sampler = ch.sampler();
            let interpolation = match sampler.interpolation() {
                FileInterpolation::Step => Interpolation::Step,
                FileInterpolation::Linear => Interpolation::Linear,
                FileInterpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let (path_kind, width) = match ch.target().property() {
                Property::Translation => (Target::Translation, 3),
                Property::Rotation => (Target::Rotation, 4),
                Property::Scale => (Target::Scale, 3),
                Property::MorphTargetWeights => {
                    let targets = node
                        .mesh()
                        .and_then(|m| m.primitives().map(|p| p.morph_targets().count()).max())
                        .unwrap_or(0);
                    if targets == 0 {
                        bail_input!(
                            path,
                            "{at}: animates the morph weights of node {}, whose mesh has no morph targets",
                            node.index()
                        );
                    }
                    (Target::Weights, targets)
                }
            };
            let input = sampler.input();
            let output = sampler.output();
            let times = read(&format!("{at} input"), &input)?;
            finite(
                path,
                &format!("{at}: input (accessor {})", input.index()),
                &times,
            )?;
            if times.is_empty() || times.windows(2).any(|w| w[0] >= w[1]) {
                bail_input!(
                    path,
                    "{at}: key times (accessor {}) are not strictly increasing",
                    input.index()
                );
            }
            let values = read(&format!("{at} output"), &output)?;
            finite(
                path,
                &format!("{at}: output (accessor {})", output.index()),
                &values,
            )?;
            let groups = if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if values.len() != times.len() * groups * width {
                bail_input!(
                    path,
                    "{at}: {} output values (accessor {}) for {} keys of {width} component(s){}",
                    values.len(),
                    output.index(),
                    times.len(),
                    if groups == 3 { " with tangents" } else { "" }
                );
            }
            duration = duration.max(*times.last().unwrap_or(&0.0));
            channels.push(Channel {
                node: node.index(),
                path: path_kind,
                interpolation,
                times,
                values,
                width,
            });
        }
        clips.push(Clip {
            name: a.name().map(str::to_string),
            channels,
            duration,
        });
    }
    Ok(clips)
}

/// A primitive's joints and weights (`JOINTS_0`/`WEIGHTS_0` and the `_1` set), `count`
/// vertices, each joint checked against the skin's `joints`; empty without `JOINTS_0`.
pub fn influences(
    path: &Path,
    at: &str,
    primitive: &Primitive,
    count: usize,
    joints: usize,
    read: &Read,
) -> Result<Influences> {
    let mut inf = Influences::default();
    if primitive.get(&Semantic::Joints(0)).is_none() {
        return Ok(inf);
    }
    inf.joints = vec![0; count * Influences::MAX];
    inf.weights = vec![0.0; count * Influences::MAX];
    for set in 0..2u32 {
        let (Some(j), Some(w)) = (
            primitive.get(&Semantic::Joints(set)),
            primitive.get(&Semantic::Weights(set)),
        ) else {
            continue;
        };
        for acc in [&j, &w] {
            if acc.count() != count || acc.dimensions().multiplicity() != 4 {
                bail_input!(
                    path,
                    "{at}: accessor {} (JOINTS_{set}/WEIGHTS_{set}) is not one VEC4 per vertex ({count} vertices)",
                    acc.index()
                );
            }
        }
        let jv = read(at, &j)?;
        let wv = read(at, &w)?;
        finite(path, &format!("{at}: WEIGHTS_{set}"), &wv)?;
        for v in 0..count {
            for k in 0..4 {
                let joint = jv[4 * v + k];
                let weight = wv[4 * v + k] as f32;
                if weight != 0.0 && !(joint >= 0.0 && (joint as usize) < joints) {
                    bail_input!(
                        path,
                        "{at}: vertex {v} names joint {joint}; its skin has {joints}"
                    );
                }
                let slot = v * Influences::MAX + 4 * set as usize + k;
                inf.joints[slot] = joint as u16;
                inf.weights[slot] = weight;
            }
        }
    }
    Ok(inf)
}

/// A primitive's morph targets: POSITION, NORMAL and TANGENT displacements, `count` each.
pub fn targets(
    path: &Path,
    at: &str,
    primitive: &Primitive,
    count: usize,
    read: &Read,
) -> Result<Targets> {
    let mut out = Vec::new();
    for (i, t) in primitive.morph_targets().enumerate() {
        let attribute = |acc: Option<Accessor>, name: &str| -> Result<Vec<Vec3>> {
            let Some(acc) = acc else {
                return Ok(Vec::new());
            };
            if acc.count() != count || acc.dimensions().multiplicity() != 3 {
                bail_input!(
                    path,
                    "{at}: morph target {i} {name} (accessor {}) is not one VEC3 per vertex ({count} vertices)",
                    acc.index()
                );
            }
            let v = read(at, &acc)?;
            finite(path, &format!("{at}: morph target {i} {name}"), &v)?;
            Ok(v.chunks_exact(3)
                .map(|c| DVec3::from_slice(c).as_vec3())
                .collect())
        };
        out.push(MorphTarget {
            positions: attribute(t.positions(), "POSITION")?,
            normals: attribute(t.normals(), "NORMAL")?,
            tangents: attribute(t.tangents(), "TANGENT")?,
        });
    }
    Ok(Targets(out))
}

/// Tangents placed by `world` brought back to the mesh's space (directions, by its inverse;
/// the handedness a mirroring `world` flipped, flipped back).
pub fn local_tangents(placed: &[Vec4], world: DMat4) -> Vec<Vec4> {
    let inverse = world.inverse();
    let flip = if world.determinant() < 0.0 { -1.0 } else { 1.0 };
    placed
        .iter()
        .map(|t| {
            let d = inverse
                .transform_vector3(t.truncate().as_dvec3())
                .normalize_or_zero()
                .as_vec3();
            d.extend(t.w * flip)
        })
        .collect()
}
