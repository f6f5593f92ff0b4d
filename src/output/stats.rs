//! Ray-savings statistics: counts per tile and frame, and `stats.csv` (one row per frame).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use glam::Vec3;

use crate::error::{Result, input_error};
use crate::film::{Counts, ImageError};

/// One frame's row of `stats.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameStats {
    pub frame: usize,
    pub method: String,
    pub lights: usize,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel: the counts are per (sample, light) query.
    pub spp: u32,
    pub counts: Counts,
    /// With validation: the image against brute force.
    pub image_error: Option<ImageError>,
    /// The frame's own compute time: seconds the worker threads spent on it — its tiles and
    /// shared passes, and its serial set-up and assembly (posing, BVH, previous frame,
    /// film, validation) — summed over the threads. Frames in flight together do not count
    /// each other's work, so a run's frames add up to at most its threads × its wall time
    /// (the run's wall time is in `runs.csv`). File writing is not included.
    pub thread_seconds: f64,
    pub camera_position: Vec3,
    pub camera_target: Vec3,
    pub camera_up: Vec3,
    pub vfov_deg: f32,
}

/// The header of `stats.csv`.
pub const HEADER: &str = "frame,method,lights,width,height,queries,rays_traced,percent_traced,\
halo_pixels,halo_rays,thread_seconds,wrong_visible,wrong_blocked,error_percent,wrong_pixels,rmse,rel_rmse,\
psnr_db,camera_x,camera_y,camera_z,target_x,target_y,target_z,up_x,up_y,up_z,vfov_deg,\
temporal_pixels,temporal_rays,spatial_rays,rays_every_light,rays_unsure,rays_flooded,flood_fixes,spp";

impl FrameStats {
    /// The CSV row (no newline), columns as in [`HEADER`]. Validation columns are empty for
    /// frames rendered without `--validate`.
    pub fn csv_row(&self) -> String {
        let mut s = String::new();
        let c = &self.counts;
        let (p, t, u) = (self.camera_position, self.camera_target, self.camera_up);
        let _ = write!(
            s,
            "{},{},{},{},{},{},{},{:.4},{},{},{:.4},",
            self.frame,
            self.method,
            self.lights,
            self.width,
            self.height,
            c.queries,
            c.rays,
            c.percent_traced(),
            c.halo_pixels,
            c.halo_rays,
            self.thread_seconds,
        );
        match &self.image_error {
            Some(e) => {
                let _ = write!(
                    s,
                    "{},{},{:.6},{},{:.6e},{:.6e},{:.3},",
                    c.wrong_visible,
                    c.wrong_blocked,
                    c.error_percent(),
                    c.wrong_pixels,
                    e.rmse,
                    e.rel_rmse,
                    e.psnr_db
                );
            }
            None => s.push_str(",,,,,,,"),
        }
        let _ = write!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            p.x,
            p.y,
            p.z,
            t.x,
            t.y,
            t.z,
            u.x,
            u.y,
            u.z,
            self.vfov_deg,
            c.temporal_pixels,
            c.temporal_rays,
            c.rays - c.temporal_rays,
            c.rays_every_light,
            c.rays_unsure(),
            c.rays_flooded,
            c.flood_fixes,
            self.spp
        );
        s
    }
}

/// `stats.csv` in an output folder: rows keyed by frame, so a partial or resumed run replaces
/// the rows of the frames it rendered and keeps the others.
pub struct StatsFile {
    rows: BTreeMap<usize, String>,
}

impl StatsFile {
    /// Reads the rows already in `path` (none if it does not exist or has another header:
    /// rows with other columns are not ours to keep).
    pub fn open(path: &Path) -> StatsFile {
        let mut rows = BTreeMap::new();
        if let Ok(text) = std::fs::read_to_string(path) {
            let mut lines = text.lines();
            if lines.next() == Some(HEADER) {
                for line in lines {
                    if let Some(frame) = line.split(',').next().and_then(|f| f.parse().ok()) {
                        rows.insert(frame, line.to_string());
                    }
                }
            }
        }
        StatsFile { rows }
    }

    pub fn set(&mut self, stats: &FrameStats) {
        self.rows.insert(stats.frame, stats.csv_row());
    }

    /// `frame`'s row, if there is one.
    pub fn row(&self, frame: usize) -> Option<&String> {
        self.rows.get(&frame)
    }

    /// Sets `frame`'s row from its text (a frame record's copy of it).
    pub fn set_row(&mut self, frame: usize, row: &str) {
        self.rows.insert(frame, row.to_string());
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Writes all rows, sorted by frame, atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut text = String::with_capacity(64 * (self.rows.len() + 1));
        text.push_str(HEADER);
        text.push('\n');
        for row in self.rows.values() {
            text.push_str(row);
            text.push('\n');
        }
        super::write_atomic(path, text.as_bytes())
    }
}

