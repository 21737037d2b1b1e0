//! A simulation driven from outside the scene's controller (the Python package's
//! `Simulation`): a shared scene, a caller's actuation in place of the controller,
//! restarting at a state (checked as a scene's start is), a run continued span by span,
//! and a run stopped from another thread.

mod common;

use common::scene;
use hopsim_control::ControlEvent;
use hopsim_record::EventKind;
use hopsim_scene::{StartProblem, StateProblem};
use hopsim_sim::{run_for, Observer, RunError, Simulation, StepView, StopFlag};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// The events of the last step seen.
#[derive(Default)]
struct LastEvents(Vec<EventKind>);

impl Observer for LastEvents {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        self.0 = v.events.iter().map(|e| e.kind.clone()).collect();
        Ok(())
    }
}

/// Each step of Robbit with the actuation its controller chose, given back as a caller's
/// (brakes as brake events), gives the controller's state and events bit for bit: the
/// stepper cannot tell who commanded it.
#[test]
fn a_callers_actuation_acts_as_the_controllers() {
    let scene = scene("robbit.toml", &["simulation.duration=2.0"]);
    let mut by_controller = Simulation::new(&scene);
    let mut by_caller = Simulation::shared(Arc::new(scene.setup.clone()));
    let steps = (scene.settings.duration / scene.settings.dt).round() as u64;
    let (mut seen_a, mut seen_b) = (LastEvents::default(), LastEvents::default());
    let mut brakes = 0;
    for _ in 0..steps {
        by_controller.step(&mut seen_a).unwrap();
        let actuation = by_controller.actuation().clone();
        let events: Vec<ControlEvent> = seen_a
            .0
            .iter()
            .filter(|k| matches!(k, EventKind::Brake { .. }))
            .map(|_| {
                let (body, other) = actuation.locks[0];
                ControlEvent::Brake { body, other }
            })
            .collect();
        brakes += events.len();
        by_caller
            .step_with(&actuation, &events, &mut seen_b)
            .unwrap();
        assert_eq!(by_caller.state(), by_controller.state());
        assert_eq!(seen_b.0, seen_a.0);
    }
    assert!(brakes >= 2, "{brakes} brakes");
    assert_eq!(by_caller.hops(), by_controller.hops());
}

/// An applied impulse is an event of its magnitude and changes the momentum by itself:
/// an upward impulse `ζ` at the centre of mass of Robbit at rest lifts it at
/// `ζ/m − g Δt` (the contact opens), docs/physics.md §3.
#[test]
fn an_applied_impulse_is_an_event_and_a_momentum_change() {
    let scene = scene("robbit.toml", &[]);
    let mut sim = Simulation::new(&scene);
    let mut actuation = hopsim_step::Actuation::default();
    let zeta = 2.0;
    actuation.impulses.push(hopsim_step::ImpulseCommand::Point {
        body: 0,
        offset: hopsim_model::Vec2::zeros(),
        impulse: hopsim_model::Vec2::new(0.0, zeta),
    });
    let mut seen = LastEvents::default();
    sim.step_with(&actuation, &[], &mut seen).unwrap();
    let m = scene.model.total_mass();
    let expected = zeta / m - scene.settings.gravity * scene.settings.dt;
    assert!((sim.state().u[1] - expected).abs() <= 1e-12 * expected.abs());
    assert_eq!(seen.0, vec![EventKind::AppliedImpulse { magnitude: zeta }]);
}

/// Robbit restarted at the state another run reached continues exactly as that run does
/// (both controllers still spinning the flywheel up: its first brake comes later).
#[test]
fn set_state_continues_from_the_given_state() {
    let scene = scene("robbit.toml", &[]);
    let mut kicked = Simulation::new(&scene);
    let mut state = scene.initial.clone();
    state.u[0] = 0.3; // rolling forward
    state.u[2] = -1.5;
    kicked.set_state(state).unwrap();
    for _ in 0..500 {
        kicked.step(&mut ()).unwrap();
    }
    let mut restarted = Simulation::new(&scene);
    restarted.restore_state(kicked.state().clone()).unwrap();
    assert_eq!(restarted.stepper().record().step, 0);
    for _ in 0..500 {
        kicked.step(&mut ()).unwrap();
        restarted.step(&mut ()).unwrap();
    }
    assert_eq!(restarted.state(), kicked.state());
}

