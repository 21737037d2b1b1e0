//! Actuators: motors and position and velocity servos, each in one joint (docs/physics.md
//! §7.4). The force law is MuJoCo's for a joint transmission: with the actuator's length
//! `l = gear · s` and velocity `v = gear · ṡ` (`s` the joint position),
//!
//! ```text
//! force = clamp(gain · clamp(ctrl, ctrl_range) + b₀ + b₁ l + b₂ v, force_range)
//! generalised force = gear · force along the joint's coordinate
//! ```
//!
//! with `gain = 1, b = 0` (motor), `gain = k_p, b = (0, −k_p, −k_v)` (position servo) and
//! `gain = k_v, b = (0, 0, −k_v)` (velocity servo).

use crate::{Kinematics, Model, ModelError};

/// What an actuator's force follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ActuatorKind {
    /// `force = ctrl`.
    Motor,
    /// `force = k_p (ctrl − l) − k_v v`: a spring to the control's position and a damper.
    Position { kp: f64, kv: f64 },
    /// `force = k_v (ctrl − v)`: a damper to the control's velocity.
    Velocity { kv: f64 },
}

impl ActuatorKind {
    /// The kind's name in scenes: `motor`, `position` or `velocity`.
    pub fn name(&self) -> &'static str {
        match self {
            ActuatorKind::Motor => "motor",
            ActuatorKind::Position { .. } => "position",
            ActuatorKind::Velocity { .. } => "velocity",
        }
    }
}

/// An actuator in the joint of one body.
#[derive(Clone, Debug, PartialEq)]
pub struct Actuator {
    /// Name in scenes, records and front ends.
    pub name: String,
    /// The body whose joint it drives (a revolute or prismatic joint).
    pub body: usize,
    pub kind: ActuatorKind,
    /// Transmission ratio: the length is `gear · s`, the generalised force `gear · force`.
    pub gear: f64,
    /// Bounds the control is clamped to (MuJoCo's `ctrlrange` when `ctrllimited`).
    pub ctrl_range: Option<[f64; 2]>,
    /// Bounds the force is clamped to (MuJoCo's `forcerange` when `forcelimited`), N m or N.
    pub force_range: Option<[f64; 2]>,
}

/// An actuator's force at one state, split as the stepper takes it (docs/physics.md §7.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActuatorForce {
    /// The force (clamped), N m or N, before the gear.
    pub force: f64,
    /// `gear² · (−b₂)`: the damping coefficient of the force's velocity term, or 0 when
    /// the force is clamped (it then does not depend on the velocity).
    pub damping: f64,
}

impl Actuator {
    /// A motor with gear 1 and no bounds in the joint of `body`.
    pub fn motor(name: impl Into<String>, body: usize) -> Self {
        Self {
            name: name.into(),
            body,
            kind: ActuatorKind::Motor,
            gear: 1.0,
            ctrl_range: None,
            force_range: None,
        }
    }

    /// The gain on the control.
    pub fn gain(&self) -> f64 {
        match self.kind {
            ActuatorKind::Motor => 1.0,
            ActuatorKind::Position { kp, .. } => kp,
            ActuatorKind::Velocity { kv } => kv,
        }
    }

    /// The bias terms `(b₀, b₁, b₂)` on `(1, l, v)`.
    pub fn bias(&self) -> [f64; 3] {
        match self.kind {
            ActuatorKind::Motor => [0.0; 3],
            ActuatorKind::Position { kp, kv } => [0.0, -kp, -kv],
            ActuatorKind::Velocity { kv } => [0.0, 0.0, -kv],
        }
    }

    /// The control clamped to the control range.
    #[inline]
    pub fn clamp_control(&self, ctrl: f64) -> f64 {
        match self.ctrl_range {
            Some([lo, hi]) => ctrl.clamp(lo, hi),
            None => ctrl,
        }
    }

    /// The force at control `ctrl`, joint position `s` and joint velocity `rate`.
    #[inline]
    pub fn force(&self, ctrl: f64, s: f64, rate: f64) -> ActuatorForce {
        let [b0, b1, b2] = self.bias();
        let (l, v) = (self.gear * s, self.gear * rate);
        let raw = self.gain() * self.clamp_control(ctrl) + b0 + b1 * l + b2 * v;
        match self.force_range {
            Some([lo, hi]) if !(lo..=hi).contains(&raw) => ActuatorForce {
                force: raw.clamp(lo, hi),
                damping: 0.0,
            },
            _ => ActuatorForce {
                force: raw,
                damping: -b2 * self.gear * self.gear,
            },
        }
    }

    /// Whether the force has a velocity term (a servo with `k_v ≠ 0`).
    pub fn has_damping(&self) -> bool {
        self.bias()[2] != 0.0
    }
}

