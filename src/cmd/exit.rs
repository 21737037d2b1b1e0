//! Exit codes of `hopsim` (documented in the README).

/// A scene file, override or argument is invalid.
pub const INVALID_INPUT: u8 = 2;
/// The simulation stopped: NaN or runaway state, or an LCP failure in strict mode.
pub const SIMULATION_FAILED: u8 = 3;
/// A run was stopped by Ctrl-C or SIGTERM (128 + SIGINT, as shells report it).
pub const INTERRUPTED: u8 = 130;
