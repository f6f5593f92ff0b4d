//! The coordinator: loads an animation's inputs once, renders its frames tile by tile over a
//! worker pool — two frames in flight, so the next frame's tiles start while the last tiles of
//! the current one finish — and streams finished frames over a bounded channel to one writer
//! thread that writes them while rendering goes on. Memory stays bounded by the frames in
//! flight and the channel's capacity.

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

use anyhow::Context;
use crossbeam_channel::bounded;
use rayon::prelude::*;

use crate::accel::Accel;
use crate::anim::{Animation, EnvSource, MotionKind, SceneSource};
use crate::background::Backdrop;
use crate::cancel::Cancel;
use crate::context::FrameContext;
use crate::driver::{FrameWork, Slot};
use crate::envmap::EnvMap;
use crate::error::{Interrupted, Result, input_error};
use crate::film::{Counts, Film};
use crate::glossy::Glossy;
use crate::history::{Carried, CarryPatch, Edges};
use crate::lights::{LightSet, Tracks};
use crate::output;
use crate::output::lock::FolderLock;
use crate::output::record::{FrameRecord, SettingsRecord};
use crate::output::runs::RunRecord;
use crate::output::stats::{FrameStats, StatsFile};
use crate::scene::{Model, Scene};
use crate::temporal::{chains, prev_view};
use crate::tile::{Rect, Tile};

/// Progress reports from the library; the CLI decides how to show them (a bar or log lines).
pub trait Progress: Sync {
    /// The run starts: `frames` to render, `tiles` per frame.
    fn begin(&self, _frames: usize, _tiles: usize) {}
    /// A tile finished.
    fn tile_done(&self, _tile: &TileDone) {}
    /// A frame finished rendering (it is being written).
    fn frame_done(&self, _stats: &FrameStats) {}
    /// A frame was skipped because its files exist (`--resume`).
    fn frame_skipped(&self, _frame: usize) {}
    /// A one-line note for the user.
    fn note(&self, _msg: &str) {}
    /// Something the input had that is not rendered (a loader skipped it).
    fn warning(&self, _msg: &str) {}
    /// A one-line note worth showing only to who asked for detail (`-v`): timings, sizes.
    fn detail(&self, _msg: &str) {}
    /// The run ended.
    fn finish(&self) {}
}

/// One finished tile, as [`Progress::tile_done`] reports it.
#[derive(Clone, Copy, Debug)]
pub struct TileDone {
    pub frame: usize,
    /// The tile's number in the frame-anchored grid, and its pixels.
    pub index: usize,
    pub rect: Rect,
    pub counts: Counts,
    /// Wall-clock seconds of this tile alone (tiles run in parallel).
    pub seconds: f64,
}

/// Reports nothing.
pub struct Silent;
impl Progress for Silent {}

/// Where a run's finished frames go: frame files and `stats.csv` in the output folder
/// ([`FrameFiles`]), or a farm job's tile images and statistics (the farm's `JobWriter`).
pub trait FrameSink: Send {
    /// Called once the output folder exists, before any frame is rendered.
    fn begin(&mut self) -> Result<()> {
        Ok(())
    }
    /// Whether `frame` is already complete here (`--resume` skips it).
    fn frame_done(&self, frame: usize) -> bool;
    /// Publishes one finished frame (from the writer thread, in the order frames finish).
    fn write(&mut self, film: &Film, stats: &FrameStats) -> Result<()>;
    /// The run ended with every frame written: what it did.
    fn finish(&mut self, _summary: &RunSummary) -> Result<()> {
        Ok(())
    }
}

/// A render's own folder: `frame_NNNN.exr` and `.png` per frame, each committed with its
/// record, `settings.txt`, and `stats.csv` rebuilt from the records ([`output::record`]).
pub struct FrameFiles {
    dir: PathBuf,
    format: output::FrameFormat,
    fps: f32,
    /// The settings record's lines, which each frame's EXR header repeats.
    record: Vec<(String, String)>,
    /// What the settings record is made from (in `begin`: the inputs are loaded by then, so a
    /// missing file gets the loader's message).
    anim: Animation,
    region: Option<Rect>,
    resume: bool,
    /// The settings' fingerprint, which each frame's record names.
    settings: String,
    stats: StatsFile,
}

