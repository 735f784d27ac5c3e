//! SIGINT and SIGTERM during a batch: the first asks the batch to stop after the output it
//! is writing (its file renamed into place, its manifest line appended), so nothing is left
//! half-done; a second ends the process at once (exit 1; an output being written is left
//! as its temporary file, never under its own name).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use signal_hook::consts::{SIGINT, SIGTERM};
use texmap::Error;

/// Whether a stop was asked for, and by which signal.
pub struct Stop {
    signal: Arc<AtomicUsize>,
}

impl Stop {
    /// Catches SIGINT and SIGTERM from now on (see the module docs).
    ///
    /// # Errors
    /// [`Error::Unsupported`] when the handlers cannot be registered.
    pub fn install() -> Result<Stop, Error> {
        let signal = Arc::new(AtomicUsize::new(0));
        let asked = Arc::new(AtomicBool::new(false));
        for sig in [SIGINT, SIGTERM] {
            let registered =
                signal_hook::flag::register_conditional_shutdown(sig, 1, asked.clone())
                    .and_then(|_| signal_hook::flag::register(sig, asked.clone()))
                    .and_then(|_| {
                        signal_hook::flag::register_usize(sig, signal.clone(), sig as usize)
                    });
            registered.map_err(|e| Error::Unsupported(format!("signal handlers: {e}")))?;
        }
        Ok(Stop { signal })
    }

    /// A stop that is never asked for (a single output keeps the default handlers: Ctrl-C
    /// ends it at once, leaving no file).
    pub fn never() -> Stop {
        Stop {
            signal: Arc::new(AtomicUsize::new(0)),
        }
    }

    /// The signal that asked for a stop: its name and number.
    pub fn asked(&self) -> Option<(&'static str, i32)> {
        match self.signal.load(Ordering::SeqCst) as i32 {
            0 => None,
            SIGINT => Some(("SIGINT", SIGINT)),
            SIGTERM => Some(("SIGTERM", SIGTERM)),
            n => Some(("a signal", n)),
        }
    }
}
