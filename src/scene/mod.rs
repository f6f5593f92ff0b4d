//! Scenes: triangle meshes flattened to world space, with glTF metallic-roughness materials.
//!
//! A [`Scene`] is one flat triangle soup: every glTF primitive of the default scene, already
//! transformed to world space, with one material per triangle. [`Scene::load`] reads glTF
//! (`.gltf` with external or `data:` buffers and images, or `.glb`); [`Scene::shapes`] builds a
//! small test scene in code.
//!
//! Conventions: triangles wind counter-clockwise seen from the side their shading normals point
//! to, so the geometric normal `(p1 − p0) × (p2 − p0)` agrees with the vertex normals.
//! Barycentric coordinates `(u, v)` name the point `(1 − u − v)·p0 + u·p1 + v·p2`.

mod alpha;
pub mod clip;
pub mod draco;
mod extensions;
mod gltf;
pub mod ground;
mod material;
mod meshopt;
pub mod morph;
mod origin;
pub mod playback;
pub mod resource;
pub mod rig;
mod rig_read;
mod shapes;
pub mod skin;
pub mod sniff;
mod tangents;
mod texture;

use glam::{DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::limits::Budget;

pub use alpha::{AlphaMode, AlphaTest, coverage_threshold};
pub use material::{
    Material, MaterialOverride, MaterialSample, Model, SurfaceMaterial, TextureSlot, UvTransform,
    ior_f0,
};
pub use origin::render_origin;
pub use resource::AllowedFolder;
pub use texture::{Encoding, Sampler, Wrap, srgb_to_linear};

/// A linear RGB texture (sRGB-decoded, or linear data as it was), with its alpha when the image
/// had one, row-major, row 0 at the top (glTF's UV origin), with its mip pyramid.
///
/// Sampling is bilinear with repeat wrap ([`Texture::sample`]), trilinear over a footprint
/// ([`Texture::sample_footprint`]), or as a glTF sampler says ([`Texture::lookup`]). The fields
/// are private because the pyramid is made from the texels once, by the constructors: texels
/// changed afterwards would disagree with it.
#[derive(Clone, Debug)]
pub struct Texture {
    /// Level 0 (the texels as decoded), then each level half the size of the one before, down
    /// to 1 × 1; only level 0 when the texture is empty. Shared: the posed copies of a
    /// spinning scene keep the same texels.
    levels: std::sync::Arc<[texture::Level]>,
}

/// The largest coordinate a turned scene (a spin) may have, it or its pivot: an eighth of the
/// largest f32, so that the turn's translation (pivot − R·pivot, up to three coordinates
/// summed) plus a turned point (two) cannot reach infinity.
pub const MAX_TURNED_COORDINATE: f32 = f32::MAX / 8.0;

/// A light placed by the scene file (glTF's `KHR_lights_punctual`), in world space, with its
/// photometric intensity as the file gives it. File lights stay where the file puts them: a
/// spin turns the geometry, not them (they light the turning object like the map does).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLight {
    /// The file's name for the light, or `light N` (N its index in the file's list).
    pub name: String,
    pub kind: SceneLightKind,
    /// World-space position (unused by a directional light).
    pub position: Vec3,
    /// Unit world-space direction the light shines along: its node's −Z (unused by a point
    /// light).
    pub direction: Vec3,
    /// Linear RGB colour, a multiplier of the intensity.
    pub color: Vec3,
    /// Lux (lm/m²) for a directional light, candela (lm/sr) for point and spot lights.
    pub intensity: f32,
    /// Distance at which a point or spot light's influence ends, if the file sets one.
    pub range: Option<f32>,
}

/// The three kinds of `KHR_lights_punctual` light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SceneLightKind {
    Directional,
    Point,
    /// A cone: full intensity within `inner` radians of its axis, none beyond `outer`.
    Spot {
        inner: f32,
        outer: f32,
    },
}

impl SceneLightKind {
    /// `directional`, `point` or `spot`, as the extension spells them.
    pub fn name(self) -> &'static str {
        match self {
            SceneLightKind::Directional => "directional",
            SceneLightKind::Point => "point",
            SceneLightKind::Spot { .. } => "spot",
        }
    }
}

/// A perspective camera found in a scene file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneCamera {
    /// World-space eye position.
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit up vector, orthogonal to `forward`.
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub vfov_deg: f32,
}