/// Whether `a` fits `model`: a named actuator of its own on a body with a joint coordinate,
/// finite non-negative gains, a finite non-zero gear, ordered ranges.
pub(crate) fn check_actuator(a: &Actuator, model: &Model) -> Result<(), ModelError> {
    let bad = |reason: String| ModelError::BadActuator {
        actuator: a.name.clone(),
        reason,
    };
    let count = model.bodies().len();
    let Some(body) = model.bodies().get(a.body) else {
        return Err(ModelError::UnknownBody {
            owner: "actuator",
            name: a.name.clone(),
            body: a.body,
            count,
        });
    };
    if a.name.is_empty() {
        return Err(bad("an actuator needs a name".into()));
    }
    if model.actuators().iter().any(|b| b.name == a.name) {
        return Err(bad("the name is taken by another actuator".into()));
    }
    if !body.joint.as_ref().is_some_and(|j| j.has_coordinate()) {
        return Err(bad(format!(
            "body '{}' has no joint with a coordinate to drive (a floating or fixed body)",
            body.name
        )));
    }
    let finite_non_negative = |v: f64| v.is_finite() && v >= 0.0;
    match a.kind {
        ActuatorKind::Motor => {}
        ActuatorKind::Position { kp, kv } => {
            if !finite_non_negative(kp) || !finite_non_negative(kv) {
                return Err(bad(format!(
                    "kp and kv must be finite and non-negative, got kp = {kp}, kv = {kv}"
                )));
            }
        }
        ActuatorKind::Velocity { kv } => {
            if !finite_non_negative(kv) {
                return Err(bad(format!("kv must be finite and non-negative, got {kv}")));
            }
        }
    }
    if !a.gear.is_finite() || a.gear == 0.0 {
        return Err(bad(format!(
            "gear must be finite and not zero, got {}",
            a.gear
        )));
    }
    for (what, range) in [("control", a.ctrl_range), ("force", a.force_range)] {
        if let Some([lo, hi]) = range {
            // Infinite bounds are allowed (one-sided); NaN and inverted ranges are not.
            if lo.is_nan()
                || hi.is_nan()
                || lo > hi
                || lo == f64::INFINITY
                || hi == f64::NEG_INFINITY
            {
                return Err(bad(format!(
                    "the {what} range must be [lower, upper] with lower <= upper, got [{lo}, {hi}]"
                )));
            }
        }
    }
    Ok(())
}

impl Model {
    /// The actuators, in the order the controls are given.
    pub fn actuators(&self) -> &[Actuator] {
        &self.actuators
    }

    /// The index of the actuator called `name`.
    pub fn actuator_index(&self, name: &str) -> Option<usize> {
        self.actuators.iter().position(|a| a.name == name)
    }

    /// How many actuators have a velocity term (dampers in the step, §4.9).
    pub fn actuator_damper_capacity(&self) -> usize {
        self.actuators.iter().filter(|a| a.has_damping()).count()
    }

    /// Actuator `a`'s force at the kinematics' state under the control `ctrl`.
    #[inline]
    pub fn actuator_force(&self, kinematics: &Kinematics, a: usize, ctrl: f64) -> ActuatorForce {
        let actuator = &self.actuators[a];
        let b = actuator.body;
        actuator.force(ctrl, kinematics.joint_position(b), kinematics.joint_rate(b))
    }

    /// Adds the actuators' generalised forces (MuJoCo's `qfrc_actuator`) at the kinematics'
    /// state under `controls` (one per actuator; those past its end are 0) to `out`
    /// (length `n`).
    pub fn add_actuator_forces_to(
        &self,
        kinematics: &Kinematics,
        controls: &[f64],
        out: &mut [f64],
    ) {
        for (a, actuator) in self.actuators.iter().enumerate() {
            let f = self
                .actuator_force(kinematics, a, control(controls, a))
                .force;
            self.add_joint_force_to(kinematics, actuator.body, actuator.gear * f, out);
        }
    }

    /// The actuators' generalised forces as the step takes them (docs/physics.md §7.4):
    /// adds to `applied` each force without the velocity term of an unclamped servo, and
    /// writes that term as a damper (coefficient `gear² k_v` into `coefficients`, row into
    /// `rows`, row-major, length `n`) to be taken at the step's mean velocity (§4.9).
    /// Returns the number of dampers written; the slices hold
    /// [`Model::actuator_damper_capacity`] dampers. Controls past the end of `controls`
    /// are 0.
    pub fn actuator_forces_split(
        &self,
        kinematics: &Kinematics,
        controls: &[f64],
        applied: &mut [f64],
        coefficients: &mut [f64],
        rows: &mut [f64],
    ) -> usize {
        let n = self.dof();
        let mut count = 0;
        for (a, actuator) in self.actuators.iter().enumerate() {
            let b = actuator.body;
            let ActuatorForce { force, damping } =
                self.actuator_force(kinematics, a, control(controls, a));
            if damping == 0.0 {
                self.add_joint_force_to(kinematics, b, actuator.gear * force, applied);
                continue;
            }
            // The velocity term `−gear² k_v ṡ` leaves the force for the damper.
            let rest = actuator.gear * force + damping * kinematics.joint_rate(b);
            self.add_joint_force_to(kinematics, b, rest, applied);
            coefficients[count] = damping;
            let row = &mut rows[count * n..(count + 1) * n];
            row.fill(0.0);
            self.add_joint_force_to(kinematics, b, 1.0, row);
            count += 1;
        }
        count
    }
}

/// Control `a` of `controls`, 0 past its end.
#[inline]
fn control(controls: &[f64], a: usize) -> f64 {
    controls.get(a).copied().unwrap_or(0.0)
}
