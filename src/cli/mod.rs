//! The command line: argument definitions (clap), and each command's run — a library call,
//! then what it did printed (results on stdout, progress and notes on stderr). The library
//! does the work and never prints; this is the only code that talks to the terminal.

mod docs;
mod progress;
mod talk;

pub use talk::say;

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::bench::{self, BenchArgs};
use envshadow::coordinator;
use envshadow::envmap::EnvMap;
use envshadow::error::{Result, input_error};
use envshadow::lights::LightSet;
use envshadow::run::{Progress, RunOptions};
use envshadow::settings::LightsLayer;
use envshadow::table::{self, TableArgs};
use envshadow::tile::Rect;
use progress::Reporter;
use talk::{Level, Talk, TalkArgs, out};

const AFTER_HELP: &str = "\
Exit codes: 0 success; 1 internal failure (a bug, or the disk); 2 bad input (a file, a flag or
an animation spec is wrong, or the request is over a limit; the one-line message names the file
and where in it; a usage error gives clap's usage line and hints too); 130 interrupted by
Ctrl-C, SIGTERM or SIGHUP, on Windows Ctrl-C or Ctrl-Break (frames in flight are dropped,
complete frames are kept; run again with --resume; a second signal stops at once).

Output: results on stdout, progress and notes on stderr; -q prints only errors, -v adds detail
(per tile, timings).

Frames (--frames) are numbered from 0; 1-10 includes 10 (as Blender's lists), 0..10 does not.
Files are named frame_0000.exr/.png; --output-pattern turntable_#### names them as Blender does
(the # run is the zero-padded number) and --frame-start 1 numbers them from 1 (--frames still
counts from 0). --fps 29.97 is stored exactly, as 30000/1001.

Limits, checked before work starts: width and height up to 16384, 64 Mpixels, 4096 lights,
10^6 frames, 2 GB per input file, 2^26 triangles, and 16 GB of expected memory.

Examples:
  envshadow render anims/shapes-turntable.toml
  envshadow render anims/bunny-turntable.toml --frames 0-7 --lights 400 --out out/bunny
  envshadow render anims/bunny-turntable.toml --frames 0-143:12 -q
  envshadow lights assets/grace.hdr -n 200 --json lights.json --png cells.png
  envshadow report out/shapes-turntable
  envshadow video out/shapes-turntable";

/// Batch renderer for turntable animations of glTF scenes lit by HDR environment maps, with
/// shadows from every light direction (Ben-Artzi, Ramamoorthi & Agrawala 2004).
#[derive(Parser, Debug)]
#[command(name = "envshadow", version, about, after_help = AFTER_HELP)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    #[command(flatten)]
    pub talk: TalkArgs,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render an animation spec (TOML) into frames, stats.csv and lights.json.
    Render(RenderArgs),
    /// Reduce an environment map to N directional lights; write them as JSON and a picture.
    // A map has no glTF lights: --scene-lights, which the lights settings share with render,
    // means nothing here (refused in `lights`).
    #[command(mut_arg("scene_lights", |a| a.hide(true)))]
    Lights(LightsArgs),
    /// Measure seconds per frame and shadow rays per second (see BENCHMARKS.md).
    Bench(BenchArgs),
    /// Reproduce the paper's Table 1: % of shadow queries traced per method, validated.
    Table(TableArgs),
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
    /// List the shadow methods: name, evaluation order, voting and flood rule, the settings
    /// each reads, and what it does.
    Methods,
    /// Print the version; with --build also the build identity (a hash of the sources,
    /// compiler, target and flags it was built from), which every farm host must share.
    Version(VersionArgs),
    /// Write one frame's triangles, normals, albedos, lights, camera rays and shadow offset for
    /// another renderer (scripts/compare-mitsuba.sh).
    // One frame: --frame; the --frames of the flags it shares with render is refused with a
    // hint (in `run`).
    #[command(mut_arg("frames", |a| a.hide(true)))]
    Export(envshadow::export::ExportArgs),
    /// Plot percent traced per frame with and without --temporal (DIR/savings.png) from two
    /// renders of the same frames (scripts/temporal-savings.sh makes both).
    Savings(SavingsArgs),
    /// Print a shell completion script: bash, zsh, fish, powershell or elvish (README:
    /// "Shell completions and manual pages" says where each shell reads it).
    Completions(docs::CompletionsArgs),
    /// Print the manual page envshadow(1) in roff, or with --out DIR write one page per
    /// command (envshadow-render.1, …) into DIR.
    Man(docs::ManArgs),
    /// Encode a render's frame PNGs into DIR/video.mp4 (H.264) with the system's ffmpeg, at
    /// the animation's frame rate; DIR/report.html, if there, is rebuilt to show it.
    Video(VideoArgs),
}

