//! A textured box truck, written as a GLB for the tests (issue 23's spin defect): a vehicle of
//! several parts with large flat side panels — cargo box, cab, chassis, bumper, six wheels,
//! side mirrors on thin arms, a trim strip along each side — its cargo box's sides textured
//! (stripes and a block "logo" in a PNG), standing on a ground square. Metres, +Y up, the
//! truck along X, its front towards +X.

use std::path::{Path, PathBuf};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::coordinator::render_animation;
use envshadow::frame_files::FrameFiles;
use envshadow::output::stats::read_stats;
use envshadow::run::{RunOptions, Silent};

use crate::common::{Failures, Gltf};
use serde_json::json;

/// A part's triangles, vertices with normals and texture coordinates.
#[derive(Default)]
struct Mesh {
    pos: Vec<f32>,
    nrm: Vec<f32>,
    uv: Vec<f32>,
    idx: Vec<u32>,
}

impl Mesh {
    /// A quad `a b c d` (counter-clockwise seen from the side `n` points to), UVs over [0, 1]².
    fn quad(&mut self, corners: [[f32; 3]; 4], n: [f32; 3]) {
        let base = (self.pos.len() / 3) as u32;
        let uvs = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
        for (c, uv) in corners.iter().zip(uvs) {
            self.pos.extend(c);
            self.nrm.extend(n);
            self.uv.extend(uv);
        }
        self.idx
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// An axis-aligned box, its six faces each one flat quad (two triangles).
    fn cuboid(&mut self, lo: [f32; 3], hi: [f32; 3]) {
        let [x0, y0, z0] = lo;
        let [x1, y1, z1] = hi;
        // +Z, −Z (the truck's sides), +X, −X, +Y, −Y.
        self.quad(
            [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
            [0.0, 0.0, 1.0],
        );
        self.quad(
            [[x1, y0, z0], [x0, y0, z0], [x0, y1, z0], [x1, y1, z0]],
            [0.0, 0.0, -1.0],
        );
        self.quad(
            [[x1, y0, z1], [x1, y0, z0], [x1, y1, z0], [x1, y1, z1]],
            [1.0, 0.0, 0.0],
        );
        self.quad(
            [[x0, y0, z0], [x0, y0, z1], [x0, y1, z1], [x0, y1, z0]],
            [-1.0, 0.0, 0.0],
        );
        self.quad(
            [[x0, y1, z1], [x1, y1, z1], [x1, y1, z0], [x0, y1, z0]],
            [0.0, 1.0, 0.0],
        );
        self.quad(
            [[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]],
            [0.0, -1.0, 0.0],
        );
    }

    /// A wheel: a cylinder of `segments` flat facets about the Z axis through `c`, its outer
    /// faces at `c.z ± width / 2`.
    fn wheel(&mut self, c: [f32; 3], r: f32, width: f32, segments: u32) {
        let (z0, z1) = (c[2] - width / 2.0, c[2] + width / 2.0);
        let at = |k: u32| {
            let a = std::f32::consts::TAU * k as f32 / segments as f32;
            (c[0] + r * a.cos(), c[1] + r * a.sin(), a)
        };
        for k in 0..segments {
            let (xa, ya, aa) = at(k);
            let (xb, yb, ab) = at(k + 1);
            let mid = (aa + ab) / 2.0;
            self.quad(
                [[xa, ya, z1], [xa, ya, z0], [xb, yb, z0], [xb, yb, z1]],
                [mid.cos(), mid.sin(), 0.0],
            );
            // The caps as fans of flat triangles.
            for (z, nz) in [(z1, 1.0f32), (z0, -1.0)] {
                let base = (self.pos.len() / 3) as u32;
                let (p, q) = if nz > 0.0 {
                    ([xa, ya, z], [xb, yb, z])
                } else {
                    ([xb, yb, z], [xa, ya, z])
                };
                for v in [[c[0], c[1], z], p, q] {
                    self.pos.extend(v);
                    self.nrm.extend([0.0, 0.0, nz]);
                    self.uv.extend([0.5, 0.5]);
                }
                self.idx.extend([base, base + 1, base + 2]);
            }
        }
    }
}

/// The side-panel texture: horizontal stripes and a block logo, 128 × 64, sRGB PNG.
fn livery_png() -> Vec<u8> {
    let (w, h) = (128u32, 64u32);
    let mut img = image::RgbImage::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let stripe = (y / 4) % 4 == 0;
            let logo = (40..88).contains(&x) && (20..44).contains(&y) && ((x / 6 + y / 6) % 2 == 0);
            let c = if logo {
                [200, 40, 30]
            } else if stripe {
                [30, 60, 160]
            } else {
                [235, 235, 225]
            };
            img.put_pixel(x, y, image::Rgb(c));
        }
    }
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// Writes the truck as `dir/truck.glb` and returns its path.
pub fn truck_glb(dir: &Path) -> PathBuf {
    // Parts: (name, material, mesh). Material 0 is the textured livery.
    let mut parts: Vec<(&str, u32, Mesh)> = Vec::new();
    let mut cargo = Mesh::default();
    cargo.cuboid([-3.0, 0.8, -1.25], [1.5, 3.4, 1.25]);
    parts.push(("cargo box", 0, cargo));
    let mut cab = Mesh::default();
    cab.cuboid([1.6, 0.8, -1.2], [3.2, 2.8, 1.2]);
    parts.push(("cab", 1, cab));
    let mut chassis = Mesh::default();
    chassis.cuboid([-3.0, 0.55, -0.9], [3.2, 0.8, 0.9]);
    chassis.cuboid([3.2, 0.45, -1.2], [3.35, 0.8, 1.2]); // bumper
    parts.push(("chassis", 2, chassis));
    let mut trim = Mesh::default();
    for s in [-1.0f32, 1.0] {
        // A strip 15 cm high standing 3 cm proud of each side panel, and a mirror on a thin
        // arm beside the cab.
        let (z0, z1) = if s > 0.0 {
            (1.25, 1.28)
        } else {
            (-1.28, -1.25)
        };
        trim.cuboid([-3.0, 0.85, z0], [1.5, 1.0, z1]);
        let (a0, a1) = if s > 0.0 { (1.2, 1.45) } else { (-1.45, -1.2) };
        trim.cuboid([2.9, 2.2, a0], [2.95, 2.24, a1]);
        let (m0, m1) = if s > 0.0 { (1.42, 1.5) } else { (-1.5, -1.42) };
        trim.cuboid([2.85, 1.8, m0], [2.95, 2.3, m1]);
    }
    parts.push(("trim", 2, trim));
    let mut wheels = Mesh::default();
    for x in [-2.2f32, -1.1, 2.4] {
        for z in [-1.0f32, 1.0] {
            wheels.wheel([x, 0.5, z], 0.5, 0.35, 16);
        }
    }
    parts.push(("wheels", 3, wheels));
    let mut ground = Mesh::default();
    ground.quad(
        [
            [-12.0, 0.0, 12.0],
            [12.0, 0.0, 12.0],
            [12.0, 0.0, -12.0],
            [-12.0, 0.0, -12.0],
        ],
        [0.0, 1.0, 0.0],
    );
    parts.push(("ground", 4, ground));

    let mut g = Gltf::default();
    let png = livery_png();
    let image_view = g.view(&png);
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    for (k, (name, material, m)) in parts.iter().enumerate() {
        let pos = g.floats("VEC3", &m.pos);
        let nrm = g.floats("VEC3", &m.nrm);
        let uv = g.floats("VEC2", &m.uv);
        let idx = g.indices(&m.idx);
        meshes.push(json!({"name": name, "primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv},
            "indices": idx, "material": material
        }]}));
        nodes.push(json!({"name": name, "mesh": k}));
    }
    let doc = json!({
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [
            {"name": "livery", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
            {"name": "cab", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.1, 0.08, 1.0]}},
            {"name": "steel", "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.3, 0.32, 1.0]}},
            {"name": "rubber", "pbrMetallicRoughness": {"baseColorFactor": [0.04, 0.04, 0.04, 1.0]}},
            {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.45, 0.42, 0.38, 1.0]}},
        ],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{}],
        "images": [{"bufferView": image_view, "mimeType": "image/png"}],
    });
    g.write_glb(dir, "truck", doc)
}

