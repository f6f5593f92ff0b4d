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
use crate::anim::{Animation, Overrides};
use crate::coordinator::{Inputs, Silent, render_frame, thread_pool};
use crate::error::{Result, input_error};
use crate::predict::{FloodTo, Method, Variant};
use crate::raydump::{self, REPLAY_CHUNK};

#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// `shapes`, `bunny` (anims/shapes-turntable.toml, anims/bunny-turntable.toml) or a spec file.
    #[arg(long, default_value = "bunny")]
    pub scene: String,
    #[command(flatten)]
    pub sweep: Sweep,
    /// Thread counts, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub threads: Vec<usize>,
    /// Methods, comma-separated (`none` is the frame without shadows).
    #[arg(long, value_delimiter = ',', default_value = "none,brute")]
    pub methods: Vec<Method>,
    /// Renders per configuration; the median time is reported.
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Tile size.
    #[arg(long, default_value_t = 64)]
    pub tile: u32,
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
}

/// The frames a measuring command renders: one frame of an animation at each light count.
#[derive(Args, Debug, Clone)]
pub struct Sweep {
    /// Light counts, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "50,100,200,400")]
    pub lights: Vec<usize>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 480)]
    pub height: u32,
    /// Which frame of the animation.
    #[arg(long, default_value_t = 0)]
    pub frame: usize,
    /// Coarse grid spacing of the grid methods (default: the spec's, else 16).
    #[arg(long, value_name = "N")]
    pub h0: Option<u32>,
    /// Uncertainty methods' voter threshold, 1–4 (default: the spec's, else 3).
    #[arg(long, value_name = "K")]
    pub min_voters: Option<u32>,
    /// Flood rules, comma-separated: each uncertainty method is measured with each (the
    /// others trace the same under every rule).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "contrary-finest",
        value_name = "RULES"
    )]
    pub flood_to: Vec<FloodTo>,
}

impl Sweep {
    /// The parameters the sweep sets beyond the spec's, for a table's heading
    /// (", h0 8, min_voters 2"; empty when none).
    pub fn tuning(&self) -> String {
        let mut s = String::new();
        if let Some(h0) = self.h0 {
            s.push_str(&format!(", h0 {h0}"));
        }
        if let Some(k) = self.min_voters {
            s.push_str(&format!(", min_voters {k}"));
        }
        s
    }

    /// The animation `spec` at `lights` lights and the sweep's size, with its inputs loaded.
    pub fn load(
        &self,
        spec: &Path,
        lights: usize,
        tile: Option<u32>,
    ) -> Result<(Animation, Inputs)> {
        let overrides = Overrides {
            lights: Some(lights),
            width: Some(self.width),
            height: Some(self.height),
            tile,
            h0: self.h0,
            min_voters: self.min_voters,
            ..Default::default()
        };
        let anim = Animation::load(spec, &overrides)?;
        let inputs = Inputs::load(&anim)?;
        Ok((anim, inputs))
    }
}

/// One measured configuration.
#[derive(Clone, Debug)]
pub struct BenchRow {
    pub lights: usize,
    pub threads: usize,
    /// The method with its flood rule.
    pub variant: Variant,
    pub seconds: f64,
    pub queries: u64,
    pub rays: u64,
    /// Whether the timed frame built its BVH (moving geometry) or reused the run's (still
    /// geometry, built before timing).
    pub build_in_frame: bool,
    /// The split (absent with `--no-split`).
    pub split: Option<Split>,
}

/// Where a frame's time went, in seconds (medians).
#[derive(Clone, Copy, Debug, Default)]
pub struct Split {
    /// Building the BVH of the frame's geometry.
    pub build: f64,
    /// Tracing the method's shadow rays alone.
    pub shadow: f64,
    /// Rays traced alone (the tile's and its halo's: more than `BenchRow::rays`).
    pub replayed: u64,
    /// Occluded rays among them (a check against other tracers on the same rays).
    pub blocked: u64,
}

/// Traces `rays` on the current pool in chunks of [`REPLAY_CHUNK`]; returns the occluded count.
/// One at a time (`packets` false), as another tracer's single-ray query would; or as a frame
/// traces them, each run of up to [`PACKET`] consecutive rays from one origin (a pixel's) as
/// one packet.
pub fn replay(accel: &Accel, rays: &[ShadowRay], packets: bool) -> u64 {
    rays.par_chunks(REPLAY_CHUNK)
        .map(|c| {
            if !packets {
                return c
                    .iter()
                    .filter(|r| accel.occluded_unrecorded(r.origin, r.dir))
                    .count() as u64;
            }
            let mut blocked = 0;
            let mut dirs = [glam::Vec3::ZERO; PACKET];
            let mut i = 0;
            while i < c.len() {
                let origin = c[i].origin;
                let mut n = 0;
                while i < c.len() && c[i].origin == origin && n < PACKET {
                    dirs[n] = c[i].dir;
                    n += 1;
                    i += 1;
                }
                blocked += accel
                    .occluded_packet_unrecorded(origin, &dirs[..n])
                    .count_ones() as u64;
            }
            blocked
        })
        .sum()
}

