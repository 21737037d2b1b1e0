//! Small models with known mechanics, shared by the stepper's tests, its benchmark and
//! the profiling example.
#![allow(dead_code)]

use hopsim_model::{
    Body, ContactMaterial, Joint, JointCoordinate, LoopJoint, LoopKind, Model, ModelBuilder, Shape,
    ShapeInstance, Terrain, Vec2,
};
use hopsim_step::{Actuation, State, StepRecord, StepSettings, Stepper, TorqueCommand};
use nalgebra::DVector;

pub const G: f64 = 9.81;

pub fn material(friction: f64, restitution: f64) -> ContactMaterial {
    ContactMaterial {
        friction,
        restitution_normal: restitution,
        restitution_tangent: 0.0,
    }
}

/// One body carrying one shape on `terrain` ([`Model::single_body`]).
pub fn single_body(
    mass: f64,
    inertia: f64,
    shape: Shape,
    terrain: Terrain,
    mat: ContactMaterial,
) -> Model {
    Model::single_body(mass, inertia, shape, terrain, mat).unwrap()
}

/// A disc of radius `r` whose centre of mass sits `a` below its centre at `φ = 0` (§2).
pub fn eccentric_disc(mass: f64, inertia: f64, r: f64, a: f64, mat: ContactMaterial) -> Model {
    single_body(
        mass,
        inertia,
        Shape::Circle {
            center: Vec2::new(0.0, a),
            radius: r,
        },
        Terrain::flat(0.0),
        mat,
    )
}

/// Robbit of docs/physics.md §5.3: off-centred disc plus a flywheel pivoting at the CoM,
/// coordinates `(x, y, φ, ψ)` with `ψ` absolute.
pub fn robbit() -> Model {
    Model::new(
        vec![
            Body::base("disc", 0.974, 3.004e-3),
            Body::flywheel("flywheel", 0.431, 1.543e-3, 0),
        ],
        vec![ShapeInstance {
            name: "disc".into(),
            body: 0,
            shape: Shape::Circle {
                center: Vec2::new(0.0, 0.1),
                radius: 0.2,
            },
        }],
        Terrain::flat(0.0),
        vec![],
        Vec2::new(0.0, -G),
        material(1.0, 0.0),
    )
    .unwrap()
}

/// The motor torque `torque` on body 1 (Robbit's flywheel, the hopper's lower body), its
/// reaction on body 0.
pub fn motor(torque: f64) -> TorqueCommand {
    TorqueCommand {
        body: 1,
        reaction: Some(0),
        torque,
    }
}

pub fn stepper(model: &Model, dt: f64) -> Stepper {
    Stepper::new(model, StepSettings::strict(dt))
}

pub fn state(q: &[f64], u: &[f64]) -> State {
    State {
        t: 0.0,
        q: DVector::from_row_slice(q),
        u: DVector::from_row_slice(u),
    }
}

/// Runs `steps` passive steps, calling `each` after every one.
pub fn run(
    model: &Model,
    stepper: &mut Stepper,
    state: &mut State,
    steps: usize,
    mut each: impl FnMut(&State, &StepRecord),
) {
    let act = Actuation::default();
    stepper.start(model, state);
    for _ in 0..steps {
        let rec = stepper.step(model, state, &act).expect("step");
        each(state, rec);
    }
}

/// A two-body hopper in the spirit of CaneBot (docs/physics.md §5.4): an upper body, a lower
/// body on a damped relative joint carrying a circular-arc foot and a point cane, two
/// damped springs across the joint (one an extension spring), friction `mu`.
pub fn two_body_hopper(mu: f64) -> Model {
    use hopsim_model::Spring;
    let lower = Body {
        name: "lower".into(),
        mass: 0.8,
        inertia: 0.006,
        joint: Some(Joint {
            coordinate: JointCoordinate::Relative,
            damping: 0.01,
            ..Joint::revolute(Some(0), Vec2::new(0.0, -0.08), Vec2::new(0.01, -0.06))
        }),
    };
    let half = std::f64::consts::FRAC_PI_2;
    let shapes = vec![
        ShapeInstance {
            name: "foot".into(),
            body: 1,
            shape: Shape::Arc {
                center: Vec2::new(0.0, 0.05),
                radius: 0.15,
                start: -half - 0.8,
                end: -half + 0.8,
            },
        },
        ShapeInstance {
            name: "cane".into(),
            body: 1,
            shape: Shape::Point {
                position: Vec2::new(0.14, -0.09),
            },
        },
    ];
    let spring = |name: &str, x: f64, tension_only: bool| Spring {
        name: name.into(),
        body_a: 0,
        point_a: Vec2::new(x, 0.0),
        body_b: 1,
        point_b: Vec2::new(x, -0.02),
        stiffness: 150.0,
        rest_length: 0.09,
        damping: 0.3,
        tension_only,
    };
    Model::new(
        vec![Body::base("upper", 1.2, 0.01), lower],
        shapes,
        Terrain::flat(0.0),
        vec![spring("front", 0.05, false), spring("back", -0.05, true)],
        Vec2::new(0.0, -G),
        material(mu, 0.0),
    )
    .unwrap()
}

