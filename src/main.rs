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
    /// Simulate a scene file; record to MCAP / Rerun / CSV; print the run summary.
    Run(cmd::run::RunArgs),
    /// Run a scene over a parameter grid on all cores; CSV of summaries and a plot.
    Sweep(cmd::sweep::SweepArgs),
    /// Search scene keys for the best run-summary field (CMA-ES, parallel, resumable).
    Optimize(cmd::optimize::OptimizeArgs),
    /// Scene files: validate without running.
    Scene(cmd::scene::SceneCommandArgs),
    /// Linear complementarity problems: solve `.dat` files with Lemke's method.
    Lcp(cmd::lcp::LcpArgs),
    /// Reduced models and analyses: template, obstacle, impulsive wheel, Robbit fixed points (docs/analysis.md).
    Analyze(cmd::analyze::AnalyzeArgs),
    /// Compare two recordings' contact-impulse traces; non-zero exit where they differ.
    Compare(cmd::compare::CompareArgs),
    /// Write a MuJoCo model (MJCF, .xml) of a planar mechanism as the equivalent scene file.
    Import(cmd::import::ImportArgs),
}

fn main() -> ExitCode {
    restore_default_sigpipe();
    let cli = Cli::parse();
    cmd::interrupt::install();
    report_panics_briefly();
    // Runs catch panics in their steps themselves (an internal error with the step and the
    // partial recordings kept); this catches the rest, so that a bug still ends with the
    // documented exit code.
    let result = std::panic::catch_unwind(|| match cli.command {
        Command::Run(args) => cmd::run::run(args),
        Command::Sweep(args) => cmd::sweep::run(args),
        Command::Optimize(args) => cmd::optimize::run_command(args),
        Command::Scene(args) => cmd::scene::run(args),
        Command::Lcp(args) => cmd::lcp::run(args),
        Command::Analyze(args) => cmd::analyze::run(args),
        Command::Compare(args) => cmd::compare::run(args),
        Command::Import(args) => cmd::import::run(args),
    });
    match result {
        Ok(Ok(code)) => code,
        Ok(Err(err)) => {
            eprintln!("error: {}", error_chain(&err));
            ExitCode::from(cmd::exit::of_error(&err))
        }
        Err(payload) => {
            eprintln!(
                "error: internal error: {}. This is a bug in hopsim; please report it with \
                 the command line and its input files",
                hopsim_sim::panic_message(payload.as_ref())
            );
            ExitCode::from(cmd::exit::INTERNAL_ERROR)
        }
    }
}

/// A panic (a bug) prints one line with its place, not a backtrace per sweep run, unless
/// `RUST_BACKTRACE` asks for one.
fn report_panics_briefly() {
    if std::env::var_os("RUST_BACKTRACE").is_some_and(|v| v != "0") {
        return;
    }
    std::panic::set_hook(Box::new(|info| {
        let place = info
            .location()
            .map_or_else(String::new, |l| format!(" at {}:{}", l.file(), l.line()));
        eprintln!("hopsim: internal error{place} (set RUST_BACKTRACE=1 for a backtrace)");
    }));
}

/// The error and its causes, `: `-separated, leaving out a cause whose text the message
/// already contains (an I/O error is often both quoted and chained).
fn error_chain(err: &anyhow::Error) -> String {
    let mut message = err.to_string();
    for cause in err.chain().skip(1) {
        let cause = cause.to_string();
        if !message.contains(&cause) {
            message.push_str(": ");
            message.push_str(&cause);
        }
    }
    message
}

/// `hopsim … | head` should end quietly when the reader goes away, as other command-line
/// tools do, instead of panicking on a failed write to stdout.
fn restore_default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
