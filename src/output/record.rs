//! What a render folder's frames were made with, so a re-run can trust them and no
//! `stats.csv` row is ever lost:
//!
//! - `settings.txt`: the resolved settings, one `key = value` per line ([`SettingsRecord`]);
//!   `--resume` refuses a folder whose settings differ, naming the first difference.
//! - `records/frame_0042.json`, one per frame ([`FrameRecord`]): the frame's `stats.csv` row,
//!   the settings' fingerprint and the sizes and SHA-256 of its EXR and PNG (named by the
//!   folder's [`FrameNames`]; the record by the frame's index). It is published
//!   after the PNG and before the EXR, whose rename commits the frame: a crash at any instant
//!   leaves a frame either committed with its record, or not committed at all. `stats.csv` is
//!   rebuilt from the records, and `--resume` skips a frame only when its files match its
//!   record.

use std::io::Read;
use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::{Result, input_error};
use crate::output::names::FrameNames;

/// The settings file of a render folder.
pub const SETTINGS_FILE: &str = "settings.txt";
/// The settings record's key of the loader's warnings: `[warnings] 1 = …`, `[warnings] 2`, ….
pub const WARNINGS_KEY: &str = "[warnings]";
/// The settings record's lines of the loader's `warnings`, in order: `[warnings] 1`, ….
pub fn warning_lines(warnings: &[String]) -> impl Iterator<Item = (String, String)> + '_ {
    warnings
        .iter()
        .enumerate()
        .map(|(k, w)| (format!("{WARNINGS_KEY} {}", k + 1), w.clone()))
}

/// The folder of per-frame records inside a render folder.
pub const RECORDS_DIR: &str = "records";
/// [`FrameRecord::format`].
pub const FRAME_FORMAT: &str = "envshadow-frame 1";

/// SHA-256 of bytes, lowercase hex.
pub fn sha256(bytes: &[u8]) -> String {
    format!("{:x}", Sha256::digest(bytes))
}

/// SHA-256 of a file, lowercase hex.
pub fn file_sha256(path: &Path) -> Result<String> {
    let mut f = std::fs::File::open(path).with_context(|| format!("opening {}", path.display()))?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f
            .read(&mut buf)
            .with_context(|| format!("reading {}", path.display()))?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
    }
    Ok(format!("{:x}", h.finalize()))
}

/// The settings a folder's frames were rendered with: (key, value) pairs in a fixed order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SettingsRecord {
    pub lines: Vec<(String, String)>,
}

impl SettingsRecord {
    /// `settings.txt`'s text.
    pub fn text(&self) -> String {
        let mut s = String::from(
            "# envshadow: the settings this folder's frames were rendered with; render --resume \
             refuses other settings\n",
        );
        for (k, v) in &self.lines {
            s.push_str(k);
            s.push_str(" = ");
            s.push_str(v);
            s.push('\n');
        }
        s
    }

    /// A short hash of the settings: what each frame record names.
    pub fn fingerprint(&self) -> String {
        let mut id = sha256(self.text().as_bytes());
        id.truncate(16);
        id
    }

    /// Reads `dir/settings.txt`: `None` if there is none (a folder rendered by an older
    /// version, or never rendered). A file that is not ours is an error naming it.
    pub fn read(dir: &Path) -> Result<Option<SettingsRecord>> {
        let path = dir.join(SETTINGS_FILE);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(input_error(&path, format!("cannot read: {e}"))),
        };
        let mut lines = Vec::new();
        for (n, line) in text.lines().enumerate() {
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            let Some((k, v)) = line.split_once(" = ") else {
                return Err(input_error(
                    &path,
                    format!("line {}: expected `key = value`, found {line:?}", n + 1),
                ));
            };
            lines.push((k.to_string(), v.to_string()));
        }
        Ok(Some(SettingsRecord { lines }))
    }

    /// Publishes `dir/settings.txt`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        super::write_atomic(&dir.join(SETTINGS_FILE), self.text().as_bytes())
    }

    /// The first setting in which `self` (the folder's) and `now` (this run's) differ, as
    /// `key = old, now new`; `None` if they agree.
    pub fn first_difference(&self, now: &SettingsRecord) -> Option<String> {
        let find = |lines: &[(String, String)], key: &str| {
            lines.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone())
        };
        let keys = now
            .lines
            .iter()
            .map(|(k, _)| k)
            .chain(self.lines.iter().map(|(k, _)| k));
        for key in keys {
            let (was, is) = (find(&self.lines, key), find(&now.lines, key));
            if was != is {
                let show = |v: Option<String>| v.unwrap_or_else(|| "(not set)".into());
                return Some(format!("{key} = {}, now {}", show(was), show(is)));
            }
        }
        None
    }
}