/// Whether the frame's geometry is the unposed scene (its BVH is built once per run).
fn still_geometry(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<bool> {
    let camera0 = anim.camera(&inputs.scene, 0)?;
    Ok(anim.scene_transform(frame, camera0.target).is_none())
}

/// The frame's BVH, built as `render_frame` builds it.
fn frame_accel(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<Accel> {
    let camera0 = anim.camera(&inputs.scene, 0)?;
    Ok(match anim.scene_transform(frame, camera0.target) {
        Some(m) => {
            let posed = inputs.scene.transformed(m);
            Accel::build(&posed.positions, &posed.triangles)
        }
        None => Accel::build(&inputs.scene.positions, &inputs.scene.triangles),
    })
}

/// The shadow rays of one render of the frame, in the order a single thread traces them.
fn record_rays(anim: &Animation, inputs: &Inputs, frame: usize) -> Result<Vec<ShadowRay>> {
    let pool = thread_pool(1)?;
    accel::set_recording(true);
    let result = pool.install(|| render_frame(anim, inputs, frame, None, &Silent));
    accel::set_recording(false);
    let rays = pool.install(accel::take_recorded);
    result?;
    Ok(rays)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn spec_path(scene: &str) -> PathBuf {
    match scene {
        "shapes" => PathBuf::from("anims/shapes-turntable.toml"),
        "bunny" => PathBuf::from("anims/bunny-turntable.toml"),
        other => PathBuf::from(other),
    }
}

/// Measures every configuration and returns the rows.
pub fn measure(args: &BenchArgs, mut log: impl FnMut(&BenchRow)) -> Result<Vec<BenchRow>> {
    if args.repeat == 0 {
        return Err(input_error("--repeat", "must be at least 1"));
    }
    let spec = spec_path(&args.scene);
    let frame = args.sweep.frame;
    let split = !args.no_split || args.dump_rays.is_some();
    let variants = Variant::sweep(&args.methods, &args.sweep.flood_to);
    let mut rows = Vec::new();
    for &n in &args.sweep.lights {
        let (mut anim, inputs) = args.sweep.load(&spec, n, Some(args.tile))?;
        let accel = if split {
            Some(frame_accel(&anim, &inputs, frame)?)
        } else {
            None
        };
        // Each method's rays, recorded once per light count (they do not depend on threads).
        let base = anim.params;
        let mut recorded: Vec<(Variant, Vec<ShadowRay>)> = Vec::new();
        if let Some(accel) = &accel {
            for &v in &variants {
                anim.method = v.method;
                anim.params = v.params(base);
                let rays = record_rays(&anim, &inputs, frame)?;
                if let (Some(dir), false) = (&args.dump_rays, rays.is_empty()) {
                    let name = if v.flood_to == FloodTo::default() {
                        v.method.to_string()
                    } else {
                        format!("{}-{}", v.method, v.flood_to)
                    };
                    let path = dir.join(format!("rays-{}-{name}.bin", inputs.lights.len()));
                    raydump::write(&path, accel, &rays)?;
                    eprintln!("wrote {} ({} rays)", path.display(), rays.len());
                }
                recorded.push((v, rays));
            }
        }
        // Still geometry (an orbit turntable) has one BVH per run, built by its first frame:
        // build it before timing so every repeat measures a frame as the run's later frames
        // cost. The build itself is the split's `build s` column.
        let still = still_geometry(&anim, &inputs, frame)?;
        if still {
            inputs.still_accel();
        }
        for &threads in &args.threads {
            let pool = thread_pool(threads)?;
            // Round robin: each repeat renders every method once, so a slow spell of the
            // shared machine falls on all methods alike instead of on one method's repeats.
            let mut times = vec![Vec::with_capacity(args.repeat); variants.len()];
            let mut counts = vec![Default::default(); variants.len()];
            for _ in 0..args.repeat {
                for (k, &v) in variants.iter().enumerate() {
                    anim.method = v.method;
                    anim.params = v.params(base);
                    let t = Instant::now();
                    let (film, _) =
                        pool.install(|| render_frame(&anim, &inputs, frame, None, &Silent))?;
                    times[k].push(t.elapsed().as_secs_f64());
                    counts[k] = film.counts;
                }
            }
            for (k, &v) in variants.iter().enumerate() {
                anim.method = v.method;
                anim.params = v.params(base);
                let counts: crate::film::Counts = counts[k];
                let split = match &accel {
                    Some(accel) => {
                        let rays = &recorded.iter().find(|(r, _)| *r == v).unwrap().1;
                        let mut build = Vec::new();
                        let mut shadow = Vec::new();
                        let mut blocked = 0;
                        for _ in 0..args.repeat {
                            let t = Instant::now();
                            pool.install(|| frame_accel(&anim, &inputs, frame))?;
                            build.push(t.elapsed().as_secs_f64());
                            let t = Instant::now();
                            blocked = pool.install(|| replay(accel, rays, true));
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
                    threads: pool.current_num_threads(),
                    variant: v,
                    seconds: median(std::mem::take(&mut times[k])),
                    queries: counts.queries,
                    rays: counts.rays,
                    split,
                };
                log(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// The rows as a markdown table; `× none` is the time relative to the same frame without
/// shadows at the same light and thread count.
pub fn markdown(rows: &[BenchRow]) -> String {
    let with_split = rows.iter().any(|r| r.split.is_some());
    let mut s = String::from(
        "| lights | threads | method | s/frame | × none | queries | rays traced | % traced | M rays/s |",
    );
    if with_split {
        s.push_str(
            " build s | primary+shading s | shadow rays s | prediction s | M rays/s traced alone |",
        );
    }
    s.push_str("\n|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    if with_split {
        s.push_str("---:|---:|---:|---:|---:|");
    }
    s.push('\n');
    for r in rows {
        let none_row = rows.iter().find(|o| {
            o.lights == r.lights && o.threads == r.threads && o.variant.method == Method::NONE
        });
        let none = none_row
            .map(|o| format!("{:.2}", r.seconds / o.seconds))
            .unwrap_or_else(|| "–".into());
        let pct = if r.queries > 0 {
            100.0 * r.rays as f64 / r.queries as f64
        } else {
            0.0
        };
        s.push_str(&format!(
            "| {} | {} | {} | {:.3} | {} | {} | {} | {:.1} | {:.2} |\n",
            r.lights,
            r.threads,
            r.variant,
            r.seconds,
            none,
            r.queries,
            r.rays,
            pct,
            r.rays as f64 / r.seconds / 1e6
        ));
        if with_split {
            s.pop();
            s.push_str(&split_cells(r, none_row));
            s.push('\n');
        }
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
fn run_replay(path: &Path, args: &BenchArgs) -> Result<()> {
    let dump = raydump::read(path)?;
    let positions: Vec<_> = dump.triangles.iter().flatten().copied().collect();
    let triangles: Vec<[u32; 3]> = (0..dump.triangles.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let t = Instant::now();
    let accel = Accel::build(&positions, &triangles);
    let build = t.elapsed().as_secs_f64();
    println!(
        "{}: {} triangles (BVH built in {:.3} s), {} rays, chunks of {}, median of {}\n",
        path.display(),
        dump.triangles.len(),
        build,
        dump.rays.len(),
        REPLAY_CHUNK,
        args.repeat
    );
    println!("| tracer | threads | s | M rays/s | occluded |\n|---|---:|---:|---:|---:|");
    // One at a time: the work of another tracer's single-ray query. Packets: as a frame
    // traces them. Alternated, so both see the same machine load.
    let tracers = [
        ("envshadow (obvhs), one ray at a time", false),
        ("envshadow (obvhs), packets from one origin", true),
    ];
    for &threads in &args.threads {
        let pool = thread_pool(threads)?;
        let mut times = vec![Vec::new(); tracers.len()];
        let mut blocked = vec![0; tracers.len()];
        for _ in 0..args.repeat {
            for (k, &(_, packets)) in tracers.iter().enumerate() {
                let t = Instant::now();
                blocked[k] = pool.install(|| replay(&accel, &dump.rays, packets));
                times[k].push(t.elapsed().as_secs_f64());
            }
        }
        for (k, &(name, _)) in tracers.iter().enumerate() {
            let s = median(std::mem::take(&mut times[k]));
            println!(
                "| {} | {} | {:.3} | {:.2} | {} |",
                name,
                pool.current_num_threads(),
                s,
                dump.rays.len() as f64 / s / 1e6,
                blocked[k]
            );
        }
    }
    Ok(())
}

/// `envshadow bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    if args.repeat == 0 {
        return Err(input_error("--repeat", "must be at least 1"));
    }
    if let Some(path) = &args.replay {
        return run_replay(path, args);
    }
    let rows = measure(args, |r| {
        eprintln!(
            "{} lights, {} threads, {}: {:.3} s/frame",
            r.lights, r.threads, r.variant, r.seconds
        )
    })?;
    let builds = match rows.first() {
        Some(r) if !r.build_in_frame => {
            "; still geometry: the BVH is built once per run, so s/frame excludes its build"
        }
        Some(_) => "; moving geometry: every frame builds its BVH",
        None => "",
    };
    println!(
        "{} {}x{}, frame {}{}, median of {}{}:\n",
        args.scene,
        args.sweep.width,
        args.sweep.height,
        args.sweep.frame,
        args.sweep.tuning(),
        args.repeat,
        builds
    );
    print!("{}", markdown(&rows));
    Ok(())
}
