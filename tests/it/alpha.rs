//! Alpha coverage (issue 24, item 3): `MASK` cut-outs stop camera and shadow rays only where
//! alpha reaches the cutoff, the predictors and `--validate` see the same cut-out geometry as
//! brute force, and `BLEND` is coverage for camera rays.

use crate::common::{self, Failures};

use envshadow::coordinator::thread_pool;

use envshadow::frame::render_frame;

use envshadow::inputs::Inputs;

use envshadow::envmap::EnvMap;
use envshadow::film::{Channel, Film};
use envshadow::lights::{Light, LightSet, Sampler};
use envshadow::predict::Method;
use envshadow::run::Silent;
use envshadow::scene::{AlphaMode, Material, Scene, Texture, TextureSlot};
use glam::{Vec2, Vec3};

/// Alpha texels of the test masks (a side).
const SIDE: usize = 512;

/// A disc of radius `r` (in UV units) centred in the texture: alpha 1 inside, 0 outside.
fn disc(r: f32) -> Vec<f32> {
    (0..SIDE * SIDE)
        .map(|i| {
            let (x, y) = (i % SIDE, i / SIDE);
            let u = (x as f32 + 0.5) / SIDE as f32 - 0.5;
            let v = (y as f32 + 0.5) / SIDE as f32 - 0.5;
            if u * u + v * v < r * r { 1.0 } else { 0.0 }
        })
        .collect()
}

/// An 8 × 8 checkerboard of alpha 0.9 and 0.1 squares.
fn checker() -> Vec<f32> {
    (0..SIDE * SIDE)
        .map(|i| {
            let (x, y) = (i % SIDE * 8 / SIDE, i / SIDE * 8 / SIDE);
            if (x + y) % 2 == 0 { 0.9 } else { 0.1 }
        })
        .collect()
}

/// A ground plane (material 0) and, 1 unit above the origin, a horizontal 1 × 1 panel
/// (material 1, UV = (x + ½, z + ½)) whose coverage is `mode` over the alpha texels `alpha`.
fn panel_scene(alpha: Vec<f32>, mode: AlphaMode) -> Scene {
    let mut scene = common::scene_with_materials(&[0.5, 0.8]);
    // A white base colour texture carrying the alpha.
    let white = vec![Vec3::ONE; SIDE * SIDE];
    let texture = Texture::from_linear_alpha(SIDE, SIDE, white, alpha).unwrap();
    scene.materials[1].base_color_texture = Some(TextureSlot::plain(scene.textures.len()));
    scene.textures.push(texture);
    scene.materials[1].alpha_mode = mode;
    common::add_plane(&mut scene, 40.0, 0.0, 0);
    let base = scene.positions.len() as u32;
    for (x, z) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
        scene.positions.push(Vec3::new(x, 1.0, z));
        scene.normals.push(Vec3::Y);
        scene.uvs.push(Vec2::new(x + 0.5, z + 0.5));
    }
    scene.triangles.push([base, base + 3, base + 2]);
    scene.triangles.push([base, base + 2, base + 1]);
    scene.tri_material.extend([1; 2]);
    scene
}

fn black_env() -> EnvMap {
    EnvMap::from_texels(16, 8, vec![Vec3::ZERO; 128], "black").unwrap()
}

/// The light 45° up towards +X: the panel's shadow falls on the ground around (−1, 0, 0), the
/// panel's own shape moved, its area unchanged (the panel is parallel to the ground).
fn slanted_light() -> LightSet {
    LightSet::from_lights(vec![Light {
        dir: Vec3::new(1.0, 1.0, 0.0).normalize(),
        energy: Vec3::ONE,
        solid_angle: 1e-3,
    }])
}

/// A 300 × 300 view straight down onto the shadow from 10 units up, 1.6 units across.
fn view_of_the_shadow(method: Method) -> envshadow::anim::Animation {
    let mut anim = common::animation(
        "[camera]\nposition = [-1.0, 10.0, 0.0]\ntarget = [-1.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
         vfov = 9.15\n[motion]\nkind = \"none\"\n[render]\nwidth = 300\nheight = 300\ntile = 32\n",
    );
    anim.render.method = method;
    anim
}

