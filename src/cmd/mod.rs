//! One module per `hopsim` subcommand.

pub mod lcp;
