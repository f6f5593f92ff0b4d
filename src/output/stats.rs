//! Ray-savings statistics: counts per tile and frame, and `stats.csv` (one row per frame).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use glam::Vec3;

use crate::error::Result;
use crate::film::{Counts, ImageError};

/// One frame's row of `stats.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameStats {
    pub frame: usize,
    pub method: String,
    pub lights: usize,
    pub width: u32,
    pub height: u32,
    pub counts: Counts,
    /// With validation: the image against brute force.
    pub image_error: Option<ImageError>,
    /// Wall-clock seconds to render the frame (scene setup, BVH, tiles, validation traces;
    /// not file writing).
    pub seconds: f64,
    pub camera_position: Vec3,
    pub camera_target: Vec3,
    pub camera_up: Vec3,
    pub vfov_deg: f32,
}

/// The header of `stats.csv`.
pub const HEADER: &str = "frame,method,lights,width,height,queries,rays_traced,percent_traced,\
halo_pixels,halo_rays,seconds,wrong_visible,wrong_blocked,error_percent,wrong_pixels,rmse,rel_rmse,\
psnr_db,camera_x,camera_y,camera_z,target_x,target_y,target_z,up_x,up_y,up_z,vfov_deg,\
temporal_pixels,temporal_rays,spatial_rays,rays_every_light,rays_unsure,rays_flooded,flood_fixes";

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
            self.seconds,
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
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
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
            c.flood_fixes
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
