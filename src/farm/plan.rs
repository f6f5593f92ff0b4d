//! Splitting a run into farm jobs: a job is a set of frames × a set of tiles of the
//! frame-anchored tile grid (`crate::tile`).
//!
//! The plan is a pure function of the frames, the tile count, the animation's frame alignment,
//! the job count and the split, so `plan` and every `render --job K --of N` compute the same
//! jobs without sharing a file.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::anim::{Animation, SceneSource};
use crate::error::{Result, input_error};
use crate::frames::FrameSet;
use crate::scene::Scene;

/// How a plan splits the work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum By {
    /// Runs of frames, whole frames each.
    Frames,
    /// Tile strips (consecutive tiles in row-major order) through all the frames.
    Tiles,
    /// Runs of frames × tile strips, about √N of each.
    Both,
}

impl By {
    pub fn name(self) -> &'static str {
        match self {
            By::Frames => "frames",
            By::Tiles => "tiles",
            By::Both => "both",
        }
    }
}

/// A set of tile indices, kept sorted and unique; written as ranges: `0-4,9,12-13`.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct TileSet(Vec<usize>);

impl TileSet {
    pub fn from_indices(mut v: Vec<usize>) -> TileSet {
        v.sort_unstable();
        v.dedup();
        TileSet(v)
    }
    pub fn range(r: Range<usize>) -> TileSet {
        TileSet(r.collect())
    }
    pub fn indices(&self) -> &[usize] {
        &self.0
    }
    pub fn len(&self) -> usize {
        self.0.len()
    }
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    pub fn contains(&self, t: usize) -> bool {
        self.0.binary_search(&t).is_ok()
    }
    pub fn max(&self) -> Option<usize> {
        self.0.last().copied()
    }
}

impl fmt::Display for TileSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut i = 0;
        let mut first = true;
        while i < self.0.len() {
            let mut j = i;
            while j + 1 < self.0.len() && self.0[j + 1] == self.0[j] + 1 {
                j += 1;
            }
            if !first {
                f.write_str(",")?;
            }
            first = false;
            if j == i {
                write!(f, "{}", self.0[i])?;
            } else {
                write!(f, "{}-{}", self.0[i], self.0[j])?;
            }
            i = j + 1;
        }
        Ok(())
    }
}

impl std::str::FromStr for TileSet {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<TileSet, String> {
        let mut v = Vec::new();
        for part in s.split(',') {
            let num = |t: &str| {
                t.trim().parse::<usize>().map_err(|_| {
                    format!("{s:?}: {t:?} is not a tile number (expected a list like 0-4,9)")
                })
            };
            match part.split_once('-') {
                Some((a, b)) => {
                    let (a, b) = (num(a)?, num(b)?);
                    if b < a {
                        return Err(format!("{s:?}: tile range {a}-{b} is backwards"));
                    }
                    if b - a > 1 << 24 {
                        return Err(format!("{s:?}: tile range {a}-{b} is too long"));
                    }
                    v.extend(a..=b);
                }
                None => v.push(num(part)?),
            }
        }
        if v.is_empty() {
            return Err(format!("{s:?}: no tiles"));
        }
        Ok(TileSet::from_indices(v))
    }
}

impl TryFrom<String> for TileSet {
    type Error = String;
    fn try_from(s: String) -> std::result::Result<TileSet, String> {
        s.parse()
    }
}

impl From<TileSet> for String {
    fn from(t: TileSet) -> String {
        t.to_string()
    }
}

/// One job: frames `frames` × tiles `tiles`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Job {
    /// Position in the plan (absent for a job given by explicit `--frames`/`--tiles`).
    pub index: Option<usize>,
    pub frames: FrameSet,
    pub tiles: TileSet,
}

impl Job {
    /// The job's folder name under `OUT/jobs/`: its content, so the same frames and tiles land
    /// in the same folder whether they were asked for by index or explicitly. Contiguous
    /// frames `A..B` name it `fAAAA-BBBB_t…`; other sets add the first 8 hex digits of their
    /// text's SHA-256 after that span (`f0001-0004x1f2e3d4c_t…`), which keeps the name short
    /// and free of `,` and `:`.
    pub fn folder(&self) -> String {
        let (first, end) = (
            self.frames.first().unwrap_or(0),
            self.frames.last().map_or(0, |l| l + 1),
        );
        let list = match self.frames.as_range() {
            Some(_) => String::new(),
            None => {
                use sha2::{Digest, Sha256};
                let hash = Sha256::digest(self.frames.to_string().as_bytes());
                let hex: String = hash[..4].iter().map(|b| format!("{b:02x}")).collect();
                format!("x{hex}")
            }
        };
        format!("f{first:04}-{end:04}{list}_t{}", self.tiles)
    }

