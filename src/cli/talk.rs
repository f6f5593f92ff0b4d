//! How much the binary says: `-q` (errors only), the default, or `-v` (detail), accepted by
//! every command. Errors are always printed (by main.rs), and so is what a command exists to
//! print on stdout (a version, a table, a listing, a completion script, a man page). Every
//! write here ignores a failed write: a full disk under a redirected stderr or a closed pipe
//! loses the line, not the run or its exit code, where `eprintln!`/`println!` would panic.

use std::io::Write;

use clap::{ArgAction, Args};
use envshadow::error::escaped;

/// `-q` and `-v`, global: given before or after the command's name.
#[derive(Args, Debug, Clone, Copy, Default)]
pub struct TalkArgs {
    /// Print only errors: no progress, per-frame lines, notes, warnings, summaries or "wrote
    /// …" lines; what a command exists to print on stdout (a version, a table, job lines of
    /// `assemble --pending`, a completion script, a man page) is still printed.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Say more on stderr: `render` adds a line per tile (its queries, rays traced and
    /// seconds), each frame's rays by kind and the seconds spent writing it, and the time
    /// spent loading the inputs; `lights` the time to build them. Repeating it says no more.
    #[arg(short, long, global = true, action = ArgAction::Count)]
    pub verbose: u8,
}

/// How much to say.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    Quiet,
    Normal,
    Verbose,
}

impl TalkArgs {
    pub fn talk(&self) -> Talk {
        Talk(if self.quiet {
            Level::Quiet
        } else if self.verbose > 0 {
            Level::Verbose
        } else {
            Level::Normal
        })
    }
}

/// What a command says, at the level asked for.
#[derive(Clone, Copy, Debug)]
pub struct Talk(pub Level);

impl Talk {
    pub fn level(self) -> Level {
        self.0
    }

    /// A note, progress or summary on stderr (not with `-q`).
    pub fn info(self, line: &str) {
        if self.0 >= Level::Normal {
            say(line);
        }
    }

    /// Detail on stderr (only with `-v`).
    pub fn detail(self, line: &str) {
        if self.0 >= Level::Verbose {
            say(line);
        }
    }

    /// What a loader skipped, one `warning: ` line each on stderr (not with `-q`), its control
    /// characters escaped: a name from a file must not drive the terminal or forge a line.
    pub fn warn(self, warnings: &[String]) {
        for w in warnings {
            self.info(&escaped(&format!("warning: {w}")));
        }
    }

    /// A line on stdout that reports what was done, `wrote …` (not with `-q`), its control
    /// characters escaped (it names paths).
    pub fn done(self, line: &str) {
        if self.0 >= Level::Normal {
            out(&format!("{}\n", escaped(line)));
        }
    }
}

/// One line on stderr, whatever the level: errors.
pub fn say(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// Text on stdout as it is, whatever the level: what the command exists to print.
pub fn out(text: &str) {
    let mut o = std::io::stdout().lock();
    let _ = o.write_all(text.as_bytes());
    let _ = o.flush();
}
