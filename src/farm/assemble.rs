//! `envshadow assemble DIR`: stitches the jobs' tile images into the frames a one-process
//! render writes (the same bytes: the film is rebuilt from the very floats and written by the
//! same code), merges their statistics into `stats.csv`, and names every job that is missing,
//! incomplete, corrupt or from other settings or another build. [`pending`] makes the same
//! judgement without writing anything: the jobs a re-run must render again.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;

use crate::error::{Result, input_error};
use crate::farm::PlanFile;
use crate::farm::job::{
    CRYPTOMATTE_FILE, FrameProblem, Manifest, Settings, TileFrame, check_frame, read_manifest,
    tiles_path,
};
use crate::farm::plan::{Job, PlanRequest, plan};
use crate::film::Counts;
use crate::film::{Film, Holds};
use crate::frame_files::exr_header;
use crate::output::exr::{fill_film, read_frame};
use crate::output::rate::FrameRate;
use crate::output::record::{SettingsRecord, warning_lines};
use crate::output::stats::{FrameStats, StatsFile};
use crate::output::write_atomic;
use crate::output::{publish_frame, write_frame_files};
use crate::tile::{Tile, bounding};

/// What `assemble` did.
#[derive(Debug, Default)]
pub struct Assembled {
    /// Frames written, and frames the plan has.
    pub written: usize,
    pub frames: usize,
    pub jobs: usize,
    /// One line per job (or job folder) that is missing, incomplete, corrupt or foreign.
    pub problems: Vec<String>,
    /// The expected jobs that owe frames (in plan order): what a re-run must render.
    pub pending: Vec<Job>,
    /// The plan asked for a video (`[output] video`) at this frame rate.
    pub video_fps: Option<FrameRate>,
}

/// A valid job folder.
struct Source {
    folder: String,
    manifest: Manifest,
    tiles: Vec<Tile>,
}

/// Frames as ranges: `2-5, 9`.
fn frame_list(frames: &BTreeSet<usize>) -> String {
    let v: Vec<usize> = frames.iter().copied().collect();
    crate::farm::plan::TileSet::from_indices(v)
        .to_string()
        .replace(',', ", ")
}

/// Assembles `dir` (see the module doc): judges the job folders as [`pending`] does, then
/// writes `lights.json`, `settings.txt` and every frame whose every tile is present (even
/// when others are not), and `stats.csv`; the problems are returned for the caller to print.
pub fn assemble(dir: &Path) -> Result<Assembled> {
    let judged = Judged::read(dir)?;
    let settings = &judged.settings;
    let stats_path = dir.join("stats.csv");
    let mut stats_file = StatsFile::open(&stats_path);
    let mut tally = Tally::default();
    if let Some(l) = &judged.lights {
        write_atomic(&dir.join("lights.json"), l)?;
    }
    // The folder a one-process render would leave: settings.txt and each frame committed
    // with its record, so `render --resume` into it trusts these frames.
    // The loader's warnings follow the settings, as `FrameFiles` records them.
    let record = (!settings.record.is_empty()).then(|| SettingsRecord {
        lines: (settings.record.iter().cloned())
            .chain(warning_lines(&judged.warnings))
            .collect(),
    });
    if let Some(r) = &record {
        r.write(dir)?;
    }
    for &f in &judged.frames {
        let holds = Holds {
            validated: settings.validate,
            samples: settings.spp > 1,
            transparent: settings.alpha,
            cryptomatte: judged.cryptomatte.is_some(),
        };
        let mut film = Film::new(settings.width, settings.height, holds);
        film.cryptomatte = judged.cryptomatte.clone();
        let pieces = judged.pieces(f, Some(&mut film), &mut tally);
        if pieces.complete()
            && let Some(tf) = pieces.meta
        {
            film.counts = pieces.counts;
            let full = crate::tile::Rect::frame(settings.width, settings.height);
            let v = |a: [f32; 3]| Vec3::from_array(a);
            let stats = FrameStats {
                frame: f,
                method: tf.method.clone(),
                lights: tf.lights,
                width: settings.width,
                height: settings.height,
                spp: settings.spp,
                counts: pieces.counts,
                image_error: film.image_error(full, settings.exposure, settings.view),
                thread_seconds: pieces.thread_seconds,
                camera_position: v(tf.camera_position),
                camera_target: v(tf.camera_target),
                camera_up: v(tf.camera_up),
                vfov_deg: tf.vfov_deg,
            };
            let format = settings.frame_format();
            let number = format.names.number(f);
            let lines = record.as_ref().map_or(&settings.record, |r| &r.lines);
            let header = exr_header(&stats, number, settings.fps, lines);
            match &record {
                Some(r) => {
                    publish_frame(dir, &film, &header, &format, &r.fingerprint())?;
                }
                None => write_frame_files(dir, &film, &header, &format)?,
            }
            stats_file.set(&stats);
            tally.written += 1;
        } else {
            judged.owe(f, &pieces.covered, &mut tally);
        }
    }
    if tally.written > 0 {
        stats_file.write(&stats_path)?;
    }
    Ok(judged.verdict(tally))
}