#[test]
fn the_truck_loads_with_its_parts_and_texture() {
    let dir = tempfile::tempdir().unwrap();
    let scene = envshadow::scene::Scene::load(&truck_glb(dir.path())).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.materials.len(), 5);
    assert_eq!(scene.textures.len(), 1);
    // Cargo box, cab, chassis and bumper, six strip/arm/mirror boxes, six 16-facet wheels, the
    // ground: 12 triangles a box, 64 a wheel, 2 the ground.
    assert_eq!(scene.triangle_count(), 12 * (1 + 1 + 2 + 6) + 6 * 64 + 2);
    let (lo, hi) = scene.bounds();
    assert_eq!((lo.y, hi.y), (0.0, 3.4));
}

/// A spinning textured truck with flat side panels keeps its temporal prediction within the
/// documented 0.05 % of wrong pairs on every frame of a key-frame interval (issue 23, defect
/// 2; docs/temporal.md, "Flat panels"). Without the grazing lights marked uncertain, frame 3
/// had 0.054 % (320×240, 200 lights, grace.hdr); with them, 0.021–0.030 %.
#[test]
fn a_spinning_flat_panelled_truck_keeps_temporal_wrong_pairs_within_the_bound() {
    let dir = tempfile::tempdir().unwrap();
    let truck = truck_glb(dir.path());
    let text = format!(
        "[scene]\nfile = \"{}\"\n[environment]\nfile = \"{}\"\n[lights]\ncount = 200\n\
         [camera]\nelevation = 25.0\nazimuth = 20.0\nvfov = 40.0\n\
         [motion]\nkind = \"spin\"\nframes = 4\ndegrees_per_frame = 3.0\n\
         [render]\nwidth = 320\nheight = 240\nvalidate = true\ntemporal = true\n\
         keyframe = 4\n[output]\ndir = \"{}\"\n",
        truck.display(),
        crate::common::asset("grace.hdr").display(),
        dir.path().join("out").display()
    );
    let anim = Animation::parse(&text, Path::new("truck.toml"), &AnimFlags::default()).unwrap();
    let opts = RunOptions::default();
    render_animation(&anim, &opts, &mut FrameFiles::new(&anim, &opts), &Silent).unwrap();
    let rows = read_stats(&anim.output.dir.join("stats.csv")).unwrap();
    assert_eq!(rows.len(), 4);
    let mut failures = Failures::new();
    for r in &rows {
        failures.case(&format!("frame {}", r.frame), || {
            assert!(r.image_error.is_some(), "not validated");
            let err = r.counts.error_percent();
            assert!(err <= 0.05, "{err:.4} % wrong pairs");
            if r.frame > 0 {
                assert!(
                    r.counts.temporal_pixels > 0,
                    "no pixel predicted from the last frame"
                );
            }
        });
    }
    failures.assert_none();
}
