//! Runs a fixed number of Robbit steps in stance or in flight, for profiling and A/B
//! comparisons on a busy machine:
//!
//! ```text
//! step_profile flight 22000      # valgrind --tool=callgrind: instructions per step are
//! step_profile flight 2000       # the difference of two runs divided by 20 000
//! step_profile stance 22000 no-ledger    # without the energy account
//! perf record -e cpu-clock step_profile stance 3000000
//! step_profile hopper 22000      # the two-body hopper in stance (the bench's step)
//! ```
//!
//! valgrind 3.19 cannot decode the LCP's AVX2 path: count the stance steps of a build with
//! `--features hopsim-lcp/portable` (docs/performance.md).

#[path = "../tests/common/mod.rs"]
mod common;

use hopsim_step::Actuation;
use std::hint::black_box;

fn main() {
    let mut args = std::env::args().skip(1);
    let phase = args.next().unwrap_or_else(|| "stance".into());
    let steps: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let ledger = args.next().as_deref() != Some("no-ledger");
    let hopper = phase == "hopper";
    let model = if hopper {
        common::two_body_hopper(0.8)
    } else {
        common::robbit()
    };
    let mut stepper = common::stepper(&model, 2e-4);
    stepper.set_ledger(ledger);
    let start = match phase.as_str() {
        "hopper" => common::two_body_hopper_state(&model, 0.0),
        "flight" => common::state(&[0.0, 1.0, 0.0, 0.0], &[0.0; 4]),
        _ => common::state(&[0.0, 0.1, 0.0, 0.0], &[0.0; 4]),
    };
    let mut act = Actuation::default();
    act.torques
        .push(common::motor(if hopper { 0.2 } else { 0.16 }));
    stepper.start(&model, &start);
    let mut state = start.clone();
    for k in 0..steps {
        // Restart every 1000 steps, as the benchmark does, so the phase does not change.
        if k % 1000 == 0 {
            state.clone_from(&start);
        }
        let rec = stepper.step(&model, &mut state, &act).unwrap();
        black_box(rec.contacts.len());
    }
    black_box(&state);
}
