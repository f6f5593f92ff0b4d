//! `envshadow bench`: seconds per frame and shadow rays per second, for each light count,
//! thread count and method, measured side by side in one run (the machines are shared and
//! noisy, so ratios are only meaningful within one run; each repeat renders every method once,
//! round robin, and the median per method is reported). Prints a markdown table.
//!
//! The split of a frame's time: the BVH build is timed on its own; the shadow rays are the
//! method's own rays, recorded during an extra (untimed) render and traced again alone, in the
//! same order and in the same chunks over the same thread count; the frame without shadows
//! (`none`) is primary rays and shading; what a method costs beyond `none` and its rays is its
//! prediction overhead (voting, flooding, halo pixels, bitset work).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use rayon::prelude::*;

use crate::accel::{self, Accel, PACKET, ShadowRay};
use crate::anim::{Animation, MaterialFlags};
use crate::coordinator::thread_pool;
use crate::error::{Result, input_error};
use crate::film::Counts;
use crate::frame::render_frame;
use crate::inputs::Inputs;
use crate::predict::Method;
use crate::raydump::{self, REPLAY_CHUNK};
use crate::run::Silent;
use crate::scene::Scene;
use crate::settings::{LightsSweep, RenderSweep};
use crate::sweep::{Variant, light_layers, load_scene, tuning, variants};

#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// `shapes`, `bunny` (anims/shapes-turntable.toml, anims/bunny-turntable.toml), a spec
    /// file, or a glTF model (`.glb`, `.gltf`): an auto-framed turntable of it (the camera
    /// framing the model as it turns, 25° up, 40° field of view; see --env).
    #[arg(long, default_value = "bunny")]
    pub scene: String,
    /// The environment map instead of the spec's (for a model: instead of the built-in sky):
    /// an `.exr` or `.hdr` file, or `sky`.
    #[arg(long, value_name = "FILE")]
    pub env: Option<PathBuf>,
    /// Also render each configuration once with validation (untimed): the wrong pairs and the
    /// image's relative RMSE against brute force.
    #[arg(long)]
    pub accuracy: bool,
    /// Print the rows as CSV (one header line) instead of a markdown table.
    #[arg(long)]
    pub csv: bool,
    /// Which frame of the animation.
    #[arg(long, default_value_t = 0)]
    pub frame: usize,
    /// Renders per configuration; the median time is reported.
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Skip the split of frame time (BVH build, shadow rays, prediction overhead), which costs
    /// one extra render and a replay of the rays per configuration.
    #[arg(long)]
    pub no_split: bool,
    /// Also write each method's shadow rays and the frame's triangles to
    /// DIR/rays-LIGHTS-METHOD.bin (see src/raydump.rs), for benches/embree.
    #[arg(long, value_name = "DIR")]
    pub dump_rays: Option<PathBuf>,
    /// Instead of rendering: trace the rays of a dump (from --dump-rays) against its
    /// triangles at each --threads count and print rays/s (the same work as benches/embree).
    #[arg(long, value_name = "FILE")]
    pub replay: Option<PathBuf>,
    /// Light counts and samplers.
    #[command(
        flatten,
        next_help_heading = "Swept settings: comma-separated lists, every combination measured (bench's defaults: --lights 50,100,200,400 --method none,brute --threads 1,2; the rest the spec's)"
    )]
    pub lights: LightsSweep,
    /// Render settings.
    #[command(flatten)]
    pub render: RenderSweep,
    /// Material overrides (`--lambert`: diffuse only, to measure what specular costs).
    #[command(flatten)]
    pub material: MaterialFlags,
}

/// One measured configuration.
#[derive(Clone, Debug)]
pub struct BenchRow {
    pub lights: usize,
    /// The frame's size and samples per pixel.
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub threads: usize,
    /// The method with its flood rule.
    pub variant: Variant,
    pub seconds: f64,
    pub queries: u64,
    /// Shadow rays the frame traced at its pixels, and again at tiles' halos.
    pub rays: u64,
    pub halo_rays: u64,
    /// Whether the timed frame built its BVH (moving geometry) or reused the run's (still
    /// geometry, built before timing).
    pub build_in_frame: bool,
    /// The split (absent with `--no-split`).
    pub split: Option<Split>,
    /// With `--accuracy`: the frame validated against brute force.
    pub accuracy: Option<Accuracy>,
}