/// The planned jobs of `dir` that are not done, judged from their files exactly as
/// [`assemble`] judges them (a job is done when its manifest agrees with the plan, its
/// `lights.json` is there and every frame's tile image matches its recorded size and SHA-256),
/// without decoding images or writing anything. `pending` and `problems` say which and why;
/// `written` counts the frames an assembly would write. Needs `plan.json`: a job folder that
/// was deleted is known only from the plan.
pub fn pending(dir: &Path) -> Result<Assembled> {
    let plan = dir.join("plan.json");
    if dir.is_dir() && !plan.exists() {
        return Err(input_error(
            &plan,
            "no plan: the jobs to render are judged against the plan (run envshadow plan first)",
        ));
    }
    let judged = Judged::read(dir)?;
    let mut tally = Tally::default();
    for &f in &judged.frames {
        let pieces = judged.pieces(f, None, &mut tally);
        if pieces.complete() {
            tally.written += 1;
        } else {
            judged.owe(f, &pieces.covered, &mut tally);
        }
    }
    Ok(judged.verdict(tally))
}

/// A farm render's job folders judged as wholes, before any frame of them is read: what
/// [`assemble`] and [`pending`] share.
struct Judged {
    jobs_dir: PathBuf,
    settings: Settings,
    /// The jobs expected, and the frames they cover.
    expected: Vec<Job>,
    frames: BTreeSet<usize>,
    grid: Vec<Tile>,
    /// The valid job folders, and the problem of each other one (by folder name).
    sources: Vec<Source>,
    folder_problem: BTreeMap<String, String>,
    /// `lights.json`, the same in every valid job.
    lights: Option<Vec<u8>>,
    /// With `--cryptomatte`: the manifests of `cryptomatte.json`, the same in every valid job.
    cryptomatte: Option<Arc<[String; 2]>>,
    /// What loading the inputs warned about, the same in every valid job's manifest.
    warnings: Vec<String>,
    /// The plan's video frame rate.
    video_fps: Option<FrameRate>,
}

/// What the frames of a farm render came to, frame by frame.
#[derive(Default)]
struct Tally {
    /// Frames written (or, judging only, that an assembly would write).
    written: usize,
    /// Problems per (folder, frame).
    file_problem: BTreeMap<(String, usize), FrameProblem>,
    /// Expected job → frames it still owes.
    owed: BTreeMap<usize, BTreeSet<usize>>,
}

/// The valid jobs' pieces of one frame.
struct Pieces {
    /// Which tiles of the grid some job gave.
    covered: Vec<bool>,
    counts: Counts,
    thread_seconds: f64,
    /// The first piece's statistics (the frame's method, lights and camera).
    meta: Option<TileFrame>,
}

impl Pieces {
    fn complete(&self) -> bool {
        self.covered.iter().all(|&c| c)
    }
}

impl Judged {
    /// Reads `dir`'s plan and job manifests and judges each job folder as a whole.
    fn read(dir: &Path) -> Result<Judged> {
        if !dir.is_dir() {
            return Err(input_error(dir, "no such folder"));
        }
        let jobs_dir = dir.join("jobs");
        let manifests = read_manifests(&jobs_dir);
        let plan_file = read_plan_file(dir)?;
        let (settings, build, expected) = expectation(dir, plan_file.as_ref(), &manifests)?;
        // Builds: the plan's, else the most common among the jobs.
        let build = build.or_else(|| common_build(&manifests));
        let grid = settings.grid();
        let (mut sources, mut folder_problem) =
            sort_folders(manifests, &settings, build.as_deref(), &grid);
        let lights = shared_file(&jobs_dir, "lights.json", &sources, &mut folder_problem);
        let cryptomatte = if settings.cryptomatte() {
            shared_manifests(&jobs_dir, &sources, &mut folder_problem)
        } else {
            None
        };
        let warnings = shared_warnings(&sources, &mut folder_problem);
        sources.retain(|s| !folder_problem.contains_key(&s.folder));
        let frames: BTreeSet<usize> = expected.iter().flat_map(|j| j.frames.iter()).collect();
        Ok(Judged {
            jobs_dir,
            settings,
            expected,
            frames,
            grid,
            sources,
            folder_problem,
            lights,
            cryptomatte,
            warnings,
            video_fps: plan_file.as_ref().and_then(|p| p.video_fps),
        })
    }

