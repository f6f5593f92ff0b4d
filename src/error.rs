//! Errors that read well.
//!
//! Two kinds matter to the user and to the exit code: a problem with something the user gave us
//! (a file, a flag, a spec key) — [`InputError`], exit code 2 — and everything else, which is
//! our fault or the machine's (exit code 1). An interrupted render exits with 130.
//! Context is chained with `anyhow::Context`, so a message reads
//! `while loading anims/x.toml: assets/b.glb: mesh 0 primitive 1: accessor 3 ...`.

use std::fmt;
use std::path::Path;

/// Exit codes, documented in `envshadow --help` and the README.
pub mod exit {
    /// Success.
    pub const OK: i32 = 0;
    /// Internal failure (a bug, or the machine: disk full, permission denied on output).
    pub const INTERNAL: i32 = 1;
    /// Bad input: a file, a flag or an animation spec is wrong (also clap's usage errors).
    pub const BAD_INPUT: i32 = 2;
    /// Interrupted by Ctrl-C or SIGTERM; complete frames are kept, `--resume` continues.
    pub const INTERRUPTED: i32 = 130;
}

/// Something the user gave us is wrong. `path` names the file (or the flag), `message` the problem.
#[derive(Debug, Clone)]
pub struct InputError {
    pub path: String,
    pub message: String,
}

impl InputError {
    pub fn new(path: impl AsRef<Path>, message: impl Into<String>) -> Self {
        InputError {
            path: path.as_ref().display().to_string(),
            message: message.into(),
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.path, self.message)
        }
    }
}

impl std::error::Error for InputError {}

/// Shorthand: an `anyhow::Error` carrying an [`InputError`].
pub fn input_error(path: impl AsRef<Path>, message: impl Into<String>) -> anyhow::Error {
    anyhow::Error::new(InputError::new(path, message))
}

/// Returns early with an [`InputError`]: `bail_input!(path, "bad thing {}", x)`.
#[macro_export]
macro_rules! bail_input {
    ($path:expr, $($fmt:tt)+) => {
        return Err($crate::error::input_error($path, format!($($fmt)+)))
    };
}

/// The render was interrupted (Ctrl-C / SIGTERM). Exit code 130.
#[derive(Debug, Clone, Copy)]
pub struct Interrupted;

impl fmt::Display for Interrupted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "interrupted; complete frames are kept, run again with --resume to continue"
        )
    }
}

impl std::error::Error for Interrupted {}

/// The exit code for an error chain: bad input anywhere in the chain wins.
pub fn exit_code(err: &anyhow::Error) -> i32 {
    for cause in err.chain() {
        if cause.downcast_ref::<Interrupted>().is_some() {
            return exit::INTERRUPTED;
        }
        if cause.downcast_ref::<InputError>().is_some() {
            return exit::BAD_INPUT;
        }
    }
    exit::INTERNAL
}

pub type Result<T> = anyhow::Result<T>;
