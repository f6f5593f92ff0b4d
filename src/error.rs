//! Errors that read well.
//!
//! Two kinds matter to the user and to the exit code: a problem with something the user gave us
//! (a file, a flag, a spec key) — [`InputError`], exit code 2 — and everything else, which is
//! our fault or the machine's (exit code 1). An interrupted render exits with 130.
//! Context is chained with `anyhow::Context`, so a message reads
//! `while loading anims/x.toml: assets/b.glb: mesh 0 primitive 1: accessor 3 ...`.

use std::borrow::Cow;
use std::fmt;
use std::path::Path;

/// `s` with its control characters escaped (`\n`, `\t`, `\u{1b}`, …), for names, URIs and
/// paths that reach a terminal or a log: an ANSI escape in a file's URI must not drive the
/// terminal, nor a newline forge a line in a farm's log. Printable text, non-ASCII included,
/// is kept as it is.
pub fn escaped(s: &str) -> Cow<'_, str> {
    if !s.chars().any(char::is_control) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// [`escaped`] for a path (non-UTF-8 bytes shown as U+FFFD).
pub fn escaped_path(path: &Path) -> String {
    escaped(&path.to_string_lossy()).into_owned()
}

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
            path: escaped_path(path.as_ref()),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 39: control characters in a name are escaped, printable text is kept.
    #[test]
    fn escaped_names_hold_no_control_characters() {
        assert!(matches!(
            escaped("plain/é.png"),
            Cow::Borrowed("plain/é.png")
        ));
        let e = escaped("a\u{1b}[31mred\nforged\r\u{7f}\u{85}");
        assert_eq!(e, "a\\u{1b}[31mred\\nforged\\r\\u{7f}\\u{85}");
        assert!(!e.chars().any(char::is_control));
        let err = InputError::new("x\ny.gltf", "bad");
        assert_eq!(err.to_string(), "x\\ny.gltf: bad");
    }
}