/// The triangles one glTF node brought into the scene, and its names (for `[scene] catchers`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Part {
    /// The node's name, if it has one.
    pub node: Option<String>,
    /// Its mesh's name, if it has one.
    pub mesh: Option<String>,
    /// Its triangles (indices into [`Scene::triangles`]).
    pub triangles: Range<usize>,
}

impl Part {
    /// Whether `name` is the node's or its mesh's name.
    pub fn is_named(&self, name: &str) -> bool {
        self.node.as_deref() == Some(name) || self.mesh.as_deref() == Some(name)
    }

    /// Its name as an object: the node's, else its mesh's, else `object N` (N its index in
    /// [`Scene::parts`]).
    pub fn object_name(&self, index: usize) -> String {
        self.node
            .clone()
            .or_else(|| self.mesh.clone())
            .unwrap_or_else(|| format!("object {index}"))
    }
}

/// Which way is up in a scene file: glTF's +Y, or +Z (CAD and many exported models), which
/// [`Scene::stood_up`] turns to +Y.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Up {
    #[default]
    Y,
    Z,
}

impl std::str::FromStr for Up {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Up, String> {
        match s {
            "y" | "Y" => Ok(Up::Y),
            "z" | "Z" => Ok(Up::Z),
            _ => Err(format!("unknown up axis {s:?} (expected y or z)")),
        }
    }
}

impl std::fmt::Display for Up {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Up::Y => "y",
            Up::Z => "z",
        })
    }
}

/// All triangles of the default scene in world space, counted from [`Scene::origin`].
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Vertex positions: world space less [`origin`](Self::origin).
    pub positions: Vec<Vec3>,
    /// Unit shading normals per vertex.
    pub normals: Vec<Vec3>,
    /// Per vertex; (0, 0) where the file had none.
    pub uvs: Vec<Vec2>,
    /// `TEXCOORD_1` per vertex, or empty when no material of the scene reads it (then set 1
    /// reads set 0); (0, 0) where a primitive had none.
    pub uvs1: Vec<Vec2>,
    /// Unit tangent per vertex (xyz, world space) and the bitangent's handedness (w = ±1):
    /// the file's `TANGENT`, or MikkTSpace's; empty when no material has a normal map.
    pub tangents: Vec<Vec4>,
    /// `COLOR_0` per vertex, linear RGBA, or empty when no primitive has one (white where a
    /// primitive has none).
    pub colors: Vec<Vec4>,
    /// Vertex indices per triangle, counter-clockwise around the shading normal.
    pub triangles: Vec<[u32; 3]>,
    /// Material index per triangle.
    pub tri_material: Vec<u32>,
    /// Materials referenced by `tri_material`.
    pub materials: Vec<Material>,
    /// Textures referenced by the materials' [`TextureSlot`]s.
    pub textures: Vec<Texture>,
    /// The first perspective camera of the file, if any.
    pub camera: Option<SceneCamera>,
    /// The file's lights (`KHR_lights_punctual`), one per node that places one.
    pub lights: Vec<SceneLight>,
    /// Per triangle: whether it is a shadow catcher (it receives shadows and shows only them,
    /// as the tile services shade it). Empty when no triangle is.
    pub catcher: Vec<bool>,
    /// The glTF nodes that brought triangles, in file order (empty for built-in scenes).
    pub parts: Vec<Part>,
    /// The first triangle of the ground envshadow added below the model ([`ground`]), if it
    /// added one: it is the scene's last triangles, and the model is everything before it.
    pub added_ground: Option<usize>,
    /// Where it came from: a path, or `builtin:shapes`.
    pub source: String,
    /// The world-space point the positions (and the file's camera) count from: zero unless
    /// the scene lies far from the world's origin for its size ([`render_origin`]).
    pub origin: DVec3,
    /// Things skipped while loading (non-triangle primitives, …); each was also printed to
    /// stderr as `warning: …`.
    pub warnings: Vec<String>,
    /// What posing the file's animations needs (its nodes, skins, animations and moving
    /// primitives), shared by every copy; None when the file animates, skins and morphs
    /// nothing, or for built-in scenes.
    pub rig: Option<rig::Rig>,
    /// Points the model reaches in the poses a render plays (the played animation's frames),
    /// which [`model_bounds`](Self::model_bounds) and
    /// [`model_radius_about`](Self::model_radius_about) read instead of the vertices: the
    /// camera frames and a spin turns about the union of the poses, not the rest pose. None
    /// when nothing plays.
    pub framing: Option<std::sync::Arc<[Vec3]>>,
}

