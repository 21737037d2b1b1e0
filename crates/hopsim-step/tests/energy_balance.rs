//! The energy ledger closes (docs/physics.md §6) over a long run with every kind of flow: a
//! two-body hopper with a relative joint, damped springs (one an extension spring), joint
//! damping, motor torque pulses, applied impulses, a brake and frictional contacts that
//! switch on and off (a cane).

mod common;
use common::*;
use hopsim_model::Vec2;
use hopsim_step::{Actuation, ImpulseCommand};

/// Largest |balance error| over the run and the size of the flows at its end, J.
fn run_hopper(dt: f64, duration: f64) -> (f64, f64, usize, usize) {
    let model = two_body_hopper(0.8);
    let mut st = stepper(&model, dt);
    let mut s = two_body_hopper_state(&model, 0.02);
    st.start(&model, &s);
    let cane: Vec<usize> = (0..model.contacts().len())
        .filter(|&i| model.contacts()[i].shape == 1)
        .collect();
    let mut act = Actuation::default();
    let (mut max_error, mut locks, mut contact_steps) = (0.0f64, 0, 0);
    let every = |period: f64, t: f64| {
        ((t / dt).round() as u64).is_multiple_of((period / dt).round() as u64)
    };
    for _ in 0..(duration / dt).round() as usize {
        act.clear();
        let phase = s.t % 0.3;
        let torque = if phase < 0.1 {
            0.4
        } else if phase < 0.2 {
            -0.4
        } else {
            0.0
        };
        act.torques.push(motor(torque));
        if every(0.45, s.t) && s.t > 0.0 {
            act.locks.push((1, 0));
        }
        if every(0.6, s.t) && s.t > 0.0 {
            act.impulses.push(ImpulseCommand::Point {
                body: 0,
                offset: Vec2::new(0.05, 0.0),
                impulse: Vec2::new(0.3, 0.5),
            });
        }
        let cane_out = (s.t % 0.5) < 0.25;
        for &i in &cane {
            st.set_contact_enabled(i, cane_out);
        }
        let rec = st.step(&model, &mut s, &act).expect("step");
        locks += rec.locks.len();
        contact_steps += usize::from(rec.in_contact());
        max_error = max_error.max(rec.energy.balance_error().abs());
    }
    let e = st.record().energy;
    let flows = e.actuator_work.abs() + e.dissipated().abs();
    assert!(e.damping_work < 0.0 && e.lock_work < 0.0 && e.contact_work < 0.0);
    (max_error, flows, locks, contact_steps)
}

/// The account closes to the scheme's error, which shrinks with `Δt`.
#[test]
fn energy_balance_closes_over_a_long_two_body_run() {
    let duration = 4.0;
    let (coarse, flows, locks, contacts) = run_hopper(2e-4, duration);
    let (fine, _, _, _) = run_hopper(1e-4, duration);
    eprintln!(
        "two-body hopper, {duration} s: max |balance error| {coarse:.3e} J (Δt = 2e-4), \
         {fine:.3e} J (Δt = 1e-4), flows {flows:.3} J, {locks} brake steps, {contacts} steps in contact"
    );
    assert!(
        locks >= 8 && contacts > 1000,
        "{locks} locks, {contacts} contact steps"
    );
    assert!(
        coarse < 1e-3 * flows,
        "balance error {coarse} vs flows {flows}"
    );
    assert!(
        fine < 0.7 * coarse,
        "balance error did not shrink with Δt: {coarse} → {fine}"
    );
}

/// The energy account is for observers only: switched off, a run of the hopper with
/// motor pulses, brakes and contacts takes the same steps (states, contact and lock
/// impulses bit for bit), and the record's energies stay those of the start.
#[test]
fn the_energy_account_does_not_change_the_run() {
    let model = two_body_hopper(0.8);
    let dt = 2e-4;
    let run = |ledger: bool| {
        let mut st = stepper(&model, dt);
        st.set_ledger(ledger);
        let mut s = two_body_hopper_state(&model, 0.02);
        let start = st.start(&model, &s).energy;
        let mut act = Actuation::default();
        let mut impulses = Vec::new();
        for k in 0..10_000u32 {
            act.clear();
            act.torques
                .push(motor(if k % 1500 < 500 { 0.4 } else { -0.1 }));
            if k % 2250 == 2249 {
                act.locks.push((1, 0));
            }
            let rec = st.step(&model, &mut s, &act).expect("step");
            impulses.extend(rec.contacts.iter().map(|c| c.impulse_normal.to_bits()));
            impulses.extend(rec.locks.iter().map(|l| l.impulse.to_bits()));
        }
        (s, impulses, start, st.record().energy)
    };
    let (with, without) = (run(true), run(false));
    assert_eq!(with.0, without.0);
    assert_eq!(with.1, without.1);
    // Four brakes and many contact steps were compared.
    assert!(with.1.len() > 4, "{}", with.1.len());
    assert_ne!(with.3, with.2);
    assert_eq!(without.3, without.2);
}
