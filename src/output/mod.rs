//! Writing results: EXR frames with AOV layers, PNG previews, `stats.csv`, all published
//! atomically (written under a temporary name in the same folder, then renamed), so a reader
//! or a crash never sees half a file; each frame's record ([`record`]) makes the frame and its
//! `stats.csv` row one commit.

pub mod exr;
pub mod lock;
pub mod names;
pub mod png;
pub mod rate;
pub mod record;
pub mod runs;
pub mod stats;

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::error::Result;
use crate::film::{Channel, Film};
use crate::view::View;

/// The temporary name a file is written under before it is renamed into place: unique to the
/// process (its PID), the write (a counter: threads of one process may publish the same file)
/// and the moment (nanoseconds, for two hosts of a shared folder whose PIDs coincide), so two
/// writers never share one.
pub fn temp_path(path: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicU64, Ordering};
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let n = WRITES.fetch_add(1, Ordering::Relaxed);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".{}-{n}-{nanos:08x}.tmp", std::process::id()));
    path.with_file_name(name)
}

/// Whether `name` is one of [`temp_path`]'s names (`<file>.<pid>-<n>-<nanos>.tmp`, or the
/// older `<file>.<pid>.tmp`): a file only a write in progress, or one a kill interrupted,
/// leaves behind. Other names ending in `.tmp` are not ours.
pub fn is_temp_name(name: &str) -> bool {
    let Some(stem) = name.strip_suffix(".tmp") else {
        return false;
    };
    let Some((file, tag)) = stem.rsplit_once('.') else {
        return false;
    };
    let mut parts = tag.split('-');
    let pid_ok = parts
        .next()
        .is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
    let rest: Vec<&str> = parts.collect();
    let rest_ok = match rest.as_slice() {
        [] => true,
        [n, nanos] => {
            !n.is_empty()
                && n.bytes().all(|b| b.is_ascii_digit())
                && nanos.len() == 8
                && nanos.bytes().all(|b| b.is_ascii_hexdigit())
        }
        _ => false,
    };
    !file.is_empty() && pid_ok && rest_ok
}

