//! Rendering against analytic answers and invariants.

use crate::common::{self, Failures};

use envshadow::film::Channel;
use envshadow::frame::render_frame;

use envshadow::inputs::Inputs;

use envshadow::envmap::EnvMap;
use envshadow::lights::{Light, LightSet, Sampler};
use envshadow::predict::Method;
use envshadow::run::Silent;
use glam::Vec3;

fn uniform_env(radiance: f32) -> EnvMap {
    let (w, h) = (64, 32);
    EnvMap::from_texels(w, h, vec![Vec3::splat(radiance); w * h], "uniform").expect("valid map")
}

fn one_light(dir: Vec3) -> LightSet {
    LightSet::from_lights(vec![Light {
        dir: dir.normalize(),
        energy: Vec3::splat(1.0),
        solid_angle: 1e-3,
    }])
}

/// Ray–sphere test for t > 0.
fn hits_sphere(o: Vec3, d: Vec3, c: Vec3, r: f32) -> bool {
    let oc = o - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.length_squared() - r * r);
    disc >= 0.0 && (-b + disc.sqrt()) > 0.0
}

#[test]
fn sphere_shadow_on_plane_matches_the_analytic_shadow() {
    let (centre, r) = (Vec3::new(0.0, 1.0, 0.0), 1.0);
    let mut scene = common::scene_with_materials(&[0.5, 0.8]);
    common::add_plane(&mut scene, 40.0, 0.0, 0);
    common::add_sphere(&mut scene, centre, r, 256, 512, 1);
    let light = Vec3::new(1.0, 1.0, 0.3).normalize();
    let inputs = Inputs::new(scene, uniform_env(0.0), one_light(light));
    let anim = common::animation(
        "[camera]\nposition = [-1.4, 9.0, -0.4]\ntarget = [-1.4, 0.0, -0.4]\nup = [0.0, 0.0, -1.0]\nvfov = 32.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = 200\nheight = 200\ntile = 32\n",
    );
    let cam = anim.camera(&inputs.scene, 0).unwrap();
    // Classify every pixel analytically: 0 lit plane, 1 shadowed plane, 2 sphere or sky.
    let (w, h) = (200usize, 200usize);
    let mut class = vec![0u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let d = cam.ray_dir(x as u32, y as u32);
            class[y * w + x] = if hits_sphere(cam.position, d, centre, r) || d.y >= 0.0 {
                2
            } else {
                let p = cam.position + d * (-cam.position.y / d.y);
                u8::from(hits_sphere(p, light, centre, r))
            };
        }
    }
    let mut failures = Failures::new();
    for method in [Method::BRUTE, Method::DEFAULT] {
        failures.case(&method.to_string(), || {
            let mut anim = anim.clone();
            anim.render.method = method;
            let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
            check_shadow_mask(film.plane(Channel::Visible).unwrap(), &class, w, h, method);
        });
    }
    failures.assert_none();
}

fn check_shadow_mask(visible: &[f32], class: &[u8], w: usize, h: usize, method: Method) {
    let (mut compared, mut agree, mut shadowed) = (0, 0, 0);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let c = class[y * w + x];
            let band = (0..9).any(|k| class[(y + k / 3 - 1) * w + x + k % 3 - 1] != c);
            if c == 2 || band {
                continue;
            }
            compared += 1;
            shadowed += usize::from(c == 1);
            let rendered_shadow = visible[y * w + x] < 0.5;
            agree += usize::from(rendered_shadow == (c == 1));
        }
    }
    assert!(
        shadowed > 2000,
        "the view must contain the shadow ({shadowed} px)"
    );
    assert!(compared - shadowed > 2000, "and lit plane");
    let share = agree as f64 / compared as f64;
    assert!(
        share >= 0.995,
        "{method}: {agree}/{compared} pixels agree ({share:.4})"
    );
}

#[test]
fn open_plane_under_uniform_white_sky_renders_albedo_times_radiance() {
    let radiance = 2.0;
    let albedo = 0.6;
    let mut scene = common::scene_with_materials(&[albedo]);
    common::add_plane(&mut scene, 10.0, 0.0, 0);
    let env = uniform_env(radiance);
    let lights = LightSet::build(&env, 400, Sampler::Sis).unwrap();
    let inputs = Inputs::new(scene, env, lights);
    let anim = common::animation(
        "[camera]\nposition = [0.0, 3.0, 0.5]\ntarget = [0.0, 0.0, 0.0]\nvfov = 30.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = 32\nheight = 32\n",
    );
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let want = albedo * radiance;
    for p in &film.layer(Channel::BEAUTY).unwrap() {
        for c in p {
            assert!((c - want).abs() <= 0.01 * want, "{c} vs {want}");
        }
    }
}