/// The ground area, in square units, of the pixels whose one light is blocked.
fn shadow_area(film: &Film, anim: &envshadow::anim::Animation, inputs: &Inputs) -> f64 {
    let cam = anim.camera(&inputs.scene, 0).unwrap();
    let ground = |x: u32, y: u32| {
        let d = cam.ray_dir(x, y);
        cam.position + d * (-cam.position.y / d.y)
    };
    // Looking straight down at a plane, every pixel covers the same square of ground.
    let side = (ground(1, 0) - ground(0, 0)).length() as f64;
    let blocked = film
        .plane(Channel::Visible)
        .unwrap()
        .iter()
        .filter(|&&v| v < 0.5)
        .count() as f64;
    blocked * side * side
}

/// The area the mask covers on the 1 × 1 panel: its texels at or above the cutoff.
fn mask_area(alpha: &[f32], cutoff: f32) -> f64 {
    alpha.iter().filter(|&&a| a >= cutoff).count() as f64 / alpha.len() as f64
}

#[test]
fn alpha_cutoff_shadow_area_on_a_plane_matches_the_masks_area() {
    // A disc-alpha and a checkerboard-alpha panel under one slanted light: the shadow's area
    // on the ground is the mask's, within 1 %, for brute force and the predicting methods;
    // the same panel opaque shadows its whole square (or the masks would prove nothing).
    let r = 0.3;
    let cases = [
        ("disc", disc(r), std::f64::consts::PI * f64::from(r * r)),
        ("checker", checker(), 0.5),
        ("opaque", disc(r), 1.0),
    ];
    let mut failures = Failures::new();
    for (name, alpha, analytic) in cases {
        let mode = if name == "opaque" {
            AlphaMode::Opaque
        } else {
            AlphaMode::Mask { cutoff: 0.5 }
        };
        let texels = if name == "opaque" {
            1.0
        } else {
            mask_area(&alpha, 0.5)
        };
        assert!(
            (texels - analytic).abs() < 0.002 * analytic,
            "{name}: {texels}"
        );
        let inputs = Inputs::new(panel_scene(alpha, mode), black_env(), slanted_light());
        // The grid's uncertainty methods: a single light has no neighbours, so the boundary
        // rule has no light-space edge to trace, and the scanline's voters all lie on one side
        // (the sky-lit tests below cover every method).
        for method in [
            Method::BRUTE,
            Method::DEFAULT,
            "grid-warp-uncertainty".parse().unwrap(),
        ] {
            failures.case(&format!("{name} {method}"), || {
                let anim = view_of_the_shadow(method);
                let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
                let area = shadow_area(&film, &anim, &inputs);
                let err = (area - analytic).abs() / analytic;
                assert!(
                    err < 0.01,
                    "shadow area {area:.4}, the mask's {analytic:.4}: {:.2} % off",
                    100.0 * err
                );
            });
        }
    }
    failures.assert_none();
}

/// The disc panel and a ring of ground under the built-in sky's lights (many lights, soft
/// overlapping shadows), seen at an angle through the panel's holes.
fn sky_panel(lights: usize) -> (envshadow::anim::Animation, Inputs) {
    let env = EnvMap::builtin_sky();
    let set = LightSet::build(&env, lights, Sampler::Sis).unwrap();
    let inputs = Inputs::new(
        panel_scene(checker(), AlphaMode::Mask { cutoff: 0.5 }),
        env,
        set,
    );
    let anim = common::animation(
        "[camera]\nposition = [1.2, 2.2, 2.0]\ntarget = [0.0, 0.4, 0.0]\nvfov = 45.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = 120\nheight = 90\ntile = 32\n",
    );
    (anim, inputs)
}

