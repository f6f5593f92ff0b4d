//! Morph targets: displacements of a primitive's positions, normals and tangents, added in
//! proportion to the mesh's weights (the node's default weights, or an animation's), before
//! skinning or the node's transform, as the glTF 2.0 specification orders them.

use glam::Vec3;

/// One target's displacements per vertex; an attribute the target lacks is empty.
#[derive(Clone, Debug, Default)]
pub struct Target {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tangents: Vec<Vec3>,
}

/// A primitive's targets.
#[derive(Clone, Debug, Default)]
pub struct Targets(pub Vec<Target>);

impl Targets {
    /// Vertex `v`'s position, normal and tangent direction with the targets added by
    /// `weights` (missing weights count as zero).
    pub fn apply(&self, v: usize, weights: &[f64], p: &mut Vec3, n: &mut Vec3, t: &mut Vec3) {
        for (target, &w) in self.0.iter().zip(weights) {
            if w == 0.0 {
                continue;
            }
            let w = w as f32;
            if let Some(d) = target.positions.get(v) {
                *p += *d * w;
            }
            if let Some(d) = target.normals.get(v) {
                *n += *d * w;
            }
            if let Some(d) = target.tangents.get(v) {
                *t += *d * w;
            }
        }
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_scale_each_targets_displacement() {
        let targets = Targets(vec![
            Target {
                positions: vec![Vec3::X],
                normals: vec![],
                tangents: vec![],
            },
            Target {
                positions: vec![Vec3::Y],
                normals: vec![Vec3::Z],
                tangents: vec![],
            },
        ]);
        let (mut p, mut n, mut t) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        targets.apply(0, &[0.5, 2.0], &mut p, &mut n, &mut t);
        assert_eq!(p, Vec3::new(0.5, 2.0, 0.0));
        assert_eq!(n, Vec3::new(0.0, 0.0, 2.0));
        assert_eq!(t, Vec3::ZERO);
    }
}
