//! One writer per output folder (issue 20): a render holds an advisory lock on the folder
//! itself — `flock` on the directory's descriptor, through `std::fs::File::try_lock` — from
//! before it writes `lights.json` until its last frame and `stats.csv` are published. A second
//! render into the same folder is refused with the holder's PID, or waits behind it (`--wait`;
//! farm jobs always wait, so two attempts of one job run one after the other). Locking the
//! folder rather than a file in it leaves nothing behind: the folder holds only what the
//! render wrote, and the lock ends with the process, however it ends.
//!
//! Windows cannot open a folder as a file to lock it (`File::open` on a folder is refused), so
//! there the lock is `LockFileEx` (the same `try_lock`) on [`LOCK_FILE`] in the folder: an
//! empty file left behind, the lock still ending with the process.

use std::fs::{File, TryLockError};
use std::path::Path;

use anyhow::Context;

use crate::error::{Result, input_error};

/// On Windows, the file in an output folder that carries its lock.
#[cfg(not(unix))]
pub const LOCK_FILE: &str = ".envshadow-lock";

/// The lock on one output folder, released when dropped (or when the process ends).
#[derive(Debug)]
pub struct FolderLock {
    _dir: Option<File>,
}

impl FolderLock {
    /// Locks the existing folder `dir` for writing. When another process holds it: with
    /// `wait`, blocks until it is released; without, fails with a message naming the holder.
    /// A filesystem that cannot lock a folder (some network mounts) gives no lock rather
    /// than an error: renders there are as before, one writer by convention.
    pub fn acquire(dir: &Path, wait: bool) -> Result<FolderLock> {
        let f =
            lock_handle(dir).with_context(|| format!("opening {} to lock it", dir.display()))?;
        match f.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) if wait => f
                .lock()
                .with_context(|| format!("waiting for the lock on {}", dir.display()))?,
            Err(TryLockError::WouldBlock) => {
                let who = match holder(dir) {
                    Some(pid) => format!("another render (PID {pid})"),
                    None => "another render".to_string(),
                };
                return Err(input_error(
                    dir,
                    format!(
                        "this output folder is being written by {who}; wait for it to finish, choose another folder with --out, or pass --wait to start when it is free"
                    ),
                ));
            }
            Err(TryLockError::Error(e)) if unsupported(&e) => return Ok(FolderLock { _dir: None }),
            Err(TryLockError::Error(e)) => {
                return Err(anyhow::Error::new(e).context(format!("locking {}", dir.display())));
            }
        }
        Ok(FolderLock { _dir: Some(f) })
    }
}

/// What the lock is taken on: the folder itself.
#[cfg(unix)]
fn lock_handle(dir: &Path) -> std::io::Result<File> {
    File::open(dir)
}

/// What the lock is taken on: [`LOCK_FILE`] in the folder, made if missing.
#[cfg(not(unix))]
fn lock_handle(dir: &Path) -> std::io::Result<File> {
    std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(dir.join(LOCK_FILE))
}

/// Errors that mean "this filesystem does not lock folders", not "something is wrong".
fn unsupported(e: &std::io::Error) -> bool {
    // EBADF (9): flock on a directory over some NFS versions.
    let ebadf = cfg!(unix) && e.raw_os_error() == Some(9);
    matches!(
        e.kind(),
        std::io::ErrorKind::Unsupported | std::io::ErrorKind::InvalidInput
    ) || ebadf
}

/// The PID holding a `flock` on `dir`, from Linux's `/proc/locks` (None elsewhere, or when it
/// cannot be told: a lock held from another host of a shared filesystem is not listed).
fn holder(dir: &Path) -> Option<u32> {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::MetadataExt;
        let meta = std::fs::metadata(dir).ok()?;
        let dev = meta.dev();
        // glibc's gnu_dev_major / gnu_dev_minor.
        let major = ((dev >> 8) & 0xfff) | ((dev >> 32) & !0xfff);
        let minor = (dev & 0xff) | ((dev >> 12) & !0xff);
        let id = format!("{major:02x}:{minor:02x}:{}", meta.ino());
        let locks = std::fs::read_to_string("/proc/locks").ok()?;
        // "1: FLOCK  ADVISORY  WRITE 12345 00:2a:1234 0 EOF"
        locks.lines().find_map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            (f.get(1) == Some(&"FLOCK") && f.get(5) == Some(&id.as_str()))
                .then(|| f.get(4)?.parse().ok())
                .flatten()
        })
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = dir;
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second lock on a locked folder is refused naming the holder — this process, here —
    /// and granted once the first is dropped.
    #[test]
    fn a_locked_folder_refuses_a_second_writer_until_released() {
        let tmp = tempfile::tempdir().unwrap();
        let first = FolderLock::acquire(tmp.path(), false).unwrap();
        assert!(first._dir.is_some(), "tmpfs and ext4 lock folders");
        let err = FolderLock::acquire(tmp.path(), false).unwrap_err();
        let msg = format!("{err:#}");
        assert!(
            msg.contains(&format!("PID {}", std::process::id())),
            "holder not named: {msg}"
        );
        assert!(msg.contains("--wait"), "{msg}");
        drop(first);
        FolderLock::acquire(tmp.path(), false).unwrap();
    }
}
