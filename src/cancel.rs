//! Cancellation: Ctrl-C, SIGTERM and SIGHUP (what GNU parallel and batch schedulers send) ask a
//! render to stop; on Windows, Ctrl-C and Ctrl-Break (and SIGTERM, which only the process
//! itself can raise there). The signal handler only sets a flag; the coordinator checks it
//! before each frame and each tile, drops the frames still rendering, lets the writer finish
//! the frames already complete, and returns [`Interrupted`](crate::error::Interrupted) (exit
//! code 130). A second signal while stopping exits at once with code 130.
//!
//! signal-hook covers both: POSIX signals through `sigaction`, and on Windows the C runtime's
//! `signal`, which the console's Ctrl-C and Ctrl-Break handlers call.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;

use crate::error::{Interrupted, Result};

/// The signals that ask a render to stop: Ctrl-C (SIGINT), SIGTERM, and SIGHUP (a closed
/// terminal or ssh session, GNU parallel's `--termseq`).
#[cfg(unix)]
pub const STOP_SIGNALS: &[std::ffi::c_int] = &[
    signal_hook::consts::SIGINT,
    signal_hook::consts::SIGTERM,
    signal_hook::consts::SIGHUP,
];

/// The signals that ask a render to stop: Ctrl-C (SIGINT), Ctrl-Break (SIGBREAK) and SIGTERM.
/// Windows has no SIGHUP; a closed console window ends the process without one.
#[cfg(windows)]
pub const STOP_SIGNALS: &[std::ffi::c_int] = &[
    signal_hook::consts::SIGINT,
    signal_hook::consts::SIGBREAK,
    signal_hook::consts::SIGTERM,
];

/// A shared stop flag. The default one is never set unless [`Cancel::cancel`] is called.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A flag that [`STOP_SIGNALS`] set. A second signal, once the flag is set, ends the
    /// process at once with exit code 130.
    pub fn on_signals() -> Result<Cancel> {
        let flag = Arc::new(AtomicBool::new(false));
        for &sig in STOP_SIGNALS {
            // Registered first, so it sees the flag as it was before this signal set it.
            signal_hook::flag::register_conditional_shutdown(
                sig,
                crate::error::exit::INTERRUPTED,
                Arc::clone(&flag),
            )
            .context("installing the signal handlers")?;
            signal_hook::flag::register(sig, Arc::clone(&flag))
                .context("installing the signal handlers")?;
        }
        Ok(Cancel(flag))
    }

    /// Asks the work to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether a stop was asked for.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// `Err(Interrupted)` once a stop was asked for.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            return Err(Interrupted.into());
        }
        Ok(())
    }
}
