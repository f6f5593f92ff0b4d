//! Rendering one frame: poses the scene, builds the frame's context and method, runs the shared
//! phases and then the tiles (dearest first) over the current pool, and assembles the film and
//! its statistics. Tiles are added in tile order, so the film does not depend on which thread
//! finished first.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use crate::anim::Animation;
use crate::cancel::Cancel;
use crate::context::FrameContext;
use crate::driver::{FrameWork, Slot};
use crate::error::{Interrupted, Result};
use crate::film::{Film, TileResult};
use crate::history::{Carried, CarryPatch};
use crate::inputs::Inputs;
use crate::lattice::Lattice;
use crate::motion::MotionKind;
use crate::moved::Moved;
use crate::output::stats::FrameStats;
use crate::run::{Progress, TileDone};
use crate::temporal::{Before, Now};
use crate::tile::{Rect, Tile};

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

/// Renders `list` (tiles of one frame); `region` (if any) bounds them and decides how far the
/// shared phases run and over which pixels validation compares images. Once `cancel` is set,
/// tiles not yet started are skipped and the frame ends with [`Interrupted`].
// The frame, its tiles, the temporal link and the stop flag: a struct for them would only be
// unpacked again here.
#[allow(clippy::too_many_arguments)]
pub fn render_tile_list(
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
    let mut time = FrameTime::new();
    let pivot = anim.pivot(&inputs.scene)?;
    let pose = anim.scene_transform(frame, pivot);
    // A moving or animated object gets its own posed scene and BVH; a still one shares the
    // run's.
    let started = Instant::now();
    let moved = match inputs.posed(anim, frame, pose)? {
        Some(scene) => {
            let posed = started.elapsed();
            let accel = inputs.posed_accel(&scene, pose.is_some());
            progress.detail(&format!(
                "frame {frame}: scene posed in {:.1} ms, BVH built in {:.1} ms ({} of {} triangles rebuilt)",
                posed.as_secs_f64() * 1e3,
                (started.elapsed() - posed).as_secs_f64() * 1e3,
                accel.built_triangles(),
                accel.triangle_count()
            ));
            Some((scene, accel))
        }
        None => None,
    };
    let (scene, accel) = match &moved {
        Some((scene, accel)) => (scene, accel),
        None => (&inputs.scene, inputs.still_accel()),
    };
    let camera = anim.camera(&inputs.scene, frame)?;
    let lights = inputs.lights_at(anim, frame);
    let ctx = FrameContext::new(scene, accel, camera, &lights, &inputs.env)
        .with_samples(anim.render.samples())
        .with_terminator_offset(anim.render.terminator_offset)
        .with_glossy(anim.render.glossy_env.then(|| inputs.glossy()).flatten())
        .with_backdrop(&inputs.backdrop)
        .with_environment_turn(anim.motion.environment_degrees(frame));
    // The link in time, decided once for the frame.
    let prev_lights;
    let animated = inputs.animated_triangles();
    let change = temporal
        .prev
        .map(|c| change_since(anim, frame, c, scene, &animated));
    let (prev, moved) = match change {
        Some(Change::Moved(m)) => (temporal.prev, Some(m)),
        Some(Change::Unknown) => (None, None),
        _ => (temporal.prev, None),
    };
    let before = match prev {
        Some(carried) => {
            prev_lights = inputs.lights_at(anim, carried.frame);
            Some(Before {
                carried,
                camera: anim.camera(&inputs.scene, carried.frame)?,
                lights: &prev_lights,
                moved: moved.as_ref(),
            })
        }
        None => None,
    };
    let now = Now {
        frame,
        pivot,
        posed: pose,
        camera: &camera,
        lights: &lights,
    };
    let link = crate::temporal::link(anim, &now, before, temporal.carry);
    // The methods run on the samples: their spacings grow with the samples per pixel side.
    let shadows = anim.render.method.build(
        anim.render
            .params()
            .for_samples(ctx.samples.k)
            .for_cutouts(accel.has_cutouts()),
    );
    let ids = anim
        .output
        .cryptomatte
        .then(|| inputs.scene.cryptomatte_ids());
    let work = FrameWork {
        ctx: &ctx,
        shadows: &shadows,
        link: &link,
        validate: anim.render.validate && !temporal.no_validate,
        shading_rate: anim.render.shading_rate,
        ids: ids.as_ref(),
    };
    let lattice = shared_phases(&work, anim, list, region, cancel, &mut time)?;
    let results = final_phase(&work, list, &lattice, frame, progress, cancel, &mut time)?;
    let (width, height) = (anim.render.width, anim.render.height);
    let mut film = Film::new(width, height, work.holds());
    film.cryptomatte = ids.map(|i| std::sync::Arc::new(i.manifests(scene.triangle_count())));
    let mut carried = link.carried(frame, width, height, ctx.words());
    // A pose of the file's animation: the next frame compares its positions with these.
    if let (Some(c), false) = (&mut carried, animated.is_empty()) {
        c.keep_positions(&scene.positions);
    }
    for (r, patch) in &results {
        film.add(r);
        if let (Some(c), Some(p)) = (&mut carried, patch) {
            c.insert(p);
        }
    }
    drop(results);
    let rendered = region.unwrap_or(Rect::frame(width, height));
    let stats = FrameStats {
        frame,
        method: anim.render.method.name().to_string(),
        lights: lights.len(),
        width,
        height,
        spp: anim.render.spp,
        counts: film.counts,
        image_error: film.image_error(rendered, anim.render.exposure, anim.render.view),
        thread_seconds: time.thread_seconds(),
        camera_position: inputs.scene.to_world(camera.position),
        camera_target: inputs.scene.to_world(camera.target),
        camera_up: camera.up,
        vfov_deg: camera.vfov_deg,
    };
    Ok((film, stats, carried))
}