#[derive(Args, Debug)]
pub struct VideoArgs {
    /// A render's output folder (with frame_NNNN.png, or the names its settings.txt's
    /// `[output] output_pattern` gives).
    pub dir: PathBuf,
    /// Frames per second: a whole number, N/D (30000/1001) or 23.976, 29.97, 59.94 (the NTSC
    /// n·1000/1001). Default: the render's `[output] fps`, from DIR/settings.txt, else 24.
    #[arg(long, value_name = "FPS")]
    pub fps: Option<envshadow::output::rate::FrameRate>,
    /// Where to write the video (default: DIR/video.mp4; the report shows only that one).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
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
    /// How to split: tiles (tile strips through all the frames; the default), frames
    /// (runs of frames; the default when frames depend on whole previous frames) or both.
    #[arg(long, value_enum)]
    pub by: Option<envshadow::farm::plan::By>,
}

#[derive(Args, Debug)]
pub struct AssembleArgs {
    /// The farm's output folder (with plan.json and jobs/).
    pub dir: PathBuf,
    /// Do not write report.html (and report/).
    #[arg(long)]
    pub no_report: bool,
    /// Write nothing: print the plan's line (as in jobs.txt) of every job still to render —
    /// missing, incomplete, truncated or corrupt, judged from its files and their recorded
    /// SHA-256 — and on stderr why. What scripts/farm.sh and slurm.sh re-run.
    #[arg(long, conflicts_with = "no_report")]
    pub pending: bool,
    /// Also encode DIR/video.mp4 once every frame is assembled (as `envshadow video DIR`);
    /// a plan made with `[output] video` or `--video` asks for it without this flag.
    #[arg(long, conflicts_with = "pending")]
    pub video: bool,
}

#[derive(Args, Debug)]
pub struct VersionArgs {
    /// Also print the build identity: `envshadow 0.1.0 build 0123456789abcdef`.
    #[arg(long)]
    pub build: bool,
    /// Also print, on a line of its own, the SIMD kernels this machine runs: `kernels avx2`,
    /// `kernels sse2` (no AVX2, or ENVSHADOW_NO_AVX2 set) or `kernels scalar`.
    #[arg(long)]
    pub kernels: bool,
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

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The animation spec, e.g. anims/shapes-turntable.toml; or a glTF model (.glb, .gltf)
    /// for a default turntable of it: 72 frames orbiting the model, auto-framed, built-in
    /// sky (or --env), a ground if it has none, 640x480 at 4 spp, into out/<model name>/.
    pub spec: PathBuf,
    #[command(flatten)]
    pub flags: AnimFlags,
    /// Render nothing: write this render's resolved settings (the spec's, or a model's
    /// turntable's, with every flag applied) as a spec to FILE, which `envshadow render FILE`
    /// renders into the same frames, byte for byte (all of them: --frames is not written).
    /// Its input and output paths are absolute, so it renders the same from anywhere.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["resume", "region", "job", "tiles"])]
    pub write_spec: Option<PathBuf>,
    /// Skip the frames already complete in the output folder: those whose EXR and PNG are the
    /// very files their record names (size and SHA-256), rendered with these settings. A
    /// folder rendered with other settings or inputs is refused, naming the first difference
    /// (settings.txt: every setting but --threads, --tile, --out and --video, and the SHA-256
    /// of the scene and map files). Without it, every frame asked for is rendered again.
    #[arg(long)]
    pub resume: bool,
    /// When another render is writing the same output folder, wait for it to finish instead
    /// of refusing (one writer per folder; farm jobs always wait).
    #[arg(long)]
    pub wait: bool,
    /// Render only the pixel rectangle x0,y0,x1,y1 (x1, y1 excluded); the rest stays black.
    #[arg(long, value_name = "x0,y0,x1,y1", value_parser = parse_region)]
    pub region: Option<Rect>,
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
    pub by: Option<envshadow::farm::plan::By>,
    /// Farm job: render these tiles (e.g. 0-4,9; frame-anchored tile numbers) of the --frames
    /// into OUT/jobs/<folder>/, as `--job` does.
    #[arg(long, value_name = "LIST", conflicts_with = "region")]
    pub tiles: Option<envshadow::farm::plan::TileSet>,
}

