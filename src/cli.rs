//! The command line: argument definitions (clap) and the progress display. The library does
//! the work; this module turns flags into library calls and library reports into output.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use crate::anim::{Animation, FrameRange, Overrides, parse_sampler};
use crate::bench;
use crate::coordinator::{self, Progress, RunOptions};
use crate::envmap::EnvMap;
use crate::error::{Result, input_error};
use crate::lights::{LightSet, Sampler};
use crate::output::stats::FrameStats;
use crate::predict::{FloodTo, Method};
use crate::tile::Rect;

const AFTER_HELP: &str = "\
Exit codes: 0 success; 1 internal failure (a bug, or the disk); 2 bad input (a file, a flag or
an animation spec is wrong, or the request is over a limit; the one-line message names the file
and where in it); 130 interrupted by Ctrl-C, SIGTERM or SIGHUP (frames in flight are dropped,
complete frames are kept; run again with --resume; a second signal stops at once).

Limits, checked before work starts: width and height up to 16384, 64 Mpixels, 4096 lights,
10^6 frames, 2 GB per input file, 2^26 triangles, and 16 GB of expected memory.

Examples:
  envshadow render anims/shapes-turntable.toml
  envshadow render anims/bunny-turntable.toml --frames 0..8 --lights 400 --out out/bunny
  envshadow lights assets/grace.hdr -n 200 --json lights.json --png cells.png
  envshadow report out/shapes-turntable";

/// Batch renderer for turntable animations of glTF scenes lit by HDR environment maps, with
/// shadows from every light direction (Ben-Artzi, Ramamoorthi & Agrawala 2004).
#[derive(Parser, Debug)]
#[command(name = "envshadow", version, about, after_help = AFTER_HELP)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render an animation spec (TOML) into frames, stats.csv and lights.json.
    Render(RenderArgs),
    /// Reduce an environment map to N directional lights; write them as JSON and a picture.
    Lights(LightsArgs),
    /// Measure seconds per frame and shadow rays per second (see BENCHMARKS.md).
    Bench(bench::BenchArgs),
    /// Reproduce the paper's Table 1: % of shadow queries traced per method, validated.
    Table(crate::table::TableArgs),
    /// Write DIR/report.html about a finished render: frames, savings plot, heat maps of the
    /// rays traced (and, validated, of wrong predictions), the lights, settings and totals.
    Report(ReportArgs),
    /// Split a render into N jobs for several machines: writes OUT/plan.json, OUT/jobs.txt
    /// (one job per line: index, frames, tiles, folder; tab-separated for GNU parallel) and
    /// OUT/inputs.txt, and prints the job lines. See docs/farm.md.
    Plan(PlanArgs),
    /// Stitch the jobs under DIR/jobs/ into DIR's frames, stats.csv and lights.json, exactly
    /// as a one-process render writes them; names every missing or corrupt job (exit 2).
    Assemble(AssembleArgs),
    /// Print the version; with --build also the build identity (a hash of this executable),
    /// which every farm host must share.
    Version(VersionArgs),
    /// Write one frame's triangles, normals, albedos, lights, camera rays and shadow offset for
    /// another renderer (scripts/compare-mitsuba.sh).
    Export(crate::export::ExportArgs),
    /// Plot percent traced per frame with and without --temporal (DIR/savings.png) from two
    /// renders of the same frames (scripts/temporal-savings.sh makes both).
    Savings(SavingsArgs),
}