/// The two-body hopper standing with its foot's lowest point at height `clearance`.
pub fn two_body_hopper_state(model: &Model, clearance: f64) -> State {
    let mut s = state(&[0.0, 0.0, 0.0, 0.0], &[0.0; 4]);
    let mut kinematics = hopsim_model::Kinematics::new(model);
    kinematics.update(model, &s.q, &s.u);
    let lowest = (0..model.contacts().len())
        .filter_map(|i| model.contact_geometry(&kinematics, i))
        .map(|g| g.gap)
        .fold(f64::INFINITY, f64::min);
    s.q[1] = clearance - lowest;
    s
}

/// A uniform bar of length `l` and mass `m` on `joint`, its inertia about its centre.
pub fn bar(name: &str, l: f64, m: f64, joint: Joint) -> Body {
    let mut body = Body::base(name, m, m * l * l / 12.0);
    body.joint = Some(joint);
    body
}

/// A four-bar linkage of uniform 1 kg bars (docs/physics.md §8) with link lengths
/// `[a, b, c, d]`: the crank `a` pinned at the origin, the coupler `b` on its end, the
/// rocker `c` pinned at `(d, 0)`, the loop joint `coupler-rocker` closing the coupler's end
/// on the rocker's. Coordinates `(θ_2, θ_3 − θ_2, θ_4)`: the crank's angle, the coupler's
/// relative to it, the rocker's. `crank_inertia` replaces the crank's own (a flywheel).
pub fn four_bar([a, b, c, d]: [f64; 4], gravity: f64, crank_inertia: Option<f64>) -> Model {
    let mut crank = bar(
        "crank",
        a,
        1.0,
        Joint::revolute(None, Vec2::zeros(), Vec2::new(a / 2.0, 0.0)),
    );
    if let Some(i) = crank_inertia {
        crank.inertia = i;
    }
    let coupler = bar(
        "coupler",
        b,
        1.0,
        Joint::revolute(Some(0), Vec2::new(a / 2.0, 0.0), Vec2::new(b / 2.0, 0.0)),
    );
    let mut rocker_joint = Joint::revolute(None, Vec2::new(d, 0.0), Vec2::new(c / 2.0, 0.0));
    rocker_joint.coordinate = JointCoordinate::Absolute;
    let rocker = bar("rocker", c, 1.0, rocker_joint);
    closed_chain(
        vec![crank, coupler, rocker],
        gravity,
        vec![LoopJoint {
            name: "coupler-rocker".into(),
            body_a: 1,
            point_a: Vec2::new(b / 2.0, 0.0),
            body_b: Some(2),
            point_b: Vec2::new(c / 2.0, 0.0),
            kind: LoopKind::Revolute,
        }],
    )
}

/// A model of `bodies` without shapes or terrain contacts under gravity `gravity` (along
/// `−y`), closed by the loop joints `loops` (docs/physics.md §8).
pub fn closed_chain(bodies: Vec<Body>, gravity: f64, loops: Vec<LoopJoint>) -> Model {
    let mut builder = ModelBuilder::new(
        bodies,
        vec![],
        Terrain::flat(-100.0),
        vec![],
        Vec2::new(0.0, -gravity),
        ContactMaterial::inelastic(0.0),
    )
    .unwrap();
    for joint in loops {
        builder.add_loop(joint).unwrap();
    }
    builder.build()
}
