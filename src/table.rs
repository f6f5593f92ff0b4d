//! `envshadow table`: the paper's Table 1 — the share of shadow queries each method traces —
//! rendered for our scenes, beside the paper's figures, with our validated error rates.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;

use crate::coordinator::thread_pool;
use crate::key::Key;

use crate::frame::render_frame;

use crate::error::{Result, input_error};
use crate::output::write_atomic;
use crate::paper::{paper_percent, table1_methods};
use crate::predict::{FloodTo, Method};
use crate::run::Silent;
use crate::settings::{LightsSweep, RenderSweep};
use crate::sweep::{Variant, light_layers, load, tuning, variants};

#[derive(Args, Debug, Clone)]
pub struct TableArgs {
    /// `shapes` or `bunny` (anims/paper-shapes.toml, anims/paper-bunny.toml) or a spec file.
    #[arg(long, default_value = "shapes")]
    pub scene: String,
    /// Which frame of the animation.
    #[arg(long, default_value_t = 0)]
    pub frame: usize,
    /// Also write the rows as CSV here.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Light counts and samplers.
    #[command(
        flatten,
        next_help_heading = "Swept settings: comma-separated lists, every combination a row (table's defaults: --lights 50,100,200,400 and the paper's methods; one --threads at most; every method but brute validated)"
    )]
    pub lights: LightsSweep,
    /// Render settings.
    #[command(flatten)]
    pub render: RenderSweep,
}

/// One validated frame of one method at one light count.
#[derive(Clone, Debug)]
pub struct TableRow {
    /// The method with the settings the row varies.
    pub variant: Variant,
    /// The flood rule, for the methods it changes.
    pub flood_to: Option<FloodTo>,
    pub lights: usize,
    /// The frame's size.
    pub width: u32,
    pub height: u32,
    pub queries: u64,
    /// Rays traced at the frame's pixels, and again at tiles' halos; `percent` counts both.
    pub rays: u64,
    pub halo_rays: u64,
    pub percent: f64,
    pub error_percent: f64,
    pub wrong_pixels: u64,
    pub rel_rmse: f64,
    /// The frame's thread-seconds.
    pub seconds: f64,
    pub paper: Option<f64>,
    /// Where the rays went: at pixels tracing every light, queued by the prediction, queued
    /// by flooding; and the flooded rays that caught a wrong prediction.
    pub rays_every_light: u64,
    pub rays_unsure: u64,
    pub rays_flooded: u64,
    pub flood_fixes: u64,
}

fn spec_and_key(scene: &str) -> (PathBuf, String) {
    match scene {
        "shapes" | "bunny" => (
            PathBuf::from(format!("anims/paper-{scene}.toml")),
            scene.to_string(),
        ),
        other => {
            let key = if other.contains("bunny") {
                "bunny"
            } else if other.contains("shapes") {
                "shapes"
            } else {
                ""
            };
            (PathBuf::from(other), key.to_string())
        }
    }
}

