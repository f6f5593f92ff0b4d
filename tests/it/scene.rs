//! Scene loading: the shared bunny assets, glTF files generated here (hierarchies, textures,
//! cameras, missing normals, non-triangle primitives, bad inputs), and the built-in shapes.

use crate::common::{self, Failures, Gltf};

use envshadow::error::{InputError, exit_code};
use envshadow::scene::{AlphaMode, Scene};
use glam::{Mat4, Vec2, Vec3};
use serde_json::{Value, json};
use std::path::Path;

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

fn assert_close(a: Vec3, b: Vec3, tol: f32, what: &str) {
    assert!(close(a, b, tol), "{what}: got {a}, expected {b}");
}

/// Geometric normal of triangle `t`.
fn geometric(scene: &Scene, t: usize) -> Vec3 {
    let [a, b, c] = scene.triangle(t);
    (b - a).cross(c - a).normalize()
}

/// Every triangle's vertex normals agree with its geometric normal (same side).
fn assert_winding_agrees(scene: &Scene) {
    for t in 0..scene.triangle_count() {
        let g = geometric(scene, t);
        for &i in &scene.triangles[t] {
            let n = scene.normals[i as usize];
            assert!(
                g.dot(n) > 0.0,
                "triangle {t}: geometric {g} vs vertex normal {n}"
            );
        }
    }
}

/// The error must be an InputError (exit code 2) whose message contains every `needle`.
fn assert_input_error(result: anyhow::Result<Scene>, needles: &[&str]) {
    let err = match result {
        Ok(_) => panic!("expected an error containing {needles:?}"),
        Err(e) => e,
    };
    eprintln!("{err:#}");
    assert_eq!(exit_code(&err), 2, "not an input error: {err:#}");
    assert!(
        err.chain()
            .any(|c| c.downcast_ref::<InputError>().is_some())
    );
    let message = format!("{err:#}");
    for needle in needles {
        assert!(
            message.contains(needle),
            "message {message:?} lacks {needle:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Shared assets.

#[test]
fn bunny_assets_load_with_documented_counts_and_bounds() {
    let cases = [
        (
            "bunny.glb",
            69_451,
            [-0.07785, 0.0, -0.06034],
            [0.07785, 0.15433, 0.06034],
        ),
        (
            "bunny_on_plane.glb",
            69_453,
            [-0.3114, 0.0, -0.3114],
            [0.3114, 0.15433, 0.3114],
        ),
        (
            "bunny_res4.glb",
            948,
            [-0.07565, 0.0, -0.05722],
            [0.07565, 0.14828, 0.05722],
        ),
    ];
    let mut failures = Failures::new();
    for (name, tris, lo, hi) in cases {
        failures.case(name, || {
            let scene = Scene::load(&common::asset(name)).unwrap();
            assert_eq!(scene.triangle_count(), tris, "{name}");
            let (min, max) = scene.bounds();
            // SOURCES.md gives 5 decimals: within half a unit of the last place, plus 1e-4.
            assert_close(min, Vec3::from_array(lo), 1e-4, name);
            assert_close(max, Vec3::from_array(hi), 1e-4, name);
            assert!(
                scene
                    .normals
                    .iter()
                    .all(|n| (n.length() - 1.0).abs() < 1e-4)
            );
            assert!(scene.camera.is_none());
            assert!(scene.warnings.is_empty());
            assert_eq!(scene.tri_material.len(), tris);
            assert!(scene.source.ends_with(name));
        });
    }
    let plane = Scene::load(&common::asset("bunny_on_plane.glb")).unwrap();
    let greys: Vec<f32> = plane.materials.iter().map(|m| m.base_color.x).collect();
    failures.check(greys.contains(&0.8) && greys.contains(&0.5), || {
        format!("bunny_on_plane.glb: greys {greys:?}")
    });
    failures.assert_none();
}

// ---------------------------------------------------------------------------------------------
// Transforms.

/// One triangle (0,0,0), (1,0,0), (0,1,1) with its true normal (0,−1,1)/√2, instanced under
/// parent(TRS) → child(matrix) → grandchild(TRS) and under a mirror.
fn hierarchy_file(g: &mut Gltf) -> Value {
    let n = Vec3::new(0.0, -1.0, 1.0).normalize();
    let pos = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0]);
    let nrm = g.floats("VEC3", &[n.x, n.y, n.z, n.x, n.y, n.z, n.x, n.y, n.z]);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    json!({
        "scene": 0,
        "scenes": [{"nodes": [0, 3]}],
        "nodes": [
            {"translation": [1.0, 2.0, 3.0], "rotation": [0.0, s, 0.0, s], "scale": [2.0, 2.0, 2.0], "children": [1]},
            // 90° about +Z (x → y, y → −x), then up by 1; column-major.
            {"matrix": [0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0], "children": [2]},
            {"translation": [1.0, 0.0, 0.0], "scale": [1.0, 3.0, 1.0], "mesh": 0},
            {"translation": [0.0, 0.0, -5.0], "scale": [-1.0, 1.0, 1.0], "mesh": 0}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm}}]}]
    })
}

fn check_hierarchy(scene: &Scene) {
    assert_eq!(scene.triangle_count(), 2);
    // Hand-computed: grandchild (x+1, 3y, z); child (−y, x, z) + (0, 1, 0); parent
    // (1, 2, 3) + 2·(z, y, −x).
    let nested = scene.triangle(0);
    assert_close(nested[0], Vec3::new(1.0, 6.0, 3.0), 1e-5, "nested p0");
    assert_close(nested[1], Vec3::new(1.0, 8.0, 3.0), 1e-5, "nested p1");
    assert_close(nested[2], Vec3::new(3.0, 6.0, 9.0), 1e-5, "nested p2");
    // The normal through the inverse transposes: (0,−1,1) → (0,−1,3) → (1,0,3) → (3,0,−1).
    let expected = Vec3::new(3.0, 0.0, -1.0).normalize();
    for &i in &scene.triangles[0] {
        assert_close(scene.normals[i as usize], expected, 1e-5, "nested normal");
    }
    assert_close(
        geometric(scene, 0),
        expected,
        1e-5,
        "nested geometric normal",
    );

    // Mirror x → −x, then z − 5: the winding must flip so (p1−p0)×(p2−p0) still faces the normal.
    let mirrored = scene.triangle(1);
    let mut got: Vec<[f32; 3]> = mirrored.iter().map(|p| p.to_array()).collect();
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut want = vec![[0.0, 0.0, -5.0], [-1.0, 0.0, -5.0], [0.0, 1.0, -4.0]];
    want.sort_by(|a, b| a.partial_cmp(b).unwrap());
    for (g, w) in got.iter().zip(&want) {
        assert_close(
            Vec3::from_array(*g),
            Vec3::from_array(*w),
            1e-5,
            "mirrored vertex",
        );
    }
    let expected = Vec3::new(0.0, -1.0, 1.0).normalize();
    for &i in &scene.triangles[1] {
        assert_close(scene.normals[i as usize], expected, 1e-5, "mirrored normal");
    }
    assert_close(
        geometric(scene, 1),
        expected,
        1e-5,
        "mirrored geometric normal",
    );
    assert_close(
        scene.shading_normal(1, (0.2, 0.3)),
        expected,
        1e-5,
        "mirrored shading",
    );
}

