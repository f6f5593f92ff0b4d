//! Frames for compositing: backgrounds and alpha, shadow catchers, the ground added under a
//! model that has none, the up axis, and `envshadow render model.glb`.

use std::fs;
use std::path::{Path, PathBuf};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::background::{Backdrop, blurred};
use envshadow::context::FrameContext;
use envshadow::envmap::{EnvMap, luminance};
use envshadow::film::{Channel, Film};
use envshadow::frame::render_frame;
use envshadow::inputs::Inputs;
use envshadow::lights::{LightSet, Sampler};
use envshadow::output::exr::read_frame;
use envshadow::run::Silent;
use envshadow::scene::ground::has_ground;
use envshadow::scene::{Scene, SceneCamera, Up};
use envshadow::view::View;
use glam::{Mat4, Vec3, Vec4};
use serde_json::{Value, json};

use crate::common::{self, Failures};

/// A sphere hovering over a 6 m square floor (the floor is triangles 0 and 1), both grey 0.5;
/// the floor a shadow catcher when `catcher`.
fn sphere_over_floor(catcher: bool) -> Scene {
    let mut scene = common::scene_with_materials(&[0.5]);
    common::add_plane(&mut scene, 6.0, 0.0, 0);
    common::add_sphere(&mut scene, Vec3::new(0.0, 0.8, 0.0), 0.5, 64, 128, 0);
    if catcher {
        scene.set_catcher(0..2);
    }
    scene
}

/// The sphere alone.
fn sphere() -> Scene {
    let mut scene = common::scene_with_materials(&[0.5]);
    common::add_sphere(&mut scene, Vec3::new(0.0, 0.8, 0.0), 0.5, 64, 128, 0);
    scene
}

/// What a pixel centre sees.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Sees {
    Model,
    Catcher,
    Background,
}

/// One frame of `scene` under the built-in sky's 100 lights, seen from above the floor's
/// front edge, with `render` (lines of `[render]`) and `backdrop`; with what each pixel
/// centre sees and its primary ray's direction.
fn frame(scene: Scene, render: &str, backdrop: Backdrop) -> (Film, Vec<(Sees, Vec3)>) {
    let env = EnvMap::builtin_sky();
    let lights = LightSet::build(&env, 100, Sampler::Sis).unwrap();
    let inputs = Inputs::new(scene, env, lights).with_backdrop(backdrop);
    let anim = common::animation(&format!(
        "[camera]\ntarget = [0.0, 0.3, 0.0]\ndistance = 4.0\nelevation = 35.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = 160\nheight = 120\ntile = 32\n{render}"
    ));
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let camera = anim.camera(&inputs.scene, 0).unwrap();
    let ctx = FrameContext::new(
        &inputs.scene,
        inputs.still_accel(),
        camera,
        &inputs.lights,
        &inputs.env,
    );
    let mut sees = Vec::new();
    for y in 0..120 {
        for x in 0..160 {
            let s = ctx.surface(x, y);
            let what = match (s.hit, s.catcher) {
                (false, _) => Sees::Background,
                (true, true) => Sees::Catcher,
                (true, false) => Sees::Model,
            };
            sees.push((what, s.dir));
        }
    }
    (film, sees)
}

