//! glTF materials: the metallic-roughness BRDF against analytic answers (a white furnace),
//! normal maps and tangents, texture transforms and samplers, emission and occlusion, the
//! warnings for what is not supported, and `[material]` overrides.

use crate::common::Gltf;
use crate::common::{self, Failures};

use envshadow::film::Channel;
use envshadow::frame::render_frame;

use envshadow::inputs::Inputs;

use envshadow::envmap::EnvMap;
use envshadow::lights::{LightSet, Sampler};
use envshadow::run::Silent;
use envshadow::scene::{Material, Model, Scene, Texture, TextureSlot};
use envshadow::shading_rate::ShadingRate;
use glam::{Vec2, Vec3, Vec4};
use serde_json::json;

fn uniform_env(radiance: f32) -> EnvMap {
    let (w, h) = (256, 128);
    EnvMap::from_texels(w, h, vec![Vec3::splat(radiance); w * h], "uniform").expect("valid map")
}

/// The glTF BRDF's directional albedo `∫ f(v, l) (n·l) dω` over the upper hemisphere, for a
/// white dielectric (F0 0.04) of `roughness` seen at `cos_view` from the normal: the spec's
/// formulas in f64 (h normalised, D and Vis apart; α = max(roughness², 0.001)), by a midpoint
/// rule over (θ, φ) fine enough that its own error is below 10⁻⁴.
fn furnace_albedo(roughness: f64, cos_view: f64) -> f64 {
    let a = (roughness * roughness).max(1e-3);
    let a2 = a * a;
    let nv = cos_view;
    let v = [(1.0 - nv * nv).sqrt(), 0.0, nv];
    let (nt, np) = (1500, 1500);
    let mut sum = 0.0;
    for i in 0..nt {
        let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
        let (st, ct) = theta.sin_cos();
        for j in 0..np {
            let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
            let l = [st * phi.cos(), st * phi.sin(), ct];
            let hs = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
            let len = (hs[0] * hs[0] + hs[1] * hs[1] + hs[2] * hs[2]).sqrt();
            let (nh, vh) = (hs[2] / len, (v[0] * hs[0] + v[2] * hs[2]) / len);
            let d = a2 / (std::f64::consts::PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
            let vis = 0.5
                / (ct * (nv * nv * (1.0 - a2) + a2).sqrt()
                    + nv * (ct * ct * (1.0 - a2) + a2).sqrt());
            let f = 0.04 + 0.96 * (1.0 - vh).powi(5);
            let brdf = (1.0 - f) / std::f64::consts::PI + f * d * vis;
            let dw = st
                * (std::f64::consts::FRAC_PI_2 / nt as f64)
                * (std::f64::consts::TAU / np as f64);
            sum += brdf * ct * dw;
        }
    }
    sum
}

/// A white rough dielectric (base colour 1, metallic 0, F0 0.04) on a large plane under a map
/// of radiance 1 everywhere, reduced to 400 lights: nothing shadows it, so each pixel's
/// radiance is the BRDF's directional albedo for its view — the "white furnace". Expected:
/// [`furnace_albedo`] at the pixel's own view angle. Within 1 % at every roughness, the glossy
/// ones through the prefiltered map and the lobe integrals, the rough ones over the lights.
#[test]
fn a_rough_dielectric_in_a_white_furnace_reflects_its_albedo() {
    let mut failures = Failures::new();
    for roughness in [0.15f32, 0.3, 0.5, 0.75, 1.0] {
        failures.case(&format!("roughness {roughness}"), || {
            let mut scene = Scene {
                materials: vec![Material {
                    base_color: Vec3::ONE,
                    roughness,
                    ..Material::default()
                }],
                source: "furnace".into(),
                ..Scene::default()
            };
            common::add_plane(&mut scene, 400.0, 0.0, 0);
            let env = uniform_env(1.0);
            let lights = LightSet::build(&env, 400, Sampler::Sis).unwrap();
            let inputs = Inputs::new(scene, env, lights);
            // Looking down at 60° from the vertical: n·v = 0.5 at the centre.
            let anim = common::animation(
                "[camera]\nposition = [0.0, 1.0, 1.7320508]\ntarget = [0.0, 0.0, 0.0]\nvfov = 10.0\n\
                 [motion]\nkind = \"none\"\n[render]\nwidth = 9\nheight = 9\n",
            );
            let cam = anim.camera(&inputs.scene, 0).unwrap();
            let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
            for (x, y) in [(4u32, 4u32), (0, 0), (8, 8), (0, 8)] {
                let d = cam.ray_dir(x, y);
                let cos_view = f64::from(-d.y);
                let want = furnace_albedo(f64::from(roughness), cos_view);
                let got = film.beauty((y * 9 + x) as usize);
                for c in got {
                    let err = (f64::from(c) - want).abs() / want;
                    assert!(
                        err < 0.01,
                        "pixel ({x}, {y}), n·v {cos_view:.3}: {c} vs {want:.5} ({:.2} %)",
                        100.0 * err
                    );
                }
            }
        });
    }
    failures.assert_none();
}

/// A scene of one textured, tangent-framed quad in y = 0 facing +Y (UVs u = x, v = z over
/// [−1, 1]), material `m`.
fn quad_scene(m: Material, textures: Vec<Texture>) -> Scene {
    let mut scene = Scene {
        materials: vec![m],
        textures,
        source: "quad".into(),
        ..Scene::default()
    };
    common::add_plane(&mut scene, 2.0, 0.0, 0);
    scene.uvs = scene
        .positions
        .iter()
        .map(|p| Vec2::new(p.x * 0.5 + 0.5, p.z * 0.5 + 0.5))
        .collect();
    scene.tangents = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4];
    scene
}