/// The columns a `stats.csv` written before the ray split existed lacks; read as 0.
const SPLIT_COLUMNS: [&str; 4] = [
    "rays_every_light",
    "rays_unsure",
    "rays_flooded",
    "flood_fixes",
];

/// The column a `stats.csv` written before samples per pixel lacks; read as 1.
const SPP_COLUMN: &str = "spp";

/// The time column, and what a `stats.csv` written before issue 23 had instead: each frame's
/// wall-clock seconds, which overlapped while two frames were in flight (read as it is).
const TIME_COLUMN: &str = "thread_seconds";
const OLD_TIME_COLUMN: &str = "seconds";

/// Reads `stats.csv`: one [`FrameStats`] per row, sorted by frame, columns found by their
/// header names (the derived ones — percent traced, error percent, spatial and unsure rays —
/// are recomputed from the counts). Every reader of `stats.csv` reads it through this.
/// A missing or malformed file is an input error naming it (and the line).
pub fn read_stats(path: &Path) -> Result<Vec<FrameStats>> {
    let text = read_text(path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    check_header(path, &header)?;
    let mut rows = Vec::new();
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let line_no = n + 2;
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != header.len() {
            return Err(input_error(
                path,
                format!(
                    "line {line_no}: {} fields, expected {}",
                    fields.len(),
                    header.len()
                ),
            ));
        }
        let row = Row {
            path,
            line_no,
            header: &header,
            fields,
        };
        rows.push(row.frame_stats()?);
    }
    rows.sort_by_key(|r| r.frame);
    Ok(rows)
}

/// The text of `stats.csv`; a missing file says it is no render output folder.
fn read_text(path: &Path) -> Result<String> {
    match std::fs::read_to_string(path) {
        Ok(t) => Ok(t),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(input_error(
            path,
            "not found: not a render output folder (envshadow render writes stats.csv)",
        )),
        Err(e) => Err(input_error(path, format!("cannot read: {e}"))),
    }
}

/// Every column of [`HEADER`] is in `header`, but those older files lack (the split columns,
/// `spp`, and `thread_seconds` where the old time column stands).
fn check_header(path: &Path, header: &[&str]) -> Result<()> {
    for name in HEADER.split(',') {
        let old_time = name == TIME_COLUMN && header.contains(&OLD_TIME_COLUMN);
        if !header.contains(&name)
            && !SPLIT_COLUMNS.contains(&name)
            && name != SPP_COLUMN
            && !old_time
        {
            return Err(input_error(
                path,
                format!("no column {name:?} in the header"),
            ));
        }
    }
    Ok(())
}

/// One row of `stats.csv`, its cells read by column name.
struct Row<'a> {
    path: &'a Path,
    /// Its line in the file, from 1 (the header is line 1).
    line_no: usize,
    header: &'a [&'a str],
    fields: Vec<&'a str>,
}