    /// `job 3 (frames 0..8, tiles 20-39)`.
    pub fn describe(&self) -> String {
        let what = format!("frames {}, tiles {}", self.frames, self.tiles);
        match self.index {
            Some(k) => format!("job {k} ({what})"),
            None => format!("job ({what})"),
        }
    }
}

/// What a plan is computed from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanRequest {
    /// The run's frames.
    pub frames: FrameSet,
    /// Tiles per frame in the frame-anchored grid.
    pub tiles: usize,
    /// `Animation::frame_alignment`: frame ranges start on multiples of it; > 1 forbids
    /// splitting frames into tiles.
    pub alignment: usize,
    /// Jobs asked for (the plan may have fewer when the work does not split that far).
    pub jobs: usize,
    pub by: By,
}

/// The split used when none is asked for: tile strips through the frame range, or frame
/// ranges when jobs must be whole frames.
pub fn default_by(alignment: usize) -> By {
    if alignment > 1 { By::Frames } else { By::Tiles }
}

/// `n` items in `parts` contiguous chunks as equal as possible: chunk `i` is
/// `[i*n/parts, (i+1)*n/parts)`.
fn chunk(n: usize, parts: usize, i: usize) -> Range<usize> {
    i * n / parts..(i + 1) * n / parts
}

/// Computes the jobs. Errors (bad input) on zero jobs, an empty frame range or tile grid,
/// and on a tile split when frames must stay whole.
pub fn plan(req: &PlanRequest) -> Result<Vec<Job>> {
    if req.jobs == 0 {
        return Err(input_error("--jobs", "zero jobs: ask for at least 1"));
    }
    if req.frames.is_empty() || req.tiles == 0 {
        return Err(input_error(
            "--frames",
            "nothing to render: no frames or no tiles",
        ));
    }
    let align = req.alignment.max(1);
    if align > 1 && req.by != By::Frames {
        return Err(input_error(
            "--by",
            format!(
                "{}: this animation's frames depend on whole previous frames (temporal groups of {align} frames), so jobs must be whole frames; use --by frames",
                req.by.name()
            ),
        ));
    }
    // Frame groups: the run's frames in [g*align, (g+1)*align), so a job's frames never
    // share a temporal chain with another job's (a chain starts at a multiple of the
    // alignment): every job renders its frames as the whole run would.
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for f in req.frames.iter() {
        match groups.last_mut() {
            Some(g) if g[0] / align == f / align => g.push(f),
            _ => groups.push(vec![f]),
        }
    }
    let (frame_parts, tile_parts) = match req.by {
        By::Frames => (req.jobs.min(groups.len()), 1),
        By::Tiles => (1, req.jobs.min(req.tiles)),
        By::Both => {
            let root = (req.jobs as f64).sqrt().floor() as usize;
            let fp = root.max(1).min(groups.len());
            (fp, (req.jobs / fp).min(req.tiles))
        }
    };
    let mut jobs = Vec::with_capacity(frame_parts * tile_parts);
    for fi in 0..frame_parts {
        let g = chunk(groups.len(), frame_parts, fi);
        let frames = FrameSet::from_frames(groups[g].iter().flatten().copied());
        for ti in 0..tile_parts {
            jobs.push(Job {
                index: Some(jobs.len()),
                frames: frames.clone(),
                tiles: TileSet::range(chunk(req.tiles, tile_parts, ti)),
            });
        }
    }
    Ok(jobs)
}

/// The job list as GNU parallel reads it with `--colsep '\t'`: one job per line,
/// `INDEX<TAB>FRAMES<TAB>TILES<TAB>FOLDER`, e.g. `3\t0..8\t20-39\tf0000-0008_t20-39`
/// (FRAMES as `--frames` reads it).
pub fn job_lines(jobs: &[Job]) -> String {
    let mut s = String::new();
    for j in jobs {
        s.push_str(&format!(
            "{}\t{}\t{}\t{}\n",
            j.index.unwrap_or(0),
            j.frames,
            j.tiles,
            j.folder()
        ));
    }
    s
}