fn surfaces(scene: &Scene) -> Vec<envshadow::context::Surface> {
    let accel = envshadow::accel::Accel::build(&scene.positions, &scene.triangles);
    let env = uniform_env(1.0);
    let lights = LightSet::build(&env, 50, Sampler::Sis).unwrap();
    let camera = envshadow::camera::Camera::look_at(
        Vec3::new(0.3, 2.0, 1.5),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        32,
        24,
    );
    let ctx = envshadow::context::FrameContext::new(scene, &accel, camera, &lights, &env);
    let mut out = Vec::new();
    for y in 0..24 {
        for x in 0..32 {
            out.push(ctx.surface(x, y));
        }
    }
    out
}

#[test]
fn a_normal_map_with_a_flat_texture_is_no_normal_map_bit_for_bit() {
    let plain = Material {
        roughness: 0.4,
        ..Material::default()
    };
    // (0.5, 0.5, 1) is the tangent-space +Z exactly: 0.5 · 2 − 1 = 0.
    let flat = Texture::from_linear(4, 4, vec![Vec3::new(0.5, 0.5, 1.0); 16]).unwrap();
    let mapped = Material {
        normal_texture: Some(TextureSlot::plain(0)),
        normal_scale: 0.7,
        ..plain.clone()
    };
    let a = surfaces(&quad_scene(plain, vec![]));
    let b = surfaces(&quad_scene(mapped, vec![flat]));
    assert!(a.iter().filter(|s| s.hit).count() > 100);
    let bits = |s: &envshadow::context::Surface| {
        (
            s.n.to_array().map(f32::to_bits),
            s.albedo.to_array().map(f32::to_bits),
            s.hit,
        )
    };
    assert!(a.iter().zip(&b).all(|(a, b)| bits(a) == bits(b)));

    // A tilted texel does bend the normal, towards the tangent (+X) for red above 0.5.
    let tilted = Texture::from_linear(1, 1, vec![Vec3::new(0.75, 0.5, 0.9)]).unwrap();
    let mapped = Material {
        normal_texture: Some(TextureSlot::plain(0)),
        ..Material::default()
    };
    let c = surfaces(&quad_scene(mapped, vec![tilted]));
    let s = c.iter().find(|s| s.hit).unwrap();
    // The tangent is +X, the normal +Y: the bent normal leans towards +X.
    let want = Vec3::new(0.5, 0.8, 0.0).normalize();
    assert!((s.n - want).length() < 1e-5, "{} vs {want}", s.n);
}

