//! `envshadow export`: one frame's exact inputs for another renderer (scripts/compare-mitsuba.sh):
//! the posed triangles, vertex normals and per-face albedo as a binary PLY, the lights as
//! `lights.json`, the primary-ray direction of every sample of every pixel (`--spp`; with one
//! sample, the pixel centre), and a `frame.json` with the camera, the sample pattern and the
//! shadow-ray offset. With these, an independent renderer can evaluate exactly what envshadow's
//! `brute` method does: Lambertian shading of every light at every sample, shadow rays from the
//! hit point moved `shadow_eps` along the geometric normal, a pixel the plain mean of its
//! samples.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use serde_json::json;

use crate::anim::{AnimFlags, Animation};
use crate::context::shadow_epsilon;
use crate::coordinator::Inputs;
use crate::error::{Result, input_error};
use crate::output::write_atomic_with;

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// The animation spec, e.g. anims/bunny-turntable.toml.
    pub spec: PathBuf,
    /// Which frame.
    #[arg(long, default_value_t = 0)]
    pub frame: usize,
    /// The spec's settings export reads — light count and sampler, width and height, samples
    /// per pixel and the filter — and the folder it writes (`--out DIR`, required):
    /// scene.ply, lights.json, primary.f32, frame.json.
    #[command(flatten)]
    pub flags: AnimFlags,
}

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
const READS: [&str; 8] = [
    "count",
    "sampler",
    "width",
    "height",
    "spp",
    "filter",
    "filter_width",
    "dir",
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
    if !anim.frames.contains(&args.frame) {
        return Err(input_error(
            &args.spec,
            format!(
                "frame {} is outside the animation's frames {:?}",
                args.frame, anim.frames
            ),
        ));
    }
    let inputs = Inputs::load(&anim)?;
    let camera0 = anim.camera(&inputs.scene, 0)?;
    let posed;
    let scene = match anim.scene_transform(args.frame, camera0.target) {
        Some(m) => {
            posed = inputs.scene.transformed(m);
            &posed
        }
        None => &inputs.scene,
    };
    let camera = anim.camera(&inputs.scene, args.frame)?;
    let samples = anim.render.samples();
    let dir = &dir;
    fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;

    // scene.ply: float vertices and normals; faces with their material's linear albedo.
    write_atomic_with(&dir.join("scene.ply"), |tmp| {
        let mut f = BufWriter::new(fs::File::create(tmp)?);
        write!(
            f,
            "ply\nformat binary_little_endian 1.0\ncomment envshadow export of {} frame {}\n\
             element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face {}\nproperty list uchar int vertex_indices\n\
             property float r\nproperty float g\nproperty float b\nend_header\n",
            anim.spec_path.display(),
            args.frame,
            scene.positions.len(),
            scene.triangles.len()
        )?;
        for (p, n) in scene.positions.iter().zip(&scene.normals) {
            for c in p.to_array().into_iter().chain(n.to_array()) {
                f.write_all(&c.to_le_bytes())?;
            }
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
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })?;

    // primary.f32: the unit direction of every sample's ray, pixel by pixel row by row from
    // the top, each pixel's k × k samples in stratum order (row j, column i): an array
    // (height, width, k·k, 3). These are the renderer's directions bit for bit: sample (i, j)
    // of pixel (x, y) is the renderer's sample (k·x + i, k·y + j), whose direction
    // `FrameContext::sample_dir` makes from the same two calls. With one sample the offset is
    // zero and `ray_dir_at` is `ray_dir`: the pixel centres, as before there were samples.
    let k = samples.k;
    write_atomic_with(&dir.join("primary.f32"), |tmp| {
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
    })?;

    inputs.lights.write_json(&dir.join("lights.json"))?;
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
        "shadow_eps": shadow_epsilon(scene),
        "triangles": scene.triangles.len(),
        "lights": inputs.lights.len(),
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