/// How a method's frame compares with brute force (one validated render).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Accuracy {
    /// Wrong (sample, light) pairs, % of queries.
    pub wrong_percent: f64,
    /// The image's RMSE over the mean of the brute-force image.
    pub rel_rmse: f64,
}

/// Where a frame's time went, in seconds (medians).
#[derive(Clone, Copy, Debug, Default)]
pub struct Split {
    /// Posing the frame's geometry (a spin, the file's animation) and building its BVH.
    pub build: f64,
    /// Tracing the method's shadow rays alone.
    pub shadow: f64,
    /// Rays traced alone (the tile's and its halo's: more than `BenchRow::rays`).
    pub replayed: u64,
    /// Occluded rays among them (a check against other tracers on the same rays).
    pub blocked: u64,
}

/// How a replay groups the rays it traces together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grouping {
    /// One ray at a time, as another tracer's single-ray query would.
    Single,
    /// Each run of up to [`PACKET`] consecutive rays from one origin (a pixel's) as one
    /// packet: how a frame traced them before they were grouped by light.
    Origin,
    /// Within each chunk, the rays sorted by direction (stably) and each run of up to
    /// [`PACKET`] parallel rays as one packet: a light's queries from nearby points.
    Direction,
}

/// `rays` with each chunk of [`REPLAY_CHUNK`] sorted by direction, and within a direction
/// by their origins' place on a Morton curve over the chunk's bounds: the order
/// [`Grouping::Direction`] traces (sorted before timing, as a frame would collect a light's
/// queries while deciding them).
pub fn by_direction(rays: &[ShadowRay]) -> Vec<ShadowRay> {
    let mut sorted = rays.to_vec();
    for c in sorted.chunks_mut(REPLAY_CHUNK) {
        let (lo, hi) = c
            .iter()
            .fold((glam::Vec3::MAX, glam::Vec3::MIN), |(l, h), r| {
                (l.min(r.origin), h.max(r.origin))
            });
        let scale = 1023.0 / (hi - lo).max(glam::Vec3::splat(1e-30));
        let spread = |v: u32| {
            let mut x = v as u64 & 0x3ff;
            x = (x | x << 16) & 0x0300_00ff;
            x = (x | x << 8) & 0x0300_f00f;
            x = (x | x << 4) & 0x030c_30c3;
            (x | x << 2) & 0x0924_9249
        };
        let morton = |o: glam::Vec3| {
            let q = ((o - lo) * scale).as_uvec3();
            spread(q.x) | spread(q.y) << 1 | spread(q.z) << 2
        };
        c.sort_by_cached_key(|r| {
            (
                r.dir.x.to_bits(),
                r.dir.y.to_bits(),
                r.dir.z.to_bits(),
                morton(r.origin),
            )
        });
    }
    sorted
}

/// Traces `rays` on the current pool in chunks of [`REPLAY_CHUNK`], grouped as `grouping`
/// says (for [`Grouping::Direction`], `rays` as [`by_direction`] sorts them); returns the
/// occluded count.
pub fn replay(accel: &Accel, rays: &[ShadowRay], grouping: Grouping) -> u64 {
    rays.par_chunks(REPLAY_CHUNK)
        .map(|c| {
            let same: fn(&ShadowRay, &ShadowRay) -> bool = match grouping {
                Grouping::Single => {
                    return c.iter().filter(|r| accel.occluded(r.origin, r.dir)).count() as u64;
                }
                Grouping::Origin => |a, b| a.origin == b.origin,
                Grouping::Direction => |a, b| a.dir == b.dir,
            };
            let mut blocked = 0;
            let mut dirs = [glam::Vec3::ZERO; PACKET];
            let mut origins = [glam::Vec3::ZERO; PACKET];
            let inf = [f32::INFINITY; PACKET];
            let mut i = 0;
            while i < c.len() {
                let first = c[i];
                let mut n = 0;
                while i < c.len() && same(&c[i], &first) && n < PACKET {
                    dirs[n] = c[i].dir;
                    origins[n] = c[i].origin;
                    n += 1;
                    i += 1;
                }
                // Packets from one origin as frames trace them; parallel rays each from its own.
                let hit = if grouping == Grouping::Origin {
                    accel.occluded_packet(first.origin, &dirs[..n])
                } else {
                    accel.occluded_rays_within(&origins[..n], &dirs[..n], &inf, &accel::Opaque)
                };
                blocked += hit.count_ones() as u64;
            }
            blocked
        })
        .sum()
}

