//! The render report: `DIR/report.html`, one self-contained page about a finished render, built
//! only from what the render left in its folder (`stats.csv`, `frame_NNNN.exr`/`.png` or the
//! names its `settings.txt` gives, `lights.json`, `video.mp4`). Generated pictures go to `DIR/report/`; the page references
//! them, the frame PNGs and the video by relative paths, uses no JavaScript and nothing from
//! the network, so it works opened from disk.
//!
//! The page leads with what a person opens it for: the animation (the video when the folder
//! has one, else an animated GIF) beside the run's settings and totals, the savings plot, and
//! a contact sheet of numbered thumbnails (JPEG); then the lights; the per-frame detail (heat
//! maps, figures) and the other plots come collapsed (`<details>`), their images loaded only
//! when opened. Thumbnails and heat maps are JPEG, so the report's folder stays small: about
//! 2.4 MB for the default animation's 96 frames at 640×480 (3.6 MB with the GIF).
//!
//! Plots are drawn without text (plotters' bitmap backend with no font feature) and labelled
//! in HTML, so the report needs no system fonts.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;
use image::{Rgb, RgbImage};
use rayon::prelude::*;

use crate::envmap::EnvMap;
use crate::error::{Result, input_error};
use crate::film::Channel;
use crate::folder::VIDEO_FILE;
use crate::lights::{self, LightSet};
use crate::output;
use crate::output::names::FrameNames;
use crate::output::record::{FrameRecord, count_histogram, finite_max, parse_histogram};
use crate::plot::{draw_lines, save_png, tick};
use crate::predict::Method;

/// Widest thumbnail (contact sheet and per-frame table), pixels.
const THUMB_WIDTH: u32 = 160;
/// Widest frame of the animated preview, pixels.
const GIF_WIDTH: u32 = 320;
/// Widest heat map, pixels: larger frames are shown scaled down (a 640×480 frame's map is
/// 105 kB as a JPEG at full size, 15 MB for 144 frames; at 320 pixels wide, a quarter).
const MAP_WIDTH: u32 = 320;
/// JPEG quality of thumbnails and heat maps.
const JPEG_QUALITY: u8 = 85;
/// Animated preview: milliseconds per frame (12.5 frames per second).
const GIF_FRAME_MS: u32 = 80;
/// Plot size in pixels and its margin around the plotting area (the HTML labels rely on it).
const PLOT_SIZE: (u32, u32) = (640, 180);
const PLOT_MARGIN: u32 = 8;
/// Wrong-prediction maps start the colour ramp here, so one wrong pair stands out from the
/// dimmed frame under it.
const WRONG_RAMP_START: f32 = 0.3;

/// One row of `stats.csv`.
#[derive(Clone, Debug)]
struct Row {
    frame: usize,
    method: String,
    lights: usize,
    width: u32,
    height: u32,
    /// Samples per pixel.
    spp: u32,
    queries: u64,
    /// Every ray the frame traced, tiles' halos included.
    rays: u64,
    percent: f64,
    /// The frame's thread-seconds.
    seconds: f64,
    /// With validation: wrong pairs, error percent, wrong pixels, PSNR (dB).
    wrong: Option<u64>,
    error_percent: Option<f64>,
    wrong_pixels: Option<u64>,
    psnr_db: Option<f64>,
    camera: [f64; 3],
    target: [f64; 3],
    vfov_deg: f64,
}

impl Row {
    fn rays_per_pixel(&self) -> f64 {
        self.rays as f64 / (self.width as f64 * self.height as f64).max(1.0)
    }
}

fn read_stats(path: &Path) -> Result<Vec<Row>> {
    let rows: Vec<Row> = crate::output::stats::read_stats(path)?
        .iter()
        .map(|f| {
            let c = &f.counts;
            let validated = f.image_error.is_some();
            let v3 = |v: glam::Vec3| v.to_array().map(f64::from);
            Row {
                frame: f.frame,
                method: f.method.clone(),
                lights: f.lights,
                width: f.width,
                height: f.height,
                spp: f.spp,
                queries: c.queries,
                rays: c.traced(),
                percent: c.percent_traced(),
                seconds: f.thread_seconds,
                wrong: validated.then_some(c.wrong_visible + c.wrong_blocked),
                error_percent: validated.then_some(c.error_percent()),
                wrong_pixels: validated.then_some(c.wrong_pixels),
                psnr_db: f.image_error.map(|e| e.psnr_db),
                camera: v3(f.camera_position),
                target: v3(f.camera_target),
                vfov_deg: f64::from(f.vfov_deg),
            }
        })
        .collect();
    if rows.is_empty() {
        return Err(input_error(path, "no frames in it: nothing to report"));
    }
    Ok(rows)
}

/// Escapes text for HTML element content and quoted attribute values.
fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A sequential colour ramp (close to matplotlib's "inferno"): dark for little, bright for much.
fn ramp(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.0, 0.0, 4.0],
        [87.0, 16.0, 110.0],
        [188.0, 55.0, 84.0],
        [249.0, 142.0, 9.0],
        [252.0, 255.0, 164.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|c| (a[c] + (b[c] - a[c]) * f + 0.5) as u8)
}

fn save_jpeg(path: &Path, img: &RgbImage) -> Result<()> {
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, JPEG_QUALITY)
        .encode_image(img)
        .context("encoding JPEG")?;
    output::write_atomic(path, &bytes)
}