/// A quad's glTF with a normal map and no TANGENT: the loader makes MikkTSpace tangents along
/// +U; with TANGENT given it takes the file's, moved by the node.
#[test]
fn tangents_are_generated_for_normal_maps_or_taken_from_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let png = {
        let img = image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 255]));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    };
    for with_tangents in [false, true] {
        let mut g = Gltf::default();
        // A unit quad in z = 0 facing +Z, u along +X, v down the quad (glTF's convention).
        let pos = g.floats(
            "VEC3",
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
        );
        let nrm = g.floats("VEC3", &[0.0, 0.0, 1.0].repeat(4));
        let uv = g.floats("VEC2", &[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
        let tan = g.floats("VEC4", &[0.0, 1.0, 0.0, 1.0].repeat(4));
        let idx = g.indices(&[0, 1, 2, 0, 2, 3]);
        let image = g.view(&png);
        let mut attributes = json!({"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv});
        if with_tangents {
            attributes["TANGENT"] = json!(tan);
        }
        let doc = json!({
            "scenes": [{"nodes": [0]}],
            // Turned 90° about +Z: a file tangent along +Y ends along −X.
            "nodes": [{"mesh": 0, "rotation": [0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2]}],
            "meshes": [{"primitives": [{"attributes": attributes, "indices": idx, "material": 0}]}],
            "materials": [{"normalTexture": {"index": 0}}],
            "textures": [{"source": 0}],
            "images": [{"bufferView": image, "mimeType": "image/png"}]
        });
        let path = g.write_glb(dir.path(), &format!("quad{with_tangents}"), doc);
        let scene = Scene::load(&path).unwrap();
        assert_eq!(scene.tangents.len(), scene.positions.len());
        let want = if with_tangents {
            Vec3::NEG_X
        } else {
            // +U is +X before the turn, +Y after it.
            Vec3::Y
        };
        for t in &scene.tangents {
            assert!(
                (t.truncate() - want).length() < 1e-5,
                "{with_tangents}: {t}"
            );
            assert_eq!(t.w.abs(), 1.0);
        }
    }
}

#[test]
fn texture_transforms_and_second_coordinate_sets_are_read() {
    let dir = tempfile::tempdir().unwrap();
    // 2 × 1: red | green.
    let png = {
        let mut img = image::RgbImage::new(2, 1);
        img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
        img.put_pixel(1, 0, image::Rgb([0, 255, 0]));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    };
    let mut g = Gltf::default();
    let pos = g.floats(
        "VEC3",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
    );
    let uv0 = g.floats("VEC2", &[0.25; 8]);
    // Set 1 puts u = 0.25 (red) everywhere too, but the transform's offset moves it by 0.5
    // to green; the texCoord override picks set 1 although the info says 0.
    let uv1 = g.floats("VEC2", &[0.25, 0.5].repeat(4));
    let idx = g.indices(&[0, 1, 2, 0, 2, 3]);
    let image = g.view(&png);
    let doc = json!({
        "extensionsUsed": ["KHR_texture_transform"],
        "extensionsRequired": ["KHR_texture_transform"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": pos, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1},
            "indices": idx, "material": 0
        }]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.0], "texCoord": 1}}}}}],
        "textures": [{"source": 0, "sampler": 0}],
        // Nearest: the exact texel, no blend across the edge.
        "samplers": [{"magFilter": 9728, "wrapS": 33071}],
        "images": [{"bufferView": image, "mimeType": "image/png"}]
    });
    let path = g.write_glb(dir.path(), "transformed", doc);
    let scene = Scene::load(&path).expect("KHR_texture_transform is required and supported");
    let slot = scene.materials[0].base_color_texture.unwrap();
    assert_eq!(slot.tex_coord, 1);
    assert_eq!(slot.sampler.wrap_s, envshadow::scene::Wrap::Clamp);
    assert!(slot.sampler.mag_nearest);
    assert_eq!(scene.albedo(0, (0.3, 0.3)), Vec3::new(0.0, 1.0, 0.0));
    // A rotation of 90° turns (0.25, 0.5) to (0.5, −0.25): with clamp on S, still in the
    // texture; the transform's algebra is the extension's (translation × rotation × scale).
    let t = envshadow::scene::UvTransform::new([0.1, 0.2], std::f32::consts::FRAC_PI_2, [2.0, 3.0]);
    let got = t.apply(Vec2::new(1.0, 1.0));
    // rotation [cos sin; −sin cos] of (2, 3) is (3, −2), then the offset.
    assert!((got - Vec2::new(3.1, -1.8)).length() < 1e-5, "{got}");
}