/// `set_state` refuses what a scene's `[initial]` refuses, and changes nothing then: a
/// value out of bounds, a start in the ground (with its depth) or past a stop.
/// `restore_state` takes a state the run reached, in load with a slight penetration.
#[test]
fn set_state_checks_the_state_as_a_start() {
    let robbit = scene("robbit.toml", &[]);
    let mut sim = Simulation::new(&robbit);
    let mut state = robbit.initial.clone();
    state.q[1] = 1e300;
    assert!(matches!(
        sim.set_state(state.clone()),
        Err(StateProblem::Value { .. })
    ));
    assert!(matches!(
        sim.restore_state(state),
        Err(StateProblem::Value { .. })
    ));
    let mut lowered = robbit.initial.clone();
    lowered.q[1] -= 0.01;
    match sim.set_state(lowered.clone()) {
        // Lowered 1 cm from resting on the ground: 1 cm deep.
        Err(StateProblem::Start(StartProblem::InTerrain { depth, .. })) => {
            assert!((depth - 0.01).abs() < 1e-9, "{depth}")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        sim.state(),
        &robbit.initial,
        "a refused state changes nothing"
    );
    sim.restore_state(lowered.clone()).unwrap();
    assert_eq!(sim.state(), &lowered);

    let pendulum = scene("classic/pendulum-stop.toml", &[]);
    let mut sim = Simulation::new(&pendulum);
    let mut past = pendulum.initial.clone();
    past.q[0] = -0.25;
    match sim.set_state(past) {
        Err(StateProblem::Start(StartProblem::PastStop { depth, upper, .. })) => {
            assert!(!upper && (depth - 0.25).abs() < 1e-12, "{depth}")
        }
        other => panic!("{other:?}"),
    }
}

/// A run whose stop flag is set (by another thread) stops at its next step.
#[test]
fn a_stop_flag_stops_a_run_at_the_next_step() {
    let scene = scene("robbit.toml", &[]);
    let mut sim = Simulation::new(&scene);
    let flag = AtomicBool::new(true);
    let stopped = run_for(&mut sim, 1.0, &mut StopFlag(&flag));
    let dt = scene.settings.dt;
    assert!(
        matches!(stopped, Err(RunError::Interrupted { t }) if t == dt),
        "{stopped:?}"
    );
    assert_eq!(sim.stepper().record().step, 1);
    flag.store(false, std::sync::atomic::Ordering::Relaxed);
    run_for(&mut sim, 0.01, &mut StopFlag(&flag)).unwrap();
}

/// A run continued in two spans ends where one run of the whole length ends, and each
/// span's summary counts its own steps and hops.
#[test]
fn a_run_continues_span_by_span() {
    let scene = scene("robbit.toml", &["simulation.duration=3.0"]);
    let whole = hopsim_sim::run(&scene, &mut ()).unwrap();
    let mut sim = Simulation::new(&scene);
    let first = run_for(&mut sim, 1.0, &mut ()).unwrap();
    let second = run_for(&mut sim, 2.0, &mut ()).unwrap();
    assert_eq!(first.steps + second.steps, whole.steps);
    assert_eq!(first.hops + second.hops, whole.hops);
    assert_eq!(first.duration_s, 1.0);
    assert!((second.duration_s - 2.0).abs() < 1e-12);
    assert!(
        (first.distance_m + second.distance_m - whole.distance_m).abs() < 1e-12,
        "{} + {} ≠ {}",
        first.distance_m,
        second.distance_m,
        whole.distance_m
    );
}
