//! The ground under a model that has none (`[scene] ground`): whether the scene already has a
//! surface the model stands on ([`has_ground`]), and the ground envshadow adds below it
//! ([`add_ground`]). Up is +Y (a Z-up file is stood up first, [`super::Scene::stood_up`]).
//!
//! [ours] A scene has a ground when, seen from above, a thin, roughly horizontal sheet at its
//! bottom takes most of the edge of its footprint and reaches beyond everything standing on
//! it on all four sides: a floor, a plane, a terrain under a tree, a board under objects. A
//! statue's plinth (thick), a model's wing or tail (not at the bottom, not around the model),
//! a crate's bottom or a model's own feet (not beyond the model) are no ground. The view from
//! above is a height map over a 64 × 64 grid of the scene's horizontal extent: each cell keeps
//! the highest surface over its centre, its slope, and the lowest surface under it (triangles
//! rasterised by their projection, so the test is exact, deterministic and needs no BVH).

use glam::{Vec2, Vec3};

use super::{Material, Scene};

/// What `[scene] ground` asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Ground {
    /// Add a ground when the scene has none ([`has_ground`]).
    #[default]
    Auto,
    /// Never add one.
    None,
    /// Always add one, even under a scene that has its own.
    Always,
}

impl std::str::FromStr for Ground {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Ground, String> {
        match s {
            "auto" => Ok(Ground::Auto),
            "none" => Ok(Ground::None),
            "always" => Ok(Ground::Always),
            _ => Err(format!(
                "unknown ground {s:?} (expected auto, none or always)"
            )),
        }
    }
}

impl std::fmt::Display for Ground {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Ground::Auto => "auto",
            Ground::None => "none",
            Ground::Always => "always",
        })
    }
}

/// Cells per side of the height map seen from above.
const GRID: usize = 64;
/// Cells of the outer ring (on each side) where a ground shows beyond what stands on it.
const RING: usize = GRID / 10;
/// A surface at most this steep (its normal within 40° of up, either side: glTF windings of
/// double-sided terrain are not to be trusted) counts as roughly horizontal.
const FLAT_COS: f32 = 0.766;
/// A ground's thickness at most, and how far above the level of its edge it may rise inside
/// (uneven terrain), as a share of the scene's largest extent.
const BAND: f32 = 0.05;
/// The share of the outer ring's cells seen from above that must be thin flat ground.
const MIN_RING: f32 = 0.6;
/// How far above the scene's lowest point the ground's edge may lie, as a share of the scene's
/// height (a terrain's dips may go lower than its edge).
const BOTTOM: f32 = 0.25;
/// The share of the footprint a ground must cover, seen from above.
const MIN_SHARE: f32 = 0.25;

/// The albedo of the ground envshadow adds (neutral, a little below the 0.8 of glTF's
/// default material, so a default-grey model stands out from it).
pub const GROUND_ALBEDO: f32 = 0.5;
/// The added ground's radius, in radii of the model's bounding sphere: with the default
/// camera (40° field of view, 25° above the horizon, framing the cylinder the model sweeps:
/// at most about 3.2 radii away) the frame's top edge looks 5° below the horizon and meets
/// the ground at most about 30 radii away, so
/// the ground's edge stays out of view, and shadows of lights down to 2° above the horizon
/// fall on it.
pub const GROUND_RADII: f32 = 32.0;
/// The name the added ground's material and part carry.
pub const GROUND_NAME: &str = "envshadow-ground";

/// How a cell of the height map sees the scene from above.
#[derive(Clone, Copy)]
struct Cell {
    /// The highest surface over the cell's centre (−∞: none), and whether it is roughly
    /// horizontal.
    top: f32,
    flat: bool,
    /// The lowest surface under the cell's centre (+∞: none).
    bottom: f32,
}

impl Cell {
    const EMPTY: Cell = Cell {
        top: f32::NEG_INFINITY,
        flat: false,
        bottom: f32::INFINITY,
    };

    fn is_empty(&self) -> bool {
        self.top == f32::NEG_INFINITY
    }
}

