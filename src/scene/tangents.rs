//! Tangents for normal maps: MikkTSpace (the `mikktspace` crate), as glTF 2.0 asks when a
//! normal-mapped primitive has no `TANGENT` attribute.
//!
//! MikkTSpace gives a tangent per triangle corner. Corners that share a vertex mostly agree;
//! where they do not (mirrored UV islands meeting at a vertex, a handedness change), the vertex
//! is split so that every corner keeps its own tangent: the glTF sample viewer's "unweld,
//! generate, reweld" with the reweld done by tangent, not by position alone.

use glam::{Vec2, Vec3, Vec4};

/// One primitive's triangles as MikkTSpace reads them, and the corner tangents it writes.
struct Mesh<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    corners: Vec<Vec4>,
}

impl mikktspace::Geometry for Mesh<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.triangles[face][vert] as usize].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.triangles[face][vert] as usize].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[self.triangles[face][vert] as usize].to_array()
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.corners[face * 3 + vert] = Vec4::from_array(tangent);
    }
}

/// MikkTSpace tangents for a primitive's `triangles` over its vertices (`positions`,
/// `normals`, texture coordinates `uvs`, all one per vertex). Returns a tangent per vertex
/// (xyz unit, w = ±1 the bitangent's handedness), with `triangles` rewritten and the vertex
/// attributes grown where a vertex had to be split (its copies appended at the end, and
/// `split` told which vertex each copy came from, in order). `None` when MikkTSpace cannot
/// (no triangles with UV area): the caller drops the normal map with a warning.
pub fn generate(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    triangles: &mut [[u32; 3]],
    split: &mut Vec<u32>,
) -> Option<Vec<Vec4>> {
    let mut mesh = Mesh {
        positions,
        normals,
        uvs,
        triangles,
        corners: vec![Vec4::ZERO; triangles.len() * 3],
    };
    if !mikktspace::generate_tangents(&mut mesh) {
        return None;
    }
    let corners = mesh.corners;
    let n = positions.len();
    let mut tangents: Vec<Option<Vec4>> = vec![None; n];
    // A vertex's copies by tangent: (original vertex, tangent bits) → new index.
    let mut copies: std::collections::HashMap<(u32, [u32; 4]), u32> =
        std::collections::HashMap::new();
    let mut extra: Vec<Vec4> = Vec::new();
    for (t, tri) in triangles.iter_mut().enumerate() {
        for (k, v) in tri.iter_mut().enumerate() {
            let mut tangent = corners[t * 3 + k];
            // Degenerate corners come back as zero vectors: any unit tangent will do there.
            if !tangent.truncate().is_finite() || tangent.truncate() == Vec3::ZERO {
                tangent = Vec4::new(1.0, 0.0, 0.0, 1.0);
            }
            let tangent = tangent
                .truncate()
                .normalize_or(Vec3::X)
                .extend(if tangent.w < 0.0 { -1.0 } else { 1.0 });
            let i = *v as usize;
            match tangents[i] {
                None => tangents[i] = Some(tangent),
                Some(same) if bits(same) == bits(tangent) => {}
                Some(_) => {
                    let key = (*v, bits(tangent));
                    let next = (n + extra.len()) as u32;
                    let index = *copies.entry(key).or_insert_with(|| {
                        split.push(*v);
                        extra.push(tangent);
                        next
                    });
                    *v = index;
                }
            }
        }
    }
    Some(
        tangents
            .into_iter()
            .map(|t| t.unwrap_or(Vec4::new(1.0, 0.0, 0.0, 1.0)))
            .chain(extra)
            .collect(),
    )
}

fn bits(v: Vec4) -> [u32; 4] {
    v.to_array().map(f32::to_bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad in the XY plane facing +Z, UVs u = x, v = 1 − y (glTF's v points down):
    /// the tangent is +X (the direction u grows), the bitangent n × t = +Y, where v falls —
    /// MikkTSpace's bitangent follows v as stored, so the handedness is −1.
    #[test]
    fn a_quads_tangent_follows_u() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let normals = [Vec3::Z; 4];
        let uvs = positions.map(|p| Vec2::new(p.x, 1.0 - p.y));
        let mut triangles = [[0, 1, 2], [0, 2, 3]];
        let mut split = Vec::new();
        let t = generate(&positions, &normals, &uvs, &mut triangles, &mut split).unwrap();
        assert!(split.is_empty());
        assert_eq!(t.len(), 4);
        for (i, t) in t.iter().enumerate() {
            assert!((t.truncate() - Vec3::X).length() < 1e-6, "vertex {i}: {t}");
            assert_eq!(t.w, -1.0, "vertex {i}");
        }
        // With v growing up the quad instead, the bitangent agrees with n × t: +1.
        let uvs = positions.map(|p| Vec2::new(p.x, p.y));
        let t = generate(&positions, &normals, &uvs, &mut triangles, &mut split).unwrap();
        for t in &t {
            assert!((t.truncate() - Vec3::X).length() < 1e-6);
            assert_eq!(t.w, 1.0);
        }
    }

    /// Two quads sharing an edge, the second's UVs mirrored: the shared vertices get two
    /// tangents, so they are split, and every corner keeps its own.
    #[test]
    fn mirrored_uvs_split_the_shared_vertices() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
        ];
        let normals = [Vec3::Z; 6];
        // u grows to the right on the left quad and back to the left on the right one.
        let uvs = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(0.0, 1.0),
        ];
        let mut triangles = [[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]];
        let mut split = Vec::new();
        let t = generate(&positions, &normals, &uvs, &mut triangles, &mut split).unwrap();
        assert_eq!(
            split,
            vec![1, 2],
            "the shared edge's two vertices are split"
        );
        assert_eq!(t.len(), 8);
        for (k, tri) in triangles.iter().enumerate() {
            let expected = if k < 2 { Vec3::X } else { Vec3::NEG_X };
            for &v in tri {
                let tangent = t[v as usize];
                assert!(
                    (tangent.truncate() - expected).length() < 1e-5,
                    "triangle {k} vertex {v}: {tangent}"
                );
            }
        }
    }
}
