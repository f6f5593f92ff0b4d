//! `envshadow video DIR` (and `[output] video = true` at the end of a render): the frames'
//! PNG previews as an H.264 MP4, `DIR/video.mp4`, encoded by the system's `ffmpeg` — never
//! downloaded: without it the command says what to install.
//!
//! The frames go to ffmpeg as raw RGB through a pipe, in frame-number order (a folder with
//! gaps gives a video without them), found by the folder's names (`frame_NNNN.png`, or its
//! `[output] output_pattern`), at the animation's frame rate (`[output] fps`, from the
//! folder's `settings.txt`, passed as the exact rational: 30000/1001). The encoding is what players and web pages expect: H.264
//! (libx264, CRF 18, preset medium: visually lossless for renders), 4:2:0 chroma
//! (`yuv420p`, which needs even sizes: an odd width or height gets its last column or row
//! repeated), BT.709 matrix, limited range, tagged sRGB-transfer BT.709 so players convert
//! the colours back as the PNG shows them, and the index at the front (`+faststart`) so a
//! browser starts playing before the whole file has arrived. Written under a temporary name
//! and renamed into place.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::Context;

use crate::error::{Result, input_error};
use crate::folder::VIDEO_FILE;
use crate::output::names::FrameNames;
use crate::output::rate::FrameRate;
use crate::output::record::SETTINGS_FILE;

/// What to install when ffmpeg is missing.
pub const FFMPEG_MISSING: &str = "ffmpeg is not installed (or not on PATH): install it \
     (Debian/Ubuntu: apt-get install ffmpeg; Fedora: dnf install ffmpeg; macOS: brew install \
     ffmpeg) and run envshadow video DIR; envshadow does not download it";

/// x264's constant rate factor: 18 is visually lossless for rendered frames.
const CRF: &str = "18";

/// What [`write_video`] wrote.
#[derive(Clone, Debug)]
pub struct Video {
    pub path: PathBuf,
    /// Frames encoded, the first and last frame numbers.
    pub frames: usize,
    pub first: usize,
    pub last: usize,
    pub fps: FrameRate,
    /// The video's size (the frames' rounded up to even).
    pub width: u32,
    pub height: u32,
}

/// Checks that ffmpeg runs, before work whose end needs it.
pub fn check_ffmpeg() -> Result<()> {
    match Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
    {
        Ok(s) if s.success() => Ok(()),
        Ok(s) => Err(input_error(
            "ffmpeg",
            format!("`ffmpeg -version` failed ({s})"),
        )),
        Err(_) => Err(input_error("ffmpeg", FFMPEG_MISSING)),
    }
}

/// The frame rate a render folder's `settings.txt` records (`[output] fps`), if any.
pub fn recorded_fps(dir: &Path) -> Option<FrameRate> {
    let text = std::fs::read_to_string(dir.join(SETTINGS_FILE)).ok()?;
    text.lines()
        .find_map(|l| l.strip_prefix("[output] fps = "))
        .and_then(|v| v.trim().parse().ok())
}

/// The folder's frame PNGs (named by `names`), by frame number.
fn frame_pngs(dir: &Path, names: &FrameNames) -> Result<Vec<(usize, PathBuf)>> {
    let rd = std::fs::read_dir(dir).map_err(|e| input_error(dir, format!("cannot list: {e}")))?;
    let mut frames: Vec<(usize, PathBuf)> = rd
        .flatten()
        .filter_map(|e| {
            let frame = names.frame_of(e.file_name().to_str()?, "png")?;
            Some((names.number(frame), e.path()))
        })
        .collect();
    frames.sort();
    Ok(frames)
}

