//! `envshadow savings`: the plot of percent traced per frame with and without `--temporal`
//! (`DIR/savings.png`).
//!
//! The curve without temporal prediction is never estimated: it is read from the `stats.csv`
//! of a render of the same frames without `--temporal` (`scripts/temporal-savings.sh` renders
//! both and draws the plot). The plot has no text (the bitmap backend has no fonts):
//! blue = with `--temporal`, grey = without, frames on x, percent traced from 0 on y, grid
//! lines every `step` percent (printed by the command).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use image::RgbImage;

use crate::error::{Result, input_error};
use crate::output;

/// Percent traced per frame from a render folder's `stats.csv`.
pub fn percent_per_frame(dir: &Path) -> Result<BTreeMap<usize, f64>> {
    let path = dir.join("stats.csv");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| input_error(&path, format!("cannot read: {e}")))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| input_error(&path, format!("no column {name:?} in the header")))
    };
    let (fc, pc) = (col("frame")?, col("percent_traced")?);
    let mut out = BTreeMap::new();
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let bad = || input_error(&path, format!("line {}: malformed row", n + 2));
        let frame = f.get(fc).and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let pct: f64 = f.get(pc).and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        out.insert(frame, pct);
    }
    if out.is_empty() {
        return Err(input_error(&path, "no frames in it"));
    }
    Ok(out)
}

/// What [`write_savings`] drew.
#[derive(Debug)]
pub struct Savings {
    pub png: PathBuf,
    /// Frames in both renders: (frame, with, without).
    pub frames: Vec<(usize, f64, f64)>,
    /// The y axis: top and grid step, percent.
    pub axis: (f64, f64),
}

/// Draws `out` (default `with/savings.png`) from the renders in `with` (`--temporal`) and
/// `without`, over the frames both rendered.
pub fn write_savings(with: &Path, without: &Path, out: Option<&Path>) -> Result<Savings> {
    use plotters::prelude::*;
    let a = percent_per_frame(with)?;
    let b = percent_per_frame(without)?;
    let frames: Vec<(usize, f64, f64)> = a
        .iter()
        .filter_map(|(&f, &p)| b.get(&f).map(|&q| (f, p, q)))
        .collect();
    if frames.is_empty() {
        return Err(input_error(
            without,
            format!("has no frame in common with {}", with.display()),
        ));
    }
    let png = out.map_or_else(|| with.join("savings.png"), Path::to_path_buf);
    let max = frames.iter().map(|r| r.1.max(r.2)).fold(0.0, f64::max);
    let step = [0.5, 1.0, 2.0, 2.5, 5.0, 10.0, 20.0, 25.0]
        .into_iter()
        .find(|s| max / s <= 6.0)
        .unwrap_or(25.0);
    let top = ((max / step).floor() + 1.0) * step;
    let (x0, x1) = (
        frames[0].0 as f64 - 0.5,
        frames.last().unwrap().0 as f64 + 0.5,
    );
    let (w, h) = (800u32, 360u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let err = |e: DrawingAreaErrorKind<_>| anyhow!("drawing {}: {e}", png.display());
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .margin(12)
            .build_cartesian_2d(x0..x1, 0.0..top)
            .map_err(err)?;
        let grid = RGBColor(220, 220, 220);
        for k in 0..=((top / step).round() as usize) {
            let y = k as f64 * step;
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x0, y), (x1, y)],
                    grid.stroke_width(1),
                )))
                .map_err(err)?;
        }
        for (colour, pick) in [
            (RGBColor(150, 150, 150), 2usize),
            (RGBColor(31, 90, 200), 1usize),
        ] {
            let pts: Vec<(f64, f64)> = frames
                .iter()
                .map(|r| (r.0 as f64, if pick == 1 { r.1 } else { r.2 }))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))
                .map_err(err)?;
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    let img = RgbImage::from_raw(w, h, buf).context("plot buffer size")?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .context("encoding PNG")?;
    output::write_atomic(&png, &bytes)?;
    Ok(Savings {
        png,
        frames,
        axis: (top, step),
    })
}
