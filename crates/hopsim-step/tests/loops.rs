//! Closed kinematic chains (docs/physics.md §8): the four-bar against its closed-form
//! position analysis, its energy account, a redundant parallelogram, a singular
//! configuration as an error, and random four-bars.

mod common;

use common::bar;
use hopsim_model::{Body, Joint, JointCoordinate, Kinematics, LoopJoint, LoopKind, Model, Vec2};
use hopsim_step::{Actuation, State, StepError, StepSettings, Stepper};
use nalgebra::DVector;
use std::f64::consts::TAU;

/// Link lengths of a four-bar: crank `a` (pinned at the origin), coupler `b`, rocker `c`
/// (pinned at `(d, 0)`), ground `d`.
#[derive(Clone, Copy, Debug)]
struct FourBar {
    a: f64,
    b: f64,
    c: f64,
    d: f64,
}

impl FourBar {
    /// The model of [`common::four_bar`]: coordinates `(θ_2, θ_3 − θ_2, θ_4)`.
    fn model(&self, gravity: f64, crank_inertia: Option<f64>) -> Model {
        common::four_bar([self.a, self.b, self.c, self.d], gravity, crank_inertia)
    }

    /// The closed-form position analysis: the rocker angle `θ_4` and the coupler angle
    /// `θ_3` at crank angle `θ_2` on the open (`+`) branch, from the triangle of the crank
    /// end `A`, the rocker pivot `O_4` and the coupler–rocker pin `B`.
    fn angles(&self, theta2: f64) -> (f64, f64) {
        let a = Vec2::new(self.a * theta2.cos(), self.a * theta2.sin());
        let e = Vec2::new(self.d, 0.0) - a;
        let f = e.norm();
        let alpha = e.y.atan2(e.x);
        let cos = (self.b * self.b - f * f - self.c * self.c) / (2.0 * self.c * f);
        let theta4 = alpha + cos.clamp(-1.0, 1.0).acos();
        let pin = Vec2::new(self.d + self.c * theta4.cos(), self.c * theta4.sin());
        let theta3 = (pin - a).y.atan2((pin - a).x);
        (theta4, theta3)
    }

    /// The assembled state at crank angle `theta2`, crank speed `omega` (the other speeds
    /// from the stepper's projection onto the closure).
    fn state(&self, model: &Model, theta2: f64, omega: f64) -> State {
        let (theta4, theta3) = self.angles(theta2);
        let mut state = State {
            t: 0.0,
            q: DVector::from_vec(vec![theta2, theta3 - theta2, theta4]),
            u: DVector::from_vec(vec![omega, 0.0, 0.0]),
        };
        let mut stepper = Stepper::new(model, StepSettings::strict(1e-3));
        stepper.assemble(model, &mut state).unwrap();
        state
    }
}

/// The angle `x − y` wrapped into `(−π, π]`.
fn angle_between(x: f64, y: f64) -> f64 {
    let d = (x - y).rem_euclid(TAU);
    if d > TAU / 2.0 {
        d - TAU
    } else {
        d
    }
}

/// A Grashof crank–rocker (shortest link the crank, `s + l ≤ p + q`: 0.1 + 0.35 ≤ 0.3 + 0.25).
const CRANK_ROCKER: FourBar = FourBar {
    a: 0.1,
    b: 0.35,
    c: 0.25,
    d: 0.3,
};

/// The loop error at `state`, measured from the bodies' positions (not the stepper's).
fn pin_gap(bar: &FourBar, model: &Model, state: &State) -> f64 {
    let mut k = Kinematics::new(model);
    k.update(model, &state.q, &state.u);
    let end = |b: usize, l: f64| {
        let t = k.angle(b);
        k.position(b) + Vec2::new(t.cos(), t.sin()) * (l / 2.0)
    };
    (end(1, bar.b) - end(2, bar.c)).norm()
}