#[test]
fn a_catcher_in_shadow_has_the_brute_force_ground_s_shadow_fraction() {
    let (predicted, sees) = frame(sphere_over_floor(true), "", Backdrop::Transparent);
    let (traced, _) = frame(
        sphere_over_floor(true),
        "method = \"brute\"\n",
        Backdrop::Transparent,
    );
    // The reference: the floor as a plain diffuse surface, traced, and without shadows.
    let (shadowed, _) = frame(
        sphere_over_floor(false),
        "method = \"brute\"\n",
        Backdrop::Environment,
    );
    let (open, _) = frame(
        sphere_over_floor(false),
        "method = \"none\"\n",
        Backdrop::Environment,
    );
    let (a_pred, a_traced) = (
        predicted.plane(Channel::A).unwrap(),
        traced.plane(Channel::A).unwrap(),
    );
    let mut failures = Failures::new();
    let (mut in_shadow, mut close, mut sum_err, mut catcher) = (0, 0, 0.0f64, 0);
    for (i, &(what, _)) in sees.iter().enumerate() {
        match what {
            Sees::Catcher => {
                catcher += 1;
                let lum = |f: &Film| luminance(Vec3::from_array(f.beauty(i)));
                let fraction = 1.0 - lum(&shadowed) / lum(&open);
                failures.check((a_traced[i] - fraction).abs() <= 1e-4, || {
                    format!(
                        "pixel {i}: traced catcher alpha {} vs {fraction}",
                        a_traced[i]
                    )
                });
                failures.check(predicted.beauty(i) == [0.0; 3], || {
                    format!("pixel {i}: catcher colour {:?}", predicted.beauty(i))
                });
                let err = (a_pred[i] - fraction).abs();
                sum_err += err as f64;
                if fraction >= 0.5 {
                    in_shadow += 1;
                    close += usize::from(err <= 0.01);
                }
            }
            Sees::Model => {
                failures.check(a_pred[i] == 1.0 && a_traced[i] == 1.0, || {
                    format!("pixel {i}: model alpha {} / {}", a_pred[i], a_traced[i])
                });
            }
            Sees::Background => {
                failures.check(a_pred[i] == 0.0 && predicted.beauty(i) == [0.0; 3], || {
                    format!(
                        "pixel {i}: background alpha {} colour {:?}",
                        a_pred[i],
                        predicted.beauty(i)
                    )
                });
            }
        }
    }
    failures.assert_none();
    assert!(catcher > 5000 && in_shadow > 150, "{catcher} {in_shadow}");
    // The predicted bits: the shadow's pixels within 1 % of brute force (a wrong prediction
    // of the sun may put a rare pixel off), and little error over the whole catcher.
    assert!(
        close as f64 >= 0.99 * in_shadow as f64,
        "{close} of {in_shadow} in-shadow pixels within 1 %"
    );
    eprintln!(
        "catcher: {close} of {in_shadow} in-shadow pixels within 1 % of brute force, mean error {:.5} over {catcher}",
        sum_err / catcher as f64
    );
    assert!(
        sum_err / catcher as f64 <= 0.002,
        "{}",
        sum_err / catcher as f64
    );
    // The catcher's rays are counted like any surface's: the same work as a plain floor.
    let (plain, _) = frame(sphere_over_floor(false), "", Backdrop::Environment);
    assert_eq!(predicted.counts, plain.counts);
    assert!(predicted.counts.rays > 0);
}

#[test]
fn a_catcher_over_the_environment_shows_it_darkened_by_the_shadow() {
    let (over_env, sees) = frame(sphere_over_floor(true), "", Backdrop::Environment);
    let (over_nothing, _) = frame(sphere_over_floor(true), "", Backdrop::Transparent);
    assert!(over_env.plane(Channel::A).is_none());
    let alpha = over_nothing.plane(Channel::A).unwrap();
    let env = EnvMap::builtin_sky();
    let mut failures = Failures::new();
    for (i, &(what, dir)) in sees.iter().enumerate() {
        let got = Vec3::from_array(over_env.beauty(i));
        let want = match what {
            Sees::Catcher => env.radiance(dir) * (1.0 - alpha[i]),
            Sees::Background => env.radiance(dir),
            Sees::Model => Vec3::from_array(over_nothing.beauty(i)),
        };
        failures.check(
            (got - want).abs().max_element() <= 1e-5 * want.max_element().max(1.0),
            || format!("pixel {i} ({what:?}): {got} vs {want}"),
        );
    }
    failures.assert_none();
}

#[test]
fn alpha_is_the_model_s_coverage_over_a_transparent_background() {
    // Four samples: alpha is the fraction that hit, exactly the coverage AOV, and the beauty
    // is premultiplied (nothing where nothing was hit).
    let (film, sees) = frame(sphere(), "spp = 4\n", Backdrop::Transparent);
    let (alpha, coverage) = (
        film.plane(Channel::A).unwrap(),
        film.plane(Channel::Coverage).unwrap(),
    );
    assert_eq!(alpha, coverage);
    assert!(alpha.iter().any(|&a| a > 0.0 && a < 1.0));
    for (i, &a) in alpha.iter().enumerate() {
        if a == 0.0 {
            assert_eq!(film.beauty(i), [0.0; 3], "pixel {i}");
        }
    }
    // One sample: the hit mask itself.
    let (film, sees1) = frame(sphere(), "", Backdrop::Transparent);
    let alpha = film.plane(Channel::A).unwrap();
    for (i, &(what, _)) in sees1.iter().enumerate() {
        let want = if what == Sees::Model { 1.0 } else { 0.0 };
        assert_eq!(alpha[i], want, "pixel {i}: {what:?}");
    }
    assert!(sees.iter().any(|s| s.0 == Sees::Background));
    // An opaque background keeps no alpha plane (alpha 1).
    assert!(
        frame(sphere(), "", Backdrop::Environment)
            .0
            .plane(Channel::A)
            .is_none()
    );
}