fn scaled(img: &RgbImage, max_width: u32) -> RgbImage {
    if img.width() <= max_width {
        return img.clone();
    }
    let h = ((img.height() as u64 * max_width as u64) / img.width() as u64).max(1) as u32;
    image::imageops::resize(img, max_width, h, image::imageops::FilterType::Triangle)
}

/// One per-frame series of the savings plot.
struct Series {
    file: &'static str,
    title: &'static str,
    unit: &'static str,
    points: Vec<(f64, f64)>,
    colour: [u8; 3],
    /// Shown at the top (the savings, the error); the others are collapsed.
    lead: bool,
}

/// Draws a text-free line plot of `s` (frames on x, from 0 on y) and returns its y axis.
fn draw_plot(path: &Path, s: &Series, frames: (f64, f64)) -> Result<(f64, f64)> {
    let x = if frames.1 > frames.0 {
        frames
    } else {
        (frames.0 - 0.5, frames.0 + 0.5)
    };
    draw_lines(path, &[(&s.points, s.colour)], x, PLOT_SIZE, PLOT_MARGIN)
}

/// The rays heat maps' colour scale ends at this percentile of the rays per pixel over all
/// frames (brighter pixels clip), so a few pixels that traced every light do not leave the rest
/// of the map black.
const RAYS_SCALE_PERCENTILE: f64 = 99.5;

/// The `p`-th percentile of the samples a histogram of counts describes.
fn histogram_percentile(hist: &[u64], p: f64) -> f32 {
    let n: u64 = hist.iter().sum();
    let want = (n as f64 * p / 100.0).ceil() as u64;
    let mut seen = 0;
    for (b, c) in hist.iter().enumerate() {
        seen += c;
        if seen >= want {
            return b as f32;
        }
    }
    hist.len().saturating_sub(1) as f32
}

/// What the report found about one frame's files.
struct FrameImages {
    /// The frame's PNG, as the folder names it (`frame_0003.png`, `turntable_0004.png`).
    png: String,
    thumb: Option<String>,
    rays_map: Option<String>,
    wrong_map: Option<String>,
    problem: Option<String>,
}

/// A first look at one frame: its thumbnail (written), its preview at the GIF's size, and
/// what its EXR holds for the colour scales (shared by all frames). Only small images are
/// kept, so memory does not grow with the frames' resolution.
struct Scan {
    thumb: Option<String>,
    gif: Option<RgbImage>,
    exr_ok: bool,
    rays_hist: Vec<u64>,
    wrong_max: Option<f32>,
    problem: Option<String>,
}

fn scan_frame(dir: &Path, names: &FrameNames, out: &Path, frame: usize, gif: bool) -> Scan {
    let mut scan = Scan {
        thumb: None,
        gif: None,
        exr_ok: false,
        rays_hist: Vec::new(),
        wrong_max: None,
        problem: None,
    };
    let mut problems = Vec::new();
    let png = names.path(dir, frame, "png");
    match image::open(&png) {
        Ok(img) => {
            // A transparent frame is shown over a checkerboard.
            let img = output::png::over_checkerboard(&img.to_rgba8(), 8);
            let name = format!("thumb_{frame:04}.jpg");
            match save_jpeg(&out.join(&name), &scaled(&img, THUMB_WIDTH)) {
                Ok(()) => scan.thumb = Some(name),
                Err(e) => problems.push(format!("{name}: {e:#}")),
            }
            if gif {
                scan.gif = Some(scaled(&img, GIF_WIDTH));
            }
        }
        Err(e) => problems.push(format!("{}: {e}", file_name(&png))),
    }
    // The colour scales' figures from the frame's record where its files are the recorded
    // ones (sizes: cheap), else from the EXR itself (a folder from an earlier version).
    let recorded = FrameRecord::read(dir, frame)
        .filter(|r| r.sizes_match(dir, names))
        .and_then(|r| Some((parse_histogram(&r.rays_histogram)?, r.wrong_max)))
        .filter(|(hist, _)| !hist.is_empty());
    let exr = names.path(dir, frame, "exr");
    if let Some((hist, wrong_max)) = recorded {
        scan.exr_ok = true;
        scan.rays_hist = hist;
        scan.wrong_max = wrong_max;
    } else {
        match output::exr::read_frame_here(&exr) {
            Ok(f) => {
                scan.exr_ok = true;
                if let Some(r) = f.channel(Channel::Rays.name()) {
                    scan.rays_hist = count_histogram(r);
                }
                scan.wrong_max = f.channel(Channel::Wrong.name()).map(finite_max);
            }
            Err(e) => problems.push(format!("{}: {e:#}", file_name(&exr))),
        }
    }
    if !problems.is_empty() {
        scan.problem = Some(problems.join("; "));
    }
    scan
}

/// A frame's rays and wrong-pair heat maps (file names), and a problem reading its EXR.
type HeatMaps = (Option<String>, Option<String>, Option<String>);

