//! `hopsim lcp solve FILE... [--json] [--repeat N]`: solve LCPs from dense Siconos `.dat`
//! files with Lemke's method (crate `hopsim-lcp`, docs/lcp.md).

use clap::{Args, Subcommand};
use hopsim_lcp::dat::read_dat;
use hopsim_lcp::{LcpProblem, LcpSolution, LemkeSolver};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use super::exit;

/// Linear complementarity problems: find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0.
#[derive(Args)]
pub struct LcpArgs {
    #[command(subcommand)]
    pub command: LcpCommand,
}

#[derive(Subcommand)]
pub enum LcpCommand {
    /// Solve LCPs stored in dense Siconos `.dat` files with Lemke's method.
    ///
    /// Prints, per file, the status (solved, ray_termination, pivot_limit,
    /// numerical_breakdown), z, w, the pivot count and the certificate. "solved" is only
    /// reported when the certificate holds. An LCP without a solution is a result (exit 0);
    /// a malformed or unreadable file is reported on stderr, the other files are still
    /// solved, and the exit status is 2.
    Solve(SolveArgs),
}

#[derive(Args)]
pub struct SolveArgs {
    /// The `.dat` files to solve.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Print one JSON object per file and line: {"file", "status", "method", "n", "z", "w",
    /// "pivots", "certificate": {...}} (plus "median_solve_ns" with --repeat).
    #[arg(long)]
    pub json: bool,
    /// Re-solve each problem N times (1 … 10 000 000) with one reused solver and report the
    /// median time of one solve in nanoseconds.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    pub repeat: Option<u32>,
}

pub fn run(args: LcpArgs) -> anyhow::Result<ExitCode> {
    match args.command {
        LcpCommand::Solve(args) => Ok(solve(&args)),
    }
}

fn solve(args: &SolveArgs) -> ExitCode {
    let mut solver = LemkeSolver::default();
    let mut failed = false;
    for (k, path) in args.files.iter().enumerate() {
        let outcome = read_dat(path)
            .map_err(|e| e.to_string())
            .and_then(|problem| {
                let sol = solver
                    .solve_problem(&problem)
                    .map_err(|e| format!("{}: {e}", path.display()))?
                    .clone();
                let median = args
                    .repeat
                    .map(|n| median_solve_ns(&mut solver, &problem, n));
                Ok((problem, sol, median))
            });
        match outcome {
            Ok((problem, sol, median)) if args.json => {
                println!("{}", json_line(path, &problem, &sol, median));
            }
            Ok((problem, sol, median)) => {
                if k > 0 {
                    println!();
                }
                print!("{}", human(path, &problem, &sol, median));
            }
            Err(message) => {
                failed = true;
                eprintln!("error: {message}");
                if args.json {
                    let line = ErrorLine {
                        file: path.display().to_string(),
                        error: &message,
                    };
                    println!("{}", serde_json::to_string(&line).unwrap_or_default());
                }
            }
        }
    }
    if failed {
        ExitCode::from(exit::INVALID_INPUT)
    } else {
        ExitCode::SUCCESS
    }
}

/// Median wall time of one solve over about `repeat` solves. Solves are timed in batches
/// of at least ~2 µs so the clock's own cost and resolution do not dominate.
fn median_solve_ns(solver: &mut LemkeSolver, problem: &LcpProblem, repeat: u32) -> f64 {
    let (m, q) = (problem.m.as_view(), problem.q.as_view());
    let start = Instant::now();
    std::hint::black_box(solver.solve(m, q).ok());
    let one = start.elapsed().as_nanos().max(1);
    let batch = (2_000 / one).clamp(1, u128::from(repeat)) as u32;
    let samples = repeat.div_ceil(batch);
    let mut times: Vec<f64> = (0..samples)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..batch {
                std::hint::black_box(solver.solve(std::hint::black_box(m), q).ok());
            }
            start.elapsed().as_nanos() as f64 / f64::from(batch)
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let mid = times.len() / 2;
    if times.len() % 2 == 1 {
        times[mid]
    } else {
        0.5 * (times[mid - 1] + times[mid])
    }
}

/// One `--json` line of a solved problem.
#[derive(Serialize)]
struct SolveLine<'a> {
    file: String,
    status: &'a str,
    method: &'a str,
    n: usize,
    z: &'a [f64],
    w: &'a [f64],
    pivots: usize,
    certificate: CertificateLine,
    /// Median wall time of one solve with `--repeat`, ns (one decimal).
    #[serde(skip_serializing_if = "Option::is_none")]
    median_solve_ns: Option<f64>,
}

/// The certificate of a `--json` line.
#[derive(Serialize)]
struct CertificateLine {
    complementarity: f64,
    most_negative: f64,
    residual: f64,
    tolerance: f64,
    holds: bool,
}

/// One `--json` line of a problem that could not be read or solved.
#[derive(Serialize)]
struct ErrorLine<'a> {
    file: String,
    error: &'a str,
}

fn json_line(path: &Path, problem: &LcpProblem, sol: &LcpSolution, median: Option<f64>) -> String {
    let c = &sol.certificate;
    let line = SolveLine {
        file: path.display().to_string(),
        status: sol.status.as_str(),
        method: sol.method.as_str(),
        n: problem.n(),
        z: sol.z.as_slice(),
        w: sol.w.as_slice(),
        pivots: sol.pivots,
        certificate: CertificateLine {
            complementarity: c.complementarity,
            most_negative: c.most_negative,
            residual: c.residual,
            tolerance: c.tolerance,
            holds: c.holds(),
        },
        median_solve_ns: median.map(|ns| (ns * 10.0).round() / 10.0),
    };
    hopsim_io::to_json_value(&line)
        .and_then(|json| serde_json::to_string(&json))
        .unwrap_or_default()
}

fn human(path: &Path, problem: &LcpProblem, sol: &LcpSolution, median: Option<f64>) -> String {
    let numbers = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join("  ")
    };
    let c = &sol.certificate;
    let verdict = if c.holds() { "holds" } else { "does not hold" };
    let mut lines = vec![
        path.display().to_string(),
        format!("  {:<16} {}", "status", sol.status.as_str()),
        format!("  {:<16} {}", "method", sol.method.as_str()),
        format!("  {:<16} {}", "size", problem.n()),
        format!("  {:<16} {}", "pivots", sol.pivots),
        format!("  {:<16} {}", "z", numbers(sol.z.as_slice())),
        format!("  {:<16} {}", "w", numbers(sol.w.as_slice())),
        format!(
            "  {:<16} {verdict} (tolerance {:.3e})",
            "certificate", c.tolerance
        ),
        format!("  {:<16} {:.3e}", "complementarity", c.complementarity),
        format!("  {:<16} {:.3e}", "most negative", c.most_negative),
        format!("  {:<16} {:.3e}", "residual", c.residual),
    ];
    if let Some(ns) = median {
        lines.push(format!("  {:<16} {ns:.1} ns", "median solve"));
    }
    if !problem.comment.is_empty() {
        lines.push(format!(
            "  {:<16} {}",
            "comment",
            problem.comment.lines().next().unwrap_or("")
        ));
    }
    lines.join("\n") + "\n"
}
