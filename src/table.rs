//! `envshadow table`: the paper's Table 1 — the share of shadow queries each method traces —
//! rendered for our scenes, beside the paper's figures, with our validated error rates.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;

use crate::bench::Sweep;
use crate::coordinator::{Silent, render_frame, thread_pool};
use crate::error::Result;
use crate::output::write_atomic;
use crate::predict::{Method, Variant};

#[derive(Args, Debug, Clone)]
pub struct TableArgs {
    /// `shapes` or `bunny` (anims/paper-shapes.toml, anims/paper-bunny.toml) or a spec file.
    #[arg(long, default_value = "shapes")]
    pub scene: String,
    #[command(flatten)]
    pub sweep: Sweep,
    /// Methods, comma-separated (default: the paper's rows).
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<Method>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Also write the rows as CSV here.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
}

/// One validated frame of one method at one light count.
#[derive(Clone, Debug)]
pub struct TableRow {
    /// The method with its flood rule.
    pub variant: Variant,
    pub lights: usize,
    pub queries: u64,
    pub rays: u64,
    pub percent: f64,
    pub error_percent: f64,
    pub wrong_pixels: u64,
    pub rel_rmse: f64,
    pub seconds: f64,
    pub paper: Option<f64>,
    /// Where the rays went: at pixels tracing every light, queued by the prediction, queued
    /// by flooding; and the flooded rays that caught a wrong prediction.
    pub rays_every_light: u64,
    pub rays_unsure: u64,
    pub rays_flooded: u64,
    pub flood_fixes: u64,
}

/// The paper's Table 1: % of N·L > 0 shadow rays traced per method, for shapes then bunny at
/// 50, 100, 200 and 400 lights; its rows in the paper's order ("true" = brute first).
pub const TABLE1: [(&str, [f64; 8]); 6] = [
    ("brute", [100.0; 8]),
    (
        "scan-warp-boundary",
        [40.5, 34.3, 26.3, 22.4, 52.4, 42.6, 33.6, 25.9],
    ),
    (
        "grid-warp-boundary",
        [22.0, 17.9, 15.1, 12.4, 21.5, 16.6, 13.5, 11.6],
    ),
    (
        "grid-nowarp-boundary",
        [21.7, 17.1, 13.8, 10.6, 21.2, 15.8, 12.0, 9.3],
    ),
    (
        "grid-warp-uncertainty",
        [10.4, 10.7, 11.0, 11.3, 9.1, 9.4, 10.2, 11.5],
    ),
    (
        "grid-nowarp-uncertainty",
        [9.4, 8.8, 8.3, 7.5, 8.1, 7.7, 7.2, 6.7],
    ),
];

/// The methods of the paper's Table 1, in its row order.
pub fn table1_methods() -> Vec<Method> {
    TABLE1
        .iter()
        .map(|(name, _)| name.parse().expect("Table 1 names registered methods"))
        .collect()
}

/// The paper's Table 1 figure (% of N·L > 0 shadow rays traced) for this method, scene
/// (`shapes` or `bunny`) and light count, where the paper gives one.
pub fn paper_percent(method: Method, scene: &str, lights: usize) -> Option<f64> {
    let col = match lights {
        50 => 0,
        100 => 1,
        200 => 2,
        400 => 3,
        _ => return None,
    };
    let row = TABLE1.iter().find(|(name, _)| *name == method.name())?.1;
    match scene {
        "shapes" => Some(row[col]),
        "bunny" => Some(row[4 + col]),
        _ => None,
    }
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
pub fn measure(args: &TableArgs, mut log: impl FnMut(&TableRow)) -> Result<Vec<TableRow>> {
    let (spec, key) = spec_and_key(&args.scene);
    let methods: Vec<Method> = if args.methods.is_empty() {
        table1_methods()
    } else {
        args.methods.clone()
    };
    let variants = Variant::sweep(&methods, &args.sweep.flood_to);
    let pool = thread_pool(args.threads)?;
    let mut rows = Vec::new();
    for &n in &args.sweep.lights {
        let (mut anim, inputs) = args.sweep.load(&spec, n, None)?;
        let base = anim.params;
        for &variant in &variants {
            let method = variant.method;
            anim.method = method;
            anim.params = variant.params(base);
            // Brute force is its own reference: nothing to validate.
            anim.validate = method != Method::BRUTE;
            let (_, stats) =
                pool.install(|| render_frame(&anim, &inputs, args.sweep.frame, None, &Silent))?;
            let c = stats.counts;
            let row = TableRow {
                variant,
                lights: n,
                queries: c.queries,
                rays: c.rays,
                percent: c.percent_traced(),
                error_percent: c.error_percent(),
                wrong_pixels: c.wrong_pixels,
                rel_rmse: stats.image_error.map_or(0.0, |e| e.rel_rmse),
                seconds: stats.seconds,
                paper: paper_percent(method, &key, n),
                rays_every_light: c.rays_every_light,
                rays_unsure: c.rays_unsure(),
                rays_flooded: c.rays_flooded,
                flood_fixes: c.flood_fixes,
            };
            log(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Table 1 as markdown: % traced (the paper's figure in parentheses), then error rates.
pub fn markdown(rows: &[TableRow], lights: &[usize]) -> String {
    let mut variants: Vec<Variant> = Vec::new();
    for r in rows {
        if !variants.contains(&r.variant) {
            variants.push(r.variant);
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
    let cell = |m: Variant, n: usize| rows.iter().find(|r| r.variant == m && r.lights == n);
    let mut s = head("% of shadow queries traced: ours (paper)");
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
        "where the rays go, % of queries: every light + prediction + flooding (flooded rays that caught a wrong prediction)",
    ));
    let pct = |r: &TableRow, n: u64| 100.0 * n as f64 / r.queries.max(1) as f64;
    for &m in &variants {
        let _ = write!(s, "| {m} |");
        for &n in lights {
            match cell(m, n) {
                Some(r) => {
                    let _ = write!(
                        s,
                        " {:.1} + {:.1} + {:.1} ({}) |",
                        pct(r, r.rays_every_light),
                        pct(r, r.rays_unsure),
                        pct(r, r.rays_flooded),
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
        "scene,method,flood_to,lights,queries,rays_traced,percent_traced,paper_percent,error_percent,wrong_pixels,rel_rmse,seconds,rays_every_light,rays_unsure,rays_flooded,flood_fixes\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{scene},{},{},{},{},{},{:.4},{},{:.6},{},{:.6e},{:.3},{},{},{},{}",
            r.variant.method,
            // Empty for the methods every rule traces alike.
            if r.variant.method.reads("flood_to") {
                r.variant.flood_to.name()
            } else {
                ""
            },
            r.lights,
            r.queries,
            r.rays,
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

/// `envshadow table`.
pub fn run(args: &TableArgs) -> Result<()> {
    let rows = measure(args, |r| {
        eprintln!(
            "{} lights, {}: {:.2} % traced, {:.4} % wrong, {:.2} s",
            r.lights, r.variant, r.percent, r.error_percent, r.seconds
        )
    })?;
    println!(
        "Table 1, {} at {}x{}, frame {}{}:\n",
        args.scene,
        args.sweep.width,
        args.sweep.height,
        args.sweep.frame,
        args.sweep.tuning()
    );
    print!("{}", markdown(&rows, &args.sweep.lights));
    if let Some(path) = &args.csv {
        write_atomic(path, csv(&rows, &args.scene).as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