/// Writes one frame's heat maps (`rays_NNNN.jpg`, and `wrong_NNNN.png` when the EXR has a
/// `wrong` channel: single wrong pixels would smear in a JPEG) into `out`, at most
/// [`MAP_WIDTH`] wide; returns their file names, and what kept them from being made if the
/// EXR does not read.
fn heat_maps(
    dir: &Path,
    names: &FrameNames,
    out: &Path,
    frame: usize,
    rays_top: f32,
    wrong_top: f32,
) -> Result<HeatMaps> {
    let exr = names.path(dir, frame, "exr");
    let f = match output::exr::read_frame_here(&exr) {
        Ok(f) => f,
        // A file the record vouched for by its size alone may still not read: said on the
        // frame, as when the first pass reads it.
        Err(e) => return Ok((None, None, Some(format!("{}: {e:#}", file_name(&exr))))),
    };
    let (w, h) = (f.width as u32, f.height as u32);
    let mut names = (None, None, None);
    if let Some(rays) = f.channel(Channel::Rays.name()) {
        let mut img = RgbImage::new(w, h);
        for (p, v) in img.pixels_mut().zip(rays) {
            *p = Rgb(ramp(if rays_top > 0.0 { v / rays_top } else { 0.0 }));
        }
        let name = format!("rays_{frame:04}.jpg");
        save_jpeg(&out.join(&name), &scaled(&img, MAP_WIDTH))?;
        names.0 = Some(name);
    }
    if let Some(wrong) = f.channel(Channel::Wrong.name()) {
        let mut img = RgbImage::new(w, h);
        let (rr, gg, bb) = (f.channel("R"), f.channel("G"), f.channel("B"));
        for (k, (p, v)) in img.pixels_mut().zip(wrong).enumerate() {
            *p = if *v > 0.0 {
                let t = v / wrong_top.max(1.0);
                Rgb(ramp(WRONG_RAMP_START + (1.0 - WRONG_RAMP_START) * t))
            } else {
                // The frame under it, dimmed and grey, so the mistakes can be placed.
                let lum = match (rr, gg, bb) {
                    (Some(r), Some(g), Some(b)) => 0.2126 * r[k] + 0.7152 * g[k] + 0.0722 * b[k],
                    _ => 0.0,
                };
                let g = (crate::view::srgb_encode(lum) * 90.0) as u8;
                Rgb([g, g, g])
            };
        }
        let name = format!("wrong_{frame:04}.png");
        save_png(&out.join(&name), &scaled(&img, MAP_WIDTH))?;
        names.1 = Some(name);
    }
    Ok(names)
}

/// Writes `DIR/report.html` (and its pictures in `DIR/report/`) for the render in `dir`.
/// Returns the page's path. A missing folder or `stats.csv` is an input error naming the path.
/// Frames are read in parallel on the current rayon pool, twice (once for the colour scales,
/// once for the heat maps), so memory stays bounded by the threads, not the frame count.
pub fn write_report(dir: &Path) -> Result<PathBuf> {
    if !dir.exists() {
        return Err(input_error(dir, "no such folder"));
    }
    if !dir.is_dir() {
        return Err(input_error(dir, "not a folder"));
    }
    let rows = read_stats(&dir.join("stats.csv"))?;
    let names = FrameNames::of_folder(dir);
    let out = dir.join("report");
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    remove_old_pictures(&out)?;
    let video = dir.join(VIDEO_FILE).is_file().then_some(VIDEO_FILE);

    // Pass 1: thumbnails, previews for the GIF (when there is no video), and the colour
    // scales' ranges over all frames.
    let mut scans: Vec<Scan> = rows
        .par_iter()
        .map(|r| scan_frame(dir, &names, &out, r.frame, video.is_none()))
        .collect();
    let (rays_max, wrong_max, any_wrong_channel) = colour_scales(&scans);

    // Pass 2, the heat maps, beside the pictures that do not read the frames: the animated
    // preview (the video, else a GIF), the colour scales, the plots and the lights.
    let previews: Vec<RgbImage> = scans.iter_mut().filter_map(|s| s.gif.take()).collect();
    let series = plot_series(&rows);
    let (maps, pictures) = rayon::join(
        || -> Result<Vec<HeatMaps>> {
            rows.par_iter()
                .zip(&scans)
                .map(|(r, s)| {
                    if s.exr_ok {
                        heat_maps(dir, &names, &out, r.frame, rays_max, wrong_max)
                    } else {
                        Ok((None, None, None))
                    }
                })
                .collect()
        },
        || -> Result<_> {
            let animation = match video {
                Some(v) => Animation::Video(v),
                None if !previews.is_empty() => {
                    write_gif(&out.join("turntable.gif"), &previews)?;
                    Animation::Gif
                }
                None => Animation::None,
            };
            let scale = |from: f32| {
                RgbImage::from_fn(256, 14, |x, _| {
                    Rgb(ramp(from + (1.0 - from) * x as f32 / 255.0))
                })
            };
            save_png(&out.join("scale_rays.png"), &scale(0.0))?;
            if any_wrong_channel {
                save_png(&out.join("scale_wrong.png"), &scale(WRONG_RAMP_START))?;
            }
            // Savings plot, one panel per quantity.
            let frames = (rows[0].frame as f64, rows[rows.len() - 1].frame as f64);
            let axes = series
                .par_iter()
                .map(|s| draw_plot(&out.join(s.file), s, frames))
                .collect::<Result<Vec<_>>>()?;
            // The lights over the environment map.
            let lights_note = lights_picture(dir, &out.join("lights.png"));
            Ok((animation, axes, lights_note))
        },
    );
    let (maps, (animation, axes, lights_note)) = (maps?, pictures?);
    let mut images = Vec::new();
    for ((s, (rays_map, wrong_map, unread)), r) in scans.into_iter().zip(maps).zip(&rows) {
        let problem = match (s.problem, unread) {
            (Some(a), Some(b)) => Some(format!("{a}; {b}")),
            (a, b) => a.or(b),
        };
        images.push(FrameImages {
            png: names.name(r.frame, "png"),
            thumb: s.thumb,
            rays_map,
            wrong_map,
            problem,
        });
    }

    let html = page(
        dir,
        &rows,
        &images,
        animation,
        (rays_max, wrong_max, any_wrong_channel),
        &series,
        &axes,
        &lights_note,
    );
    let path = dir.join("report.html");
    output::write_atomic(&path, html.as_bytes())?;
    Ok(path)
}

