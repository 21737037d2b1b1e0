//! Signals: SIGINT (Ctrl-C), SIGTERM and SIGHUP. During `hopsim run` the first signal asks
//! the run loop to stop at the next step, so that its recordings up to there are kept under
//! partial names (`FILE.partial.mcap`) and the error says where it stopped. Otherwise, and
//! on a second signal, every temporary output file is deleted at once
//! ([`hopsim_io::remove_temporary_files`]) and the process exits with 128 + the signal's
//! number. Either way the complete outputs' names hold complete files or what was there
//! before.
//!
//! The handler only sets a flag and writes the signal's number to a pipe
//! (async-signal-safe); a watcher thread reads the pipe and does the rest.

use hopsim_sim::{Observer, RunError, StepView};
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// A signal arrived.
static REQUESTED: AtomicBool = AtomicBool::new(false);
/// The running command stops by itself on the first signal ([`stop_gracefully`]).
static GRACEFUL: AtomicBool = AtomicBool::new(false);
/// The pipe's writing end (−1 before [`install`]).
static PIPE: AtomicI32 = AtomicI32::new(-1);
/// The last signal's number.
static SIGNAL: AtomicI32 = AtomicI32::new(0);
/// Held while a stopped run keeps its recordings under partial names
/// ([`keeping_partial_outputs`]): a second signal waits for it, so that the partial files
/// are all kept, never a subset.
static KEEPING: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[cfg(unix)]
extern "C" fn on_signal(signal: libc::c_int) {
    REQUESTED.store(true, Ordering::SeqCst);
    SIGNAL.store(signal, Ordering::SeqCst);
    let byte = signal as u8;
    // SAFETY: write(2) is async-signal-safe; the buffer is one valid byte.
    unsafe {
        libc::write(PIPE.load(Ordering::SeqCst), (&byte as *const u8).cast(), 1);
    }
}

/// Installs the handlers and starts the watcher thread (a no-op off Unix).
pub fn install() {
    #[cfg(unix)]
    {
        let mut fds = [0 as libc::c_int; 2];
        // SAFETY: `fds` has room for the two descriptors pipe(2) writes.
        if unsafe { libc::pipe(fds.as_mut_ptr()) } != 0 {
            return;
        }
        PIPE.store(fds[1], Ordering::SeqCst);
        let read_end = fds[0];
        std::thread::spawn(move || watch(read_end));
        // SAFETY: the handler only touches atomics and write(2); the `sigaction` struct is
        // fully initialised (zeroed, then the fields set).
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
            action.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                libc::sigaction(signal, &action, std::ptr::null_mut());
            }
        }
    }
}

/// The first signal stops the running command through [`StopOnSignal`] instead of ending
/// the process.
pub fn stop_gracefully() {
    GRACEFUL.store(true, Ordering::SeqCst);
}

/// The exit code of a command stopped by the last signal: 128 + its number, as shells
/// report it (130 for Ctrl-C).
pub fn exit_code() -> u8 {
    u8::try_from(128 + SIGNAL.load(Ordering::SeqCst)).unwrap_or(130)
}

/// Reads signals from the pipe: the first one is left to the command if it stops
/// gracefully; any other removes the temporary files and exits.
#[cfg(unix)]
fn watch(read_end: libc::c_int) {
    let mut seen = 0;
    loop {
        let mut byte = 0u8;
        // SAFETY: reads one byte into a valid buffer.
        let n = unsafe { libc::read(read_end, (&mut byte as *mut u8).cast(), 1) };
        if n != 1 {
            continue;
        }
        seen += 1;
        if seen == 1 && GRACEFUL.load(Ordering::SeqCst) {
            continue;
        }
        // A run keeping its partial recordings finishes that first (it only flushes and
        // renames files).
        let _kept = KEEPING
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        hopsim_io::remove_temporary_files();
        eprintln!("\ninterrupted: unfinished output files removed");
        std::process::exit(128 + i32::from(byte));
    }
}

/// Runs `keep` (which renames a stopped run's recordings to their partial names) so that a
/// signal arriving meanwhile waits for it to finish.
pub fn keeping_partial_outputs<T>(keep: impl FnOnce() -> T) -> T {
    let _keeping = KEEPING
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    keep()
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
