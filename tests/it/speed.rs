//! The measuring tools of issue 8: shadow-ray recording and dumps (what `envshadow bench`
//! replays and benches/embree traces) and `envshadow export` (what compare-mitsuba renders).

use crate::common::{self, Failures};

use envshadow::accel::{self, Accel};
use envshadow::anim::{AnimFlags, Animation};
use envshadow::bench::replay;
use envshadow::coordinator::{Inputs, Silent, render_frame, thread_pool};
use envshadow::predict::Method;
use envshadow::raydump;
use envshadow::settings::{LightsLayer, RenderLayer};

fn shapes(lights: usize, method: Method) -> (Animation, Inputs) {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let overrides = AnimFlags {
        lights: LightsLayer {
            count: Some(lights),
            ..Default::default()
        },
        render: RenderLayer {
            width: Some(64),
            height: Some(48),
            method: Some(method),
            tile: Some(16),
            ..Default::default()
        },
        ..Default::default()
    };
    let anim = Animation::load(&root.join("anims/shapes-turntable.toml"), &overrides).unwrap();
    let inputs = Inputs::load(&anim).unwrap();
    (anim, inputs)
}

/// Renders frame 0 on one thread while recording its shadow rays.
fn recorded(anim: &Animation, inputs: &Inputs) -> (envshadow::film::Film, Vec<accel::ShadowRay>) {
    let pool = thread_pool(1).unwrap();
    accel::set_recording(true);
    let film = pool.install(|| render_frame(anim, inputs, 0, None, &Silent));
    accel::set_recording(false);
    let rays = pool.install(accel::take_recorded);
    (film.unwrap().0, rays)
}

#[test]
fn recorded_rays_are_the_frames_rays_and_a_dump_replays_them_identically() {
    let mut failures = Failures::new();
    for method in [Method::BRUTE, Method::DEFAULT] {
        failures.case(&method.to_string(), || {
            let (anim, inputs) = shapes(50, method);
            let (film, rays) = recorded(&anim, &inputs);
            let c = film.counts;
            assert!(c.rays > 0);
            // Every traced ray is recorded once: the tiles' own and their halos'.
            assert_eq!(rays.len() as u64, c.rays + c.halo_rays, "{method}");
            if method == Method::BRUTE {
                assert_eq!(c.rays, c.queries);
            }
            // Not recording: nothing is kept.
            let pool = thread_pool(1).unwrap();
            pool.install(|| render_frame(&anim, &inputs, 0, None, &Silent))
                .unwrap();
            assert!(pool.install(accel::take_recorded).is_empty());

            // The dump holds the frame's triangles and the same rays; tracing them against a BVH
            // rebuilt from the dump finds the same occluded rays, on 1 and 2 threads.
            let scene = &inputs.scene;
            let frame_accel = Accel::build(&scene.positions, &scene.triangles);
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("rays.bin");
            raydump::write(&path, &frame_accel, &rays).unwrap();
            let dump = raydump::read(&path).unwrap();
            assert_eq!(dump.rays, rays);
            assert_eq!(dump.triangles.len(), scene.triangles.len());
            let positions: Vec<_> = dump.triangles.iter().flatten().copied().collect();
            let tris: Vec<[u32; 3]> = (0..dump.triangles.len() as u32)
                .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
                .collect();
            let rebuilt = Accel::build(&positions, &tris);
            let blocked = thread_pool(1)
                .unwrap()
                .install(|| replay(&frame_accel, &rays, false));
            assert!(
                blocked > 0 && blocked < rays.len() as u64,
                "{method}: {blocked}"
            );
            // Packets from one origin answer exactly as single rays do.
            for threads in [1, 2] {
                let pool = thread_pool(threads).unwrap();
                for packets in [false, true] {
                    assert_eq!(
                        pool.install(|| replay(&rebuilt, &dump.rays, packets)),
                        blocked,
                        "{method}: {threads} threads, packets {packets}"
                    );
                }
            }
        });
    }
    failures.assert_none();
}

#[test]
fn a_truncated_ray_dump_is_refused_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.bin");
    std::fs::write(&path, b"ESRAYS1\0\x01\0\0\0\0\x10\0\0\x05\0\0\0\0\0\0\0").unwrap();
    let err = raydump::read(&path).err().expect("refused");
    let msg = format!("{err:#}");
    assert!(msg.contains("short.bin") && msg.contains("size"), "{msg}");
}

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
    assert!(meta["shadow_eps"].as_f64().unwrap() > 0.0);
    let tris = meta["triangles"].as_u64().unwrap();
    let ply = std::fs::read(out.join("scene.ply")).unwrap();
    let header_end = ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = String::from_utf8_lossy(&ply[..header_end]);
    let count = |what: &str| -> u64 {
        let line = header.lines().find(|l| l.starts_with(what)).unwrap();
        line.split_whitespace().last().unwrap().parse().unwrap()
    };
    assert_eq!(count("element face"), tris);
    let verts = count("element vertex");
    // 6 floats per vertex; per face a count byte, 3 indices and 3 albedo floats.
    assert_eq!(ply.len() as u64 - header_end as u64, verts * 24 + tris * 25);
    let primary = std::fs::read(out.join("primary.f32")).unwrap();
    assert_eq!(primary.len(), 32 * 24 * 12);
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
