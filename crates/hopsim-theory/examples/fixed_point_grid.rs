//! Solves Robbit's default fixed-point grid (`N × N`, default 30) with the flywheel locked
//! and then free at touchdown, and prints every grid point in full precision (Rust's
//! `Debug` of `f64` round-trips), for instruction counts and for bit-for-bit comparisons
//! of two builds (docs/performance.md):
//!
//! ```text
//! fixed_point_grid 30 > before.txt      # then the same with the other build, and cmp
//! valgrind --tool=callgrind fixed_point_grid 10 > /dev/null
//! ```

use hopsim_theory::fixed_points::{FixedPointGrid, DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE};
use hopsim_theory::grid::NO_PROGRESS;
use hopsim_theory::robbit::{FlywheelAtTouchdown, RobbitParams};
use std::process::ExitCode;

fn main() -> ExitCode {
    let n: usize = match std::env::args().nth(1).map(|s| s.parse()) {
        None => 30,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("usage: fixed_point_grid [N > 0]");
            return ExitCode::FAILURE;
        }
    };
    for touchdown in [FlywheelAtTouchdown::Locked, FlywheelAtTouchdown::Free] {
        let p = RobbitParams {
            touchdown,
            ..RobbitParams::default()
        };
        let grid = FixedPointGrid::new(p, DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE, n, n);
        let started = std::time::Instant::now();
        let points = match grid.run(NO_PROGRESS) {
            Ok(points) => points,
            Err(err) => {
                eprintln!("error: {err}");
                return ExitCode::FAILURE;
            }
        };
        let name = touchdown.name();
        let elapsed = started.elapsed().as_secs_f64();
        eprintln!("{n} x {n}, flywheel {name} at touchdown: {elapsed:.3} s");
        for point in points {
            println!("{point:?}");
        }
    }
    ExitCode::SUCCESS
}