/// Cranked by a heavy flywheel at one revolution per second for 10 s: the rocker and coupler
/// angles follow the closed-form position analysis at the crank's angle, the pin stays
/// closed to 1e-10 m at every step, and the crank's angle stays on `ω t` to the scheme's
/// error (the flywheel's speed varies by the small share of energy the links exchange).
#[test]
fn a_cranked_four_bar_follows_the_closed_form_position_analysis() {
    let bar = CRANK_ROCKER;
    let model = bar.model(0.0, Some(1e3));
    let omega = TAU;
    let mut state = bar.state(&model, 0.0, omega);
    let dt = 1e-3;
    let mut stepper = Stepper::new(&model, StepSettings::strict(dt));
    stepper.start(&model, &state);
    let (mut worst_rocker, mut worst_coupler, mut worst_gap, mut worst_phase) =
        (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for _ in 0..10_000 {
        let record = stepper
            .step(&model, &mut state, &Actuation::default())
            .unwrap();
        assert!(record.loop_error <= 1e-10, "{}", record.loop_error);
        let theta2 = state.q[0];
        let (theta4, theta3) = bar.angles(theta2);
        worst_rocker = worst_rocker.max(angle_between(state.q[2], theta4).abs());
        worst_coupler = worst_coupler.max(angle_between(state.q[0] + state.q[1], theta3).abs());
        worst_gap = worst_gap.max(pin_gap(&bar, &model, &state));
        worst_phase = worst_phase.max(angle_between(theta2, omega * state.t).abs());
    }
    eprintln!(
        "four-bar: rocker {worst_rocker:.2e} rad, coupler {worst_coupler:.2e} rad, pin {worst_gap:.2e} m, crank phase {worst_phase:.2e} rad"
    );
    assert!(worst_gap <= 1e-10, "{worst_gap}");
    assert!(worst_rocker <= 1e-9 && worst_coupler <= 1e-9);
    assert!(worst_phase <= 1e-2, "{worst_phase}");
    assert!((state.t - 10.0).abs() < 1e-9);
}

/// Free under gravity, without friction or actuation: the energy account closes (its
/// balance error, with the projection booked as its own term, stays below 1 % of the run's
/// energy scale) and the mechanical energy drifts by less than the ledger's warning bound
/// (5 % of the scale, docs/physics.md §6.1) over 10 s.
#[test]
fn a_free_four_bar_keeps_its_energy_account() {
    let bar = CRANK_ROCKER;
    let model = bar.model(9.81, None);
    let mut state = bar.state(&model, 0.3, 12.0);
    let mut stepper = Stepper::new(&model, StepSettings::strict(1e-4));
    let potential_start = stepper.start(&model, &state).energy.potential;
    let (mut worst_balance, mut scale, mut worst_gap) = (0.0_f64, 0.0_f64, 0.0_f64);
    for _ in 0..100_000 {
        let record = stepper
            .step(&model, &mut state, &Actuation::default())
            .unwrap();
        worst_gap = worst_gap.max(record.loop_error);
        worst_balance = worst_balance.max(record.energy.balance_error().abs());
        scale = scale.max(record.energy.scale(potential_start));
    }
    let energy = stepper.record().energy;
    eprintln!(
        "free four-bar: balance {worst_balance:.3e} J of scale {scale:.3e} J, projection {:.3e} J, loop work {:.3e} J, drift {:.3e} J, loop error {worst_gap:.2e} m",
        energy.projection,
        energy.loop_work,
        energy.total() - energy.initial
    );
    assert!(worst_gap <= 1e-10);
    assert!(worst_balance <= 1e-2 * scale, "{worst_balance} of {scale}");
    assert!((energy.total() - energy.initial).abs() <= 5e-2 * scale);
}

/// A parallelogram with a third parallel bar: one of its loop's equations is redundant
/// (the third bar's closure repeats the second's motion), which the pivoted factor drops
/// instead of failing; the loops stay closed and the bars parallel.
#[test]
fn a_parallelogram_with_a_redundant_bar_runs() {
    let (l, span) = (0.3, 0.5);
    let mut bodies = Vec::new();
    for (i, x) in [0.0, span / 2.0, span].into_iter().enumerate() {
        let mut joint = Joint::revolute(None, Vec2::new(x, 0.0), Vec2::new(l / 2.0, 0.0));
        joint.coordinate = JointCoordinate::Absolute;
        bodies.push(bar(&format!("bar{i}"), l, 1.0, joint));
    }
    // The coupler hangs on the first bar's end.
    bodies.push(bar(
        "coupler",
        span,
        1.0,
        Joint::revolute(Some(0), Vec2::new(l / 2.0, 0.0), Vec2::new(span / 2.0, 0.0)),
    ));
    let loops = [(1, 0.0), (2, span / 2.0)].map(|(i, at)| LoopJoint {
        name: format!("bar{i}"),
        body_a: 3,
        point_a: Vec2::new(at, 0.0),
        body_b: Some(i),
        point_b: Vec2::new(l / 2.0, 0.0),
        kind: LoopKind::Revolute,
    });
    let model = common::closed_chain(bodies, 9.81, loops.to_vec());
    // Bars at 60°, the coupler horizontal (relative angle −60°), swinging.
    let up = 1.0_f64;
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![up, up, up, -up]),
        u: DVector::from_vec(vec![2.0, 2.0, 2.0, -2.0]),
    };
    let mut stepper = Stepper::new(&model, StepSettings::strict(1e-3));
    assert!(stepper.assemble(&model, &mut state).unwrap() < 1e-12);
    stepper.start(&model, &state);
    for _ in 0..5000 {
        let record = stepper
            .step(&model, &mut state, &Actuation::default())
            .unwrap();
        assert!(record.loop_error <= 1e-10);
        // The bars stay parallel, the coupler horizontal.
        assert!((state.q[0] - state.q[1]).abs() < 1e-9 && (state.q[0] - state.q[2]).abs() < 1e-9);
        assert!((state.q[0] + state.q[3]).abs() < 1e-9);
    }
}