#[test]
fn nested_rotated_scaled_and_mirrored_nodes_gltf_and_glb() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = hierarchy_file(&mut g);
    let mut failures = Failures::new();
    for (form, path) in [
        (".gltf + .bin", g.write_gltf(dir.path(), "h", doc.clone())),
        (".glb", g.write_glb(dir.path(), "h", doc.clone())),
        (
            ".gltf with a data: URI",
            g.write_gltf_data_uri(dir.path(), "h64", doc),
        ),
    ] {
        failures.case(form, || check_hierarchy(&Scene::load(&path).unwrap()));
    }
    failures.assert_none();
}

#[test]
fn transformed_moves_normals_and_flips_mirrored_winding() {
    let shapes = Scene::shapes();
    let m = Mat4::from_scale(Vec3::new(-1.0, 2.0, 1.0)) * Mat4::from_rotation_y(0.7);
    let moved = shapes.transformed(m);
    assert_eq!(moved.triangle_count(), shapes.triangle_count());
    assert_close(
        moved.positions[10],
        m.transform_point3(shapes.positions[10]),
        1e-6,
        "moved vertex",
    );
    assert_winding_agrees(&moved);
    // Shading normals still match geometry on a flat face (the ground's first triangle).
    assert_close(
        moved.shading_normal(0, (0.3, 0.3)),
        geometric(&moved, 0),
        1e-5,
        "ground",
    );

    let mut merged = shapes.clone();
    merged.merge(moved);
    assert_eq!(merged.triangle_count(), 2 * shapes.triangle_count());
    assert_eq!(merged.materials.len(), 2 * shapes.materials.len());
    let t = shapes.triangle_count() + 5;
    assert_eq!(merged.albedo(t, (0.2, 0.2)), shapes.albedo(5, (0.2, 0.2)));
}

#[test]
fn strips_and_fans_become_consistent_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    // A unit square in z = 0 facing +Z, as a strip (0,1,2,3 zig-zag) and as a fan.
    let strip = g.floats(
        "VEC3",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
    );
    let fan = g.floats(
        "VEC3",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
    );
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": strip}, "mode": 5},
            {"attributes": {"POSITION": fan}, "mode": 6}
        ]}]
    });
    let scene = Scene::load(&g.write_gltf(dir.path(), "sf", doc)).unwrap();
    assert_eq!(scene.triangle_count(), 4);
    for t in 0..4 {
        assert_close(geometric(&scene, t), Vec3::Z, 1e-6, "strip/fan winding");
    }
    assert_winding_agrees(&scene);
    let (lo, hi) = scene.bounds();
    assert_eq!((lo, hi), (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
}

// ---------------------------------------------------------------------------------------------
// Textures.

const TEXELS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [200, 100, 50]];

fn png_2x2() -> Vec<u8> {
    let mut img = image::RgbImage::new(2, 2);
    for (k, c) in TEXELS.iter().enumerate() {
        img.put_pixel((k % 2) as u32, (k / 2) as u32, image::Rgb(*c));
    }
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// The sRGB decode written out independently of the crate's.
fn decode(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A unit quad in z = 0 with the image's top row at the top (y = 1), textured through
/// TEXCOORD_1 (TEXCOORD_0 holds decoys), base colour (0.5, 1, 0.8).
fn textured_file(g: &mut Gltf, image: Value, extra_view: Option<&[u8]>) -> Value {
    let pos = g.floats(
        "VEC3",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
    );
    let decoy = g.floats("VEC2", &[0.5; 8]);
    let uv = g.floats("VEC2", &[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
    let idx = g.indices(&[0, 1, 2, 0, 2, 3]);
    let mut image = image;
    if let Some(bytes) = extra_view {
        image["bufferView"] = json!(g.view(bytes));
    }
    json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": pos, "TEXCOORD_0": decoy, "TEXCOORD_1": uv},
            "indices": idx, "material": 0
        }]}],
        "materials": [{"name": "checker", "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 1.0, 0.8, 0.3],
            "baseColorTexture": {"index": 0, "texCoord": 1}
        }}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{}],
        "images": [image]
    })
}

/// Finds a triangle and barycentrics whose interpolated UV is `uv` (of TEXCOORD_1 where the
/// scene has it: the textured files here read that set).
fn locate(scene: &Scene, uv: Vec2) -> (usize, (f32, f32)) {
    let uvs = if scene.uvs1.is_empty() {
        &scene.uvs
    } else {
        &scene.uvs1
    };
    for t in 0..scene.triangle_count() {
        let [a, b, c] = scene.triangles[t].map(|i| uvs[i as usize]);
        let (e1, e2, d) = (b - a, c - a, uv - a);
        let det = e1.perp_dot(e2);
        let u = d.perp_dot(e2) / det;
        let v = e1.perp_dot(d) / det;
        if u >= -1e-6 && v >= -1e-6 && u + v <= 1.0 + 1e-6 {
            return (t, (u, v));
        }
    }
    panic!("uv {uv} not on the quad");
}

fn check_textured(scene: &Scene) {
    assert_eq!(scene.textures.len(), 1);
    assert_eq!(
        (scene.textures[0].width(), scene.textures[0].height()),
        (2, 2)
    );
    let raw: Vec<u8> = TEXELS.iter().flatten().copied().collect();
    let direct = envshadow::scene::Texture::from_srgb8(2, 2, &raw).unwrap();
    assert_eq!(direct.texels(), scene.textures[0].texels());
    let base = Vec3::new(0.5, 1.0, 0.8);
    for (k, c) in TEXELS.iter().enumerate() {
        let expected = base * Vec3::new(decode(c[0]), decode(c[1]), decode(c[2]));
        let centre = Vec2::new((k % 2) as f32 * 0.5 + 0.25, (k / 2) as f32 * 0.5 + 0.25);
        let (t, bary) = locate(scene, centre);
        assert_close(scene.albedo(t, bary), expected, 1e-3, &format!("texel {k}"));
        // The UV convention: texel row 0 is at the quad's top (y = 1).
        let p = {
            let [a, b, c] = scene.triangle(t);
            a * (1.0 - bary.0 - bary.1) + b * bary.0 + c * bary.1
        };
        assert_close(
            p,
            Vec3::new(centre.x, 1.0 - centre.y, 0.0),
            1e-5,
            "texel position",
        );
    }
    // Bilinear: halfway between texels 0 and 1 on the top row is their average.
    let (t, bary) = locate(scene, Vec2::new(0.5, 0.25));
    let mix = 0.5 * (Vec3::new(decode(255), 0.0, 0.0) + Vec3::new(0.0, decode(255), 0.0));
    assert_close(scene.albedo(t, bary), base * mix, 1e-3, "bilinear midpoint");
}