/// Whether the scene has a ground under what stands on it (see the module comment).
pub fn has_ground(scene: &Scene) -> bool {
    if scene.triangles.is_empty() {
        return false;
    }
    let (lo, hi) = scene.bounds();
    let ext = hi - lo;
    if !(ext.x > 0.0 && ext.z > 0.0) {
        // Flat as a wall seen edge-on from above: nothing lies on it.
        return false;
    }
    let cells = height_map(scene, lo, ext);
    let tol = BAND * ext.max_element();
    // The edge of the footprint: mostly a thin flat sheet near the bottom.
    let ring = |i: usize| {
        let (x, z) = (i % GRID, i / GRID);
        x < RING || z < RING || x >= GRID - RING || z >= GRID - RING
    };
    let seen: Vec<&Cell> = (0..cells.len())
        .filter(|&i| ring(i) && !cells[i].is_empty())
        .map(|i| &cells[i])
        .collect();
    let mut edge: Vec<f32> = seen
        .iter()
        .filter(|c| c.flat && c.top - c.bottom <= tol)
        .map(|c| c.top)
        .collect();
    if edge.len() < 8 || (edge.len() as f32) < MIN_RING * seen.len() as f32 {
        return false;
    }
    edge.sort_by(f32::total_cmp);
    let (level_lo, level_hi) = (edge[edge.len() / 10], edge[edge.len() * 9 / 10]);
    if level_lo - lo.y > BOTTOM * ext.y {
        return false;
    }
    // Inside: flat cells no higher than the edge's level (plus the tolerance) are ground;
    // everything else seen from above stands on it.
    let mut ground = Span::default();
    let mut standing = Span::default();
    for (i, c) in cells.iter().enumerate() {
        let (x, z) = (i % GRID, i / GRID);
        if c.is_empty() {
            continue;
        }
        if c.flat && c.top <= level_hi + tol {
            ground.add(x, z);
        } else {
            standing.add(x, z);
        }
    }
    // A scene that is all low and flat (a board, a rug) has nothing standing to shadow it.
    if standing.count == 0 {
        return true;
    }
    let share = ground.count as f32 / (ground.count + standing.count) as f32;
    share >= MIN_SHARE
        && ground.x0 < standing.x0
        && ground.x1 > standing.x1
        && ground.z0 < standing.z0
        && ground.z1 > standing.z1
}

/// The cells a class of the height map takes: how many, and their bounding rectangle.
struct Span {
    count: usize,
    x0: usize,
    x1: usize,
    z0: usize,
    z1: usize,
}

impl Default for Span {
    fn default() -> Span {
        Span {
            count: 0,
            x0: usize::MAX,
            x1: 0,
            z0: usize::MAX,
            z1: 0,
        }
    }
}

impl Span {
    fn add(&mut self, x: usize, z: usize) {
        self.count += 1;
        self.x0 = self.x0.min(x);
        self.x1 = self.x1.max(x);
        self.z0 = self.z0.min(z);
        self.z1 = self.z1.max(z);
    }
}

/// The scene seen from above: for each cell of a `GRID × GRID` grid over the horizontal
/// extent from `lo` (sizes `ext`), the highest and lowest surfaces over the cell's centre.
fn height_map(scene: &Scene, lo: Vec3, ext: Vec3) -> Vec<Cell> {
    let mut cells = vec![Cell::EMPTY; GRID * GRID];
    let size = Vec2::new(ext.x, ext.z) / GRID as f32;
    let centre = |i: usize, j: usize| {
        Vec2::new(
            lo.x + (i as f32 + 0.5) * size.x,
            lo.z + (j as f32 + 0.5) * size.y,
        )
    };
    // The cells whose centres lie in [a, b] along one axis.
    let range = |a: f32, b: f32, origin: f32, step: f32| {
        let first = ((a - origin) / step - 0.5).ceil().max(0.0);
        let last = ((b - origin) / step - 0.5).floor().min((GRID - 1) as f32);
        (last >= first).then_some((first as usize, last as usize))
    };
    for t in 0..scene.triangles.len() {
        let [a, b, c] = scene.triangle(t);
        let (pa, pb, pc) = (
            Vec2::new(a.x, a.z),
            Vec2::new(b.x, b.z),
            Vec2::new(c.x, c.z),
        );
        let d = (pb - pa).perp_dot(pc - pa);
        if d == 0.0 || !d.is_finite() {
            continue; // vertical: it covers no cell centre
        }
        let flat = scene.face_normal(t).y.abs() >= FLAT_COS;
        let (min, max) = (pa.min(pb).min(pc), pa.max(pb).max(pc));
        let (Some((x0, x1)), Some((z0, z1))) = (
            range(min.x, max.x, lo.x, size.x),
            range(min.y, max.y, lo.z, size.y),
        ) else {
            continue;
        };
        for j in z0..=z1 {
            for i in x0..=x1 {
                let p = centre(i, j);
                let wb = (p - pa).perp_dot(pc - pa) / d;
                let wc = (pb - pa).perp_dot(p - pa) / d;
                let wa = 1.0 - wb - wc;
                if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                    continue;
                }
                let y = a.y * wa + b.y * wb + c.y * wc;
                let cell = &mut cells[j * GRID + i];
                if y > cell.top {
                    cell.top = y;
                    cell.flat = flat;
                }
                cell.bottom = cell.bottom.min(y);
            }
        }
    }
    cells
}

