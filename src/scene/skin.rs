//! Skins: a mesh bent by a skeleton. Each vertex follows up to eight joints (`JOINTS_0`/
//! `WEIGHTS_0`, `JOINTS_1`/`WEIGHTS_1`), each joint's matrix its node's world transform times
//! its inverse bind matrix; the vertex moves by the weighted sum of those matrices (linear
//! blend skinning, as the glTF 2.0 specification defines it). The skinned mesh's own node
//! transform is ignored, as the specification requires.

use glam::{DMat4, DVec3};

/// A glTF skin: its joints (node indices) and their inverse bind matrices.
#[derive(Clone, Debug)]
pub struct Skin {
    pub joints: Vec<usize>,
    /// One per joint (identity where the file gives none).
    pub inverse_bind: Vec<DMat4>,
}

impl Skin {
    /// Each joint's matrix for the nodes' world transforms `world`: world × inverse bind.
    pub fn joint_matrices(&self, world: &[DMat4]) -> Vec<DMat4> {
        self.joints
            .iter()
            .zip(&self.inverse_bind)
            .map(|(&j, ib)| world[j] * *ib)
            .collect()
    }
}

/// Influences per vertex: up to [`Influences::MAX`] (joint, weight) pairs, unused ones weight 0.
#[derive(Clone, Debug, Default)]
pub struct Influences {
    /// Joint indices into the skin's list, `MAX` per vertex.
    pub joints: Vec<u16>,
    /// Weights, `MAX` per vertex.
    pub weights: Vec<f32>,
}

impl Influences {
    /// Two sets of four.
    pub const MAX: usize = 8;

    /// The matrix that moves vertex `v`: its joints' matrices blended by its weights.
    /// Weights are used as the file gives them (the specification requires them to sum to
    /// one; a vertex with none stays at the origin, as a renderer would put it).
    pub fn blend(&self, v: usize, joints: &[DMat4]) -> DMat4 {
        let mut m = DMat4::ZERO;
        for k in v * Self::MAX..(v + 1) * Self::MAX {
            let w = self.weights[k];
            if w != 0.0 {
                m += joints[self.joints[k] as usize] * f64::from(w);
            }
        }
        m
    }

    /// Vertices.
    pub fn len(&self) -> usize {
        self.weights.len() / Self::MAX
    }

    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }
}

/// The unit normal `n` carried by `m` (its inverse transpose), or `n` itself where `m` flattens it.
pub fn carry_normal(m: &DMat4, n: DVec3) -> DVec3 {
    let linear = glam::DMat3::from_mat4(*m);
    let det = linear.determinant();
    if det == 0.0 || !det.is_finite() {
        return n;
    }
    let t = (linear.inverse().transpose() * n).normalize_or_zero();
    if t == DVec3::ZERO { n } else { t }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertex_halfway_between_two_joints_moves_halfway() {
        let inf = Influences {
            joints: vec![0, 1, 0, 0, 0, 0, 0, 0],
            weights: vec![0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        };
        let joints = [
            DMat4::IDENTITY,
            DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)),
        ];
        let m = inf.blend(0, &joints);
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn the_second_weight_set_counts() {
        let mut inf = Influences {
            joints: vec![0; 8],
            weights: vec![0.0; 8],
        };
        inf.joints[5] = 1;
        inf.weights[5] = 1.0;
        let joints = [
            DMat4::IDENTITY,
            DMat4::from_translation(DVec3::new(0.0, 3.0, 0.0)),
        ];
        let p = inf.blend(0, &joints).transform_point3(DVec3::ZERO);
        assert_eq!(p, DVec3::new(0.0, 3.0, 0.0));
    }
}