#[test]
fn textured_quad_external_png_embedded_glb_and_data_uri() {
    let dir = tempfile::tempdir().unwrap();
    let png = png_2x2();
    std::fs::write(dir.path().join("checker texture.png"), &png).unwrap();

    let mut g = Gltf::default();
    let doc = textured_file(&mut g, json!({"uri": "checker%20texture.png"}), None);
    check_textured(&Scene::load(&g.write_gltf(dir.path(), "tex", doc)).unwrap());

    let mut g = Gltf::default();
    let doc = textured_file(&mut g, json!({"mimeType": "image/png"}), Some(&png));
    check_textured(&Scene::load(&g.write_glb(dir.path(), "tex", doc)).unwrap());

    let mut g = Gltf::default();
    let uri = format!("data:image/png;base64,{}", common::base64(&png));
    let doc = textured_file(&mut g, json!({ "uri": uri }), None);
    check_textured(&Scene::load(&g.write_gltf_data_uri(dir.path(), "tex64", doc)).unwrap());
}

// ---------------------------------------------------------------------------------------------
// Texture filtering at the pixel footprint (issue 21): a checkered ground plane seen towards
// its horizon, where one pixel covers many squares.

/// A ground plane (y = 0, ±1000 units) with a 16 × 16 texture of 2-texel black and white
/// squares repeated once per world unit (8 squares a unit), and what sees it: a camera 1 unit
/// up looking just below the horizon, one light, a constant map.
struct CheckerGround {
    scene: Scene,
    accel: envshadow::accel::Accel,
    lights: envshadow::lights::LightSet,
    env: envshadow::envmap::EnvMap,
    camera: envshadow::camera::Camera,
}

impl CheckerGround {
    fn new() -> CheckerGround {
        use envshadow::scene::{Material, Texture};
        let rgb: Vec<u8> = (0..16 * 16)
            .flat_map(|i| {
                [if (i % 16 / 2 + i / 16 / 2) % 2 == 0 {
                    255
                } else {
                    0
                }; 3]
            })
            .collect();
        let texture = Texture::from_srgb8(16, 16, &rgb).unwrap();
        let l = 1000.0;
        let positions = vec![
            Vec3::new(-l, 0.0, -l),
            Vec3::new(l, 0.0, -l),
            Vec3::new(l, 0.0, l),
            Vec3::new(-l, 0.0, l),
        ];
        let scene = Scene {
            uvs: positions.iter().map(|p| Vec2::new(p.x, p.z)).collect(),
            normals: vec![Vec3::Y; 4],
            positions,
            triangles: vec![[0, 2, 1], [0, 3, 2]],
            tri_material: vec![0, 0],
            materials: vec![Material {
                base_color_texture: Some(envshadow::scene::TextureSlot::plain(0)),
                ..Material::lambert("checker", Vec3::ONE)
            }],
            textures: vec![texture],
            ..Scene::default()
        };
        let accel = envshadow::accel::Accel::build(&scene.positions, &scene.triangles);
        let lights = envshadow::lights::LightSet::from_lights(vec![envshadow::lights::Light {
            dir: Vec3::Y,
            energy: Vec3::ONE,
            solid_angle: 1.0,
        }]);
        let env =
            envshadow::envmap::EnvMap::from_texels(8, 4, vec![Vec3::ONE; 32], "ones").unwrap();
        let camera = envshadow::camera::Camera::look_at(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, -20.0),
            Vec3::Y,
            40.0,
            64,
            48,
        );
        CheckerGround {
            scene,
            accel,
            lights,
            env,
            camera,
        }
    }

    fn context(&self, spp: u32) -> envshadow::context::FrameContext<'_> {
        use envshadow::samples::{Filter, Samples};
        envshadow::context::FrameContext::new(
            &self.scene,
            &self.accel,
            self.camera,
            &self.lights,
            &self.env,
        )
        .with_samples(Samples::new(spp, Filter::Box, 0.0))
    }
}

/// Each pixel's albedo as the film makes it: the mean of its samples' (filters are
/// importance-sampled, so every sample weighs one). `None` where a sample missed the plane.
fn pixel_albedos(ctx: &envshadow::context::FrameContext) -> Vec<Option<Vec3>> {
    let k = ctx.samples.k;
    let (w, h) = (ctx.camera.width, ctx.camera.height);
    let mut out = Vec::new();
    for py in 0..h {
        for px in 0..w {
            let mut sum = Some(Vec3::ZERO);
            for sy in py * k..(py + 1) * k {
                for sx in px * k..(px + 1) * k {
                    let s = ctx.surface(sx, sy);
                    sum = sum.filter(|_| s.hit).map(|sum| sum + s.albedo);
                }
            }
            out.push(sum.map(|sum| sum / (k * k) as f32));
        }
    }
    out
}