#[test]
fn color_and_blurred_backgrounds_show_behind_the_model_and_do_not_light_it() {
    let colour = Vec3::new(0.2, 0.4, 0.6);
    let (plain, sees) = frame(sphere(), "", Backdrop::Environment);
    let (flat, _) = frame(sphere(), "", Backdrop::Color(colour));
    let sky = EnvMap::builtin_sky();
    let soft = blurred(&sky, 10.0).unwrap();
    let (blur, _) = frame(sphere(), "", Backdrop::Blurred(soft.clone()));
    for (i, &(what, dir)) in sees.iter().enumerate() {
        if what == Sees::Background {
            assert_eq!(flat.beauty(i), colour.to_array(), "pixel {i}");
            assert_eq!(blur.beauty(i), soft.radiance(dir).to_array(), "pixel {i}");
        } else {
            assert_eq!(flat.beauty(i), plain.beauty(i), "pixel {i}");
            assert_eq!(blur.beauty(i), plain.beauty(i), "pixel {i}");
        }
    }
}

fn run(args: &[&str], cwd: &Path) -> std::process::Output {
    common::bin().args(args).current_dir(cwd).output().unwrap()
}

fn ok(o: &std::process::Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "exit {:?}: {err}", o.status.code());
    err
}

fn corpus(name: &str) -> PathBuf {
    common::asset(&format!("corpus/{name}"))
}

#[test]
fn transparent_frames_are_premultiplied_rgba_in_exr_and_straight_rgba_in_png() {
    let tmp = tempfile::tempdir().unwrap();
    let model = common::asset("bunny_res4.glb");
    let model = model.to_str().unwrap();
    let small = [
        "--frames",
        "0",
        "--width",
        "64",
        "--height",
        "48",
        "--spp",
        "4",
        "--lights",
        "24",
        "--no-report",
        "-q",
    ];
    let out = tmp.path().join("t");
    let mut args = vec!["render", model, "--background", "transparent", "--out"];
    args.push(out.to_str().unwrap());
    args.extend(small);
    ok(&run(&args, tmp.path()));
    let exr = read_frame(&out.join("frame_0000.exr")).unwrap();
    let ch = |c: &str| exr.channel(c).unwrap().to_vec();
    let (r, g, b, a) = (ch("R"), ch("G"), ch("B"), ch("A"));
    let png = image::open(out.join("frame_0000.png")).unwrap();
    assert_eq!(png.color(), image::ColorType::Rgba8);
    let png = png.to_rgba8();
    let (mut clear, mut partial, mut solid) = (0, 0, 0);
    for (i, p) in png.pixels().enumerate() {
        let alpha = a[i];
        assert_eq!(p.0[3], (alpha * 255.0 + 0.5) as u8, "pixel {i}");
        if alpha == 0.0 {
            clear += 1;
            assert_eq!([r[i], g[i], b[i]], [0.0; 3], "pixel {i}: premultiplied");
            assert_eq!(&p.0[..3], &[0, 0, 0]);
        } else {
            // PNG's colour is the straight colour: the EXR's divided by alpha.
            let straight = View::default().to_8bit([r[i] / alpha, g[i] / alpha, b[i] / alpha], 1.0);
            assert_eq!(&p.0[..3], &straight, "pixel {i}");
            if alpha < 1.0 {
                partial += 1;
            } else {
                solid += 1;
            }
        }
    }
    assert!(
        clear > 0 && partial > 0 && solid > 0,
        "{clear} {partial} {solid}"
    );

    // The environment behind: alpha 1 in the EXR, and a plain RGB PNG.
    let opaque = tmp.path().join("o");
    let mut args = vec!["render", model, "--out", opaque.to_str().unwrap()];
    args.extend(small);
    ok(&run(&args, tmp.path()));
    let exr = read_frame(&opaque.join("frame_0000.exr")).unwrap();
    assert!(exr.channel("A").unwrap().iter().all(|&v| v == 1.0));
    let png = image::open(opaque.join("frame_0000.png")).unwrap();
    assert_eq!(png.color(), image::ColorType::Rgb8);
}

