//! hopsim-step