#[test]
fn no_shadow_acne_on_the_ground_plane_at_grazing_lights() {
    // A large plane seen at a low angle, lit by lights 0.5°–3° above the horizon from
    // several azimuths: nothing can block them, so every plane pixel must see every light.
    let mut scene = common::scene_with_materials(&[0.5]);
    common::add_plane(&mut scene, 200.0, 0.0, 0);
    let mut lights = Vec::new();
    for (k, el) in [0.5f32, 1.0, 2.0, 3.0].iter().enumerate() {
        for az in 0..6 {
            let (el, az) = (
                el.to_radians(),
                (az as f32 * 60.0 + k as f32 * 7.0).to_radians(),
            );
            lights.push(Light {
                dir: Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos()),
                energy: Vec3::ONE,
                solid_angle: 1e-3,
            });
        }
    }
    let inputs = Inputs::new(scene, uniform_env(0.0), LightSet::from_lights(lights));
    let anim = common::animation(
        "[camera]\nposition = [3.0, 1.5, 40.0]\ntarget = [0.0, 0.0, 0.0]\nvfov = 40.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = 120\nheight = 90\nmethod = \"brute\"\n",
    );
    let (film, stats) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    assert!(stats.counts.queries > 100_000);
    let plane_px: Vec<f32> = film
        .plane(Channel::Visible)
        .unwrap()
        .iter()
        .zip(film.plane(Channel::Rays).unwrap())
        .filter(|(_, r)| **r > 0.0)
        .map(|(v, _)| *v)
        .collect();
    assert!(plane_px.len() > 5000);
    let dark = plane_px.iter().filter(|v| **v < 1.0).count();
    assert_eq!(dark, 0, "{dark} plane pixels see a grazing light blocked");
}

#[test]
fn brute_force_equals_no_shadows_where_nothing_can_block() {
    let mut scene = common::scene_with_materials(&[0.7]);
    common::add_plane(&mut scene, 10.0, 0.0, 0);
    let env = EnvMap::builtin_sky();
    let lights = LightSet::build(&env, 64, Sampler::Sis).unwrap();
    let inputs = Inputs::new(scene, env, lights);
    let mut anim = common::animation(
        "[camera]\nposition = [0.0, 2.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n[motion]\nkind = \"none\"\n[render]\nwidth = 48\nheight = 32\n",
    );
    anim.render.method = Method::BRUTE;
    let (brute, bs) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    anim.render.method = Method::NONE;
    let (none, ns) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    assert_eq!(
        brute.layer(Channel::BEAUTY).unwrap(),
        none.layer(Channel::BEAUTY).unwrap()
    );
    assert_eq!(bs.counts.queries, ns.counts.queries);
    assert_eq!(bs.counts.rays, bs.counts.queries);
    assert_eq!(ns.counts.rays, 0);
}

#[test]
fn shadows_remove_energy_and_never_add_it() {
    // Every pixel of the brute-force shapes frame is at most its unshadowed value, and the
    // frame as a whole is darker: shadows only ever take light away.
    let anim0 = common::animation(
        "[lights]\ncount = 60\n[motion]\nkind = \"none\"\n[render]\nwidth = 80\nheight = 60\n",
    );
    let inputs = Inputs::load(&anim0).unwrap();
    let mut anim = anim0.clone();
    anim.render.method = Method::BRUTE;
    let (brute, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    anim.render.method = Method::NONE;
    let (none, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let (mut sb, mut sn) = (0.0f64, 0.0f64);
    for (b, n) in brute
        .layer(Channel::BEAUTY)
        .unwrap()
        .iter()
        .zip(&none.layer(Channel::BEAUTY).unwrap())
    {
        for c in 0..3 {
            assert!(b[c] <= n[c] * (1.0 + 1e-6) + 1e-9, "{b:?} > {n:?}");
            sb += b[c] as f64;
            sn += n[c] as f64;
        }
    }
    assert!(sb < sn * 0.99, "the shapes frame has shadows: {sb} vs {sn}");
}