/// The colour scales' ranges over all frames: the rays heat maps' top (at
/// [`RAYS_SCALE_PERCENTILE`]), the wrong-pair maps' top, and whether any frame has a `wrong`
/// channel.
fn colour_scales(scans: &[Scan]) -> (f32, f32, bool) {
    let mut rays_hist: Vec<u64> = Vec::new();
    for s in scans {
        if s.rays_hist.len() > rays_hist.len() {
            rays_hist.resize(s.rays_hist.len(), 0);
        }
        for (a, b) in rays_hist.iter_mut().zip(&s.rays_hist) {
            *a += b;
        }
    }
    let rays_max = histogram_percentile(&rays_hist, RAYS_SCALE_PERCENTILE);
    let any_wrong_channel = scans.iter().any(|s| s.wrong_max.is_some());
    let wrong_max = scans
        .iter()
        .filter_map(|s| s.wrong_max)
        .fold(0.0f32, f32::max);
    (rays_max, wrong_max, any_wrong_channel)
}

/// The per-frame series of the savings plot, one panel per quantity: the share traced, rays
/// per pixel, thread-seconds, and with validation the wrong predictions.
fn plot_series(rows: &[Row]) -> Vec<Series> {
    let fx = |f: fn(&Row) -> Option<f64>| -> Vec<(f64, f64)> {
        rows.iter()
            .filter_map(|r| f(r).map(|v| (r.frame as f64, v)))
            .collect()
    };
    let mut series = vec![
        Series {
            file: "plot_percent.png",
            title: "Shadow queries traced",
            unit: "%",
            points: fx(|r| Some(r.percent)),
            colour: [31, 119, 180],
            lead: true,
        },
        Series {
            file: "plot_rays_per_pixel.png",
            title: "Shadow rays traced per pixel",
            unit: "rays",
            points: fx(|r| Some(r.rays_per_pixel())),
            colour: [44, 160, 44],
            lead: false,
        },
        Series {
            file: "plot_seconds.png",
            title: "Thread-seconds per frame",
            unit: "s",
            points: fx(|r| Some(r.seconds)),
            colour: [255, 127, 14],
            lead: false,
        },
    ];
    let error_points = fx(|r| r.error_percent);
    if !error_points.is_empty() {
        series.push(Series {
            file: "plot_error.png",
            title: "Wrong predictions (validation)",
            unit: "% of queries",
            points: error_points,
            colour: [214, 39, 40],
            lead: true,
        });
    }
    series
}

/// The animation the page leads with.
#[derive(Clone, Copy)]
enum Animation {
    /// The folder's video (its file name).
    Video(&'static str),
    /// `report/turntable.gif`.
    Gif,
    /// No frame could be read.
    None,
}

/// Removes the pictures an earlier report left in `out` (a report rebuilt after the video
/// was made has no GIF; renamed frames leave no stale maps). Only our own names go.
fn remove_old_pictures(out: &Path) -> Result<()> {
    let ours = |n: &str| {
        let stem = ["thumb_", "rays_", "wrong_", "plot_", "scale_"]
            .iter()
            .any(|p| n.starts_with(p));
        let whole = ["turntable.gif", "contact_sheet.png", "lights.png"].contains(&n);
        (stem && (n.ends_with(".png") || n.ends_with(".jpg"))) || whole
    };
    let rd = std::fs::read_dir(out).with_context(|| format!("listing {}", out.display()))?;
    for e in rd.flatten() {
        if e.file_name().to_str().is_some_and(ours) && e.path().is_file() {
            std::fs::remove_file(e.path())
                .with_context(|| format!("removing {}", e.path().display()))?;
        }
    }
    Ok(())
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

/// The animated preview: each frame's palette (NeuQuant at speed 10) and its LZW stream made
/// in parallel, then the frames written in order — the file the image crate's GIF encoder
/// writes, a frame at a time.
fn write_gif(path: &Path, frames: &[RgbImage]) -> Result<()> {
    let Some(first) = frames.first() else {
        return Ok(());
    };
    let size = |n: u32| u16::try_from(n).context("encoding GIF: a preview over 65535 pixels");
    let (width, height) = (size(first.width())?, size(first.height())?);
    let encoded: Vec<gif::Frame> = frames
        .par_iter()
        .map(|p| {
            let mut rgba = image::DynamicImage::ImageRgb8(p.clone())
                .to_rgba8()
                .into_raw();
            let mut frame = gif::Frame::from_rgba_speed(width, height, &mut rgba, 10);
            frame.delay = (GIF_FRAME_MS / 10) as u16; // hundredths of a second
            frame.dispose = gif::DisposalMethod::Background;
            frame.make_lzw_pre_encoded();
            frame
        })
        .collect();
    let mut bytes = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut bytes, width, height, &[]).context("encoding GIF")?;
        enc.set_repeat(gif::Repeat::Infinite)
            .context("encoding GIF")?;
        for frame in &encoded {
            enc.write_lzw_pre_encoded_frame(frame)
                .context("encoding GIF")?;
        }
    }
    output::write_atomic(path, &bytes)
}

