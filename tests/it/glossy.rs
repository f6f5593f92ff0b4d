//! Glossy lobes narrower than the lights can resolve (issue 42): shadows still darken the
//! reflection where the environment stands in for the lights, a mirror reflects its occluders
//! sharply, and the export carries the map
//! a reference renderer needs. (Where the lights stand in and where they do not is tested in
//! `glossy::tests`; the dots' disappearance is measured against Mitsuba in docs/materials.md.)

use glam::Vec3;

use crate::common;
use envshadow::envmap::EnvMap;
use envshadow::frame::render_frame;
use envshadow::inputs::Inputs;
use envshadow::lights::{LightSet, Sampler};
use envshadow::run::Silent;
use envshadow::scene::{Material, Scene};

/// Spheres of the given (metallic, roughness) in a row along x, radius 0.4, 1 apart, on no
/// ground; and, with `blocker`, a large dark dielectric slab above them all.
fn spheres(materials: &[(f32, f32)], blocker: bool) -> Scene {
    let mut scene = Scene {
        materials: materials
            .iter()
            .map(|&(metallic, roughness)| Material {
                base_color: Vec3::splat(0.9),
                metallic,
                roughness,
                ..Material::default()
            })
            .collect(),
        source: "glossy spheres".into(),
        ..Scene::default()
    };
    let left = -(materials.len() as f32 - 1.0) / 2.0;
    for i in 0..materials.len() {
        let centre = Vec3::new(left + i as f32, 0.0, 0.0);
        common::add_sphere(&mut scene, centre, 0.4, 48, 96, i as u32);
    }
    if blocker {
        let m = scene.materials.len() as u32;
        scene
            .materials
            .push(Material::lambert("slab", Vec3::splat(0.1)));
        common::add_plane(&mut scene, 30.0, 0.9, m);
    }
    scene
}

/// Each sphere's pixels of a `width × 40` frame of `scene` under the studio map reduced to
/// `lights` lights by brute force (every light traced: the shading alone), looking along −z,
/// as (x, y, luminance); `glossy_env` as `[render] glossy_env`.
fn render_spheres(
    scene: Scene,
    lights: usize,
    count: usize,
    width: u32,
    glossy_env: bool,
) -> Vec<Vec<(u32, u32, f64)>> {
    let env = EnvMap::load(&common::asset("studio_small_03_1k.hdr")).unwrap();
    let set = LightSet::build(&env, lights, Sampler::Sis).unwrap();
    let inputs = Inputs::new(scene, env, set);
    let anim = common::animation(&format!(
        "[camera]\nposition = [0.0, 0.0, 6.0]\ntarget = [0.0, 0.0, 0.0]\nvfov = 9.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = {width}\nheight = 40\nmethod = \"brute\"\n\
         glossy_env = {glossy_env}\n"
    ));
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let cam = anim.camera(&inputs.scene, 0).unwrap();
    let mut out = vec![Vec::new(); count];
    let left = -(count as f32 - 1.0) / 2.0;
    for y in 0..40u32 {
        for x in 0..width {
            // The pixel's ray against each sphere, well inside its outline.
            let d = cam.ray_dir(x, y);
            let o = cam.position;
            for (i, px) in out.iter_mut().enumerate() {
                let c = Vec3::new(left + i as f32, 0.0, 0.0);
                let t = (c - o).dot(d);
                if (o + d * t - c).length() < 0.4 * 0.85 {
                    let b = film.beauty((y * width + x) as usize);
                    let lum = 0.2126 * f64::from(b[0])
                        + 0.7152 * f64::from(b[1])
                        + 0.0722 * f64::from(b[2]);
                    px.push((x, y, lum));
                }
            }
        }
    }
    out
}

/// Where the environment stands in for the lights, a slab that hides the upper sky still
/// darkens the reflection (the environment term is weighted by the share of the lobe's light
/// its rays find unblocked): a mirror-like metal sphere under the slab is darker than without
/// it.
#[test]
fn shadows_still_darken_a_reflection_taken_from_the_environment() {
    let materials = [(1.0, 0.1), (0.0, 0.1)];
    let open = render_spheres(spheres(&materials, false), 200, 2, 80, true);
    let covered = render_spheres(spheres(&materials, true), 200, 2, 80, true);
    for i in 0..2 {
        let sum = |px: &[(u32, u32, f64)]| px.iter().map(|p| p.2).sum::<f64>();
        let (o, c) = (sum(&open[i]), sum(&covered[i]));
        assert!(c < 0.8 * o, "sphere {i}: {c} covered vs {o} open");
    }
}

