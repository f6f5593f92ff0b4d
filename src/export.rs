//! `envshadow export`: one frame's exact inputs for another renderer (scripts/compare-mitsuba.sh):
//! the posed triangles, vertex normals, texture coordinates and `COLOR_0` alpha, and per face
//! the base colour factor and material index, as a binary PLY; the lights as `lights.json`, the
//! primary-ray direction of every sample of every pixel (`--spp`; with one sample, the pixel
//! centre), what envshadow's primary ray found at each sample (`surface.f32`: the material
//! there with its textures read, and the shading normal after the normal map), the materials
//! (`materials.json`: names, and the alpha mode, cutoff and base colour alpha with the alpha
//! texture's slot, so another renderer can cut out what envshadow cuts out; each alpha
//! texture's decoded level 0 as `alpha_T.f32`), and a `frame.json` with the camera, the sample
//! pattern and the shadow-ray offset. With these, an independent renderer
//! can evaluate exactly what envshadow's `brute` method does: the material's BRDF for every
//! light at every sample, shadow rays from the hit point moved along the geometric normal by
//! its error bound (`src/offset.rs`: `dot(|ng|, err)` with `err = gamma7 · (|p0| + |p1 − p0| +
//! |p2 − p0|)` per axis, `frame.json`'s `shadow_offset_gamma`), a pixel the plain mean of its
//! samples.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use serde_json::json;

use crate::anim::{AnimFlags, Animation};
use crate::camera::Camera;
use crate::context::FrameContext;
use crate::error::{Result, input_error};
use crate::inputs::Inputs;
use crate::key::Key;
use crate::output::write_atomic_with;
use crate::samples::Samples;
use crate::scene::{AlphaMode, AlphaTest, Model, Scene, TextureSlot, Wrap, coverage_threshold};

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// The animation spec, e.g. anims/bunny-turntable.toml.
    pub spec: PathBuf,
    /// Which frame.
    #[arg(long, default_value_t = 0)]
    pub frame: usize,
    /// The spec's settings export reads — light count and sampler, width and height, samples
    /// per pixel and the filter, material overrides — and the folder it writes (`--out DIR`,
    /// required): scene.ply, lights.json, primary.f32, surface.f32, materials.json,
    /// frame.json, env.f32, and alpha_T.f32 for each alpha texture of a cut-out material.
    #[command(flatten)]
    pub flags: AnimFlags,
}

/// Floats per sample in surface.f32.
pub const SURFACE_FLOATS: usize = 19;

/// What [`run`] wrote.
#[derive(Clone, Debug)]
pub struct Exported {
    pub frame: usize,
    pub triangles: usize,
    pub lights: usize,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel: primary.f32 holds `width × height × spp` directions.
    pub spp: u32,
    pub dir: PathBuf,
    /// What the scene loader skipped.
    pub warnings: Vec<String>,
}

/// The settings an export reads; the others would change nothing it writes.
/// (The material flags, `--clay` and `--lambert`, are not settings: export reads both.)
const READS: [Key; 10] = [
    Key::Up,
    Key::Ground,
    Key::Count,
    Key::Sampler,
    Key::Width,
    Key::Height,
    Key::Spp,
    Key::Filter,
    Key::FilterWidth,
    Key::Dir,
];

