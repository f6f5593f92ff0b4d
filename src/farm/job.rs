//! One farm job's folder, `OUT/jobs/<folder>/`:
//!
//! | file | content |
//! |---|---|
//! | `job.json` | the manifest: format, build identity, host, settings fingerprint, frame and tile grid, the plan it belongs to, the job's frames and tiles |
//! | `lights.json` | the lights, as a one-process render writes them |
//! | `cryptomatte.json` | with `--cryptomatte`: the ID mattes' manifests, which the assembled frames' headers carry |
//! | `tiles_0003.exr` | frame 3's pixels of the job's tiles, over the tiles' bounding rectangle (float channels `R G B rays visible`, with validation also `wrong ref.R ref.G ref.B`, with samples per pixel `coverage`, over a transparent background `A`) |
//! | `tiles_0003.json` | frame 3's statistics for those tiles (counts, thread-seconds, camera) and the EXR's size and SHA-256; written after the EXR, so it marks the frame done |
//!
//! Every file is published atomically (`crate::output`), so a crashed or duplicated attempt
//! leaves either nothing or a complete, identical file.

use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::{Deserialize, Serialize};

use crate::anim::Animation;
use crate::error::{Result, input_error};
use crate::farm::identity;
use crate::farm::plan::{By, Job};
use crate::film::Counts;
use crate::film::Film;
use crate::frames::FrameSet;
use crate::output::names::FrameNames;
use crate::output::rate::FrameRate;
use crate::output::stats::FrameStats;
use crate::output::write_atomic;
use crate::run::FrameSink;
use crate::tile::{Rect, Tile, bounding, tiles};

/// With `--cryptomatte`: the ID mattes' manifests ([`crate::cryptomatte::TYPES`]' order) as a
/// JSON array of two strings, the same in every job.
pub const CRYPTOMATTE_FILE: &str = "cryptomatte.json";

/// The manifest's `format`; assemble refuses others.
pub const FORMAT: &str = "envshadow-job 1";

/// What every job of one run shares: the pixels' settings and the tile grid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// `identity::settings_fingerprint` of the animation.
    pub fingerprint: String,
    pub width: u32,
    pub height: u32,
    /// Tile size (0: the whole frame is one tile) and tiles per frame.
    pub tile: u32,
    pub tiles: usize,
    pub exposure: f32,
    /// The previews' view transform, the EXR's precision and the frame rate (absent in
    /// manifests written before them: what those wrote).
    #[serde(default = "standard_view")]
    pub view: crate::view::View,
    #[serde(default)]
    pub half: bool,
    #[serde(default = "default_fps")]
    pub fps: FrameRate,
    /// The EXR's channel names (absent in manifests written before layouts: ours).
    #[serde(default)]
    pub exr_layout: crate::output::exr::ExrLayout,
    pub validate: bool,
    /// Samples per pixel: above 1, tile images carry `coverage` (absent in manifests written
    /// before samples per pixel: 1).
    #[serde(default = "one")]
    pub spp: u32,
    /// A transparent background: tile images carry `A` (absent in manifests written before
    /// backgrounds: opaque).
    #[serde(default)]
    pub alpha: bool,
    /// The run's frames (for an explicit job: its own).
    pub frames: FrameSet,
    pub alignment: usize,
    /// The settings record (`Animation::settings_record`) an assembled folder publishes as
    /// `settings.txt`, so a later `render --resume` into it trusts its frames (absent in
    /// plans written before it: the assembled frames then carry no records).
    #[serde(default)]
    pub record: Vec<(String, String)>,
}

impl Settings {
    pub fn of(anim: &Animation) -> Result<Settings> {
        Ok(Settings {
            fingerprint: identity::settings_fingerprint(anim)?,
            width: anim.render.width,
            height: anim.render.height,
            tile: anim.render.tile,
            tiles: anim.render.tiles(None).len(),
            exposure: anim.render.exposure,
            view: anim.render.view,
            half: anim.output.half,
            fps: anim.output.fps,
            exr_layout: anim.output.exr_layout,
            validate: anim.render.validate,
            spp: anim.render.spp,
            alpha: anim.render.background == crate::background::Background::Transparent,
            frames: anim.frames.clone(),
            alignment: anim.frame_alignment(),
            record: anim.settings_record()?.lines,
        })
    }

    /// Whether the frames carry Cryptomatte ID mattes (`--cryptomatte`, as the record says).
    pub fn cryptomatte(&self) -> bool {
        let key = crate::key::Key::Cryptomatte;
        let setting = format!("[{}] {}", key.table(), key.name());
        self.record.contains(&(setting, "true".to_string()))
    }

