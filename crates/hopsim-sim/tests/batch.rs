//! A batch of simulations against single simulations: copy `i` of a [`Batch`] equals a
//! [`Simulation`] with the same start and controls bit for bit at 1, 2 and 4 threads; a
//! copy that fails stops alone; reset and `set_state` restart one copy.

mod common;

use hopsim_scene::Scene;
use hopsim_sim::{Batch, BatchError, RunError, Simulation};
use hopsim_step::State;
use nalgebra::DVector;
use std::sync::Arc;

/// Robbit (its momentum-stored impulse controller) with a motor on the flywheel's joint.
fn robbit() -> Scene {
    let path = common::repo("scenes/robbit.toml");
    let text = std::fs::read_to_string(&path).unwrap()
        + "\n[[actuators]]\nname = \"motor\"\njoint = \"flywheel\"\nkind = \"motor\"\n";
    hopsim_scene::parse(&text, &path, &[]).unwrap()
}

/// Copy `i`'s start: standing at `x = i cm`, sliding and spinning by amounts of its own.
fn start(scene: &Scene, i: usize) -> State {
    let mut state = scene.initial.clone();
    let k = i as f64;
    state.q[0] = 0.01 * k;
    state.u[0] = 0.02 * (k - 32.0);
    state.u[3] = 0.5 * (k % 7.0);
    state
}

