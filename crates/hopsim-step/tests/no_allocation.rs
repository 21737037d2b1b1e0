//! The stepper allocates nothing per step (counted by a global allocator): in stance, in
//! flight, with brakes, and with several contacts at once (lines, arc ends, a cane, a
//! polygon's edges and an ellipse at a step's corner).

mod common;

use hopsim_model::{Model, Shape, Terrain, Vec2};
use hopsim_step::{Actuation, ImpulseCommand, State, Stepper};

#[path = "../../../tests/support/counting_allocator.rs"]
mod counting_allocator;
use counting_allocator::allocated;

/// Allocations made by `steps` calls of `step` after `warm_up` calls.
fn allocations(warm_up: usize, steps: usize, mut step: impl FnMut(usize)) -> usize {
    for k in 0..warm_up {
        step(k);
    }
    let before = allocated();
    for k in warm_up..warm_up + steps {
        step(k);
    }
    allocated() - before
}

/// Allocations in passive steps of `model` from `state` (restarting every 2000 steps),
/// the most contacts of one step and whether terrain feature `corner` was touched.
fn passive(model: &Model, state: State, steps: usize, corner: usize) -> (usize, usize, bool) {
    let mut stepper = common::stepper(model, 1e-4);
    let mut s = state.clone();
    stepper.start(model, &s);
    let act = Actuation::default();
    let (mut most, mut touched) = (0, false);
    let count = allocations(2000, steps, |k| {
        if k % 2000 == 0 {
            s.q.copy_from(&state.q);
            s.u.copy_from(&state.u);
        }
        let rec = stepper.step(model, &mut s, &act).unwrap();
        most = most.max(rec.contacts.len());
        touched |= rec
            .contacts
            .iter()
            .any(|c| model.contacts()[c.contact].terrain == corner && c.impulse_normal > 0.0);
    });
    (count, most, touched)
}

#[test]
fn flight_steps_do_not_allocate() {
    let model = common::robbit();
    let state = common::state(&[0.0, 5.0, 0.0, 0.0], &[1.0, 2.0, 3.0, 4.0]);
    assert_eq!(passive(&model, state, 2000, 0), (0, 0, false));
}

#[test]
fn multi_contact_steps_at_a_step_corner_do_not_allocate() {
    let square = Shape::rectangle(Vec2::zeros(), 0.05, 0.05);
    let ellipse = Shape::Ellipse {
        center: Vec2::zeros(),
        semi_x: 0.08,
        semi_y: 0.04,
    };
    // A box coming to rest over the edge of a step (a vertex on the top, its bottom edge on
    // the corner), an ellipse rolling off the edge.
    for (shape, x, least) in [(square, 0.01, 2), (ellipse, -0.05, 1)] {
        let model = common::single_body(
            1.0,
            0.002,
            shape,
            Terrain::step(0.0, 0.1),
            common::material(0.6, 0.0),
        );
        let state = common::state(&[x, 0.16, 0.0], &[0.3, 0.0, -1.0]);
        let (count, most, corner) = passive(&model, state, 2000, 3);
        assert_eq!(count, 0);
        assert!(
            most >= least && corner,
            "{most} contacts at most, corner touched: {corner}"
        );
    }
}

#[test]
fn two_body_hopper_with_springs_cane_impulses_and_brakes_does_not_allocate() {
    let model = common::two_body_hopper(0.8);
    let mut stepper: Stepper = common::stepper(&model, 1e-4);
    let start = common::two_body_hopper_state(&model, 0.0);
    let mut state = start.clone();
    stepper.start(&model, &state);
    let mut act = Actuation::default();
    act.torques.reserve(4);
    act.impulses.reserve(4);
    act.locks.reserve(4);
    let count = allocations(3000, 3000, |k| {
        act.clear();
        act.torques
            .push(common::motor(if k % 2000 < 1000 { 0.4 } else { -0.4 }));
        if k % 700 == 350 {
            act.locks.push((1, 0));
        }
        if k % 900 == 100 {
            act.impulses.push(ImpulseCommand::Point {
                body: 0,
                offset: Vec2::new(0.05, 0.0),
                impulse: Vec2::new(0.2, 0.4),
            });
        }
        for i in 0..model.contacts().len() {
            if model.contacts()[i].shape == 1 {
                stepper.set_contact_enabled(i, k % 500 < 250);
            }
        }
        stepper.step(&model, &mut state, &act).unwrap();
    });
    assert_eq!(count, 0);
}