#[test]
fn a_checkered_plane_at_16_spp_is_its_mean_grey_towards_the_horizon() {
    let ground = CheckerGround::new();
    let with_mips = ground.context(16);
    assert_eq!(with_mips.texture_footprint, 0.25);
    let mut without = ground.context(16);
    without.texture_footprint = 0.0;
    let (filtered, point) = (pixel_albedos(&with_mips), pixel_albedos(&without));
    // The pixels whose centre ray meets the plane at least 10 units away (the rows just below
    // the horizon): one pixel there spans over 0.15 units across the view (1.2 squares) and
    // over 1.5 units along it (12 squares), so its mean is the squares' mean, 0.5.
    let cam = &ground.camera;
    let far: Vec<usize> = (0..filtered.len())
        .filter(|&i| {
            let d = cam.ray_dir(i as u32 % cam.width, i as u32 / cam.width);
            d.y < 0.0 && 1.0 / -d.y >= 10.0
        })
        .collect();
    assert!(far.len() >= 6 * 64, "{} far pixels", far.len());
    let deviation = |v: &[Option<Vec3>]| -> (f32, f32) {
        let errs: Vec<f32> = (far.iter())
            .map(|&i| (v[i].expect("a far pixel's samples all hit") - Vec3::splat(0.5)).abs())
            .map(|e| e.max_element())
            .collect();
        let rms = (errs.iter().map(|e| e * e).sum::<f32>() / errs.len() as f32).sqrt();
        (errs.iter().copied().fold(0.0, f32::max), rms)
    };
    // Measured over the 416 far pixels: filtered, every one exactly 0.5 (every sample's
    // footprint reaches the last level); point-sampled, max 0.24 and rms 0.08 off (the 16
    // samples of a pixel land on black or white nearly at random).
    let (max, rms) = deviation(&filtered);
    assert!(
        max < 0.02,
        "with mip-maps: max |pixel − 0.5| = {max} (rms {rms})"
    );
    let (max, rms) = deviation(&point);
    assert!(
        max > 0.15 && rms > 0.04,
        "point-sampled, the far pixels should alias: max {max}, rms {rms}"
    );
    // Near the camera a sample covers less than a texel: no filtering, the same lookups.
    let last_row = (cam.height - 1) * cam.width;
    for x in 0..cam.width as usize {
        let i = last_row as usize + x;
        assert_eq!(filtered[i], point[i], "pixel {x} of the last row");
    }
}

#[test]
fn uv_density_and_footprint_width() {
    use envshadow::scene::footprint_width;
    let ground = CheckerGround::new();
    // One texture tile per world unit.
    for tri in 0..2 {
        assert!((ground.scene.uv_density(tri) - 1.0).abs() < 1e-6);
    }
    // Scaling the world by 4 leaves the UVs: a quarter of a tile per unit.
    let big = ground.scene.transformed(Mat4::from_scale(Vec3::splat(4.0)));
    assert!(
        (big.uv_density(0) - 0.25).abs() < 1e-6,
        "{}",
        big.uv_density(0)
    );
    // A stretched mapping (u × 9, v × 1) gets the geometric mean, 3.
    let mut stretched = ground.scene.clone();
    for uv in &mut stretched.uvs {
        uv.x *= 9.0;
    }
    assert!((stretched.uv_density(1) - 3.0).abs() < 1e-4);
    // A triangle with no UV area (the file had no UVs) is point-sampled.
    let mut flat = ground.scene.clone();
    flat.uvs.fill(Vec2::ZERO);
    assert_eq!(flat.uv_density(0), 0.0);
    for bary in [(0.2, 0.3), (0.7, 0.1)] {
        let a = flat.albedo_footprint(0, bary, 1e6);
        assert_eq!(a, flat.albedo(0, bary));
    }

    // Head on, the cone's width; at 60° twice that; at grazing no more than the distance.
    assert!((footprint_width(10.0, 0.01, 1.0) - 0.1).abs() < 1e-6);
    assert!((footprint_width(10.0, 0.01, -0.5) - 0.2).abs() < 1e-6);
    assert_eq!(footprint_width(10.0, 0.01, 0.0), 10.0);
    assert_eq!(footprint_width(10.0, 0.01, 1e-9), 10.0);
    for bad in [f32::NAN, f32::INFINITY, -1.0, 0.0] {
        assert_eq!(footprint_width(bad, 0.01, 1.0), 0.0, "distance {bad}");
        assert_eq!(footprint_width(10.0, bad, 1.0), 0.0, "angle {bad}");
    }
}

#[test]
fn one_sample_per_pixel_keeps_point_sampled_textures_bit_for_bit() {
    // The choice documented at `context::texture_footprint`: frames at one sample per pixel
    // (every frame before `--spp`) keep their level-0 lookups.
    let ground = CheckerGround::new();
    let ctx = ground.context(1);
    assert_eq!(ctx.texture_footprint, 0.0);
    let mut hits = 0;
    for y in 0..ground.camera.height {
        for x in 0..ground.camera.width {
            let s = ctx.surface(x, y);
            let Some(hit) = ground
                .accel
                .intersect(ground.camera.position, ctx.sample_dir(x, y))
            else {
                assert!(!s.hit);
                continue;
            };
            hits += 1;
            let expected = ground.scene.albedo(hit.tri as usize, (hit.u, hit.v));
            assert_eq!(
                s.albedo.to_array().map(f32::to_bits),
                expected.to_array().map(f32::to_bits)
            );
        }
    }
    assert!(hits > 1000, "{hits}");
}

#[test]
fn primitives_without_material_get_default_grey() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = hierarchy_file(&mut g);
    let scene = Scene::load(&g.write_gltf(dir.path(), "grey", doc)).unwrap();
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.albedo(0, (0.1, 0.1)), Vec3::splat(0.8));
    assert_eq!(scene.uvs, vec![Vec2::ZERO; 6]);
}

// ---------------------------------------------------------------------------------------------
// Cameras, normals, primitive modes.

#[test]
fn camera_from_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let pos = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let doc = json!({
        "scene": 1,
        "scenes": [{"nodes": [3]}, {"nodes": [0, 2]}],
        "nodes": [
            {"translation": [1.0, 0.0, 0.0], "children": [1]},
            // 90° about +Y: looks down −X instead of −Z.
            {"translation": [0.0, 1.0, 5.0], "rotation": [0.0, s, 0.0, s], "camera": 0},
            {"mesh": 0},
            {"camera": 1, "mesh": 0}
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01}},
            {"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.01}}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}]
    });
    let scene = Scene::load(&g.write_glb(dir.path(), "cam", doc)).unwrap();
    let cam = scene.camera.expect("camera");
    assert_close(cam.position, Vec3::new(1.0, 1.0, 5.0), 1e-5, "position");
    assert_close(cam.forward, Vec3::NEG_X, 1e-5, "forward");
    assert_close(cam.up, Vec3::Y, 1e-5, "up");
    assert!(
        (cam.vfov_deg - 0.6f32.to_degrees()).abs() < 1e-4,
        "{}",
        cam.vfov_deg
    );
}