/// A four-bar whose links can line up (a change-point linkage, `s + l = p + q`: four equal
/// links) cranked slowly into its flat configuration, where its loop's rows lose rank, is
/// stopped with an error naming the loop, not a NaN.
#[test]
fn a_four_bar_driven_into_a_singular_configuration_is_an_error_naming_the_loop() {
    let bar = FourBar {
        a: 0.2,
        b: 0.2,
        c: 0.2,
        d: 0.2,
    };
    let model = bar.model(0.0, Some(1e3));
    // A parallelogram 0.01 rad before it folds flat at θ_2 = π, turning towards it.
    let theta = TAU / 2.0 - 0.01;
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![theta, -theta, theta]),
        u: DVector::from_vec(vec![0.01, 0.0, 0.0]),
    };
    let mut stepper = Stepper::new(&model, StepSettings::strict(1e-3));
    stepper.assemble(&model, &mut state).unwrap();
    stepper.start(&model, &state);
    let err = (0..2000)
        .find_map(|_| {
            stepper
                .step(&model, &mut state, &Actuation::default())
                .err()
        })
        .expect("the linkage reaches its flat configuration");
    let StepError::Loop {
        loop_index,
        singular,
        t,
        ..
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!(model.loops()[*loop_index].name, "coupler-rocker");
    assert!(*singular);
    // It folds at t ≈ 0.01 rad / 0.01 rad/s = 1 s.
    assert!((t - 1.0).abs() < 0.05, "{t}");
    assert!(state.q.iter().chain(state.u.iter()).all(|v| v.is_finite()));
    eprintln!("{err}");
}

/// Random Grashof crank–rockers (a fixed-seed generator), cranked for 2 s: no panic, no
/// error, loop error ≤ 1e-10 m at every step and the rocker on the closed form.
#[test]
fn random_crank_rockers_hold_their_loop() {
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut uniform = |lo: f64, hi: f64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut tried = 0;
    while tried < 20 {
        let bar = FourBar {
            a: uniform(0.05, 0.15),
            b: uniform(0.2, 0.6),
            c: uniform(0.2, 0.6),
            d: uniform(0.2, 0.6),
        };
        let mut sides = [bar.a, bar.b, bar.c, bar.d];
        sides.sort_by(f64::total_cmp);
        // Grashof with the crank shortest, kept away from the change point.
        if bar.a != sides[0] || sides[0] + sides[3] > sides[1] + sides[2] - 0.02 {
            continue;
        }
        tried += 1;
        let model = bar.model(9.81, Some(10.0));
        let mut state = bar.state(&model, uniform(0.0, TAU), TAU);
        let mut stepper = Stepper::new(&model, StepSettings::strict(1e-3));
        stepper.start(&model, &state);
        for _ in 0..2000 {
            let record = stepper
                .step(&model, &mut state, &Actuation::default())
                .unwrap_or_else(|e| panic!("{bar:?}: {e}"));
            assert!(record.loop_error <= 1e-10, "{bar:?}");
            let (theta4, _) = bar.angles(state.q[0]);
            assert!(angle_between(state.q[2], theta4).abs() < 1e-8, "{bar:?}");
        }
    }
}

