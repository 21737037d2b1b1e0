//! Stepping a Robbit-like model (4 DOF, one frictional contact) under motor torque, and a
//! two-body hopper (relative joint, springs, arc foot and cane: several contacts).

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use hopsim_step::{Actuation, TorqueCommand};
use std::hint::black_box;

fn robbit_step(c: &mut Criterion) {
    let model = common::robbit();
    let mut stepper = common::stepper(&model, 2e-4);
    let start = common::state(&[0.0, 0.1, 0.0, 0.0], &[0.0; 4]);
    let mut act = Actuation::default();
    act.torques.push(TorqueCommand {
        body: 1,
        reaction: Some(0),
        torque: 0.16,
    });
    stepper.start(&model, &start);
    let mut state = start.clone();
    c.bench_function("robbit_step_in_stance", |b| {
        b.iter(|| {
            // Restart every 1000 steps so the robot stays in stance.
            if stepper.record().step.is_multiple_of(1000) {
                state.clone_from(&start);
            }
            let rec = stepper.step(&model, &mut state, &act).unwrap();
            black_box(rec.contacts.len());
        })
    });
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
    act.torques.push(TorqueCommand {
        body: 1,
        reaction: Some(0),
        torque: 0.2,
    });
    stepper.start(&model, &start);
    let mut state = start.clone();
    c.bench_function("two_body_hopper_step_in_stance", |b| {
        b.iter(|| {
            if stepper.record().step.is_multiple_of(1000) {
                state.q.copy_from(&start.q);
                state.u.copy_from(&start.u);
            }
            let rec = stepper.step(&model, &mut state, &act).unwrap();
            black_box(rec.contacts.len());
        })
    });
}

criterion_group!(benches, robbit_step, two_body_hopper_step);
criterion_main!(benches);
