//! `envshadow bench`: seconds per frame and shadow rays per second, for each light count,
//! thread count and method, measured side by side in one run (the machines are shared and
//! noisy, so ratios are only meaningful within one run). Prints a markdown table.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use crate::anim::{Animation, Overrides};
use crate::coordinator::{Inputs, Silent, render_frame, thread_pool};
use crate::error::{Result, input_error};
use crate::predict::Method;

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
}

impl Sweep {
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
    pub method: Method,
    pub seconds: f64,
    pub queries: u64,
    pub rays: u64,
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
    let mut rows = Vec::new();
    for &n in &args.sweep.lights {
        let (mut anim, inputs) = args.sweep.load(&spec, n, Some(args.tile))?;
        for &threads in &args.threads {
            let pool = thread_pool(threads)?;
            for &method in &args.methods {
                anim.method = method;
                let mut times = Vec::with_capacity(args.repeat);
                let mut counts = Default::default();
                for _ in 0..args.repeat {
                    let t = Instant::now();
                    let (film, _) = pool.install(|| {
                        render_frame(&anim, &inputs, args.sweep.frame, None, &Silent)
                    })?;
                    times.push(t.elapsed().as_secs_f64());
                    counts = film.counts;
                }
                times.sort_by(f64::total_cmp);
                let row = BenchRow {
                    lights: inputs.lights.len(),
                    threads: pool.current_num_threads(),
                    method,
                    seconds: times[times.len() / 2],
                    queries: counts.queries,
                    rays: counts.rays,
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
    let mut s = String::from(
        "| lights | threads | method | s/frame | × none | queries | rays traced | % traced | M rays/s |\n|---:|---:|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let none = rows
            .iter()
            .find(|o| o.lights == r.lights && o.threads == r.threads && o.method == Method::None)
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
            r.method,
            r.seconds,
            none,
            r.queries,
            r.rays,
            pct,
            r.rays as f64 / r.seconds / 1e6
        ));
    }
    s
}

/// `envshadow bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    let rows = measure(args, |r| {
        eprintln!(
            "{} lights, {} threads, {}: {:.3} s/frame",
            r.lights, r.threads, r.method, r.seconds
        )
    })?;
    println!(
        "{} {}x{}, frame {}, median of {}:\n",
        args.scene, args.sweep.width, args.sweep.height, args.sweep.frame, args.repeat
    );
    print!("{}", markdown(&rows));
    Ok(())
}