impl Row<'_> {
    /// The cell of column `name`, trimmed; None for a missing column or an empty cell.
    fn cell(&self, name: &str) -> Option<&str> {
        let k = self.header.iter().position(|h| *h == name)?;
        Some(self.fields[k].trim()).filter(|s| !s.is_empty())
    }

    /// The error for cell `s` of column `name`, which is not a number.
    fn bad(&self, name: &str, s: &str) -> anyhow::Error {
        input_error(
            self.path,
            format!("line {}: {name} {s:?} is not a number", self.line_no),
        )
    }

    /// A number that must be there.
    fn need(&self, name: &str) -> Result<f64> {
        let s = self.cell(name).unwrap_or("");
        s.parse().map_err(|_| self.bad(name, s))
    }

    /// A count; 0 where an older file lacks the column (or leaves a split column empty).
    fn count(&self, name: &str) -> Result<u64> {
        match self.cell(name) {
            None if SPLIT_COLUMNS.contains(&name) || !self.header.contains(&name) => Ok(0),
            s => {
                let s = s.unwrap_or("");
                s.parse().map_err(|_| self.bad(name, s))
            }
        }
    }

    /// A number that may be left empty (the validation columns).
    fn optional(&self, name: &str) -> Result<Option<f64>> {
        match self.cell(name) {
            None => Ok(None),
            Some(s) => s.parse().map(Some).map_err(|_| self.bad(name, s)),
        }
    }

    /// A vector from three number columns.
    fn v3(&self, x: &str, y: &str, z: &str) -> Result<Vec3> {
        Ok(Vec3::new(
            self.need(x)? as f32,
            self.need(y)? as f32,
            self.need(z)? as f32,
        ))
    }

    /// The frame's counts; the validation counts 0 for a frame rendered without `--validate`.
    fn counts(&self) -> Result<Counts> {
        let validated = self.cell("wrong_visible").is_some();
        let count = |name: &str| self.count(name);
        Ok(Counts {
            queries: count("queries")?,
            rays: count("rays_traced")?,
            halo_pixels: count("halo_pixels")?,
            halo_rays: count("halo_rays")?,
            wrong_visible: if validated {
                count("wrong_visible")?
            } else {
                0
            },
            wrong_blocked: if validated {
                count("wrong_blocked")?
            } else {
                0
            },
            wrong_pixels: if validated { count("wrong_pixels")? } else { 0 },
            wrong_traced: 0,
            temporal_pixels: count("temporal_pixels")?,
            temporal_rays: count("temporal_rays")?,
            temporal_stale: 0,
            rays_every_light: count("rays_every_light")?,
            rays_flooded: count("rays_flooded")?,
            flood_fixes: count("flood_fixes")?,
        })
    }

    /// The image against brute force, when the row has all three measures.
    fn image_error(&self) -> Result<Option<ImageError>> {
        Ok(
            match (
                self.optional("rmse")?,
                self.optional("rel_rmse")?,
                self.optional("psnr_db")?,
            ) {
                (Some(rmse), Some(rel_rmse), Some(psnr_db)) => Some(ImageError {
                    rmse,
                    rel_rmse,
                    psnr_db,
                }),
                _ => None,
            },
        )
    }

    /// The row as a [`FrameStats`] (a bad cell is an error naming its column and line).
    fn frame_stats(&self) -> Result<FrameStats> {
        let counts = self.counts()?;
        let image_error = self.image_error()?;
        Ok(FrameStats {
            frame: self.count("frame")? as usize,
            method: self.cell("method").unwrap_or_default().to_string(),
            lights: self.count("lights")? as usize,
            width: self.count("width")? as u32,
            height: self.count("height")? as u32,
            spp: if self.header.contains(&SPP_COLUMN) {
                self.count(SPP_COLUMN)? as u32
            } else {
                1
            },
            counts,
            image_error,
            thread_seconds: if self.header.contains(&TIME_COLUMN) {
                self.need(TIME_COLUMN)?
            } else {
                self.need(OLD_TIME_COLUMN)?
            },
            camera_position: self.v3("camera_x", "camera_y", "camera_z")?,
            camera_target: self.v3("target_x", "target_y", "target_z")?,
            camera_up: self.v3("up_x", "up_y", "up_z")?,
            vfov_deg: self.need("vfov_deg")? as f32,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats(frame: usize, validated: bool) -> FrameStats {
        FrameStats {
            frame,
            method: "grid-nowarp-uncertainty".into(),
            lights: 200,
            width: 64,
            height: 48,
            spp: 4,
            counts: Counts {
                queries: 1000,
                rays: 120,
                halo_pixels: 7,
                halo_rays: 30,
                wrong_visible: u64::from(validated) * 3,
                wrong_blocked: u64::from(validated) * 2,
                wrong_pixels: u64::from(validated),
                wrong_traced: 0,
                temporal_pixels: 11,
                temporal_rays: 40,
                temporal_stale: 0,
                rays_every_light: 50,
                rays_flooded: 20,
                flood_fixes: 4,
            },
            image_error: validated.then_some(ImageError {
                rmse: 0.5,
                rel_rmse: 0.25,
                psnr_db: 40.0,
            }),
            thread_seconds: 1.5,
            camera_position: Vec3::new(1.0, 2.5, -3.0),
            camera_target: Vec3::new(0.0, 0.075, 0.0),
            camera_up: Vec3::Y,
            vfov_deg: 40.0,
        }
    }

    #[test]
    fn rows_written_are_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stats.csv");
        let mut file = StatsFile::open(&path);
        let (a, b) = (stats(3, true), stats(1, false));
        file.set(&a);
        file.set(&b);
        file.write(&path).unwrap();
        assert_eq!(read_stats(&path).unwrap(), vec![b, a]);
    }

    #[test]
    fn a_malformed_row_names_the_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stats.csv");
        let mut text = format!("{HEADER}\n{}\n", stats(0, false).csv_row());
        text.push_str(&stats(1, false).csv_row().replacen("1,", "x,", 1));
        std::fs::write(&path, text).unwrap();
        let err = read_stats(&path).unwrap_err().to_string();
        assert!(err.contains("stats.csv: line 3: frame \"x\""), "{err}");
        std::fs::write(&path, "frame,method\n").unwrap();
        let err = read_stats(&path).unwrap_err().to_string();
        assert!(err.contains("no column \"lights\""), "{err}");
    }
}
