//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// The folder with the shared test assets (bunny glTF, HDR maps): `$ENVSHADOW_ASSETS`, else
/// `assets/` in the repo (filled by scripts/fetch-assets.sh), else `../shared/assets`.
pub fn assets_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("ENVSHADOW_ASSETS") {
        return PathBuf::from(dir);
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    for candidate in [root.join("assets"), root.join("../shared/assets")] {
        if candidate.join("bunny_on_plane.glb").exists() {
            return candidate;
        }
    }
    panic!(
        "test assets not found: set ENVSHADOW_ASSETS, run scripts/fetch-assets.sh, or keep ../shared/assets beside the repo"
    );
}

/// One asset by file name.
pub fn asset(name: &str) -> PathBuf {
    let p = assets_dir().join(name);
    assert!(p.exists(), "missing test asset {}", p.display());
    p
}

use envshadow::anim::{AnimFlags, Animation};
use envshadow::scene::{Material, Scene};
use glam::{Vec2, Vec3};

/// Appends a square of side `size` in the plane y = `y`, facing +Y, to `scene`.
pub fn add_plane(scene: &mut Scene, size: f32, y: f32, material: u32) {
    let h = size / 2.0;
    let base = scene.positions.len() as u32;
    for (x, z) in [(-h, -h), (h, -h), (h, h), (-h, h)] {
        scene.positions.push(Vec3::new(x, y, z));
        scene.normals.push(Vec3::Y);
        scene.uvs.push(Vec2::ZERO);
    }
    // Counter-clockwise seen from +Y.
    scene.triangles.push([base, base + 3, base + 2]);
    scene.triangles.push([base, base + 2, base + 1]);
    scene.tri_material.extend([material; 2]);
}

/// Appends a finely tessellated UV sphere with smooth normals.
pub fn add_sphere(
    scene: &mut Scene,
    centre: Vec3,
    r: f32,
    rings: u32,
    segments: u32,
    material: u32,
) {
    let base = scene.positions.len() as u32;
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            scene.positions.push(centre + n * r);
            scene.normals.push(n);
            scene.uvs.push(Vec2::ZERO);
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let a = base + i * row + j;
            let b = a + row;
            // Outward-facing winding.
            scene.triangles.push([a, a + 1, b]);
            scene.triangles.push([a + 1, b + 1, b]);
            scene.tri_material.extend([material; 2]);
        }
    }
}

/// A scene with the given grey albedos as materials 0, 1, ….
pub fn scene_with_materials(albedos: &[f32]) -> Scene {
    Scene {
        materials: albedos
            .iter()
            .enumerate()
            .map(|(i, &a)| Material {
                name: format!("m{i}"),
                base_color: Vec3::splat(a),
                texture: None,
            })
            .collect(),
        source: "test".into(),
        ..Default::default()
    }
}

/// An animation from spec text (with `[scene] builtin = "shapes"` prepended) for tests that
/// supply their own inputs.
pub fn animation(body: &str) -> Animation {
    let text = format!("[scene]\nbuiltin = \"shapes\"\n{body}");
    Animation::parse(
        &text,
        std::path::Path::new("test.toml"),
        &AnimFlags::default(),
    )
    .expect("test spec parses")
}

/// The envshadow binary built for these tests.
pub fn bin() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_envshadow"))
}
