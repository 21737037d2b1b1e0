//! The stepper's warm-started contact LCP ([`StepSettings::warm_start`]) gives the run of
//! the cold solves: Robbit's single-contact LCP has one solution, so the two runs differ
//! only by round-off, while most stance steps are answered without pivots.

mod common;
use common::*;
use hopsim_step::{Actuation, StepSettings, Stepper};

/// Robbit dropped from 2 cm, driven by a motor torque of ±1.5 N m that reverses every
/// 0.25 s (touchdowns, hops, sticking and slipping stance), 1.5 s at `Δt = 2e-4 s`: the
/// states of every step, the solves, and the warm answers among them.
fn run_robbit(warm_start: bool) -> (Vec<Vec<f64>>, u64, u64) {
    let model = robbit();
    let dt = 2e-4;
    let settings = StepSettings {
        warm_start,
        ..StepSettings::strict(dt)
    };
    let mut st = Stepper::new(&model, settings);
    let mut s = state(&[0.0, 0.12, 0.0, 0.0], &[0.3, 0.0, 0.0, 0.0]);
    st.start(&model, &s);
    let mut act = Actuation::default();
    let mut states = Vec::new();
    for k in 0..(1.5 / dt).round() as usize {
        act.clear();
        let sign = if ((k as f64 * dt / 0.25) as usize).is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        act.torques.push(motor(1.5 * sign));
        st.step(&model, &mut s, &act).expect("step");
        states.push(s.q.iter().chain(s.u.iter()).copied().collect());
    }
    let stats = st.lcp_stats();
    (states, stats.solves, stats.warm_starts)
}

#[test]
fn warm_started_steps_follow_the_cold_run() {
    let (cold, cold_solves, cold_warm) = run_robbit(false);
    let (warm, solves, warm_starts) = run_robbit(true);
    assert_eq!(cold_warm, 0);
    assert_eq!(solves, cold_solves);
    let max_diff = cold
        .iter()
        .zip(&warm)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0.0, f64::max);
    // Measured: 4.6e-14 (round-off of the two ways to solve the same basis); a different
    // solution or basis would show at the size of the impulses (1e-3 N s and more).
    assert!(max_diff < 1e-9, "max |Δ(q, u)| = {max_diff:e}");
    // Measured: 4 923 warm answers of 4 982 solves; the other 59 (touchdowns, changes
    // between sticking and slipping) took Lemke's method.
    assert!(
        warm_starts * 10 > solves * 9,
        "{warm_starts} warm of {solves}"
    );
    assert!(solves - warm_starts >= 10, "{warm_starts} warm of {solves}");
}