impl FrameFiles {
    /// The frame files of `anim`'s output folder for a run with `opts` (`stats.csv` rows
    /// already there are kept).
    pub fn new(anim: &Animation, opts: &RunOptions) -> FrameFiles {
        let dir = anim.output.dir.clone();
        FrameFiles {
            stats: StatsFile::open(&dir.join("stats.csv")),
            dir,
            format: frame_format(anim),
            fps: anim.output.fps,
            record: Vec::new(),
            anim: anim.clone(),
            region: opts.region,
            resume: opts.resume,
            settings: String::new(),
        }
    }
}

impl FrameSink for FrameFiles {
    /// Checks (`--resume`) and publishes `settings.txt`, and restores the `stats.csv` rows of
    /// committed frames from their records.
    fn begin(&mut self) -> Result<()> {
        let mut now = self.anim.settings_record()?;
        if let Some(r) = self.region {
            now.lines.push(("--region".into(), r.to_string()));
        }
        let old = SettingsRecord::read(&self.dir)?;
        // [ours] A resumed folder holds one render's frames: mixing sizes, light counts or
        // methods would make its frames and rows disagree without a word.
        if self.resume
            && let Some(old) = &old
            && let Some(diff) = old.first_difference(&now)
        {
            return Err(input_error(
                &self.dir,
                format!(
                    "cannot resume: its frames were rendered with other settings ({diff}); \
                     render into another folder, or without --resume to render every frame again"
                ),
            ));
        }
        if old.as_ref() != Some(&now) {
            now.write(&self.dir)?;
        }
        self.settings = now.fingerprint();
        self.record = now.lines;
        // A kill between a frame's commit and the stats.csv that follows it loses no row: the
        // committed frame's record has it.
        let mut restored = 0;
        for rec in FrameRecord::read_all(&self.dir) {
            if rec.sizes_match(&self.dir) && self.stats.row(rec.frame) != Some(&rec.stats_row) {
                self.stats.set_row(rec.frame, &rec.stats_row);
                restored += 1;
            }
        }
        if restored > 0 {
            self.stats.write(&self.dir.join("stats.csv"))?;
        }
        Ok(())
    }

    /// The frame's record names this run's settings and its EXR and PNG are the recorded files.
    fn frame_done(&self, frame: usize) -> bool {
        FrameRecord::read(&self.dir, frame)
            .is_some_and(|r| r.settings == self.settings && r.files_match(&self.dir))
    }

    fn write(&mut self, film: &Film, stats: &FrameStats) -> Result<()> {
        let header = exr_header(stats, self.fps, &self.record);
        let rec = output::publish_frame(&self.dir, film, &header, &self.format, &self.settings)?;
        self.stats.set_row(stats.frame, &rec.stats_row);
        self.stats.write(&self.dir.join("stats.csv"))
    }

    /// Records the run in `records/runs.csv`: its wall time beside its frames' thread-seconds.
    fn finish(&mut self, summary: &RunSummary) -> Result<()> {
        RunRecord {
            started_unix: summary.started_unix,
            threads: summary.threads,
            frames_rendered: summary.rendered,
            frames_skipped: summary.skipped,
            wall_seconds: summary.seconds,
            thread_seconds: summary.thread_seconds,
            queries: summary.counts.queries,
            rays_traced: summary.counts.traced(),
        }
        .append(&self.dir)
    }
}

/// How `anim`'s frames are written: preview exposure and view, EXR precision.
pub fn frame_format(anim: &Animation) -> output::FrameFormat {
    output::FrameFormat {
        exposure: anim.render.exposure,
        view: anim.render.view,
        half: anim.output.half,
    }
}

