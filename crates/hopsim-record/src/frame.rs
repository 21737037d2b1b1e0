//! Plain data handed to recorders: the static description of a run and per-frame samples.

use crate::geometry::CoordinateUnit;
use hopsim_model::{Shape, Terrain};
use serde::{Deserialize, Serialize};
use std::fmt;

/// A body and the shapes drawn with it (body frame, relative to its centre of mass).
#[derive(Clone, Debug)]
pub struct BodyInfo {
    pub name: String,
    pub shapes: Vec<(String, Shape)>,
}

/// A joint, as recordings describe and draw it (docs/physics.md §1, §7).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointInfo {
    /// Index of the body on the joint (in `RecordingInfo::bodies`).
    pub body: usize,
    /// Index of its parent body; `None`: the world (a pinned base).
    pub parent: Option<usize>,
    /// The joint's anchor: in the parent's frame relative to its centre of mass, or the
    /// world point of a pinned base, m.
    pub anchor_m: [f64; 2],
    /// The joint point on the child, in its frame relative to its centre of mass, m.
    pub child_point_m: [f64; 2],
    /// Revolute or prismatic.
    pub kind: JointInfoKind,
}

/// What a recorded joint lets the child do.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum JointInfoKind {
    /// Rotation about the anchor.
    Revolute,
    /// Translation along `axis` (a unit vector in the parent's frame): the child's joint
    /// point is at `anchor + s axis`.
    Prismatic {
        axis: [f64; 2],
        /// The extensions drawn as the joint's rail, `[lower, upper]`, m: its limits, or
        /// without them the span from 0 to the initial extension.
        stroke_m: [f64; 2],
    },
}

impl JointInfo {
    /// The joint's link in the world at `poses` (one per body): from the anchor on the
    /// parent to the child's joint point; for a prismatic joint a segment of length `|s|`
    /// along the axis.
    pub fn link(&self, poses: &[BodyPose]) -> [[f64; 2]; 2] {
        let anchor = match self.parent {
            Some(p) => world_point(&poses[p], self.anchor_m),
            None => self.anchor_m,
        };
        [anchor, world_point(&poses[self.body], self.child_point_m)]
    }

    /// A prismatic joint on a body: its parent and its rail in the parent's frame, from
    /// the anchor moved by the lower to the upper extension of `stroke_m` along the axis.
    pub fn rail(&self) -> Option<(usize, [[f64; 2]; 2])> {
        match (self.parent, self.kind) {
            (Some(parent), JointInfoKind::Prismatic { axis, stroke_m }) => {
                let at = |s: f64| {
                    [
                        self.anchor_m[0] + s * axis[0],
                        self.anchor_m[1] + s * axis[1],
                    ]
                };
                Some((parent, [at(stroke_m[0]), at(stroke_m[1])]))
            }
            _ => None,
        }
    }

    /// Whether the joint is prismatic.
    pub fn is_prismatic(&self) -> bool {
        matches!(self.kind, JointInfoKind::Prismatic { .. })
    }
}

/// The world point of `[x, y]` in the frame of a body at `pose`.
pub(crate) fn world_point(pose: &BodyPose, [x, y]: [f64; 2]) -> [f64; 2] {
    let (sin, cos) = pose.angle.sin_cos();
    [
        pose.position[0] + cos * x - sin * y,
        pose.position[1] + sin * x + cos * y,
    ]
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
    /// The unit of each coordinate, indexed like `coordinates`.
    pub coordinate_units: Vec<CoordinateUnit>,
    /// Bodies with their shapes.
    pub bodies: Vec<BodyInfo>,
    /// Names of the potential contacts (indexed by `ContactSample::contact`).
    pub contacts: Vec<String>,
    /// The joints of the bodies that hang on one (floating and fixed bases have none).
    pub joints: Vec<JointInfo>,
    /// The loop joints (docs/physics.md §8).
    pub loops: Vec<crate::LoopInfo>,
    /// Names of the springs (indexed like `Frame::springs`).
    pub springs: Vec<String>,
    /// The terrain to draw.
    pub terrain: Terrain,
    /// Step size, s.
    pub dt: f64,
    /// Weight `m g` of the whole robot, N. Sets the scale of the contact-force arrows in
    /// Rerun (an arrow as long as the robot is a force equal to its weight); a value that
    /// is not positive and finite falls back to 0.01 m/N.
    pub weight_newtons: f64,
    /// Whether a controller drives the robot (actuator torque and work are recorded
    /// either way; the Rerun view plots them only then).
    pub actuated: bool,
    /// What the recorded actuator value is: a torque (N m) or a force (N, a prismatic
    /// joint's motor).
    pub actuator: ActuatorQuantity,
    /// The model's actuators (docs/physics.md §7.4), in the order of their controls
    /// ([`Frame::controls`], [`Frame::actuator_efforts`]); empty without.
    pub actuators: Vec<ActuatorInfo>,
}

