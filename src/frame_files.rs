//! A render's own folder as a [`FrameSink`]: each frame's EXR and PNG committed with its
//! record, `settings.txt`, `stats.csv` rebuilt from the records, and the run's line in
//! `records/runs.csv`.

use std::path::PathBuf;
use std::sync::Mutex;

use crate::anim::Animation;
use crate::error::{Result, input_error};
use crate::film::Film;
use crate::output;
use crate::output::rate::FrameRate;
use crate::output::record::{FrameRecord, SettingsRecord, warning_lines};
use crate::output::runs::RunRecord;
use crate::output::stats::{FrameStats, StatsFile};
use crate::run::{FrameSink, RunOptions, RunSummary};
use crate::tile::Rect;

/// A render's own folder: `frame_NNNN.exr` and `.png` per frame (or as `--output-pattern`
/// and `--frame-start` name them), each committed with its
/// record, `settings.txt`, and `stats.csv` rebuilt from the records ([`output::record`]).
pub struct FrameFiles {
    dir: PathBuf,
    format: output::FrameFormat,
    fps: FrameRate,
    /// The settings record's lines, which each frame's EXR header repeats.
    record: Vec<(String, String)>,
    /// What the settings record is made from (in `begin`: the inputs are loaded by then, so a
    /// missing file gets the loader's message).
    anim: Animation,
    region: Option<Rect>,
    resume: bool,
    /// The settings' fingerprint, which each frame's record names.
    settings: String,
    /// The loader's warnings, recorded with the settings (`[warnings] N = …`): in
    /// `settings.txt`, so the report shows them, and in every frame's EXR header.
    warnings: Vec<String>,
    /// Frames finish in any order, on several writer threads: each sets its row and
    /// rewrites the file holding the lock, so the file last written has every row set.
    stats: Mutex<StatsFile>,
}

impl FrameFiles {
    /// The frame files of `anim`'s output folder for a run with `opts` (`stats.csv` rows
    /// already there are kept).
    pub fn new(anim: &Animation, opts: &RunOptions) -> FrameFiles {
        let dir = anim.output.dir.clone();
        FrameFiles {
            stats: Mutex::new(StatsFile::open(&dir.join("stats.csv"))),
            dir,
            format: frame_format(anim),
            fps: anim.output.fps,
            record: Vec::new(),
            anim: anim.clone(),
            region: opts.region,
            resume: opts.resume,
            settings: String::new(),
            warnings: Vec::new(),
        }
    }
}

impl FrameSink for FrameFiles {
    /// Checks (`--resume`) and publishes `settings.txt`, and restores the `stats.csv` rows of
    /// committed frames from their records.
    fn begin(&mut self) -> Result<()> {
        let mut now = self.anim.settings_record()?;
        if let Some(r) = self.region {
            now.lines.push(("--region".into(), r.to_string()));
        }
        now.lines.extend(warning_lines(&self.warnings));
        let old = SettingsRecord::read(&self.dir)?;
        // [ours] A resumed folder holds one render's frames: mixing sizes, light counts or
        // methods would make its frames and rows disagree without a word.
        if self.resume
            && let Some(old) = &old
            && let Some(diff) = old.first_difference(&now)
        {
            return Err(input_error(
                &self.dir,
                format!(
                    "cannot resume: its frames were rendered with other settings ({diff}); \
                     render into another folder, or without --resume to render every frame again"
                ),
            ));
        }
        if old.as_ref() != Some(&now) {
            now.write(&self.dir)?;
        }
        self.settings = now.fingerprint();
        self.record = now.lines;
        // A kill between a frame's commit and the stats.csv that follows it loses no row: the
        // committed frame's record has it.
        let stats = self.stats.get_mut().unwrap();
        let mut restored = 0;
        for rec in FrameRecord::read_all(&self.dir) {
            if rec.sizes_match(&self.dir, &self.format.names)
                && stats.row(rec.frame) != Some(&rec.stats_row)
            {
                stats.set_row(rec.frame, &rec.stats_row);
                restored += 1;
            }
        }
        if restored > 0 {
            stats.write(&self.dir.join("stats.csv"))?;
        }
        Ok(())
    }

    fn input_warnings(&mut self, warnings: &[String]) {
        self.warnings = warnings.to_vec();
    }

    /// The frame's record names this run's settings and its EXR and PNG are the recorded files.
    fn frame_done(&self, frame: usize) -> bool {
        FrameRecord::read(&self.dir, frame).is_some_and(|r| {
            r.settings == self.settings && r.files_match(&self.dir, &self.format.names)
        })
    }

    /// Commits the frame's files with its record (frames apart, at once), then its row.
    fn write(&self, film: &Film, stats: &FrameStats) -> Result<()> {
        let number = self.format.names.number(stats.frame);
        let header = exr_header(stats, number, self.fps, &self.record);
        let rec = output::publish_frame(&self.dir, film, &header, &self.format, &self.settings)?;
        let mut rows = self.stats.lock().unwrap();
        rows.set_row(stats.frame, &rec.stats_row);
        rows.write(&self.dir.join("stats.csv"))
    }

    /// Records the run in `records/runs.csv`: its wall time beside its frames' thread-seconds.
    fn finish(&mut self, summary: &RunSummary) -> Result<()> {
        RunRecord {
            started_unix: summary.started_unix,
            threads: summary.threads,
            frames_rendered: summary.rendered,
            frames_skipped: summary.skipped,
            wall_seconds: summary.seconds,
            thread_seconds: summary.thread_seconds,
            queries: summary.counts.queries,
            rays_traced: summary.counts.traced(),
        }
        .append(&self.dir)
    }
}

/// How `anim`'s frames are written: preview exposure and view, EXR precision, file names.
pub fn frame_format(anim: &Animation) -> output::FrameFormat {
    output::FrameFormat {
        exposure: anim.render.exposure,
        view: anim.render.view,
        half: anim.output.half,
        names: anim.output.frame_names(),
        layout: anim.output.exr_layout,
    }
}

/// A frame's EXR header: its camera (from `stats`, as the frame was rendered), its `number`
/// (as its file is named), the frame rate, the settings record's lines and its statistics.
pub fn exr_header<'a>(
    stats: &'a FrameStats,
    number: usize,
    fps: FrameRate,
    settings: &'a [(String, String)],
) -> output::exr::FrameHeader<'a> {
    let camera = crate::camera::Camera::look_at(
        stats.camera_position,
        stats.camera_target,
        stats.camera_up,
        stats.vfov_deg,
        stats.width,
        stats.height,
    );
    let (world_to_camera, world_to_ndc) = camera.exr_matrices();
    output::exr::FrameHeader {
        world_to_camera,
        world_to_ndc,
        number,
        fps,
        settings,
        stats,
    }
}