impl Scene {
    /// Loads `.gltf` (external buffers and images) or `.glb`.
    ///
    /// Takes every triangle primitive (triangles, strips and fans) of every node of the default
    /// scene (else scene 0, else all root nodes), transformed to world space. Bad input (missing
    /// or malformed file, out-of-range indices, non-finite positions, mismatched attribute
    /// counts, no triangles at all) is an [`crate::error::InputError`] naming the file and,
    /// where it applies, the mesh, primitive and accessor.
    ///
    /// Memory: what the file will hold (vertices and triangles of every mesh instance, image
    /// sizes) is counted from its headers and checked against the memory budget
    /// ([`crate::limits::Budget`]) before a buffer is read or an image decoded; each distinct
    /// image is decoded once, shared by every material that uses it.
    ///
    /// External buffers and images must lie inside the file's folder, after percent-decoding,
    /// normalising and following links ([`resource::Confinement`]); [`Scene::load_allowing`]
    /// opens one more folder.
    pub fn load(path: &Path) -> Result<Scene> {
        gltf::load(path, &mut Budget::default(), &AllowedFolder::NONE)
    }

    /// [`Scene::load`] against a render's `budget`, which then counts the scene.
    pub fn load_within(path: &Path, budget: &mut Budget) -> Result<Scene> {
        gltf::load(path, budget, &AllowedFolder::NONE)
    }

    /// [`Scene::load_within`], its external files read from its folder or `allowed`.
    pub fn load_allowing(
        path: &Path,
        budget: &mut Budget,
        allowed: &AllowedFolder,
    ) -> Result<Scene> {
        gltf::load(path, budget, allowed)
    }

    /// The files a glTF file's buffers and images name, resolved inside its folder or
    /// `allowed` as loading resolves them (`data:` URIs name none): what a host must hold
    /// besides the model file to load it.
    pub fn external_files(path: &Path, allowed: &AllowedFolder) -> Result<Vec<PathBuf>> {
        gltf::external_files(path, allowed)
    }

    /// Loads a glTF or GLB file's bytes, as [`Scene::load`] does the file: `path` names it in
    /// errors, and external buffers and images are read from its folder.
    pub fn load_bytes(bytes: &[u8], path: &Path) -> Result<Scene> {
        gltf::load_bytes(bytes, path, &mut Budget::default(), &AllowedFolder::NONE)
    }

    /// [`Scene::load_bytes`] against `budget`, which then counts the scene.
    pub fn load_bytes_within(bytes: &[u8], path: &Path, budget: &mut Budget) -> Result<Scene> {
        gltf::load_bytes(bytes, path, budget, &AllowedFolder::NONE)
    }

    /// The scene's ID mattes (`--cryptomatte`): its parts as objects ([`Part::object_name`])
    /// and its materials by name.
    pub fn cryptomatte_ids(&self) -> crate::cryptomatte::Ids {
        let objects: Vec<(String, Range<usize>)> = self
            .parts
            .iter()
            .enumerate()
            .map(|(i, p)| (p.object_name(i), p.triangles.clone()))
            .collect();
        let materials: Vec<String> = self.materials.iter().map(|m| m.name.clone()).collect();
        crate::cryptomatte::Ids::new(&objects, &materials)
    }