    /// The frame's tiles (frame-anchored grid).
    pub fn grid(&self) -> Vec<Tile> {
        tiles(self.width, self.height, self.tile, None)
    }
}

/// Which plan a job belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanRef {
    pub jobs: usize,
    pub by: By,
}

/// `job.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: String,
    /// `envshadow version --build` of the executable that rendered it.
    pub build: String,
    pub host: String,
    pub settings: Settings,
    pub plan: Option<PlanRef>,
    pub job: Job,
    /// What loading the inputs warned about (the `[warnings]` a one-process render records):
    /// assembling loads no inputs, so the assembled settings and frame headers take them from
    /// here. The same in every job of a run (absent in manifests written before them, and
    /// when loading warned of nothing).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// `tiles_NNNN.json`: one frame of one job.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TileFrame {
    pub frame: usize,
    pub exr_bytes: u64,
    pub exr_sha256: String,
    pub method: String,
    pub lights: usize,
    /// Every counter of the frame's tiles (flattened, so the JSON keeps one key per counter).
    #[serde(flatten)]
    pub counts: Counts,
    /// The thread-seconds the job spent on these tiles of the frame (its stats.csv row's
    /// `thread_seconds`): the jobs' add up to the frame's.
    #[serde(rename = "seconds")]
    pub thread_seconds: f64,
    pub camera_position: [f32; 3],
    pub camera_target: [f32; 3],
    pub camera_up: [f32; 3],
    pub vfov_deg: f32,
}

impl TileFrame {
    pub fn counts(&self) -> Counts {
        self.counts
    }
}

/// `DIR/tiles_0003.exr` / `.json`.
pub fn tiles_path(dir: &Path, frame: usize, ext: &str) -> PathBuf {
    dir.join(format!("tiles_{frame:04}.{ext}"))
}

/// Why a job's frame is not done.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FrameProblem {
    /// No `tiles_NNNN.json`: the frame was never published, or its statistics were removed.
    NotRendered,
    /// Published files that do not hold together: one line naming the file and the problem.
    Corrupt(String),
}

/// Checks frame `frame` of the job folder `dir` from its files alone: `tiles_NNNN.json` reads
/// and names the frame, and `tiles_NNNN.exr` has the size and SHA-256 it records. The size
/// alone would miss a flipped byte; the hash is what the job wrote, so a match means these
/// are the very bits. Returns the frame's statistics.
pub fn check_frame(dir: &Path, frame: usize) -> std::result::Result<TileFrame, FrameProblem> {
    let json = tiles_path(dir, frame, "json");
    let exr = tiles_path(dir, frame, "exr");
    let name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let corrupt = |msg: String| FrameProblem::Corrupt(msg);
    let text = match std::fs::read_to_string(&json) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(FrameProblem::NotRendered);
        }
        Err(e) => return Err(corrupt(format!("{}: cannot read: {e}", name(&json)))),
    };
    let tf: TileFrame = serde_json::from_str(&text)
        .map_err(|e| corrupt(format!("{}: unreadable: {e}", name(&json))))?;
    if tf.frame != frame {
        return Err(corrupt(format!("{}: says frame {}", name(&json), tf.frame)));
    }
    let bytes = std::fs::read(&exr).map_err(|e| {
        corrupt(format!(
            "{}: {e}, though {} records it",
            name(&exr),
            name(&json)
        ))
    })?;
    if bytes.len() as u64 != tf.exr_bytes {
        return Err(corrupt(format!(
            "{}: checksum mismatch: {} bytes, {} records {} (truncated or replaced)",
            name(&exr),
            bytes.len(),
            name(&json),
            tf.exr_bytes
        )));
    }
    if identity::sha256(&bytes) != tf.exr_sha256 {
        return Err(corrupt(format!(
            "{}: checksum mismatch: the SHA-256 differs from the one {} records (same size, {} bytes: corrupted)",
            name(&exr),
            name(&json),
            bytes.len()
        )));
    }
    Ok(tf)
}

/// `Settings::spp` in manifests written before samples per pixel.
fn one() -> u32 {
    1
}

fn standard_view() -> crate::view::View {
    crate::view::View::Standard
}

fn default_fps() -> FrameRate {
    crate::settings::Output::default().fps
}

impl Settings {
    /// How the assembled frames are written, as the jobs' own render would.
    pub fn frame_format(&self) -> crate::output::FrameFormat {
        crate::output::FrameFormat {
            exposure: self.exposure,
            view: self.view,
            half: self.half,
            names: FrameNames::from_record(&self.record),
            layout: self.exr_layout,
        }
    }
}