#[test]
fn missing_normals_are_smooth_area_weighted() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    // A 2 × 2-quad grid in the plane z = 1, facing +Z.
    let mut grid = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            grid.extend_from_slice(&[i as f32 * 0.5, j as f32 * 0.5, 1.0]);
        }
    }
    let grid_pos = g.floats("VEC3", &grid);
    let mut idx = Vec::new();
    for j in 0..2u32 {
        for i in 0..2u32 {
            let a = j * 3 + i;
            idx.extend_from_slice(&[a, a + 1, a + 4, a, a + 4, a + 3]);
        }
    }
    let grid_idx = g.indices(&idx);
    // A tetrahedron with outward faces: corner normals are the area-weighted face averages.
    let tet_pos = g.floats(
        "VEC3",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
    );
    let tet_idx = g.indices(&[0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]);
    let doc = json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [5.0, 0.0, 0.0]}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": grid_pos}, "indices": grid_idx}]},
            {"primitives": [{"attributes": {"POSITION": tet_pos}, "indices": tet_idx}]}
        ]
    });
    let scene = Scene::load(&g.write_gltf(dir.path(), "smooth", doc)).unwrap();
    assert_eq!(scene.triangle_count(), 8 + 4);
    for i in 0..9 {
        assert_close(scene.normals[i], Vec3::Z, 1e-6, "grid normal");
    }
    // Vertex 0: three right-angle faces of equal area facing −X, −Y, −Z. Vertex 1: −Z and −Y
    // faces (|cross| = 1 each) plus the slanted face (cross = (1, 1, 1)) sum to (1, 0, 0).
    let tet = &scene.normals[9..13];
    assert_close(tet[0], -Vec3::ONE.normalize(), 1e-6, "tet corner 0");
    assert_close(tet[1], Vec3::X, 1e-6, "tet corner 1");
    assert_close(tet[2], Vec3::Y, 1e-6, "tet corner 2");
    assert_close(tet[3], Vec3::Z, 1e-6, "tet corner 3");
    // The faces keep their outward winding (a tetrahedron's corner normals may be at 90° to
    // a face, so compare faces with their own normals here).
    assert_close(geometric(&scene, 8), Vec3::NEG_Z, 1e-6, "tet face 0");
    assert_close(
        geometric(&scene, 11),
        Vec3::ONE.normalize(),
        1e-6,
        "tet face 3",
    );
    for t in 0..8 {
        assert_close(geometric(&scene, t), Vec3::Z, 1e-6, "grid face");
    }
}

#[test]
fn non_triangle_primitives_are_skipped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let pos = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": pos}, "mode": 0},
            {"attributes": {"POSITION": pos}, "mode": 1},
            {"attributes": {"POSITION": pos}}
        ]}]
    });
    let scene = Scene::load(&g.write_gltf(dir.path(), "modes", doc)).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
    assert!(scene.warnings[0].contains("modes.gltf"));
    assert!(
        scene.warnings[0].contains("mesh 0 primitive 0: mode Points is not triangles, skipped")
    );
    assert!(scene.warnings[1].contains("mesh 0 primitive 1: mode Lines is not triangles"));
}

// ---------------------------------------------------------------------------------------------
// Bad inputs.

/// A one-triangle file with the given attribute and index data.
fn single(
    g: &mut Gltf,
    positions: &[f32],
    normals: Option<&[f32]>,
    indices: Option<&[u32]>,
) -> Value {
    let pos = g.floats("VEC3", positions);
    let mut attributes = json!({ "POSITION": pos });
    if let Some(n) = normals {
        attributes["NORMAL"] = json!(g.floats("VEC3", n));
    }
    let mut primitive = json!({ "attributes": attributes });
    if let Some(i) = indices {
        primitive["indices"] = json!(g.indices(i));
    }
    json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}, primitive]}]
    })
}

const TRI: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

#[test]
fn missing_file() {
    let dir = tempfile::tempdir().unwrap();
    assert_input_error(
        Scene::load(&dir.path().join("nope.glb")),
        &["nope.glb", "cannot read"],
    );
}

#[test]
fn malformed_json() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("broken.gltf");
    std::fs::write(
        &path,
        b"{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ {",
    )
    .unwrap();
    assert_input_error(Scene::load(&path), &["broken.gltf", "not a valid glTF"]);
}

#[test]
fn truncated_glb() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(common::asset("bunny_res4.glb")).unwrap();
    let path = dir.path().join("half.glb");
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    assert_input_error(Scene::load(&path), &["half.glb", "truncated GLB"]);
}

#[test]
fn missing_external_buffer() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = single(&mut g, &TRI, None, None);
    let path = g.write_gltf(dir.path(), "lost", doc);
    std::fs::remove_file(dir.path().join("lost.bin")).unwrap();
    assert_input_error(Scene::load(&path), &["lost.gltf", "buffer 0", "lost.bin"]);
}

#[test]
fn index_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = single(&mut g, &TRI, None, Some(&[0, 1, 7]));
    let path = g.write_glb(dir.path(), "oob", doc);
    assert_input_error(
        Scene::load(&path),
        &[
            "oob.glb",
            "mesh 0 primitive 1",
            "accessor 1",
            "index 7 out of range (3 vertices)",
        ],
    );
}

#[test]
fn nan_position() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let mut bad = TRI;
    bad[4] = f32::NAN;
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": g.floats("VEC3", &TRI)}},
                                    {"attributes": {"POSITION": g.floats("VEC3", &bad)}}]}]
    });
    let path = g.write_gltf(dir.path(), "nan", doc);
    assert_input_error(
        Scene::load(&path),
        &[
            "nan.gltf",
            "mesh 0 primitive 1",
            "accessor 1",
            "vertex 1 is not finite",
        ],
    );
}

#[test]
fn attribute_count_mismatch() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = single(&mut g, &TRI, Some(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]), None);
    let path = g.write_gltf(dir.path(), "count", doc);
    assert_input_error(
        Scene::load(&path),
        &[
            "count.gltf",
            "mesh 0 primitive 1",
            "accessor 1 (NORMAL) has 2 elements",
            "(POSITION) has 3",
        ],
    );
}

#[test]
fn no_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let pos = g.floats("VEC3", &TRI);
    let doc = json!({
        "scenes": [{"nodes": [0, 1]}, {"nodes": [2]}],
        "nodes": [{"mesh": 0}, {"translation": [1.0, 0.0, 0.0]}, {"mesh": 1}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "mode": 0}]},
                   {"primitives": [{"attributes": {"POSITION": pos}}]}]
    });
    // Scene 0 is the one taken (no `scene`): its only mesh is points.
    let path = g.write_gltf(dir.path(), "empty", doc);
    assert_input_error(
        Scene::load(&path),
        &["empty.gltf", "no triangles in the default scene"],
    );
}

#[test]
fn byte_stride_smaller_than_element_is_refused_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = single(&mut g, &TRI, None, None);
    g.views[0]["byteStride"] = json!(4);
    let path = g.write_glb(dir.path(), "stride", doc);
    assert_input_error(
        Scene::load(&path),
        &["stride.glb", "accessor 0", "byteStride 4"],
    );
}