/// The frame's geometry as `render_frame` poses it (the file's animation, then a spin), or
/// None for the unposed scene.
fn frame_scene(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<Option<Scene>> {
    inputs.posed(anim, frame, frame_spin(anim, inputs, frame)?)
}

/// The spin that `frame` turns the scene by, if any.
fn frame_spin(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<Option<glam::Mat4>> {
    Ok(anim.scene_transform(frame, anim.pivot(&inputs.scene)?))
}

/// Whether the frame's geometry is the unposed scene (its BVH is built once per run).
fn still_geometry(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<bool> {
    Ok(frame_scene(anim, inputs, frame)?.is_none())
}

/// The frame's posed scene and BVH, built as `render_frame` builds them.
fn frame_accel(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<Accel> {
    let spin = frame_spin(anim, inputs, frame)?;
    Ok(match inputs.posed(anim, frame, spin)? {
        Some(posed) => inputs.posed_accel(&posed, spin.is_some()),
        None => inputs.scene.accel(),
    })
}

/// The shadow rays of one render of the frame, in the order a single thread traces them.
fn record_rays(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<Vec<ShadowRay>> {
    let pool = thread_pool(1)?;
    raydump::set_recording(true);
    let result = pool.install(|| render_frame(anim, inputs, frame, None, &Silent));
    raydump::set_recording(false);
    let rays = pool.install(raydump::take_recorded);
    result?;
    Ok(rays)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The spec a measuring command renders: `shapes`, `bunny` or a spec file.
pub fn spec_path(scene: &str, shapes: &str, bunny: &str) -> PathBuf {
    match scene {
        "shapes" => PathBuf::from(shapes),
        "bunny" => PathBuf::from(bunny),
        other => PathBuf::from(other),
    }
}

/// What [`measure`] reports as it goes.
pub enum Log<'a> {
    /// A configuration was measured.
    Row(&'a BenchRow),
    /// A ray dump was written (`--dump-rays`): its path and ray count.
    Dumped(&'a Path, usize),
    /// What the scene loader skipped.
    Warning(&'a str),
}

/// Measures every configuration and returns the rows.
pub fn measure(args: &BenchArgs, mut log: impl FnMut(Log)) -> Result<Vec<BenchRow>> {
    if args.repeat == 0 {
        return Err(input_error("--repeat", "must be at least 1"));
    }
    let spec = spec_path(
        &args.scene,
        "anims/shapes-turntable.toml",
        "anims/bunny-turntable.toml",
    );
    let frame = args.frame;
    let split = !args.no_split || args.dump_rays.is_some();
    let threads = if args.render.threads.is_empty() {
        vec![1, 2]
    } else {
        args.render.threads.clone()
    };
    let mut rows = Vec::new();
    for lights in light_layers(&args.lights)? {
        let (base, inputs) = load_scene(&spec, args.env.as_deref(), &lights, &args.material)?;
        for w in &inputs.scene.warnings {
            log(Log::Warning(w));
        }
        let variants = variants(&base, &args.render, &[Method::NONE, Method::BRUTE])?;
        let anims = variants
            .iter()
            .map(|v| base.with_render(&v.layer))
            .collect::<Result<Vec<_>>>()?;
        let accel = if split {
            Some(frame_accel(&base, &inputs, frame)?)
        } else {
            None
        };
        // Each variant's rays, recorded once per light count (they do not depend on threads).
        let mut recorded: Vec<Vec<ShadowRay>> = Vec::new();
        if let Some(accel) = &accel {
            for (v, anim) in variants.iter().zip(&anims) {
                let rays = record_rays(anim, &inputs, frame)?;
                if let (Some(dir), false) = (&args.dump_rays, rays.is_empty()) {
                    let name = v.label.replace(" --", "-").replace(' ', "-");
                    let path = dir.join(format!("rays-{}-{name}.bin", inputs.lights.len()));
                    raydump::write(&path, accel, &rays)?;
                    log(Log::Dumped(&path, rays.len()));
                }
                recorded.push(rays);
            }
        }
        // One validated render of each variant (untimed): its mistakes against brute force.
        let mut accuracy = vec![None; variants.len()];
        if args.accuracy {
            let pool = thread_pool(threads.iter().copied().max().unwrap_or(0))?;
            for (k, anim) in anims.iter().enumerate() {
                let mut a = anim.clone();
                a.render.validate = true;
                let (film, stats) =
                    pool.install(|| render_frame(&a, &inputs, frame, None, &Silent))?;
                accuracy[k] = Some(Accuracy {
                    wrong_percent: film.counts.error_percent(),
                    rel_rmse: stats.image_error.map_or(0.0, |e| e.rel_rmse),
                });
            }
        }
        // Still geometry (an orbit turntable) has one BVH per run, built by its first frame:
        // build it before timing so every repeat measures a frame as the run's later frames
        // cost. The build itself is the split's `build s` column.
        let still = still_geometry(&base, &inputs, frame)?;
        if still {
            inputs.still_accel();
        }
        // The environment prefiltered for glossy lobes is built once per run too (by its first
        // frame, on the pool): without this the first timed render paid for it, which was
        // the whole of a `--repeat 1` none frame's lead on the metal spheres.
        let pool = thread_pool(threads.iter().copied().max().unwrap_or(0))?;
        pool.install(|| inputs.glossy());
        for &threads in &threads {
            let pool = thread_pool(threads)?;
            // Round robin: each repeat renders every variant once, so a slow spell of the
            // shared machine falls on all of them alike instead of on one variant's repeats.
            let mut times = vec![Vec::with_capacity(args.repeat); variants.len()];
            let mut counts = vec![Counts::default(); variants.len()];
            for _ in 0..args.repeat {
                for (k, anim) in anims.iter().enumerate() {
                    let t = Instant::now();
                    let (film, _) =
                        pool.install(|| render_frame(anim, &inputs, frame, None, &Silent))?;
                    times[k].push(t.elapsed().as_secs_f64());
                    counts[k] = film.counts;
                }
            }
            for (k, v) in variants.iter().enumerate() {
                let split = match &accel {
                    Some(accel) => {
                        let rays = &recorded[k];
                        let mut build = Vec::new();
                        let mut shadow = Vec::new();
                        let mut blocked = 0;
                        for _ in 0..args.repeat {
                            let t = Instant::now();
                            pool.install(|| frame_accel(&base, &inputs, frame))?;
                            build.push(t.elapsed().as_secs_f64());
                            let t = Instant::now();
                            blocked = pool.install(|| replay(accel, rays, Grouping::Origin));
                            shadow.push(t.elapsed().as_secs_f64());
                        }
                        Some(Split {
                            build: median(build),
                            shadow: median(shadow),
                            replayed: rays.len() as u64,
                            blocked,
                        })
                    }
                    None => None,
                };
                let row = BenchRow {
                    build_in_frame: !still,
                    lights: inputs.lights.len(),
                    width: anims[k].render.width,
                    height: anims[k].render.height,
                    spp: anims[k].render.spp,
                    threads: pool.current_num_threads(),
                    variant: v.clone(),
                    seconds: median(std::mem::take(&mut times[k])),
                    queries: counts[k].queries,
                    rays: counts[k].rays,
                    halo_rays: counts[k].halo_rays,
                    split,
                    accuracy: accuracy[k],
                };
                log(Log::Row(&row));
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

impl BenchRow {
    /// Every shadow ray the frame traced: at its pixels and at tiles' halos.
    pub fn traced(&self) -> u64 {
        self.rays + self.halo_rays
    }

    /// The row of `method` among `rows` measured like this one (same lights, threads, size
    /// and samples per pixel).
    pub fn peer<'a>(&self, rows: &'a [BenchRow], method: Method) -> Option<&'a BenchRow> {
        rows.iter().find(|o| {
            o.variant.method == method
                && (o.lights, o.threads, o.width, o.height, o.spp)
                    == (self.lights, self.threads, self.width, self.height, self.spp)
        })
    }

    /// What this method's shadows cost per ray it traced, over what brute force pays per ray:
    /// ((frame − none) ÷ rays traced) ÷ ((brute − none) ÷ queries), from the `none` and
    /// `brute` rows measured beside it. 1 would mean a traced query costs what a brute-force
    /// ray does, bookkeeping included. `None` for `none` and `brute` themselves, without
    /// both peers, or without rays.
    pub fn cost_per_traced(&self, rows: &[BenchRow]) -> Option<f64> {
        if self.variant.method == Method::NONE || self.variant.method == Method::BRUTE {
            return None;
        }
        let none = self.peer(rows, Method::NONE)?;
        let brute = self.peer(rows, Method::BRUTE)?;
        let brute_shadow = brute.seconds - none.seconds;
        if self.traced() == 0 || brute.queries == 0 || brute_shadow <= 0.0 {
            return None;
        }
        let mine = (self.seconds - none.seconds) / self.traced() as f64;
        Some(mine / (brute_shadow / brute.queries as f64))
    }

    /// [`traced`](Self::traced) as a percentage of the queries (0 without queries).
    pub fn percent_traced(&self) -> f64 {
        if self.queries > 0 {
            100.0 * self.traced() as f64 / self.queries as f64
        } else {
            0.0
        }
    }
}

/// The rows as a markdown table; `× none` is the time relative to the same frame without
/// shadows at the same light and thread count. Rays are every ray the frame traced, halos'
/// included.
pub fn markdown(rows: &[BenchRow]) -> String {
    let with_split = rows.iter().any(|r| r.split.is_some());
    let with_accuracy = rows.iter().any(|r| r.accuracy.is_some());
    let mut s = String::from(
        "| lights | threads | method | s/frame | × none | queries | rays traced | % traced | M rays/s |",
    );
    let mut rule = String::from("\n|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    if with_accuracy {
        s.push_str(" wrong pairs % | rel. RMSE |");
        rule.push_str("---:|---:|");
    }
    if with_split {
        s.push_str(
            " build s | primary+shading s | shadow rays s | prediction s | M rays/s traced alone |",
        );
        rule.push_str("---:|---:|---:|---:|---:|");
    }
    let with_cost = rows.iter().any(|r| r.cost_per_traced(rows).is_some());
    if with_cost {
        s.push_str(" traced query ÷ brute ray |");
        rule.push_str("---:|");
    }
    s.push_str(&rule);
    s.push('\n');
    for r in rows {
        let none_row = r.peer(rows, Method::NONE);
        let none = none_row
            .map(|o| format!("{:.2}", r.seconds / o.seconds))
            .unwrap_or_else(|| "–".into());
        s.push_str(&format!(
            "| {} | {} | {} | {:.3} | {} | {} | {} | {:.1} | {:.2} |",
            r.lights,
            r.threads,
            r.variant,
            r.seconds,
            none,
            r.queries,
            r.traced(),
            r.percent_traced(),
            r.traced() as f64 / r.seconds / 1e6
        ));
        if with_accuracy {
            match r.accuracy {
                Some(a) => s.push_str(&format!(" {:.4} | {:.5} |", a.wrong_percent, a.rel_rmse)),
                None => s.push_str(" – | – |"),
            }
        }
        if with_split {
            s.push_str(&split_cells(r, none_row));
        }
        if with_cost {
            match r.cost_per_traced(rows) {
                Some(c) => s.push_str(&format!(" {c:.2} |")),
                None => s.push_str(" – |"),
            }
        }
        s.push('\n');
    }
    s
}

/// The header of [`csv`].
pub const CSV_HEADER: &str = "scene,environment,frame,width,height,spp,lights,threads,method,\
repeats,seconds,queries,rays_traced,halo_rays,percent_traced,wrong_percent,rel_rmse";

/// The rows as CSV ([`CSV_HEADER`], then a line per row; `wrong_percent` and `rel_rmse` empty
/// without `--accuracy`): what scripts/bench-corpus.sh gathers. `rays_traced` counts every ray
/// the frame traced, `halo_rays` those of them traced at tiles' halos.
pub fn csv(args: &BenchArgs, rows: &[BenchRow]) -> String {
    let env = args
        .env
        .as_deref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "spec".into());
    let field = |s: &str| {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    let mut s = format!("{CSV_HEADER}\n");
    for r in rows {
        let (wrong, rel) = match r.accuracy {
            Some(a) => (
                format!("{:.6}", a.wrong_percent),
                format!("{:.6e}", a.rel_rmse),
            ),
            None => (String::new(), String::new()),
        };
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{:.4},{},{},{},{:.4},{},{}\n",
            field(&args.scene),
            field(&env),
            args.frame,
            r.width,
            r.height,
            r.spp,
            r.lights,
            r.threads,
            field(&r.variant.label),
            args.repeat,
            r.seconds,
            r.queries,
            r.traced(),
            r.halo_rays,
            r.percent_traced(),
            wrong,
            rel
        ));
    }
    s
}

/// The split columns of row `r`: primary rays and shading are the frame without shadows less
/// its build (when the frame builds one); prediction is what remains of the frame beyond `none` and the shadow rays.
fn split_cells(r: &BenchRow, none: Option<&BenchRow>) -> String {
    let Some(sp) = r.split else {
        return " – | – | – | – | – |".into();
    };
    let own_build = if r.build_in_frame { sp.build } else { 0.0 };
    let primary = none.map(|o| o.seconds - own_build);
    let prediction = none.map(|o| r.seconds - o.seconds - sp.shadow);
    let f = |v: Option<f64>| v.map(|v| format!("{v:.3}")).unwrap_or_else(|| "–".into());
    let rate = if sp.shadow > 0.0 && sp.replayed > 0 {
        format!("{:.2}", sp.replayed as f64 / sp.shadow / 1e6)
    } else {
        "–".into()
    };
    format!(
        " {:.3} | {} | {:.3} | {} | {} |",
        sp.build,
        f(primary),
        sp.shadow,
        if r.variant.method == Method::NONE {
            "–".into()
        } else {
            f(prediction)
        },
        rate
    )
}

/// `envshadow bench --replay FILE`: our occlusion queries on a dump's rays, per thread count.
/// `envshadow bench --replay FILE`: our occlusion queries on a dump's rays, per thread count
/// (default 1,2), as a heading and a markdown table.
pub fn replay_table(path: &Path, args: &BenchArgs) -> Result<String> {
    if args.repeat == 0 {
        return Err(input_error("--repeat", "must be at least 1"));
    }
    let dump = raydump::read(path)?;
    let positions: Vec<_> = dump.triangles.iter().flatten().copied().collect();
    let triangles: Vec<[u32; 3]> = (0..dump.triangles.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let t = Instant::now();
    let accel = Accel::build(&positions, &triangles);
    let build = t.elapsed().as_secs_f64();
    let mut out = format!(
        "{}: {} triangles (BVH built in {:.3} s), {} rays, chunks of {}, median of {}\n\n",
        path.display(),
        dump.triangles.len(),
        build,
        dump.rays.len(),
        REPLAY_CHUNK,
        args.repeat
    );
    out.push_str("| tracer | threads | s | M rays/s | occluded |\n|---|---:|---:|---:|---:|\n");
    // One at a time: the work of another tracer's single-ray query. Packets: as a frame
    // traces them. Alternated, so both see the same machine load.
    let tracers = [
        ("envshadow (obvhs), one ray at a time", Grouping::Single),
        (
            "envshadow (obvhs), packets from one origin",
            Grouping::Origin,
        ),
        (
            "envshadow (obvhs), packets of parallel rays",
            Grouping::Direction,
        ),
    ];
    let threads = if args.render.threads.is_empty() {
        vec![1, 2]
    } else {
        args.render.threads.clone()
    };
    let sorted = by_direction(&dump.rays);
    for &threads in &threads {
        let pool = thread_pool(threads)?;
        let mut times = vec![Vec::new(); tracers.len()];
        let mut blocked = vec![0; tracers.len()];
        for _ in 0..args.repeat {
            for (k, &(_, packets)) in tracers.iter().enumerate() {
                let t = Instant::now();
                let rays = if packets == Grouping::Direction {
                    &sorted
                } else {
                    &dump.rays
                };
                blocked[k] = pool.install(|| replay(&accel, rays, packets));
                times[k].push(t.elapsed().as_secs_f64());
            }
        }
        for (k, &(name, _)) in tracers.iter().enumerate() {
            let s = median(std::mem::take(&mut times[k]));
            out.push_str(&format!(
                "| {} | {} | {:.3} | {:.2} | {} |\n",
                name,
                pool.current_num_threads(),
                s,
                dump.rays.len() as f64 / s / 1e6,
                blocked[k]
            ));
        }
    }
    Ok(out)
}

/// The heading of a bench table: the scene, frame size, the settings every row shares, the
/// repeats, and whether frames build their BVH.
pub fn heading(args: &BenchArgs, rows: &[BenchRow]) -> String {
    let builds = match rows.first() {
        Some(r) if !r.build_in_frame => {
            "; still geometry: the BVH is built once per run, so s/frame excludes its build"
        }
        Some(_) => "; moving geometry: every frame builds its BVH",
        None => "",
    };
    let size = rows
        .first()
        .map(|r| format!(" {}x{}", r.width, r.height))
        .unwrap_or_default();
    let env = args
        .env
        .as_deref()
        .map(|p| format!(" under {}", p.display()))
        .unwrap_or_default();
    format!(
        "{}{env}{size}, frame {}{}, median of {}{}:",
        args.scene,
        args.frame,
        tuning(&args.render),
        args.repeat,
        builds
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::RenderLayer;

    fn row(method: Method, seconds: f64, queries: u64, rays: u64, spp: u32) -> BenchRow {
        BenchRow {
            lights: 400,
            width: 64,
            height: 48,
            spp,
            threads: 1,
            variant: Variant {
                layer: RenderLayer::default(),
                method,
                label: method.to_string(),
            },
            seconds,
            queries,
            rays,
            halo_rays: rays / 4,
            build_in_frame: false,
            split: None,
            accuracy: None,
        }
    }

    /// none 1 s, brute 11 s for 1000 queries (10 ms a ray); the default 2 s with 32 + 8
    /// rays traced at its tiles and halos (25 ms a ray): 2.5× brute force's cost per ray. Rows of another size of
    /// sample are not its peers, and `none` and `brute` have no such cost.
    #[test]
    fn a_traced_query_is_costed_against_brute_forces_ray_measured_beside_it() {
        let rows = vec![
            row(Method::NONE, 1.0, 1000, 0, 1),
            row(Method::BRUTE, 11.0, 1000, 1000, 1),
            row(Method::DEFAULT, 2.0, 1000, 32, 1),
            row(Method::NONE, 3.0, 4000, 0, 4),
            row(Method::DEFAULT, 5.0, 4000, 40, 4),
        ];
        let cost = rows[2].cost_per_traced(&rows).expect("peers measured");
        assert!((cost - 2.5).abs() < 1e-12, "{cost}");
        assert_eq!(
            rows[4].cost_per_traced(&rows),
            None,
            "no brute row at 4 spp"
        );
        assert_eq!(rows[0].cost_per_traced(&rows), None);
        assert_eq!(rows[1].cost_per_traced(&rows), None);
        let table = markdown(&rows);
        assert!(table.contains("traced query ÷ brute ray"), "{table}");
        let line = table.lines().nth(4).unwrap();
        assert!(line.ends_with(" 2.50 |"), "{line}");
        // The 4-spp row's `× none` is against the 4-spp none row (5 ÷ 3), not the 1-spp one.
        let line = table.lines().last().unwrap();
        assert!(line.contains("| 1.67 |"), "{line}");
    }
}
