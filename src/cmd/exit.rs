//! Exit codes of `hopsim` (documented in the README).

/// A scene file, override or argument is invalid.
pub const INVALID_INPUT: u8 = 2;
/// The simulation stopped: NaN or runaway state, or an LCP failure in strict mode.
pub const SIMULATION_FAILED: u8 = 3;
// A command stopped by a signal exits with 128 + the signal's number, as shells report it
// (130 for Ctrl-C, 143 for SIGTERM, 129 for SIGHUP): `interrupt::exit_code`.