    /// The built-in `shapes` scene: sphere, box, cylinder, cone, torus and a thin upright slab
    /// on a ground plane, made in code (no files), the same bits on every call.
    ///
    /// Layout (metres-ish units, +Y up, everything resting on the ground at y = 0):
    ///
    /// | object | material | colour (linear) | placement and size |
    /// |---|---|---|---|
    /// | ground | `ground` | (0.5, 0.5, 0.5) | square x, z ∈ [−5, 5] at y = 0, 8 × 8 quads, normal +Y |
    /// | sphere | `sphere` | (0.75, 0.18, 0.15) red | centre (0, 0.5, 0), radius 0.5 |
    /// | box | `box` | (0.2, 0.35, 0.75) blue | 0.8 cube, centre (−1.25, 0.4, −0.5), turned 30° about +Y |
    /// | cylinder | `cylinder` | (0.25, 0.6, 0.25) green | axis x = 1.2, z = −0.7, radius 0.3, y ∈ [0, 1.2] |
    /// | cone | `cone` | (0.85, 0.65, 0.2) yellow | base centre (1.1, 0, 0.9), radius 0.45, apex at y = 1.0 |
    /// | torus | `torus` | (0.55, 0.3, 0.7) purple | lying flat, centre (−1.0, 0.14, 1.0), ring radius 0.45, tube radius 0.14 |
    /// | slab | `slab` | (0.85, 0.82, 0.75) off-white | thin upright wall, centre (0.1, 0.45, −1.5), 1.4 (x) × 0.9 (y) × 0.04 (z) |
    ///
    /// The objects fill x ∈ [−1.83, 1.55], y ∈ [0, 1.2], z ∈ [−1.52, 1.59]; the whole scene,
    /// ground included, is x, z ∈ [−5, 5], y ∈ [0, 1.2]. Frame the objects around (0, 0.5, 0),
    /// e.g. from (0, 2.5, 5.5) looking at (0, 0.4, 0) with a 40° vertical field of view.
    /// The torus is concave (it shadows itself), the slab is thin (its shadow comes from a
    /// 4 cm-thick occluder), and the objects stand close enough that low lights cast one onto
    /// another (box onto sphere from −X, cylinder onto slab from +X+Z). About 17,000 triangles: curved surfaces share vertices with smooth normals;
    /// box faces and caps have their own vertices, so creases stay sharp.
    pub fn shapes() -> Scene {
        shapes::build()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Axis-aligned bounds `(min, max)` of the vertices used by triangles; `(0, 0)` when there
    /// are no triangles.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        bounds_of(&self.positions, &self.triangles)
    }

    /// Bounds of the model: [`bounds`](Self::bounds) without the ground envshadow added, if
    /// any (what the camera frames and a spin turns about).
    pub fn model_bounds(&self) -> (Vec3, Vec3) {
        match &self.framing {
            Some(points) if !points.is_empty() => {
                let lo = points.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
                let hi = points.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
                (lo, hi)
            }
            _ => bounds_of(&self.positions, self.model_triangles()),
        }
    }

    /// The model's triangles: all of them but the ground envshadow added, if any (it comes
    /// last).
    pub fn model_triangles(&self) -> &[[u32; 3]] {
        &self.triangles[..self.added_ground.unwrap_or(self.triangles.len())]
    }

    /// The farthest any point of the model (not an added ground) lies from the vertical line
    /// through `axis`: the radius of the cylinder the model sweeps as it turns about that line
    /// (a turntable's spin or orbit).
    pub fn model_radius_about(&self, axis: Vec3) -> f32 {
        let mut r2 = 0.0f32;
        let mut reach = |p: Vec3| {
            let d = p - axis;
            r2 = r2.max(d.x * d.x + d.z * d.z);
        };
        match &self.framing {
            Some(points) if !points.is_empty() => points.iter().for_each(|&p| reach(p)),
            _ => {
                for &i in self.model_triangles().iter().flatten() {
                    reach(self.positions[i as usize]);
                }
            }
        }
        r2.sqrt()
    }

    /// Whether triangle `tri` is a shadow catcher.
    #[inline]
    pub fn is_catcher(&self, tri: usize) -> bool {
        self.catcher.get(tri).copied().unwrap_or(false)
    }

    /// Makes the triangles `tris` shadow catchers.
    pub fn set_catcher(&mut self, tris: Range<usize>) {
        if tris.is_empty() {
            return;
        }
        self.catcher.resize(self.triangles.len(), false);
        self.catcher[tris].fill(true);
    }

    /// Makes the nodes (or meshes) called `names` shadow catchers; the first name no node or
    /// mesh has is returned as the error.
    pub fn mark_catchers(&mut self, names: &[String]) -> std::result::Result<(), String> {
        for name in names {
            let tris: Vec<Range<usize>> = self
                .parts
                .iter()
                .filter(|p| p.is_named(name))
                .map(|p| p.triangles.clone())
                .collect();
            if tris.is_empty() {
                return Err(name.clone());
            }
            for t in tris {
                self.set_catcher(t);
            }
        }
        Ok(())
    }

