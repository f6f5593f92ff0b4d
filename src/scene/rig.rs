//! What posing a glTF scene needs, kept at load beside the flat [`Scene`]: the node hierarchy
//! with each node's rest transform, the file's animations ([`Clip`]), its skins, and, for
//! every primitive that can move, its vertices in the mesh's own space with their joints,
//! weights and morph targets.
//!
//! [`Rig::pose`] evaluates the nodes at a time of a chosen animation (or at rest), then moves
//! each primitive that animation moves: morph targets added by the node's weights, then the
//! skin's blended joint matrices (or the node's world transform), then the loader's render
//! origin and up axis — the same path a vertex takes at load. Primitives no channel reaches
//! keep the loaded bits, and so do the scene's other arrays.

use std::ops::Range;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec3, Vec4};

use super::clip::{Clip, Path};
use super::morph::Targets;
use super::skin::{Influences, Skin, carry_normal};
use super::{Scene, Up};

/// A node's transform before any animation: a matrix (which the specification forbids
/// animating) or translation, rotation and scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rest {
    Matrix(DMat4),
    Trs {
        translation: DVec3,
        rotation: DQuat,
        scale: DVec3,
    },
}

impl Rest {
    fn matrix(&self) -> DMat4 {
        match *self {
            Rest::Matrix(m) => m,
            Rest::Trs {
                translation,
                rotation,
                scale,
            } => DMat4::from_scale_rotation_translation(scale, rotation, translation),
        }
    }
}

/// One glTF node as posing sees it.
#[derive(Clone, Debug)]
pub struct RigNode {
    pub parent: Option<usize>,
    pub rest: Rest,
    /// The default morph weights of its mesh (the node's, else the mesh's; empty without).
    pub weights: Vec<f64>,
}

/// A primitive that can move: where its vertices and triangles sit in the scene, and its
/// vertices in its mesh's space.
#[derive(Clone, Debug)]
pub struct RigPrimitive {
    /// The node that places it.
    pub node: usize,
    /// Its node's skin, when the primitive has joints and weights.
    pub skin: Option<usize>,
    /// Its first vertex in [`Scene::positions`].
    pub first_vertex: usize,
    /// Its triangles in [`Scene::triangles`].
    pub triangles: Range<usize>,
    /// Whether the loader reversed its winding (its node's transform mirrors).
    pub mirrored: bool,
    pub positions: Vec<Vec3>,
    /// Unit normals; recomputed from the posed triangles when `smooth` (the file had none).
    pub normals: Vec<Vec3>,
    pub smooth: bool,
    /// Tangents (xyz, handedness w), or empty when the scene keeps none for it.
    pub tangents: Vec<Vec4>,
    pub influences: Influences,
    pub targets: Targets,
}

/// Everything the rig holds, shared by every copy of a scene.
#[derive(Debug, Default)]
pub struct RigData {
    pub nodes: Vec<RigNode>,
    /// The nodes of the default scene, each after its parent.
    pub order: Vec<usize>,
    pub skins: Vec<Skin>,
    pub primitives: Vec<RigPrimitive>,
    pub clips: Vec<Clip>,
    /// The loader's render origin, in the file's axes: posed positions count from it, as
    /// loaded ones do.
    pub origin: DVec3,
}

/// A scene's rig: its shared data and the up axis the scene was stood up to.
#[derive(Clone, Debug)]
pub struct Rig {
    pub data: Arc<RigData>,
    pub up: Up,
}

/// The nodes' world transforms and morph weights at one moment.
pub struct Pose {
    pub world: Vec<DMat4>,
    pub weights: Vec<Vec<f64>>,
}