#[test]
fn transparent_frames_are_the_same_tiled_threaded_and_farmed() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("t.toml");
    fs::write(
        &spec,
        format!(
            "[scene]\nfile = \"{}\"\n[lights]\ncount = 24\n[motion]\nframes = 3\n\
             [render]\nwidth = 64\nheight = 48\nspp = 4\nbackground = \"transparent\"\n",
            common::asset("bunny_res4.glb").display()
        ),
    )
    .unwrap();
    let spec = spec.to_str().unwrap();
    let dir = |n: &str| tmp.path().join(n).to_str().unwrap().to_string();
    let (one, tiled, farm) = (dir("one"), dir("tiled"), dir("farm"));
    let render = |out: &str, more: &[&str]| {
        let mut a = vec!["render", spec, "--out", out, "--no-report", "-q"];
        a.extend_from_slice(more);
        ok(&run(&a, tmp.path()));
    };
    render(&one, &["--tile", "0", "--threads", "2"]);
    render(&tiled, &["--tile", "16", "--threads", "1"]);
    ok(&run(
        &[
            "plan", spec, "--out", &farm, "--jobs", "3", "--by", "both", "--tile", "16",
        ],
        tmp.path(),
    ));
    for k in ["0", "1", "2"] {
        render(
            &farm,
            &["--job", k, "--of", "3", "--by", "both", "--tile", "16"],
        );
    }
    ok(&run(&["assemble", &farm, "--no-report"], tmp.path()));
    for f in 0..3 {
        for ext in ["exr", "png"] {
            let name = format!("frame_{f:04}.{ext}");
            let a = fs::read(Path::new(&one).join(&name)).unwrap();
            for other in [&tiled, &farm] {
                let b = fs::read(Path::new(other).join(&name)).unwrap();
                assert!(a == b, "{other}/{name} differs from the one-process render");
            }
        }
    }
    let exr = read_frame(&Path::new(&farm).join("frame_0001.exr")).unwrap();
    assert!(exr.channel("A").unwrap().iter().any(|&v| v < 1.0));
}

/// A GLB whose JSON chunk is edited by `edit`.
fn edited_glb(path: &Path, edit: impl Fn(&mut Value)) -> Vec<u8> {
    let b = fs::read(path).unwrap();
    let u32_at = |i: usize| u32::from_le_bytes(b[i..i + 4].try_into().unwrap()) as usize;
    let json_len = u32_at(12);
    let mut doc: Value = serde_json::from_slice(&b[20..20 + json_len]).unwrap();
    edit(&mut doc);
    let mut js = serde_json::to_vec(&doc).unwrap();
    while !js.len().is_multiple_of(4) {
        js.push(b' ');
    }
    let rest = &b[20 + json_len..];
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((20 + js.len() + rest.len()) as u32).to_le_bytes());
    out.extend((js.len() as u32).to_le_bytes());
    out.extend(0x4E4F_534Au32.to_le_bytes());
    out.extend(js);
    out.extend(rest);
    out
}

