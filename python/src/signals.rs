//! Ctrl-C during long calls. Python runs its signal handlers (SIGINT raises
//! `KeyboardInterrupt`) only when the interpreter gets control; a call that runs Rust for
//! a long time, the GIL released, gives it control about every [`POLL_INTERVAL`] instead.

use hopsim_sim::{Observer, RunError, StepView};
use pyo3::prelude::*;
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// How often a long call lets Python run its signal handlers.
pub const POLL_INTERVAL: Duration = Duration::from_millis(50);

/// The clock is read about this often (the number of steps between readings adapts to
/// their cost: a step takes 0.2 µs in flight and milliseconds on a large model).
const CLOCK_INTERVAL: Duration = Duration::from_millis(1);

/// Most steps between two readings of the clock.
const MAX_STRIDE: u32 = 1 << 16;

/// Polls Python's signal handlers during a loop of steps: [`SignalPoll::poll`] once per
/// step; as an [`Observer`] it stops a run with [`RunError::Interrupted`] once a handler
/// raised, and keeps that exception for [`SignalPoll::take_error`].
pub struct SignalPoll {
    countdown: u32,
    stride: u32,
    /// The last reading of the clock, and the last time the handlers ran.
    clock: Option<(Instant, Instant)>,
    error: Option<PyErr>,
}

impl SignalPoll {
    pub fn new() -> Self {
        Self {
            countdown: 1,
            stride: 1,
            clock: None,
            error: None,
        }
    }

    /// Counts one step; about every [`POLL_INTERVAL`] runs Python's signal handlers
    /// (re-attaching to the interpreter if the GIL is released). `false` once a handler
    /// raised.
    pub fn poll(&mut self) -> bool {
        self.countdown -= 1;
        if self.countdown > 0 {
            return true;
        }
        let now = Instant::now();
        let (read, handled) = self.clock.get_or_insert((now, now));
        let since = now - *read;
        self.stride = if since < CLOCK_INTERVAL / 2 {
            (self.stride * 2).min(MAX_STRIDE)
        } else if since > CLOCK_INTERVAL * 2 {
            (self.stride / 2).max(1)
        } else {
            self.stride
        };
        self.countdown = self.stride;
        *read = now;
        if now - *handled < POLL_INTERVAL {
            return true;
        }
        *handled = now;
        // `None`: the interpreter is shutting down; nothing to handle.
        if let Some(Err(e)) = Python::try_attach(|py| py.check_signals()) {
            self.error = Some(e);
            self.countdown = 1;
            return false;
        }
        true
    }

    /// The exception a signal handler raised, if one did.
    pub fn take_error(&mut self) -> Option<PyErr> {
        self.error.take()
    }
}

impl Observer for SignalPoll {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        if self.poll() {
            Ok(())
        } else {
            Err(RunError::Interrupted { t: view.state.t })
        }
    }
}

/// Waits for the answer of another thread on `receive`, the GIL released, running Python's
/// signal handlers every [`POLL_INTERVAL`]. `Ok(None)`: the thread went away without an
/// answer; `Err`: a handler raised (`receive` stays usable for a caller that still wants
/// the answer).
pub fn wait_for<T: Send>(py: Python<'_>, receive: &mut Receiver<T>) -> PyResult<Option<T>> {
    loop {
        // `&mut` is `Send` where the receiver is (`&` would need `Sync`).
        let waiting = &mut *receive;
        match py.detach(move || waiting.recv_timeout(POLL_INTERVAL)) {
            Ok(answer) => return Ok(Some(answer)),
            Err(RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(RecvTimeoutError::Disconnected) => return Ok(None),
        }
    }
}