/// The reference renderer sees envshadow's own map (scripts/reference-mitsuba.py): the export
/// writes its texels as envshadow decoded them (intensity applied), with their size and the
/// turn from the map's frame to the world's.
#[test]
fn the_export_carries_the_map_as_envshadow_decoded_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("exp");
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let status = common::bin()
        .args(["export", "anims/shapes-turntable.toml", "--frame", "3"])
        .args(["--lights", "20", "--width", "16", "--height", "12"])
        .arg("--out")
        .arg(&out)
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("frame.json")).unwrap()).unwrap();
    let (w, h) = (
        meta["env_width"].as_u64().unwrap() as usize,
        meta["env_height"].as_u64().unwrap() as usize,
    );
    let bytes = std::fs::read(out.join("env.f32")).unwrap();
    assert_eq!(bytes.len(), w * h * 12);
    let texels: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let anim = envshadow::anim::Animation::load(
        &root.join("anims/shapes-turntable.toml"),
        &envshadow::anim::AnimFlags::default(),
    )
    .unwrap();
    let inputs = Inputs::load(&anim).unwrap();
    assert_eq!((inputs.env.width, inputs.env.height), (w, h));
    for (i, t) in inputs.env.texels.iter().enumerate() {
        assert_eq!(&texels[3 * i..3 * i + 3], &t.to_array(), "texel {i}");
    }
    let turn = anim.motion.environment_degrees(3).unwrap_or(0.0);
    assert_eq!(
        meta["env_rotation_deg"].as_f64().unwrap() as f32,
        inputs.env.rotation_deg + turn
    );
}

/// Issue 42: a mirror reflects exactly what blocks it. Under the slab, every pixel of a mirror
/// sphere whose reflected ray rises into the slab is black (the metal has no diffuse part, and
/// the ray into the lobe finds the slab), however near the slab's edge on the sphere; the
/// pixels whose reflected ray falls below the horizon see the lower sky. Before the lobe's rays
/// (the share of visible light measured over the lights near the lobe, a lobe 0.5 δ wide), the
/// reflection of the slab's edge was blurred over the lights' spacing into the black zone.
#[test]
fn a_mirror_reflects_its_occluder_as_sharply_as_it_sees_it() {
    let width = 80;
    let env = EnvMap::load(&common::asset("studio_small_03_1k.hdr")).unwrap();
    let set = LightSet::build(&env, 200, Sampler::Sis).unwrap();
    let inputs = Inputs::new(spheres(&[(1.0, 0.0)], true), env, set);
    let anim = common::animation(&format!(
        "[camera]\nposition = [0.0, 0.0, 6.0]\ntarget = [0.0, 0.0, 0.0]\nvfov = 9.0\n\
         [motion]\nkind = \"none\"\n[render]\nwidth = {width}\nheight = 40\nmethod = \"brute\"\n"
    ));
    let (film, _) = render_frame(&anim, &inputs, 0, None, &Silent).unwrap();
    let cam = anim.camera(&inputs.scene, 0).unwrap();
    let (mut blocked, mut open) = (Vec::new(), Vec::new());
    for y in 0..40u32 {
        for x in 0..width {
            // The pixel's ray against the sphere (centre 0, radius 0.4), well inside its
            // outline, and the ray it reflects.
            let (o, d) = (cam.position, cam.ray_dir(x, y));
            let t = -o.dot(d);
            let miss = (o + d * t).length();
            if miss > 0.4 * 0.85 {
                continue;
            }
            let p = o + d * (t - (0.16 - miss * miss).sqrt());
            let n = p.normalize();
            let mirror = d - n * (2.0 * d.dot(n));
            let b = film.beauty((y * width + x) as usize);
            let lum =
                0.2126 * f64::from(b[0]) + 0.7152 * f64::from(b[1]) + 0.0722 * f64::from(b[2]);
            if mirror.y > 0.1 {
                blocked.push(lum);
            } else if mirror.y < -0.1 {
                open.push(lum);
            }
        }
    }
    assert!(
        blocked.len() > 50 && open.len() > 50,
        "{} {}",
        blocked.len(),
        open.len()
    );
    let mean = open.iter().sum::<f64>() / open.len() as f64;
    assert!(mean > 0.01, "the lower sky is reflected: {mean}");
    let worst = blocked.iter().cloned().fold(0.0, f64::max);
    assert!(
        worst <= 1e-3 * mean,
        "a pixel reflecting the slab is lit: {worst} against {mean} for the open ones"
    );
}