/// A frame's EXR header: its camera (from `stats`, as the frame was rendered), the frame
/// rate, the settings record's lines and its statistics.
pub fn exr_header<'a>(
    stats: &'a FrameStats,
    fps: f32,
    settings: &'a [(String, String)],
) -> output::exr::FrameHeader<'a> {
    let camera = crate::camera::Camera::look_at(
        stats.camera_position,
        stats.camera_target,
        stats.camera_up,
        stats.vfov_deg,
        stats.width,
        stats.height,
    );
    let (world_to_camera, world_to_ndc) = camera.exr_matrices();
    output::exr::FrameHeader {
        world_to_camera,
        world_to_ndc,
        fps,
        settings,
        stats,
    }
}

/// An animation's inputs, loaded once per run.
pub struct Inputs {
    /// The scene as the spec asks for it: stood up, its catchers marked, a ground added
    /// ([`Animation::prepare_scene`]).
    pub scene: Scene,
    pub env: EnvMap,
    pub lights: LightSet,
    /// What rays that leave the scene see.
    pub backdrop: Backdrop,
    /// The BVH of the unposed scene, built by the first frame that needs it: frames whose
    /// geometry does not move (orbit turntables, still cameras) share one build per run.
    still: OnceLock<Accel>,
    /// The prefiltered environment, made by the first frame that needs it: only when some
    /// material is glossier than the lights resolve (see [`Glossy`]).
    glossy: OnceLock<Option<Glossy>>,
}

impl Inputs {
    /// Inputs from parts already loaded.
    pub fn new(scene: Scene, env: EnvMap, lights: LightSet) -> Inputs {
        Inputs {
            scene,
            env,
            lights,
            backdrop: Backdrop::Environment,
            still: OnceLock::new(),
            glossy: OnceLock::new(),
        }
    }

    /// The environment prefiltered for glossy lobes, if any material may need it: one whose
    /// roughness factor (its texture can only lower it) is below what the map's lights
    /// resolve.
    pub fn glossy(&self) -> Option<&Glossy> {
        self.glossy
            .get_or_init(|| {
                let map_lights = self.lights.lights.len();
                let (_, rough_lights) = Glossy::roughness_range(map_lights);
                let needed = self
                    .scene
                    .materials
                    .iter()
                    .any(|m| m.model == Model::MetallicRoughness && m.roughness < rough_lights);
                needed.then(|| Glossy::build(&self.env, map_lights))
            })
            .as_ref()
    }

    /// These inputs with rays that leave the scene seeing `backdrop`.
    pub fn with_backdrop(self, backdrop: Backdrop) -> Inputs {
        Inputs { backdrop, ..self }
    }

    /// The lights of `frame`: the sampled set, turned by the environment's turn at that frame
    /// (`[motion] kind = "environment"`).
    pub fn lights_at(&self, anim: &Animation, frame: usize) -> Cow<'_, LightSet> {
        match anim.motion.environment_degrees(frame) {
            None => Cow::Borrowed(&self.lights),
            Some(degrees) => Cow::Owned(self.lights.turned(degrees)),
        }
    }

    /// The unposed scene's BVH, built once.
    pub fn still_accel(&self) -> &Accel {
        self.still.get_or_init(|| self.scene.accel())
    }

    /// Loads the scene and environment and samples the lights. Each file is counted against
    /// the render's memory budget from its headers before it is decoded; the map's header is
    /// read first, so the scene is checked with what will light it.
    pub fn load(anim: &Animation) -> Result<Inputs> {
        let mut budget = anim.budget();
        if let EnvSource::File(p) = &anim.env
            && let Some((texels, bytes)) = EnvMap::declared_size(p)
        {
            budget.expect_map(texels, bytes);
        }
        let scene = match &anim.scene {
            SceneSource::Shapes => Scene::shapes(),
            SceneSource::File(p) => Scene::load_within(p, &mut budget)
                .with_context(|| format!("while loading {}", anim.spec_path.display()))?,
        };
        let scene = anim.prepare_scene(scene)?;
        // A spin poses the scene every frame: refused here if that could overflow (found by
        // fuzzing the posed scene: tests/data/fuzz/posed_scene/huge-pivot).
        for s in anim.motion.segments() {
            if s.kind != MotionKind::Spin {
                continue;
            }
            let pivot = match s.pivot {
                Some(p) => scene.to_local(p),
                None => anim.camera(&scene, 0)?.target,
            };
            if let Some(why) = scene.turn_problem(pivot) {
                crate::bail_input!(&anim.spec_path, "[motion] kind = \"spin\": {why}");
            }
        }
        let env = match &anim.env {
            EnvSource::Sky => EnvMap::builtin_sky(),
            EnvSource::File(p) => EnvMap::load_within(p, &mut budget)
                .with_context(|| format!("while loading {}", anim.spec_path.display()))?,
        };
        let env = env
            .with_rotation(anim.env_rotation_deg)
            .with_intensity(anim.env_intensity)?;
        let mut lights = LightSet::build(&env, anim.lights.count, anim.lights.sampler)?;
        if anim.lights.scene_lights {
            lights = lights.with_scene_lights(&scene.lights, Path::new(&scene.source))?;
        }
        let r = &anim.render;
        let backdrop = Backdrop::new(r.background, r.background_color, r.background_blur, &env)?;
        Ok(Inputs::new(scene, env, lights).with_backdrop(backdrop))
    }
}