impl RigData {
    /// The nodes at time `t` (seconds) of clip `clip`, or at rest for `None`.
    pub fn nodes_at(&self, clip: Option<(usize, f64)>) -> Pose {
        let mut local: Vec<Rest> = self.nodes.iter().map(|n| n.rest).collect();
        let mut weights: Vec<Vec<f64>> = self.nodes.iter().map(|n| n.weights.clone()).collect();
        if let Some((c, t)) = clip {
            let mut value = Vec::new();
            for ch in &self.clips[c].channels {
                value.resize(ch.width, 0.0);
                ch.sample(t, &mut value);
                let rest = &mut local[ch.node];
                if ch.path == Path::Weights {
                    weights[ch.node].clone_from(&value);
                    continue;
                }
                // A matrix node is not animated (the specification forbids it): a channel on
                // one starts from its decomposition.
                if let Rest::Matrix(m) = *rest {
                    let (scale, rotation, translation) = m.to_scale_rotation_translation();
                    *rest = Rest::Trs {
                        translation,
                        rotation,
                        scale,
                    };
                }
                if let Rest::Trs {
                    translation,
                    rotation,
                    scale,
                } = rest
                {
                    match ch.path {
                        Path::Translation => *translation = DVec3::from_slice(&value),
                        Path::Rotation => *rotation = super::clip::quat(&value),
                        Path::Scale => *scale = DVec3::from_slice(&value),
                        Path::Weights => {}
                    }
                }
            }
        }
        let mut world = vec![DMat4::IDENTITY; self.nodes.len()];
        for &n in &self.order {
            let parent = self.nodes[n].parent.map_or(DMat4::IDENTITY, |p| world[p]);
            world[n] = parent * local[n].matrix();
        }
        Pose { world, weights }
    }

    /// Per node: whether clip `clip` moves it (a channel on it or on an ancestor).
    fn moved_nodes(&self, clip: usize) -> Vec<bool> {
        let mut direct = vec![false; self.nodes.len()];
        for ch in &self.clips[clip].channels {
            if ch.path != Path::Weights {
                direct[ch.node] = true;
            }
        }
        let mut moved = vec![false; self.nodes.len()];
        for &n in &self.order {
            moved[n] = direct[n] || self.nodes[n].parent.is_some_and(|p| moved[p]);
        }
        moved
    }

    /// Per primitive: whether clip `clip` changes it (its node moves, a joint of its skin
    /// moves, or its weights are animated).
    pub fn moved_primitives(&self, clip: usize) -> Vec<bool> {
        let moved = self.moved_nodes(clip);
        let weighted: Vec<usize> = self.clips[clip]
            .channels
            .iter()
            .filter(|c| c.path == Path::Weights)
            .map(|c| c.node)
            .collect();
        self.primitives
            .iter()
            .map(|p| match p.skin {
                Some(s) => self.skins[s].joints.iter().any(|&j| moved[j]),
                None => moved[p.node],
            } || (!p.targets.is_empty() && weighted.contains(&p.node)))
            .collect()
    }

    /// Per primitive: whether its rest pose differs from what the loader placed (a skin
    /// bends it, or a default morph weight is not zero).
    pub fn bent_at_rest(&self) -> Vec<bool> {
        self.primitives
            .iter()
            .map(|p| {
                p.skin.is_some()
                    || (!p.targets.is_empty()
                        && self.nodes[p.node].weights.iter().any(|&w| w != 0.0))
            })
            .collect()
    }
}

impl Rig {
    /// The file's animations.
    pub fn clips(&self) -> &[Clip] {
        &self.data.clips
    }

    /// `scene` (the scene this rig was loaded with, as prepared for the render) posed at
    /// time `t` (seconds) of clip `clip`: only the primitives the clip moves are redone.
    pub fn posed(&self, scene: &Scene, clip: usize, t: f64) -> Scene {
        let mut out = scene.clone();
        let which = self.data.moved_primitives(clip);
        self.pose(&mut out, Some((clip, t)), &which);
        out
    }

    /// Moves the primitives `which` selects to the pose at `clip` (or rest), in `scene` (a
    /// copy of the scene this rig was loaded with).
    pub fn pose(&self, scene: &mut Scene, clip: Option<(usize, f64)>, which: &[bool]) {
        let data = &*self.data;
        let pose = data.nodes_at(clip);
        for (p, _) in data.primitives.iter().zip(which).filter(|(_, w)| **w) {
            self.pose_primitive(scene, p, &pose);
        }
    }