#[derive(Args, Debug)]
pub struct PlanArgs {
    /// The animation spec.
    pub spec: PathBuf,
    #[command(flatten)]
    pub flags: AnimFlags,
    /// Number of jobs (the plan has fewer when the work does not split that far).
    #[arg(long, value_name = "N")]
    pub jobs: usize,
    /// How to split: tiles (tile strips through the frame range; the default), frames
    /// (frame ranges; the default when frames depend on whole previous frames) or both.
    #[arg(long, value_enum)]
    pub by: Option<crate::farm::plan::By>,
    /// Do not print the job lines.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Args, Debug)]
pub struct AssembleArgs {
    /// The farm's output folder (with plan.json and jobs/).
    pub dir: PathBuf,
    /// Do not write report.html (and report/).
    #[arg(long)]
    pub no_report: bool,
}

#[derive(Args, Debug)]
pub struct VersionArgs {
    /// Also print the build identity: `envshadow 0.1.0 build 0123456789abcdef`.
    #[arg(long)]
    pub build: bool,
}

#[derive(Args, Debug)]
pub struct SavingsArgs {
    /// The output folder of the render with --temporal.
    pub dir: PathBuf,
    /// The output folder of the same frames rendered without --temporal.
    #[arg(long, value_name = "DIR")]
    pub without: PathBuf,
    /// Where to write the plot (default: DIR/savings.png).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A render's output folder (with stats.csv, the frames and lights.json).
    pub dir: PathBuf,
}

/// Flags shared by every command that renders an animation: each overrides the spec.
#[derive(Args, Debug, Clone, Default)]
pub struct AnimFlags {
    /// Frames to render: A..B (B excluded), A..=B, or A. Default: all of the animation.
    #[arg(long, value_name = "RANGE")]
    pub frames: Option<FrameRange>,
    /// Number of directional lights the environment is reduced to.
    #[arg(long, value_name = "N")]
    pub lights: Option<usize>,
    /// Light sampler: sis (structured importance sampling) or median-cut.
    #[arg(long, value_parser = parse_sampler)]
    pub sampler: Option<Sampler>,
    /// Image width in pixels.
    #[arg(long, value_name = "W")]
    pub width: Option<u32>,
    /// Image height in pixels.
    #[arg(long, value_name = "H")]
    pub height: Option<u32>,
    /// Shadow method: grid-nowarp-uncertainty (the default), grid-warp-uncertainty,
    /// grid-nowarp-boundary, grid-warp-boundary, scan-warp-boundary, brute (trace every shadow
    /// ray) or none (no shadows).
    #[arg(long, value_name = "METHOD")]
    pub method: Option<Method>,
    /// Also trace every shadow query and record the method's mistakes: stats.csv gains wrong
    /// pairs, error rate and image error; the EXR gains a `wrong` layer.
    #[arg(long)]
    pub validate: bool,
    /// Coarse grid spacing of the grid methods (a power of two; default 16).
    #[arg(long, value_name = "N")]
    pub h0: Option<u32>,
    /// Uncertainty methods: trace a light when fewer voters than this have it above their
    /// horizon (1–4; default 3).
    #[arg(long, value_name = "K")]
    pub min_voters: Option<u32>,
    /// Uncertainty methods: which neighbour lights a flooding trace also traces — `all`
    /// untraced ones; `contrary`: only those predicted opposite to the traced answer, about a
    /// third fewer rays with more wrong pairs; `contrary-finest` (the default): `contrary` at
    /// the grid's finest level, whose wrong pairs mislead no coarser pixel, and `all` above
    /// it, about a fifth fewer rays than `all` for a few percent more wrong pairs
    /// (docs/methods.md). Boundary methods trace the same under every rule.
    #[arg(long, value_name = "RULE")]
    pub flood_to: Option<FloodTo>,
    /// Block size at which the scanline order restarts (default 64).
    #[arg(long, value_name = "N")]
    pub scan_block: Option<u32>,
    /// Let every pixel whose surface point the previous frame saw use the previous frame's
    /// pixels there as voters (camera orbit: reprojection; object spin: votes pulled through
    /// the turn). Grid uncertainty methods only. See docs/temporal.md.
    #[arg(long)]
    pub temporal: bool,
    /// With --temporal: frames 0, N, 2N, … are predicted from their own pixels and restart the
    /// chain (default 16 for a camera orbit, 4 for a spinning object). A run starting between key frames first renders, without writing,
    /// the frames back to the key frame before it.
    #[arg(long, value_name = "N")]
    pub keyframe: Option<u32>,
    /// Worker threads (0: one per core).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Tile size in pixels (0: the whole frame is one tile; otherwise at least 8).
    #[arg(long, value_name = "N")]
    pub tile: Option<u32>,
    /// Output folder (default: the spec's [output] dir).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Exposure of the PNG previews (the EXR keeps linear radiance).
    #[arg(long, value_name = "X")]
    pub exposure: Option<f32>,
}

impl AnimFlags {
    pub fn overrides(&self) -> Overrides {
        Overrides {
            frames: self.frames,
            lights: self.lights,
            sampler: self.sampler,
            width: self.width,
            height: self.height,
            method: self.method,
            threads: self.threads,
            tile: self.tile,
            out: self.out.clone(),
            exposure: self.exposure,
            validate: self.validate,
            h0: self.h0,
            min_voters: self.min_voters,
            flood_to: self.flood_to,
            scan_block: self.scan_block,
            temporal: self.temporal,
            keyframe: self.keyframe,
        }
    }
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The animation spec, e.g. anims/shapes-turntable.toml.
    pub spec: PathBuf,
    #[command(flatten)]
    pub flags: AnimFlags,
    /// Skip frames whose EXR and PNG already exist in the output folder.
    #[arg(long)]
    pub resume: bool,
    /// Render only the pixel rectangle x0,y0,x1,y1 (x1, y1 excluded); the rest stays black.
    #[arg(long, value_name = "x0,y0,x1,y1", value_parser = parse_region)]
    pub region: Option<Rect>,
    /// No progress output.
    #[arg(long, short)]
    pub quiet: bool,
    /// Do not write report.html (and report/) into the output folder at the end.
    #[arg(long)]
    pub no_report: bool,
    /// Farm job: render job K of the plan for --of N jobs (see `envshadow plan`) into
    /// OUT/jobs/<folder>/ as tile images and per-frame statistics.
    #[arg(long, value_name = "K", requires = "of", conflicts_with_all = ["tiles", "region"])]
    pub job: Option<usize>,
    /// The plan's job count for --job.
    #[arg(long, value_name = "N", requires = "job")]
    pub of: Option<usize>,
    /// The plan's split for --job (as given to `envshadow plan`).
    #[arg(long, value_enum, requires = "job")]
    pub by: Option<crate::farm::plan::By>,
    /// Farm job: render these tiles (e.g. 0-4,9; frame-anchored tile numbers) of the --frames
    /// into OUT/jobs/<folder>/, as `--job` does.
    #[arg(long, value_name = "LIST", conflicts_with = "region")]
    pub tiles: Option<crate::farm::plan::TileSet>,
}

#[derive(Args, Debug)]
pub struct LightsArgs {
    /// Environment map: a lat-long .exr or .hdr file, or `builtin:sky`.
    pub map: String,
    /// Number of lights.
    #[arg(short = 'n', long = "count", default_value_t = 200)]
    pub count: usize,
    /// Light sampler: sis or median-cut.
    #[arg(long, value_parser = parse_sampler, default_value = "sis")]
    pub sampler: Sampler,
    /// Rotate the map about the up axis, degrees.
    #[arg(long, default_value_t = 0.0)]
    pub rotation: f32,
    /// Scale the map's radiance.
    #[arg(long, default_value_t = 1.0)]
    pub intensity: f32,
    /// Write the lights as JSON here.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write a picture of the cells and light positions over the map here.
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
}

fn parse_region(s: &str) -> std::result::Result<Rect, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.trim().parse::<u32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| format!("{s:?}: expected four pixel bounds x0,y0,x1,y1"))?;
    match v[..] {
        [x0, y0, x1, y1] if x1 > x0 && y1 > y0 => Ok(Rect::new(x0, y0, x1, y1)),
        [_, _, _, _] => Err(format!(
            "{s:?}: the region is empty (need x1 > x0 and y1 > y0)"
        )),
        _ => Err(format!("{s:?}: expected four pixel bounds x0,y0,x1,y1")),
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render(args),
        Command::Lights(args) => lights(args),
        Command::Bench(args) => bench::run(&args),
        Command::Table(args) => crate::table::run(&args),
        Command::Plan(args) => plan(args),
        Command::Assemble(args) => assemble(args),
        Command::Version(args) => {
            if args.build {
                println!(
                    "envshadow {} build {}",
                    env!("CARGO_PKG_VERSION"),
                    crate::farm::identity::build_id()?
                );
            } else {
                println!("envshadow {}", env!("CARGO_PKG_VERSION"));
            }
            Ok(())
        }
        Command::Export(args) => crate::export::run(&args),
        Command::Savings(args) => {
            let s = crate::savings::write_savings(&args.dir, &args.without, args.out.as_deref())?;
            let n = s.frames.len() as f64;
            let (with, without) = s
                .frames
                .iter()
                .fold((0.0, 0.0), |acc, r| (acc.0 + r.1 / n, acc.1 + r.2 / n));
            println!(
                "wrote {}: {} frames, mean {with:.2} % traced with --temporal, {without:.2} % \
                 without ({:.0} %); blue = with, grey = without, y grid every {} % up to {} %",
                s.png.display(),
                s.frames.len(),
                100.0 * with / without.max(1e-12),
                s.axis.1,
                s.axis.0
            );
            Ok(())
        }
        Command::Report(args) => {
            let start = Instant::now();
            let page = crate::report::write_report(&args.dir)?;
            println!(
                "wrote {} in {:.1} s",
                page.display(),
                start.elapsed().as_secs_f64()
            );
            Ok(())
        }
    }
}