/// The complete elliptic integral of the first kind `K(k)` (arithmetic–geometric mean).
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-15 * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    TAU / 4.0 / a
}

/// A free body hung from a world point by a massless rod (a distance loop joint) at its
/// centre of mass swings as a simple pendulum of the rod's length: its period from 0.5 rad
/// is `4 √(L/g) K(sin(θ₀/2))`, to the scheme's first-order error; the body's own rotation
/// stays free (it keeps its spin).
#[test]
fn a_body_on_a_massless_rod_swings_with_the_pendulum_period() {
    let (length, theta0, g) = (0.8, 0.5_f64, 9.81);
    let model = common::closed_chain(
        vec![Body::base("bob", 2.0, 0.05)],
        g,
        vec![LoopJoint {
            name: "rod".into(),
            body_a: 0,
            point_a: Vec2::zeros(),
            body_b: None,
            point_b: Vec2::zeros(),
            kind: LoopKind::Distance { length },
        }],
    );
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![length * theta0.sin(), -length * theta0.cos(), 0.0]),
        u: DVector::from_vec(vec![0.0, 0.0, 3.0]),
    };
    let dt = 1e-4;
    let mut stepper = Stepper::new(&model, StepSettings::strict(dt));
    stepper.start(&model, &state);
    // Times the bob crosses x = 0 moving towards −x (once per period).
    let mut crossings = Vec::new();
    let mut x = state.q[0];
    for _ in 0..60_000 {
        let record = stepper
            .step(&model, &mut state, &Actuation::default())
            .unwrap();
        assert!(record.loop_error <= 1e-10);
        if x > 0.0 && state.q[0] <= 0.0 {
            crossings.push(state.t - dt * state.q[0] / (state.q[0] - x));
        }
        x = state.q[0];
    }
    let period = 4.0 * (length / g).sqrt() * elliptic_k((theta0 / 2.0).sin());
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    eprintln!("rod pendulum: period {measured:.6} s, closed form {period:.6} s");
    assert!(crossings.len() >= 3);
    assert!(
        (measured - period).abs() < 1e-4 * period,
        "{measured} vs {period}"
    );
    assert!((state.u[2] - 3.0).abs() < 1e-9, "{}", state.u[2]);
}

/// The impact law with loops (docs/physics.md §8.2): a free rod pinned to the world at one
/// end by a revolute loop joint falls onto the ground with its tip; in the impact step the
/// tip's normal velocity reverses by `ε` (Newton's law on the unilateral row) while the pin
/// holds, so the one-coordinate mechanism keeps `ε²` of its kinetic energy.
#[test]
fn an_impact_of_a_closed_chain_follows_newtons_law_with_the_loop_holding() {
    use hopsim_model::{ContactMaterial, ModelBuilder, Shape, ShapeInstance, Terrain};
    let (length, eps) = (0.6, 0.5);
    let mut builder = ModelBuilder::new(
        vec![Body::base("rod", 1.0, length * length / 12.0)],
        vec![ShapeInstance {
            name: "tip".into(),
            body: 0,
            shape: Shape::Point {
                position: Vec2::new(length / 2.0, 0.0),
            },
        }],
        Terrain::flat(0.0),
        vec![],
        Vec2::new(0.0, -9.81),
        ContactMaterial {
            friction: 0.0,
            restitution_normal: eps,
            restitution_tangent: 0.0,
        },
    )
    .unwrap();
    builder
        .add_loop(LoopJoint {
            name: "pin".into(),
            body_a: 0,
            point_a: Vec2::new(-length / 2.0, 0.0),
            body_b: None,
            point_b: Vec2::new(0.0, 0.3),
            kind: LoopKind::Revolute,
        })
        .unwrap();
    let model = builder.build();
    // Horizontal, at rest: the tip falls through 0.3 m onto the ground (at 30° below).
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![length / 2.0, 0.3, 0.0]),
        u: DVector::zeros(3),
    };
    let mut stepper = Stepper::new(&model, StepSettings::strict(1e-5));
    stepper.start(&model, &state);
    let mut before = stepper.record().energy.kinetic;
    for _ in 0..100_000 {
        let record = stepper
            .step(&model, &mut state, &Actuation::default())
            .unwrap();
        assert!(record.loop_error <= 1e-10);
        if let Some(c) = record.contacts.iter().find(|c| c.impulse_normal > 0.0) {
            let after = record.energy.kinetic;
            eprintln!(
                "pinned rod impact: tip velocity {:.5} -> {:.5} m/s, kinetic energy ratio {:.5}",
                c.approach_velocity,
                c.normal_velocity - eps * c.approach_velocity,
                after / before
            );
            // Newton's law on the contact row: ξ_N = γ^E + ε γ^A = 0.
            assert!(c.normal_velocity.abs() < 1e-9 * c.approach_velocity.abs());
            assert!(
                (after / before - eps * eps).abs() < 1e-3,
                "{}",
                after / before
            );
            return;
        }
        before = record.energy.kinetic;
    }
    panic!("the rod never hit the ground");
}

