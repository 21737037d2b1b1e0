//! Ctrl-C (SIGINT) and SIGTERM during `hopsim run`: the first signal asks the run loop to
//! stop at the next step, so that unfinished recorders delete their temporary files; a
//! second signal terminates at once (the handler is reset after the first).

use hopsim_sim::{Observer, RunError, StepView};
use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

#[cfg(unix)]
extern "C" fn on_signal(_: libc::c_int) {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Installs the handler for SIGINT and SIGTERM (a no-op off Unix).
pub fn install() {
    #[cfg(unix)]
    // SAFETY: the handler only stores to an atomic, which is async-signal-safe; the
    // `sigaction` struct is fully initialised (zeroed, then the fields set).
    unsafe {
        let mut action: libc::sigaction = std::mem::zeroed();
        action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        action.sa_flags = libc::SA_RESETHAND;
        libc::sigemptyset(&mut action.sa_mask);
        libc::sigaction(libc::SIGINT, &action, std::ptr::null_mut());
        libc::sigaction(libc::SIGTERM, &action, std::ptr::null_mut());
    }
}

/// Forwards every step to `inner` and stops the run once a signal has arrived.
pub struct StopOnSignal<O>(pub O);

impl<O: Observer> Observer for StopOnSignal<O> {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        if REQUESTED.load(Ordering::Relaxed) {
            return Err(RunError::Interrupted { t: view.state.t });
        }
        self.0.on_step(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.0.on_start(view)
    }
}
