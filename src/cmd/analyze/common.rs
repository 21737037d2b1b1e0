//! Shared pieces of the `analyze` subcommands: output options, checks of numbers, and the
//! mapping of invalid input to exit code 2.

use clap::Args;
use hopsim_analysis::AnalysisError;
use hopsim_studies::StudyError;
use std::fmt;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::cmd::exit;
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

/// An invalid command-line argument (exit code 2).
#[derive(Debug)]
pub struct InvalidInput(pub String);

impl fmt::Display for InvalidInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InvalidInput {}

/// Returns an [`InvalidInput`] error.
pub fn invalid<T>(message: impl Into<String>) -> anyhow::Result<T> {
    Err(InvalidInput(message.into()).into())
}

/// Maps a subcommand's result to an exit code: invalid input prints the error and exits
/// with 2; other errors go to `main` (exit 1).
pub fn exit_code(result: anyhow::Result<()>) -> anyhow::Result<ExitCode> {
    match result {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(err) if is_invalid_input(&err) => {
            eprintln!("error: {err:#}");
            Ok(ExitCode::from(exit::INVALID_INPUT))
        }
        Err(err) => Err(err),
    }
}

fn is_invalid_input(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<InvalidInput>().is_some()
            || e.downcast_ref::<StudyError>()
                .is_some_and(StudyError::is_invalid_input)
            || matches!(
                e.downcast_ref::<AnalysisError>(),
                Some(AnalysisError::InvalidParameter { .. })
            )
    })
}