/// Every file a render of `anim` reads, for `inputs.txt` (what a farm without a shared file
/// system ships to its hosts): the spec, the scene and map, and the buffers and images the
/// scene's glTF file names, each once, absolute with links resolved.
pub fn input_files(spec: &Path, anim: &Animation) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for p in std::iter::once(spec.to_path_buf()).chain(super::identity::input_files(anim)) {
        let abs = std::fs::canonicalize(&p)
            .map_err(|e| input_error(&p, format!("cannot resolve: {e}")))?;
        if !files.contains(&abs) {
            files.push(abs);
        }
    }
    if let SceneSource::File(model) = &anim.scene {
        for f in Scene::external_files(model, &anim.scene_settings.allow_folder)? {
            if !files.contains(&f) {
                files.push(f);
            }
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(
        frames: impl Into<FrameSet>,
        tiles: usize,
        alignment: usize,
        jobs: usize,
        by: By,
    ) -> PlanRequest {
        PlanRequest {
            frames: frames.into(),
            tiles,
            alignment,
            jobs,
            by,
        }
    }

    /// Every (frame, tile) of the run exactly once.
    fn covers_once(r: &PlanRequest, jobs: &[Job]) {
        for f in r.frames.clone() {
            for t in 0..r.tiles {
                let n = jobs
                    .iter()
                    .filter(|j| j.frames.contains(f) && j.tiles.contains(t))
                    .count();
                assert_eq!(n, 1, "frame {f} tile {t} in {n} jobs");
            }
        }
    }

    #[test]
    fn plans_cover_every_frame_and_tile_once() {
        for by in [By::Frames, By::Tiles, By::Both] {
            for jobs in [1, 2, 3, 5, 7, 16, 100] {
                for (frames, tiles) in [(0..8, 20), (3..11, 1), (0..1, 80), (5..6, 3)] {
                    let r = req(frames, tiles, 1, jobs, by);
                    let p = plan(&r).unwrap();
                    assert!(!p.is_empty() && p.len() <= jobs);
                    covers_once(&r, &p);
                    for (k, j) in p.iter().enumerate() {
                        assert_eq!(j.index, Some(k));
                    }
                }
            }
        }
        let p = plan(&req(0..8, 20, 1, 4, By::Tiles)).unwrap();
        assert_eq!(p.len(), 4);
        assert!(
            p.iter()
                .all(|j| j.frames == FrameSet::range(0..8) && j.tiles.len() == 5)
        );
        let p = plan(&req(0..8, 20, 1, 16, By::Both)).unwrap();
        assert_eq!(p.len(), 16);
        assert_eq!(p[0].frames, FrameSet::range(0..2));
    }

    #[test]
    fn frame_ranges_start_on_the_alignment_and_tiles_are_refused() {
        let r = req(3..23, 12, 4, 3, By::Frames);
        let p = plan(&r).unwrap();
        covers_once(&r, &p);
        for j in &p[1..] {
            assert_eq!(j.frames.first().unwrap() % 4, 0, "{:?}", j.frames);
        }
        assert_eq!(p[0].frames.first(), Some(3));
        for by in [By::Tiles, By::Both] {
            let e = plan(&req(0..8, 12, 4, 3, by)).unwrap_err().to_string();
            assert!(
                e.contains("whole frames") && e.contains("--by frames"),
                "{e}"
            );
        }
        assert_eq!(default_by(4), By::Frames);
        assert_eq!(default_by(1), By::Tiles);
    }

    #[test]
    fn tile_sets_read_and_write_ranges() {
        let t: TileSet = "9,0-4, 3,12-13".parse().unwrap();
        assert_eq!(t.indices(), &[0, 1, 2, 3, 4, 9, 12, 13]);
        assert_eq!(t.to_string(), "0-4,9,12-13");
        assert!("".parse::<TileSet>().is_err());
        assert!("4-2".parse::<TileSet>().is_err());
        assert!("x".parse::<TileSet>().is_err());
        let j = Job {
            index: Some(2),
            frames: FrameSet::range(0..8),
            tiles: t.clone(),
        };
        assert_eq!(j.folder(), "f0000-0008_t0-4,9,12-13");
        // A list: its span and a hash of its text, nothing a file name could trip on.
        let list = Job {
            index: Some(2),
            frames: "1,3".parse().unwrap(),
            tiles: t,
        };
        let name = list.folder();
        assert!(
            name.starts_with("f0001-0004x") && name.ends_with("_t0-4,9,12-13"),
            "{name}"
        );
        assert_eq!(name.len(), "f0001-0004x".len() + 8 + "_t0-4,9,12-13".len());
        assert!(!name.contains(':'));
    }

    /// A frame list splits like a range: whole temporal groups per job, and with frames
    /// alone each frame its own group.
    #[test]
    fn frame_lists_split_into_whole_groups() {
        let frames: FrameSet = "1,3,5,9-12,30".parse().unwrap();
        for by in [By::Frames, By::Tiles, By::Both] {
            for jobs in [1, 2, 3, 4, 9] {
                let r = req(frames.clone(), 6, 1, jobs, by);
                covers_once(&r, &plan(&r).unwrap());
            }
        }
        // Alignment 4: groups {1,3}, {5}, {9,10,11}, {12}, {30}.
        let r = req(frames.clone(), 6, 4, 5, By::Frames);
        let p = plan(&r).unwrap();
        covers_once(&r, &p);
        let shown: Vec<String> = p.iter().map(|j| j.frames.to_string()).collect();
        assert_eq!(shown, ["1,3", "5", "9..12", "12", "30"]);
        let lines = job_lines(&p);
        assert!(lines.starts_with("0\t1,3\t0-5\tf0001-0004x"), "{lines}");
    }
}
