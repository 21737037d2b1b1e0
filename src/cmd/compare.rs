//! `hopsim compare A B`: compares two recordings' contact-impulse traces and states
//! (the differences are found by `hopsim_record::diff_run_files`).

use clap::Args;
use hopsim_record::{diff_run_files, RunDiffOptions, TraceTolerance};
use std::path::PathBuf;
use std::process::ExitCode;

use super::exit;

/// Compare the contact impulses (and states) of two recordings; exit non-zero where they
/// differ beyond tolerance, naming the first time and contact that differs.
///
/// A and B are hopsim `.mcap` recordings or impulse traces (`.csv`, as in tests/golden).
/// Exit status: 0 when they agree, 1 when they differ, 2 when an input cannot be read.
#[derive(Args)]
pub struct CompareArgs {
    /// The reference recording (.mcap) or impulse trace (.csv).
    pub reference: PathBuf,
    /// The recording to check against it.
    pub other: PathBuf,
    /// Absolute impulse tolerance, N s.
    #[arg(long, value_name = "NS", default_value_t = TraceTolerance::default().abs, allow_negative_numbers = true, value_parser = super::non_negative)]
    pub abs_tol: f64,
    /// Relative impulse tolerance: |a − b| ≤ abs + rel·max(|a|, |b|).
    #[arg(long, value_name = "REL", default_value_t = TraceTolerance::default().rel, allow_negative_numbers = true, value_parser = super::non_negative)]
    pub rel_tol: f64,
    /// Also compare the states q, u at the steps both recordings hold (two .mcap files).
    #[arg(long)]
    pub states: bool,
    /// Absolute tolerance on each state value (m, rad, m/s, rad/s).
    #[arg(long, value_name = "X", default_value_t = 1e-9, allow_negative_numbers = true, value_parser = super::non_negative)]
    pub state_tol: f64,
}

pub fn run(args: CompareArgs) -> anyhow::Result<ExitCode> {
    let options = RunDiffOptions {
        tolerance: TraceTolerance {
            abs: args.abs_tol,
            rel: args.rel_tol,
        },
        state_tolerance: args.states.then_some(args.state_tol),
    };
    match diff_run_files(&args.reference, &args.other, &options) {
        Ok(diff) => {
            print!("{diff}");
            Ok(if diff.agree() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        Err(err) => {
            eprintln!("error: {err}");
            Ok(ExitCode::from(exit::INVALID_INPUT))
        }
    }
}
