//! Cancellation: Ctrl-C, SIGTERM and SIGHUP (what GNU parallel and batch schedulers send) ask a
//! render to stop. The signal handler only sets a flag; the coordinator checks it before each
//! frame and each tile, drops the frames still rendering, lets the writer finish the frames
//! already complete, and returns [`Interrupted`](crate::error::Interrupted) (exit code 130).
//! A second signal while stopping exits at once with code 130.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;

use crate::error::{Interrupted, Result};

/// A shared stop flag. The default one is never set unless [`Cancel::cancel`] is called.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A flag that Ctrl-C (SIGINT), SIGTERM and SIGHUP set. A second signal, once the flag is
    /// set, ends the process at once with exit code 130.
    pub fn on_signals() -> Result<Cancel> {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        let flag = Arc::new(AtomicBool::new(false));
        for sig in [SIGINT, SIGTERM, SIGHUP] {
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