#[test]
fn stepping_robbit_with_contacts_torque_and_a_brake_does_not_allocate() {
    let model = common::robbit();
    let mut stepper = common::stepper(&model, 2e-4);
    let mut state = common::state(&[0.0, 0.1, 0.0, 0.0], &[0.0; 4]);
    stepper.start(&model, &state);
    let mut act = Actuation::default();
    act.torques.reserve(4);
    act.locks.reserve(4);
    let mut run = |steps: usize, state: &mut hopsim_step::State| {
        for k in 0..steps {
            act.clear();
            if k % 500 == 499 {
                act.locks.push((0, 1));
            } else {
                act.torques.push(common::motor(0.16));
            }
            let rec = stepper.step(&model, state, &act).unwrap();
            assert!(rec.step > 0);
        }
    };
    // Warm up: buffers reach their final size.
    run(1000, &mut state);
    let before = allocated();
    run(2000, &mut state);
    let after = allocated();
    assert_eq!(
        after - before,
        0,
        "{} allocations in 2000 steps",
        after - before
    );
}

/// A point-foot hopper on a sprung prismatic leg with a stop and dry friction in the leg
/// (docs/physics.md §7.2, §7.5): touchdowns, stance and the stop's impacts at lift-off in
/// the same LCP allocate nothing.
#[test]
fn prismatic_leg_with_a_joint_stop_and_dry_friction_does_not_allocate() {
    use hopsim_model::{Body, Joint, JointKind, JointLimits, ShapeInstance};
    let leg = Joint {
        kind: JointKind::Prismatic {
            axis: Vec2::new(0.0, -1.0),
        },
        stiffness: 1000.0,
        rest_position: 0.5,
        dry_friction: 0.5,
        limits: Some(JointLimits {
            lower: 0.1,
            upper: 0.5,
            restitution: 0.0,
        }),
        ..Joint::revolute(Some(0), Vec2::zeros(), Vec2::zeros())
    };
    let model = Model::new(
        vec![
            Body::base("body", 1.0, 0.01),
            Body {
                name: "foot".into(),
                mass: 0.01,
                inertia: 1e-6,
                joint: Some(leg),
            },
        ],
        vec![ShapeInstance {
            name: "foot".into(),
            body: 1,
            shape: Shape::Point {
                position: Vec2::zeros(),
            },
        }],
        Terrain::flat(0.0),
        vec![],
        Vec2::new(0.0, -9.81),
        common::material(1.0, 0.0),
    )
    .unwrap();
    let state = common::state(&[0.0, 0.6, 0.0, 0.5], &[0.3, 0.0, 0.0, 0.0]);
    let mut stepper = common::stepper(&model, 1e-4);
    let mut s = state.clone();
    stepper.start(&model, &s);
    let act = Actuation::default();
    let (mut contacts, mut stops) = (false, false);
    let count = allocations(2000, 6000, |_| {
        let rec = stepper.step(&model, &mut s, &act).unwrap();
        contacts |= rec.contacts.iter().any(|c| c.impulse_normal > 0.0);
        stops |= rec.limits.iter().any(|l| l.impulse > 1e-6);
    });
    assert_eq!(count, 0);
    assert!(
        contacts && stops,
        "contacts {contacts}, stop impacts {stops}"
    );
    assert!(stepper.record().energy.dry_friction_work < 0.0);
}

/// Contacts between bodies (docs/physics.md §7): three discs and a box dropped onto a fixed
/// floor and onto each other, every pair a candidate; impacts, resting stacks and sliding
/// allocate nothing.
#[test]
fn body_contacts_do_not_allocate() {
    use hopsim_model::{Body, ContactMaterial, Joint, JointKind, ShapeInstance};
    let disc = |b: usize| ShapeInstance {
        name: format!("disc{b}"),
        body: b,
        shape: Shape::Circle {
            center: Vec2::zeros(),
            radius: 0.1,
        },
    };
    let mut floor = Body::base("floor", 0.0, 0.0);
    floor.joint = Some(Joint {
        kind: JointKind::Fixed { angle: 0.0 },
        ..Joint::revolute(None, Vec2::new(0.0, -0.5), Vec2::zeros())
    });
    let mut builder = hopsim_model::ModelBuilder::new(
        vec![
            Body::base("a", 1.0, 0.005),
            Body::base("b", 1.0, 0.005),
            Body::base("c", 1.0, 0.005),
            Body::base("crate", 2.0, 0.01),
            floor,
        ],
        vec![
            disc(0),
            disc(1),
            disc(2),
            ShapeInstance {
                name: "crate".into(),
                body: 3,
                shape: Shape::rectangle(Vec2::zeros(), 0.15, 0.1),
            },
            ShapeInstance {
                name: "floor".into(),
                body: 4,
                shape: Shape::rectangle(Vec2::zeros(), 5.0, 0.5),
            },
        ],
        Terrain::flat(-10.0),
        vec![],
        Vec2::new(0.0, -9.81),
        ContactMaterial::default(),
    )
    .unwrap();
    for a in 0..5 {
        for b in a + 1..5 {
            builder
                .add_body_contacts(a, b, common::material(0.5, 0.3))
                .unwrap();
        }
    }
    let model = builder.build();
    let q = [
        0.0, 0.3, 0.0, 0.05, 0.55, 0.0, -0.08, 0.8, 0.0, 0.3, 0.15, 0.3,
    ];
    let state = common::state(
        &q,
        &[0.5, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, -1.0, 0.0, -0.5, 0.0, 0.0],
    );
    let mut stepper = common::stepper(&model, 1e-3);
    let mut s = state.clone();
    stepper.start(&model, &s);
    let mut most = 0;
    let count = allocations(500, 1500, |k| {
        if k % 1000 == 0 {
            s.q.copy_from(&state.q);
            s.u.copy_from(&state.u);
        }
        let rec = stepper.step(&model, &mut s, &Actuation::default()).unwrap();
        most = most.max(rec.pair_contacts.len());
    });
    assert_eq!(count, 0);
    assert!(most >= 3, "{most} body–body contacts at most");
}