fn plan(args: PlanArgs) -> Result<()> {
    let anim = Animation::load(&args.spec, &args.flags.overrides())?;
    let jobs = crate::farm::write_plan(&anim, &args.spec, args.jobs, args.by)?;
    if !args.quiet {
        print!("{}", crate::farm::plan::job_lines(&jobs));
    }
    eprintln!(
        "{}: {} jobs for frames {}..{} ({} asked); plan in {}",
        anim.name,
        jobs.len(),
        anim.frames.start,
        anim.frames.end,
        args.jobs,
        anim.out_dir.join("plan.json").display()
    );
    Ok(())
}

fn assemble(args: AssembleArgs) -> Result<()> {
    let start = Instant::now();
    let done = crate::farm::assemble::assemble(&args.dir)?;
    for p in &done.problems {
        eprintln!("{p}");
    }
    eprintln!(
        "{}: {} of {} frames assembled from {} jobs in {:.1} s",
        args.dir.display(),
        done.written,
        done.frames,
        done.jobs,
        start.elapsed().as_secs_f64()
    );
    if !done.problems.is_empty() {
        return Err(input_error(
            &args.dir,
            format!(
                "{} job(s) missing, incomplete or corrupt (listed above); render them again (e.g. rerun scripts/farm.sh, or envshadow render --job K --of N --resume) and assemble again",
                done.problems.len()
            ),
        ));
    }
    if !args.no_report && done.written > 0 {
        crate::report::write_report(&args.dir)?;
    }
    Ok(())
}

