//! Controllers: each step they read the state and fill an [`Actuation`] (torques,
//! impulses, brakes) and switch contact shapes (docs/physics.md §5.3, §5.4).

mod config;
mod momentum_impulse;
mod pulse;
mod signal;

pub use config::{CaneMode, ControllerConfig, MomentumImpulseConfig, PulseConfig, Release};
pub use momentum_impulse::MomentumImpulse;
pub use pulse::Pulse;
pub use signal::ControlSignal;

use hopsim_model::{Kinematics, Model};
use hopsim_step::{check_lock, Actuation, ActuationError, State};

/// What a controller sees before a step.
pub struct ControlInput<'a> {
    /// The model.
    pub model: &'a Model,
    /// State at the start of the step.
    pub state: &'a State,
    /// Step size `Δt`, s: the step runs from `state.t` to `state.t + Δt`, and the forces of
    /// the midpoint scheme act at `t^M = state.t + Δt/2` (docs/physics.md §4).
    pub dt: f64,
    /// Kinematics at the start of the step.
    pub kinematics: &'a Kinematics,
    /// Whether any contact carried a normal percussion in the previous step.
    pub in_contact: bool,
    /// Whether each shape is currently switched on.
    pub shapes_active: &'a [bool],
}

/// What a controller did in a step besides its actuation, for records and events.
#[derive(Clone, Debug, PartialEq)]
pub enum ControlEvent {
    /// A brake locks the relative rotation of `body` and `other` in this step.
    Brake { body: usize, other: usize },
    /// Shape `shape` is switched on (`true`) or off.
    ShapeSwitch { shape: usize, active: bool },
}

impl ControlEvent {
    /// Checks the event against `model`: its bodies and shape exist, a brake joins two
    /// bodies.
    pub fn validate(&self, model: &hopsim_model::Model) -> Result<(), ActuationError> {
        match *self {
            ControlEvent::Brake { body, other } => check_lock(model, "brake", body, other),
            ControlEvent::ShapeSwitch { shape, .. } => {
                let shapes = model.shapes().len();
                if shape < shapes {
                    Ok(())
                } else {
                    Err(ActuationError::NoSuchShape {
                        command: "switch_shape",
                        shape,
                        shapes,
                    })
                }
            }
        }
    }
}

/// A controller: called once before every step.
pub trait Controller: Send {
    /// Fills `actuation` (already cleared) and pushes any events of this step.
    fn control(
        &mut self,
        input: &ControlInput<'_>,
        actuation: &mut Actuation,
        events: &mut Vec<ControlEvent>,
    );
}

/// A controller that does nothing.
pub struct Passive;

impl Controller for Passive {
    fn control(&mut self, _: &ControlInput<'_>, _: &mut Actuation, _: &mut Vec<ControlEvent>) {}
}

impl ControllerConfig {
    /// The controller these settings describe.
    pub fn build(&self, model: &Model) -> Box<dyn Controller> {
        match self {
            ControllerConfig::Passive => Box::new(Passive),
            ControllerConfig::MomentumImpulse(c) => {
                Box::new(MomentumImpulse::new(c.clone(), model))
            }
            ControllerConfig::Pulse(c) => Box::new(Pulse::new(c.clone())),
        }
    }
}

/// Lowest gap of an enabled-or-not shape against the terrain (`+∞` if it touches nothing).
pub fn shape_gap(model: &Model, kinematics: &Kinematics, shape: usize) -> f64 {
    (0..model.contacts().len())
        .filter(|&i| model.contacts()[i].shape == shape)
        .filter_map(|i| model.contact_geometry(kinematics, i))
        .map(|g| g.gap)
        .fold(f64::INFINITY, f64::min)
}
