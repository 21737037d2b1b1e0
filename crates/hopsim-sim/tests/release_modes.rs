//! The momentum-impulse controller's release modes (docs/physics.md §5.3, docs/scene-format.md),
//! step by step: from each step's contact load and brakes, the steps in which the motor
//! must be on are derived independently of the controller and compared with the torque it
//! commanded.
//!
//! * `off_time = τ`: the motor is off in the brake's step and in the steps that start less
//!   than `τ` after it, i.e. for `max(1, round(τ / Δt))` steps, in flight or not.
//! * `touchdown`: off from the brake until the first step after a loaded step that
//!   follows a step without load (a flight); or, if no flight follows, the first step that
//!   starts at least `rearm_timeout` after the brake and follows a loaded step.

mod common;

use common::{run, scene};
use hopsim_record::EventKind;
use hopsim_scene::Scene;
use hopsim_sim::{Observer, RunError, StepView};

/// Per step, in order: the commanded torque, whether a brake fired, whether any contact
/// carried load, whether a lock acted.
#[derive(Default)]
struct StepLog {
    torque: Vec<f64>,
    brake: Vec<bool>,
    loaded: Vec<bool>,
    locked: Vec<bool>,
}

impl Observer for StepLog {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        self.torque.push(v.torque);
        self.brake.push(
            v.events
                .iter()
                .any(|e| matches!(e.kind, EventKind::Brake { .. })),
        );
        self.loaded.push(v.record.in_contact());
        self.locked.push(!v.record.locks.is_empty());
        Ok(())
    }
}

/// The scene's torque and its run's step log.
fn log(name: &str, overrides: &[&str]) -> (Scene, StepLog) {
    let scene = scene(name, overrides);
    let mut log = StepLog::default();
    run(&scene, &mut log);
    (scene, log)
}

fn torque(scene: &Scene) -> f64 {
    match &scene.controller {
        hopsim_control::ControllerConfig::MomentumImpulse(c) => c.torque,
        other => panic!("{other:?}"),
    }
}

/// Checks that the motor is off from each brake up to (not including) the step
/// `restart(brake)` gives, and on at `torque` from there to the next brake; returns the
/// number of brakes checked. The last brake's cycle is checked up to the end of the run.
fn check_cycles(log: &StepLog, torque: f64, restart: impl Fn(usize) -> Option<usize>) -> usize {
    let brakes: Vec<usize> = (0..log.brake.len()).filter(|&k| log.brake[k]).collect();
    assert!(brakes.len() >= 10, "only {} brakes", brakes.len());
    for (i, &b) in brakes.iter().enumerate() {
        let next = brakes.get(i + 1).copied().unwrap_or(log.torque.len());
        let on = restart(b).unwrap_or(log.torque.len()).min(next);
        for k in b..next {
            let expected = if k < on { 0.0 } else { torque };
            assert_eq!(
                log.torque[k], expected,
                "brake at step {b}: step {k} (restart expected at step {on}, next brake {next})"
            );
        }
    }
    brakes.len()
}

/// `off_time = 0.1 s` (the experiment), 0.02 s (the motor back on while the disc is still
/// in the air) and 0 (only the brake's own step without torque), at Δt = 2e-4 s.
#[test]
fn off_time_switches_the_motor_off_for_exactly_that_many_steps() {
    for (off_time, steps) in [("0.1", 500), ("0.02", 100), ("0", 1)] {
        let (scene, log) = log(
            "robbit-experiment.toml",
            &[&format!("controller.off_time={off_time}")],
        );
        let brakes = check_cycles(&log, torque(&scene), |b| Some(b + steps));
        // Where the motor came back on: in flight (no load in the step before) or not.
        let in_flight = (1..log.torque.len())
            .filter(|&k| log.torque[k] != 0.0 && log.torque[k - 1] == 0.0 && !log.loaded[k - 1])
            .count();
        eprintln!("off_time {off_time} s: {brakes} brakes, {in_flight} restarts in flight");
        if off_time == "0.02" {
            assert!(in_flight > 0, "off_time = 0.02 s never restarts in flight");
        }
    }
}

/// The first step after a loaded step that follows an unloaded one since the brake; or the
/// first step at least `timeout_steps` after the brake that follows a loaded step.
fn touchdown_restart(log: &StepLog, brake: usize, timeout_steps: usize) -> Option<usize> {
    let mut airborne = false;
    for k in brake + 1..log.loaded.len() {
        let contact = log.loaded[k - 1];
        if contact && (airborne || k - brake >= timeout_steps) {
            return Some(k);
        }
        airborne |= !contact;
    }
    None
}

/// The touchdown release: the default scene (every brake lifts the disc) and the same robot
/// at `T = 0.16 N m` with a 0.3 s rearm timeout (many brakes cannot lift it, and the timeout
/// restarts the motor).
#[test]
fn touchdown_restarts_the_motor_after_landing_or_the_rearm_timeout() {
    for (overrides, timeout_steps) in [
        (vec![], 5000),
        (
            vec!["controller.torque=0.16", "controller.rearm_timeout=0.3"],
            1500,
        ),
    ] {
        let (scene, log) = log("robbit.toml", &overrides);
        let brakes = check_cycles(&log, torque(&scene), |b| {
            touchdown_restart(&log, b, timeout_steps)
        });
        let by_timeout = (0..log.brake.len())
            .filter(|&b| log.brake[b])
            .filter(|&b| {
                touchdown_restart(&log, b, timeout_steps)
                    .is_some_and(|k| !log.loaded[b..k - 1].contains(&false))
            })
            .count();
        eprintln!("{overrides:?}: {brakes} brakes, {by_timeout} restarted by the timeout");
        if overrides.is_empty() {
            assert_eq!(
                by_timeout, 0,
                "the default gait lifts off after every brake"
            );
        } else {
            assert!(by_timeout > 0, "no brake without lift-off at T = 0.16 N m");
        }
    }
}

/// With `hold_brake = true` the lock acts in exactly the steps without motor torque, in
/// both release modes.
#[test]
fn a_held_brake_locks_while_the_motor_is_off() {
    for name in ["robbit.toml", "robbit-experiment.toml"] {
        let (_, log) = log(name, &["controller.hold_brake=true"]);
        let first_brake = log.brake.iter().position(|&b| b).expect("a brake");
        for k in first_brake..log.torque.len() {
            assert_eq!(log.locked[k], log.torque[k] == 0.0, "{name}: step {k}");
        }
    }
}
