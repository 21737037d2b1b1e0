//! Exit codes of `hopsim` (documented in the README) and the mapping of run errors to them.

use hopsim_sim::RunError;

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
        RunError::Step(_) | RunError::NotFinite { .. } => SIMULATION_FAILED,
        RunError::Record(_) => FAILURE,
        RunError::Internal { .. } => INTERNAL_ERROR,
        RunError::Interrupted { .. } => super::interrupt::exit_code(),
    }
}