/// An actuator as recordings name it.
#[derive(Clone, Debug, PartialEq)]
pub struct ActuatorInfo {
    /// Its name.
    pub name: String,
    /// What it exerts at its joint: a torque (revolute joint, N m) or a force (prismatic
    /// joint, N).
    pub effort: ActuatorQuantity,
}

impl ActuatorInfo {
    /// The column of its control: `control_<name>`.
    pub fn control_column(&self) -> String {
        format!("control_{}", self.name)
    }

    /// The column of its effort: `effort_<name>_Nm` or `effort_<name>_N`.
    pub fn effort_column(&self) -> String {
        let unit = match self.effort {
            ActuatorQuantity::Torque => "Nm",
            ActuatorQuantity::Force => "N",
        };
        format!("effort_{}_{unit}", self.name)
    }
}

/// The kind of the recorded actuator value ([`Frame::actuator_torque`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ActuatorQuantity {
    /// A torque in a revolute joint or between two bodies, N m.
    #[default]
    Torque,
    /// A force along a prismatic joint, N.
    Force,
}

impl ActuatorQuantity {
    /// The name of its column and field: `actuator_torque_Nm` or `actuator_force_N`.
    pub fn column(self) -> &'static str {
        match self {
            ActuatorQuantity::Torque => "actuator_torque_Nm",
            ActuatorQuantity::Force => "actuator_force_N",
        }
    }

    /// In words, for legends: `actuator torque` or `actuator force`.
    pub fn words(self) -> &'static str {
        match self {
            ActuatorQuantity::Torque => "actuator torque",
            ActuatorQuantity::Force => "actuator force",
        }
    }
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
    /// The contact's friction is indeterminate (its normal and tangential rows are
    /// dependent, docs/physics.md §4.8): it was resolved without friction, so
    /// `impulse_tangent` is 0 and the percussion drawn is the normal one only.
    pub friction_indeterminate: bool,
}

/// Energies at a frame, J (docs/physics.md §6).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct EnergySample {
    pub kinetic: f64,
    pub potential: f64,
    pub spring: f64,
    pub actuator_work: f64,
    pub dissipated: f64,
    pub balance_error: f64,
}

impl EnergySample {
    /// The field names, in the order of [`EnergySample::values`].
    pub const NAMES: [&'static str; 6] = [
        "kinetic",
        "potential",
        "spring",
        "actuator_work",
        "dissipated",
        "balance_error",
    ];

    /// The energies of a step's ledger (docs/physics.md §6).
    pub fn from_ledger(e: &hopsim_step::EnergyLedger) -> Self {
        Self {
            kinetic: e.kinetic,
            potential: e.potential,
            spring: e.spring,
            actuator_work: e.actuator_work,
            dissipated: e.dissipated(),
            balance_error: e.balance_error(),
        }
    }

    /// The energies in the order of [`EnergySample::NAMES`] (the column order of the
    /// recordings).
    pub fn values(&self) -> [f64; 6] {
        [
            self.kinetic,
            self.potential,
            self.spring,
            self.actuator_work,
            self.dissipated,
            self.balance_error,
        ]
    }
}

/// Decimals of a recorded time: 1 ps, far below the smallest step (`simulation.dt ≥ 1e-9
/// s`), so distinct steps keep distinct times.
pub const TIME_DECIMALS: i32 = 12;

