//! Exit codes of `hopsim` (documented in the README).

/// A scene file, override or argument is invalid.
pub const INVALID_INPUT: u8 = 2;