#[derive(Args, Debug)]
pub struct LightsArgs {
    /// Environment map: a lat-long .exr or .hdr file, or `builtin:sky`.
    pub map: String,
    /// How many lights, by which sampler.
    #[command(flatten)]
    pub lights: LightsLayer,
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
    let talk = cli.talk.talk();
    match cli.command {
        Command::Render(args) => render(args, talk),
        Command::Lights(args) => lights(args, talk),
        Command::Bench(args) => bench_command(args, talk),
        Command::Table(args) => table_command(args, talk),
        Command::Plan(args) => plan(args, talk),
        Command::Assemble(args) => assemble(args, talk),
        Command::Methods => {
            methods();
            Ok(())
        }
        Command::Version(args) => {
            if args.build {
                out(&format!(
                    "envshadow {} build {}\n",
                    env!("CARGO_PKG_VERSION"),
                    envshadow::farm::identity::BUILD_ID
                ));
            } else {
                out(&format!("envshadow {}\n", env!("CARGO_PKG_VERSION")));
            }
            // A line of its own: farm hosts compare the `--build` line, and hosts with and
            // without AVX2 write the same bits.
            if args.kernels {
                out(&format!("kernels {}\n", envshadow::simd::kernels()));
            }
            Ok(())
        }
        Command::Export(args) => {
            if let Some(frames) = &args.flags.frames {
                return Err(input_error(
                    "--frames",
                    format!("export writes one frame: use --frame N (not --frames {frames})"),
                ));
            }
            let e = envshadow::export::run(&args)?;
            talk.warn(&e.warnings);
            talk.done(&format!(
                "exported frame {} ({} triangles, {} lights, {}x{}) to {}",
                e.frame,
                e.triangles,
                e.lights,
                e.width,
                e.height,
                e.dir.display()
            ));
            Ok(())
        }
        Command::Savings(args) => {
            let s =
                envshadow::savings::write_savings(&args.dir, &args.without, args.out.as_deref())?;
            let n = s.frames.len() as f64;
            let (with, without) = s
                .frames
                .iter()
                .fold((0.0, 0.0), |acc, r| (acc.0 + r.1 / n, acc.1 + r.2 / n));
            talk.done(&format!(
                "wrote {}: {} frames, mean {with:.2} % traced with --temporal, {without:.2} % \
                 without ({:.0} %); blue = with, grey = without, y grid every {} % up to {} %",
                s.png.display(),
                s.frames.len(),
                100.0 * with / without.max(1e-12),
                s.axis.1,
                s.axis.0
            ));
            Ok(())
        }
        Command::Video(args) => video(args, talk),
        Command::Report(args) => {
            let start = Instant::now();
            let page = envshadow::report::write_report(&args.dir)?;
            talk.done(&format!(
                "wrote {} in {:.1} s",
                page.display(),
                start.elapsed().as_secs_f64()
            ));
            Ok(())
        }
        Command::Completions(args) => {
            docs::completions(&args);
            Ok(())
        }
        Command::Man(args) => docs::man(&args, talk),
    }
}