/// The time `t` (s) as recordings, events and summaries write it: rounded to
/// [`TIME_DECIMALS`] decimals, so that the time of step `k`, `t0 + k·Δt` in floating point
/// (e.g. `0.45170000000000005`), reads as the decimal it stands for (`0.4517`). Times too
/// large for the rounding to be exact (beyond about 9000 s) are returned unchanged.
pub fn recorded_time(t: f64) -> f64 {
    let scale = 10f64.powi(TIME_DECIMALS);
    let scaled = t * scale;
    // Exact integers only up to 2^53.
    if !scaled.is_finite() || scaled.abs() >= 9.0e15 {
        return t;
    }
    scaled.round() / scale
}

/// One recorded instant.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Simulation time, s ([`recorded_time`]).
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
    /// The controls of the model's actuators in this step (one per
    /// [`RecordingInfo::actuators`]).
    pub controls: &'a [f64],
    /// The torque (N m) or force (N) each actuator exerts at its joint, `gear · force`
    /// at the frame's state (MuJoCo's `qfrc_actuator` on that joint).
    pub actuator_efforts: &'a [f64],
}

/// What kind of discrete event happened. Serialised (MCAP `/hopsim/events`) with a `kind`
/// tag in snake case and SI units in the field names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EventKind {
    /// A contact started carrying load after a flight phase.
    Touchdown { contact: String },
    /// The robot left the ground (no contact carries load).
    TakeOff,
    /// A brake locked a relative rotation; `impulse` is the angular impulse transferred,
    /// N m s (docs/physics.md §5.3, `ζ`).
    Brake {
        #[serde(rename = "impulse_Nms")]
        impulse: f64,
    },
    /// A switchable shape (the cane) was extended or retracted.
    ShapeSwitch { shape: String, active: bool },
    /// A contact of a switchable shape (the cane's tip) started carrying load.
    ShapeContact { contact: String },
    /// An impulse was applied by the controller, N s or N m s.
    AppliedImpulse { magnitude: f64 },
    /// A joint stop (`<body>/lower` or `<body>/upper`) started carrying load: its
    /// percussion in that step, N m s (revolute joint) or N s (prismatic joint)
    /// (docs/physics.md §7).
    JointLimit { limit: String, impulse: f64 },
    /// An impact at `contact` added `energy` J (its percussions' work over the step's mean
    /// velocity was positive): Newton's law with `ε_T ≠ ε_N` and friction can do that
    /// (docs/physics.md §4.7).
    EnergyCreated {
        contact: String,
        #[serde(rename = "energy_J")]
        energy: f64,
    },
    /// A frictional contact started carrying load while its bodies could move relative to
    /// each other along one direction only there: its friction is indeterminate (a jam of
    /// rigid Coulomb friction), and it is resolved without it (docs/physics.md §4.8);
    /// `impulse` is its normal percussion, N s.
    IndeterminateFriction { contact: String, impulse: f64 },
}

impl EventKind {
    /// The `kind` tag, e.g. `"take_off"`.
    pub fn name(&self) -> &'static str {
        match self {
            EventKind::Touchdown { .. } => "touchdown",
            EventKind::TakeOff => "take_off",
            EventKind::Brake { .. } => "brake",
            EventKind::ShapeSwitch { .. } => "shape_switch",
            EventKind::ShapeContact { .. } => "shape_contact",
            EventKind::AppliedImpulse { .. } => "applied_impulse",
            EventKind::JointLimit { .. } => "joint_limit",
            EventKind::EnergyCreated { .. } => "energy_created",
            EventKind::IndeterminateFriction { .. } => "indeterminate_friction",
        }
    }
}

/// The event's fields as `key=value` pairs, e.g. `impulse_Nms=0.059` (empty for a take-off).
impl fmt::Display for EventKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EventKind::Touchdown { contact } | EventKind::ShapeContact { contact } => {
                write!(f, "contact={contact}")
            }
            EventKind::TakeOff => Ok(()),
            EventKind::Brake { impulse } => write!(f, "impulse_Nms={impulse:?}"),
            EventKind::ShapeSwitch { shape, active } => {
                write!(f, "shape={shape} active={active}")
            }
            EventKind::AppliedImpulse { magnitude } => write!(f, "magnitude={magnitude:?}"),
            EventKind::JointLimit { limit, impulse } => {
                write!(f, "limit={limit} impulse={impulse:?}")
            }
            EventKind::EnergyCreated { contact, energy } => {
                write!(f, "contact={contact} energy_J={energy:?}")
            }
            EventKind::IndeterminateFriction { contact, impulse } => {
                write!(f, "contact={contact} impulse={impulse:?}")
            }
        }
    }
}