/// Copy `i`'s motor control in block `b` of steps.
fn control(i: usize, b: usize) -> f64 {
    0.05 * (((i * 13 + b * 7) % 11) as f64 - 5.0)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Copy `i`'s time and state equal `sim`'s, bit for bit.
fn assert_copy_is(batch: &Batch, i: usize, sim: &Simulation) {
    let (state, nq) = (sim.state(), batch.nq());
    assert_eq!(batch.t()[i].to_bits(), state.t.to_bits(), "copy {i}");
    let rows = i * nq..(i + 1) * nq;
    assert_eq!(bits(&batch.q()[rows.clone()]), bits(state.q.as_slice()));
    assert_eq!(bits(&batch.u()[rows]), bits(state.u.as_slice()));
}

/// `blocks` blocks of `steps` steps of 64 Robbits in a batch on `threads` threads and one
/// by one in single simulations: every copy's time, state and contact flag equal.
fn compare(threads: usize, blocks: usize, steps: usize) {
    let scene = robbit();
    let n = 64;
    let mut batch = Batch::new(&scene, n, threads).unwrap();
    let mut singles: Vec<Simulation> = (0..n).map(|_| Simulation::new(&scene)).collect();
    for (i, sim) in singles.iter_mut().enumerate() {
        batch.set_state(i, start(&scene, i)).unwrap();
        sim.set_state(start(&scene, i)).unwrap();
    }
    let nq = batch.nq();
    let mut touched = 0;
    for b in 0..blocks {
        for i in 0..n {
            batch.controls_mut()[i] = control(i, b);
        }
        batch.step(steps);
        for (i, sim) in singles.iter_mut().enumerate() {
            sim.set_controls(&[control(i, b)]).unwrap();
            for _ in 0..steps {
                sim.step(&mut ()).unwrap();
            }
            assert_copy_is(&batch, i, sim);
            assert_eq!(batch.in_contact()[i], sim.in_contact());
            touched += usize::from(sim.in_contact());
        }
        assert!(!batch.done().contains(&true));
    }
    // The copies did different things: some in contact, some not, states apart.
    assert!(touched > 0 && touched < n * blocks, "{touched}");
    assert_ne!(bits(&batch.q()[..nq]), bits(&batch.q()[nq..2 * nq]));
}

#[test]
fn batch_of_64_equals_single_simulations_at_1_thread() {
    compare(1, 40, 50);
}

#[test]
fn batch_of_64_equals_single_simulations_at_2_threads() {
    compare(2, 40, 50);
}

#[test]
fn batch_of_64_equals_single_simulations_at_4_threads() {
    compare(4, 200, 10);
}

#[test]
fn a_failing_copy_stops_alone_and_resets() {
    let scene = robbit();
    let mut batch = Batch::new(&scene, 8, 2).unwrap();
    let mut single = Simulation::new(&scene);
    batch.controls_mut().fill(0.1);
    batch.controls_mut()[3] = f64::NAN;
    single.set_controls(&[0.1]).unwrap();
    for _ in 0..20 {
        batch.step(25);
        for _ in 0..25 {
            single.step(&mut ()).unwrap();
        }
    }
    let done: Vec<usize> = (0..8).filter(|&i| batch.done()[i]).collect();
    assert_eq!(done, [3]);
    assert!(matches!(batch.error(3), Some(RunError::Actuation(_))));
    assert_eq!(batch.t()[3], 0.0, "the failed copy did not step");
    let nq = batch.nq();
    for i in (0..8).filter(|&i| i != 3) {
        assert!(batch.error(i).is_none());
        assert_eq!(batch.t()[i].to_bits(), single.state().t.to_bits());
        assert_eq!(
            bits(&batch.q()[i * nq..(i + 1) * nq]),
            bits(single.state().q.as_slice())
        );
    }
    // Reset: copy 3 runs again from the start, as a new simulation does.
    batch.reset(3).unwrap();
    assert!(!batch.done()[3] && batch.error(3).is_none());
    assert_eq!(
        bits(&batch.q()[3 * nq..4 * nq]),
        bits(scene.initial.q.as_slice())
    );
    batch.controls_mut()[3] = 0.1;
    batch.step(10);
    let mut fresh = Simulation::new(&scene);
    fresh.set_controls(&[0.1]).unwrap();
    for _ in 0..10 {
        fresh.step(&mut ()).unwrap();
    }
    assert_eq!(
        bits(&batch.q()[3 * nq..4 * nq]),
        bits(fresh.state().q.as_slice())
    );
}

#[test]
fn set_state_refuses_a_state_inside_the_ground_and_changes_nothing() {
    let scene = robbit();
    let mut batch = Batch::new(&scene, 4, 1).unwrap();
    let before = batch.q().to_vec();
    let mut sunk = scene.initial.clone();
    sunk.q[1] = 0.05; // the disc's lowest point 5 cm below the ground
    let err = batch.set_state(2, sunk).unwrap_err();
    assert!(matches!(err, BatchError::State { copy: 2, .. }), "{err}");
    assert_eq!(bits(batch.q()), bits(&before));
    assert!(matches!(
        batch.set_state(4, scene.initial.clone()),
        Err(BatchError::NoSuchCopy { copy: 4, copies: 4 })
    ));
    let moved = State {
        t: 0.0,
        q: DVector::from_vec(vec![1.0, 0.1, 0.0, 0.0]),
        u: DVector::zeros(4),
    };
    batch.set_state(1, moved).unwrap();
    assert_eq!(batch.q()[4], 1.0);
}

#[test]
fn copies_of_different_sizes_or_none_are_refused() {
    let robbit = Arc::new(robbit().setup.clone());
    let canebot = Arc::new(common::scene("canebot.toml", &[]).setup.clone());
    let err = Batch::of_setups(vec![robbit.clone(), canebot], 1)
        .err()
        .unwrap();
    assert!(matches!(err, BatchError::Sizes { copy: 1, .. }), "{err}");
    assert!(matches!(
        Batch::of_setups(vec![], 1),
        Err(BatchError::Empty)
    ));
    assert!(matches!(
        Batch::of_setups(vec![robbit], 0),
        Err(BatchError::NoThreads)
    ));
}

/// Copy `i`'s brake (disc–flywheel) in block `b`: engaged in alternate blocks of odd copies.
fn braked(i: usize, b: usize) -> bool {
    i % 2 == 1 && (b + i / 2).is_multiple_of(2)
}

#[test]
fn brakes_engaged_per_copy_equal_single_simulations_stepped_with_the_lock() {
    let scene = robbit();
    let (n, blocks, steps) = (16, 6, 40);
    let mut batch = Batch::new(&scene, n, 2).unwrap();
    batch.set_commands(&[(0, 1)], &[]).unwrap();
    assert_eq!(batch.brakes(), &[(0, 1)]);
    assert_eq!(batch.engaged(), vec![false; n].as_slice());
    let mut singles: Vec<Simulation> = (0..n).map(|_| Simulation::new(&scene)).collect();
    for (i, sim) in singles.iter_mut().enumerate() {
        batch.set_state(i, start(&scene, i)).unwrap();
        sim.set_state(start(&scene, i)).unwrap();
    }
    let lock = hopsim_step::Actuation {
        locks: vec![(0, 1)],
        ..Default::default()
    };
    let nq = batch.nq();
    for b in 0..blocks {
        for i in 0..n {
            batch.controls_mut()[i] = control(i, b);
            batch.engaged_mut()[i] = braked(i, b);
        }
        batch.step(steps);
        for (i, sim) in singles.iter_mut().enumerate() {
            sim.set_controls(&[control(i, b)]).unwrap();
            for _ in 0..steps {
                match braked(i, b) {
                    true => sim.step_with(&lock, &[], &mut ()).unwrap(),
                    false => sim.step(&mut ()).unwrap(),
                }
            }
            assert_copy_is(&batch, i, sim);
            if braked(i, b) {
                // The lock holds at the end of every braked step: θ̇_flywheel = θ̇_disc.
                let u = &batch.u()[i * nq..];
                assert!(
                    (u[3] - u[2]).abs() <= 1e-9 * (1.0 + u[2].abs()),
                    "copy {i}: {u:?}"
                );
            }
        }
    }
}

#[test]
fn brakes_and_switches_the_model_lacks_are_refused() {
    let mut batch = Batch::new(&robbit(), 2, 1).unwrap();
    assert!(matches!(
        batch.set_commands(&[(0, 7)], &[]),
        Err(BatchError::Brake(_))
    ));
    assert!(matches!(
        batch.set_commands(&[(1, 1)], &[]),
        Err(BatchError::Brake(_))
    ));
    assert!(matches!(
        batch.set_commands(&[], &[3]),
        Err(BatchError::Brake(_))
    ));
    assert!(batch.brakes().is_empty());
}

#[test]
fn restore_state_accepts_a_penetrated_state_that_set_state_refuses() {
    let scene = robbit();
    let mut batch = Batch::new(&scene, 2, 1).unwrap();
    let mut state = scene.initial.clone();
    state.q[1] -= 1e-3; // the disc 1 mm in the ground, as a step in load leaves it
    assert!(matches!(
        batch.set_state(1, state.clone()),
        Err(BatchError::State { copy: 1, .. })
    ));
    batch.restore_state(1, state.clone()).unwrap();
    assert_eq!(batch.q()[4 + 1], state.q[1]);
    // Values are still checked.
    state.q[0] = f64::NAN;
    assert!(batch.restore_state(1, state).is_err());
}

#[test]
fn shape_switches_per_copy_equal_single_simulations_stepped_with_the_switch() {
    // CaneBot without its controller (which would retract the cane at every step).
    let mut scene = hopsim_scene::load(&common::repo("scenes/canebot.toml"), &[])
        .unwrap()
        .setup
        .clone();
    scene.controller = hopsim_control::ControllerConfig::Passive;
    let cane = scene.switchable[0];
    let (n, blocks, steps) = (8, 6, 300);
    let mut batch = Batch::new(&scene, n, 2).unwrap();
    batch.set_commands(&[], &[cane]).unwrap();
    assert_eq!(batch.switches(), &[cane]);
    let mut singles: Vec<Simulation> = (0..n).map(|_| Simulation::new(&scene)).collect();
    let none = hopsim_step::Actuation::default();
    let mut switched = 0;
    for b in 0..blocks {
        for i in 0..n {
            batch.active_mut()[i] = braked(i, b);
        }
        batch.step(steps);
        for (i, sim) in singles.iter_mut().enumerate() {
            let on = braked(i, b);
            if sim.shapes_active()[cane] != on {
                switched += 1;
                let switch = hopsim_control::ControlEvent::ShapeSwitch {
                    shape: cane,
                    active: on,
                };
                sim.step_with(&none, &[switch], &mut ()).unwrap();
            } else {
                sim.step(&mut ()).unwrap();
            }
            for _ in 1..steps {
                sim.step(&mut ()).unwrap();
            }
            assert_eq!(sim.shapes_active()[cane], on);
            assert_eq!(batch.simulation(i).unwrap().shapes_active()[cane], on);
            assert_copy_is(&batch, i, sim);
        }
    }
    assert!(switched >= n, "{switched}");
}

/// What an observer saw of each step: step, time, `q` and the kinetic energy, as bits.
#[derive(Clone, Default)]
struct Seen(Arc<std::sync::Mutex<Vec<Vec<u64>>>>);

impl hopsim_sim::Observer for Seen {
    fn on_step(&mut self, view: &hopsim_sim::StepView<'_>) -> Result<(), RunError> {
        let mut row = vec![view.record.step, view.state.t.to_bits()];
        row.extend(bits(view.state.q.as_slice()));
        row.push(view.record.energy.kinetic.to_bits());
        self.0.lock().unwrap().push(row);
        Ok(())
    }

    fn on_start(&mut self, view: &hopsim_sim::StepView<'_>) -> Result<(), RunError> {
        self.on_step(view)
    }
}

/// An observer on copy 5 of a batch on two threads sees what it sees of a single
/// simulation with the same start and controls: the same steps, states and energies (the
/// copy's energy account is switched on for it); the copy cannot be reset or restarted
/// while it is watched, and can once the observer is detached.
#[test]
fn an_observed_copy_shows_its_steps_as_a_single_simulation() {
    let scene = robbit();
    let (n, copy) = (8, 5);
    let mut batch = Batch::new(&scene, n, 2).unwrap();
    let mut single = Simulation::new(&scene);
    batch.set_state(copy, start(&scene, copy)).unwrap();
    single.set_state(start(&scene, copy)).unwrap();
    let (on_batch, mut on_single) = (Seen::default(), Seen::default());
    batch.observe(copy, Box::new(on_batch.clone())).unwrap();
    single.start(&mut on_single).unwrap();
    for b in 0..4 {
        batch.controls_mut()[copy] = control(copy, b);
        batch.step(250);
        single.set_controls(&[control(copy, b)]).unwrap();
        for _ in 0..250 {
            single.step(&mut on_single).unwrap();
        }
    }
    let seen = on_batch.0.lock().unwrap().clone();
    assert_eq!(seen.len(), 1001);
    assert_eq!(seen, *on_single.0.lock().unwrap());
    assert!(seen
        .iter()
        .any(|row| f64::from_bits(*row.last().unwrap()) > 0.0));
    assert!(matches!(
        batch.reset(copy),
        Err(BatchError::Observed { copy: 5 })
    ));
    assert!(matches!(
        batch.reset_all(),
        Err(BatchError::Observed { copy: 5 })
    ));
    let again = start(&scene, copy);
    assert!(matches!(
        batch.set_state(copy, again),
        Err(BatchError::Observed { .. })
    ));
    assert!(batch.detach(copy).is_some());
    batch.step(1);
    assert_eq!(
        on_batch.0.lock().unwrap().len(),
        1001,
        "no steps after detach"
    );
    batch.reset(copy).unwrap();
}