#[test]
fn unsupported_extensions_are_named_once_per_material() {
    let dir = tempfile::tempdir().unwrap();
    let mut g = Gltf::default();
    let pos = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let idx = g.indices(&[0, 1, 2]);
    let doc = json!({
        "extensionsUsed": ["KHR_materials_sheen", "KHR_materials_clearcoat", "KHR_materials_variants"],
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": pos}, "indices": idx, "material": 0},
            {"attributes": {"POSITION": pos}, "indices": idx, "material": 0}
        ]}],
        "materials": [{"name": "velvet", "extensions": {
            "KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.3, 0.1]},
            "KHR_materials_clearcoat": {"clearcoatFactor": 1.0}
        }}]
    });
    let path = g.write_glb(dir.path(), "sheen", doc);
    let scene = Scene::load(&path).unwrap();
    let about: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("velvet"))
        .collect();
    assert_eq!(about.len(), 1, "{:?}", scene.warnings);
    assert!(
        about[0].contains("KHR_materials_sheen") && about[0].contains("KHR_materials_clearcoat")
    );
    let file_level: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("KHR_materials_variants"))
        .collect();
    assert_eq!(file_level.len(), 1, "{:?}", scene.warnings);
    assert!(
        !file_level[0].contains("KHR_materials_sheen"),
        "named once: {}",
        file_level[0]
    );
}

#[test]
fn the_corpus_materials_load_as_their_authors_made_them() {
    let spheres = Scene::load(&common::asset("corpus/metal_rough_spheres.glb")).unwrap();
    let m = spheres
        .materials
        .iter()
        .find(|m| m.name == "metal0.75_rough0.25")
        .unwrap();
    assert_eq!(
        (m.metallic, m.roughness, m.model),
        (0.75, 0.25, Model::MetallicRoughness)
    );
    let golf = Scene::load(&common::asset("corpus/golf_ball.glb")).unwrap();
    assert!(golf.materials[0].normal_texture.is_some());
    assert_eq!(
        golf.tangents.len(),
        golf.positions.len(),
        "MikkTSpace tangents made"
    );
    assert!(
        golf.warnings
            .iter()
            .any(|w| w.contains("KHR_materials_clearcoat"))
    );
    // The sheen chair requires KHR_texture_transform, which is read now: what refuses it, if
    // anything, is not that.
    match Scene::load(&common::asset("corpus/sheen_chair_scene.glb")) {
        Ok(chair) => {
            let wood = chair
                .materials
                .iter()
                .find(|m| m.name == "wood Brown")
                .unwrap();
            assert!(wood.base_color_texture.unwrap().transform.is_some());
            let fabric = chair
                .materials
                .iter()
                .find(|m| m.name == "fabric Mystere Mango Velvet")
                .unwrap();
            assert_eq!(fabric.occlusion_texture.unwrap().tex_coord, 1);
        }
        Err(e) => assert!(!format!("{e:#}").contains("KHR_texture_transform"), "{e:#}"),
    }
}

/// Emission adds to a pixel as it is; occlusion scales what the lights give.
#[test]
fn emission_adds_and_occlusion_darkens_the_environment_light() {
    let render = |m: Material, textures: Vec<Texture>| {
        let scene = quad_scene(m, textures);
        let env = uniform_env(1.0);
        let lights = LightSet::build(&env, 100, Sampler::Sis).unwrap();
        let inputs = Inputs::new(scene, env, lights);
        let anim = common::animation(
            "[camera]\nposition = [0.0, 3.0, 0.001]\ntarget = [0.0, 0.0, 0.0]\nvfov = 10.0\n\
             [motion]\nkind = \"none\"\n[render]\nwidth = 4\nheight = 4\n",
        );
        render_frame(&anim, &inputs, 0, None, &Silent)
            .unwrap()
            .0
            .beauty(5)
    };
    let plain = Material {
        roughness: 0.8,
        ..Material::default()
    };
    let base = render(plain.clone(), vec![]);
    let glowing = render(
        Material {
            emissive: Vec3::new(2.0, 0.5, 0.0),
            ..plain.clone()
        },
        vec![],
    );
    for c in 0..3 {
        let want = base[c] + [2.0, 0.5, 0.0][c];
        assert!((glowing[c] - want).abs() < 1e-5, "{glowing:?} vs {base:?}");
    }
    let ao = Texture::from_linear(1, 1, vec![Vec3::new(0.25, 1.0, 1.0)]).unwrap();
    let occluded = render(
        Material {
            occlusion_texture: Some(TextureSlot::plain(0)),
            occlusion_strength: 0.5,
            ..plain
        },
        vec![ao],
    );
    // 1 + 0.5 (0.25 − 1) = 0.625.
    for c in 0..3 {
        assert!((occluded[c] - 0.625 * base[c]).abs() < 1e-5 * base[c].max(1.0));
    }
}

