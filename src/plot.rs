//! Text-free plots: lines with dots over a light grid, drawn with plotters' bitmap backend,
//! which has no font feature here, so no plot needs system fonts. The caller labels the axes
//! outside the picture (the report in HTML, `savings` in its message): [`draw_lines`] returns
//! the y axis it chose and [`tick`] formats its labels.

use std::path::Path;

use anyhow::{Context, anyhow};
use image::RgbImage;

use crate::error::Result;
use crate::output;

/// A line of a plot: its points and its colour.
pub type Line<'a> = (&'a [(f64, f64)], [u8; 3]);

/// Draws text-free lines with dots (`lines`: drawn in order) over `x` and
/// from 0 on y, with a light grid at each y step, into a `size` PNG at `path`; returns the y
/// axis (top, step) so the caller can label it outside the image.
pub fn draw_lines(
    path: &Path,
    lines: &[Line],
    x: (f64, f64),
    size: (u32, u32),
    margin: u32,
) -> Result<(f64, f64)> {
    use plotters::prelude::*;
    let max = lines
        .iter()
        .flat_map(|l| l.0.iter().map(|p| p.1))
        .fold(0.0, f64::max);
    let (top, step) = nice_axis(max);
    let (w, h) = size;
    let (x0, x1) = x;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let err = |e: DrawingAreaErrorKind<_>| anyhow!("drawing {}: {e}", path.display());
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .margin(margin)
            .build_cartesian_2d(x0..x1, 0.0..top)
            .map_err(err)?;
        let grid = RGBColor(220, 220, 220);
        let steps = (top / step).round() as usize;
        for k in 0..=steps {
            let y = k as f64 * step;
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x0, y), (x1, y)],
                    grid.stroke_width(1),
                )))
                .map_err(err)?;
        }
        for (points, colour) in lines {
            let c = RGBColor(colour[0], colour[1], colour[2]);
            chart
                .draw_series(LineSeries::new(points.iter().copied(), c.stroke_width(2)))
                .map_err(err)?;
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 3, c.filled())))
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    let img = RgbImage::from_raw(w, h, buf).context("plot buffer size")?;
    save_png(path, &img)?;
    Ok((top, step))
}

/// "Nice" axis top and step for values up to `max`: four or five steps of 1, 2, 2.5 or 5 × 10^k.
fn nice_axis(max: f64) -> (f64, f64) {
    if !(max.is_finite() && max > 0.0) {
        return (1.0, 0.25);
    }
    let raw = max / 4.0;
    let mag = libm::pow(10.0, libm::log10(raw).floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let top = (max / step).ceil().max(1.0) * step;
    (top, step)
}

/// Formats an axis label without trailing noise.
pub fn tick(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn png_bytes(img: &RgbImage) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .context("encoding PNG")?;
    Ok(bytes)
}

/// Writes `img` as a PNG at `path`, atomically: the plots' encoding, which the report's other
/// lossless pictures share.
pub fn save_png(path: &Path, img: &RgbImage) -> Result<()> {
    output::write_atomic(path, &png_bytes(img)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_axes_cover_the_maximum() {
        for max in [0.003, 0.7, 1.0, 6.3, 7.9, 12.0, 99.0, 1234.0] {
            let (top, step) = nice_axis(max);
            assert!(top >= max && top <= max * 2.6 + step, "{max}: {top} {step}");
            let n = top / step;
            assert!((n - n.round()).abs() < 1e-9 && (1.0..=5.0).contains(&n.round()));
        }
        assert_eq!(nice_axis(0.0), (1.0, 0.25));
    }
}
