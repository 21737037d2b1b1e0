//! Hands the run to recorders: frames at the recording rate, every event exactly.

use crate::Setup;
use crate::{Observer, RunError, StepView};
use hopsim_control::ControllerConfig;
use hopsim_model::{JointKind, LoopJoint, LoopKind};
use hopsim_record::{
    recorded_time, ActuatorInfo, ActuatorQuantity, BodyInfo, BodyPose, ContactSample,
    CoordinateUnit, EnergySample, Event, EventKind, Frame, JointInfo, JointInfoKind, LoopInfo,
    LoopInfoKind, RecorderSet, RecordingInfo, Stop,
};
use std::path::PathBuf;

/// The static description of a scene for recorders.
pub fn recording_info(scene: &Setup) -> RecordingInfo {
    let model = &scene.model;
    RecordingInfo {
        scene: scene.title.clone(),
        scene_path: scene.path.display().to_string(),
        scene_text: scene.text.clone(),
        coordinates: scene.coordinates.clone(),
        coordinate_units: (0..scene.coordinates.len())
            .map(|i| {
                if model.coordinate_is_length(i) {
                    CoordinateUnit::Metre
                } else {
                    CoordinateUnit::Radian
                }
            })
            .collect(),
        bodies: model
            .bodies()
            .iter()
            .enumerate()
            .map(|(b, body)| BodyInfo {
                name: body.name.clone(),
                shapes: model
                    .shapes()
                    .iter()
                    .filter(|s| s.body == b)
                    .map(|s| (s.name.clone(), s.shape.clone()))
                    .collect(),
            })
            .collect(),
        // Terrain contacts, then body–body contacts (docs/physics.md §7).
        contacts: (0..model.contact_count())
            .map(|i| model.contact_name(i).to_string())
            .collect(),
        joints: joint_infos(scene),
        loops: model.loops().iter().map(loop_info).collect(),
        springs: model.springs().iter().map(|s| s.name.clone()).collect(),
        terrain: model.terrain().clone(),
        dt: scene.settings.dt,
        weight_newtons: model.total_mass() * model.gravity().norm(),
        actuated: !matches!(scene.controller, ControllerConfig::Passive),
        actuator: match &scene.controller {
            ControllerConfig::Pulse(c) if c.drives_force(&scene.model) => ActuatorQuantity::Force,
            _ => ActuatorQuantity::Torque,
        },
        actuators: model
            .actuators()
            .iter()
            .map(|a| ActuatorInfo {
                name: a.name.clone(),
                effort: match model.bodies()[a.body].joint.as_ref().map(|j| j.kind) {
                    Some(JointKind::Prismatic { .. }) => ActuatorQuantity::Force,
                    _ => ActuatorQuantity::Torque,
                },
            })
            .collect(),
    }
}

/// A loop joint as recordings draw it (docs/physics.md §8).
fn loop_info(joint: &LoopJoint) -> LoopInfo {
    let point = |v: hopsim_model::Vec2| [v.x, v.y];
    LoopInfo {
        name: joint.name.clone(),
        kind: match joint.kind {
            LoopKind::Revolute => LoopInfoKind::Revolute,
            LoopKind::Weld { angle } => LoopInfoKind::Weld { angle_rad: angle },
            LoopKind::Distance { length } => LoopInfoKind::Distance { length_m: length },
            LoopKind::Slot { axis } => LoopInfoKind::Slot { axis: point(axis) },
        },
        body_a: joint.body_a,
        point_a_m: point(joint.point_a),
        body_b: joint.body_b,
        point_b_m: point(joint.point_b),
    }
}

/// The revolute and prismatic joints of `scene` (docs/physics.md §7): a prismatic joint's rail
/// spans its limits, or without them the initial extension.
fn joint_infos(scene: &Setup) -> Vec<JointInfo> {
    let model = &scene.model;
    let point = |v: hopsim_model::Vec2| [v.x, v.y];
    model
        .bodies()
        .iter()
        .enumerate()
        .filter_map(|(b, body)| {
            let joint = body.joint.as_ref()?;
            let kind = match joint.kind {
                JointKind::Fixed { .. } => return None,
                JointKind::Revolute => JointInfoKind::Revolute,
                JointKind::Prismatic { axis } => {
                    let s0 = model.coordinate(b).map_or(0.0, |i| scene.initial.q[i]);
                    let stroke_m = match joint.limits {
                        Some(l) if l.lower.is_finite() && l.upper.is_finite() => [l.lower, l.upper],
                        _ => [s0.min(0.0), s0.max(0.0)],
                    };
                    JointInfoKind::Prismatic {
                        axis: point(axis),
                        stroke_m,
                    }
                }
            };
            Some(JointInfo {
                body: b,
                parent: joint.parent,
                anchor_m: point(joint.pivot_in_parent),
                child_point_m: point(-joint.com_in_child),
                kind,
            })
        })
        .collect()
}

/// Builds frames from steps and passes them, with the events, to a [`RecorderSet`].
pub struct RecordingObserver {
    recorders: RecorderSet,
    every: u64,
    bodies: Vec<BodyPose>,
    contacts: Vec<ContactSample>,
    springs: Vec<([f64; 2], [f64; 2])>,
    shapes_active: Vec<bool>,
    /// The actuators' efforts at their joints (`gear · force`).
    efforts: Vec<f64>,
    /// Per joint stop: whether it carried load in the previous step (a hit is a stop that
    /// starts carrying load).
    limit_loaded: Vec<bool>,
    limit_loaded_now: Vec<bool>,
    limit_events: Vec<Event>,
    /// The last step shown to the observer and its time, s.
    last_step: (u64, f64),
}

