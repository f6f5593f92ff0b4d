//! The built-in `shapes` scene, made in code. The layout is documented on [`Scene::shapes`].

use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use std::f32::consts::{PI, TAU};

use super::{Material, Scene, normal_matrix};

/// Builds the scene documented on [`Scene::shapes`].
pub(super) fn build() -> Scene {
    let mut b = Builder {
        scene: Scene {
            source: "builtin:shapes".to_string(),
            ..Scene::default()
        },
        xf: Mat4::IDENTITY,
        nm: Mat3::IDENTITY,
        material: 0,
    };

    b.begin("ground", Vec3::splat(0.5), Mat4::IDENTITY);
    b.surface(8, 8, |u, v| {
        let p = Vec3::new(-5.0 + 10.0 * u, 0.0, -5.0 + 10.0 * v);
        (p, Vec3::Y)
    });

    b.begin(
        "sphere",
        Vec3::new(0.75, 0.18, 0.15),
        Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)),
    );
    sphere(&mut b, 0.5);

    b.begin(
        "box",
        Vec3::new(0.2, 0.35, 0.75),
        Mat4::from_scale_rotation_translation(
            Vec3::splat(0.8),
            Quat::from_rotation_y(30f32.to_radians()),
            Vec3::new(-1.25, 0.4, -0.5),
        ),
    );
    unit_box(&mut b);

    b.begin(
        "cylinder",
        Vec3::new(0.25, 0.6, 0.25),
        Mat4::from_translation(Vec3::new(1.2, 0.0, -0.7)),
    );
    cylinder(&mut b, 0.3, 1.2);

    b.begin(
        "cone",
        Vec3::new(0.85, 0.65, 0.2),
        Mat4::from_translation(Vec3::new(1.1, 0.0, 0.9)),
    );
    cone(&mut b, 0.45, 1.0);

    b.begin(
        "torus",
        Vec3::new(0.55, 0.3, 0.7),
        Mat4::from_translation(Vec3::new(-1.0, 0.14, 1.0)),
    );
    torus(&mut b, 0.45, 0.14);

    b.begin(
        "slab",
        Vec3::new(0.85, 0.82, 0.75),
        Mat4::from_scale_rotation_translation(
            Vec3::new(1.4, 0.9, 0.04),
            Quat::IDENTITY,
            Vec3::new(0.1, 0.45, -1.5),
        ),
    );
    unit_box(&mut b);

    // Each object is its material's triangles, named as it (for ID mattes and `[scene]
    // catchers`).
    let mut start = 0;
    let tris = &b.scene.tri_material;
    for (m, material) in b.scene.materials.iter().enumerate() {
        let end = start + tris[start..].iter().take_while(|&&t| t == m as u32).count();
        b.scene.parts.push(super::Part {
            node: Some(material.name.clone()),
            mesh: None,
            triangles: start..end,
        });
        start = end;
    }
    b.scene
}

/// Accumulates geometry for one object at a time under a placement transform.
struct Builder {
    scene: Scene,
    xf: Mat4,
    nm: Mat3,
    material: u32,
}

impl Builder {
    /// Starts a new object with its own material, placed by `xf`.
    fn begin(&mut self, name: &str, color: Vec3, xf: Mat4) {
        self.material = self.scene.materials.len() as u32;
        // [ours] Lambertian, as the paper's scenes were shaded: the built-in scene's frames
        // stay what they were before glTF materials.
        self.scene.materials.push(Material::lambert(name, color));
        self.xf = xf;
        self.nm = normal_matrix(xf);
    }

