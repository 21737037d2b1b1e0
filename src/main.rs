//! `hopsim`: the command-line front end of the hopsim simulator.
//!
//! Each subcommand lives in its own module under `cmd/`; `main` only parses arguments
//! and maps errors to exit codes.

mod cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Planar non-smooth multibody simulator for impulse-actuated hopping robots.
#[derive(Parser)]
#[command(name = "hopsim", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Linear complementarity problems: solve `.dat` files with Lemke's method.
    Lcp(cmd::lcp::LcpArgs),
    /// Reduced models of the thesis: template, obstacle, impulsive wheel (docs/analysis.md).
    Analyze(cmd::analyze::AnalyzeArgs),
    /// Compare two recordings' contact-impulse traces; non-zero exit where they differ.
    Compare(cmd::compare::CompareArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Lcp(args) => cmd::lcp::run(args),
        Command::Analyze(args) => cmd::analyze::run(args),
        Command::Compare(args) => cmd::compare::run(args),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
