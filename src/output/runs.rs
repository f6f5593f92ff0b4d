//! `records/runs.csv`: one row per render run into a folder — when it started, its threads,
//! the frames it rendered and skipped, its wall time, its frames' thread-seconds (stats.csv's
//! `thread_seconds`, summed), its queries and the rays it traced — so the rate a user saw (rays
//! per second of wall time) and the cost of the frames (thread-seconds) are both on record.
//! A resumed folder gains a row per run; the farm's assembled folders have none (their jobs
//! ran on many hosts).

use std::path::{Path, PathBuf};

use crate::error::{Result, input_error};

/// The file, under the folder's records.
pub fn path(dir: &Path) -> PathBuf {
    dir.join(super::record::RECORDS_DIR).join("runs.csv")
}

/// The header of `runs.csv`.
pub const HEADER: &str = "started_unix,threads,frames_rendered,frames_skipped,wall_seconds,thread_seconds,queries,rays_traced";

/// One run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunRecord {
    /// When it started, Unix seconds.
    pub started_unix: u64,
    pub threads: usize,
    pub frames_rendered: usize,
    pub frames_skipped: usize,
    pub wall_seconds: f64,
    /// The thread-seconds of the frames it rendered (warm-up frames of `--temporal` included).
    pub thread_seconds: f64,
    pub queries: u64,
    /// Every shadow ray traced, tiles' halos included.
    pub rays_traced: u64,
}

impl RunRecord {
    fn row(&self) -> String {
        format!(
            "{},{},{},{},{:.4},{:.4},{},{}",
            self.started_unix,
            self.threads,
            self.frames_rendered,
            self.frames_skipped,
            self.wall_seconds,
            self.thread_seconds,
            self.queries,
            self.rays_traced
        )
    }

    /// Appends this run to `dir`'s `records/runs.csv` (a file with another header is replaced).
    pub fn append(&self, dir: &Path) -> Result<()> {
        let path = path(dir);
        let mut text = match std::fs::read_to_string(&path) {
            Ok(t) if t.lines().next() == Some(HEADER) => t,
            _ => format!("{HEADER}\n"),
        };
        text.push_str(&self.row());
        text.push('\n');
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| input_error(parent, format!("cannot create: {e}")))?;
        }
        super::write_atomic(&path, text.as_bytes())
    }

    /// The runs recorded in `dir` (none when there is no `records/runs.csv`); a malformed row
    /// is an input error naming the file and line.
    pub fn read_all(dir: &Path) -> Result<Vec<RunRecord>> {
        let path = path(dir);
        let Ok(text) = std::fs::read_to_string(&path) else {
            return Ok(Vec::new());
        };
        let mut lines = text.lines();
        if lines.next() != Some(HEADER) {
            return Err(input_error(&path, "not a runs file: unexpected header"));
        }
        let mut runs = Vec::new();
        for (n, line) in lines.enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            let f: Vec<&str> = line.split(',').collect();
            let bad = || input_error(&path, format!("line {}: malformed row {line:?}", n + 2));
            if f.len() != 8 {
                return Err(bad());
            }
            let int = |k: usize| f[k].parse::<u64>().map_err(|_| bad());
            let float = |k: usize| f[k].parse::<f64>().map_err(|_| bad());
            runs.push(RunRecord {
                started_unix: int(0)?,
                threads: int(1)? as usize,
                frames_rendered: int(2)? as usize,
                frames_skipped: int(3)? as usize,
                wall_seconds: float(4)?,
                thread_seconds: float(5)?,
                queries: int(6)?,
                rays_traced: int(7)?,
            });
        }
        Ok(runs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_append_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        assert!(RunRecord::read_all(dir.path()).unwrap().is_empty());
        let a = RunRecord {
            started_unix: 1_700_000_000,
            threads: 2,
            frames_rendered: 16,
            frames_skipped: 0,
            wall_seconds: 28.75,
            thread_seconds: 55.5,
            queries: 1000,
            rays_traced: 120,
        };
        let b = RunRecord {
            frames_skipped: 16,
            frames_rendered: 0,
            ..a.clone()
        };
        a.append(dir.path()).unwrap();
        b.append(dir.path()).unwrap();
        assert_eq!(RunRecord::read_all(dir.path()).unwrap(), vec![a, b]);
        std::fs::write(path(dir.path()), format!("{HEADER}\n1,2,x\n")).unwrap();
        let err = RunRecord::read_all(dir.path()).unwrap_err().to_string();
        assert!(err.contains("runs.csv: line 2"), "{err}");
    }
}