/// `envshadow methods`.
fn methods() {
    let mut text = String::new();
    for m in envshadow::predict::Method::all() {
        let (order, vote, flood) = m.parts();
        let parts = [order, vote, flood]
            .iter()
            .filter(|p| !p.is_empty())
            .copied()
            .collect::<Vec<_>>()
            .join(" + ");
        let reads: Vec<String> = envshadow::settings::method_settings()
            .filter(|&k| m.reads(k))
            .map(|k| format!("--{}", k.flag()))
            .collect();
        let default = if m == envshadow::predict::Method::DEFAULT {
            " (default)"
        } else {
            ""
        };
        text.push_str(&format!("{}{default}: {parts}\n", m.name()));
        text.push_str(&format!("    {}\n", m.about()));
        if !reads.is_empty() {
            text.push_str(&format!("    settings: {}\n", reads.join(" ")));
        }
    }
    out(&text);
}

/// Progress on stderr at the level asked for: a bar on a terminal, lines in a log; nothing
/// with `-q`.
fn progress(talk: Talk) -> Box<dyn Progress> {
    match talk.level() {
        Level::Quiet => Box::new(progress::Quiet),
        level => Box::new(Reporter::new(
            std::io::stderr().is_terminal(),
            level == Level::Verbose,
        )),
    }
}

fn bench_command(args: BenchArgs, talk: Talk) -> Result<()> {
    if let Some(path) = &args.replay {
        out(&bench::replay_table(path, &args)?);
        return Ok(());
    }
    let rows = bench::measure(&args, |log| match log {
        bench::Log::Row(r) => talk.info(&format!(
            "{} lights, {} threads, {}: {:.3} s/frame",
            r.lights, r.threads, r.variant, r.seconds
        )),
        bench::Log::Dumped(path, rays) => {
            talk.info(&format!("wrote {} ({rays} rays)", path.display()))
        }
        bench::Log::Warning(w) => talk.warn(&[w.to_string()]),
    })?;
    if args.csv {
        out(&bench::csv(&args, &rows));
    } else {
        out(&format!(
            "{}\n\n{}",
            bench::heading(&args, &rows),
            bench::markdown(&rows)
        ));
    }
    Ok(())
}

fn table_command(args: TableArgs, talk: Talk) -> Result<()> {
    let rows = table::measure(&args, |log| match log {
        table::Log::Row(r) => talk.info(&format!(
            "{} lights, {}: {:.2} % traced, {:.4} % wrong, {:.2} s",
            r.lights, r.variant, r.percent, r.error_percent, r.seconds
        )),
        table::Log::Warning(w) => talk.warn(&[w.to_string()]),
    })?;
    out(&format!(
        "{}\n\n{}",
        table::heading(&args, &rows),
        table::markdown(&rows)
    ));
    if let Some(path) = &args.csv {
        table::write_csv(path, &rows, &args.scene)?;
        talk.info(&format!("wrote {}", path.display()));
    }
    Ok(())
}

fn plan(args: PlanArgs, talk: Talk) -> Result<()> {
    let anim = Animation::load(&args.spec, &args.flags)?;
    // The video is encoded where the jobs are assembled: say so before any job runs.
    if anim.output.video {
        envshadow::video::check_ffmpeg()?;
    }
    let jobs = envshadow::farm::write_plan(&anim, &args.spec, args.jobs, args.by)?;
    // The job lines echo jobs.txt: shown unless -q.
    if talk.level() >= Level::Normal {
        out(&envshadow::farm::plan::job_lines(&jobs));
    }
    talk.info(&format!(
        "{}: {} jobs for frames {} ({} asked); plan in {}",
        anim.name,
        jobs.len(),
        anim.frames,
        args.jobs,
        anim.output.dir.join("plan.json").display()
    ));
    Ok(())
}