/// What became of the scene file's lights, for the user: lit by them, or ignored.
pub fn scene_lights_note(anim: &Animation, scene: &Scene) -> Option<String> {
    if scene.lights.is_empty() {
        return None;
    }
    let names: Vec<String> = scene
        .lights
        .iter()
        .map(|l| format!("{} '{}'", l.kind.name(), l.name))
        .collect();
    let n = scene.lights.len();
    let (lights, join) = if n == 1 {
        ("light", "joins")
    } else {
        ("lights", "join")
    };
    Some(if anim.lights.scene_lights {
        format!(
            "the scene file's {n} {lights} {join} the map's: {}",
            names.join(", ")
        )
    } else {
        format!(
            "the scene file's {n} {lights} ignored ([lights] scene_lights = false): {}",
            names.join(", ")
        )
    })
}

/// Frames rendered at once (see `render_animation`); the memory estimate counts them.
const FRAMES_IN_FLIGHT: usize = crate::limits::FRAMES_IN_FLIGHT;

/// Options of a run beyond the animation itself.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Skip frames whose EXR and PNG already exist.
    pub resume: bool,
    /// Render only this pixel rectangle (the rest of the frame stays black).
    pub region: Option<Rect>,
    /// Render only these tiles of the frame-anchored grid (sorted; a farm job's), as a region
    /// render of their bounding rectangle would.
    pub tiles: Option<Vec<usize>>,
    /// Stops the run between tiles: complete frames are written, frames in flight dropped.
    pub cancel: Cancel,
    /// When another render holds the output folder, wait for it rather than refuse
    /// ([`FolderLock`]).
    pub wait: bool,
}

/// What a run did.
#[derive(Clone, Debug, Default)]
pub struct RunSummary {
    pub rendered: usize,
    pub skipped: usize,
    /// The written frames' counts.
    pub counts: Counts,
    /// Wall-clock seconds of the whole run, loading included.
    pub seconds: f64,
    /// When it started, Unix seconds.
    pub started_unix: u64,
    /// Worker threads.
    pub threads: usize,
    /// The thread-seconds of every frame rendered (warm-up frames included).
    pub thread_seconds: f64,
}

thread_local! {
    /// Each worker's tile buffers and scratch, kept across tiles and frames so they are
    /// allocated once.
    static SLOT: std::cell::RefCell<Slot> = std::cell::RefCell::new(Slot::default());
}

/// Runs `f` with this thread's slot. Tile work never re-enters the pool, so the slot is never
/// borrowed twice.
fn with_slot<R>(f: impl FnOnce(&mut Slot) -> R) -> R {
    SLOT.with_borrow_mut(f)
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
    let (film, stats, _) =
        render_frame_with(anim, inputs, frame, region, progress, &Temporal::default())?;
    Ok((film, stats))
}