#[test]
fn validate_counts_wrong_pairs_against_the_alpha_tested_geometry() {
    // Brute force traces the cut-out panel as --validate does: no wrong pair. The predicting
    // methods are compared with the same truth and stay within the bounds the predict tests
    // state for small frames; the panel's holes do reach the ground (some lights visible
    // under it, some blocked).
    let (anim, inputs) = sky_panel(100);
    let mut failures = Failures::new();
    for method in Method::all().filter(|&m| m != Method::NONE) {
        failures.case(&method.to_string(), || {
            let mut a = anim.clone();
            a.render.method = method;
            a.render.validate = true;
            let (_, stats) = render_frame(&a, &inputs, 0, None, &Silent).unwrap();
            let c = stats.counts;
            let wrong = c.wrong_visible + c.wrong_blocked;
            let share = 100.0 * wrong as f64 / c.queries as f64;
            let bound = if method == Method::BRUTE {
                0.0
            } else if method.name().starts_with("scan") {
                2.5
            } else {
                0.5
            };
            assert!(
                share <= bound,
                "{wrong} wrong of {} ({share:.3} %)",
                c.queries
            );
        });
    }
    failures.assert_none();
}

#[test]
fn the_default_flood_rule_floods_to_all_lights_where_shadows_fall_through_cut_outs() {
    // `--flood-to auto` (the default): `all` on a frame with cut-out triangles, where contrary
    // flooding misses the lights beside a hole; `contrary-finest` on one without.
    use envshadow::predict::FloodTo;
    let render = |inputs: &Inputs, flood_to: FloodTo| {
        let (mut a, _) = sky_panel(100);
        a.render.flood_to = flood_to;
        let (film, stats) = render_frame(&a, inputs, 0, None, &Silent).unwrap();
        (film.layer(Channel::BEAUTY).unwrap(), stats.counts.rays)
    };
    let (anim, cut) = sky_panel(100);
    assert_eq!(anim.render.flood_to, FloodTo::Auto, "the default");
    let auto = render(&cut, FloodTo::Auto);
    assert_eq!(auto, render(&cut, FloodTo::All));
    assert_ne!(auto.1, render(&cut, FloodTo::ContraryFinest).1);
    let opaque = Inputs::new(
        panel_scene(checker(), AlphaMode::Opaque),
        EnvMap::builtin_sky(),
        LightSet::build(&EnvMap::builtin_sky(), 100, Sampler::Sis).unwrap(),
    );
    let auto = render(&opaque, FloodTo::Auto);
    assert_eq!(auto, render(&opaque, FloodTo::ContraryFinest));
    assert_ne!(auto.1, render(&opaque, FloodTo::All).1);
}

#[test]
fn cut_out_frames_do_not_depend_on_tiles_or_threads() {
    let (anim, inputs) = sky_panel(64);
    let mut failures = Failures::new();
    for method in [Method::DEFAULT, "grid-warp-uncertainty".parse().unwrap()] {
        let render = |tile: u32, threads: usize| {
            let mut a = anim.clone();
            a.render.method = method;
            a.render.tile = tile;
            a.render.validate = true;
            thread_pool(threads)
                .unwrap()
                .install(|| render_frame(&a, &inputs, 0, None, &Silent))
                .unwrap()
                .0
        };
        let whole = render(0, 1);
        for (tile, threads) in [(16, 1), (32, 2), (8, 2)] {
            failures.case(&format!("{method} tile {tile} threads {threads}"), || {
                common::assert_same_film(&render(tile, threads), &whole);
            });
        }
    }
    failures.assert_none();
}

#[test]
fn packets_blockers_and_single_rays_agree_on_cut_out_geometry() {
    // From points on the ground under and around the panel, to every light of the sky: a
    // packet's answers are the single rays', a blocker is found exactly when the single ray
    // is blocked, and some rays pass through the holes that the opaque panel would stop.
    use envshadow::context::FrameContext;
    let (anim, inputs) = sky_panel(200);
    let accel = inputs.scene.accel();
    assert!(accel.has_cutouts());
    let camera = anim.camera(&inputs.scene, 0).unwrap();
    let ctx = FrameContext::new(&inputs.scene, &accel, camera, &inputs.lights, &inputs.env);
    let opaque = envshadow::accel::Accel::build(&inputs.scene.positions, &inputs.scene.triangles);
    let (mut through, mut blocked) = (0, 0);
    for k in 0..400 {
        let s = common::ground_surface((k % 20) as f32 * 0.1 - 1.0, (k / 20) as f32 * 0.1 - 1.0);
        let p = s.p;
        let lights: Vec<u32> = (0..ctx.light_count() as u32)
            .filter(|&j| ctx.light_dir[j as usize].y > 0.0)
            .collect();
        for chunk in lights.chunks(envshadow::accel::PACKET) {
            let packet = ctx.trace_packet(&s, chunk);
            for (r, &j) in chunk.iter().enumerate() {
                let visible = ctx.trace(&s, j as usize);
                assert_eq!(packet >> r & 1 == 0, visible, "point {p} light {j}");
                assert_eq!(ctx.trace_blocker(&s, j as usize).is_none(), visible);
                let o = s.origin;
                let stopped = opaque.occluded(o, ctx.light_dir[j as usize]);
                through += usize::from(visible && stopped);
                blocked += usize::from(!visible);
            }
        }
    }
    assert!(
        through > 500 && blocked > 500,
        "{through} through holes, {blocked} blocked"
    );
}