fn assemble(args: AssembleArgs, talk: Talk) -> Result<()> {
    if args.pending {
        let done = envshadow::farm::assemble::pending(&args.dir)?;
        for p in &done.problems {
            talk.info(p);
        }
        out(&envshadow::farm::plan::job_lines(&done.pending));
        talk.info(&format!(
            "{}: {} of {} jobs to render ({} of {} frames complete)",
            args.dir.display(),
            done.pending.len(),
            done.jobs,
            done.written,
            done.frames
        ));
        return Ok(());
    }
    let start = Instant::now();
    let done = envshadow::farm::assemble::assemble(&args.dir)?;
    let video_fps = done.video_fps.or(args.video.then(|| {
        envshadow::video::recorded_fps(&args.dir)
            .unwrap_or(envshadow::settings::Output::default().fps)
    }));
    // The problems are what the error below refers to: printed even with -q.
    for p in &done.problems {
        say(p);
    }
    talk.info(&format!(
        "{}: {} of {} frames assembled from {} jobs in {:.1} s",
        args.dir.display(),
        done.written,
        done.frames,
        done.jobs,
        start.elapsed().as_secs_f64()
    ));
    if !done.problems.is_empty() {
        return Err(input_error(
            &args.dir,
            format!(
                "{} job(s) missing, incomplete or corrupt (listed above); render them again (e.g. rerun scripts/farm.sh, or envshadow render --job K --of N --resume) and assemble again",
                done.problems.len()
            ),
        ));
    }
    if let Some(fps) = video_fps.filter(|_| done.written > 0) {
        let v = envshadow::video::write_video(&args.dir, fps, None).with_context(|| {
            format!(
                "the frames are assembled, but not the video (retry with envshadow video {})",
                args.dir.display()
            )
        })?;
        talk.info(&format!(
            "video: {} ({} frames at {} fps)",
            v.path.display(),
            v.frames,
            v.fps
        ));
    }
    if !args.no_report && done.written > 0 {
        envshadow::report::write_report(&args.dir)?;
    }
    Ok(())
}

fn render(args: RenderArgs, talk: Talk) -> Result<()> {
    let anim = if envshadow::anim::is_model(&args.spec) {
        Animation::of_model(&args.spec, None, &args.flags)?
    } else {
        Animation::load(&args.spec, &args.flags)?
    };
    if let Some(file) = &args.write_spec {
        anim.write_spec(file)?;
        talk.done(&format!(
            "wrote {}: renders as this command would (envshadow render {})",
            file.display(),
            file.display()
        ));
        return Ok(());
    }
    let selection = match (args.job, args.of, &args.tiles) {
        (Some(index), Some(of), _) => Some(envshadow::farm::JobSelection::Planned {
            index,
            of,
            by: args.by,
        }),
        (_, _, Some(t)) => Some(envshadow::farm::JobSelection::Tiles(t.clone())),
        _ => None,
    };
    // A render that ends in a video needs ffmpeg: say so before the frames, not after.
    if anim.output.video && selection.is_none() {
        envshadow::video::check_ffmpeg()?;
    }
    let progress = progress(talk);
    if let Some(sel) = selection {
        let (job, dir, summary) = envshadow::farm::render_job(
            &anim,
            &sel,
            args.resume,
            envshadow::cancel::Cancel::on_signals()?,
            progress.as_ref(),
        )?;
        talk.info(&format!(
            "{}: {} frames rendered, {} skipped in {:.1} s; output in {}",
            job.describe(),
            summary.rendered,
            summary.skipped,
            summary.seconds,
            dir.display()
        ));
        return Ok(());
    }
    let (width, height) = (anim.render.width, anim.render.height);
    if let Some(r) = args.region
        && (r.x1 > width || r.y1 > height)
    {
        return Err(input_error(
            "--region",
            format!("{r} reaches outside the {width}x{height} frame"),
        ));
    }
    let opts = RunOptions {
        resume: args.resume,
        region: args.region,
        tiles: None,
        cancel: envshadow::cancel::Cancel::on_signals()?,
        wait: args.wait,
    };
    let mut files = envshadow::frame_files::FrameFiles::new(&anim, &opts);
    let summary = coordinator::render_animation(&anim, &opts, &mut files, progress.as_ref())?;
    let dir = &anim.output.dir;
    talk.info(&format!(
        "{}: {} frames rendered, {} skipped in {:.1} s ({:.1} thread-s on {} threads); {} shadow queries, {} rays traced ({:.2} %, {:.1} M rays/s); output in {}",
        anim.name,
        summary.rendered,
        summary.skipped,
        summary.seconds,
        summary.thread_seconds,
        summary.threads,
        summary.counts.queries,
        summary.counts.traced(),
        summary.counts.percent_traced(),
        summary.counts.traced() as f64 / summary.seconds.max(1e-9) / 1e6,
        dir.display()
    ));
    if anim.output.video {
        let v = envshadow::video::write_video(dir, anim.output.fps, None).with_context(|| {
            format!(
                "the frames are written, but not the video (retry with envshadow video {})",
                dir.display()
            )
        })?;
        talk.info(&format!(
            "video: {} ({} frames at {} fps)",
            v.path.display(),
            v.frames,
            v.fps
        ));
    }
    if !args.no_report {
        let start = Instant::now();
        let page = envshadow::report::write_report(dir).with_context(|| {
            format!(
                "the frames are written, but not the report (retry with envshadow report {})",
                dir.display()
            )
        })?;
        talk.info(&format!(
            "report: {} ({:.1} s)",
            page.display(),
            start.elapsed().as_secs_f64()
        ));
    }
    Ok(())
}

