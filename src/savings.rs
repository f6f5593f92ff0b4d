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

use crate::error::{Result, input_error};

/// Percent traced per frame from a render folder's `stats.csv`.
pub fn percent_per_frame(dir: &Path) -> Result<BTreeMap<usize, f64>> {
    let path = dir.join("stats.csv");
    let out: BTreeMap<usize, f64> = crate::output::stats::read_stats(&path)?
        .iter()
        .map(|r| (r.frame, r.counts.percent_traced()))
        .collect();
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
    let x = (
        frames[0].0 as f64 - 0.5,
        frames.last().unwrap().0 as f64 + 0.5,
    );
    let without_pts: Vec<(f64, f64)> = frames.iter().map(|r| (r.0 as f64, r.2)).collect();
    let with_pts: Vec<(f64, f64)> = frames.iter().map(|r| (r.0 as f64, r.1)).collect();
    // Grey (without) first, so blue (with) is drawn on top where they meet at key frames.
    let (top, step) = crate::plot::draw_lines(
        &png,
        &[(&without_pts, [150, 150, 150]), (&with_pts, [31, 90, 200])],
        x,
        (800, 360),
        12,
    )?;
    Ok(Savings {
        png,
        frames,
        axis: (top, step),
    })
}
