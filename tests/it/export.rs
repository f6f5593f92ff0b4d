//! `envshadow export` (issue 8's measuring tools): the frame written for another renderer, what
//! compare-mitsuba renders.

use crate::common::{self, Failures};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::context::FrameContext;
use envshadow::inputs::Inputs;
use envshadow::settings::{LightsLayer, RenderLayer};

#[test]
fn export_writes_the_frame_for_another_renderer() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("exp");
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let status = common::bin()
        .args([
            "export",
            "anims/shapes-turntable.toml",
            "--frame",
            "3",
            "--lights",
            "20",
        ])
        .args(["--width", "32", "--height", "24", "--out"])
        .arg(&out)
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("frame.json")).unwrap()).unwrap();
    assert_eq!(meta["frame"], 3);
    assert_eq!(meta["lights"], 20);
    let gamma = meta["shadow_offset_gamma"].as_f64().unwrap();
    assert!(gamma > 0.0 && gamma < 1e-6, "{gamma}");
    assert_eq!(meta["origin"], serde_json::json!([0.0, 0.0, 0.0]));
    let tris = meta["triangles"].as_u64().unwrap();
    let (ply, header_end, header) = common::read_ply(&out.join("scene.ply"));
    let count = |what: &str| -> u64 {
        let line = header.lines().find(|l| l.starts_with(what)).unwrap();
        line.split_whitespace().last().unwrap().parse().unwrap()
    };
    assert_eq!(count("element face"), tris);
    let verts = count("element vertex");
    // 11 floats per vertex (position, normal, two texture coordinate sets, alpha); per face a
    // count byte, 3 indices, 3 albedo floats and the material index.
    assert_eq!(ply.len() as u64 - header_end as u64, verts * 44 + tris * 29);
    let materials: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("materials.json")).unwrap())
            .unwrap();
    let first = &materials["materials"][0];
    assert_eq!(first["alpha_mode"], "OPAQUE", "{first}");
    assert_eq!(first["cut_out"], false, "{first}");
    // The spec renders 4 samples per pixel: a direction for each.
    assert_eq!(meta["spp"], 4);
    let primary = std::fs::read(out.join("primary.f32")).unwrap();
    assert_eq!(primary.len(), 32 * 24 * 4 * 12);
    let lights = envshadow::lights::read_json(&out.join("lights.json")).unwrap();
    assert_eq!(lights.len(), 20);

    // A frame outside the animation is bad input.
    let bad = common::bin()
        .args([
            "export",
            "anims/shapes-turntable.toml",
            "--frame",
            "100000",
            "--out",
        ])
        .arg(&out)
        .current_dir(&root)
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2), "{bad:?}");
}

/// Exports shapes-turntable's frame 3 at 32×24 with `flags`; returns frame.json and the
/// directions of primary.f32.
fn export_dirs(flags: &[&str]) -> (serde_json::Value, Vec<[f32; 3]>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("exp");
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let status = common::bin()
        .args(["export", "anims/shapes-turntable.toml", "--frame", "3"])
        .args(["--lights", "20", "--width", "32", "--height", "24"])
        .args(flags)
        .arg("--out")
        .arg(&out)
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    let meta = serde_json::from_str(&std::fs::read_to_string(out.join("frame.json")).unwrap());
    let bytes = std::fs::read(out.join("primary.f32")).unwrap();
    let f = |b: &[u8]| f32::from_le_bytes(b.try_into().unwrap());
    let dirs = bytes
        .chunks_exact(12)
        .map(|c| [f(&c[0..4]), f(&c[4..8]), f(&c[8..12])])
        .collect();
    (meta.unwrap(), dirs)
}

/// What compare-mitsuba needs to trace the renderer's very samples: with `--spp 1` the pixel
/// centres (the file of before there were samples), with `--spp 4` every sample of every pixel,
/// pixel by pixel, in stratum order, bit for bit the renderer's `sample_dir`.
#[test]
fn export_writes_every_samples_direction_as_the_renderer_traces_it() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut failures = Failures::new();
    for (spp, filter) in [
        (1u32, "blackman-harris"),
        (4, "blackman-harris"),
        (4, "box"),
    ] {
        failures.case(&format!("--spp {spp} --filter {filter}"), || {
            let (meta, dirs) = export_dirs(&["--spp", &spp.to_string(), "--filter", filter]);
            assert_eq!(meta["spp"], spp);
            assert_eq!(meta["filter"], filter);
            let (w, h) = (32u32, 24u32);
            assert_eq!(dirs.len(), (w * h * spp) as usize);

            let overrides = AnimFlags {
                lights: LightsLayer {
                    count: Some(20),
                    ..Default::default()
                },
                render: RenderLayer {
                    width: Some(w),
                    height: Some(h),
                    spp: Some(spp),
                    filter: Some(filter.parse().unwrap()),
                    ..Default::default()
                },
                ..Default::default()
            };
            let anim =
                Animation::load(&root.join("anims/shapes-turntable.toml"), &overrides).unwrap();
            let inputs = Inputs::load(&anim).unwrap();
            let camera = anim.camera(&inputs.scene, 3).unwrap();
            let ctx = FrameContext::new(
                &inputs.scene,
                inputs.still_accel(),
                camera,
                &inputs.lights,
                &inputs.env,
            )
            .with_samples(anim.render.samples());
            let k = ctx.samples.k;
            assert_eq!(k * k, spp);
            let bits = |v: [f32; 3]| v.map(f32::to_bits);
            let mut n = 0;
            for y in 0..h {
                for x in 0..w {
                    for j in 0..k {
                        for i in 0..k {
                            let want = ctx.sample_dir(k * x + i, k * y + j).to_array();
                            assert_eq!(bits(dirs[n]), bits(want), "pixel ({x}, {y}) ({i}, {j})");
                            n += 1;
                        }
                    }
                    if spp == 1 {
                        // The pixel centre, as primary.f32 always held.
                        let centre = camera.ray_dir(x, y).to_array();
                        assert_eq!(bits(dirs[n - 1]), bits(centre), "pixel ({x}, {y})");
                    }
                }
            }
            if spp > 1 {
                // The first pixel's samples are not its centre, nor one another.
                let centre = camera.ray_dir(0, 0).to_array();
                let first = &dirs[..spp as usize];
                for (a, d) in first.iter().enumerate() {
                    assert_ne!(bits(*d), bits(centre), "sample {a}");
                    for e in &first[a + 1..] {
                        assert_ne!(bits(*d), bits(*e), "sample {a}");
                    }
                }
            }
        });
    }
    failures.assert_none();
}