/// Two free bodies welded together (a weld loop joint) fly as one rigid body: the loop's
/// percussions and the projection are internal forces, so the pair's centre of mass follows
/// the free-fall parabola to round-off and its angular momentum about that centre is
/// kept; the weld's relative angle and point stay closed.
#[test]
fn welded_bodies_fly_as_one_rigid_body() {
    let (g, angle) = (9.81, 0.3);
    let (ma, mb) = (1.0, 2.0);
    let model = common::closed_chain(
        vec![Body::base("a", ma, 0.01), Body::base("b", mb, 0.02)],
        g,
        vec![LoopJoint {
            name: "weld".into(),
            body_a: 0,
            point_a: Vec2::new(0.1, 0.0),
            body_b: Some(1),
            point_b: Vec2::new(-0.1, 0.05),
            kind: LoopKind::Weld { angle },
        }],
    );
    // Roughly assembled, thrown up and spinning; the stepper closes it.
    let mut state = State {
        t: 0.0,
        q: DVector::from_vec(vec![0.0, 0.0, 0.0, 0.2, 0.0, -angle]),
        u: DVector::from_vec(vec![1.0, 3.0, 6.0, 1.0, 3.0, 6.0]),
    };
    let mut stepper = Stepper::new(&model, StepSettings::strict(1e-4));
    stepper.assemble(&model, &mut state).unwrap();
    stepper.start(&model, &state);
    let com = |s: &State| {
        let p = |i: usize| Vec2::new(s.q[i], s.q[i + 1]) * if i == 0 { ma } else { mb };
        let v = |i: usize| Vec2::new(s.u[i], s.u[i + 1]) * if i == 0 { ma } else { mb };
        ((p(0) + p(3)) / (ma + mb), (v(0) + v(3)) / (ma + mb))
    };
    let spin = |s: &State| {
        let (c, v) = com(s);
        let own = |i: usize, m: f64| {
            let (r, w) = (
                Vec2::new(s.q[i], s.q[i + 1]) - c,
                Vec2::new(s.u[i], s.u[i + 1]) - v,
            );
            m * (r.x * w.y - r.y * w.x)
        };
        own(0, ma) + own(3, mb) + 0.01 * s.u[2] + 0.02 * s.u[5]
    };
    let ((c0, v0), l0) = (com(&state), spin(&state));
    let (mut worst_com, mut worst_spin, mut worst_angle) = (0.0_f64, 0.0_f64, 0.0_f64);
    for _ in 0..10_000 {
        let record = stepper
            .step(&model, &mut state, &Actuation::default())
            .unwrap();
        assert!(record.loop_error <= 1e-10);
        let t = state.t;
        let parabola = c0 + v0 * t + Vec2::new(0.0, -0.5 * g * t * t);
        worst_com = worst_com.max((com(&state).0 - parabola).norm());
        worst_spin = worst_spin.max((spin(&state) - l0).abs() / l0.abs());
        worst_angle = worst_angle.max((state.q[2] - state.q[5] - angle).abs());
    }
    eprintln!(
        "weld: centre of mass off the parabola by {worst_com:.2e} m, angular momentum by \
         {worst_spin:.2e} (relative), angle by {worst_angle:.2e} rad"
    );
    assert!(worst_com < 1e-10, "{worst_com}");
    assert!(worst_angle <= 1e-12, "{worst_angle}");
    assert!(worst_spin < 1e-3, "{worst_spin}");
}