#[test]
fn material_overrides_replace_what_the_file_says() {
    let dir = tempfile::tempdir().unwrap();
    let spheres = common::asset("corpus/metal_rough_spheres.glb");
    let spec = |extra: &str| {
        let path = dir.path().join("spec.toml");
        std::fs::write(
            &path,
            format!(
                "[scene]\nfile = {:?}\n[lights]\ncount = 20\n[render]\nwidth = 8\nheight = 8\n{extra}",
                spheres.display()
            ),
        )
        .unwrap();
        path
    };
    let load = |extra: &str, flags: &envshadow::anim::AnimFlags| {
        let anim = envshadow::anim::Animation::load(&spec(extra), flags)?;
        Inputs::load(&anim).map(|i| i.scene)
    };
    let none = envshadow::anim::AnimFlags::default();
    let scene = load(
        "[material]\nroughness = 0.35\n[material.named.\"ground_diffuse\"]\nroughness = 0.9\nlambert = true\n",
        &none,
    )
    .unwrap();
    for m in &scene.materials {
        if m.name == "ground_diffuse" {
            assert_eq!((m.roughness, m.model), (0.9, Model::Lambert));
        } else {
            assert_eq!(
                (m.roughness, m.model),
                (0.35, Model::MetallicRoughness),
                "{}",
                m.name
            );
        }
    }
    // --clay over the spec: grey, half rough, not metal, for every material.
    let clay = envshadow::anim::AnimFlags {
        material: envshadow::anim::MaterialFlags {
            clay: true,
            lambert: false,
        },
        ..Default::default()
    };
    let scene = load("[material]\nroughness = 0.1\n", &clay).unwrap();
    for m in &scene.materials {
        assert_eq!(
            (m.base_color, m.roughness, m.metallic),
            (Vec3::splat(0.5), 0.5, 0.0)
        );
        assert!(m.plain_base_color);
    }
    // A name no material has, and a value out of range, are refused naming the key.
    let e = load("[material.named.\"nope\"]\nroughness = 0.5\n", &none).unwrap_err();
    let text = format!("{e:#}");
    assert!(
        text.contains("\"nope\"") && text.contains("metal0.00_rough0.00"),
        "{text}"
    );
    let e = load("[material]\nmetallic = 1.5\n", &none).unwrap_err();
    assert!(
        format!("{e:#}").contains("[material] metallic = 1.5"),
        "{e:#}"
    );
    let e = load("[material]\nshiny = true\n", &none).unwrap_err();
    assert!(format!("{e:#}").contains("shiny"), "{e:#}");
}