    /// The scene turned so that `up` points along +Y, the camera with it: for Z-up, the
    /// rotation of −90° about +X (Blender's own glTF convention: +Z → +Y, +Y → −Z), exact
    /// (no trigonometry), applied before anything else reads the scene.
    pub fn stood_up(self, up: Up) -> Scene {
        match up {
            Up::Y => self,
            Up::Z => {
                let m = Mat4::from_cols(
                    glam::Vec4::new(1.0, 0.0, 0.0, 0.0),
                    glam::Vec4::new(0.0, 0.0, -1.0, 0.0),
                    glam::Vec4::new(0.0, 1.0, 0.0, 0.0),
                    glam::Vec4::W,
                );
                let mut out = self.transformed(m);
                out.camera = self.camera.map(|c| SceneCamera {
                    position: m.transform_point3(c.position),
                    forward: m.transform_vector3(c.forward),
                    up: m.transform_vector3(c.up),
                    vfov_deg: c.vfov_deg,
                });
                // The file's lights live in the file's world, as its camera does.
                for l in &mut out.lights {
                    l.position = m.transform_point3(l.position);
                    l.direction = m.transform_vector3(l.direction);
                }
                // The positions count from the origin, which turns with them.
                out.origin = m.as_dmat4().transform_point3(self.origin);
                // Poses stand up as the loaded vertices did.
                if let Some(rig) = &mut out.rig {
                    rig.up = Up::Z;
                }
                out
            }
        }
    }

    /// A world-space point (a spec's camera position, target or pivot) in the scene's
    /// coordinates, which count from [`origin`](Self::origin); the point itself when that is
    /// zero.
    pub fn to_local(&self, world: Vec3) -> Vec3 {
        (world.as_dvec3() - self.origin).as_vec3()
    }

