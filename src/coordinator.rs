//! The coordinator: loads an animation's inputs once, renders its frames tile by tile over a
//! worker pool — two frames in flight, so the next frame's tiles start while the last tiles of
//! the current one finish — and streams finished frames over a bounded channel to one writer
//! thread that writes them while rendering goes on. Memory stays bounded by the frames in
//! flight and the channel's capacity.

use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context;
use crossbeam_channel::bounded;
use rayon::prelude::*;

use crate::accel::Accel;
use crate::anim::{Animation, EnvSource, SceneSource};
use crate::cancel::Cancel;
use crate::envmap::EnvMap;
use crate::error::{Interrupted, Result};
use crate::film::Film;
use crate::frame::{FrameContext, TileWork, render_shared, render_tile};
use crate::lights::LightSet;
use crate::output::stats::{Counts, FrameStats, StatsFile};
use crate::output::{self, frame_path};
use crate::predict::Lattice;
use crate::scene::Scene;
use crate::tile::{Rect, tiles};

/// Progress reports from the library; the CLI decides how to show them (a bar or log lines).
pub trait Progress: Sync {
    /// The run starts: `frames` to render, `tiles` per frame.
    fn begin(&self, _frames: usize, _tiles: usize) {}
    /// A tile finished after tracing `rays` shadow rays.
    fn tile_done(&self, _rays: u64) {}
    /// A frame finished rendering (it is being written).
    fn frame_done(&self, _stats: &FrameStats) {}
    /// A frame was skipped because its files exist (`--resume`).
    fn frame_skipped(&self, _frame: usize) {}
    /// A one-line note for the user.
    fn note(&self, _msg: &str) {}
    /// The run ended.
    fn finish(&self) {}
}

/// Reports nothing.
pub struct Silent;
impl Progress for Silent {}

/// An animation's inputs, loaded once per run.
pub struct Inputs {
    pub scene: Scene,
    pub env: EnvMap,
    pub lights: LightSet,
}

impl Inputs {
    /// Loads the scene and environment and samples the lights.
    pub fn load(anim: &Animation) -> Result<Inputs> {
        let scene = match &anim.scene {
            SceneSource::Shapes => Scene::shapes(),
            SceneSource::File(p) => Scene::load(p)
                .with_context(|| format!("while loading {}", anim.spec_path.display()))?,
        };
        let env = match &anim.env {
            EnvSource::Sky => EnvMap::builtin_sky(),
            EnvSource::File(p) => EnvMap::load(p)
                .with_context(|| format!("while loading {}", anim.spec_path.display()))?,
        };
        let env = env
            .with_rotation(anim.env_rotation_deg)
            .with_intensity(anim.env_intensity)?;
        let lights = LightSet::build(&env, anim.lights, anim.sampler)?;
        Ok(Inputs { scene, env, lights })
    }
}

/// Frames rendered at once (see `render_animation`).
const FRAMES_IN_FLIGHT: usize = 2;

/// Options of a run beyond the animation itself.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Skip frames whose EXR and PNG already exist.
    pub resume: bool,
    /// Render only this pixel rectangle (the rest of the frame stays black).
    pub region: Option<Rect>,
    /// Stops the run between tiles: complete frames are written, frames in flight dropped.
    pub cancel: Cancel,
}

/// What a run did.
#[derive(Clone, Debug, Default)]
pub struct RunSummary {
    pub rendered: usize,
    pub skipped: usize,
    pub counts: Counts,
    pub seconds: f64,
}

thread_local! {
    /// Each worker's tile buffers, kept across tiles and frames so they are allocated once.
    static WORK: std::cell::RefCell<TileWork> = std::cell::RefCell::new(TileWork::default());
}

/// Runs `f` with this thread's tile buffers. Tile work never re-enters the pool, so the
/// buffers are never borrowed twice.
fn with_work<R>(f: impl FnOnce(&mut TileWork) -> R) -> R {
    WORK.with_borrow_mut(f)
}

