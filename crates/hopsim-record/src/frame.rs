//! Plain data handed to recorders: the static description of a run and per-frame samples.

use hopsim_model::{Shape, Terrain};
use serde::Serialize;

/// A body and the shapes drawn with it (body frame, relative to its centre of mass).
#[derive(Clone, Debug)]
pub struct BodyInfo {
    pub name: String,
    pub shapes: Vec<(String, Shape)>,
}

/// What a recording needs to know once, before the first frame.
#[derive(Clone, Debug)]
pub struct RecordingInfo {
    /// Scene name (the `[meta] title` or the file stem).
    pub scene: String,
    /// Path of the scene file.
    pub scene_path: String,
    /// The scene file's text, stored in the recording so it can be rerun.
    pub scene_text: String,
    /// Names of the generalised coordinates, e.g. `["x", "y", "phi", "psi"]`.
    pub coordinates: Vec<String>,
    /// Bodies with their shapes.
    pub bodies: Vec<BodyInfo>,
    /// Names of the potential contacts (indexed by `ContactSample::contact`).
    pub contacts: Vec<String>,
    /// Names of the springs (indexed like `Frame::springs`).
    pub springs: Vec<String>,
    /// The terrain to draw.
    pub terrain: Terrain,
    /// Step size, s.
    pub dt: f64,
}

/// Pose of one body.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct BodyPose {
    /// Centre of mass, m.
    pub position: [f64; 2],
    /// Absolute angle, rad.
    pub angle: f64,
}

/// One contact of the step's index set.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ContactSample {
    /// Index into `RecordingInfo::contacts`.
    pub contact: usize,
    /// Contact point, m.
    pub point: [f64; 2],
    /// Unit normal (terrain towards body).
    pub normal: [f64; 2],
    /// Normal percussion `Λ_N`, N s.
    pub impulse_normal: f64,
    /// Tangential percussion `Λ_T`, N s.
    pub impulse_tangent: f64,
    /// "open", "stick" or "slip".
    pub state: &'static str,
}

/// Energies at a frame, J (physics.md §6).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct EnergySample {
    pub kinetic: f64,
    pub potential: f64,
    pub spring: f64,
    pub actuator_work: f64,
    pub dissipated: f64,
    pub balance_error: f64,
}

/// One recorded instant.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Simulation time, s.
    pub t: f64,
    /// Step index.
    pub step: u64,
    /// Generalised coordinates.
    pub q: &'a [f64],
    /// Generalised velocities.
    pub u: &'a [f64],
    /// Pose of every body (same order as `RecordingInfo::bodies`).
    pub bodies: &'a [BodyPose],
    /// Whole-robot centre of mass, m.
    pub com: [f64; 2],
    /// Contacts of this step.
    pub contacts: &'a [ContactSample],
    /// Spring end points (world), same order as `RecordingInfo::springs`.
    pub springs: &'a [([f64; 2], [f64; 2])],
    /// Whether each shape is active (a retracted cane is not), per body then shape order.
    pub shapes_active: &'a [bool],
    /// Energies.
    pub energy: EnergySample,
    /// Actuator torque commanded this step, N m (0 when idle).
    pub actuator_torque: f64,
}

/// What kind of discrete event happened.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EventKind {
    /// A contact started carrying load after a flight phase.
    Touchdown { contact: String },
    /// The robot left the ground (no contact carries load).
    TakeOff,
    /// A brake locked a relative rotation; `impulse` is the angular impulse transferred, N m s.
    Brake { impulse: f64 },
    /// A switchable shape (the cane) was extended or retracted.
    ShapeSwitch { shape: String, active: bool },
    /// An impulse was applied by the controller, N s or N m s.
    AppliedImpulse { magnitude: f64 },
}

/// A discrete event at a time.
#[derive(Clone, Debug, Serialize)]
pub struct Event {
    /// Time, s.
    pub t: f64,
    /// Step index.
    pub step: u64,
    #[serde(flatten)]
    pub kind: EventKind,
}
