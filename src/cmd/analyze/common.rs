//! Shared pieces of the `analyze` subcommands: output options and checks of numbers.

use clap::Args;
use std::path::PathBuf;

use crate::cmd::progress::CountBars;

/// `--json`, `--out DIR` and `--quiet`, shared by every analyze subcommand.
#[derive(Args, Clone, Debug)]
pub struct OutputArgs {
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write CSV files and PNG/SVG plots into DIR (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print nothing but errors (no progress bar, no table); --json still prints its
    /// object and --out still writes its files.
    #[arg(long, short)]
    pub quiet: bool,
}

impl OutputArgs {
    /// True when progress bars must not draw: with `--json` or `--quiet`.
    pub fn hide_progress(&self) -> bool {
        self.json || self.quiet
    }

    /// One progress bar per grid of a study, counting cells (hidden as above).
    pub fn cell_bars(&self) -> CountBars {
        CountBars {
            unit: "cells",
            quiet: self.hide_progress(),
        }
    }
}

pub use crate::cmd::exit::{invalid, InvalidInput};