/// `envshadow export`.
pub fn run(args: &ExportArgs) -> Result<Exported> {
    let flags = &args.flags;
    flags.refuse_unread(&READS, "export")?;
    let Some(dir) = flags.output.dir.clone() else {
        return Err(input_error(
            "--out",
            "export needs the folder to write: --out DIR",
        ));
    };
    let anim = Animation::load(&args.spec, flags)?;
    if !anim.frames.contains(args.frame) {
        return Err(input_error(
            &args.spec,
            format!(
                "frame {} is outside the animation's frames ({})",
                args.frame, anim.frames
            ),
        ));
    }
    let inputs = Inputs::load(&anim)?;
    // The frame's geometry as a render poses it: the file's animation, then a spin.
    let pivot = anim.pivot(&inputs.scene)?;
    let posed = inputs.posed(&anim, args.frame, anim.scene_transform(args.frame, pivot))?;
    let scene = posed.as_ref().unwrap_or(&inputs.scene);
    let camera = anim.camera(&inputs.scene, args.frame)?;
    let samples = anim.render.samples();
    let dir = &dir;
    fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;

    write_ply(&dir.join("scene.ply"), scene, &anim, args.frame)?;
    write_primary(&dir.join("primary.f32"), &camera, &samples)?;
    let accel = scene.accel();
    let lights = inputs.lights_at(&anim, args.frame);
    let ctx = FrameContext::new(scene, &accel, camera, &lights, &inputs.env)
        .with_samples(samples.clone())
        .with_terminator_offset(anim.render.terminator_offset);
    write_surface(&dir.join("surface.f32"), &ctx)?;
    write_materials(dir, scene)?;

    // The frame's lights: turned with the environment where it turns.
    lights.write_json(&dir.join("lights.json"))?;
    write_env(&dir.join("env.f32"), &inputs.env)?;
    let turn = anim.motion.environment_degrees(args.frame).unwrap_or(0.0);
    let meta = json!({
        "spec": anim.spec_path.display().to_string(),
        "frame": args.frame,
        "width": camera.width,
        "height": camera.height,
        "camera_position": camera.position.to_array(),
        "camera_target": camera.target.to_array(),
        "camera_up": camera.up.to_array(),
        "vfov_deg": camera.vfov_deg,
        "spp": samples.spp(),
        "filter": samples.filter.name(),
        "filter_width": samples.width,
        "shadow_offset_gamma": crate::offset::gamma(7),
        // The world point the positions and the camera count from (scene::render_origin).
        "origin": inputs.scene.origin.to_array(),
        "triangles": scene.triangles.len(),
        "lights": inputs.lights.len(),
        "surface_floats": SURFACE_FLOATS,
        // env.f32: the map's texels as envshadow decoded them (intensity applied), and the
        // turn from the map's own frame to the world's (its rotation and this frame's turn).
        "env_width": inputs.env.width,
        "env_height": inputs.env.height,
        "env_rotation_deg": inputs.env.rotation_deg + turn,
        "env_source": inputs.env.source,
    });
    crate::output::write_atomic(
        &dir.join("frame.json"),
        serde_json::to_string_pretty(&meta)?.as_bytes(),
    )?;
    Ok(Exported {
        frame: args.frame,
        triangles: scene.triangles.len(),
        lights: inputs.lights.len(),
        width: camera.width,
        height: camera.height,
        spp: samples.spp(),
        dir: dir.clone(),
        warnings: inputs.scene.warnings.clone(),
    })
}