/// Loading must give a scene or an input error, never a panic or an internal error: a case
/// of `failures`, so every input that breaks the rule is listed.
fn load_survives(failures: &mut Failures, path: &Path, what: &str) {
    failures.case(what, || {
        if let Err(e) = Scene::load(path) {
            assert_eq!(exit_code(&e), 2, "not an input error: {e:#}");
        }
    });
}

#[test]
fn hostile_field_values_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut base = Gltf::default();
    let png = png_2x2();
    let doc = textured_file(&mut base, json!({"mimeType": "image/png"}), Some(&png));
    let numbers: [u64; 12] = [0, 1, 2, 3, 4, 7, 12, 255, 4096, 65_535, 1 << 32, 1 << 62];
    let mut failures = Failures::new();
    let mut case = 0;
    let mut run = |g: &Gltf, what: String| {
        case += 1;
        let path = g.write_glb(dir.path(), &format!("case{case}"), doc.clone());
        load_survives(&mut failures, &path, &what);
    };
    for a in 0..base.accessors.len() {
        for field in ["count", "byteOffset"] {
            for &n in &numbers {
                let mut g = base.clone();
                g.accessors[a][field] = json!(n);
                run(&g, format!("accessor {a} {field} = {n}"));
            }
        }
        for ty in [5120, 5121, 5122, 5123, 5125, 5126] {
            let mut g = base.clone();
            g.accessors[a]["componentType"] = json!(ty);
            run(&g, format!("accessor {a} componentType {ty}"));
        }
        for ty in ["SCALAR", "VEC2", "VEC3", "VEC4", "MAT4"] {
            let mut g = base.clone();
            g.accessors[a]["type"] = json!(ty);
            run(&g, format!("accessor {a} type {ty}"));
        }
        let mut g = base.clone();
        g.accessors[a]["normalized"] = json!(true);
        g.accessors[a]["componentType"] = json!(5121);
        run(&g, format!("accessor {a} normalized bytes"));
        let mut g = base.clone();
        g.accessors[a].as_object_mut().unwrap().remove("bufferView");
        run(&g, format!("accessor {a} without view"));
        for (count, index) in [(1u64, 0u64), (1, 99), (3, 2), (1 << 20, 0)] {
            let mut g = base.clone();
            g.accessors[a]["sparse"] = json!({
                "count": count,
                "indices": {"bufferView": 0, "componentType": 5125, "byteOffset": index},
                "values": {"bufferView": 1}
            });
            run(&g, format!("accessor {a} sparse {count} at {index}"));
        }
    }
    for v in 0..base.views.len() {
        for field in ["byteOffset", "byteLength", "byteStride"] {
            for &n in &numbers {
                let mut g = base.clone();
                g.views[v][field] = json!(n);
                run(&g, format!("view {v} {field} = {n}"));
            }
        }
    }
    failures.assert_none();
}

#[test]
fn flipped_bytes_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let original = std::fs::read(common::asset("bunny_res4.glb")).unwrap();
    // A fixed LCG: the same mutations every run.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        (state >> 33) as usize
    };
    let path = dir.path().join("flipped.glb");
    let mut failures = Failures::new();
    for round in 0..150 {
        let mut bytes = original.clone();
        for _ in 0..1 + round % 4 {
            let at = next() % bytes.len();
            bytes[at] = (next() & 0xff) as u8;
        }
        if round % 10 == 0 {
            bytes.truncate(next() % bytes.len());
        }
        std::fs::write(&path, &bytes).unwrap();
        load_survives(&mut failures, &path, &format!("round {round}"));
    }

    // Digits changed in the JSON of a small file keep it parseable and reach deeper checks.
    let mut g = Gltf::default();
    let doc = hierarchy_file(&mut g);
    let gltf_path = g.write_gltf(dir.path(), "digits", doc);
    let text = std::fs::read(&gltf_path).unwrap();
    let digits: Vec<usize> = (0..text.len())
        .filter(|&i| text[i].is_ascii_digit())
        .collect();
    for round in 0..DIGIT_ROUNDS {
        let mut bytes = text.clone();
        for _ in 0..1 + round % 3 {
            bytes[digits[next() % digits.len()]] = b'0' + (next() % 10) as u8;
        }
        std::fs::write(&gltf_path, &bytes).unwrap();
        load_survives(&mut failures, &gltf_path, &format!("digit round {round}"));
    }
    failures.assert_none();
}

const DIGIT_ROUNDS: usize = 300;

// ---------------------------------------------------------------------------------------------
// Built-in shapes.

#[test]
fn shapes_scene_is_sound_and_deterministic() {
    let scene = Scene::shapes();
    assert_eq!(scene.source, "builtin:shapes");
    let n = scene.triangle_count();
    assert!((5_000..=30_000).contains(&n), "{n} triangles");
    assert!(scene.materials.len() >= 6);
    assert_eq!(scene.tri_material.len(), n);
    assert_eq!(scene.normals.len(), scene.positions.len());
    assert_eq!(scene.uvs.len(), scene.positions.len());
    assert!(scene.positions.iter().all(|p| p.is_finite()));
    assert!(
        scene
            .normals
            .iter()
            .all(|n| (n.length() - 1.0).abs() < 1e-5)
    );
    let (lo, hi) = scene.bounds();
    assert!(lo.cmpge(Vec3::new(-5.0, 0.0, -5.0) - 1e-5).all(), "{lo}");
    assert!(hi.cmple(Vec3::new(5.0, 1.2, 5.0) + 1e-5).all(), "{hi}");
    assert!((hi.y - 1.2).abs() < 1e-5 && lo.y.abs() < 1e-6);
    assert_winding_agrees(&scene);
    // Distinct colours per object.
    for (i, a) in scene.materials.iter().enumerate() {
        for b in &scene.materials[i + 1..] {
            assert!(a.base_color != b.base_color, "{} and {}", a.name, b.name);
        }
    }
    // Objects (everything but the ground) stay inside the documented area.
    let ground = scene
        .materials
        .iter()
        .position(|m| m.name == "ground")
        .unwrap() as u32;
    for (t, tri) in scene.triangles.iter().enumerate() {
        if scene.tri_material[t] == ground {
            continue;
        }
        for &i in tri {
            let p = scene.positions[i as usize];
            assert!(
                p.x.abs() <= 1.83 && p.z.abs() <= 1.6 && p.y >= -1e-6 && p.y <= 1.2 + 1e-5,
                "{p}"
            );
        }
    }
    let again = Scene::shapes();
    assert_eq!(scene.positions, again.positions);
    assert_eq!(scene.normals, again.normals);
    assert_eq!(scene.triangles, again.triangles);
    assert_eq!(scene.tri_material, again.tri_material);
}

