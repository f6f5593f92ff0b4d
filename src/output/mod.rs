//! Writing results: EXR frames with AOV layers, PNG previews, `stats.csv`, all published
//! atomically (written under a temporary name in the same folder, then renamed), so a reader
//! or a crash never sees half a file.

pub mod exr;
pub mod lock;
pub mod png;
pub mod stats;

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::error::Result;
use crate::film::Film;

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

/// `DIR/frame_0042.ext`.
pub fn frame_path(dir: &Path, frame: usize, ext: &str) -> PathBuf {
    dir.join(format!("frame_{frame:04}.{ext}"))
}

/// Writes one frame's files: `frame_NNNN.exr` (beauty + AOVs) and `frame_NNNN.png`.
pub fn write_frame_files(dir: &Path, frame: usize, film: &Film, exposure: f32) -> Result<()> {
    let mut aovs = Vec::new();
    if let Some(wrong) = &film.wrong {
        aovs.push(exr::Aov {
            name: "wrong",
            values: wrong,
        });
    }
    if let Some(coverage) = &film.coverage {
        aovs.push(exr::Aov {
            name: "coverage",
            values: coverage,
        });
    }
    exr::write_frame(&frame_path(dir, frame, "exr"), film, &aovs)?;
    png::write_preview(
        &frame_path(dir, frame, "png"),
        film.width,
        film.height,
        &film.beauty,
        exposure,
    )
}
