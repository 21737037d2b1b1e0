//! Small models with known mechanics, shared by the stepper's tests and benchmark.
#![allow(dead_code)]

use hopsim_model::{
    Body, ContactMaterial, Joint, JointCoordinate, Model, Shape, ShapeInstance, Terrain, Vec2,
};
use hopsim_step::{Actuation, State, StepRecord, StepSettings, Stepper};
use nalgebra::DVector;

pub const G: f64 = 9.81;

pub fn material(friction: f64, restitution: f64) -> ContactMaterial {
    ContactMaterial {
        friction,
        restitution_normal: restitution,
        restitution_tangent: 0.0,
    }
}

fn base(name: &str, mass: f64, inertia: f64) -> Body {
    Body {
        name: name.into(),
        mass,
        inertia,
        joint: None,
    }
}

/// One body carrying one shape on `terrain`.
pub fn single_body(
    mass: f64,
    inertia: f64,
    shape: Shape,
    terrain: Terrain,
    mat: ContactMaterial,
) -> Model {
    Model::new(
        vec![base("body", mass, inertia)],
        vec![ShapeInstance {
            name: "shape".into(),
            body: 0,
            shape,
        }],
        terrain,
        vec![],
        Vec2::new(0.0, -G),
        mat,
    )
    .unwrap()
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

/// Robbit of physics.md §5.3: off-centred disc plus a flywheel pivoting at the CoM,
/// coordinates `(x, y, φ, ψ)` with `ψ` absolute.
pub fn robbit() -> Model {
    let flywheel = Body {
        name: "flywheel".into(),
        mass: 0.431,
        inertia: 1.543e-3,
        joint: Some(Joint {
            parent: 0,
            pivot_in_parent: Vec2::zeros(),
            com_in_child: Vec2::zeros(),
            coordinate: JointCoordinate::Absolute,
            damping: 0.0,
        }),
    };
    Model::new(
        vec![base("disc", 0.974, 3.004e-3), flywheel],
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

pub fn stepper(model: &Model, dt: f64) -> Stepper {
    Stepper::new(
        model,
        StepSettings {
            dt,
            strict: true,
            ..StepSettings::default()
        },
    )
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