/// Issue 20, item 11: the posed-scene fuzz target's first seeds found that a finite pivot far
/// from the scene turned its vertices to infinity, and the BVH build over the posed copy panicked
/// (exit 101). Such a spin is refused before any file is written; a far pivot that stays within
/// range still renders.
#[test]
fn a_spin_that_would_turn_the_scene_to_infinity_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let render = |pivot: &str| {
        let spec = dir.path().join("spin.toml");
        std::fs::write(
            &spec,
            format!(
                "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 4\n[camera]\ntarget = [0.0, 0.5, 0.0]\ndistance = 6.0\n[motion]\nkind = \"spin\"\nframes = 3\ndegrees_per_frame = 90.0\npivot = {pivot}\n[render]\nwidth = 16\nheight = 12\n[output]\ndir = \"{}\"\n",
                out.display()
            ),
        )
        .unwrap();
        common::bin()
            .arg("render")
            .arg(&spec)
            .args(["--no-report", "-q"])
            .output()
            .unwrap()
    };
    let o = render("[3e38, 0.0, 0.0]");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for needle in [
        "spin.toml: [motion] kind = \"spin\"",
        "about its pivot (coordinates up to 3.0e38) could overflow",
    ] {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    assert!(common::file_names(&out).is_empty());
    let o = render("[1e6, 0.0, 1e6]");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

// ---------------------------------------------------------------------------------------------
// Alpha coverage (issue 24, item 3).

/// A 2 × 2 RGBA PNG: grey texels with alphas 0, 64, 128 and 255, row by row.
fn rgba_png_2x2() -> Vec<u8> {
    let mut img = image::RgbaImage::new(2, 2);
    for (k, a) in [0u8, 64, 128, 255].iter().enumerate() {
        img.put_pixel(
            (k % 2) as u32,
            (k / 2) as u32,
            image::Rgba([200, 200, 200, *a]),
        );
    }
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// Two unit quads side by side in z = 0, the first with material 0, the second with material
/// 1, both UV-mapped to the whole image (row 0 at the top) and with a COLOR_0 whose alpha is
/// 1 on the left edge and 0.5 on the right (of each quad); `materials` as given.
fn two_quads(g: &mut Gltf, png: &[u8], materials: Value) -> Value {
    let mut primitives = Vec::new();
    for q in 0..2 {
        let x = q as f32 * 2.0;
        let pos = g.floats(
            "VEC3",
            &[
                x,
                0.0,
                0.0,
                x + 1.0,
                0.0,
                0.0,
                x + 1.0,
                1.0,
                0.0,
                x,
                1.0,
                0.0,
            ],
        );
        let uv = g.floats("VEC2", &[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
        let color = g.floats(
            "VEC4",
            &[
                1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 1.0,
            ],
        );
        let idx = g.indices(&[0, 1, 2, 0, 2, 3]);
        primitives.push(json!({
            "attributes": {"POSITION": pos, "TEXCOORD_0": uv, "COLOR_0": color},
            "indices": idx, "material": q
        }));
    }
    let view = g.view(png);
    json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": primitives}],
        "materials": materials,
        "textures": [{"source": 0}],
        "images": [{"bufferView": view, "mimeType": "image/png"}]
    })
}

#[test]
fn masked_materials_read_texture_factor_and_vertex_alpha() {
    // Material 0 is MASK (cutoff 0.4, factor alpha 0.5), material 1 OPAQUE, over the same RGBA
    // image: the mask reads factor × texture alpha × COLOR_0 alpha and is cut out; the opaque
    // quad is not, and the image's colour is decoded as it would be without alpha.
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = two_quads(
        &mut g,
        &rgba_png_2x2(),
        json!([
            {"name": "leaf", "alphaMode": "MASK", "alphaCutoff": 0.4,
             "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5], "baseColorTexture": {"index": 0}}},
            {"name": "wall", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}
        ]),
    );
    let scene = Scene::load(&g.write_glb(dir.path(), "alpha", doc)).unwrap();
    assert_eq!(scene.textures.len(), 1, "one image, decoded once");
    assert!(scene.textures[0].has_alpha(), "its alpha kept with it");
    let leaf = &scene.materials[scene.tri_material[0] as usize];
    assert_eq!(leaf.alpha_mode, AlphaMode::Mask { cutoff: 0.4 });
    assert_eq!(leaf.base_alpha, 0.5);
    assert_eq!(leaf.base_color_texture.map(|s| s.texture), Some(0));
    let wall = &scene.materials[scene.tri_material[2] as usize];
    assert_eq!(wall.alpha_mode, AlphaMode::Opaque);
    // Texture alpha at the texel centres, times the factor, times COLOR_0 (1 at x = 0, 0.5 at
    // x = 1, linear between).
    let png_alpha = [0.0, 64.0 / 255.0, 128.0 / 255.0, 1.0];
    for (k, a) in png_alpha.iter().enumerate() {
        let centre = Vec2::new((k % 2) as f32 * 0.5 + 0.25, (k / 2) as f32 * 0.5 + 0.25);
        let (t, bary) = locate(&scene, centre);
        let vertex = 1.0 - 0.5 * centre.x;
        let want = 0.5 * a * vertex;
        let got = scene.alpha(t, bary);
        assert!(
            (got - want).abs() < 1e-5,
            "texel {k}: alpha {got}, want {want}"
        );
    }
    let cut = scene.cut_out_triangles();
    assert_eq!(cut, vec![true, true, false, false]);
    // The colour is the image's whether or not its alpha is kept.
    let rgb = envshadow::scene::Texture::decode(&rgba_png_2x2()).unwrap();
    assert_eq!(rgb.texels(), scene.textures[0].texels());
    // Opaque only: nothing kept, nothing cut out.
    let mut g = Gltf::default();
    let doc = two_quads(
        &mut g,
        &rgba_png_2x2(),
        json!([
            {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.2]}}
        ]),
    );
    let scene = Scene::load(&g.write_glb(dir.path(), "opaque", doc)).unwrap();
    assert!(
        scene
            .materials
            .iter()
            .all(|m| m.alpha_mode == AlphaMode::Opaque)
    );
    assert!(scene.cut_out_triangles().is_empty());
}

#[test]
fn blend_materials_are_named_once_in_a_warning_and_bad_cutoffs_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let doc = two_quads(
        &mut g,
        &rgba_png_2x2(),
        json!([
            {"name": "glass", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3]}},
            {"name": "glass2", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}
        ]),
    );
    let mut doc2 = doc.clone();
    // Both quads use "glass": one warning for it.
    doc2["meshes"][0]["primitives"][1]["material"] = json!(0);
    let scene = Scene::load(&g.write_glb(dir.path(), "blend", doc2)).unwrap();
    let about: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("BLEND"))
        .collect();
    assert_eq!(about.len(), 1, "{:?}", scene.warnings);
    assert!(
        about[0].contains("'glass'") && about[0].contains("0.5"),
        "{}",
        about[0]
    );
    assert_eq!(scene.materials[0].alpha_mode, AlphaMode::Blend);
    assert_eq!(scene.cut_out_triangles(), vec![true; 4]);
    let scene = Scene::load(&g.write_glb(dir.path(), "blend2", doc.clone())).unwrap();
    let names: Vec<bool> = ["'glass'", "'glass2'"]
        .iter()
        .map(|n| scene.warnings.iter().filter(|w| w.contains(n)).count() == 1)
        .collect();
    assert_eq!(names, vec![true, true], "{:?}", scene.warnings);
    // A negative cutoff is refused, naming the material.
    let mut bad = doc;
    bad["materials"][0] = json!({"alphaMode": "MASK", "alphaCutoff": -0.5});
    let e = Scene::load(&g.write_glb(dir.path(), "bad", bad)).unwrap_err();
    assert_eq!(exit_code(&e), envshadow::error::exit::BAD_INPUT, "{e:#}");
    assert!(
        format!("{e:#}").contains("material 0: alphaCutoff -0.5"),
        "{e:#}"
    );
}

