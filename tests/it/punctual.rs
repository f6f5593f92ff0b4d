//! Lights of the scene file (issue 24, item 4): `KHR_lights_punctual` directional, point and
//! spot lights against their analytic irradiance, a file sun against a map light of the same
//! energy, prediction against brute force with them, and the corpus files that list the
//! extension as required.

use crate::common::{self, Failures};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::brdf::brdf;
use envshadow::coordinator::thread_pool;
use envshadow::envmap::EnvMap;
use envshadow::film::{Channel, Film};
use envshadow::frame::render_frame;
use envshadow::inputs::Inputs;
use envshadow::lights::{LightSet, Sampler};
use envshadow::predict::Method;
use envshadow::run::Silent;
use envshadow::scene::{Material, Scene, SceneLight, SceneLightKind};
use glam::Vec3;
use std::path::Path;

const ALBEDO: f32 = 0.5;

fn black_env() -> EnvMap {
    EnvMap::from_texels(16, 8, vec![Vec3::ZERO; 128], "black").unwrap()
}

/// Map lights that light nothing (a black map), and the scene file's `lights`.
fn dark_map_and(lights: &[SceneLight]) -> LightSet {
    LightSet::build(&black_env(), 16, Sampler::Sis)
        .unwrap()
        .with_scene_lights(lights, Path::new("test.glb"))
        .unwrap()
}

fn light(kind: SceneLightKind, position: Vec3, direction: Vec3, cd: f32) -> SceneLight {
    SceneLight {
        name: "test light".into(),
        kind,
        position,
        direction: direction.normalize(),
        color: Vec3::new(1.0, 0.5, 0.25),
        intensity: cd,
        range: None,
    }
}

/// A large ground plane of albedo 0.5, nothing else.
fn ground() -> Scene {
    let mut scene = common::scene_with_materials(&[ALBEDO]);
    common::add_plane(&mut scene, 40.0, 0.0, 0);
    scene
}

/// A `w × w` view straight down at the ground from 6 units up, 6 units across.
fn looking_down(w: u32, method: Method) -> Animation {
    let mut anim = common::animation(&format!(
        "[camera]\nposition = [0.0, 6.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
         vfov = 53.13\n[motion]\nkind = \"none\"\n[render]\nwidth = {w}\nheight = {w}\n"
    ));
    anim.render.method = method;
    anim
}

/// Each pixel's ground point and its rendered radiance (red channel).
fn ground_pixels(film: &Film, anim: &Animation, inputs: &Inputs) -> Vec<(Vec3, f32)> {
    let cam = anim.camera(&inputs.scene, 0).unwrap();
    let (w, h) = (anim.render.width, anim.render.height);
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let d = cam.ray_dir(x, y);
            let p = cam.position + d * (-cam.position.y / d.y);
            out.push((p, film.beauty((y * w + x) as usize)[0]));
        }
    }
    out
}

/// Radiance of the ground (red channel, colour 1) under a point light of `cd` candela at `l`,
/// with `window` the range's and `cone` the spot's falloff at that point.
fn lambert_point(p: Vec3, l: Vec3, cd: f32, falloff: f32) -> f32 {
    let d = l - p;
    let cos = d.normalize().y.max(0.0);
    ALBEDO / std::f32::consts::PI * (cd / 683.0) * cos / d.length_squared() * falloff
}

#[test]
fn point_light_over_a_plane_gives_intensity_times_cosine_over_distance_squared() {
    // E = I cos θ / d² (I = cd / 683), with and without a range window; the map's lights are
    // black, so the plane's radiance is ρ/π E, pixel for pixel.
    let l = Vec3::new(0.4, 1.5, -0.3);
    let cd = 683.0 * 3.0;
    let mut failures = Failures::new();
    for range in [None, Some(2.5f32)] {
        failures.case(&format!("range {range:?}"), || {
            let mut point = light(SceneLightKind::Point, l, -Vec3::Y, cd);
            point.range = range;
            let inputs = Inputs::new(ground(), black_env(), dark_map_and(&[point]));
            assert_eq!(inputs.lights.len(), 17);
            let anim = looking_down(96, Method::BRUTE);
            let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
            let (mut lit, mut dark) = (0, 0);
            for (p, got) in ground_pixels(&film, &anim, &inputs) {
                let window = range.map_or(1.0, |r| {
                    let q = (l - p).length() / r;
                    (1.0 - q.powi(4)).clamp(0.0, 1.0).powi(2)
                });
                let want = lambert_point(p, l, cd, window);
                assert!(
                    (got - want).abs() <= 1e-4 * want + 1e-7,
                    "at {p}: {got}, want {want}"
                );
                lit += usize::from(want > 0.0);
                dark += usize::from(want == 0.0);
            }
            assert!(lit > 1000);
            if range.is_some() {
                assert!(dark > 1000, "the range ends the light in view");
            }
        });
    }
    failures.assert_none();
}