#[test]
fn a_ground_is_added_only_under_models_that_have_none() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    let mut check = |name: &str, scene: Scene, want: bool| {
        let has = has_ground(&scene);
        failures.check(has == want, || format!("{name}: has a ground: {has}"));
    };
    for (name, want) in [
        ("spot.glb", false),
        ("skull.glb", false),
        ("lion_statue.glb", false),
        ("toy_plane.glb", false),
        ("golf_ball.glb", false),
        ("palm_tree.glb", true),
        ("metal_rough_spheres.glb", true),
        ("alpha_mask_panels.glb", true),
    ] {
        check(name, Scene::load(&corpus(name)).unwrap(), want);
    }
    // Two corpus scenes require glTF extensions the loader refuses; their geometry, with the
    // requirement lifted, still has a ground.
    for name in ["sheen_chair_scene.glb", "objects_on_circuit_board.glb"] {
        let bytes = edited_glb(&corpus(name), |d| {
            d.as_object_mut().unwrap().remove("extensionsRequired");
        });
        let path = tmp.path().join(name);
        fs::write(&path, bytes).unwrap();
        check(name, Scene::load(&path).unwrap(), true);
    }
    check(
        "bunny.glb",
        Scene::load(&common::asset("bunny.glb")).unwrap(),
        false,
    );
    let on_plane = common::asset("bunny_on_plane.glb");
    check("bunny_on_plane.glb", Scene::load(&on_plane).unwrap(), true);
    check("shapes", Scene::shapes(), true);
    failures.assert_none();
}

#[test]
fn the_default_animations_keep_their_own_grounds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for spec in [
        "anims/shapes-turntable.toml",
        "anims/bunny-turntable.toml",
        "anims/bunny-spin.toml",
        "anims/paper-bunny.toml",
        "anims/paper-shapes.toml",
    ] {
        let text = fs::read_to_string(root.join(spec)).unwrap().replace(
            "../assets/",
            &format!("{}/", common::assets_dir().display()),
        );
        let anim = Animation::parse(&text, &root.join(spec), &AnimFlags::default()).unwrap();
        let inputs = Inputs::load(&anim).unwrap();
        assert_eq!(inputs.scene.added_ground, None, "{spec}");
        assert!(inputs.scene.catcher.is_empty(), "{spec}");
    }
}

#[test]
fn the_added_ground_frames_the_model_and_catches_over_transparency() {
    let body = |scene: &str, render: &str| {
        format!(
            "[scene]\nfile = \"{}\"\n{scene}\n[lights]\ncount = 8\n[render]\nwidth = 16\nheight = 12\n{render}",
            common::asset("bunny_res4.glb").display()
        )
    };
    let load = |text: &str| {
        let anim = Animation::parse(text, Path::new("g.toml"), &AnimFlags::default()).unwrap();
        let inputs = Inputs::load(&anim).unwrap();
        (anim, inputs)
    };
    let (anim, plain) = load(&body("", ""));
    let model = Scene::load(&common::asset("bunny_res4.glb")).unwrap();
    let first = plain.scene.added_ground.expect("a ground under the bunny");
    assert_eq!(first, model.triangles.len());
    assert!(plain.scene.catcher.is_empty());
    // The camera frames the model, as it did before the ground came.
    let (lo, hi) = model.bounds();
    let camera = anim.camera(&plain.scene, 0).unwrap();
    assert!((camera.target - (lo + hi) * 0.5).length() < 1e-6);
    // Over a transparent background, or asked to, the ground is a shadow catcher.
    let (_, t) = load(&body("", "background = \"transparent\""));
    assert!(t.scene.is_catcher(first) && !t.scene.is_catcher(first - 1));
    let (_, c) = load(&body("shadow_catcher = true", ""));
    assert!(c.scene.is_catcher(first));
    let (_, none) = load(&body("ground = \"none\"", ""));
    assert_eq!(none.scene.added_ground, None);
    let plane = body("ground = \"always\"", "").replace("bunny_res4.glb", "bunny_on_plane.glb");
    let (_, always) = load(&plane);
    assert!(always.scene.added_ground.is_some());
}