#[test]
fn alpha_mask_panels_cast_the_shape_of_their_textures() {
    // The corpus scene: three masked panels on a ground. Under a low light the ground
    // shadowed by the masked panels is a fraction of what the same panels opaque shadow (their
    // alpha is 0 over much of them), and brute force validates without a wrong pair; under
    // the sky's lights the default method predicts them within its stated error.
    let path = common::assets_dir().join("corpus/alpha_mask_panels.glb");
    let scene = Scene::load(&path).unwrap();
    let masked: Vec<&Material> = scene
        .materials
        .iter()
        .filter(|m| matches!(m.alpha_mode, AlphaMode::Mask { .. }))
        .collect();
    assert_eq!(masked.len(), 3, "perforated, lattice, leafy_noise");
    let mut maps: Vec<usize> = masked
        .iter()
        .filter_map(|m| m.base_color_texture.map(|s| s.texture))
        .filter(|&t| scene.textures[t].has_alpha())
        .collect();
    maps.dedup();
    assert_eq!(maps.len(), 3, "each its own base colour alpha");
    let mut opaque = scene.clone();
    for m in &mut opaque.materials {
        m.alpha_mode = AlphaMode::Opaque;
    }
    let light = LightSet::from_lights(vec![Light {
        dir: Vec3::new(0.1, 0.6, 1.0).normalize(),
        energy: Vec3::ONE,
        solid_angle: 1e-3,
    }]);
    let anim = |method: Method| {
        let mut a = common::animation(
            "[camera]\nposition = [0.0, 6.0, 0.01]\ntarget = [0.0, 0.0, 0.0]\nvfov = 35.0\n\
             [motion]\nkind = \"none\"\n[render]\nwidth = 160\nheight = 160\n",
        );
        a.render.method = method;
        a.render.validate = true;
        a
    };
    // Pixels on the scene: brute force traces one ray at each (the background none).
    let inputs = Inputs::new(scene.clone(), black_env(), light.clone());
    let (film, _) = render_frame(&anim(Method::BRUTE), &inputs, 0, None, &Silent).unwrap();
    let on_scene: Vec<bool> = film
        .plane(Channel::Rays)
        .unwrap()
        .iter()
        .map(|&r| r > 0.0)
        .collect();
    let shadowed = |scene: Scene, method: Method| {
        let inputs = Inputs::new(scene, black_env(), light.clone());
        let (film, stats) = render_frame(&anim(method), &inputs, 0, None, &Silent).unwrap();
        let n = (film.plane(Channel::Visible).unwrap().iter().zip(&on_scene))
            .filter(|&(&v, &hit)| hit && v < 0.5)
            .count();
        (n, stats.counts)
    };
    let (cut, counts) = shadowed(scene.clone(), Method::BRUTE);
    assert_eq!(counts.wrong_visible + counts.wrong_blocked, 0);
    let (full, _) = shadowed(opaque, Method::BRUTE);
    assert!(full > 1000, "the panels' shadows are in view ({full} px)");
    let share = cut as f64 / full as f64;
    assert!(
        (0.15..0.85).contains(&share),
        "masked shadows {cut} px of the opaque panels' {full}"
    );
    // Under the sky's 100 lights the default method predicts the cut-out shadows within the
    // error the predict tests state for small frames.
    let env = EnvMap::builtin_sky();
    let sky = LightSet::build(&env, 100, Sampler::Sis).unwrap();
    let inputs = Inputs::new(scene, env, sky);
    let (_, stats) = render_frame(&anim(Method::DEFAULT), &inputs, 0, None, &Silent).unwrap();
    let c = stats.counts;
    let wrong = 100.0 * (c.wrong_visible + c.wrong_blocked) as f64 / c.queries as f64;
    assert!(wrong < 0.5, "{wrong:.3} % of {} queries wrong", c.queries);
}