/// Renders one frame: poses the scene, builds its BVH, renders every tile on the current
/// rayon pool and assembles the film. Tiles are added in tile order, so the film does not
/// depend on which thread finished first.
pub fn render_frame(
    anim: &Animation,
    inputs: &Inputs,
    frame: usize,
    region: Option<Rect>,
    progress: &dyn Progress,
) -> Result<(Film, FrameStats)> {
    render_frame_until(anim, inputs, frame, region, progress, &Cancel::default())
}

/// [`render_frame`], abandoned with [`Interrupted`] once `cancel` is set: tiles not yet started
/// are skipped and the frame is dropped.
pub fn render_frame_until(
    anim: &Animation,
    inputs: &Inputs,
    frame: usize,
    region: Option<Rect>,
    progress: &dyn Progress,
    cancel: &Cancel,
) -> Result<(Film, FrameStats)> {
    let start = Instant::now();
    let camera0 = anim.camera(&inputs.scene, 0)?;
    let posed;
    let scene = match anim.scene_transform(frame, camera0.target) {
        Some(m) => {
            posed = inputs.scene.transformed(m);
            &posed
        }
        None => &inputs.scene,
    };
    let camera = anim.camera(&inputs.scene, frame)?;
    let accel = Accel::build(&scene.positions, &scene.triangles);
    let predictor = anim.method.predictor(anim.params);
    let mut ctx = FrameContext::new(
        scene,
        &accel,
        camera,
        &inputs.lights,
        &inputs.env,
        predictor.as_ref(),
    );
    ctx.validate = anim.validate;
    let list = tiles(anim.width, anim.height, anim.tile, region);
    // Shared phases (the grid's coarse levels) run over every tile the rendered tiles' halos
    // reach, so a region render reads exactly what the whole frame would have computed.
    let phases = predictor.shared_phases();
    let mut lattice = Lattice::new(
        anim.width,
        anim.height,
        predictor.lattice_step(),
        ctx.words(),
    );
    if phases > 0 {
        let reach = region.map(|r| {
            let grown = r.grow(predictor.shared_reach());
            tiles(anim.width, anim.height, anim.tile, Some(grown))
        });
        let shared_tiles = reach.as_ref().unwrap_or(&list);
        for phase in 0..phases {
            cancel.check()?;
            let patches: Vec<_> = shared_tiles
                .par_iter()
                .map(|t| with_work(|work| render_shared(&ctx, t.rect, work, phase, &lattice)))
                .collect();
            for p in &patches {
                lattice.insert(p);
            }
        }
    }
    let results: Option<Vec<_>> = list
        .par_iter()
        .map(|t| {
            if cancel.is_cancelled() {
                return None;
            }
            let r = with_work(|work| render_tile(&ctx, t.rect, work, &lattice));
            progress.tile_done(r.counts.rays);
            Some(r)
        })
        .collect();
    let Some(results) = results else {
        return Err(Interrupted.into());
    };
    let mut film = Film::new(anim.width, anim.height, anim.validate);
    for r in &results {
        film.add(r);
    }
    let rendered = region.unwrap_or(Rect::frame(anim.width, anim.height));
    let stats = FrameStats {
        frame,
        method: anim.method.name().to_string(),
        lights: inputs.lights.len(),
        width: anim.width,
        height: anim.height,
        counts: film.counts,
        image_error: film.image_error(rendered, anim.exposure),
        seconds: start.elapsed().as_secs_f64(),
        camera_position: camera.position,
        camera_target: camera.target,
        camera_up: camera.up,
        vfov_deg: camera.vfov_deg,
    };
    Ok((film, stats))
}

/// Writes one frame's files: `frame_NNNN.exr` (beauty + AOVs) and `frame_NNNN.png`.
pub fn write_frame_files(dir: &Path, frame: usize, film: &Film, exposure: f32) -> Result<()> {
    let mut aovs = Vec::new();
    if let Some(wrong) = &film.wrong {
        aovs.push(output::exr::Aov {
            name: "wrong",
            values: wrong,
        });
    }
    output::exr::write_frame(&frame_path(dir, frame, "exr"), film, &aovs)?;
    output::png::write_preview(
        &frame_path(dir, frame, "png"),
        film.width,
        film.height,
        &film.beauty,
        exposure,
    )
}