/// How the geometry changed since the carried frame.
enum Change {
    /// Nothing moved (no animation plays, or its pose held): the previous frame votes
    /// everywhere.
    Still,
    /// The file's animation moved these triangles: the previous frame votes only where its
    /// rays cannot meet them ([`crate::moved`]).
    Moved(Moved),
    /// It moved something the previous frame's view cannot place: the previous frame does
    /// not vote (the frame is predicted from its own pixels, as a key frame is).
    Unknown,
}

/// What the file's animation moved between the carried frame `before` and `frame` (posed as
/// `scene`), of the triangles `animated` it may move.
///
/// [ours] A spin or a turning environment at a deforming frame is left to the frame itself
/// (`Unknown`): the spin's votes are pulled through the turn in the object's space and the
/// environment's are read in place, neither from where the moved triangles were.
fn change_since(
    anim: &Animation,
    frame: usize,
    before: &Carried,
    scene: &crate::scene::Scene,
    animated: &[std::ops::Range<usize>],
) -> Change {
    if animated.is_empty() {
        return Change::Still;
    }
    let Some(positions) = before.positions() else {
        return Change::Unknown;
    };
    match Moved::between(positions, scene, animated) {
        None => Change::Still,
        Some(_)
            if anim.motion.segment_at(frame).kind != MotionKind::Orbit
                && anim.motion.segment_at(frame).kind != MotionKind::Still =>
        {
            Change::Unknown
        }
        Some(m) => Change::Moved(m),
    }
}

/// Runs the frame's shared phases (the grid's coarse levels) over every tile the rendered
/// tiles' halos reach, so a region render reads exactly what the whole frame would have
/// computed; returns the frame's lattice.
fn shared_phases(
    work: &FrameWork,
    anim: &Animation,
    list: &[Tile],
    region: Option<Rect>,
    cancel: &Cancel,
    time: &mut FrameTime,
) -> Result<Lattice> {
    let phases = work.shared_phases();
    let mut lattice = work.lattice();
    if phases == 0 {
        return Ok(lattice);
    }
    let reach = region.map(|r| {
        let grown = r.grow(work.shared_reach());
        anim.render.tiles(Some(grown))
    });
    let shared_tiles = reach.as_deref().unwrap_or(list);
    for phase in 0..phases {
        cancel.check()?;
        let patches: Vec<_> = time.parallel(|tasks| {
            shared_tiles
                .par_iter()
                .map(|t| {
                    tasks
                        .time(|| with_slot(|slot| work.shared_phase(t.rect, slot, phase, &lattice)))
                })
                .collect()
        });
        for p in &patches {
            lattice.insert(p);
        }
    }
    Ok(lattice)
}

/// Renders the tiles of `list` over the current pool and returns their results (and what each
/// carries forward) in the list's order, or [`Interrupted`] once `cancel` is set.
///
/// Dearest tiles first, dealt one at a time to whichever worker is free (longest-processing-
/// time order): a tile on the object's silhouette costs many times one of open ground, and
/// splitting the list by position left one thread finishing the frame alone. Results keep the
/// list's order, so the frame does not depend on the schedule.
fn final_phase(
    work: &FrameWork,
    list: &[Tile],
    lattice: &Lattice,
    frame: usize,
    progress: &dyn Progress,
    cancel: &Cancel,
    time: &mut FrameTime,
) -> Result<Vec<(TileResult, Option<CarryPatch>)>> {
    let mut order: Vec<usize> = (0..list.len()).collect();
    order.sort_by_cached_key(|&t| (std::cmp::Reverse(work.rays_in(lattice, list[t].rect)), t));
    let slots: Vec<Mutex<Option<_>>> = (0..list.len()).map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    time.parallel(|tasks| {
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
                    let r = tasks.time(|| with_slot(|slot| work.tile(t.rect, slot, lattice)));
                    progress.tile_done(&TileDone {
                        frame,
                        index: t.index,
                        rect: t.rect,
                        counts: r.0.counts,
                        seconds: began.elapsed().as_secs_f64(),
                    });
                    *slots[order[k]].lock().unwrap() = Some(r);
                }
            })
    });
    let results: Option<Vec<_>> = slots.into_iter().map(|s| s.into_inner().unwrap()).collect();
    results.ok_or_else(|| Interrupted.into())
}

/// A frame's thread-seconds: the wall time of its serial parts plus its parallel tasks' own
/// run times.
struct FrameTime {
    start: Instant,
    /// Wall time spent in parallel sections (this thread waits there, or helps other frames).
    in_parallel: std::time::Duration,
    tasks: TaskTime,
}

impl FrameTime {
    fn new() -> FrameTime {
        FrameTime {
            start: Instant::now(),
            in_parallel: std::time::Duration::ZERO,
            tasks: TaskTime::default(),
        }
    }

    /// Runs the parallel section `f`, whose tasks time themselves through the [`TaskTime`] it
    /// is given.
    fn parallel<R>(&mut self, f: impl FnOnce(&TaskTime) -> R) -> R {
        let t = Instant::now();
        let r = f(&self.tasks);
        self.in_parallel += t.elapsed();
        r
    }

    fn thread_seconds(&self) -> f64 {
        (self.start.elapsed().saturating_sub(self.in_parallel) + self.tasks.total()).as_secs_f64()
    }
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