/// `records/frame_NNNN.json`: one committed frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    pub format: String,
    pub frame: usize,
    /// [`SettingsRecord::fingerprint`] of the settings that rendered it.
    pub settings: String,
    pub exr_bytes: u64,
    pub exr_sha256: String,
    pub png_bytes: u64,
    pub png_sha256: String,
    /// The frame's `stats.csv` row.
    pub stats_row: String,
    /// The frame's rays per pixel ([`count_histogram`] of its `shadow.rays` channel) as
    /// `rays:pixels` pairs of the non-empty bins, for the report's colour scale without
    /// decoding the EXR ([`histogram_text`]); empty in records of earlier versions.
    #[serde(default)]
    pub rays_histogram: String,
    /// With validation, the most wrong pairs of any pixel (its `shadow.wrong` channel).
    #[serde(default)]
    pub wrong_max: Option<f32>,
}

/// Histogram of a count channel (non-negative whole numbers, such as the rays per pixel):
/// bin k counts the values that round to k (at most 2^20; NaN and negative values are left out).
pub fn count_histogram(values: &[f32]) -> Vec<u64> {
    const MAX_BIN: usize = 1 << 20;
    let mut hist = Vec::new();
    for &v in values {
        if v.is_finite() && v >= 0.0 {
            let b = (v.round() as usize).min(MAX_BIN);
            if b >= hist.len() {
                hist.resize(b + 1, 0);
            }
            hist[b] += 1;
        }
    }
    hist
}

/// The largest finite value of a channel (0 if none).
pub fn finite_max(values: &[f32]) -> f32 {
    values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f32::max)
}

/// A histogram as `bin:count` pairs of its non-empty bins, space-separated.
pub fn histogram_text(hist: &[u64]) -> String {
    let pairs: Vec<String> = hist
        .iter()
        .enumerate()
        .filter(|(_, c)| **c > 0)
        .map(|(b, c)| format!("{b}:{c}"))
        .collect();
    pairs.join(" ")
}

/// [`histogram_text`] read back; `None` if the text is not one (or has a bin beyond 2^20).
pub fn parse_histogram(text: &str) -> Option<Vec<u64>> {
    let mut hist = Vec::new();
    for pair in text.split_whitespace() {
        let (b, c) = pair.split_once(':')?;
        let (b, c): (usize, u64) = (b.parse().ok()?, c.parse().ok()?);
        if b > 1 << 20 {
            return None;
        }
        if b >= hist.len() {
            hist.resize(b + 1, 0);
        }
        hist[b] += c;
    }
    Some(hist)
}

impl FrameRecord {
    /// `dir/records/frame_0042.json`.
    pub fn path(dir: &Path, frame: usize) -> PathBuf {
        dir.join(RECORDS_DIR).join(format!("frame_{frame:04}.json"))
    }

    /// The record of `frame` in `dir`, if there is a readable one of this format.
    pub fn read(dir: &Path, frame: usize) -> Option<FrameRecord> {
        let text = std::fs::read_to_string(Self::path(dir, frame)).ok()?;
        let r: FrameRecord = serde_json::from_str(&text).ok()?;
        (r.format == FRAME_FORMAT && r.frame == frame).then_some(r)
    }