    /// A point of the scene's coordinates in world space.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        (local.as_dvec3() + self.origin).as_vec3()
    }

    /// The three corners of triangle `tri`.
    #[inline]
    pub fn triangle(&self, tri: usize) -> [Vec3; 3] {
        self.triangles[tri].map(|i| self.positions[i as usize])
    }

    /// Unit geometric normal `(p1 − p0) × (p2 − p0)` of triangle `tri`; zero if degenerate.
    pub fn face_normal(&self, tri: usize) -> Vec3 {
        let [a, b, c] = self.triangle(tri);
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The vertex normals of triangle `tri`'s corners.
    #[inline]
    pub fn corner_normals(&self, tri: usize) -> [Vec3; 3] {
        self.triangles[tri].map(|i| self.normals[i as usize])
    }

    /// Interpolated, normalised vertex normal at barycentric `(u, v)` of triangle `tri`; the face
    /// normal where the interpolation cancels.
    pub fn shading_normal(&self, tri: usize, bary: (f32, f32)) -> Vec3 {
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let (u, v) = bary;
        let n = self.normals[i0] * (1.0 - u - v) + self.normals[i1] * u + self.normals[i2] * v;
        let n = n.normalize_or_zero();
        if n != Vec3::ZERO {
            n
        } else {
            self.face_normal(tri)
        }
    }

    /// Interpolated texture coordinates at barycentric `(u, v)` of triangle `tri`.
    pub fn uv(&self, tri: usize, bary: (f32, f32)) -> Vec2 {
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let (u, v) = bary;
        self.uvs[i0] * (1.0 - u - v) + self.uvs[i1] * u + self.uvs[i2] * v
    }

    /// Linear albedo at barycentric `(u, v)` of triangle `tri`: the material's base colour times
    /// its texture (if any) sampled at the interpolated UV, times the vertex colour (if any).
    pub fn albedo(&self, tri: usize, bary: (f32, f32)) -> Vec3 {
        self.base_color_at(tri, bary, 0.0).truncate()
    }

    /// UV units per world unit on triangle `tri`: `sqrt(UV area / world area)`, so that a width
    /// on the surface times this is the same width in UV (exact for a mapping that scales
    /// evenly; a stretched one gets the geometric mean of its two scales). 0 where either area
    /// is zero or not finite: such a triangle is point-sampled.
    ///
    /// Computed from the corners on each call (a dozen operations beside a traced ray, and only
    /// for textured hits) rather than stored, so it cannot go stale when
    /// [`transformed`](Self::transformed) scales the scene or a scene is built through the
    /// public fields.
    pub fn uv_density(&self, tri: usize) -> f32 {
        let [a, b, c] = self.triangle(tri);
        let world = (b - a).cross(c - a).length();
        let [ta, tb, tc] = self.triangles[tri].map(|i| self.uvs[i as usize]);
        let uv = (tb - ta).perp_dot(tc - ta).abs();
        let density = (uv / world).sqrt();
        if density.is_finite() { density } else { 0.0 }
    }

    /// Linear albedo at barycentric `(u, v)` of triangle `tri`, with the texture filtered over a
    /// footprint `footprint_world` wide on the surface (world units; [`footprint_width`] gives
    /// a sample's): the material's base colour times [`Texture::sample_footprint`] at the
    /// interpolated UV with footprint `footprint_world × uv_density(tri)`. Untextured materials
    /// give their base colour.
    ///
    /// Where that footprint is at most one texel (also zero, negative or NaN) this is exactly
    /// [`albedo`](Self::albedo), bit for bit.
    pub fn albedo_footprint(&self, tri: usize, bary: (f32, f32), footprint_world: f32) -> Vec3 {
        self.base_color_at(tri, bary, footprint_world).truncate()
    }

    /// A copy with every vertex moved by `m` (normals by its inverse transpose). Winding is
    /// flipped when `m` mirrors, so geometric and shading normals keep agreeing. The camera and
    /// the file's lights are left where they were: this moves the objects, not the viewer or
    /// the lights.
    pub fn transformed(&self, m: Mat4) -> Scene {
        let mut out = self.clone();
        out.transform(m);
        out
    }

    /// [`transformed`](Self::transformed) in place: a posed copy is moved without another.
    pub fn transform(&mut self, m: Mat4) {
        let normal_matrix = normal_matrix(m);
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        for n in &mut self.normals {
            let t = (normal_matrix * *n).normalize_or_zero();
            // A singular `m` flattens normals; keep the old one rather than a zero vector.
            if t != Vec3::ZERO {
                *n = t;
            }
        }
        // Tangents are surface directions: they move with `m` itself; a mirror flips the
        // bitangent's handedness, as it flips the winding.
        let handedness = if m.determinant() < 0.0 { -1.0 } else { 1.0 };
        for t in &mut self.tangents {
            let moved = m.transform_vector3(t.truncate()).normalize_or_zero();
            if moved != Vec3::ZERO {
                *t = moved.extend(t.w * handedness);
            }
        }
        if m.determinant() < 0.0 {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
    }

    /// Why turning this scene about a vertical axis through `pivot` could overflow (a posed
    /// vertex at infinity, which a BVH cannot hold), if it could: the turn's matrix and its
    /// products stay finite while every coordinate of the scene and of the pivot is at most
    /// [`MAX_TURNED_COORDINATE`] in magnitude.
    pub fn turn_problem(&self, pivot: Vec3) -> Option<String> {
        let (lo, hi) = self.bounds();
        let scene = lo.abs().max(hi.abs()).max_element();
        let pivot_max = pivot.abs().max_element();
        if scene <= MAX_TURNED_COORDINATE && pivot_max <= MAX_TURNED_COORDINATE {
            return None;
        }
        Some(format!(
            "turning the scene (coordinates up to {scene:.1e}) about its pivot (coordinates up to {pivot_max:.1e}) could overflow; a spin turns coordinates up to {MAX_TURNED_COORDINATE:.1e}"
        ))
    }

    /// Appends `other`'s triangles, materials and textures (indices shifted, positions moved to
    /// this scene's origin). Keeps this scene's camera, origin and source, taking `other`'s
    /// camera only if this one has none.
    pub fn merge(&mut self, other: Scene) {
        let vertices = self.positions.len();
        let vertex_base = vertices as u32;
        let material_base = self.materials.len() as u32;
        let texture_base = self.textures.len();
        let added = other.positions.len();
        extend_optional(&mut self.uvs1, vertices, other.uvs1, added, Vec2::ZERO);
        extend_optional(&mut self.tangents, vertices, other.tangents, added, Vec4::X);
        extend_optional(&mut self.colors, vertices, other.colors, added, Vec4::ONE);
        let shift = other.origin - self.origin;
        if shift == DVec3::ZERO {
            self.positions.extend(other.positions);
        } else {
            self.positions.extend(
                other
                    .positions
                    .iter()
                    .map(|p| (p.as_dvec3() + shift).as_vec3()),
            );
        }
        self.normals.extend(other.normals);
        self.uvs.extend(other.uvs);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + vertex_base)));
        self.tri_material
            .extend(other.tri_material.iter().map(|m| m + material_base));
        self.materials
            .extend(other.materials.into_iter().map(|mut m| {
                for slot in m.slots_mut().into_iter().flatten() {
                    slot.texture += texture_base;
                }
                m
            }));
        self.textures.extend(other.textures);
        let triangle_base = self.triangles.len() - other.triangles.len();
        if !other.catcher.is_empty() {
            self.catcher.resize(triangle_base, false);
            self.catcher.extend(other.catcher);
        }
        self.parts.extend(other.parts.into_iter().map(|mut p| {
            p.triangles = p.triangles.start + triangle_base..p.triangles.end + triangle_base;
            p
        }));
        if self.camera.is_none() {
            self.camera = other.camera.map(|mut c| {
                c.position = (c.position.as_dvec3() + shift).as_vec3();
                c
            });
        }
        self.lights.extend(other.lights.into_iter().map(|mut l| {
            l.position = (l.position.as_dvec3() + shift).as_vec3();
            l
        }));
        self.warnings.extend(other.warnings);
    }
}