#[test]
fn a_four_bar_with_its_loop_joint_and_a_brake_does_not_allocate() {
    let model = common::four_bar([0.1, 0.35, 0.25, 0.3], 9.81, None);
    let mut state = common::state(&[0.3, 1.0, 1.4], &[12.0, 0.0, 0.0]);
    let mut stepper = common::stepper(&model, 1e-4);
    stepper.assemble(&model, &mut state).unwrap();
    stepper.start(&model, &state);
    let mut act = Actuation::default();
    // The warm-up includes a braked stretch (the actuation's own list grows there).
    let count = allocations(200, 2000, |k| {
        // A brake between crank and coupler every other 100 steps: lock and loop rows together.
        act.locks.clear();
        if (k / 100) % 2 == 1 {
            act.locks.push((1, 0));
        }
        let record = stepper.step(&model, &mut state, &act).unwrap();
        assert!(record.loop_error <= 1e-10);
    });
    assert_eq!(count, 0);
}

/// Robbit with a velocity servo (its force clamped part of the time: its damper comes and
/// goes) and a position servo on its flywheel, the controls changed every step: no
/// allocation (docs/physics.md §7.4).
#[test]
fn actuators_with_changing_controls_do_not_allocate() {
    use hopsim_model::{Actuator, ActuatorKind, ModelBuilder};
    let robbit = common::robbit();
    let mut builder = ModelBuilder::new(
        robbit.bodies().to_vec(),
        robbit.shapes().to_vec(),
        robbit.terrain().clone(),
        robbit.springs().to_vec(),
        robbit.gravity(),
        common::material(1.0, 0.0),
    )
    .unwrap();
    builder
        .add_actuator(Actuator {
            kind: ActuatorKind::Velocity { kv: 0.05 },
            force_range: Some([-0.2, 0.2]),
            ..Actuator::motor("spin", 1)
        })
        .unwrap();
    builder
        .add_actuator(Actuator {
            kind: ActuatorKind::Position { kp: 0.5, kv: 0.01 },
            gear: 2.0,
            ctrl_range: Some([-1.0, 1.0]),
            ..Actuator::motor("hold", 1)
        })
        .unwrap();
    let model = builder.build();
    let mut stepper = common::stepper(&model, 2e-4);
    let mut state = common::state(&[0.0, 0.1, 0.0, 0.0], &[0.0; 4]);
    stepper.start(&model, &state);
    let mut act = Actuation {
        controls: vec![0.0; 2],
        ..Actuation::default()
    };
    let mut clamped = [false, false];
    let count = allocations(1000, 3000, |k| {
        let t = k as f64 * 2e-4;
        act.controls[0] = 40.0 * (3.0 * t).sin();
        act.controls[1] = 2.0 * (5.0 * t).cos();
        stepper.step(&model, &mut state, &act).unwrap();
        let speed = state.u[3] - state.u[2];
        // Whether the velocity servo's force `k_v (u − ṡ)` is beyond its range.
        clamped[usize::from((0.05 * (act.controls[0] - speed)).abs() > 0.2)] = true;
    });
    assert_eq!(count, 0, "{count} allocations in 3000 steps");
    assert!(
        clamped[0] && clamped[1],
        "the servo's force was clamped in some steps only"
    );
}