/// A discrete event at a time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    /// Time, s ([`recorded_time`]).
    #[serde(rename = "t_s")]
    pub t: f64,
    /// Step index.
    pub step: u64,
    #[serde(flatten)]
    pub kind: EventKind,
}

/// The sizes a [`Frame`] of a recording must have; recorders check every frame against
/// them so that a mismatch (a bug in the caller) is an error rather than a corrupt file.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameLayout {
    coordinates: usize,
    bodies: usize,
    contacts: usize,
    springs: usize,
    shapes: usize,
    actuators: usize,
}

impl FrameLayout {
    pub(crate) fn of(info: &RecordingInfo) -> Self {
        Self {
            coordinates: info.coordinates.len(),
            bodies: info.bodies.len(),
            contacts: info.contacts.len(),
            springs: info.springs.len(),
            shapes: info.bodies.iter().map(|b| b.shapes.len()).sum(),
            actuators: info.actuators.len(),
        }
    }

    /// `Err` names the first entry count of `frame` that does not match.
    pub(crate) fn check(&self, frame: &Frame<'_>) -> Result<(), String> {
        let counts = [
            ("q", frame.q.len(), self.coordinates),
            ("u", frame.u.len(), self.coordinates),
            ("bodies", frame.bodies.len(), self.bodies),
            ("springs", frame.springs.len(), self.springs),
            ("shapes_active", frame.shapes_active.len(), self.shapes),
            ("controls", frame.controls.len(), self.actuators),
            (
                "actuator_efforts",
                frame.actuator_efforts.len(),
                self.actuators,
            ),
        ];
        for (what, found, expected) in counts {
            if found != expected {
                return Err(format!(
                    "frame at step {} has {found} {what} entries, the recording describes {expected}",
                    frame.step
                ));
            }
        }
        match frame.contacts.iter().find(|c| c.contact >= self.contacts) {
            Some(c) => Err(format!(
                "frame at step {} names contact {}, the recording describes {}",
                frame.step, c.contact, self.contacts
            )),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn recorded_times_read_as_the_step_times_they_stand_for() {
        let dt = 2e-4;
        // k·Δt in floating point carries round-off in the last digits.
        assert_eq!(format!("{:?}", 2259.0 * dt), "0.45180000000000003");
        assert_eq!(format!("{:?}", recorded_time(2259.0 * dt)), "0.4518");
        // Every step of a long run keeps its own time, equal to k·Δt within round-off.
        let mut last = f64::NEG_INFINITY;
        for k in (0..200_000_u32).step_by(7) {
            let t = recorded_time(f64::from(k) * 1e-9 + 1.0);
            assert!(t > last && (t - (f64::from(k) * 1e-9 + 1.0)).abs() < 1e-12);
            last = t;
        }
        assert_eq!(recorded_time(-0.30000000000000004), -0.3);
        assert_eq!(recorded_time(1e20), 1e20);
    }
    use super::*;

    #[test]
    fn event_names_are_the_serialised_kind_tags() {
        let kinds = [
            EventKind::Touchdown {
                contact: "c".into(),
            },
            EventKind::TakeOff,
            EventKind::Brake { impulse: 0.05 },
            EventKind::ShapeSwitch {
                shape: "cane".into(),
                active: true,
            },
            EventKind::ShapeContact {
                contact: "cane/terrain0".into(),
            },
            EventKind::AppliedImpulse { magnitude: 1.0 },
            EventKind::JointLimit {
                limit: "rod/lower".into(),
                impulse: 0.9,
            },
        ];
        for kind in kinds {
            let event = Event {
                t: 0.5,
                step: 3,
                kind,
            };
            let json = serde_json::to_value(&event).unwrap();
            assert_eq!(json["kind"], event.kind.name());
            assert_eq!(
                (json["t_s"].as_f64(), json["step"].as_u64()),
                (Some(0.5), Some(3))
            );
            assert_eq!(serde_json::from_value::<Event>(json).unwrap(), event);
        }
    }
}