/// Appends `added` vertices' values of an optional per-vertex array (empty = every vertex has
/// `default`) to `to`, which holds `vertices` vertices' or is empty: the result is empty when
/// both are, else one value per vertex, defaults filled in on whichever side had none.
pub(crate) fn extend_optional<T: Copy>(
    to: &mut Vec<T>,
    vertices: usize,
    values: Vec<T>,
    added: usize,
    default: T,
) {
    if to.is_empty() && values.is_empty() {
        return;
    }
    if to.is_empty() {
        to.resize(vertices, default);
    }
    if values.is_empty() {
        to.resize(vertices + added, default);
    } else {
        to.extend(values);
    }
}

/// Axis-aligned bounds `(min, max)` of the vertices `triangles` use; `(0, 0)` when there are
/// none.
fn bounds_of(positions: &[Vec3], triangles: &[[u32; 3]]) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for &i in triangles.iter().flatten() {
        let p = positions[i as usize];
        lo = lo.min(p);
        hi = hi.max(p);
    }
    if triangles.is_empty() {
        (Vec3::ZERO, Vec3::ZERO)
    } else {
        (lo, hi)
    }
}

/// The width, in world units, of the surface a ray's cone covers, for
/// [`Scene::albedo_footprint`]: `distance × angle / |cos_view|`.
///
/// - `distance`: from the eye to the hit, along the ray (the ray parameter for a unit
///   direction).
/// - `angle`: the angle the cone spans at the eye, radians: what one sample stands for
///   (the camera's `Camera::pixel_angle` times the sample's share of its pixel).
/// - `cos_view`: cosine of the angle between the ray and the surface normal (either sign).
///
/// Seen at an angle, the cone covers `distance × angle` across the tilt and that over
/// `|cos_view|` along it. The filter is isotropic, so it takes the longer: it blurs across the
/// tilt at grazing angles but never aliases along it (pbrt-v4's trilinear filter makes the same
/// choice). Grazing clamp: `|cos_view|` is taken as at least `angle`, so the width stops
/// growing at `distance`. Closer to grazing than that, the far edge of the cone is about to
/// pass over the surface's horizon: its true footprint runs to infinity, and the first-order
/// `1 / cos` no longer describes it anyway. The clamp also keeps the result finite at
/// `cos_view = 0`.
///
/// Returns 0 (point sampling) for non-finite or non-positive results.
pub fn footprint_width(distance: f32, angle: f32, cos_view: f32) -> f32 {
    let cos = cos_view.abs().min(1.0).max(angle);
    let width = distance * angle / cos;
    if width.is_finite() && width > 0.0 {
        width
    } else {
        0.0
    }
}

/// The matrix that carries normals under `m`: the inverse transpose of its linear part.
/// Returns the identity for singular `m`, whose callers must avoid that case anyway.
pub fn normal_matrix(m: Mat4) -> Mat3 {
    let linear = Mat3::from_mat4(m);
    let det = linear.determinant();
    if det == 0.0 || !det.is_finite() {
        return Mat3::IDENTITY;
    }
    linear.inverse().transpose()
}