    /// Checks the valid jobs' pieces of frame `f` ([`read_piece`]), each tile from the first
    /// job that has it; given a film, copies them there. Problems go to `tally`.
    fn pieces(&self, f: usize, mut film: Option<&mut Film>, tally: &mut Tally) -> Pieces {
        let mut covered = vec![false; self.grid.len()];
        let mut counts = Counts::default();
        let mut thread_seconds = 0.0;
        let mut meta: Option<TileFrame> = None;
        for s in self
            .sources
            .iter()
            .filter(|s| s.manifest.job.frames.contains(f))
        {
            if s.tiles.iter().any(|t| covered[t.index]) {
                continue; // another job already gave these tiles
            }
            match read_piece(&self.jobs_dir.join(&s.folder), f, s, film.as_deref_mut()) {
                Ok(tf) => {
                    for t in &s.tiles {
                        covered[t.index] = true;
                    }
                    counts += tf.counts();
                    thread_seconds += tf.thread_seconds;
                    meta.get_or_insert(tf);
                }
                Err(e) => {
                    tally.file_problem.insert((s.folder.clone(), f), e);
                }
            }
        }
        Pieces {
            covered,
            counts,
            thread_seconds,
            meta,
        }
    }

    /// Marks frame `f` owed by each expected job with a tile of it not `covered`.
    fn owe(&self, f: usize, covered: &[bool], tally: &mut Tally) {
        for (k, j) in self.expected.iter().enumerate() {
            if j.frames.contains(f) && j.tiles.indices().iter().any(|&t| !covered[t]) {
                tally.owed.entry(k).or_default().insert(f);
            }
        }
    }

    /// The result: the frames written, and a line per job that owes frames or folder that is
    /// broken, saying why.
    fn verdict(&self, tally: Tally) -> Assembled {
        let mut result = Assembled {
            written: tally.written,
            frames: self.frames.len(),
            jobs: self.expected.len(),
            video_fps: self.video_fps,
            ..Default::default()
        };
        let jobs_dir = &self.jobs_dir;
        // One line per job that left frames unwritten, saying why.
        let host_of = |folder: &str| {
            read_manifest(&jobs_dir.join(folder))
                .ok()
                .map(|m| format!(", rendered on {}", m.host))
                .unwrap_or_default()
        };
        for (k, owed_frames) in &tally.owed {
            let j = &self.expected[*k];
            let folder = j.folder();
            let what = j.describe();
            let line = if !jobs_dir.join(&folder).is_dir() {
                format!("missing {what}: no folder jobs/{folder}")
            } else if let Some(p) = self.folder_problem.get(&folder) {
                format!("bad {what} in jobs/{folder}: {p}")
            } else {
                let corrupt: Vec<String> = owed_frames
                    .iter()
                    .filter_map(|f| match tally.file_problem.get(&(folder.clone(), *f)) {
                        Some(FrameProblem::Corrupt(p)) => Some(p.clone()),
                        _ => None,
                    })
                    .collect();
                if corrupt.is_empty() {
                    format!(
                        "incomplete {what} in jobs/{folder}{}: frames {} not rendered",
                        host_of(&folder),
                        frame_list(owed_frames)
                    )
                } else {
                    format!(
                        "corrupt {what} in jobs/{folder}{}: {}",
                        host_of(&folder),
                        corrupt.join("; ")
                    )
                }
            };
            result.problems.push(line);
            result.pending.push(j.clone());
        }
        // Folders outside the plan that are broken (they did not cost a frame, but say so).
        for (folder, p) in &self.folder_problem {
            if !self.expected.iter().any(|j| j.folder() == *folder) {
                result.problems.push(format!("jobs/{folder}: {p}"));
            }
        }
        result
    }
}