    /// Every readable record in `dir`, by frame.
    pub fn read_all(dir: &Path) -> Vec<FrameRecord> {
        let Ok(rd) = std::fs::read_dir(dir.join(RECORDS_DIR)) else {
            return Vec::new();
        };
        let mut v: Vec<FrameRecord> = rd
            .flatten()
            .filter_map(|e| {
                let name = e.file_name();
                let n = name
                    .to_str()?
                    .strip_prefix("frame_")?
                    .strip_suffix(".json")?;
                Self::read(dir, n.parse().ok()?)
            })
            .collect();
        v.sort_by_key(|r| r.frame);
        v
    }

    /// Publishes the record (creating `records/`).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let path = Self::path(dir, self.frame);
        let parent = dir.join(RECORDS_DIR);
        std::fs::create_dir_all(&parent)
            .with_context(|| format!("creating {}", parent.display()))?;
        let json = serde_json::to_string_pretty(self).context("encoding the frame record")?;
        super::write_atomic(&path, json.as_bytes())
    }

    /// Whether the frame's EXR and PNG (named by `names`) have the recorded sizes (cheap: no
    /// reading).
    pub fn sizes_match(&self, dir: &Path, names: &FrameNames) -> bool {
        let len = |ext| std::fs::metadata(names.path(dir, self.frame, ext)).map(|m| m.len());
        len("exr").is_ok_and(|n| n == self.exr_bytes)
            && len("png").is_ok_and(|n| n == self.png_bytes)
    }

    /// Whether the frame's EXR and PNG (named by `names`) are the very files recorded (sizes
    /// and SHA-256).
    pub fn files_match(&self, dir: &Path, names: &FrameNames) -> bool {
        let sum = |ext| file_sha256(&names.path(dir, self.frame, ext)).ok();
        self.sizes_match(dir, names)
            && sum("exr").is_some_and(|s| s == self.exr_sha256)
            && sum("png").is_some_and(|s| s == self.png_sha256)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histograms_read_back_from_their_text() {
        let values = [0.0, 0.0, 3.0, 2.6, f32::NAN, -1.0, 40.0, f32::INFINITY];
        let hist = count_histogram(&values);
        assert_eq!(hist.len(), 41);
        assert_eq!((hist[0], hist[3], hist[40]), (2, 2, 1));
        let text = histogram_text(&hist);
        assert_eq!(text, "0:2 3:2 40:1");
        assert_eq!(parse_histogram(&text), Some(hist));
        assert_eq!(parse_histogram(""), Some(vec![]));
        for bad in ["0:2 x", "3", "1:-2", "2000000:1"] {
            assert_eq!(parse_histogram(bad), None, "{bad}");
        }
        assert_eq!(finite_max(&values), 40.0);
    }

    fn record(pairs: &[(&str, &str)]) -> SettingsRecord {
        SettingsRecord {
            lines: pairs
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
        }
    }

    #[test]
    fn settings_read_back_and_name_their_first_difference() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(SettingsRecord::read(dir.path()).unwrap(), None);
        let old = record(&[("[render] width", "160"), ("[render] method", "a = b")]);
        old.write(dir.path()).unwrap();
        let back = SettingsRecord::read(dir.path()).unwrap().unwrap();
        assert_eq!(back, old);
        assert_eq!(back.fingerprint(), old.fingerprint());
        assert_eq!(back.first_difference(&old), None);
        let now = record(&[("[render] width", "320"), ("[render] method", "a = b")]);
        assert_eq!(
            old.first_difference(&now).as_deref(),
            Some("[render] width = 160, now 320")
        );
        assert_ne!(old.fingerprint(), now.fingerprint());
        let more = record(&[("[render] width", "160"), ("[render] spp", "4")]);
        assert_eq!(
            old.first_difference(&more).as_deref(),
            Some("[render] spp = (not set), now 4")
        );
        std::fs::write(dir.path().join(SETTINGS_FILE), "width: 3\n").unwrap();
        let err = SettingsRecord::read(dir.path()).unwrap_err().to_string();
        assert!(
            err.contains("settings.txt") && err.contains("line 1"),
            "{err}"
        );
    }
}