#[test]
fn blend_is_coverage_for_camera_rays() {
    // A BLEND panel of constant alpha 0.3 filling the view in front of the map: with 16
    // samples per pixel, about 0.3 of each pixel's samples see the panel (the coverage AOV),
    // and within one sample of it in every pixel; shadow rays take it as a mask at 0.5, so
    // alpha 0.3 casts no shadow and alpha 0.7 casts a full one.
    let mut failures = Failures::new();
    for (alpha, shadow) in [(0.3f32, false), (0.7, true)] {
        failures.case(&format!("alpha {alpha}"), || {
            let mut scene = panel_scene(vec![alpha; SIDE * SIDE], AlphaMode::Blend);
            // No ground: what is not the panel is the map.
            scene.triangles.drain(..2);
            scene.tri_material.drain(..2);
            let inputs = Inputs::new(scene, black_env(), slanted_light());
            let mut anim = common::animation(
                "[camera]\nposition = [0.0, 3.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
                 vfov = 10.0\n[motion]\nkind = \"none\"\n[render]\nwidth = 40\nheight = 40\nspp = 16\n",
            );
            anim.render.method = Method::BRUTE;
            let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
            let coverage = film.plane(Channel::Coverage).expect("a coverage AOV with spp > 1");
            let mean = coverage.iter().sum::<f32>() / coverage.len() as f32;
            assert!((mean - alpha).abs() < 0.02, "mean coverage {mean}");
            assert!(coverage.iter().all(|&c| (c - alpha).abs() <= 1.0 / 16.0 + 1e-6));
            // Shadows: the panel on itself cannot be seen; cast onto a ground instead.
            let scene = panel_scene(vec![alpha; SIDE * SIDE], AlphaMode::Blend);
            let inputs = Inputs::new(scene, black_env(), slanted_light());
            let anim = view_of_the_shadow(Method::BRUTE);
            let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
            let area = shadow_area(&film, &anim, &inputs);
            let want = if shadow { 1.0 } else { 0.0 };
            assert!((area - want).abs() < 0.01, "shadow area {area}");
        });
    }
    failures.assert_none();
}

#[test]
fn the_alpha_test_reads_the_base_colour_slot_as_shading_does() {
    // The panel's alpha texture read through a KHR_texture_transform and a clamping, NEAREST
    // sampler: the BVH's alpha (Scene::alpha) is the texture's alpha at the transformed
    // coordinates as that sampler reads them, and the same as the material's own alpha at the
    // point (what shading reads), so camera rays, shadow rays and shading agree.
    let mut scene = panel_scene(checker(), AlphaMode::Mask { cutoff: 0.5 });
    let panel = scene.triangle_count() - 2;
    let transform = envshadow::scene::UvTransform::new([0.3, -0.2], 0.4, [1.7, 0.6]);
    let sampler = envshadow::scene::Sampler {
        wrap_s: envshadow::scene::Wrap::Clamp,
        wrap_t: envshadow::scene::Wrap::Mirror,
        mag_nearest: true,
        mipmaps: true,
    };
    let slot = scene.materials[1].base_color_texture.as_mut().unwrap();
    slot.transform = Some(transform);
    slot.sampler = sampler;
    let texture = scene.textures[slot.texture].clone();
    let (mut differs, mut n) = (0, 0);
    for tri in [panel, panel + 1] {
        for k in 0..400 {
            let (u, v) = ((k % 20) as f32 / 20.0, (k / 20) as f32 / 20.0);
            if u + v > 1.0 {
                continue;
            }
            let uv = scene.uv(tri, (u, v));
            let want = texture.alpha_at(transform.apply(uv), &sampler);
            let got = scene.alpha(tri, (u, v));
            assert_eq!(got, want, "triangle {tri} at ({u}, {v})");
            let shading = scene.material_at(tri, (u, v), 0.0, Vec3::Y).sample.alpha;
            assert_eq!(shading, got, "shading's alpha at ({u}, {v})");
            differs += usize::from(got != texture.alpha_at(uv, &Default::default()));
            n += 1;
        }
    }
    assert!(
        differs > n / 4,
        "the transform and sampler matter: {differs} of {n}"
    );
}