/// How a frame is linked to its neighbours in time (`--temporal`).
#[derive(Default)]
pub struct Temporal<'a> {
    /// The previous frame's carried data: this frame is predicted from it where it can be.
    pub prev: Option<&'a Carried>,
    /// Keep this frame's carried data for the next frame.
    pub carry: bool,
    /// Skip validation even if the animation asks for it (warm-up frames are not written).
    pub no_validate: bool,
}

/// [`render_frame`] with temporal prediction: reads `temporal.prev` and, with
/// `temporal.carry`, returns this frame's carried data for the next frame.
pub fn render_frame_with(
    anim: &Animation,
    inputs: &Inputs,
    frame: usize,
    region: Option<Rect>,
    progress: &dyn Progress,
    temporal: &Temporal,
) -> Result<(Film, FrameStats, Option<Carried>)> {
    let list = anim.render.tiles(region);
    let never = Cancel::default();
    render_tile_list(
        anim, inputs, frame, &list, region, progress, temporal, &never,
    )
}

/// The tiles a run renders and the region that bounds them: `--region`'s tiles, or the
/// tiles of `indices` (sorted; the frame-anchored grid) with their bounding rectangle, so
/// the shared phases reach as far as their halos and each tile gets the bits of a
/// whole-frame render.
fn selection(anim: &Animation, opts: &RunOptions) -> (Vec<Tile>, Option<Rect>) {
    let Some(indices) = &opts.tiles else {
        return (anim.render.tiles(opts.region), opts.region);
    };
    let all = anim.render.tiles(None);
    let whole = indices.len() == all.len();
    let list: Vec<Tile> = all
        .into_iter()
        .filter(|t| indices.binary_search(&t.index).is_ok())
        .collect();
    let bbox = (!whole).then(|| crate::tile::bounding(&list));
    (list, bbox)
}