/// Encodes the PNGs of the render folder `dir` into `out` (default `DIR/video.mp4`) at `fps`
/// frames per second (see the module doc).
pub fn write_video(dir: &Path, fps: FrameRate, out: Option<&Path>) -> Result<Video> {
    if !dir.is_dir() {
        return Err(input_error(dir, "no such folder"));
    }
    if !(1.0..=crate::settings::MAX_FPS).contains(&fps.as_f64()) {
        return Err(input_error(
            "--fps",
            format!(
                "{fps}: must be a frame rate from 1 to {}",
                crate::settings::MAX_FPS
            ),
        ));
    }
    let names = FrameNames::of_folder(dir);
    let frames = frame_pngs(dir, &names)?;
    let Some((first, first_path)) = frames.first() else {
        return Err(input_error(
            dir,
            format!("no {} in it: nothing to encode", names.shown("png")),
        ));
    };
    let size = image::image_dimensions(first_path)
        .map_err(|e| input_error(first_path, format!("not a readable PNG: {e}")))?;
    let (w, h) = (size.0 + size.0 % 2, size.1 + size.1 % 2);
    check_ffmpeg()?;
    let out = out.map_or_else(|| dir.join(VIDEO_FILE), Path::to_path_buf);
    crate::output::write_atomic_with(&out, |tmp| encode(tmp, &frames, size, (w, h), fps))?;
    Ok(Video {
        path: out,
        frames: frames.len(),
        first: *first,
        last: frames.last().map_or(*first, |f| f.0),
        fps,
        width: w,
        height: h,
    })
}

/// Runs ffmpeg into `tmp`, feeding it `frames` of `size` padded to `even`.
fn encode(
    tmp: &Path,
    frames: &[(usize, PathBuf)],
    size: (u32, u32),
    even: (u32, u32),
    fps: FrameRate,
) -> Result<()> {
    let mut child = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-y"])
        .args(["-f", "rawvideo", "-pix_fmt", "rgb24"])
        .args(["-s", &format!("{}x{}", even.0, even.1)])
        .args(["-framerate", &fps.to_string(), "-i", "-"])
        .args([
            "-vf",
            "scale=out_color_matrix=bt709:out_range=tv,format=yuv420p",
        ])
        .args(["-c:v", "libx264", "-preset", "medium", "-crf", CRF])
        .args(["-color_primaries", "bt709", "-color_trc", "iec61966-2-1"])
        .args(["-colorspace", "bt709", "-color_range", "tv"])
        .args(["-movflags", "+faststart", "-f", "mp4"])
        .arg(tmp)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|_| input_error("ffmpeg", FFMPEG_MISSING))?;
    // ffmpeg's messages, drained while the frames go in, so neither side blocks.
    let mut stderr = child.stderr.take().context("ffmpeg's stderr")?;
    let messages = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let fed = feed(
        child.stdin.take().context("ffmpeg's stdin")?,
        frames,
        size,
        even,
    );
    let status = child.wait().context("waiting for ffmpeg")?;
    let messages = messages.join().unwrap_or_default();
    if !status.success() {
        let last: Vec<&str> = messages.lines().rev().take(3).collect();
        let why: Vec<&str> = last.into_iter().rev().collect();
        anyhow::bail!("ffmpeg failed ({status}): {}", why.join(" / "));
    }
    fed
}

/// Writes each frame as raw RGB rows into `stdin`, padded to `even` by repeating the last
/// column and row; every frame must have `size`.
fn feed(
    mut stdin: impl Write,
    frames: &[(usize, PathBuf)],
    size: (u32, u32),
    even: (u32, u32),
) -> Result<()> {
    let row = even.0 as usize * 3;
    let mut buf = vec![0u8; row * even.1 as usize];
    for (_, path) in frames {
        let img = image::open(path)
            .map_err(|e| input_error(path, format!("not a readable PNG: {e}")))?
            .to_rgb8();
        if img.dimensions() != size {
            return Err(input_error(
                path,
                format!(
                    "{}x{} pixels, the first frame has {}x{}: one video needs one size",
                    img.width(),
                    img.height(),
                    size.0,
                    size.1
                ),
            ));
        }
        let src_row = size.0 as usize * 3;
        for y in 0..even.1 as usize {
            let sy = y.min(size.1 as usize - 1);
            let dst = &mut buf[y * row..(y + 1) * row];
            dst[..src_row].copy_from_slice(&img.as_raw()[sy * src_row..(sy + 1) * src_row]);
            if row > src_row {
                let last = src_row - 3;
                dst.copy_within(last..src_row, src_row);
            }
        }
        // A closed pipe means ffmpeg stopped: its status says why.
        if stdin.write_all(&buf).is_err() {
            return Ok(());
        }
    }
    Ok(())
}
