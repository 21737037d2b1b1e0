//! hopsim-record
