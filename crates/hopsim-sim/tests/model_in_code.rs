//! A model built in Rust code alone runs exactly as the scene file that describes it: Robbit
//! (docs/physics.md §5.3) from bodies, a shape, a terrain and a controller, a [`Setup`]
//! without any scene, against `scenes/robbit.toml`, step by step and bit for bit.

use hopsim_control::{ControllerConfig, MomentumImpulseConfig, Release};
use hopsim_model::{Body, ContactMaterial, Model, Shape, ShapeInstance, Terrain, Vec2};
use hopsim_sim::{Observer, RunError, Settings, Setup, StepView};
use hopsim_step::State;
use nalgebra::DVector;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Robbit as docs/physics.md §5.3 gives it, written without a scene file.
fn robbit_in_code() -> Setup {
    let bodies = vec![
        Body::base("disc", 0.974, 3.004e-3),
        Body::flywheel("flywheel", 0.431, 1.543e-3, 0),
    ];
    let shapes = vec![ShapeInstance {
        name: "disc".into(),
        body: 0,
        shape: Shape::Circle {
            center: Vec2::new(0.0, 0.1),
            radius: 0.2,
        },
    }];
    let model = Model::new(
        bodies,
        shapes,
        Terrain::flat(0.0),
        Vec::new(),
        Vec2::new(0.0, -9.81),
        ContactMaterial::inelastic(1.0),
    )
    .unwrap();
    let settings = Settings {
        speed_window: 10.0,
        ..Settings::new(20.0, 2e-4)
    };
    let controller = ControllerConfig::MomentumImpulse(MomentumImpulseConfig {
        flywheel: 1,
        torque: 0.384,
        impulse_limit: 0.059,
        release: Release::Touchdown { rearm_timeout: 1.0 },
        hold_brake: false,
    });
    Setup {
        title: "Robbit".into(),
        path: PathBuf::from("robbit-in-code"),
        text: String::new(),
        settings,
        model: Arc::new(model),
        initial: State::at_rest(DVector::from_vec(vec![0.0, 0.1, 0.0, 0.0])),
        controller,
        switchable: Vec::new(),
        control_signals: Vec::new(),
        coordinates: ["x", "y", "phi", "psi"].map(String::from).to_vec(),
    }
}

/// Every step's state and contact percussions.
#[derive(Default)]
struct Trace(Vec<f64>);

impl Observer for Trace {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.0.push(view.state.t);
        self.0
            .extend(view.state.q.iter().chain(view.state.u.iter()));
        for c in &view.record.contacts {
            self.0.extend([c.impulse_normal, c.impulse_tangent]);
        }
        Ok(())
    }
}

#[test]
fn robbit_built_in_code_runs_as_its_scene_file_bit_for_bit() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robbit.toml");
    let file = hopsim_scene::load(&path, &[]).unwrap();
    let code = robbit_in_code();
    assert_eq!(code.title, file.title);
    assert_eq!(code.settings, file.settings);
    assert_eq!(code.controller, file.controller);
    assert_eq!(code.coordinates, file.coordinates);
    assert_eq!(code.initial, file.initial);
    assert_eq!(format!("{:?}", code.model), format!("{:?}", file.model));
    let (mut from_code, mut from_file) = (Trace::default(), Trace::default());
    let a = hopsim_sim::run(&code, &mut from_code).unwrap();
    let b = hopsim_sim::run(&file, &mut from_file).unwrap();
    assert_eq!(from_code.0.len(), from_file.0.len());
    // Bit for bit: the same numbers, NaN-free, in the same order.
    let same = from_code
        .0
        .iter()
        .zip(&from_file.0)
        .all(|(x, y)| x.to_bits() == y.to_bits());
    assert!(same, "the runs differ");
    // And it is a run worth comparing: Robbit hops forward.
    assert!(a.hops > 30 && a.distance_m > 10.0, "{a:?}");
    assert_eq!(
        (a.hops, a.distance_m.to_bits()),
        (b.hops, b.distance_m.to_bits())
    );
}
