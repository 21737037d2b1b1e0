//! One module per `hopsim` subcommand.

pub mod analyze;
pub mod compare;
pub mod exit;
pub mod interrupt;
pub mod lcp;
pub mod progress;
pub mod render;
pub mod run;
pub mod scene;
pub mod sweep;