    /// A grid of `nu × nv` quads over the parametric patch `f(u, v) → (position, normal)` in
    /// object space, u, v ∈ [0, 1]; vertices are shared inside the patch (smooth shading).
    /// Zero-area triangles (at poles and apexes) are left out, and each triangle is wound so
    /// that its geometric normal agrees with its vertex normals.
    fn surface(&mut self, nu: usize, nv: usize, f: impl Fn(f32, f32) -> (Vec3, Vec3)) {
        let base = self.scene.positions.len() as u32;
        for j in 0..=nv {
            for i in 0..=nu {
                let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
                let (p, n) = f(u, v);
                self.scene.positions.push(self.xf.transform_point3(p));
                self.scene.normals.push((self.nm * n).normalize());
                self.scene.uvs.push(Vec2::new(u, v));
            }
        }
        let at = |i: usize, j: usize| base + (j * (nu + 1) + i) as u32;
        for j in 0..nv {
            for i in 0..nu {
                self.triangle([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                self.triangle([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }

    /// Adds a triangle unless it has no area, swapping two corners if needed so that it winds
    /// counter-clockwise around its vertex normals.
    fn triangle(&mut self, mut t: [u32; 3]) {
        let [a, b, c] = t.map(|i| self.scene.positions[i as usize]);
        let geometric = (b - a).cross(c - a);
        if geometric.length_squared() < 1e-14 {
            return;
        }
        let shading: Vec3 = t.iter().map(|&i| self.scene.normals[i as usize]).sum();
        if geometric.dot(shading) < 0.0 {
            t.swap(1, 2);
        }
        self.scene.triangles.push(t);
        self.scene.tri_material.push(self.material);
    }
}

/// A UV sphere about the origin: 96 segments around, 48 from pole to pole.
fn sphere(b: &mut Builder, r: f32) {
    b.surface(96, 48, |u, v| {
        let (phi, theta) = (TAU * u, PI * v);
        let n = Vec3::new(
            libm::sinf(theta) * libm::cosf(phi),
            libm::cosf(theta),
            libm::sinf(theta) * libm::sinf(phi),
        );
        (r * n, n)
    });
}

/// A cube of side 1 about the origin, six flat faces with their own vertices.
fn unit_box(b: &mut Builder) {
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let mut s = Vec3::ZERO;
            s[(axis + 1) % 3] = 1.0;
            let mut t = Vec3::ZERO;
            t[(axis + 2) % 3] = 1.0;
            b.surface(1, 1, |u, v| (0.5 * n + (u - 0.5) * s + (v - 0.5) * t, n));
        }
    }
}

/// A closed cylinder standing on y = 0 about the Y axis: 64 segments, smooth side, flat caps.
fn cylinder(b: &mut Builder, r: f32, h: f32) {
    b.surface(64, 4, |u, v| {
        let n = Vec3::new(libm::cosf(TAU * u), 0.0, libm::sinf(TAU * u));
        (Vec3::new(r * n.x, h * v, r * n.z), n)
    });
    disc(b, r, h, Vec3::Y);
    disc(b, r, 0.0, Vec3::NEG_Y);
}

/// A closed cone standing on y = 0 about the Y axis, apex at y = h: 64 segments, 8 rings.
/// The apex vertex is repeated per segment, each with its segment's normal.
fn cone(b: &mut Builder, r: f32, h: f32) {
    b.surface(64, 8, |u, v| {
        let (c, s) = (libm::cosf(TAU * u), libm::sinf(TAU * u));
        // The side's normal leans outward by the slope: (h cos, r, h sin), normalised.
        let n = Vec3::new(h * c, r, h * s).normalize();
        (Vec3::new((1.0 - v) * r * c, v * h, (1.0 - v) * r * s), n)
    });
    disc(b, r, 0.0, Vec3::NEG_Y);
}

/// A flat cap of radius `r` at height `y`, facing `n`.
fn disc(b: &mut Builder, r: f32, y: f32, n: Vec3) {
    b.surface(64, 1, |u, v| {
        let a = TAU * u;
        (
            Vec3::new(v * r * libm::cosf(a), y, v * r * libm::sinf(a)),
            n,
        )
    });
}

/// A torus lying in the XZ plane about the origin: ring radius `big`, tube radius `small`,
/// 96 segments around the ring, 32 around the tube.
fn torus(b: &mut Builder, big: f32, small: f32) {
    b.surface(96, 32, |u, v| {
        let (phi, theta) = (TAU * u, TAU * v);
        let n = Vec3::new(
            libm::cosf(theta) * libm::cosf(phi),
            libm::sinf(theta),
            libm::cosf(theta) * libm::sinf(phi),
        );
        let centre = Vec3::new(big * libm::cosf(phi), 0.0, big * libm::sinf(phi));
        (centre + small * n, n)
    });
}
