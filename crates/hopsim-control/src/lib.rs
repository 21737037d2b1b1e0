//! hopsim-control
