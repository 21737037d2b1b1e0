//! hopsim-lcp
