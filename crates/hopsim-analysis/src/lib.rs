//! hopsim-analysis