/// What became of the lights picture: `Ok(environment source)` when drawn, `Err(why not)`.
type LightsNote = std::result::Result<String, String>;

fn lights_picture(dir: &Path, png: &Path) -> LightsNote {
    let json = dir.join("lights.json");
    let set: LightSet = lights::read_json(&json).map_err(|e| format!("{e:#}"))?;
    let Some(envs) = &set.environment else {
        return Err("the lights were placed by hand (no environment map in lights.json)".into());
    };
    let env = if envs.source == "builtin:sky" {
        EnvMap::builtin_sky()
    } else {
        let given = Path::new(&envs.source);
        let candidates = [given.to_path_buf(), dir.join(given)];
        let found = candidates.iter().find(|p| p.is_file()).ok_or_else(|| {
            format!(
                "the environment map {} named in lights.json is not found from here",
                envs.source
            )
        })?;
        EnvMap::load(found).map_err(|e| format!("{e:#}"))?
    };
    if (env.width, env.height) != (envs.width, envs.height) {
        return Err(format!(
            "{} is now {}×{}, the lights were sampled from a {}×{} map",
            envs.source, env.width, env.height, envs.width, envs.height
        ));
    }
    let env = env
        .with_rotation(envs.rotation_deg)
        .with_intensity(envs.intensity)
        .map_err(|e| format!("{e:#}"))?;
    lights::picture::cells_png(&env, &set, png).map_err(|e| format!("{e:#}"))?;
    Ok(envs.source.clone())
}

/// The scene key of the paper's Table 1 ("shapes" or "bunny") when the output folder's name
/// says which.
fn scene_key(dir: &Path) -> Option<&'static str> {
    let name = std::fs::canonicalize(dir)
        .ok()
        .and_then(|p| p.file_name().map(|n| n.to_string_lossy().to_lowercase()))
        .or_else(|| dir.file_name().map(|n| n.to_string_lossy().to_lowercase()))?;
    ["shapes", "bunny"].into_iter().find(|k| name.contains(k))
}

fn distinct<T: Ord + ToString>(v: impl Iterator<Item = T>) -> String {
    v.collect::<BTreeSet<T>>()
        .into_iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn with_commas(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, ch) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push('\u{202f}');
        }
        out.push(ch);
    }
    out
}

const CSS: &str = "\
body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1150px;padding:0 1em;color:#222;background:#fafafa}\
h1{font-size:1.5em;margin-bottom:.2em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}\
.lead{font-size:1.05em;margin:.2em 0 1em}\
table{border-collapse:collapse;font-size:.9em}td,th{border:1px solid #ccc;padding:.2em .5em;text-align:right}\
th{background:#eee}td.l,th.l{text-align:left}\
.top{display:flex;flex-wrap:wrap;gap:1.5em;align-items:flex-start}.top>figure{flex:0 1 640px}.top>div{flex:1 1 360px}\
.top video,.top img.anim{max-width:640px;width:100%;background:#000;display:block}\
figure{margin:0}figcaption{font-size:.85em;color:#555}\
.plot{display:grid;grid-template-columns:3em 640px;width:max-content;column-gap:.4em;margin-bottom:1em}\
.plot figcaption{grid-column:1/3;font-weight:bold;color:#222}\
.ylab{display:flex;flex-direction:column;justify-content:space-between;height:180px;padding:8px 0;box-sizing:border-box;font-size:.75em;text-align:right}\
.ylab span{line-height:0}\
.xlab{grid-column:2;display:flex;justify-content:space-between;padding:0 8px;font-size:.75em}\
.sheet{display:grid;grid-template-columns:repeat(auto-fill,minmax(160px,1fr));gap:6px}\
.sheet figure{background:#202020;position:relative}.sheet img{width:100%;display:block}\
.sheet figcaption{position:absolute;left:0;top:0;background:rgba(0,0,0,.6);color:#fff;font-size:.8em;padding:0 .3em}\
details{margin-top:1.2em}summary{font-size:1.1em;font-weight:bold;cursor:pointer}\
.frames td{vertical-align:top;text-align:center;white-space:nowrap}.frames td.l{white-space:normal}.frames img{width:160px;display:block}\
.scale{display:flex;align-items:center;gap:.4em;font-size:.85em}\
.note{color:#a33}";

/// Writes the lines of a two-column table (`kv` rows).
fn kv_table(h: &mut String, rows: &[(&str, String)]) {
    h.push_str("<table>\n");
    for (k, v) in rows {
        let _ = writeln!(
            h,
            "<tr><th class=\"l\">{}</th><td class=\"l\">{}</td></tr>",
            esc(k),
            esc(v)
        );
    }
    h.push_str("</table>\n");
}

/// One plot with its HTML axis labels.
fn plot_figure(h: &mut String, s: &Series, (top, step): (f64, f64), rows: &[Row], lazy: bool) {
    let _ = write!(
        h,
        "<figure class=\"plot\"><figcaption>{} ({})</figcaption><div class=\"ylab\">",
        esc(s.title),
        esc(s.unit)
    );
    let steps = (top / step).round() as usize;
    for k in (0..=steps).rev() {
        let _ = write!(h, "<span>{}</span>", tick(k as f64 * step));
    }
    let _ = writeln!(
        h,
        "</div><img src=\"report/{}\" width=\"{}\" height=\"{}\" alt=\"{}\"{}>\
         <div class=\"xlab\"><span>frame {}</span><span>frame {}</span></div></figure>",
        s.file,
        PLOT_SIZE.0,
        PLOT_SIZE.1,
        esc(s.title),
        if lazy { " loading=\"lazy\"" } else { "" },
        rows[0].frame,
        rows[rows.len() - 1].frame
    );
}