/// Writes one job's frames into its folder; the coordinator calls it in place of writing
/// whole frames.
#[derive(Clone, Debug)]
pub struct JobWriter {
    pub dir: PathBuf,
    tiles: Vec<usize>,
    bbox: Rect,
    manifest: Manifest,
}

impl JobWriter {
    /// A writer for `job` of an animation with tile grid `grid`, into `dir`.
    pub fn new(dir: PathBuf, job: &Job, grid: &[Tile], manifest: Manifest) -> JobWriter {
        let mine: Vec<Tile> = grid
            .iter()
            .filter(|t| job.tiles.contains(t.index))
            .copied()
            .collect();
        JobWriter {
            dir,
            tiles: job.tiles.indices().to_vec(),
            bbox: bounding(&mine),
            manifest,
        }
    }

    /// The tiles this job renders.
    pub fn tiles(&self) -> &[usize] {
        &self.tiles
    }
}

impl FrameSink for JobWriter {
    /// Kept in `job.json`, for the assembled frames to record.
    fn input_warnings(&mut self, warnings: &[String]) {
        self.manifest.warnings = warnings.to_vec();
    }

    /// Publishes `job.json`.
    fn begin(&mut self) -> Result<()> {
        write_manifest(&self.dir, &self.manifest)
    }

    /// The frame's files exist and the EXR has the size and SHA-256 its statistics record
    /// (`--resume`): a truncated or corrupted tile image is rendered again.
    fn frame_done(&self, frame: usize) -> bool {
        check_frame(&self.dir, frame).is_ok()
    }

    /// Publishes one rendered frame: the tile image, then its statistics.
    fn write(&self, film: &Film, stats: &FrameStats) -> Result<()> {
        // The ID mattes' manifests come from the scene's names, which assembling never
        // loads: every frame publishes them (the same bytes each time) before its tile image.
        if let Some(manifests) = &film.cryptomatte {
            let json = serde_json::to_string(&**manifests).context("encoding the manifests")?;
            write_atomic(&self.dir.join(CRYPTOMATTE_FILE), json.as_bytes())?;
        }
        let exr_path = tiles_path(&self.dir, stats.frame, "exr");
        write_tile_image(&exr_path, film, self.bbox)?;
        let bytes =
            std::fs::read(&exr_path).with_context(|| format!("reading {}", exr_path.display()))?;
        let c = stats.counts;
        let tf = TileFrame {
            frame: stats.frame,
            exr_bytes: bytes.len() as u64,
            exr_sha256: identity::sha256(&bytes),
            method: stats.method.clone(),
            lights: stats.lights,
            counts: c,
            thread_seconds: stats.thread_seconds,
            camera_position: stats.camera_position.to_array(),
            camera_target: stats.camera_target.to_array(),
            camera_up: stats.camera_up.to_array(),
            vfov_deg: stats.vfov_deg,
        };
        let json = serde_json::to_string_pretty(&tf).context("encoding tile statistics")?;
        write_atomic(&tiles_path(&self.dir, stats.frame, "json"), json.as_bytes())
    }
}

/// Writes `film`'s pixels inside `bbox` as float channels (the frame's, and with validation
/// the brute-force image), ZIP compressed, one thread: lossless (32-bit float whatever
/// `--half` says), so assembling gives back the very floats the renderer made.
fn write_tile_image(path: &Path, film: &Film, bbox: Rect) -> Result<()> {
    let (w, h) = (bbox.width() as usize, bbox.height() as usize);
    let channels = crate::output::exr::film_channels(film, bbox, true, false);
    crate::output::exr::write_channels(path, (w, h), channels)
}

/// Reads `job.json` from a job folder.
pub fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join("job.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| input_error(&path, format!("cannot read the job manifest: {e}")))?;
    let m: Manifest = serde_json::from_str(&text)
        .map_err(|e| input_error(&path, format!("not a job manifest: {e}")))?;
    if m.format != FORMAT {
        return Err(input_error(
            &path,
            format!("format {:?}, expected {FORMAT:?}", m.format),
        ));
    }
    Ok(m)
}

/// Writes `job.json` (atomically).
pub fn write_manifest(dir: &Path, m: &Manifest) -> Result<()> {
    let json = serde_json::to_string_pretty(m).context("encoding the job manifest")?;
    write_atomic(&dir.join("job.json"), json.as_bytes())
}