impl RecordingObserver {
    /// Records every `round(1 / (rate Δt))`-th step (at least every step) and every step
    /// with an event, at the scene's `simulation.record_rate`.
    pub fn new(recorders: RecorderSet, scene: &Setup) -> Self {
        Self::with_rate(recorders, scene, scene.settings.record_rate)
    }

    /// [`RecordingObserver::new`] at `rate` frames per second of simulated time.
    pub fn with_rate(recorders: RecorderSet, scene: &Setup, rate: f64) -> Self {
        let every = (1.0 / (rate * scene.settings.dt)).round().max(1.0) as u64;
        Self {
            recorders,
            every,
            bodies: Vec::new(),
            contacts: Vec::new(),
            springs: Vec::new(),
            shapes_active: Vec::new(),
            efforts: Vec::new(),
            limit_loaded: vec![false; scene.model.limits().len()],
            limit_loaded_now: vec![false; scene.model.limits().len()],
            limit_events: Vec::new(),
            last_step: (0, 0.0),
        }
    }

    /// Whether any recorder is attached.
    pub fn records_anything(&self) -> bool {
        !self.recorders.is_empty()
    }

    /// Completes every recording.
    pub fn finish(self) -> Result<(), RunError> {
        Ok(self.recorders.finish()?)
    }

    /// Keeps what was recorded of a run that stopped early because of `reason` (a
    /// [`RunError`], or a caller's own reason), under the outputs' partial names, saying
    /// why and after which step (the last one shown to this observer); returns the files
    /// kept.
    pub fn finish_partial(self, reason: &dyn std::fmt::Display) -> Result<Vec<PathBuf>, RunError> {
        let (step, t) = self.last_step;
        let stop = Stop {
            reason: reason.to_string(),
            step,
            t,
        };
        Ok(self.recorders.finish_partial(&stop)?)
    }
}

impl Observer for RecordingObserver {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.last_step = (view.record.step, view.state.t);
        if self.recorders.is_empty() {
            return Ok(());
        }
        for ev in view.events {
            self.recorders.event(ev)?;
        }
        self.joint_limit_hits(view)?;
        let step = view.record.step;
        if !step.is_multiple_of(self.every)
            && view.events.is_empty()
            && self.limit_events.is_empty()
        {
            return Ok(());
        }
        self.frame(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.last_step = (view.record.step, view.state.t);
        if self.recorders.is_empty() {
            return Ok(());
        }
        self.frame(view)
    }
}

impl RecordingObserver {
    /// Records a `joint_limit` event for every joint stop that starts carrying load in this
    /// step (docs/physics.md §7), with its percussion. A stop carries load when its percussion
    /// exceeds `LIMIT_LOAD` (round-off of a stop held closed without load stays below).
    fn joint_limit_hits(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        const LIMIT_LOAD: f64 = 1e-9;
        self.limit_events.clear();
        self.limit_loaded_now.fill(false);
        for l in view.record.limits.iter().filter(|l| l.impulse > LIMIT_LOAD) {
            self.limit_loaded_now[l.limit] = true;
            if !self.limit_loaded[l.limit] {
                self.limit_events.push(Event {
                    t: recorded_time(view.record.t),
                    step: view.record.step,
                    kind: EventKind::JointLimit {
                        limit: view.model.limits()[l.limit].name.clone(),
                        impulse: l.impulse,
                    },
                });
            }
        }
        std::mem::swap(&mut self.limit_loaded, &mut self.limit_loaded_now);
        for ev in &self.limit_events {
            self.recorders.event(ev)?;
        }
        Ok(())
    }

    /// Records the frame of `view`.
    fn frame(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        let step = view.record.step;
        let ws = view.kinematics;
        let model = view.model;
        self.bodies.clear();
        self.bodies
            .extend((0..model.bodies().len()).map(|b| BodyPose {
                position: [ws.position(b).x, ws.position(b).y],
                angle: ws.angle(b),
            }));
        self.contacts.clear();
        // Body–body contacts follow the terrain contacts in `RecordingInfo::contacts`; their
        // point is the probe's and their percussion the one on the probe's body.
        let terrain = model.contacts().len();
        let records = (view.record.contacts.iter().map(|c| (c, c.contact))).chain(
            view.record
                .pair_contacts
                .iter()
                .map(|c| (c, terrain + c.contact)),
        );
        self.contacts
            .extend(records.map(|(c, contact)| ContactSample {
                contact,
                point: [c.point.x, c.point.y],
                normal: [c.normal.x, c.normal.y],
                impulse_normal: c.impulse_normal,
                impulse_tangent: c.impulse_tangent,
                state: c.state.as_str(),
                friction_indeterminate: c.dependent,
            }));
        self.springs.clear();
        self.springs.extend((0..model.springs().len()).map(|s| {
            let (a, b) = model.spring_ends(ws, s);
            ([a.x, a.y], [b.x, b.y])
        }));
        self.shapes_active.clear();
        self.shapes_active.extend_from_slice(view.shapes_active);
        self.efforts.clear();
        self.efforts
            .extend(view.controls.iter().enumerate().map(|(a, &control)| {
                model.actuators()[a].gear * model.actuator_force(ws, a, control).force
            }));
        let com = model.center_of_mass(ws);
        let e = view.record.energy;
        self.recorders.frame(&Frame {
            t: recorded_time(view.state.t),
            step,
            q: view.state.q.as_slice(),
            u: view.state.u.as_slice(),
            bodies: &self.bodies,
            com: [com.x, com.y],
            contacts: &self.contacts,
            springs: &self.springs,
            shapes_active: &self.shapes_active,
            energy: EnergySample::from_ledger(&e),
            actuator_torque: view.torque,
            controls: view.controls,
            actuator_efforts: &self.efforts,
        })?;
        Ok(())
    }
}