#[allow(clippy::too_many_arguments)]
fn page(
    dir: &Path,
    rows: &[Row],
    images: &[FrameImages],
    animation: Animation,
    (rays_max, wrong_max, any_wrong): (f32, f32, bool),
    series: &[Series],
    axes: &[(f64, f64)],
    lights_note: &LightsNote,
) -> String {
    let name = std::fs::canonicalize(dir)
        .ok()
        .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .unwrap_or_else(|| dir.display().to_string());
    let title = format!("envshadow report: {name}");
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{}</title>\n<style>{CSS}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
        esc(&title),
        esc(&title)
    );

    // Totals and settings.
    let totals = totals(&mut h, dir, rows);

    // The animation beside the totals.
    h.push_str("<div class=\"top\">\n");
    animation_figure(&mut h, animation, images, rows);
    h.push_str("<div>\n");
    kv_table(&mut h, &totals.run);
    h.push_str("</div>\n</div>\n");

    warnings_section(&mut h, dir);

    // The savings: percent traced per frame (and the error, validated).
    h.push_str("<h2>Shadow rays traced per frame</h2>\n");
    let lead: Vec<usize> = series
        .iter()
        .enumerate()
        .filter(|(_, s)| s.lead)
        .map(|(k, _)| k)
        .collect();
    for &k in &lead {
        plot_figure(&mut h, &series[k], axes[k], rows, false);
    }

    // The paper's Table 1 beside ours.
    beside_paper(&mut h, dir, rows, totals.percent);

    // Contact sheet: every frame, numbered.
    contact_sheet(&mut h, rows, images);

    // Lights.
    lights_section(&mut h, lights_note, &totals.nlights);

    // The other plots, collapsed.
    h.push_str("<details>\n<summary>More per-frame plots: rays per pixel, seconds</summary>\n");
    for (k, s) in series.iter().enumerate() {
        if !lead.contains(&k) {
            plot_figure(&mut h, s, axes[k], rows, true);
        }
    }
    h.push_str("</details>\n");

    // Per-frame detail, collapsed.
    frame_detail(&mut h, rows, images, (rays_max, wrong_max, any_wrong));
    h.push_str("<p><small>Written by envshadow report from stats.csv, the frames and lights.json in this folder.</small></p>\n</body>\n</html>\n");
    h
}

/// What loading the inputs warned about (`settings.txt`'s `[warnings]` lines), as a list;
/// nothing when there is none.
fn warnings_section(h: &mut String, dir: &Path) {
    let Ok(Some(record)) = output::record::SettingsRecord::read(dir) else {
        return;
    };
    let prefix = format!("{} ", output::record::WARNINGS_KEY);
    let warnings: Vec<&String> = record
        .lines
        .iter()
        .filter(|(k, _)| k.starts_with(&prefix))
        .map(|(_, v)| v)
        .collect();
    if warnings.is_empty() {
        return;
    }
    h.push_str("<h2>Warnings</h2>\n<ul class=\"warnings\">\n");
    for w in warnings {
        let _ = writeln!(h, "<li>{}</li>", esc(w));
    }
    h.push_str("</ul>\n");
}