/// The folders under `jobs_dir` (none when it does not list), sorted, with their manifests.
fn read_manifests(jobs_dir: &Path) -> Vec<(String, Result<Manifest>)> {
    let mut folders: Vec<String> = match std::fs::read_dir(jobs_dir) {
        Ok(rd) => rd
            .filter_map(|e| e.ok())
            .filter(|e| e.path().is_dir())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    folders.sort();
    folders
        .iter()
        .map(|f| (f.clone(), read_manifest(&jobs_dir.join(f))))
        .collect()
}

/// `dir/plan.json`, if there is one.
fn read_plan_file(dir: &Path) -> Result<Option<PlanFile>> {
    let plan_path = dir.join("plan.json");
    Ok(if plan_path.exists() {
        let text = std::fs::read_to_string(&plan_path)
            .map_err(|e| input_error(&plan_path, format!("cannot read: {e}")))?;
        Some(
            serde_json::from_str(&text)
                .map_err(|e| input_error(&plan_path, format!("not a plan: {e}")))?,
        )
    } else {
        None
    })
}

/// The settings every job must share, the build they should come from, and the jobs
/// expected: the plan's, else the plan a job says it belongs to, else the explicit jobs.
fn expectation(
    dir: &Path,
    plan_file: Option<&PlanFile>,
    manifests: &[(String, Result<Manifest>)],
) -> Result<(Settings, Option<String>, Vec<Job>)> {
    let first_ok = manifests.iter().find_map(|(_, m)| m.as_ref().ok());
    Ok(match plan_file {
        Some(p) => (p.settings.clone(), Some(p.build.clone()), p.jobs.clone()),
        None => {
            let Some(first) = first_ok else {
                return Err(input_error(
                    dir,
                    "no plan.json and no readable job folders under jobs/: nothing to assemble",
                ));
            };
            let planned = manifests
                .iter()
                .find_map(|(_, m)| m.as_ref().ok().filter(|m| m.plan.is_some()));
            match planned {
                Some(m) => {
                    let p = m.plan.expect("filtered on a plan");
                    let s = m.settings.clone();
                    let jobs = plan(&PlanRequest {
                        frames: s.frames.clone(),
                        tiles: s.tiles,
                        alignment: s.alignment,
                        jobs: p.jobs,
                        by: p.by,
                    })?;
                    (s, None, jobs)
                }
                None => {
                    let mut jobs: Vec<Job> = manifests
                        .iter()
                        .filter_map(|(_, m)| m.as_ref().ok().map(|m| m.job.clone()))
                        .collect();
                    jobs.dedup();
                    (first.settings.clone(), None, jobs)
                }
            }
        }
    })
}

/// The build most common among the jobs' manifests.
fn common_build(manifests: &[(String, Result<Manifest>)]) -> Option<String> {
    let mut n: BTreeMap<&str, usize> = BTreeMap::new();
    for (_, m) in manifests {
        if let Ok(m) = m {
            *n.entry(m.build.as_str()).or_default() += 1;
        }
    }
    n.into_iter()
        .max_by_key(|(_, c)| *c)
        .map(|(b, _)| b.to_string())
}

/// The job folders with `settings`, from `build`, describing themselves and within the
/// `grid`, as sources; a problem with each other folder as a whole (by folder name).
fn sort_folders(
    manifests: Vec<(String, Result<Manifest>)>,
    settings: &Settings,
    build: Option<&str>,
    grid: &[Tile],
) -> (Vec<Source>, BTreeMap<String, String>) {
    let same_settings = |s: &Settings| {
        s.fingerprint == settings.fingerprint
            && s.width == settings.width
            && s.height == settings.height
            && s.tile == settings.tile
            && s.tiles == settings.tiles
    };
    let mut folder_problem: BTreeMap<String, String> = BTreeMap::new();
    let mut sources: Vec<Source> = Vec::new();
    for (folder, m) in manifests {
        match m {
            Err(e) => {
                folder_problem.insert(folder, format!("{e:#}"));
            }
            Ok(m) if !same_settings(&m.settings) => {
                folder_problem.insert(
                    folder,
                    format!(
                        "rendered on {} with other settings (fingerprint {}, {}x{} tile {}; expected {}, {}x{} tile {})",
                        m.host,
                        m.settings.fingerprint,
                        m.settings.width,
                        m.settings.height,
                        m.settings.tile,
                        settings.fingerprint,
                        settings.width,
                        settings.height,
                        settings.tile
                    ),
                );
            }
            Ok(m) if build.is_some_and(|b| *b != m.build) => {
                folder_problem.insert(
                    folder,
                    format!(
                        "rendered on {} by build {}, expected build {} (another build can give other bits)",
                        m.host,
                        m.build,
                        build.unwrap_or_default()
                    ),
                );
            }
            Ok(m) if m.job.folder() != folder => {
                folder_problem.insert(
                    folder,
                    format!("job.json describes {}, not this folder", m.job.folder()),
                );
            }
            Ok(m) if m.job.tiles.max().is_some_and(|t| t >= grid.len()) => {
                folder_problem.insert(
                    folder,
                    format!("tiles {} outside the {}-tile grid", m.job.tiles, grid.len()),
                );
            }
            Ok(m) => {
                let tiles = grid
                    .iter()
                    .filter(|t| m.job.tiles.contains(t.index))
                    .copied()
                    .collect();
                sources.push(Source {
                    folder,
                    manifest: m,
                    tiles,
                });
            }
        }
    }
    (sources, folder_problem)
}

/// A file the same in every job (same inputs, same build: `lights.json`, `cryptomatte.json`),
/// copied once. A job writes it before its first frame's files, so a job without it is not
/// done (and a re-run of the job writes it again): a problem of its folder, as is one that
/// differs.
fn shared_file(
    jobs_dir: &Path,
    name: &str,
    sources: &[Source],
    folder_problem: &mut BTreeMap<String, String>,
) -> Option<Vec<u8>> {
    let mut shared: Option<Vec<u8>> = None;
    for s in sources {
        match std::fs::read(jobs_dir.join(&s.folder).join(name)) {
            Ok(bytes) => match &shared {
                None => shared = Some(bytes),
                Some(l) if *l != bytes => {
                    folder_problem
                        .entry(s.folder.clone())
                        .or_insert_with(|| format!("{name} differs from the other jobs'"));
                }
                Some(_) => {}
            },
            Err(e) => {
                let p = match e.kind() {
                    std::io::ErrorKind::NotFound => format!("no {name}"),
                    _ => format!("{name}: cannot read: {e}"),
                };
                folder_problem.entry(s.folder.clone()).or_insert(p);
            }
        }
    }
    shared
}

/// The loader's warnings every job's manifest records: the same inputs warn the same, so a
/// job whose differ (other input files on its host) is a problem of its folder.
fn shared_warnings(
    sources: &[Source],
    folder_problem: &mut BTreeMap<String, String>,
) -> Vec<String> {
    let Some(first) = sources.first() else {
        return Vec::new();
    };
    for s in &sources[1..] {
        if s.manifest.warnings != first.manifest.warnings {
            folder_problem.entry(s.folder.clone()).or_insert_with(|| {
                format!(
                    "loading its inputs warned of other things than job folder {}'s ({} warnings, {} there): were the input files the same on {}?",
                    first.folder,
                    s.manifest.warnings.len(),
                    first.manifest.warnings.len(),
                    s.manifest.host
                )
            });
        }
    }
    first.manifest.warnings.clone()
}

/// The Cryptomatte manifests every job published ([`shared_file`]); a job whose file is not
/// two manifests is a problem of its folder.
fn shared_manifests(
    jobs_dir: &Path,
    sources: &[Source],
    folder_problem: &mut BTreeMap<String, String>,
) -> Option<Arc<[String; 2]>> {
    let bytes = shared_file(jobs_dir, CRYPTOMATTE_FILE, sources, folder_problem)?;
    match serde_json::from_slice::<[String; 2]>(&bytes) {
        Ok(m) => Some(Arc::new(m)),
        Err(e) => {
            for s in sources {
                folder_problem
                    .entry(s.folder.clone())
                    .or_insert_with(|| format!("{CRYPTOMATTE_FILE}: not two manifests: {e}"));
            }
            None
        }
    }
}

/// Checks one job's frame `f` ([`check_frame`]) and, given a film, copies the job's tiles of
/// it there. Errors are one-line descriptions naming the file.
fn read_piece(
    dir: &Path,
    f: usize,
    s: &Source,
    film: Option<&mut Film>,
) -> std::result::Result<TileFrame, FrameProblem> {
    let tf = check_frame(dir, f)?;
    if let Some(film) = film {
        copy_piece(&tiles_path(dir, f, "exr"), s, film).map_err(FrameProblem::Corrupt)?;
    }
    Ok(tf)
}

/// Copies the job's tiles of the (checked) tile image `exr` into `film`.
fn copy_piece(exr: &Path, s: &Source, film: &mut Film) -> std::result::Result<(), String> {
    let name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let img = read_frame(exr).map_err(|e| format!("{}: {e:#}", name(exr)))?;
    let bbox = bounding(&s.tiles);
    if img.width != bbox.width() as usize || img.height != bbox.height() as usize {
        return Err(format!(
            "{}: {}x{} pixels, expected {}x{}",
            name(exr),
            img.width,
            img.height,
            bbox.width(),
            bbox.height()
        ));
    }
    for t in &s.tiles {
        fill_film(&img, bbox, t.rect, film, true).map_err(|e| format!("{}: {e}", name(exr)))?;
    }
    Ok(())
}
