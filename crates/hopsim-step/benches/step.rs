//! Stepping a Robbit-like model (4 DOF, one frictional contact) under motor torque, a
//! two-body hopper (relative joint, springs, arc foot and cane: several contacts), and a
//! four-bar linkage (a loop joint: its rows in the step and the projection after it).

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use hopsim_model::Model;
use hopsim_step::{Actuation, State, Stepper};
use std::hint::black_box;

/// Steps from `start` under `act`, restarting every 1000 steps so that the robot stays in
/// stance.
fn bench_stance(
    c: &mut Criterion,
    name: &str,
    model: &Model,
    stepper: &mut Stepper,
    start: &State,
    act: &Actuation,
) {
    stepper.start(model, start);
    let mut state = start.clone();
    c.bench_function(name, |b| {
        b.iter(|| {
            if stepper.record().step.is_multiple_of(1000) {
                state.clone_from(start);
            }
            let rec = stepper.step(model, &mut state, act).unwrap();
            black_box(rec.contacts.len());
        })
    });
}

fn robbit_step(c: &mut Criterion) {
    let model = common::robbit();
    let mut stepper = common::stepper(&model, 2e-4);
    let start = common::state(&[0.0, 0.1, 0.0, 0.0], &[0.0; 4]);
    let mut act = Actuation::default();
    act.torques.push(common::motor(0.16));
    bench_stance(
        c,
        "robbit_step_in_stance",
        &model,
        &mut stepper,
        &start,
        &act,
    );
    // The same steps with nobody reading the energies (no energy account).
    let mut unobserved = common::stepper(&model, 2e-4);
    unobserved.set_ledger(false);
    let name = "robbit_step_in_stance_no_ledger";
    bench_stance(c, name, &model, &mut unobserved, &start, &act);
    let mut flying = common::state(&[0.0, 1.0, 0.0, 0.0], &[0.0; 4]);
    c.bench_function("robbit_step_in_flight", |b| {
        b.iter(|| {
            if flying.q[1] < 0.5 {
                flying = common::state(&[0.0, 1.0, 0.0, 0.0], &[0.0; 4]);
            }
            black_box(stepper.step(&model, &mut flying, &act).unwrap().step);
        })
    });
}

fn two_body_hopper_step(c: &mut Criterion) {
    let model = common::two_body_hopper(0.8);
    let mut stepper = common::stepper(&model, 2e-4);
    let start = common::two_body_hopper_state(&model, 0.0);
    let mut act = Actuation::default();
    act.torques.push(common::motor(0.2));
    let name = "two_body_hopper_step_in_stance";
    bench_stance(c, name, &model, &mut stepper, &start, &act);
}

fn four_bar_step(c: &mut Criterion) {
    let model = common::four_bar([0.1, 0.35, 0.25, 0.3], 9.81, None);
    let mut stepper = common::stepper(&model, 1e-4);
    let mut state = common::state(&[0.3, 1.0, 1.4], &[12.0, 0.0, 0.0]);
    stepper.assemble(&model, &mut state).unwrap();
    stepper.start(&model, &state);
    let act = Actuation::default();
    c.bench_function("four_bar_step", |b| {
        b.iter(|| black_box(stepper.step(&model, &mut state, &act).unwrap().loop_error))
    });
}

criterion_group!(benches, robbit_step, two_body_hopper_step, four_bar_step);
criterion_main!(benches);