/// Renders `list` (tiles of one frame); `region` (if any) bounds them and decides how far the
/// shared phases run and over which pixels validation compares images. Once `cancel` is set,
/// tiles not yet started are skipped and the frame ends with [`Interrupted`].
// The frame, its tiles, the temporal link and the stop flag: a struct for them would only be
// unpacked again here.
#[allow(clippy::too_many_arguments)]
fn render_tile_list(
    anim: &Animation,
    inputs: &Inputs,
    frame: usize,
    list: &[Tile],
    region: Option<Rect>,
    progress: &dyn Progress,
    temporal: &Temporal,
    cancel: &Cancel,
) -> Result<(Film, FrameStats, Option<Carried>)> {
    // The frame's thread-seconds: its serial parts (this thread's time outside the parallel
    // sections, which it spends waiting or on other frames' tasks) plus its tasks' own times.
    let start = Instant::now();
    let mut parallel = std::time::Duration::ZERO;
    let tasks = TaskTime::default();
    let pivot = anim.pivot(&inputs.scene)?;
    let (posed, built);
    let (scene, accel) = match anim.scene_transform(frame, pivot) {
        Some(m) => {
            posed = inputs.scene.transformed(m);
            built = posed.accel();
            (&posed, &built)
        }
        None => (&inputs.scene, inputs.still_accel()),
    };
    let camera = anim.camera(&inputs.scene, frame)?;
    let samples = anim.render.samples();
    let side = samples.k;
    let lights = inputs.lights_at(anim, frame);
    let ctx = FrameContext::new(scene, accel, camera, &lights, &inputs.env)
        .with_samples(samples)
        .with_glossy(if anim.render.glossy_env {
            inputs.glossy()
        } else {
            None
        })
        .with_backdrop(&inputs.backdrop)
        .with_environment_turn(anim.motion.environment_degrees(frame));
    let prev_lights;
    let prev = match temporal.prev {
        Some(carried) => {
            let prev_camera = anim.camera(&inputs.scene, carried.frame)?;
            prev_lights = inputs.lights_at(anim, carried.frame);
            Some(prev_view(
                anim,
                carried,
                frame,
                prev_camera,
                &camera,
                pivot,
                (&prev_lights, &lights),
            ))
        }
        None => None,
    };
    // The methods run on the samples: their spacings grow with the samples per pixel side.
    let shadows = anim.render.method.build(
        anim.render
            .params()
            .for_samples(side)
            .for_cutouts(accel.has_cutouts()),
        prev.as_ref(),
    );
    let work = FrameWork {
        ctx: &ctx,
        shadows: &shadows,
        validate: anim.render.validate && !temporal.no_validate,
    };
    // A spinning object or a turning environment turns the lights relative to the scene:
    // keep the edges of each pixel's shadow in light space, which the turn may carry across
    // a light.
    let segment = anim.motion.segment_at(frame);
    let tracks = (temporal.carry && segment.kind == MotionKind::Environment)
        .then(|| Tracks::new(&lights, segment.degrees_per_frame));
    let edges = match (&tracks, segment.kind) {
        (Some(t), _) => Edges::Track(t),
        (None, MotionKind::Spin) => Edges::Adjacent,
        _ => Edges::None,
    };
    let mut carried = temporal.carry.then(|| {
        Carried::new(
            frame,
            anim.render.width,
            anim.render.height,
            ctx.words(),
            edges.kept(),
        )
    });
    // Shared phases (the grid's coarse levels) run over every tile the rendered tiles' halos
    // reach, so a region render reads exactly what the whole frame would have computed.
    let phases = work.shared_phases();
    let mut lattice = work.lattice();
    if phases > 0 {
        let reach = region.map(|r| {
            let grown = r.grow(work.shared_reach());
            anim.render.tiles(Some(grown))
        });
        let shared_tiles = reach.as_deref().unwrap_or(list);
        for phase in 0..phases {
            cancel.check()?;
            let t = Instant::now();
            let patches: Vec<_> = shared_tiles
                .par_iter()
                .map(|t| {
                    tasks
                        .time(|| with_slot(|slot| work.shared_phase(t.rect, slot, phase, &lattice)))
                })
                .collect();
            parallel += t.elapsed();
            for p in &patches {
                lattice.insert(p);
            }
        }
    }
    let carry = carried.is_some();
    // Dearest tiles first, dealt one at a time to whichever worker is free (longest-processing-
    // time order): a tile on the object's silhouette costs many times one of open ground, and
    // splitting the list by position left one thread finishing the frame alone. Results keep
    // the list's order, so the frame does not depend on the schedule.
    let mut order: Vec<usize> = (0..list.len()).collect();
    order.sort_by_cached_key(|&t| (std::cmp::Reverse(work.rays_in(&lattice, list[t].rect)), t));
    let slots: Vec<Mutex<Option<_>>> = (0..list.len()).map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let t = Instant::now();
    (0..rayon::current_num_threads())
        .into_par_iter()
        .with_max_len(1)
        .for_each(|_| {
            loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= order.len() || cancel.is_cancelled() {
                    break;
                }
                let t = &list[order[k]];
                let began = Instant::now();
                let r = tasks.time(|| {
                    with_slot(|slot| {
                        let r = work.tile(t.rect, slot, &lattice);
                        let patch =
                            carry.then(|| CarryPatch::record(&slot.bufs, &lights, edges, side));
                        (r, patch)
                    })
                });
                progress.tile_done(&TileDone {
                    frame,
                    index: t.index,
                    rect: t.rect,
                    counts: r.0.counts,
                    seconds: began.elapsed().as_secs_f64(),
                });
                *slots[order[k]].lock().unwrap() = Some(r);
            }
        });
    parallel += t.elapsed();
    let results: Option<Vec<_>> = slots.into_iter().map(|s| s.into_inner().unwrap()).collect();
    let Some(results) = results else {
        return Err(Interrupted.into());
    };
    let mut film = Film::new(
        anim.render.width,
        anim.render.height,
        work.validate,
        side > 1,
    )
    .with_alpha(inputs.backdrop.is_transparent());
    for (r, patch) in &results {
        film.add(r);
        if let (Some(c), Some(p)) = (&mut carried, patch) {
            c.insert(p);
        }
    }
    drop(results);
    let rendered = region.unwrap_or(Rect::frame(anim.render.width, anim.render.height));
    let stats = FrameStats {
        frame,
        method: anim.render.method.name().to_string(),
        lights: lights.len(),
        width: anim.render.width,
        height: anim.render.height,
        spp: anim.render.spp,
        counts: film.counts,
        image_error: film.image_error(rendered, anim.render.exposure, anim.render.view),
        thread_seconds: (start.elapsed().saturating_sub(parallel) + tasks.total()).as_secs_f64(),
        camera_position: inputs.scene.to_world(camera.position),
        camera_target: inputs.scene.to_world(camera.target),
        camera_up: camera.up,
        vfov_deg: camera.vfov_deg,
    };
    Ok((film, stats, carried))
}