#[test]
fn a_z_up_model_is_stood_up_with_its_camera() {
    let model = Scene::load(&common::asset("bunny_res4.glb")).unwrap();
    // The bunny as a Z-up file would hold it: (x, y, z) → (x, −z, y).
    let to_z_up = Mat4::from_cols(Vec4::X, Vec4::Z, -Vec4::Y, Vec4::W);
    let mut z_up = model.transformed(to_z_up);
    z_up.camera = Some(SceneCamera {
        position: Vec3::new(0.0, -1.0, 0.2),
        forward: Vec3::Y,
        up: Vec3::Z,
        vfov_deg: 30.0,
    });
    let upright = z_up.stood_up(Up::Z);
    assert_eq!(upright.positions, model.positions);
    assert_eq!(upright.triangles, model.triangles);
    for (a, b) in upright.normals.iter().zip(&model.normals) {
        assert!((*a - *b).length() < 1e-6);
    }
    let c = upright.camera.unwrap();
    assert_eq!(
        (c.position, c.forward, c.up),
        (Vec3::new(0.0, 0.2, 1.0), Vec3::NEG_Z, Vec3::Y)
    );
    // Through a spec: a Y-up file read as Z-up turns its +Z up.
    let text = format!(
        "[scene]\nfile = \"{}\"\nup = \"z\"\nground = \"none\"\n[lights]\ncount = 8\n",
        common::asset("bunny_res4.glb").display()
    );
    let anim = Animation::parse(&text, Path::new("z.toml"), &AnimFlags::default()).unwrap();
    let inputs = Inputs::load(&anim).unwrap();
    let ((lo, hi), (mlo, mhi)) = (inputs.scene.bounds(), model.bounds());
    assert_eq!((lo.y, hi.y), (mlo.z, mhi.z));
}

/// A glTF of one quad mesh placed by four nodes, with extras and names.
fn four_quads() -> Vec<u8> {
    let mut b = Vec::new();
    for v in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 0.0, -1.0],
        [0.0, 0.0, -1.0],
    ] {
        v.iter().for_each(|c| b.extend_from_slice(&c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    let node = |name: &str, x: f32, extras: Value| {
        let mut n = json!({"name": name, "mesh": 0, "translation": [x, 0.0, 0.0]});
        if !extras.is_null() {
            n["extras"] = extras;
        }
        n
    };
    serde_json::to_vec(&json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            node("Flagged", 0.0, json!({"shadow_catcher": true})),
            node("FromBlender", 2.0, json!({"shadow_catcher": 1})),
            node("Plain", 4.0, json!({"shadow_catcher": false, "other": 3})),
            node("Named", 6.0, Value::Null),
        ],
        "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, -1], "max": [1, 0, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 12}
        ],
        "buffers": [{"byteLength": 60,
                     "uri": format!("data:application/octet-stream;base64,{}", common::base64(&b))}]
    }))
    .unwrap()
}

#[test]
fn catchers_come_from_node_extras_and_from_names() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("quads.gltf");
    fs::write(&file, four_quads()).unwrap();
    let load = |catchers: &str| {
        let text = format!(
            "[scene]\nfile = \"{}\"\nground = \"none\"\n{catchers}\n[lights]\ncount = 8\n",
            file.display()
        );
        Animation::parse(&text, Path::new("c.toml"), &AnimFlags::default())
            .and_then(|a| Inputs::load(&a))
    };
    let by_extras = load("").unwrap().scene;
    let flags: Vec<bool> = (0..8).map(|t| by_extras.is_catcher(t)).collect();
    assert_eq!(flags, [true, true, true, true, false, false, false, false]);
    let named = load("catchers = [\"Named\", \"Plain\"]").unwrap().scene;
    assert!((0..8).all(|t| named.is_catcher(t)));
    // A mesh name marks every node that places it.
    let by_mesh = load("catchers = [\"quad\"]").unwrap().scene;
    assert!((0..8).all(|t| by_mesh.is_catcher(t)));
    let err = format!("{:#}", load("catchers = [\"Flor\"]").err().unwrap());
    assert!(
        err.contains("c.toml") && err.contains("\"Flor\"") && err.contains("Flagged, quad"),
        "{err}"
    );
}