/// `∫ L(l) F D Vis (n·l) dl` over the map, by importance sampling GGX half vectors (4096
/// Hammersley points, pdf `D (n·h) / 4(v·h)`), `F = k2 + k3 (1 − v·h)⁵` of `weights`.
fn specular_by_sampling(
    env: &EnvMap,
    n: Vec3,
    v: Vec3,
    roughness: f32,
    weights: &envshadow::brdf::Weights,
) -> Vec3 {
    let a = f64::from(envshadow::brdf::alpha(roughness));
    let a2 = a * a;
    let t = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let t = (t - n * n.dot(t)).normalize();
    let b = n.cross(t);
    let nv = f64::from(n.dot(v).max(envshadow::brdf::MIN_COS_VIEW));
    let k = 4096u32;
    let mut sum = Vec3::ZERO;
    for i in 0..k {
        let u1 = (f64::from(i) + 0.5) / f64::from(k);
        let u2 = f64::from(i.reverse_bits()) / 4294967296.0;
        let ch = ((1.0 - u1) / (1.0 + (a2 - 1.0) * u1)).sqrt();
        let sh = (1.0 - ch * ch).max(0.0).sqrt();
        let phi = std::f64::consts::TAU * u2;
        let h =
            (t * (sh * phi.cos()) as f32 + b * (sh * phi.sin()) as f32 + n * ch as f32).normalize();
        let vh = f64::from(v.dot(h));
        let l = (h * (2.0 * vh) as f32 - v).normalize();
        let nl = f64::from(n.dot(l));
        if nl <= 0.0 || vh <= 0.0 {
            continue;
        }
        let vis = 0.5
            / (nl * (nv * nv * (1.0 - a2) + a2).sqrt() + nv * (nl * nl * (1.0 - a2) + a2).sqrt());
        let w = (1.0 - vh).powi(5) as f32;
        let f = weights.ks2 + weights.ks3 * w;
        sum += env.radiance(l) * f * (vis * 4.0 * vh * nl / ch) as f32;
    }
    sum / k as f32
}