    /// One primitive: morphed, skinned or placed by its node, counted from the origin and
    /// stood up.
    fn pose_primitive(&self, scene: &mut Scene, p: &RigPrimitive, pose: &Pose) {
        let data = &*self.data;
        let joints = p
            .skin
            .map(|s| data.skins[s].joint_matrices(&pose.world))
            .unwrap_or_default();
        let node = pose.world[p.node];
        let weights = &pose.weights[p.node];
        let stand = |v: DVec3| match self.up {
            Up::Y => v,
            // As Scene::stood_up turns it: +Z → +Y, +Y → −Z.
            Up::Z => DVec3::new(v.x, v.z, -v.y),
        };
        let origin = data.origin;
        let base = p.first_vertex;
        for v in 0..p.positions.len() {
            let (mut pos, mut n, mut t) = (
                p.positions[v],
                p.normals[v],
                p.tangents.get(v).map_or(Vec3::ZERO, |t| t.truncate()),
            );
            p.targets.apply(v, weights, &mut pos, &mut n, &mut t);
            let m = if joints.is_empty() {
                node
            } else {
                p.influences.blend(v, &joints)
            };
            let placed = stand(m.transform_point3(pos.as_dvec3()) - origin);
            scene.positions[base + v] = placed.as_vec3();
            if !p.smooth {
                let carried = carry_normal(&m, n.as_dvec3().normalize_or_zero());
                scene.normals[base + v] = stand(carried).as_vec3();
            }
            if let Some(t0) = p.tangents.get(v) {
                let moved = stand(m.transform_vector3(t.as_dvec3()))
                    .normalize_or_zero()
                    .as_vec3();
                let flip = if m.determinant() < 0.0 { -1.0 } else { 1.0 };
                scene.tangents[base + v] = if moved == Vec3::ZERO || !moved.is_finite() {
                    Vec4::ZERO
                } else {
                    moved.extend(t0.w * flip)
                };
            }
        }
        // A node whose transform now mirrors (or no longer does) turns its triangles over.
        if joints.is_empty() && (node.determinant() < 0.0) != p.mirrored {
            for t in &mut scene.triangles[p.triangles.clone()] {
                t.swap(1, 2);
            }
        }
        if p.smooth {
            let end = base + p.positions.len();
            let tris: Vec<[u32; 3]> = scene.triangles[p.triangles.clone()]
                .iter()
                .map(|t| t.map(|i| i - base as u32))
                .collect();
            let smooth = super::gltf::smooth_normals(&scene.positions[base..end], &tris);
            scene.normals[base..end].copy_from_slice(&smooth);
        }
    }
}

impl Rig {
    /// The points the model reaches at `times` (seconds) of clip `clip`, for framing: of each
    /// pose, the corners of its outline seen from above (the convex hull of its vertices in
    /// x, z) and its lowest and highest points — enough for the bounds and for the farthest
    /// reach from any vertical axis, which a convex hull's corners attain.
    pub fn reach(&self, scene: &Scene, clip: usize, times: &[f64]) -> Vec<Vec3> {
        let which = self.data.moved_primitives(clip);
        let mut model: Vec<u32> = scene.model_triangles().iter().flatten().copied().collect();
        model.sort_unstable();
        model.dedup();
        let mut points = Vec::new();
        // One copy posed again and again: only its positions are read (the moved
        // primitives' are all rewritten by each pose).
        let mut posed = scene.clone();
        for &t in times {
            self.pose(&mut posed, Some((clip, t)), &which);
            let pose: Vec<Vec3> = model.iter().map(|&i| posed.positions[i as usize]).collect();
            points.extend(extremes(&pose));
        }
        extremes(&points)
    }
}

/// The corners of `points`' convex hull in x, z (Andrew's monotone chain) and its lowest and
/// highest points.
fn extremes(points: &[Vec3]) -> Vec<Vec3> {
    if points.is_empty() {
        return Vec::new();
    }
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.z.total_cmp(&b.z)));
    let cross = |o: Vec3, a: Vec3, b: Vec3| (a.x - o.x) * (b.z - o.z) - (a.z - o.z) * (b.x - o.x);
    let mut hull: Vec<Vec3> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec3>> = if pass == 0 {
            Box::new(sorted.iter())
        } else {
            Box::new(sorted.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    let lowest = points.iter().copied().min_by(|a, b| a.y.total_cmp(&b.y));
    let highest = points.iter().copied().max_by(|a, b| a.y.total_cmp(&b.y));
    hull.extend(lowest);
    hull.extend(highest);
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extremes_keep_the_outline_and_the_heights() {
        let mut points = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(2.0, 0.5, 2.0),
            Vec3::new(0.0, 3.0, 2.0),
        ];
        // Inside the outline, and neither lowest nor highest: dropped.
        points.push(Vec3::new(1.0, 1.0, 1.0));
        let e = extremes(&points);
        assert!(!e.contains(&Vec3::new(1.0, 1.0, 1.0)));
        for p in &points[..4] {
            assert!(e.contains(p), "{p} kept");
        }
    }
}