// ---------------------------------------------------------------------------------------------
// Lights in the file (KHR_lights_punctual, issue 24, item 4).

/// A triangle (so the file has geometry) and `lights`, each placed by its own node: node k
/// has `nodes[k]`'s transform and children.
fn with_lights(g: &mut Gltf, lights: Value, nodes: Value) -> Value {
    let pos = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let mut nodes = nodes;
    let mesh_node = nodes.as_array().unwrap().len();
    nodes.as_array_mut().unwrap().push(json!({"mesh": 0}));
    let roots: Vec<usize> = (0..=mesh_node)
        .filter(|k| {
            !nodes.as_array().unwrap().iter().any(|n| {
                n["children"]
                    .as_array()
                    .is_some_and(|c| c.contains(&json!(k)))
            })
        })
        .collect();
    json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensionsRequired": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scenes": [{"nodes": roots}],
        "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}]
    })
}

#[test]
fn scene_lights_take_their_nodes_world_position_and_direction() {
    // A sun, a point light under a scaled, translated parent, and a spot turned 90° about +X
    // (its −Z then points down −Y): world positions and directions, names, defaults.
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let doc = with_lights(
        &mut g,
        json!([
            {"type": "directional", "name": "Sun", "intensity": 6830, "color": [1, 0.9, 0.8]},
            {"type": "point", "intensity": 100, "range": 7},
            {"type": "spot", "name": "Spot", "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}
        ]),
        json!([
            {"extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [1, 2, 3], "scale": [2, 2, 2], "children": [2]},
            {"translation": [0.5, 0, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"translation": [0, 4, 0], "rotation": [-s, 0, 0, s],
             "extensions": {"KHR_lights_punctual": {"light": 2}}}
        ]),
    );
    let scene = Scene::load(&g.write_glb(dir.path(), "lights", doc)).unwrap();
    use envshadow::scene::SceneLightKind;
    assert_eq!(scene.lights.len(), 3, "{:?}", scene.lights);
    let (sun, point, spot) = (&scene.lights[0], &scene.lights[1], &scene.lights[2]);
    assert_eq!(
        (sun.name.as_str(), sun.kind),
        ("Sun", SceneLightKind::Directional)
    );
    assert_close(sun.direction, -Vec3::Z, 1e-6, "sun direction");
    assert_eq!(
        (sun.intensity, sun.color),
        (6830.0, Vec3::new(1.0, 0.9, 0.8))
    );
    assert_eq!(
        (point.name.as_str(), point.kind),
        ("light 1", SceneLightKind::Point)
    );
    assert_close(
        point.position,
        Vec3::new(2.0, 2.0, 3.0),
        1e-6,
        "point position",
    );
    assert_eq!(
        (point.intensity, point.range, point.color),
        (100.0, Some(7.0), Vec3::ONE)
    );
    assert_eq!(
        spot.kind,
        SceneLightKind::Spot {
            inner: 0.2,
            outer: 0.5
        }
    );
    assert_eq!(spot.intensity, 1.0, "the extension's default");
    assert_close(
        spot.position,
        Vec3::new(0.0, 4.0, 0.0),
        1e-6,
        "spot position",
    );
    assert_close(spot.direction, -Vec3::Y, 1e-6, "spot direction");
}

#[test]
fn scene_lights_the_extension_forbids_are_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (json!({"type": "point", "intensity": -1}), "intensity -1"),
        (json!({"type": "point", "color": [1, -0.5, 0]}), "color"),
        (json!({"type": "point", "range": 0}), "range 0"),
        (
            json!({"type": "spot", "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.5}}),
            "spot cone angles",
        ),
        (
            json!({"type": "spot", "spot": {"outerConeAngle": 2.0}}),
            "spot cone angles",
        ),
    ];
    let mut failures = Failures::new();
    for (k, (light, needle)) in cases.into_iter().enumerate() {
        failures.case(needle, || {
            let mut g = Gltf::default();
            let doc = with_lights(
                &mut g,
                json!([light]),
                json!([{"extensions": {"KHR_lights_punctual": {"light": 0}}}]),
            );
            let e = Scene::load(&g.write_glb(dir.path(), &format!("bad{k}"), doc)).unwrap_err();
            assert_eq!(exit_code(&e), envshadow::error::exit::BAD_INPUT, "{e:#}");
            let msg = format!("{e:#}");
            assert!(
                msg.contains("node 0: light 0 ('light 0')") && msg.contains(needle),
                "{msg}"
            );
        });
    }
    // A node naming a light the file does not have: refused, not a panic.
    let mut g = Gltf::default();
    let doc = with_lights(
        &mut g,
        json!([{"type": "point"}]),
        json!([{"extensions": {"KHR_lights_punctual": {"light": 3}}}]),
    );
    let e = Scene::load(&g.write_glb(dir.path(), "dangling", doc)).unwrap_err();
    assert_eq!(exit_code(&e), envshadow::error::exit::BAD_INPUT, "{e:#}");
    failures.assert_none();
}