/// The error of the specular estimates against the map itself, over 100 random normals and
/// views, per roughness: the sum over 400 lights (`lights`), the prefiltered map with the lobe
/// integrals (`env`, the diffuse still over the lights), and what envshadow uses (`used`: the
/// lights above `Glossy::roughness_range`'s upper end, the map below its lower end, blended
/// between) — each the relative RMS error of the luminance of a white dielectric's and a white
/// metal's reflected radiance, against the sum over every texel of the map at half its
/// resolution, or for lobes narrower than a few of its texels (roughness below 0.25) the diffuse
/// so and the specular importance-sampled over the full map (no shadows: the approximations
/// alone). docs/materials.md quotes the table; the
/// asserts hold what it says.
#[test]
fn glossy_estimates_against_the_whole_map() {
    use envshadow::brdf::{Weights, brdf};
    use envshadow::envmap::luminance;
    use envshadow::glossy::Glossy;
    use envshadow::scene::MaterialSample;
    let env = EnvMap::load(&common::asset("studio_small_03_1k.hdr")).unwrap();
    // The texels at half the resolution (0.7°: finer than the narrowest lobe measured).
    let (w, h) = (env.width / 2, env.height / 2);
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Vec3::ZERO;
            for k in 0..4 {
                sum += env.texel(2 * x + k % 2, 2 * y + k / 2);
            }
            texels.push(sum / 4.0);
        }
    }
    let small = EnvMap::from_texels(w, h, texels, "half").unwrap();
    let solid: Vec<f32> = (0..h).map(|y| small.texel_solid_angle(y)).collect();
    let dirs: Vec<Vec3> = (0..w * h).map(|i| small.texel_dir(i % w, i / w)).collect();
    let lights = LightSet::build(&env, 400, Sampler::Sis).unwrap();
    let glossy = Glossy::build(&env, &lights);
    let mut seed = 12345u32;
    let mut rnd = move || {
        seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    let mut pairs = Vec::new();
    while pairs.len() < 100 {
        let n = (Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0).normalize_or(Vec3::Y);
        let v = (Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0).normalize_or(Vec3::Y);
        if n.dot(v) > 0.1 {
            pairs.push((n, v));
        }
    }
    let hi = Glossy::roughness_bound(&lights);
    eprintln!("400 lights: the map may stand in for them below roughness {hi:.3}");
    eprintln!("| roughness | dielectric: lights | env | used | metal: lights | env | used |");
    eprintln!("|---:|---:|---:|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    for r in [
        0.03f32, 0.05, 0.075, 0.1, 0.125, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0,
    ] {
        let mut cells = Vec::new();
        for metallic in [0.0f32, 1.0] {
            let m = MaterialSample {
                lambert: false,
                metallic,
                roughness: r,
                ..MaterialSample::default()
            };
            let base = Vec3::ONE;
            let weights = Weights::new(base, &m);
            let mut err = [0.0f64; 3];
            let mut mean = 0.0f64;
            for &(n, v) in &pairs {
                let lobe = envshadow::brdf::Lobe::new(n, v, r);
                let mut truth = Vec3::ZERO;
                if r >= 0.25 {
                    for (i, d) in dirs.iter().enumerate() {
                        let c = n.dot(*d);
                        if c > 0.0 {
                            truth +=
                                small.texels[i] * brdf(n, v, *d, base, &m) * (c * solid[i / w]);
                        }
                    }
                } else {
                    // A lobe narrower than a few texels: its diffuse over the texels, its
                    // specular importance-sampled (GGX half vectors, 4096 Hammersley points)
                    // with the full map looked up bilinearly.
                    for (i, d) in dirs.iter().enumerate() {
                        let c = n.dot(*d);
                        if c > 0.0 {
                            let t = envshadow::brdf::light_terms(&lobe, *d);
                            let kd = weights.kd * (weights.a - weights.b * t.w);
                            truth += small.texels[i] * kd * (c * solid[i / w]);
                        }
                    }
                    truth += specular_by_sampling(&env, n, v, r, &weights);
                }
                // The lights' diffuse and specular over a lobe of roughness `r`.
                let over_lights = |r: f32| {
                    let lobe = envshadow::brdf::Lobe::new(n, v, r);
                    let (mut diffuse, mut spec) = (Vec3::ZERO, Vec3::ZERO);
                    for l in &lights.lights {
                        let c = n.dot(l.dir);
                        if c > 0.0 {
                            let t = envshadow::brdf::light_terms(&lobe, l.dir);
                            diffuse += l.energy * c * weights.kd * (weights.a - weights.b * t.w);
                            spec += l.energy * c * t.dv * (weights.ks2 + weights.ks3 * t.w);
                        }
                    }
                    (diffuse, spec)
                };
                let mirror = n * (2.0 * lobe.n_dot_v) - v;
                let split_sum = |r: f32| {
                    let (i2, i3) = glossy.dfg(lobe.n_dot_v, r);
                    let pf = glossy.radiance(mirror, r);
                    weights.specular(pf * i2, pf * i3)
                };
                let (diffuse, spec) = over_lights(r);
                let env_spec = split_sum(r);
                let share = glossy.split(mirror, r).lights;
                let used = diffuse + spec * share + env_spec * (1.0 - share);
                let t = f64::from(luminance(truth));
                for (k, est) in [diffuse + spec, diffuse + env_spec, used]
                    .iter()
                    .enumerate()
                {
                    err[k] += (f64::from(luminance(*est)) - t).powi(2);
                }
                mean += t;
            }
            let k = pairs.len() as f64;
            let mean = mean / k;
            cells.push(err.map(|e| (e / k).sqrt() / mean));
        }
        // The map's column only where envshadow prefilters it (up to the lights' roughness).
        let env = |e: f64| {
            if r <= hi {
                format!("{:.1} %", 100.0 * e)
            } else {
                "–".to_string()
            }
        };
        eprintln!(
            "| {r:.3} | {:.1} % | {} | {:.1} % | {:.1} % | {} | {:.1} % |",
            100.0 * cells[0][0],
            env(cells[0][1]),
            100.0 * cells[0][2],
            100.0 * cells[1][0],
            env(cells[1][1]),
            100.0 * cells[1][2]
        );
        rows.push((r, cells));
    }
    for (r, cells) in rows {
        for [lights_err, env_err, used] in cells {
            // A blend is never worse than both of what it blends.
            assert!(
                r > hi || used <= lights_err.max(env_err) * 1.02 + 0.005,
                "roughness {r}: used {used}, lights {lights_err}, env {env_err}"
            );
            // [ours] Below 0.4 the environment may stand in for sparse lights, and the split
            // sum's error on this map's small bright sources is larger than theirs (15 % for
            // the metal at 0.3; docs/materials.md measures it against Mitsuba).
            if r >= 0.4 {
                assert!(used < 0.07, "roughness {r}: {used}");
            }
            if r >= hi {
                assert_eq!(used, lights_err, "roughness {r}: the lights alone");
            }
        }
    }
}

