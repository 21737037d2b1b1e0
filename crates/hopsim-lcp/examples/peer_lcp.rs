//! hopsim's side of the LCP peer benchmark (`benches/peers/run.sh`): reads dense Siconos
//! `.dat` files and times [`LemkeSolver`] on each, the same way `benches/peers/siconos_lcp.c`
//! times Siconos' `lcp_lexicolemke`:
//!
//! ```text
//! peer_lcp [--batches K] [--batch-us U] FILE...
//! ```
//!
//! Per file: one untimed solve (warm-up, and its `z` for the cross-check), then a batch size
//! `N` chosen so that one batch takes at least `U` µs (default 200), then `K` batches
//! (default 31) of `N` solves with one reused solver; the result is the median over the
//! batches of the batch time divided by `N`. Prints one JSON object per file and line:
//! `{"file", "n", "status", "pivots", "median_ns", "batch", "batches", "z"}`.

use hopsim_lcp::dat::read_dat;
use hopsim_lcp::{LcpProblem, LemkeSolver};
use std::hint::black_box;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn usage() -> ExitCode {
    eprintln!("usage: peer_lcp [--batches K] [--batch-us U] FILE...");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut batches: usize = 31;
    let mut batch_us: f64 = 200.0;
    let mut files: Vec<PathBuf> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--batches" => match args.next().and_then(|v| v.parse().ok()) {
                Some(k) if k > 0 => batches = k,
                _ => return usage(),
            },
            "--batch-us" => match args.next().and_then(|v| v.parse().ok()) {
                Some(u) if u > 0.0 => batch_us = u,
                _ => return usage(),
            },
            "-h" | "--help" => return usage(),
            _ => files.push(arg.into()),
        }
    }
    if files.is_empty() {
        return usage();
    }
    let mut solver = LemkeSolver::default();
    for path in &files {
        let problem = match read_dat(path) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        };
        let sol = match solver.solve_problem(&problem) {
            Ok(s) => s.clone(),
            Err(e) => {
                eprintln!("error: {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        };
        let (median_ns, batch) = time_solves(&mut solver, &problem, batches, batch_us);
        let z: Vec<String> = sol.z.iter().map(|v| format!("{v:e}")).collect();
        println!(
            "{{\"file\": \"{}\", \"n\": {}, \"status\": \"{}\", \"pivots\": {}, \
             \"median_ns\": {median_ns:.2}, \"batch\": {batch}, \"batches\": {batches}, \
             \"z\": [{}]}}",
            path.display(),
            problem.n(),
            sol.status,
            sol.pivots,
            z.join(", ")
        );
    }
    ExitCode::SUCCESS
}

/// Median time of one solve (ns) over `batches` batches, and the batch size.
fn time_solves(
    solver: &mut LemkeSolver,
    problem: &LcpProblem,
    batches: usize,
    batch_us: f64,
) -> (f64, u64) {
    let (m, q) = (problem.m.as_view(), problem.q.as_view());
    let solve = |solver: &mut LemkeSolver| {
        black_box(
            solver
                .solve(black_box(m), black_box(q))
                .map(|s| s.z[0])
                .ok(),
        );
    };
    // Batch size: double until one batch takes at least `batch_us`.
    let mut batch: u64 = 1;
    loop {
        let start = Instant::now();
        for _ in 0..batch {
            solve(solver);
        }
        if start.elapsed().as_secs_f64() * 1e6 >= batch_us || batch >= 1 << 30 {
            break;
        }
        batch *= 2;
    }
    let mut times: Vec<f64> = (0..batches)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..batch {
                solve(solver);
            }
            start.elapsed().as_nanos() as f64 / batch as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let mid = times.len() / 2;
    let median = if times.len() % 2 == 1 {
        times[mid]
    } else {
        0.5 * (times[mid - 1] + times[mid])
    };
    (median, batch)
}