/// The summed run time of a frame's parallel tasks (tiles, shared passes), each timed on the
/// thread that ran it.
#[derive(Default)]
struct TaskTime(std::sync::atomic::AtomicU64);

impl TaskTime {
    /// Runs `f`, adding its run time.
    fn time<R>(&self, f: impl FnOnce() -> R) -> R {
        let t = Instant::now();
        let r = f();
        let ns = u64::try_from(t.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.0.fetch_add(ns, Ordering::Relaxed);
        r
    }

    fn total(&self) -> std::time::Duration {
        std::time::Duration::from_nanos(self.0.load(Ordering::Relaxed))
    }
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
    sink: &mut dyn FrameSink,
    progress: &dyn Progress,
) -> Result<RunSummary> {
    let start = Instant::now();
    let started_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let dir = &anim.output.dir;
    if anim.render.temporal && opts.region.is_some() {
        crate::bail_input!(
            "--region",
            "cannot be combined with temporal prediction: a frame's pixels depend on the \
             whole previous frame"
        );
    }
    // Inputs first: a bad input leaves nothing behind, not even an empty folder.
    let loading = Instant::now();
    let inputs = Inputs::load(anim)?;
    progress.detail(&format!(
        "inputs in {:.2} s: {} ({} triangles), {} ({}x{}), {} lights",
        loading.elapsed().as_secs_f64(),
        inputs.scene.source,
        inputs.scene.triangles.len(),
        inputs.env.source,
        inputs.env.width,
        inputs.env.height,
        inputs.lights.len()
    ));
    // Every frame's camera, so a spec whose camera breaks at some frame (an `up` along the
    // view) is refused before lights.json or any frame is written.
    for f in anim.frames.iter() {
        anim.camera(&inputs.scene, f)?;
    }
    for w in &inputs.scene.warnings {
        progress.warning(w);
    }
    if let Some(note) = scene_lights_note(anim, &inputs.scene) {
        progress.note(&note);
    }
    if inputs.scene.added_ground.is_some() {
        let catcher = inputs.scene.catcher.last().copied().unwrap_or(false);
        progress.note(&format!(
            "{} has no ground under the model: added {} (`[scene] ground = \"none\"` or \
             --ground none leaves it out)",
            inputs.scene.source,
            if catcher {
                "a shadow-catcher ground"
            } else {
                "a grey ground"
            }
        ));
    }
    opts.cancel.check()?;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating output folder {}", dir.display()))?;
    // One writer per folder, from the first file written to the last.
    let _lock = FolderLock::acquire(dir, opts.wait)?;
    // Holding the lock, no other writer is mid-write: whatever temporaries the folder holds
    // were left by a render that was killed, and would stay for good.
    output::remove_stale_temporaries(dir)?;
    sink.begin()?;
    inputs.lights.write_json(&dir.join("lights.json"))?;

    let todo: Vec<usize> = anim
        .frames
        .iter()
        .filter(|&f| {
            let done = opts.resume && sink.frame_done(f);
            if done {
                progress.frame_skipped(f);
            }
            !done
        })
        .collect();
    let mut summary = RunSummary {
        skipped: anim.frames.len() - todo.len(),
        started_unix,
        ..Default::default()
    };
    // With temporal prediction, frames come in chains from a key frame, each frame reading
    // its predecessor; a chain's frames outside this run are rendered, not written.
    let work = chains(&todo, anim.render.temporal, |f| anim.key_frame_of(f));
    let warmup: usize = work
        .iter()
        .map(|c| c.frames.iter().filter(|f| !f.1).count())
        .sum();
    if warmup > 0 {
        progress.note(&format!(
            "temporal: {warmup} frame(s) not asked for are rendered (not written) so that each \
             frame asked for is predicted from its predecessor, as in a run of every frame \
             from its chain's key frame"
        ));
    }
    let (list, region) = selection(anim, opts);
    progress.begin(todo.len(), list.len());
    let pool = thread_pool(anim.render.threads)?;
    summary.threads = pool.current_num_threads();
    // Every frame's thread-seconds, written or warm-up.
    let thread_seconds = Mutex::new(0.0f64);

    // Two chains in flight share the pool: while the last tiles of one frame finish, idle
    // workers take tiles of the other chain's frame. Each driver thread renders its chain's
    // frames in order (a frame starts once its predecessor is complete, so its tiles read the
    // whole previous frame), hands each frame's tiles to the pool and sends the finished film
    // to the writer; files are per frame, so the order they are written in does not matter.
    // Memory stays bounded by the chains in flight (each holds at most the previous frame's
    // carried data and the one being built) plus the channel's capacity.
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let first_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    let (tx, rx) = bounded::<(Film, FrameStats)>(FRAMES_IN_FLIGHT);
    let result: Result<()> = std::thread::scope(|s| {
        let writer = s.spawn(|| -> Result<RunSummary> {
            let mut done = RunSummary::default();
            for (film, stats) in rx {
                let writing = Instant::now();
                sink.write(&film, &stats)?;
                progress.detail(&format!(
                    "frame {}: written in {:.3} s",
                    stats.frame,
                    writing.elapsed().as_secs_f64()
                ));
                done.counts += stats.counts;
                done.rendered += 1;
            }
            Ok(done)
        });
        for _ in 0..FRAMES_IN_FLIGHT.min(work.len()) {
            let tx = tx.clone();
            let (next, failed, first_error, work, pool, inputs, list, thread_seconds) = (
                &next,
                &failed,
                &first_error,
                &work,
                &pool,
                &inputs,
                &list,
                &thread_seconds,
            );
            s.spawn(move || {
                'chains: loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= work.len()
                        || failed.load(Ordering::Relaxed)
                        || opts.cancel.is_cancelled()
                    {
                        break;
                    }
                    let frames = &work[k].frames;
                    let mut prev: Option<Carried> = None;
                    for (n, &(frame, write)) in frames.iter().enumerate() {
                        if failed.load(Ordering::Relaxed) || opts.cancel.is_cancelled() {
                            break 'chains;
                        }
                        let link = Temporal {
                            prev: prev.as_ref(),
                            carry: n + 1 < frames.len(),
                            no_validate: !write,
                        };
                        let shown: &dyn Progress = if write { progress } else { &Silent };
                        let rendered = pool.install(|| {
                            render_tile_list(
                                anim,
                                inputs,
                                frame,
                                list,
                                region,
                                shown,
                                &link,
                                &opts.cancel,
                            )
                        });
                        match rendered {
                            Ok((film, stats, carried)) => {
                                *thread_seconds.lock().unwrap() += stats.thread_seconds;
                                // The previous frame's data has been used: free it now.
                                prev = carried;
                                if !write {
                                    continue;
                                }
                                progress.frame_done(&stats);
                                if tx.send((film, stats)).is_err() {
                                    break 'chains; // the writer failed; reported below
                                }
                            }
                            Err(e) => {
                                failed.store(true, Ordering::Relaxed);
                                first_error.lock().unwrap().get_or_insert(e);
                                break 'chains;
                            }
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
    summary.thread_seconds = thread_seconds.into_inner().unwrap();
    sink.finish(&summary)?;
    Ok(summary)
}
