//! Scenes: triangle meshes flattened to world space, with Lambertian materials.
//!
//! STUB: filled in by the scene helper.

use glam::{Vec2, Vec3};
use std::path::Path;

use crate::error::Result;

/// An sRGB-decoded (linear) RGB texture, row-major, row 0 at the top (glTF's UV origin).
#[derive(Clone, Debug)]
pub struct Texture {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Vec3>,
}

/// A Lambertian material: albedo = base_color × texture(uv).
#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    /// Linear RGB base colour factor.
    pub base_color: Vec3,
    pub texture: Option<usize>,
}

/// A perspective camera found in a scene file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneCamera {
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub vfov_deg: f32,
}

/// All triangles of the default scene in world space.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub positions: Vec<Vec3>,
    /// Unit shading normals per vertex.
    pub normals: Vec<Vec3>,
    /// Per vertex; (0, 0) where the file had none.
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
    /// Material index per triangle.
    pub tri_material: Vec<u32>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub camera: Option<SceneCamera>,
    /// Where it came from: a path, or `builtin:shapes`.
    pub source: String,
}

impl Scene {
    /// Loads `.gltf` (external buffers and images) or `.glb`.
    pub fn load(_path: &Path) -> Result<Scene> {
        unimplemented!()
    }
    /// The built-in `shapes` scene: sphere, box, cylinder, cone, torus on a ground plane.
    pub fn shapes() -> Scene {
        unimplemented!()
    }
}