#[test]
fn background_and_scene_settings_are_checked_and_named() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = |name: &str, body: &str| {
        let p = tmp.path().join(name);
        fs::write(&p, format!("[scene]\nbuiltin = \"shapes\"\n{body}")).unwrap();
        p.to_str().unwrap().to_string()
    };
    let fails = |args: &[&str], want: &[&str]| {
        let o = run(args, tmp.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        for w in want {
            assert!(err.contains(w), "{args:?}: {err}");
        }
    };
    let plain = spec("p.toml", "");
    fails(
        &["render", &plain, "--background-color", "1,0,0"],
        &[
            "--background-color",
            "applies only with background = \"color\"",
        ],
    );
    fails(
        &[
            "render",
            &plain,
            "--background",
            "color",
            "--background-color",
            "1,-1,0",
        ],
        &["--background-color", "≥ 0"],
    );
    fails(&["render", &plain, "--background", "sepia"], &["sepia"]);
    fails(
        &[
            "render",
            &spec(
                "b.toml",
                "[render]\nbackground = \"blurred\"\nbackground_blur = 0.5\n",
            ),
        ],
        &["b.toml", "[render] background_blur = 0.5", "1 to 90"],
    );
    fails(
        &["render", &spec("u.toml", "up = \"x\"\n")],
        &["u.toml", "up axis \"x\""],
    );
    fails(
        &["render", &spec("g.toml", "ground = \"sometimes\"\n")],
        &["g.toml", "sometimes"],
    );
    fails(
        &["render", &spec("c.toml", "catchers = [\"Floor\"]\n")],
        &["c.toml", "catchers", "shapes"],
    );
    // Issue 40: --env lights a spec too (over its [environment]); a missing map is named.
    fails(
        &["render", &plain, "--env", "x.hdr"],
        &["x.hdr", "environment map not found"],
    );
    let model = common::asset("bunny_res4.glb");
    fails(
        &["plan", model.to_str().unwrap(), "--jobs", "2"],
        &[
            "bunny_res4.glb",
            "not an animation spec",
            "envshadow render",
        ],
    );
}

#[test]
fn settings_txt_names_the_new_settings_only_when_they_are_not_the_defaults() {
    let lines = |body: &str| {
        common::animation(body)
            .settings_record()
            .unwrap()
            .lines
            .into_iter()
            .map(|(k, _)| k)
            .collect::<Vec<_>>()
    };
    let plain = lines("");
    assert!(
        !plain
            .iter()
            .any(|k| k.contains("background") || k.starts_with("[scene] up"))
    );
    let set = lines("[render]\nbackground = \"transparent\"\n");
    assert!(set.contains(&"[render] background".to_string()), "{set:?}");
}

#[test]
fn render_a_model_renders_its_default_turntable() {
    let tmp = tempfile::tempdir().unwrap();
    let spot = corpus("spot.glb");
    let err = ok(&run(
        &[
            "render",
            spot.to_str().unwrap(),
            "--frames",
            "0..2",
            "--width",
            "48",
            "--height",
            "36",
            "--lights",
            "16",
            "--spp",
            "1",
        ],
        tmp.path(),
    ));
    assert!(err.contains("added a grey ground"), "{err}");
    assert!(err.contains("spot: 2 frames rendered"), "{err}");
    let out = tmp.path().join("out/spot");
    for f in [
        "frame_0000.exr",
        "frame_0001.png",
        "report.html",
        "settings.txt",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let settings = fs::read_to_string(out.join("settings.txt")).unwrap();
    assert!(settings.contains("[motion] frames = 72"), "{settings}");
    assert!(
        settings.contains("[environment] builtin = sky"),
        "{settings}"
    );
    let rows = envshadow::output::stats::read_stats(&out.join("stats.csv")).unwrap();
    assert_eq!((rows.len(), rows[0].width, rows[0].spp), (2, 48, 1));

    // --env, --background and a relative model path.
    fs::copy(&spot, tmp.path().join("my spot.glb")).unwrap();
    let map = common::asset("grace.hdr");
    ok(&run(
        &[
            "render",
            "my spot.glb",
            "--env",
            map.to_str().unwrap(),
            "--background",
            "transparent",
            "--frames",
            "3",
            "--width",
            "32",
            "--height",
            "24",
            "--lights",
            "16",
            "--no-report",
            "-q",
        ],
        tmp.path(),
    ));
    let out = tmp.path().join("out/my spot");
    let settings = fs::read_to_string(out.join("settings.txt")).unwrap();
    assert!(
        settings.contains("[environment] file = sha256:"),
        "{settings}"
    );
    let png = image::open(out.join("frame_0003.png")).unwrap();
    assert_eq!(png.color(), image::ColorType::Rgba8);
    fails_on_missing(tmp.path());
}

/// A missing model is named, as a spec's missing scene file is.
fn fails_on_missing(dir: &Path) {
    let o = run(&["render", "nowhere.glb"], dir);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("nowhere.glb") && !err.contains("UTF-8"),
        "{err}"
    );
}
