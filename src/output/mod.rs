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

use crate::error::{Result, escaped_path};
use crate::film::{Channel, Film};
use crate::view::View;

/// The mark every temporary name of ours carries (`<file>.envshadow-<pid>-<n>-<nanos>.tmp`),
/// so that cleaning a folder never takes a user's own `.tmp` files
/// (`thesis.docx.4242-1-deadbeef.tmp` looked like one of ours before the mark).
const TEMP_TAG: &str = ".envshadow-";

/// The temporary name a file is written under before it is renamed into place: marked as
/// ours ([`TEMP_TAG`]) and unique to the process (its PID), the write (a counter: threads of
/// one process may publish the same file) and the moment (nanoseconds, for two hosts of a
/// shared folder whose PIDs coincide), so two writers never share one.
pub fn temp_path(path: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicU64, Ordering};
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let n = WRITES.fetch_add(1, Ordering::Relaxed);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(
        "{TEMP_TAG}{}-{n}-{nanos:08x}.tmp",
        std::process::id()
    ));
    path.with_file_name(name)
}

/// Whether `name` is one of [`temp_path`]'s names, `<file>.envshadow-<pid>-<n>-<nanos>.tmp`
/// exactly: a file only a write in progress, or one a kill interrupted, leaves behind. Other
/// names ending in `.tmp` are not ours.
pub fn is_temp_name(name: &str) -> bool {
    let Some(stem) = name.strip_suffix(".tmp") else {
        return false;
    };
    let Some((file, tag)) = stem.rsplit_once(TEMP_TAG) else {
        return false;
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    match tag.split('-').collect::<Vec<_>>().as_slice() {
        [pid, n, nanos] => {
            !file.is_empty()
                && digits(pid)
                && digits(n)
                && nanos.len() == 8
                && nanos.bytes().all(|b| b.is_ascii_hexdigit())
        }
        _ => false,
    }
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

/// What a file that is neither regular, a link nor a folder is (FIFOs, devices and sockets
/// are Unix's; elsewhere it is only "not a regular file").
#[cfg(unix)]
fn special_kind(ft: fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_fifo() {
        "a FIFO"
    } else if ft.is_char_device() || ft.is_block_device() {
        "a device node"
    } else if ft.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: fs::FileType) -> &'static str {
    "not a regular file"
}

/// Refuses to publish over `path` when something other than a regular file stands there (a
/// device node, a FIFO, a symbolic link, a folder): renaming over it would replace it — run as
/// root, `--json /dev/null` would replace the system's `/dev/null` — and a link would be
/// replaced, not followed. An [`crate::error::InputError`] naming the path (exit code 2).
pub fn check_replaceable(path: &Path) -> Result<()> {
    let Ok(meta) = fs::symlink_metadata(path) else {
        return Ok(());
    };
    let ft = meta.file_type();
    if ft.is_file() {
        return Ok(());
    }
    let kind = if ft.is_symlink() {
        "a symbolic link"
    } else if ft.is_dir() {
        "a folder"
    } else {
        special_kind(ft)
    };
    Err(crate::error::input_error(
        path,
        format!(
            "the output path is {kind}; refusing to replace it (name a regular file or a new path)"
        ),
    ))
}

/// Writes a file atomically with `write`, which receives the temporary path. The target is
/// checked with [`check_replaceable`] before writing and again just before the rename.
pub fn write_atomic_with(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    check_replaceable(path)?;
    let tmp = temp_path(path);
    if let Err(e) = write(&tmp) {
        let _ = fs::remove_file(&tmp);
        return Err(e.context(format!("writing {}", escaped_path(path))));
    }
    if let Err(e) = check_replaceable(path) {
        let _ = fs::remove_file(&tmp);
        return Err(e);
    }
    fs::rename(&tmp, path).with_context(|| {
        let _ = fs::remove_file(&tmp);
        format!("publishing {}", escaped_path(path))
    })
}

/// Writes `bytes` to `path` atomically. The temporary is created new (never opened through
/// something already at its name).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |tmp| {
        let mut f = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(tmp)?;
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

/// Creates a render's output folder (and those above it). A file standing where the folder
/// or one above it should be is an input error naming it (exit 2), not the system's "File
/// exists" (exit 1).
pub fn create_output_dir(dir: &Path) -> Result<()> {
    for above in dir.ancestors().filter(|a| !a.as_os_str().is_empty()) {
        match fs::metadata(above) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(crate::error::input_error(
                    above,
                    format!(
                        "is a file, not a folder: the output folder {} cannot be made there; \
                         choose another --out",
                        crate::error::escaped_path(dir)
                    ),
                ));
            }
            Err(_) => continue,
        }
    }
    fs::create_dir_all(dir).with_context(|| format!("creating output folder {}", dir.display()))
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
    use std::os::unix::fs::FileTypeExt;

    /// temp_path's names are recognised; a user's own `.tmp` files (issue 39: even those
    /// shaped like our older, unmarked names) and our published files are not.
    #[test]
    fn only_our_temporary_names_count_as_stale() {
        let ours = temp_path(Path::new("/x/frame_0001.exr"));
        let ours = ours.file_name().unwrap().to_str().unwrap();
        let mut failures = Vec::new();
        for (name, want) in [
            (ours, true),
            ("stats.csv.envshadow-17-3-0badcafe.tmp", true),
            ("thesis.docx.4242-1-deadbeef.tmp", false),
            ("x.123.tmp", false),
            ("lights.json.4242.tmp", false),
            ("frame_0001.exr", false),
            ("notes.tmp", false),
            ("scratch.draft.tmp", false),
            (".envshadow-12-3-0badcafe.tmp", false),
            ("a.envshadow-12-3.tmp", false),
            ("a.envshadow-12-3-xyz.tmp", false),
            ("a.envshadow-12-3-0badcafe-1.tmp", false),
        ] {
            if is_temp_name(name) != want {
                failures.push(format!("{name}: {}", !want));
            }
        }
        assert!(failures.is_empty(), "{failures:?}");
    }

    /// Issue 39: a FIFO, a symbolic link and a folder at an output path are refused, named,
    /// and left as they were; a regular file is replaced.
    #[test]
    fn publishing_refuses_to_replace_what_is_not_a_regular_file() {
        let dir = tempfile::tempdir().unwrap();
        let outside = dir.path().join("outside.txt");
        fs::write(&outside, b"keep").unwrap();
        let link = dir.path().join("link.json");
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        let folder = dir.path().join("folder.json");
        fs::create_dir(&folder).unwrap();
        let fifo = dir.path().join("fifo.json");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
        for target in [&link, &folder, &fifo] {
            let err = write_atomic(target, b"new").unwrap_err();
            assert_eq!(crate::error::exit_code(&err), crate::error::exit::BAD_INPUT);
            assert!(
                err.to_string().contains(&target.display().to_string()),
                "{err}"
            );
        }
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
        assert!(folder.is_dir());
        assert_eq!(fs::read(&outside).unwrap(), b"keep");
        let regular = dir.path().join("plain.json");
        fs::write(&regular, b"old").unwrap();
        write_atomic(&regular, b"new").unwrap();
        assert_eq!(fs::read(&regular).unwrap(), b"new");
        let left: Vec<_> = fs::read_dir(dir.path()).unwrap().flatten().collect();
        assert_eq!(left.len(), 5, "a temporary was left: {left:?}");
    }
}
