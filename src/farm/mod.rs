//! Rendering on many machines: `plan` splits a run into jobs (frame range × tiles), each
//! `render --job K --of N` (or `--frames A..B --tiles LIST`) renders one job into its own
//! folder, and `assemble` stitches the folders into the frames a one-process render writes.
//! GNU parallel (scripts/farm.sh) or Slurm moves the jobs; nothing here talks to the network.
//!
//! Output folder layout (`OUT` is the spec's output folder or `--out`):
//! `OUT/plan.json` (settings, build, the jobs), `OUT/jobs.txt` (one job per line for GNU
//! parallel, see [`plan::job_lines`]), `OUT/inputs.txt` (the files a host needs),
//! `OUT/jobs/<folder>/` (one job, see [`job`]), and after `assemble` the usual frames,
//! `stats.csv`, `lights.json` and report.

pub mod assemble;
pub mod identity;
pub mod job;
pub mod plan;

use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::{Deserialize, Serialize};

use crate::anim::Animation;
use crate::coordinator;
use crate::error::{Result, input_error};
use crate::output::write_atomic;
use crate::run::{Progress, RunOptions, RunSummary};
use job::{JobWriter, Manifest, PlanRef, Settings};
use plan::{By, Job, PlanRequest, TileSet};

/// `plan.json`'s `format`.
pub const PLAN_FORMAT: &str = "envshadow-plan 1";

/// `OUT/plan.json`: what `assemble` checks the jobs against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanFile {
    pub format: String,
    /// The spec as given to `plan`.
    pub spec: String,
    /// The build of the `envshadow` that planned (the hosts must run the same).
    pub build: String,
    pub settings: Settings,
    pub plan: PlanRef,
    pub jobs: Vec<Job>,
    /// With `[output] video` (or `--video`): the frame rate `assemble` encodes the assembled
    /// frames at. Not a job setting (the jobs render the same bits either way); absent in
    /// plans written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video_fps: Option<crate::output::rate::FrameRate>,
}

/// The plan request for an animation (its selected frames and tile grid).
pub fn request(anim: &Animation, jobs: usize, by: Option<By>) -> Result<PlanRequest> {
    let alignment = anim.frame_alignment();
    Ok(PlanRequest {
        frames: anim.frames.clone(),
        tiles: anim.render.tiles(None).len(),
        alignment,
        jobs,
        by: by.unwrap_or_else(|| plan::default_by(alignment)),
    })
}

/// `envshadow plan`: writes `plan.json`, `jobs.txt` and `inputs.txt` into the animation's
/// output folder and returns the jobs.
pub fn write_plan(anim: &Animation, spec: &Path, jobs: usize, by: Option<By>) -> Result<Vec<Job>> {
    let req = request(anim, jobs, by)?;
    let list = plan::plan(&req)?;
    let dir = &anim.output.dir;
    crate::output::create_output_dir(dir)?;
    let file = PlanFile {
        format: PLAN_FORMAT.into(),
        spec: spec.display().to_string(),
        build: identity::build_id(),
        settings: Settings::of(anim)?,
        plan: PlanRef {
            jobs: req.jobs,
            by: req.by,
        },
        jobs: list.clone(),
        video_fps: anim.output.video.then_some(anim.output.fps),
    };
    let json = serde_json::to_string_pretty(&file).context("encoding the plan")?;
    write_atomic(&dir.join("plan.json"), json.as_bytes())?;
    write_atomic(&dir.join("jobs.txt"), plan::job_lines(&list).as_bytes())?;
    let mut inputs = String::new();
    for abs in plan::input_files(spec, anim)? {
        inputs.push_str(&abs.display().to_string());
        inputs.push('\n');
    }
    write_atomic(&dir.join("inputs.txt"), inputs.as_bytes())?;
    Ok(list)
}

/// Which job `render` renders.
#[derive(Clone, Debug)]
pub enum JobSelection {
    /// Job K of the plan for N jobs.
    Planned {
        index: usize,
        of: usize,
        by: Option<By>,
    },
    /// Explicit tiles through the animation's (selected) frames.
    Tiles(TileSet),
}

/// `envshadow render --job K --of N` / `--tiles LIST`: renders one job into
/// `OUT/jobs/<folder>/`; with `resume`, frames already published there are skipped.
pub fn render_job(
    anim: &Animation,
    sel: &JobSelection,
    resume: bool,
    cancel: crate::cancel::Cancel,
    progress: &dyn Progress,
) -> Result<(Job, PathBuf, RunSummary)> {
    let grid = anim.render.tiles(None);
    let (job, plan_ref) = match sel {
        JobSelection::Planned { index, of, by } => {
            let req = request(anim, *of, *by)?;
            let list = plan::plan(&req)?;
            let Some(job) = list.get(*index).cloned() else {
                return Err(input_error(
                    "--job",
                    format!(
                        "job {index} does not exist: the plan for {of} jobs by {} has {} (0..{})",
                        req.by.name(),
                        list.len(),
                        list.len()
                    ),
                ));
            };
            (
                job,
                Some(PlanRef {
                    jobs: req.jobs,
                    by: req.by,
                }),
            )
        }
        JobSelection::Tiles(tiles) => {
            if let Some(t) = tiles.max()
                && t >= grid.len()
            {
                return Err(input_error(
                    "--tiles",
                    format!(
                        "tile {t} does not exist: a {}x{} frame in tiles of {} has tiles 0..{}",
                        anim.render.width,
                        anim.render.height,
                        anim.render.tile,
                        grid.len()
                    ),
                ));
            }
            if anim.frame_alignment() > 1 && tiles.len() < grid.len() {
                return Err(input_error(
                    "--tiles",
                    "this animation's frames depend on whole previous frames (temporal reuse), so a job must render whole frames",
                ));
            }
            let job = Job {
                index: None,
                frames: anim.frames.clone(),
                tiles: tiles.clone(),
            };
            (job, None)
        }
    };
    let settings = Settings::of(anim)?;
    let dir = anim.output.dir.join("jobs").join(job.folder());
    let manifest = Manifest {
        format: job::FORMAT.into(),
        build: identity::build_id(),
        host: identity::host_name(),
        settings: settings.clone(),
        plan: plan_ref,
        job: job.clone(),
        // Set by the writer once the inputs are loaded, before it publishes the manifest.
        warnings: Vec::new(),
    };
    if resume
        && let Ok(old) = job::read_manifest(&dir)
        && (old.settings.fingerprint != settings.fingerprint || old.build != manifest.build)
    {
        return Err(input_error(
            &dir,
            format!(
                "cannot resume: rendered with other settings or another build (fingerprint {} build {}, now {} build {}); remove the folder or run without --resume",
                old.settings.fingerprint, old.build, settings.fingerprint, manifest.build
            ),
        ));
    }
    // render_animation loads the inputs before it creates the folder, so a bad input
    // leaves no job folder; the writer publishes job.json first thing after that.
    let mut job_anim = anim.clone();
    job_anim.frames = job.frames.clone();
    job_anim.output.dir = dir.clone();
    let mut writer = JobWriter::new(dir.clone(), &job, &grid, manifest);
    let opts = RunOptions {
        resume,
        region: None,
        tiles: Some(writer.tiles().to_vec()),
        cancel,
        // Two attempts of one job (a requeue while the first still runs) take turns.
        wait: true,
    };
    let summary = coordinator::render_animation(&job_anim, &opts, &mut writer, progress)?;
    Ok((job, dir, summary))
}