/// Appends a ground below the model: a flat disc at the model's lowest point, centred under
/// its bounding box, [`GROUND_RADII`] radii of its bounding sphere wide, facing up, of albedo
/// [`GROUND_ALBEDO`]; a shadow catcher when `catcher` is true. Rings grow outwards from the
/// model's size, so no triangle near the model is larger than the model (long thin triangles
/// from the centre would overlap in the BVH where the shadow rays start).
pub fn add_ground(scene: &mut Scene, catcher: bool) {
    let (lo, hi) = scene.model_bounds();
    let radius = ((hi - lo) * 0.5).length().max(1e-6);
    let centre = Vec3::new((lo.x + hi.x) * 0.5, lo.y, (lo.z + hi.z) * 0.5);
    const SEGMENTS: u32 = 48;
    let mut rings = vec![radius];
    while rings[rings.len() - 1] < GROUND_RADII * radius {
        rings.push((rings[rings.len() - 1] * 2.0).min(GROUND_RADII * radius));
    }
    let first_tri = scene.triangles.len();
    let base = scene.positions.len() as u32;
    let material = scene.materials.len() as u32;
    // [ours] Lambertian, as the ground always was: a plain surface to receive shadows.
    scene
        .materials
        .push(Material::lambert(GROUND_NAME, Vec3::splat(GROUND_ALBEDO)));
    scene.positions.push(centre);
    for &r in &rings {
        for k in 0..SEGMENTS {
            let (s, c) = libm::sincosf(std::f32::consts::TAU * k as f32 / SEGMENTS as f32);
            scene.positions.push(centre + Vec3::new(r * c, 0.0, r * s));
        }
    }
    let added = scene.positions.len() - base as usize;
    scene.normals.extend(std::iter::repeat_n(Vec3::Y, added));
    scene.uvs.extend(std::iter::repeat_n(Vec2::ZERO, added));
    // The optional per-vertex arrays, where the model has them, get the ground's defaults.
    let before = base as usize;
    super::extend_optional(&mut scene.uvs1, before, Vec::new(), added, Vec2::ZERO);
    super::extend_optional(
        &mut scene.tangents,
        before,
        Vec::new(),
        added,
        glam::Vec4::X,
    );
    super::extend_optional(
        &mut scene.colors,
        before,
        Vec::new(),
        added,
        glam::Vec4::ONE,
    );
    // Counter-clockwise seen from +Y: angles grow from +X towards +Z, so (centre, next, this).
    let vertex = |ring: usize, k: u32| base + 1 + ring as u32 * SEGMENTS + k % SEGMENTS;
    for k in 0..SEGMENTS {
        scene.triangles.push([base, vertex(0, k + 1), vertex(0, k)]);
    }
    for ring in 1..rings.len() {
        for k in 0..SEGMENTS {
            let (a, b) = (vertex(ring - 1, k), vertex(ring - 1, k + 1));
            let (c, d) = (vertex(ring, k), vertex(ring, k + 1));
            scene.triangles.push([a, b, d]);
            scene.triangles.push([a, d, c]);
        }
    }
    let tris = first_tri..scene.triangles.len();
    scene
        .tri_material
        .extend(std::iter::repeat_n(material, tris.len()));
    scene.parts.push(super::Part {
        node: Some(GROUND_NAME.into()),
        mesh: None,
        triangles: tris.clone(),
    });
    if catcher {
        scene.set_catcher(tris);
    }
    scene.added_ground = Some(first_tri);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_added_ground_faces_up_and_lies_at_the_model_s_foot() {
        let mut scene = Scene::shapes();
        let (lo, hi) = scene.bounds();
        let tris = scene.triangles.len();
        add_ground(&mut scene, true);
        assert_eq!(scene.model_bounds(), (lo, hi));
        assert_eq!(scene.added_ground, Some(tris));
        for t in tris..scene.triangles.len() {
            assert!(scene.face_normal(t).y > 0.999, "triangle {t}");
            assert!(scene.is_catcher(t));
            assert!(scene.triangle(t).iter().all(|p| p.y == lo.y));
        }
        assert!(!scene.is_catcher(0));
        let (glo, ghi) = scene.bounds();
        let radius = ((hi - lo) * 0.5).length();
        assert!((ghi.x - glo.x) > 2.0 * 0.99 * GROUND_RADII * radius);
    }

    #[test]
    fn the_shapes_scene_has_a_ground_and_its_objects_alone_have_none() {
        let scene = Scene::shapes();
        assert!(has_ground(&scene));
        // The shapes without their ground (its 128 triangles come first).
        let mut objects = scene.clone();
        objects.triangles.drain(..128);
        objects.tri_material.drain(..128);
        assert!(!has_ground(&objects));
        let mut with = objects.clone();
        add_ground(&mut with, false);
        assert!(has_ground(&with));
    }
}