/// The run's settings and totals, for the table beside the animation; the share of the
/// shadow queries traced; the light counts.
struct Totals {
    run: Vec<(&'static str, String)>,
    percent: f64,
    nlights: String,
}

/// Writes the page's lead (the frames, their settings and the share traced, in a sentence)
/// and returns the run's settings and totals.
fn totals(h: &mut String, dir: &Path, rows: &[Row]) -> Totals {
    let queries: u64 = rows.iter().map(|r| r.queries).sum();
    let rays: u64 = rows.iter().map(|r| r.rays).sum();
    let seconds: f64 = rows.iter().map(|r| r.seconds).sum();
    let percent = if queries == 0 {
        100.0
    } else {
        100.0 * rays as f64 / queries as f64
    };
    let validated: Vec<&Row> = rows.iter().filter(|r| r.wrong.is_some()).collect();
    let method = distinct(rows.iter().map(|r| r.method.clone()));
    let nlights = distinct(rows.iter().map(|r| r.lights));
    let res = distinct(rows.iter().map(|r| match r.spp {
        1 => format!("{}×{}", r.width, r.height),
        n => format!("{}×{} ({n} samples per pixel)", r.width, r.height),
    }));
    let env_line = match lights::read_json(&dir.join("lights.json")) {
        Ok(set) => match &set.environment {
            Some(e) => format!(
                "{} (rotation {}°, intensity {}), {} sampler",
                e.source,
                e.rotation_deg,
                e.intensity,
                set.sampler.map_or("given", |s| s.name())
            ),
            None => "lights placed by hand".into(),
        },
        Err(e) => format!("lights.json unreadable: {e:#}"),
    };
    let frames_line = format!(
        "{} ({}–{})",
        rows.len(),
        rows[0].frame,
        rows[rows.len() - 1].frame
    );
    let _ = writeln!(
        h,
        "<p class=\"lead\">{} frames at {}, {} lights, {}: <b>{percent:.2} %</b> of the shadow \
         queries traced, the rest predicted; {seconds:.1} thread-seconds of rendering.</p>",
        rows.len(),
        esc(&res),
        esc(&nlights),
        esc(&method)
    );
    let mut run: Vec<(&'static str, String)> = vec![
        ("frames", frames_line),
        ("shadow method", method.clone()),
        ("lights", nlights.clone()),
        ("environment", env_line),
        ("resolution", res),
        (
            "validated",
            if validated.is_empty() {
                "no".to_string()
            } else {
                format!("{} of {} frames", validated.len(), rows.len())
            },
        ),
        ("shadow queries", with_commas(queries)),
        (
            "shadow rays traced",
            format!("{} ({percent:.2} % of the queries)", with_commas(rays)),
        ),
    ];
    run.extend(times(dir, seconds, rays));
    if !validated.is_empty() {
        let vq: u64 = validated.iter().map(|r| r.queries).sum();
        let vw: u64 = validated.iter().filter_map(|r| r.wrong).sum();
        run.push((
            "wrong predictions",
            format!(
                "{} pairs, {:.4} % of the validated frames' queries",
                with_commas(vw),
                100.0 * vw as f64 / (vq.max(1)) as f64
            ),
        ));
    }
    run.push(("folder", dir.display().to_string()));
    Totals {
        run,
        percent,
        nlights,
    }
}

/// The run's wall time and compute time, for the settings and totals.
fn times(dir: &Path, seconds: f64, rays: u64) -> Vec<(&'static str, String)> {
    let mut run = Vec::new();
    // Wall time from the runs that rendered the folder (records/runs.csv; none for a farm's
    // assembled folder); thread-seconds from the frames themselves.
    let runs = crate::output::runs::RunRecord::read_all(dir).unwrap_or_default();
    let wall: f64 = runs.iter().map(|r| r.wall_seconds).sum();
    let run_rays: u64 = runs.iter().map(|r| r.rays_traced).sum();
    if runs.is_empty() {
        run.push((
            "wall time",
            "not recorded (no records/runs.csv: an assembled farm render?)".to_string(),
        ));
    } else {
        let threads = distinct(runs.iter().map(|r| r.threads));
        run.push((
            "wall time",
            format!(
                "{wall:.2} s ({} run{}, {threads} threads), {:.2} M shadow rays per second",
                runs.len(),
                if runs.len() == 1 { "" } else { "s" },
                run_rays as f64 / wall.max(1e-9) / 1e6
            ),
        ));
    }
    run.push((
        "compute time",
        format!(
            "{seconds:.2} thread-seconds (the frames' own, summed), {:.2} M shadow rays per thread-second",
            rays as f64 / seconds.max(1e-9) / 1e6
        ),
    ));
    run
}

/// The animation the page leads with (the video, the GIF, or why neither).
fn animation_figure(h: &mut String, animation: Animation, images: &[FrameImages], rows: &[Row]) {
    match animation {
        Animation::Video(file) => {
            let _ = writeln!(
                h,
                "<figure><video src=\"{0}\" controls loop muted playsinline preload=\"metadata\" \
                 poster=\"{1}\"></video><figcaption>The frames as a video ({0}, H.264).</figcaption></figure>",
                esc(file),
                images
                    .iter()
                    .zip(rows)
                    .find(|(i, _)| i.thumb.is_some())
                    .map(|(i, _)| esc(&i.png))
                    .unwrap_or_default()
            );
        }
        Animation::Gif => h.push_str(
            "<figure><img class=\"anim\" src=\"report/turntable.gif\" alt=\"animated preview\">\
             <figcaption>Animated preview (GIF, 12.5 frames per second); \
             <code>envshadow video DIR</code> makes a video.</figcaption></figure>\n",
        ),
        Animation::None => h.push_str(
            "<p class=\"note\">No frame PNG could be read: no animation or contact sheet.</p>\n",
        ),
    }
}

/// The paper's Table 1 figure beside this render's, when the folder's name says which of the
/// paper's scenes it is and the render has one method and one light count.
fn beside_paper(h: &mut String, dir: &Path, rows: &[Row], percent: f64) {
    let one_method = rows.iter().all(|r| r.method == rows[0].method);
    let one_count = rows.iter().all(|r| r.lights == rows[0].lights);
    let paper = match (scene_key(dir), rows[0].method.parse::<Method>()) {
        (Some(scene), Ok(m)) if one_method && one_count => {
            crate::paper::paper_percent(m, scene, rows[0].lights).map(|p| (scene, p))
        }
        _ => None,
    };
    if let Some((scene, p)) = paper {
        let _ = write!(
            h,
            "<h2>Beside the paper</h2>\n<table>\n<tr><th class=\"l\">{} lights, {}</th><th>% of queries traced</th></tr>\n\
             <tr><td class=\"l\">Ben-Artzi et al. 2004, Table 1 (their “{}” scene, their resolution)</td><td>{p:.1}</td></tr>\n\
             <tr><td class=\"l\">this render</td><td>{percent:.2}</td></tr>\n</table>\n",
            rows[0].lights,
            esc(&rows[0].method),
            esc(scene)
        );
    }
}

/// The contact sheet: every frame's thumbnail, numbered, linking to its PNG.
fn contact_sheet(h: &mut String, rows: &[Row], images: &[FrameImages]) {
    if images.iter().any(|i| i.thumb.is_some()) {
        h.push_str("<h2>Frames</h2>\n<div class=\"sheet\">\n");
        for (r, fi) in rows.iter().zip(images) {
            if let Some(t) = &fi.thumb {
                let _ = writeln!(
                    h,
                    "<figure><a href=\"{1}\"><img src=\"report/{t}\" alt=\"frame {0}\" loading=\"lazy\"></a>\
                     <figcaption>{0}</figcaption></figure>",
                    r.frame,
                    esc(&fi.png)
                );
            }
        }
        h.push_str("</div>\n");
    }
}

/// The lights over the environment map, or why there is no picture of them.
fn lights_section(h: &mut String, lights_note: &LightsNote, nlights: &str) {
    h.push_str("<h2>Lights over the environment map</h2>\n");
    match lights_note {
        Ok(source) => {
            let _ = writeln!(
                h,
                "<figure><img src=\"report/lights.png\" alt=\"lights over the environment map\" style=\"max-width:100%\" loading=\"lazy\">\
                 <figcaption>{} lights from {}: cell borders in magenta, each light a cross, yellow for the dimmest to red for the brightest.</figcaption></figure>",
                esc(nlights),
                esc(source)
            );
        }
        Err(why) => {
            let _ = writeln!(
                h,
                "<p class=\"note\">No picture of the lights: {}</p>",
                esc(why)
            );
        }
    }
}

/// The per-frame detail, collapsed: each frame's thumbnail and heat maps beside its figures
/// and camera, under the colour scales.
fn frame_detail(
    h: &mut String,
    rows: &[Row],
    images: &[FrameImages],
    (rays_max, wrong_max, any_wrong): (f32, f32, bool),
) {
    let _ = writeln!(
        h,
        "<details>\n<summary>Per-frame detail: where the rays went ({} frames)</summary>",
        rows.len()
    );
    let _ = writeln!(
        h,
        "<div class=\"scale\">shadow rays traced per pixel: 0 <img src=\"report/scale_rays.png\" alt=\"colour scale\" width=\"256\" height=\"14\"> {} or more ({RAYS_SCALE_PERCENTILE}th percentile over all frames; click a map for a larger view)</div>",
        tick(rays_max as f64)
    );
    if any_wrong {
        let _ = writeln!(
            h,
            "<div class=\"scale\">wrong pixel–light pairs (validation; grey: none): 1 <img src=\"report/scale_wrong.png\" alt=\"colour scale\" width=\"256\" height=\"14\"> {}</div>",
            tick(wrong_max.max(1.0) as f64)
        );
    }
    h.push_str("<table class=\"frames\">\n<tr><th>frame</th><th>image</th><th>rays per pixel</th>");
    if any_wrong {
        h.push_str("<th>wrong predictions</th>");
    }
    h.push_str("<th>traced</th><th>thread-seconds</th>");
    if any_wrong {
        h.push_str("<th>error</th><th>wrong pixels</th><th>PSNR</th>");
    }
    h.push_str("<th class=\"l\">camera → target, vertical fov</th></tr>\n");
    let cell = |h: &mut String, map: &Option<String>, what: &str, frame: usize| match map {
        Some(m) => {
            let _ = write!(
                h,
                "<td><a href=\"report/{m}\"><img src=\"report/{m}\" alt=\"{what} of frame {frame}\" loading=\"lazy\"></a></td>"
            );
        }
        None => h.push_str("<td>—</td>"),
    };
    for (r, fi) in rows.iter().zip(images) {
        let _ = write!(h, "<tr><td>{}</td>", r.frame);
        match &fi.thumb {
            Some(t) => {
                let _ = write!(
                    h,
                    "<td><a href=\"{1}\"><img src=\"report/{t}\" alt=\"frame {0}\" loading=\"lazy\"></a></td>",
                    r.frame,
                    esc(&fi.png)
                );
            }
            None => h.push_str("<td>—</td>"),
        }
        cell(h, &fi.rays_map, "rays", r.frame);
        if any_wrong {
            cell(h, &fi.wrong_map, "wrong predictions", r.frame);
        }
        let _ = write!(h, "<td>{:.2} %</td><td>{:.3}</td>", r.percent, r.seconds);
        if any_wrong {
            let opt = |v: Option<String>| v.unwrap_or_else(|| "—".into());
            let _ = write!(
                h,
                "<td>{}</td><td>{}</td><td>{}</td>",
                opt(r.error_percent.map(|e| format!("{e:.4} %"))),
                opt(r.wrong_pixels.map(|w| w.to_string())),
                opt(r.psnr_db.map(|p| if p.is_finite() {
                    format!("{p:.1} dB")
                } else {
                    "∞".into()
                }))
            );
        }
        let c = r.camera;
        let t = r.target;
        let _ = write!(
            h,
            "<td class=\"l\">({:.2}, {:.2}, {:.2}) → ({:.2}, {:.2}, {:.2}), {:.1}°",
            c[0], c[1], c[2], t[0], t[1], t[2], r.vfov_deg
        );
        if let Some(p) = &fi.problem {
            let _ = write!(h, "<br><span class=\"note\">{}</span>", esc(p));
        }
        h.push_str("</td></tr>\n");
    }
    h.push_str("</table>\n</details>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup() {
        assert_eq!(
            esc("<a href=\"x\">&'"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
    }

    #[test]
    fn ramp_runs_dark_to_bright() {
        assert_eq!(ramp(0.0), [0, 0, 4]);
        assert_eq!(ramp(1.0), [252, 255, 164]);
        assert_eq!(ramp(f32::NAN), ramp(0.0));
    }
}