/// A thread pool with `threads` workers (0: one per core).
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("envshadow-worker-{i}"))
        .build()
        .context("starting the worker threads")
}

/// Renders the animation's selected frames into its output folder.
pub fn render_animation(
    anim: &Animation,
    opts: &RunOptions,
    progress: &dyn Progress,
) -> Result<RunSummary> {
    let start = Instant::now();
    let dir = &anim.out_dir;
    // Inputs first: a bad input leaves nothing behind, not even an empty folder.
    let inputs = Inputs::load(anim)?;
    opts.cancel.check()?;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating output folder {}", dir.display()))?;
    inputs.lights.write_json(&dir.join("lights.json"))?;

    let todo: Vec<usize> = anim
        .frames
        .clone()
        .filter(|&f| {
            let done = opts.resume
                && frame_path(dir, f, "exr").exists()
                && frame_path(dir, f, "png").exists();
            if done {
                progress.frame_skipped(f);
            }
            !done
        })
        .collect();
    let mut summary = RunSummary {
        skipped: anim.frames.len() - todo.len(),
        ..Default::default()
    };
    let tiles_per_frame = tiles(anim.width, anim.height, anim.tile, opts.region).len();
    progress.begin(todo.len(), tiles_per_frame);
    let pool = thread_pool(anim.threads)?;
    let stats_path = dir.join("stats.csv");
    let mut stats_file = StatsFile::open(&stats_path);

    // Two frames in flight share the pool: while the last tiles of one frame finish, idle
    // workers take tiles of the next. Each driver thread hands its frame's tiles to the pool
    // and sends the finished film to the writer; files are per frame, so the order they are
    // written in does not matter, and memory stays bounded by the frames in flight plus the
    // channel's capacity, however long the animation.
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let first_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    let (tx, rx) = bounded::<(Film, FrameStats)>(FRAMES_IN_FLIGHT);
    let result: Result<()> = std::thread::scope(|s| {
        let writer = s.spawn(|| -> Result<RunSummary> {
            let mut done = RunSummary::default();
            for (film, stats) in rx {
                write_frame_files(dir, stats.frame, &film, anim.exposure)?;
                stats_file.set(&stats);
                stats_file.write(&stats_path)?;
                done.counts += stats.counts;
                done.rendered += 1;
            }
            Ok(done)
        });
        for _ in 0..FRAMES_IN_FLIGHT.min(todo.len()) {
            let tx = tx.clone();
            let (next, failed, first_error, todo, pool, inputs) =
                (&next, &failed, &first_error, &todo, &pool, &inputs);
            s.spawn(move || {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= todo.len()
                        || failed.load(Ordering::Relaxed)
                        || opts.cancel.is_cancelled()
                    {
                        break;
                    }
                    let rendered = pool.install(|| {
                        render_frame_until(
                            anim,
                            inputs,
                            todo[k],
                            opts.region,
                            progress,
                            &opts.cancel,
                        )
                    });
                    match rendered {
                        Ok((film, stats)) => {
                            progress.frame_done(&stats);
                            if tx.send((film, stats)).is_err() {
                                break; // the writer failed; its error is reported below
                            }
                        }
                        Err(e) => {
                            failed.store(true, Ordering::Relaxed);
                            first_error.lock().unwrap().get_or_insert(e);
                            break;
                        }
                    }
                }
            });
        }
        drop(tx);
        let written = writer
            .join()
            .map_err(|_| anyhow::anyhow!("the writer thread panicked"))?;
        if let Some(e) = first_error.lock().unwrap().take() {
            return Err(e);
        }
        let done = written?;
        summary.counts = done.counts;
        summary.rendered = done.rendered;
        Ok(())
    });
    progress.finish();
    result?;
    // Frames finished before the stop are written; the rest waits for `--resume`.
    opts.cancel.check()?;
    summary.seconds = start.elapsed().as_secs_f64();
    Ok(summary)
}