fn render(args: RenderArgs) -> Result<()> {
    let anim = Animation::load(&args.spec, &args.flags.overrides())?;
    let selection = match (args.job, args.of, &args.tiles) {
        (Some(index), Some(of), _) => Some(crate::farm::JobSelection::Planned {
            index,
            of,
            by: args.by,
        }),
        (_, _, Some(t)) => Some(crate::farm::JobSelection::Tiles(t.clone())),
        _ => None,
    };
    if let Some(sel) = selection {
        let progress: Box<dyn Progress> = if args.quiet {
            Box::new(coordinator::Silent)
        } else {
            Box::new(Reporter::new(std::io::stderr().is_terminal()))
        };
        let (job, dir, summary) = crate::farm::render_job(
            &anim,
            &sel,
            args.resume,
            crate::cancel::Cancel::on_signals()?,
            progress.as_ref(),
        )?;
        if !args.quiet {
            eprintln!(
                "{}: {} frames rendered, {} skipped in {:.1} s; output in {}",
                job.describe(),
                summary.rendered,
                summary.skipped,
                summary.seconds,
                dir.display()
            );
        }
        return Ok(());
    }
    if let Some(r) = args.region
        && (r.x1 > anim.width || r.y1 > anim.height)
    {
        return Err(input_error(
            "--region",
            format!(
                "{r} reaches outside the {}x{} frame",
                anim.width, anim.height
            ),
        ));
    }
    let opts = RunOptions {
        resume: args.resume,
        region: args.region,
        tiles: None,
        cancel: crate::cancel::Cancel::on_signals()?,
    };
    let progress: Box<dyn Progress> = if args.quiet {
        Box::new(coordinator::Silent)
    } else {
        Box::new(Reporter::new(std::io::stderr().is_terminal()))
    };
    let mut files = coordinator::FrameFiles::new(&anim);
    let summary = coordinator::render_animation(&anim, &opts, &mut files, progress.as_ref())?;
    if !args.quiet {
        eprintln!(
            "{}: {} frames rendered, {} skipped in {:.1} s; {} shadow queries, {} rays traced ({:.2} %); output in {}",
            anim.name,
            summary.rendered,
            summary.skipped,
            summary.seconds,
            summary.counts.queries,
            summary.counts.rays,
            summary.counts.percent_traced(),
            anim.out_dir.display()
        );
    }
    if !args.no_report {
        let start = Instant::now();
        let page = crate::report::write_report(&anim.out_dir).with_context(|| {
            format!(
                "the frames are written, but not the report (retry with envshadow report {})",
                anim.out_dir.display()
            )
        })?;
        if !args.quiet {
            eprintln!(
                "report: {} ({:.1} s)",
                page.display(),
                start.elapsed().as_secs_f64()
            );
        }
    }
    Ok(())
}