#[test]
fn spot_light_cone_edge_falls_where_its_angles_say() {
    // A spot 2 up shining straight down, inner 15°, outer 30°: full inside 2 tan 15°, the
    // extension's smooth falloff to nothing at 2 tan 30°, nothing beyond.
    let l = Vec3::new(0.0, 2.0, 0.0);
    let (inner, outer) = (15f32.to_radians(), 30f32.to_radians());
    let cd = 683.0 * 2.0;
    let spot = light(SceneLightKind::Spot { inner, outer }, l, -Vec3::Y, cd);
    let inputs = Inputs::new(ground(), black_env(), dark_map_and(&[spot]));
    let anim = looking_down(128, Method::BRUTE);
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let pixel = 6.0 / 128.0;
    let edge = 2.0 * outer.tan();
    let (mut full, mut partial, mut outside) = (0, 0, 0);
    for (p, got) in ground_pixels(&film, &anim, &inputs) {
        let c = (l - p).normalize().y;
        let t = ((c - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        let want = lambert_point(p, l, cd, t * t);
        assert!(
            (got - want).abs() <= 1e-4 * want + 1e-7,
            "at {p}: {got}, want {want}"
        );
        let r = (p.x * p.x + p.z * p.z).sqrt();
        if r > edge + pixel {
            assert_eq!(got, 0.0, "lit beyond the outer cone at r = {r}");
            outside += 1;
        } else if r < 2.0 * inner.tan() {
            assert!((got - lambert_point(p, l, cd, 1.0)).abs() <= 1e-4 * got);
            full += 1;
        } else if r < edge - pixel {
            assert!(got > 0.0);
            partial += 1;
        }
    }
    assert!(
        full > 300 && partial > 300 && outside > 1000,
        "{full} {partial} {outside}"
    );
}

/// A sphere resting on the ground: it shadows it.
fn sphere_on_ground() -> Scene {
    let mut scene = common::scene_with_materials(&[ALBEDO, 0.8]);
    common::add_plane(&mut scene, 40.0, 0.0, 0);
    common::add_sphere(&mut scene, Vec3::new(0.0, 0.6, 0.0), 0.6, 64, 128, 1);
    scene
}

#[test]
fn a_directional_scene_light_equals_a_map_light_of_the_same_energy() {
    // A file sun of 6830 lux (Blender's strength 10 W/m²) lights and shadows the scene exactly
    // as one map light of energy 10 along the same direction: the same pixels, bit for bit,
    // and ρ/π E cos θ on the open ground.
    let sun = SceneLight {
        color: Vec3::new(1.0, 0.9, 0.8),
        intensity: 6830.0,
        ..light(
            SceneLightKind::Directional,
            Vec3::new(5.0, 9.0, 1.0),
            Vec3::new(-1.0, -0.8, -0.5),
            0.0,
        )
    };
    let with_file = dark_map_and(std::slice::from_ref(&sun));
    assert_eq!(with_file.lights.len(), 17);
    let file_sun = with_file.lights[16];
    assert_eq!(file_sun.energy, sun.color * (sun.intensity / 683.0));
    assert!(
        (file_sun.energy - Vec3::new(10.0, 9.0, 8.0))
            .abs()
            .max_element()
            < 1e-5
    );
    assert_eq!(file_sun.dir, -sun.direction);
    let map_sun = LightSet::from_lights(vec![file_sun]);
    let anim = looking_down(80, Method::BRUTE);
    let a = Inputs::new(sphere_on_ground(), black_env(), with_file);
    let b = Inputs::new(sphere_on_ground(), black_env(), map_sun);
    let (fa, _) = render_frame(&anim, &a, 0, None, &Silent).unwrap();
    let (fb, _) = render_frame(&anim, &b, 0, None, &Silent).unwrap();
    assert!(
        fa.layer(Channel::BEAUTY).unwrap() == fb.layer(Channel::BEAUTY).unwrap(),
        "the file's sun renders as the map light"
    );
    let cos = file_sun.dir.y;
    let open = ALBEDO / std::f32::consts::PI * file_sun.energy.x * cos;
    let (mut shadowed, mut matches) = (0, 0);
    for (p, got) in ground_pixels(&fa, &anim, &a) {
        if p.x < 0.0 && p.length() < 2.5 {
            shadowed += usize::from(got == 0.0);
        } else if p.x > 1.0 {
            assert!((got - open).abs() <= 1e-5 * open, "{got} vs {open}");
            matches += 1;
        }
    }
    assert!(shadowed > 100 && matches > 1000, "{shadowed} {matches}");
}

/// The shapes scene under the built-in sky's lights, with a file sun, a point light and a spot
/// light among the objects.
fn shapes_with_scene_lights(lights: usize) -> (Animation, Inputs) {
    let env = EnvMap::builtin_sky();
    let file = [
        SceneLight {
            intensity: 683.0 * 2.0,
            ..light(
                SceneLightKind::Directional,
                Vec3::ZERO,
                Vec3::new(0.6, -1.0, 0.3),
                0.0,
            )
        },
        light(
            SceneLightKind::Point,
            Vec3::new(-0.3, 1.6, 0.4),
            -Vec3::Y,
            683.0 * 6.0,
        ),
        light(
            SceneLightKind::Spot {
                inner: 0.3,
                outer: 0.6,
            },
            Vec3::new(1.5, 2.0, 1.5),
            Vec3::new(-1.0, -1.4, -1.0),
            683.0 * 12.0,
        ),
    ];
    let set = LightSet::build(&env, lights, Sampler::Sis)
        .unwrap()
        .with_scene_lights(&file, Path::new("test.glb"))
        .unwrap();
    let inputs = Inputs::new(Scene::shapes(), env, set);
    let anim = common::animation(
        "[camera]\ntarget = [0.0, 0.45, 0.0]\ndistance = 6.5\nelevation = 25.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = 160\nheight = 120\n",
    );
    (anim, inputs)
}

#[test]
fn prediction_with_scene_lights_agrees_with_brute_force_within_its_measured_error() {
    // Every method, validated: the wrong (pixel, light) pairs, over all lights and over the
    // file's point and spot lights alone, within the bounds the predict tests state for small
    // frames; brute force none. The file lights must matter: they light and shadow pixels.
    let (anim, inputs) = shapes_with_scene_lights(100);
    let points = inputs.lights.lights.len();
    assert_eq!((points, inputs.lights.len()), (101, 103));
    let mut failures = Failures::new();
    let mut reference: Option<Film> = None;
    for method in Method::all().filter(|&m| m != Method::NONE) {
        failures.case(&method.to_string(), || {
            let mut a = anim.clone();
            a.render.method = method;
            a.render.validate = true;
            let (film, stats) = render_frame(&a, &inputs, 0, None, &Silent).unwrap();
            let c = stats.counts;
            let share = 100.0 * (c.wrong_visible + c.wrong_blocked) as f64 / c.queries as f64;
            let bound = match method.name() {
                "brute" => 0.0,
                "scan-warp-boundary" => 2.5,
                "scan-nowarp-uncertainty" => 1.5,
                _ => 0.5,
            };
            assert!(
                share <= bound,
                "{share:.3} % of {} queries wrong",
                c.queries
            );
            if method == Method::BRUTE {
                reference = Some(film);
            } else if let Some(r) = &reference {
                // The image error stays small: relative mean absolute difference.
                let (mut diff, mut sum) = (0.0f64, 0.0f64);
                for (p, q) in film
                    .layer(Channel::BEAUTY)
                    .unwrap()
                    .iter()
                    .zip(&r.layer(Channel::BEAUTY).unwrap())
                {
                    diff += (p[0] - q[0]).abs() as f64;
                    sum += q[0] as f64;
                }
                assert!(
                    diff / sum < 0.01,
                    "image differs by {:.3} %",
                    100.0 * diff / sum
                );
            }
        });
    }
    failures.assert_none();
    // The file's lights matter: without them the frame is darker in many pixels.
    let r = reference.expect("brute force rendered");
    let env = EnvMap::builtin_sky();
    let map_only = Inputs::new(
        Scene::shapes(),
        env.clone(),
        LightSet::build(&env, 100, Sampler::Sis).unwrap(),
    );
    let mut a = anim.clone();
    a.render.method = Method::BRUTE;
    let (dark, _) = render_frame(&a, &map_only, 0, None, &Silent).unwrap();
    let brighter = r
        .layer(Channel::BEAUTY)
        .unwrap()
        .iter()
        .zip(&dark.layer(Channel::BEAUTY).unwrap())
        .filter(|(p, q)| p[0] > q[0] * 1.05)
        .count();
    assert!(
        brighter > r.layer(Channel::BEAUTY).unwrap().len() / 4,
        "{brighter} pixels brighter"
    );
}

#[test]
fn scene_light_frames_do_not_depend_on_tiles_or_threads() {
    let (anim, inputs) = shapes_with_scene_lights(64);
    let mut failures = Failures::new();
    for method in [
        Method::DEFAULT,
        "grid-warp-uncertainty".parse().unwrap(),
        "scan-warp-boundary".parse().unwrap(),
    ] {
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
        for (tile, threads) in [(16, 1), (32, 2)] {
            failures.case(&format!("{method} tile {tile} threads {threads}"), || {
                common::assert_same_film(&render(tile, threads), &whole);
            });
        }
    }
    failures.assert_none();
}

#[test]
fn packets_and_single_rays_agree_on_point_lights() {
    // Rays to point and spot lights end at the light: a packet mixing them with directional
    // lights answers as each ray alone, and a blocker lies before the light.
    use envshadow::context::FrameContext;
    let (anim, inputs) = shapes_with_scene_lights(100);
    let accel = inputs.scene.accel();
    let camera = anim.camera(&inputs.scene, 0).unwrap();
    let ctx = FrameContext::new(&inputs.scene, &accel, camera, &inputs.lights, &inputs.env);
    let all: Vec<u32> = (0..ctx.light_count() as u32).collect();
    let (mut blocked, mut checked) = (0, 0);
    for k in 0..300 {
        let s = common::ground_surface((k % 20) as f32 * 0.2 - 2.0, (k / 20) as f32 * 0.2 - 1.5);
        let p = s.p;
        // The file lights (the last three) with some map lights in one packet.
        let mut lights: Vec<u32> = all.iter().copied().step_by(7).take(29).collect();
        lights.extend(&all[all.len() - 3..]);
        let packet = ctx.trace_packet(&s, &lights);
        for (r, &j) in lights.iter().enumerate() {
            let visible = ctx.trace(&s, j as usize);
            assert_eq!(packet >> r & 1 == 0, visible, "point {p} light {j}");
            let (_, _, end) = ctx.shadow_ray(&s, j as usize);
            match ctx.trace_blocker(&s, j as usize) {
                Some(t) => assert!(!visible && t < end, "light {j}: blocker at {t}, end {end}"),
                None => assert!(visible),
            }
            if j as usize >= ctx.light_dir.len() {
                checked += 1;
                blocked += usize::from(!visible);
            }
        }
    }
    assert!(
        blocked > 20 && blocked + 20 < checked,
        "{blocked} of {checked} blocked"
    );
}

/// An animation of a corpus scene under the built-in sky.
fn corpus(name: &str, extra: &str) -> Animation {
    let text = format!(
        "[scene]\nfile = \"{}\"\n[lights]\ncount = 50\n{extra}\n[render]\nwidth = 64\nheight = 48\n",
        common::assets_dir().join("corpus").join(name).display()
    );
    Animation::parse(&text, Path::new("corpus.toml"), &AnimFlags::default()).unwrap()
}

#[test]
fn corpus_scenes_requiring_khr_lights_punctual_load_and_light_the_frame() {
    // objects_on_circuit_board.glb lists KHR_lights_punctual in extensionsRequired: it loads,
    // with its one directional "Sun" of 6830 lux joining the map's lights (energy 10 per
    // channel), and `scene_lights = false` leaves the map's alone.
    let anim = corpus("objects_on_circuit_board.glb", "");
    let inputs = Inputs::load(&anim).unwrap();
    let scene_lights = &inputs.scene.lights;
    assert_eq!(scene_lights.len(), 1);
    assert_eq!(scene_lights[0].name, "Sun");
    assert_eq!(scene_lights[0].kind, SceneLightKind::Directional);
    assert_eq!(scene_lights[0].intensity, 6830.0);
    assert!((scene_lights[0].direction.length() - 1.0).abs() < 1e-5);
    assert_eq!(inputs.lights.len(), 51);
    let sun = inputs.lights.lights[50];
    assert!((sun.energy - Vec3::splat(10.0)).abs().max_element() < 1e-4);
    assert_eq!(inputs.lights.from_file[0].index, 50);
    let note = envshadow::inputs::scene_lights_note(&anim, &inputs.scene).unwrap();
    assert!(note.contains("directional 'Sun'"), "{note}");
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    assert!(
        film.layer(Channel::BEAUTY)
            .unwrap()
            .iter()
            .any(|p| p[0] > 0.0)
    );

    let off = corpus("objects_on_circuit_board.glb", "scene_lights = false");
    let inputs = Inputs::load(&off).unwrap();
    assert_eq!(
        inputs.scene.lights.len(),
        1,
        "the file still loads its lights"
    );
    assert_eq!(inputs.lights.len(), 50, "but they do not light it");
    let note = envshadow::inputs::scene_lights_note(&off, &inputs.scene).unwrap();
    assert!(note.contains("ignored"), "{note}");
}

#[test]
fn lights_json_keeps_the_scene_files_lights() {
    // lights.json lists the file's lights with their bits, file values and converted ones, and
    // reads back into the same set.
    let (_, inputs) = shapes_with_scene_lights(20);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lights.json");
    inputs.lights.write_json(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let file = json["scene_lights"].as_array().unwrap();
    let kinds: Vec<&str> = file.iter().map(|l| l["type"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["directional", "point", "spot"]);
    let units: Vec<&str> = file.iter().map(|l| l["units"].as_str().unwrap()).collect();
    assert_eq!(units, ["lux", "cd", "cd"]);
    assert_eq!(file[0]["index"], 20);
    assert_eq!(file[1]["index"], 21);
    assert_eq!(file[2]["index"], 22);
    assert!(file[2]["outer_cone_angle"].as_f64().unwrap() > 0.59);
    let back = envshadow::lights::read_json(&path).unwrap();
    assert_eq!(back.lights, inputs.lights.lights);
    assert_eq!(back.points, inputs.lights.points);
    assert_eq!(back.from_file, inputs.lights.from_file);
    for j in 0..back.len() {
        assert_eq!(back.neighbors(j), inputs.lights.neighbors(j), "light {j}");
    }
    assert!(back.neighbors(21).is_empty() && back.neighbors(22).is_empty());
}

#[test]
fn point_lights_shade_metallic_roughness_materials_with_the_gltf_brdf() {
    // A point light over a glossy, partly metallic ground: every pixel is the glTF BRDF of
    // the light's direction and the pixel's view, times the irradiance (brdf::brdf, the scalar
    // reference), not the Lambertian share alone. Roughness 0.4: the lights' own sums, no
    // glossy environment.
    let l = Vec3::new(0.4, 1.5, -0.3);
    let cd = 683.0 * 3.0;
    let mut scene = ground();
    scene.materials[0] = Material {
        base_color: Vec3::new(0.8, 0.5, 0.3),
        metallic: 0.3,
        roughness: 0.4,
        ..Material::default()
    };
    let sample = scene.material_at(0, (0.3, 0.3), 0.0, Vec3::Y).sample;
    assert!(!sample.lambert);
    let point = light(SceneLightKind::Point, l, -Vec3::Y, cd);
    let colour = point.color;
    let inputs = Inputs::new(scene, black_env(), dark_map_and(&[point]));
    let anim = looking_down(64, Method::BRUTE);
    let cam = anim.camera(&inputs.scene, 0).unwrap();
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let (w, h) = (anim.render.width, anim.render.height);
    let (mut lit, mut beyond_lambert) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let d = cam.ray_dir(x, y);
            let p = cam.position + d * (-cam.position.y / d.y);
            let to = l - p;
            let dir = to.normalize();
            let e = colour * (cd / 683.0) / to.length_squared();
            let f = brdf(Vec3::Y, -d, dir, Vec3::new(0.8, 0.5, 0.3), &sample);
            let want = f * e * dir.y.max(0.0);
            let got = Vec3::from_array(film.beauty((y * w + x) as usize));
            assert!(
                (got - want).abs().max_element() <= 2e-3 * want.max_element() + 1e-6,
                "pixel ({x}, {y}): {got}, want {want}"
            );
            let lambert = Vec3::new(0.8, 0.5, 0.3) * 0.7 / std::f32::consts::PI * e * dir.y;
            lit += usize::from(want.max_element() > 0.0);
            beyond_lambert +=
                usize::from((want - lambert).abs().max_element() > 1e-3 * want.max_element());
        }
    }
    assert!(
        lit > 1000 && beyond_lambert > 1000,
        "{lit} lit, {beyond_lambert} with specular"
    );
}
