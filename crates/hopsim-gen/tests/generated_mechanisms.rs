//! Every generated mechanism runs without a panic, obeys its contact laws in every step
//! and reports finite figures (docs/reliability.md, "Generated mechanisms").
//!
//! The budget is `HOPSIM_GEN_CASES` cases (default 1500: CI's, well under two minutes);
//! `just fuzz` runs a long campaign. Seeds proptest shrank to a failure are kept in
//! `proptest-regressions/` beside this file and run first, every time.

use hopsim_gen::{genes, run_and_check, Mechanism, Outcome};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, FileFailurePersistence};
use std::sync::Mutex;

fn cases() -> u32 {
    std::env::var("HOPSIM_GEN_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1500)
}

/// Counts of the outcomes, printed at the end (`--nocapture`).
static TALLY: Mutex<[u64; 3]> = Mutex::new([0; 3]);

proptest! {
    #![proptest_config(Config {
        cases: cases(),
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("regressions"))),
        max_shrink_iters: 2000,
        ..Config::default()
    })]

    #[test]
    fn generated_mechanisms_run_and_obey_their_contact_laws(g in genes()) {
        let mechanism = Mechanism::from_genes(&g);
        let outcome = run_and_check(&mechanism)
            .map_err(|v| TestCaseError::fail(format!("{}\n--- scene ---\n{}", v.0, mechanism.to_toml())))?;
        let slot = match outcome {
            Outcome::Ran(_) => 0,
            Outcome::Stopped(_) => 1,
            Outcome::Rejected(_) => 2,
        };
        TALLY.lock().unwrap()[slot] += 1;
    }
}

#[test]
fn most_generated_mechanisms_run() {
    // The property above only says that no case breaks a law; this one that the generator
    // does produce runs (and not refusals), on its own fixed draw of 200 cases.
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut counts = [0u32; 3];
    for _ in 0..200 {
        let g = genes().new_tree(&mut runner).unwrap().current();
        match run_and_check(&Mechanism::from_genes(&g)) {
            Ok(Outcome::Ran(_)) => counts[0] += 1,
            Ok(Outcome::Stopped(_)) => counts[1] += 1,
            Ok(Outcome::Rejected(_)) => counts[2] += 1,
            Err(v) => panic!("{}", v.0),
        }
    }
    println!(
        "ran {}, stopped {}, refused {}",
        counts[0], counts[1], counts[2]
    );
    assert!(
        counts[0] >= 150,
        "only {} of 200 generated mechanisms ran: {counts:?}",
        counts[0]
    );
}