fn lights(args: LightsArgs) -> Result<()> {
    let env = if args.map == "builtin:sky" {
        EnvMap::builtin_sky()
    } else {
        EnvMap::load(std::path::Path::new(&args.map))?
    };
    let env = env
        .with_rotation(args.rotation)
        .with_intensity(args.intensity)?;
    if args.count == 0 {
        return Err(input_error("-n", "zero lights: ask for at least 1"));
    }
    if args.count > crate::anim::limits::MAX_LIGHTS {
        return Err(input_error(
            "-n",
            format!(
                "{} lights requested; at most {} are allowed",
                args.count,
                crate::anim::limits::MAX_LIGHTS
            ),
        ));
    }
    let set = LightSet::build(&env, args.count, args.sampler)?;
    let total: f64 = set
        .lights
        .iter()
        .map(|l| l.energy.element_sum() as f64)
        .sum();
    println!(
        "{}: {} lights ({}), total energy {:.6} (RGB sum)",
        env.source,
        set.len(),
        crate::anim::sampler_name(args.sampler),
        total
    );
    if let Some(p) = &args.json {
        set.write_json(p)?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = &args.png {
        crate::lights::picture::cells_png(&env, &set, p)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Progress as an indicatif bar on a terminal, plain lines (one per frame) otherwise.
pub struct Reporter {
    bar: Option<ProgressBar>,
    start: Instant,
    rays: AtomicU64,
    frames: Mutex<(usize, usize)>,
    tiles: AtomicU64,
}

impl Reporter {
    pub fn new(terminal: bool) -> Reporter {
        Reporter {
            bar: terminal.then(ProgressBar::hidden),
            start: Instant::now(),
            rays: AtomicU64::new(0),
            frames: Mutex::new((0, 0)),
            tiles: AtomicU64::new(0),
        }
    }

    fn rays_per_second(&self) -> f64 {
        self.rays.load(Ordering::Relaxed) as f64 / self.start.elapsed().as_secs_f64().max(1e-9)
    }
}

impl Progress for Reporter {
    fn begin(&self, frames: usize, tiles: usize) {
        *self.frames.lock().unwrap() = (0, frames);
        if let Some(bar) = &self.bar {
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            bar.set_length((frames * tiles) as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {bar:30} {msg} tiles {pos}/{len} ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar.set_message(format!("frame 0/{frames}"));
        } else {
            eprintln!("rendering {frames} frames of {tiles} tiles");
        }
    }

    fn tile_done(&self, rays: u64) {
        self.rays.fetch_add(rays, Ordering::Relaxed);
        self.tiles.fetch_add(1, Ordering::Relaxed);
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
    }

    fn frame_done(&self, s: &FrameStats) {
        let (done, total) = {
            let mut f = self.frames.lock().unwrap();
            f.0 += 1;
            *f
        };
        let line = format!(
            "frame {} ({done}/{total}): {:.2} s, {:.2} % of {} queries traced, {:.1} M rays/s",
            s.frame,
            s.seconds,
            s.counts.percent_traced(),
            s.counts.queries,
            self.rays_per_second() / 1e6
        );
        match &self.bar {
            Some(bar) => {
                bar.set_message(format!(
                    "frame {done}/{total} {:.1} Mrays/s",
                    self.rays_per_second() / 1e6
                ));
                bar.println(line);
            }
            None => eprintln!("{line}"),
        }
    }

    fn frame_skipped(&self, frame: usize) {
        self.note(&format!(
            "frame {frame}: already rendered, skipped (--resume)"
        ));
    }

    fn note(&self, msg: &str) {
        match &self.bar {
            Some(bar) => bar.println(msg),
            None => eprintln!("{msg}"),
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
