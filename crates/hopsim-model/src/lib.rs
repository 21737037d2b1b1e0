//! hopsim-model