#[test]
fn export_describes_cut_outs_for_another_renderer() {
    // scripts/compare-mitsuba.py cuts out what envshadow cuts out from the export alone: each
    // masked material's mode, cutoff and alpha texture (its level 0 as written), and per
    // vertex the texture coordinates, per face the material, in the PLY.
    let path = common::assets_dir().join("corpus/alpha_mask_panels.glb");
    let scene = Scene::load(&path).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("spec.toml");
    std::fs::write(
        &spec,
        format!(
            "[scene]\nfile = {:?}\n[environment]\nfile = {:?}\n[motion]\nkind = \"none\"\n\
             frames = 1\n[render]\nwidth = 32\nheight = 24\n",
            path,
            common::asset("studio_small_03_1k.hdr")
        ),
    )
    .unwrap();
    let out = dir.path().join("exp");
    let run = common::bin()
        .args(["export", "--lights", "20", "--out"])
        .arg(&out)
        .arg(&spec)
        .output()
        .unwrap();
    assert!(run.status.success(), "{run:?}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("materials.json")).unwrap())
            .unwrap();
    let exported = json["materials"].as_array().unwrap();
    let mut masked = 0;
    for m in &scene.materials {
        let e = exported
            .iter()
            .find(|e| e["name"] == m.name.as_str())
            .unwrap();
        let AlphaMode::Mask { cutoff } = m.alpha_mode else {
            assert_eq!(e["alpha_mode"], "OPAQUE", "{e}");
            assert_eq!(e["cut_out"], false, "{e}");
            continue;
        };
        masked += 1;
        assert_eq!(e["alpha_mode"], "MASK", "{e}");
        assert_eq!(e["alpha_cutoff"].as_f64(), Some(f64::from(cutoff)), "{e}");
        assert_eq!(e["cut_out"], true, "{e}");
        let slot = m.base_color_texture.unwrap();
        let texture = &scene.textures[slot.texture];
        let t = &e["alpha_texture"];
        assert_eq!(t["width"].as_u64(), Some(texture.width() as u64), "{e}");
        assert_eq!(t["height"].as_u64(), Some(texture.height() as u64), "{e}");
        assert_eq!(t["wrap_s"], "repeat", "{e}");
        let bytes = std::fs::read(out.join(t["file"].as_str().unwrap())).unwrap();
        let alpha: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(alpha, texture.alpha(), "{}'s alpha, level 0", m.name);
    }
    assert_eq!(masked, 3);

    // The PLY: 11 floats a vertex (u, v at 6 and 7), the material index last in a face.
    let (ply, end, header) = common::read_ply(&out.join("scene.ply"));
    assert!(header.contains("property float u\nproperty float v\nproperty float u1\n"));
    assert!(header.contains("property float b\nproperty int material\nend_header"));
    let f = |at: usize| f32::from_le_bytes(ply[at..at + 4].try_into().unwrap());
    let nv = scene.positions.len();
    for (i, uv) in scene.uvs.iter().enumerate() {
        assert_eq!(
            Vec2::new(f(end + 44 * i + 24), f(end + 44 * i + 28)),
            *uv,
            "vertex {i}"
        );
    }
    for (t, &m) in scene.tri_material.iter().enumerate() {
        let at = end + 44 * nv + 29 * t + 25;
        let got = i32::from_le_bytes(ply[at..at + 4].try_into().unwrap());
        let name = exported[got as usize]["name"].as_str().unwrap();
        assert_eq!(name, scene.materials[m as usize].name, "face {t}");
    }
}
