//! Exit codes of `hopsim` (documented in the README) and the one mapping of errors to
//! them: every subcommand returns its error to `main`, which prints it and exits with
//! [`of_error`]'s code.

use hopsim_scene::SceneError;
use hopsim_sim::RunError;
use hopsim_studies::StudyError;
use hopsim_theory::AnalysisError;
use std::fmt;

/// An I/O or other error, or `hopsim compare` found a difference.
pub const FAILURE: u8 = 1;
/// A scene file, override or argument is invalid.
pub const INVALID_INPUT: u8 = 2;
/// The simulation stopped: NaN or runaway state, or an LCP failure in strict mode.
pub const SIMULATION_FAILED: u8 = 3;
/// An internal error: a bug in hopsim (a panic caught at a run's boundary,
/// docs/reliability.md "Panics").
pub const INTERNAL_ERROR: u8 = 4;
// A command stopped by a signal exits with 128 + the signal's number, as shells report it
// (130 for Ctrl-C, 143 for SIGTERM, 129 for SIGHUP): `interrupt::exit_code`.

/// The exit code of a run stopped by `err`.
pub fn of_run_error(err: &RunError) -> u8 {
    match err {
        RunError::Step(_) | RunError::Loop { .. } | RunError::NotFinite { .. } => SIMULATION_FAILED,
        RunError::Actuation(_) => INVALID_INPUT,
        RunError::Record(_) => FAILURE,
        RunError::Internal { .. } => INTERNAL_ERROR,
        RunError::Interrupted { .. } => super::interrupt::exit_code(),
    }
}

/// An invalid command-line argument (exit code [`INVALID_INPUT`]).
#[derive(Debug)]
pub struct InvalidInput(pub String);

impl fmt::Display for InvalidInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InvalidInput {}

/// Returns an [`InvalidInput`] error.
pub fn invalid<T>(message: impl Into<String>) -> anyhow::Result<T> {
    Err(InvalidInput(message.into()).into())
}

/// The exit code of a command that failed with `err`: the first error of its chain that
/// says what went wrong decides (invalid input, a stopped run, a bug); anything else is
/// [`FAILURE`].
pub fn of_error(err: &anyhow::Error) -> u8 {
    for e in err.chain() {
        if e.is::<InvalidInput>() || e.is::<SceneError>() {
            return INVALID_INPUT;
        }
        if let Some(run) = e.downcast_ref::<RunError>() {
            return of_run_error(run);
        }
        if e.downcast_ref::<StudyError>()
            .is_some_and(StudyError::is_invalid_input)
            || matches!(
                e.downcast_ref::<AnalysisError>(),
                Some(AnalysisError::InvalidParameter { .. })
            )
        {
            return INVALID_INPUT;
        }
    }
    FAILURE
}
