//! Shadow-ray recording and dumps (issue 8's measuring tools): what `envshadow bench` replays
//! and benches/embree traces.

use crate::common::Failures;

use envshadow::accel::{Accel, ShadowRay};
use envshadow::anim::{AnimFlags, Animation};
use envshadow::bench::{Grouping, by_direction, replay};
use envshadow::coordinator::thread_pool;
use envshadow::frame::render_frame;
use envshadow::inputs::Inputs;
use envshadow::predict::Method;
use envshadow::raydump;
use envshadow::run::Silent;
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
fn recorded(anim: &Animation, inputs: &Inputs) -> (envshadow::film::Film, Vec<ShadowRay>) {
    let pool = thread_pool(1).unwrap();
    raydump::set_recording(true);
    let film = pool.install(|| render_frame(anim, inputs, 0, None, &Silent));
    raydump::set_recording(false);
    let rays = pool.install(raydump::take_recorded);
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
            assert!(pool.install(raydump::take_recorded).is_empty());

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
                .install(|| replay(&frame_accel, &rays, Grouping::Single));
            assert!(
                blocked > 0 && blocked < rays.len() as u64,
                "{method}: {blocked}"
            );
            // Packets from one origin and packets of parallel rays from many origins answer
            // exactly as single rays do.
            let sorted = by_direction(&dump.rays);
            for threads in [1, 2] {
                let pool = thread_pool(threads).unwrap();
                for grouping in [Grouping::Single, Grouping::Origin, Grouping::Direction] {
                    let rays = if grouping == Grouping::Direction {
                        &sorted
                    } else {
                        &dump.rays
                    };
                    assert_eq!(
                        pool.install(|| replay(&rebuilt, rays, grouping)),
                        blocked,
                        "{method}: {threads} threads, {grouping:?}"
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