/// Renders every (light count, method) frame with validation.
/// What [`measure`] reports as it goes.
pub enum Log<'a> {
    /// A frame was measured.
    Row(&'a TableRow),
    /// What the scene loader skipped.
    Warning(&'a str),
}

pub fn measure(args: &TableArgs, mut log: impl FnMut(Log)) -> Result<Vec<TableRow>> {
    let (spec, key) = spec_and_key(&args.scene);
    if !args.render.validate.is_empty() {
        return Err(input_error(
            "--validate",
            "the table validates every method but brute force (its own reference)",
        ));
    }
    let threads = match args.render.threads[..] {
        [] => 0,
        [n] => n,
        _ => {
            return Err(input_error(
                "--threads",
                "the table renders on one pool: give one thread count",
            ));
        }
    };
    let pool = thread_pool(threads)?;
    let mut rows = Vec::new();
    for lights in light_layers(&args.lights)? {
        let (base, inputs) = load(&spec, &lights, &Default::default())?;
        for w in &inputs.scene.warnings {
            log(Log::Warning(w));
        }
        let n = base.lights.count;
        for variant in variants(&base, &args.render, &table1_methods())? {
            let mut anim = base.with_render(&variant.layer)?;
            // Brute force is its own reference: nothing to validate.
            anim.render.validate = variant.method != Method::BRUTE;
            let (_, stats) =
                pool.install(|| render_frame(&anim, &inputs, args.frame, None, &Silent))?;
            let c = stats.counts;
            let row = TableRow {
                flood_to: variant
                    .method
                    .reads(Key::FloodTo)
                    .then_some(anim.render.flood_to),
                paper: paper_percent(variant.method, &key, n),
                variant,
                lights: n,
                width: anim.render.width,
                height: anim.render.height,
                queries: c.queries,
                rays: c.rays,
                halo_rays: c.halo_rays,
                percent: c.percent_traced(),
                error_percent: c.error_percent(),
                wrong_pixels: c.wrong_pixels,
                rel_rmse: stats.image_error.map_or(0.0, |e| e.rel_rmse),
                seconds: stats.thread_seconds,
                rays_every_light: c.rays_every_light,
                rays_unsure: c.rays_unsure(),
                rays_flooded: c.rays_flooded,
                flood_fixes: c.flood_fixes,
            };
            log(Log::Row(&row));
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Table 1 as markdown: % traced (the paper's figure in parentheses), then error rates; a
/// column per light count.
pub fn markdown(rows: &[TableRow]) -> String {
    let mut lights: Vec<usize> = Vec::new();
    for r in rows {
        if !lights.contains(&r.lights) {
            lights.push(r.lights);
        }
    }
    let lights = &lights[..];
    let mut variants: Vec<&Variant> = Vec::new();
    for r in rows {
        if !variants.contains(&&r.variant) {
            variants.push(&r.variant);
        }
    }
    let head = |title: &str| {
        let mut s = format!("| {title} |");
        for n in lights {
            let _ = write!(s, " {n} |");
        }
        s.push_str("\n|---|");
        for _ in lights {
            s.push_str("---:|");
        }
        s.push('\n');
        s
    };
    let cell = |m: &Variant, n: usize| rows.iter().find(|r| &r.variant == m && r.lights == n);
    let mut s = head(
        "% of shadow queries traced, every ray (tiles' halos included): ours (paper, whole frames)",
    );
    for &m in &variants {
        let _ = write!(s, "| {m} |");
        for &n in lights {
            match cell(m, n) {
                Some(r) => match r.paper {
                    Some(p) => {
                        let _ = write!(s, " {:.1} ({p:.1}) |", r.percent);
                    }
                    None => {
                        let _ = write!(s, " {:.1} |", r.percent);
                    }
                },
                None => s.push_str(" – |"),
            }
        }
        s.push('\n');
    }
    s.push('\n');
    s.push_str(&head("wrong pairs, % of queries (relative image RMSE, %)"));
    for &m in &variants {
        let _ = write!(s, "| {m} |");
        for &n in lights {
            match cell(m, n) {
                Some(r) => {
                    let _ = write!(s, " {:.4} ({:.3}) |", r.error_percent, 100.0 * r.rel_rmse);
                }
                None => s.push_str(" – |"),
            }
        }
        s.push('\n');
    }
    s.push('\n');
    s.push_str(&head(
        "where the rays go, % of queries: every light + prediction + flooding + tiles' halos (flooded rays that caught a wrong prediction)",
    ));
    let pct = |r: &TableRow, n: u64| 100.0 * n as f64 / r.queries.max(1) as f64;
    for &m in &variants {
        let _ = write!(s, "| {m} |");
        for &n in lights {
            match cell(m, n) {
                Some(r) => {
                    let _ = write!(
                        s,
                        " {:.1} + {:.1} + {:.1} + {:.1} ({}) |",
                        pct(r, r.rays_every_light),
                        pct(r, r.rays_unsure),
                        pct(r, r.rays_flooded),
                        pct(r, r.halo_rays),
                        r.flood_fixes
                    );
                }
                None => s.push_str(" – |"),
            }
        }
        s.push('\n');
    }
    s
}

/// The rows as CSV.
pub fn csv(rows: &[TableRow], scene: &str) -> String {
    let mut s = String::from(
        "scene,method,flood_to,lights,queries,rays_traced,halo_rays,percent_traced,paper_percent,error_percent,wrong_pixels,rel_rmse,thread_seconds,rays_every_light,rays_unsure,rays_flooded,flood_fixes\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{scene},{},{},{},{},{},{},{:.4},{},{:.6},{},{:.6e},{:.3},{},{},{},{}",
            r.variant.method,
            // Empty for the methods every rule traces alike.
            r.flood_to.map_or("", FloodTo::name),
            r.lights,
            r.queries,
            r.rays,
            r.halo_rays,
            r.percent,
            r.paper.map(|p| p.to_string()).unwrap_or_default(),
            r.error_percent,
            r.wrong_pixels,
            r.rel_rmse,
            r.seconds,
            r.rays_every_light,
            r.rays_unsure,
            r.rays_flooded,
            r.flood_fixes
        );
    }
    s
}

/// The heading of Table 1: the scene, frame size and the settings every row shares.
pub fn heading(args: &TableArgs, rows: &[TableRow]) -> String {
    let size = rows
        .first()
        .map(|r| format!(" at {}x{}", r.width, r.height))
        .unwrap_or_default();
    format!(
        "Table 1, {}{size}, frame {}{}:",
        args.scene,
        args.frame,
        tuning(&args.render)
    )
}

/// Writes the rows as CSV to `path` (atomically).
pub fn write_csv(path: &std::path::Path, rows: &[TableRow], scene: &str) -> Result<()> {
    write_atomic(path, csv(rows, scene).as_bytes())
}