/// Glossy lobes (the prefiltered environment and the lobe's visible share), normal maps and
/// textures give a frame whose bits do not depend on the tiles or the threads: the corpus'
/// spheres (roughness 0 to 1, metals) and the normal-mapped golf ball, at 4 samples a pixel
/// (each pixel's texture footprint), every pixel against the whole-frame, one-thread render,
/// at both shading rates.
#[test]
fn glossy_and_textured_frames_are_the_same_bits_whatever_the_tiles_and_threads() {
    use envshadow::coordinator::thread_pool;
    let mut failures = Failures::new();
    for name in ["metal_rough_spheres", "golf_ball"] {
        let file = common::asset(&format!("corpus/{name}.glb"));
        let map = common::asset("studio_small_03_1k.hdr");
        let text = format!(
            "[scene]\nfile = {:?}\n[environment]\nfile = {:?}\n[lights]\ncount = 100\n\
             [motion]\nkind = \"none\"\n[render]\nwidth = 64\nheight = 48\nspp = 4\n",
            file.display(),
            map.display()
        );
        let anim = envshadow::anim::Animation::parse(
            &text,
            std::path::Path::new("test.toml"),
            &envshadow::anim::AnimFlags::default(),
        )
        .unwrap();
        let inputs = Inputs::load(&anim).unwrap();
        let render = |rate: ShadingRate, tile: u32, threads: usize| {
            let mut a = anim.clone();
            a.render.tile = tile;
            a.render.shading_rate = rate;
            let pool = thread_pool(threads).unwrap();
            pool.install(|| render_frame(&a, &inputs, 0, None, &Silent))
                .unwrap()
                .0
        };
        for rate in ShadingRate::ALL {
            let reference = render(rate, 0, 1);
            assert!(
                reference
                    .layer(Channel::BEAUTY)
                    .unwrap()
                    .iter()
                    .any(|p| p[0] > 0.0),
                "{name}: a lit frame"
            );
            for threads in [1, 2] {
                for tile in [8, 16, 0] {
                    failures.case(
                        &format!("{name} at the {rate} rate, tile {tile} threads {threads}"),
                        || {
                            common::assert_same_film(&render(rate, tile, threads), &reference);
                        },
                    );
                }
            }
        }
    }
    failures.assert_none();
}

/// Shading once per pixel surface (the default) against once per sample, at 16 samples a
/// pixel on the corpus' glossy spheres (roughness 0 to 1, metals) and the normal-mapped golf
/// ball under the studio's lights: the same visibility, a relative RMSE under the bar issue 38
/// set (0.2 %), and the pixel rate's own brute-force reference equal to its beauty.
#[test]
fn the_pixel_rate_is_the_sample_rate_within_its_bar_on_glossy_and_normal_mapped_models() {
    let mut failures = Failures::new();
    for name in ["metal_rough_spheres", "golf_ball"] {
        failures.case(name, || {
            let file = common::asset(&format!("corpus/{name}.glb"));
            let map = common::asset("studio_small_03_1k.hdr");
            let anim = envshadow::anim::Animation::of_model(
                &file,
                Some(&map),
                &envshadow::anim::AnimFlags::default(),
            )
            .unwrap();
            let inputs = Inputs::load(&anim).unwrap();
            let render = |rate: ShadingRate| {
                let mut a = anim.clone();
                a.render.width = 96;
                a.render.height = 72;
                a.render.spp = 16;
                a.render.method = envshadow::predict::Method::BRUTE;
                a.render.validate = true;
                a.render.shading_rate = rate;
                render_frame(&a, &inputs, 0, None, &Silent).unwrap().0
            };
            let (pixel, sample) = (render(ShadingRate::Pixel), render(ShadingRate::Sample));
            let (a, b) = (
                pixel.layer(Channel::BEAUTY).unwrap(),
                sample.layer(Channel::BEAUTY).unwrap(),
            );
            let (mut se, mut sum) = (0f64, 0f64);
            for (p, q) in a.iter().zip(&b) {
                for c in 0..3 {
                    let d = f64::from(p[c] - q[c]);
                    se += d * d;
                    sum += f64::from(q[c]);
                }
            }
            let n = (a.len() * 3) as f64;
            let rel = (se / n).sqrt() / (sum / n);
            assert!(rel > 0.0, "the rates shade differently");
            assert!(rel < 0.002, "relative RMSE {:.4} %", 100.0 * rel);
            assert_eq!(
                pixel.layer(Channel::REFERENCE).unwrap(),
                a,
                "brute force's reference is its beauty at the pixel rate too"
            );
        });
    }
    failures.assert_none();
}