fn video(args: VideoArgs, talk: Talk) -> Result<()> {
    let fps = args
        .fps
        .or_else(|| envshadow::video::recorded_fps(&args.dir))
        .unwrap_or(envshadow::settings::Output::default().fps);
    let start = Instant::now();
    let v = envshadow::video::write_video(&args.dir, fps, args.out.as_deref())?;
    talk.done(&format!(
        "wrote {}: {} frames ({}–{}), {}x{}, {} fps, {:.1} s of video, in {:.1} s",
        v.path.display(),
        v.frames,
        v.first,
        v.last,
        v.width,
        v.height,
        v.fps,
        v.frames as f64 / v.fps.as_f64(),
        start.elapsed().as_secs_f64()
    ));
    if args.out.is_none() && args.dir.join("report.html").is_file() {
        let page = envshadow::report::write_report(&args.dir)?;
        talk.done(&format!("rebuilt {} to show it", page.display()));
    }
    Ok(())
}

fn lights(args: LightsArgs, talk: Talk) -> Result<()> {
    if args.lights.scene_lights.is_some() {
        return Err(input_error(
            "--scene-lights",
            "means nothing to lights, which reduces a map: it is render's, for the lights a \
             glTF file places",
        ));
    }
    args.lights.check(envshadow::settings::Source::Flags)?;
    let l = args.lights.resolve();
    if let Some(why) = envshadow::limits::lights_problem(l.count) {
        return Err(input_error("--lights", why));
    }
    let start = Instant::now();
    let env = if args.map == "builtin:sky" {
        EnvMap::builtin_sky()
    } else {
        EnvMap::load(std::path::Path::new(&args.map))?
    };
    let env = env
        .with_rotation(args.rotation)
        .with_intensity(args.intensity)?;
    let loaded = start.elapsed().as_secs_f64();
    let set = LightSet::build(&env, l.count, l.sampler)?;
    talk.detail(&format!(
        "{}x{} map read in {loaded:.2} s, lights built in {:.2} s",
        env.width,
        env.height,
        start.elapsed().as_secs_f64() - loaded
    ));
    let total: f64 = set
        .lights
        .iter()
        .map(|l| l.energy.element_sum() as f64)
        .sum();
    talk.done(&format!(
        "{}: {} lights ({}), total energy {:.6} (RGB sum)",
        env.source,
        set.len(),
        l.sampler.name(),
        total
    ));
    if let Some(p) = &args.json {
        set.write_json(p)?;
        talk.done(&format!("wrote {}", p.display()));
    }
    if let Some(p) = &args.png {
        envshadow::lights::picture::cells_png(&env, &set, p)?;
        talk.done(&format!("wrote {}", p.display()));
    }
    Ok(())
}