/// scene.ply: per vertex its position, normal, texture coordinates (sets 0 and 1; set 1 is
/// set 0 where the scene has no second set) and `COLOR_0` alpha (1 without vertex colours);
/// per face its material's linear base colour factor and the material's index in
/// materials.json.
fn write_ply(path: &Path, scene: &Scene, anim: &Animation, frame: usize) -> Result<()> {
    write_atomic_with(path, |tmp| {
        let mut f = BufWriter::new(fs::File::create(tmp)?);
        write!(
            f,
            "ply\nformat binary_little_endian 1.0\ncomment envshadow export of {} frame {}\n\
             element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             property float u\nproperty float v\nproperty float u1\nproperty float v1\n\
             property float alpha\n\
             element face {}\nproperty list uchar int vertex_indices\n\
             property float r\nproperty float g\nproperty float b\nproperty int material\n\
             end_header\n",
            anim.spec_path.display(),
            frame,
            scene.positions.len(),
            scene.triangles.len()
        )?;
        let uvs1 = if scene.uvs1.is_empty() {
            &scene.uvs
        } else {
            &scene.uvs1
        };
        for (i, (p, n)) in scene.positions.iter().zip(&scene.normals).enumerate() {
            let alpha = scene.colors.get(i).map_or(1.0, |c| c.w);
            let uv = scene.uvs[i]
                .to_array()
                .into_iter()
                .chain(uvs1[i].to_array());
            for c in p.to_array().into_iter().chain(n.to_array()).chain(uv) {
                f.write_all(&c.to_le_bytes())?;
            }
            f.write_all(&alpha.to_le_bytes())?;
        }
        for (t, &m) in scene.triangles.iter().zip(&scene.tri_material) {
            f.write_all(&[3u8])?;
            for &i in t {
                f.write_all(&(i as i32).to_le_bytes())?;
            }
            let albedo = scene.materials[m as usize].base_color;
            for c in albedo.to_array() {
                f.write_all(&c.to_le_bytes())?;
            }
            f.write_all(&(m as i32).to_le_bytes())?;
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })
}

/// primary.f32: the unit direction of every sample's ray, pixel by pixel row by row from
/// the top, each pixel's k × k samples in stratum order (row j, column i): an array
/// (height, width, k·k, 3). These are the renderer's directions bit for bit: sample (i, j)
/// of pixel (x, y) is the renderer's sample (k·x + i, k·y + j), whose direction
/// `FrameContext::sample_dir` makes from the same two calls. With one sample the offset is
/// zero and `ray_dir_at` is `ray_dir`: the pixel centres, as before there were samples.
fn write_primary(path: &Path, camera: &Camera, samples: &Samples) -> Result<()> {
    let k = samples.k;
    write_atomic_with(path, |tmp| {
        let mut f = BufWriter::new(fs::File::create(tmp)?);
        for y in 0..camera.height {
            for x in 0..camera.width {
                for j in 0..k {
                    for i in 0..k {
                        let (dx, dy) = samples.offset(x, y, i, j);
                        for c in camera.ray_dir_at(x, y, dx, dy).to_array() {
                            f.write_all(&c.to_le_bytes())?;
                        }
                    }
                }
            }
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })
}

/// surface.f32: per sample, in primary.f32's order, SURFACE_FLOATS floats: whether the ray
/// hit, the base colour (3), metallic, roughness, occlusion, emission (3), the dielectric
/// F0 (3) and F90, 1 for a Lambertian material, the shading normal facing the camera (3),
/// the material's index in materials.json (−1 for a miss).
fn write_surface(path: &Path, ctx: &FrameContext) -> Result<()> {
    let (scene, accel, camera, k) = (ctx.scene, ctx.accel, &ctx.camera, ctx.samples.k);
    write_atomic_with(path, |tmp| {
        let mut f = BufWriter::new(fs::File::create(tmp)?);
        for y in 0..camera.height {
            for x in 0..camera.width {
                for j in 0..k {
                    for i in 0..k {
                        let (sx, sy) = (x * k + i, y * k + j);
                        let s = ctx.surface(sx, sy);
                        // The triangle the sample's ray stopped at, cut-outs as it saw them.
                        let material = if s.hit {
                            let cut = AlphaTest::camera(scene, coverage_threshold(x, y, i, j, k));
                            accel
                                .intersect_cut(camera.position, ctx.sample_dir(sx, sy), &cut)
                                .map_or(-1.0, |h| scene.tri_material[h.tri as usize] as f32)
                        } else {
                            -1.0
                        };
                        let m = &s.material;
                        let values: [f32; SURFACE_FLOATS] = [
                            f32::from(u8::from(s.hit)),
                            s.albedo.x,
                            s.albedo.y,
                            s.albedo.z,
                            m.metallic,
                            m.roughness,
                            m.occlusion,
                            m.emission.x,
                            m.emission.y,
                            m.emission.z,
                            m.f0.x,
                            m.f0.y,
                            m.f0.z,
                            m.f90,
                            f32::from(u8::from(m.lambert)),
                            s.n.x,
                            s.n.y,
                            s.n.z,
                            material,
                        ];
                        for v in values {
                            f.write_all(&v.to_le_bytes())?;
                        }
                    }
                }
            }
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })
}

/// env.f32: the environment map's texels, row 0 at the top (+Y), RGB little-endian f32, as
/// envshadow looks them up (src/envmap: texel centres at ((x + ½)/w, (y + ½)/h), bilinear):
/// what a reference renderer's emitter must show.
fn write_env(path: &Path, env: &crate::envmap::EnvMap) -> Result<()> {
    write_atomic_with(path, |tmp| {
        let mut f = BufWriter::new(fs::File::create(tmp)?);
        for t in &env.texels {
            for c in t.to_array() {
                f.write_all(&c.to_le_bytes())?;
            }
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })
}

/// materials.json, and the level 0 alpha (`alpha_T.f32`) of the textures cut-out materials
/// read.
fn write_materials(dir: &Path, scene: &Scene) -> Result<()> {
    let mut cut_out = vec![false; scene.materials.len()];
    for (&m, &c) in scene.tri_material.iter().zip(&scene.cut_out_triangles()) {
        cut_out[m as usize] |= c;
    }
    let mut alpha_files = std::collections::BTreeSet::new();
    let materials: Vec<serde_json::Value> = scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let alpha_texture = m
                .base_color_texture
                .filter(|s| scene.textures.get(s.texture).is_some_and(|t| t.has_alpha()));
            if let Some(slot) = alpha_texture {
                alpha_files.insert(slot.texture);
            }
            let (mode, cutoff) = match m.alpha_mode {
                AlphaMode::Opaque => ("OPAQUE", None),
                AlphaMode::Mask { cutoff } => ("MASK", Some(cutoff)),
                AlphaMode::Blend => ("BLEND", None),
            };
            json!({
                "index": i,
                "name": m.name,
                "lambert": m.model == Model::Lambert,
                "metallic": m.metallic,
                "roughness": m.roughness,
                "textured": m.slots().iter().any(|(_, s)| s.is_some()),
                "normal_mapped": m.normal_texture.is_some(),
                "alpha_mode": mode,
                "alpha_cutoff": cutoff,
                "base_alpha": m.base_alpha,
                // Whether the BVH tests its triangles' alpha at all (Scene::cut_out_triangles).
                "cut_out": cut_out[i],
                "alpha_texture": alpha_texture.map(|slot| alpha_slot_json(scene, &slot)),
            })
        })
        .collect();
    for &t in &alpha_files {
        let texture = &scene.textures[t];
        write_atomic_with(&dir.join(format!("alpha_{t}.f32")), |tmp| {
            let mut f = BufWriter::new(fs::File::create(tmp)?);
            for a in texture.alpha() {
                f.write_all(&a.to_le_bytes())?;
            }
            f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
            Ok(())
        })?;
    }
    crate::output::write_atomic(
        &dir.join("materials.json"),
        serde_json::to_string_pretty(&json!({ "materials": materials }))?.as_bytes(),
    )?;
    Ok(())
}

/// An alpha texture's slot for materials.json: the file of its level 0 alpha (`width ×
/// height` little-endian f32, row 0 first: v = 0 at row 0's edge), the texture coordinate set,
/// `KHR_texture_transform` as the rows of its 2 × 3 matrix, the sampler's wrap modes and
/// whether it magnifies to the nearest texel (else bilinear; the alpha test reads level 0).
fn alpha_slot_json(scene: &crate::scene::Scene, slot: &TextureSlot) -> serde_json::Value {
    let texture = &scene.textures[slot.texture];
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => "repeat",
        Wrap::Clamp => "clamp",
        Wrap::Mirror => "mirror",
    };
    json!({
        "file": format!("alpha_{}.f32", slot.texture),
        "width": texture.width(),
        "height": texture.height(),
        "tex_coord": slot.tex_coord,
        "transform": slot.transform.map(|t| t.m),
        "wrap_s": wrap(slot.sampler.wrap_s),
        "wrap_t": wrap(slot.sampler.wrap_t),
        "nearest": slot.sampler.mag_nearest,
    })
}
