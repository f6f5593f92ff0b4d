//! Cancellation: Ctrl-C, SIGTERM and SIGHUP (what GNU parallel and batch schedulers send) ask a
//! render to stop; on Windows, Ctrl-C, Ctrl-Break and closing the console. The handler only
//! sets a flag; the coordinator checks it before each frame and each tile, drops the frames
//! still rendering, lets the writer finish the frames already complete, and returns
//! [`Interrupted`](crate::error::Interrupted) (exit code 130). A second signal while stopping
//! exits at once with code 130.
//!
//! Unix: signal-hook's `sigaction` handlers. Windows: the ctrlc crate's console control
//! handler (`SetConsoleCtrlHandler`), not the C runtime's `signal`: that is what the console
//! calls, whichever runtime the binary links, and closing the window reaches it too (Windows
//! ends the process soon after; the frames already written are complete).

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

/// A shared stop flag. The default one is never set unless [`Cancel::cancel`] is called.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A flag that [`STOP_SIGNALS`] set. A second signal, once the flag is set, ends the
    /// process at once with exit code 130.
    #[cfg(unix)]
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

    /// A flag that Ctrl-C, Ctrl-Break and closing the console set. A second one, once the
    /// flag is set, ends the process at once with exit code 130. Once per process (the
    /// console handler is installed once).
    #[cfg(windows)]
    pub fn on_signals() -> Result<Cancel> {
        let flag = Arc::new(AtomicBool::new(false));
        let seen = Arc::clone(&flag);
        ctrlc::set_handler(move || {
            if seen.swap(true, Ordering::SeqCst) {
                std::process::exit(crate::error::exit::INTERRUPTED);
            }
        })
        .context("installing the Ctrl-C handler")?;
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