/// Removes the temporaries an interrupted writer left in `dir` ([`is_temp_name`]); call it
/// holding the folder's lock ([`lock::FolderLock`]), when no other writer can be mid-write.
/// Its `records/` folder is cleaned too. Returns how many were removed.
pub fn remove_stale_temporaries(dir: &Path) -> Result<usize> {
    let mut removed = 0;
    let records = dir.join(record::RECORDS_DIR);
    if records.is_dir() {
        removed += remove_stale_temporaries(&records)?;
    }
    let rd = fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))?;
    for e in rd.flatten() {
        let name = e.file_name();
        if name.to_str().is_some_and(is_temp_name) && e.file_type().is_ok_and(|t| t.is_file()) {
            fs::remove_file(e.path())
                .with_context(|| format!("removing the stale {}", e.path().display()))?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Writes a file atomically with `write`, which receives the temporary path.
pub fn write_atomic_with(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let tmp = temp_path(path);
    if let Err(e) = write(&tmp) {
        let _ = fs::remove_file(&tmp);
        return Err(e.context(format!("writing {}", path.display())));
    }
    fs::rename(&tmp, path).with_context(|| {
        let _ = fs::remove_file(&tmp);
        format!("publishing {}", path.display())
    })
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |tmp| {
        let mut f = fs::File::create(tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        Ok(())
    })
}

/// How a render writes its frames: the previews' exposure and view transform, the EXR's
/// precision, the files' names, and what its header records beside each frame's own
/// [`exr::FrameHeader`].
#[derive(Clone, Debug, PartialEq)]
pub struct FrameFormat {
    pub exposure: f32,
    pub view: View,
    /// Half-float EXR channels where they suffice (`--half`).
    pub half: bool,
    /// The frames' file names (`--output-pattern`, `--frame-start`).
    pub names: names::FrameNames,
    /// How the EXR's channels are named (`--exr-layout`).
    pub layout: exr::ExrLayout,
}

/// A frame's two files: the EXR and the PNG preview, encoded at once on the current rayon
/// pool (each also parallel inside: the EXR's chunks, the preview's rows).
fn encode_files(
    film: &Film,
    header: &exr::FrameHeader,
    format: &FrameFormat,
) -> Result<[Vec<u8>; 2]> {
    let (exr, png) = rayon::join(
        || exr::encode_frame(film, header, format.half, format.layout),
        || {
            png::encode_preview(
                film.width,
                film.height,
                &film
                    .layer(Channel::BEAUTY)
                    .expect("every film holds the beauty"),
                film.plane(Channel::A),
                format.exposure,
                format.view,
            )
        },
    );
    Ok([exr?, png?])
}

/// Publishes one frame into `dir`: its PNG (`frame_NNNN.png`, or as `format.names` names it),
/// then its record (`records/frame_NNNN.json`, by the frame's index: `stats_row`, the
/// `settings` fingerprint and both files' checksums), then its EXR, whose rename commits the frame — a kill at any instant
/// leaves either the frame with its record, or a frame `--resume` renders again. Returns the
/// record.
pub fn publish_frame(
    dir: &Path,
    film: &Film,
    header: &exr::FrameHeader,
    format: &FrameFormat,
    settings: &str,
) -> Result<record::FrameRecord> {
    let frame = header.stats.frame;
    let [exr, png] = encode_files(film, header, format)?;
    let (exr_sha256, png_sha256) = rayon::join(|| record::sha256(&exr), || record::sha256(&png));
    let rec = record::FrameRecord {
        format: record::FRAME_FORMAT.into(),
        frame,
        settings: settings.into(),
        exr_bytes: exr.len() as u64,
        exr_sha256,
        png_bytes: png.len() as u64,
        png_sha256,
        stats_row: header.stats.csv_row(),
        rays_histogram: record::histogram_text(&record::count_histogram(
            film.plane(Channel::Rays).unwrap_or_default(),
        )),
        wrong_max: film.plane(Channel::Wrong).map(record::finite_max),
    };
    write_atomic(&format.names.path(dir, frame, "png"), &png)?;
    rec.write(dir)?;
    write_atomic(&format.names.path(dir, frame, "exr"), &exr)?;
    Ok(rec)
}

/// Writes one frame's files, named by `format.names`: `frame_NNNN.exr` (beauty + AOVs) and
/// `frame_NNNN.png`.
pub fn write_frame_files(
    dir: &Path,
    film: &Film,
    header: &exr::FrameHeader,
    format: &FrameFormat,
) -> Result<()> {
    let frame = header.stats.frame;
    let [exr, png] = encode_files(film, header, format)?;
    write_atomic(&format.names.path(dir, frame, "exr"), &exr)?;
    write_atomic(&format.names.path(dir, frame, "png"), &png)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// temp_path's names, this version's and the older PID-only ones, are recognised; a
    /// user's own `.tmp` files and our published files are not.
    #[test]
    fn only_our_temporary_names_count_as_stale() {
        let ours = temp_path(Path::new("/x/frame_0001.exr"));
        let ours = ours.file_name().unwrap().to_str().unwrap();
        let mut failures = Vec::new();
        for (name, want) in [
            (ours, true),
            ("lights.json.4242.tmp", true),
            ("stats.csv.17-3-0badcafe.tmp", true),
            ("frame_0001.exr", false),
            ("notes.tmp", false),
            ("scratch.draft.tmp", false),
            (".12.tmp", false),
            ("a.12-3.tmp", false),
            ("a.12-3-xyz.tmp", false),
        ] {
            if is_temp_name(name) != want {
                failures.push(format!("{name}: {}", !want));
            }
        }
        assert!(failures.is_empty(), "{failures:?}");
    }
}
