//! One step of a scene: controller → actuation → step → events → observers.

use crate::{FlightEvent, FlightTracker, Observer, RunError, StepView};
use hopsim_control::{ControlEvent, ControlInput, Controller};
use hopsim_record::{Event, EventKind};
use hopsim_scene::Scene;
use hopsim_step::{Actuation, ContactState, State, Stepper};

/// A scene being simulated: the stepper, the controller and the state.
pub struct Simulation<'s> {
    scene: &'s Scene,
    stepper: Stepper,
    controller: Box<dyn Controller>,
    state: State,
    actuation: Actuation,
    control_events: Vec<ControlEvent>,
    events: Vec<Event>,
    shapes_active: Vec<bool>,
    flight: FlightTracker,
    loaded: bool,
    /// Per contact: whether it belongs to a switchable shape (a cane).
    switchable_contact: Vec<bool>,
    /// Per contact: whether it carried load in the previous step, and in this one.
    was_loaded: Vec<bool>,
    loaded_now: Vec<bool>,
}

impl<'s> Simulation<'s> {
    /// A simulation at the scene's initial state; switchable shapes start switched off.
    pub fn new(scene: &'s Scene) -> Self {
        let model = &scene.model;
        let mut stepper = Stepper::new(model, scene.step_settings());
        let mut shapes_active = vec![true; model.shapes.len()];
        for &s in &scene.switchable {
            shapes_active[s] = false;
        }
        for (i, c) in model.contacts.iter().enumerate() {
            stepper.set_contact_enabled(i, shapes_active[c.shape]);
        }
        stepper.start(model, &scene.initial);
        Self {
            scene,
            controller: scene.controller.build(model),
            stepper,
            state: scene.initial.clone(),
            actuation: Actuation::default(),
            control_events: Vec::new(),
            events: Vec::new(),
            shapes_active,
            flight: FlightTracker::default(),
            loaded: true,
            switchable_contact: model
                .contacts
                .iter()
                .map(|c| scene.switchable.contains(&c.shape))
                .collect(),
            was_loaded: vec![false; model.contacts.len()],
            loaded_now: vec![false; model.contacts.len()],
        }
    }

    /// The scene being simulated.
    pub fn scene(&self) -> &'s Scene {
        self.scene
    }

    /// The current state.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The stepper (its record, statistics and kinematics).
    pub fn stepper(&self) -> &Stepper {
        &self.stepper
    }

    /// Flight phases so far.
    pub fn hops(&self) -> u64 {
        self.flight.hops()
    }

    /// Takes one step and shows it to `observer`.
    pub fn step(&mut self, observer: &mut dyn Observer) -> Result<(), RunError> {
        let model = &self.scene.model;
        self.actuation.clear();
        self.control_events.clear();
        self.events.clear();
        let input = ControlInput {
            model,
            state: &self.state,
            dt: self.scene.settings.dt,
            kinematics: self.stepper.kinematics(),
            in_contact: self.loaded,
            shapes_active: &self.shapes_active,
        };
        self.controller
            .control(&input, &mut self.actuation, &mut self.control_events);
        let (t0, step0) = (self.state.t, self.stepper.record().step);
        for ev in &self.control_events {
            if let ControlEvent::ShapeSwitch { shape, active } = *ev {
                self.shapes_active[shape] = active;
                for (i, c) in model.contacts.iter().enumerate() {
                    if c.shape == shape {
                        self.stepper.set_contact_enabled(i, active);
                    }
                }
                self.events.push(Event {
                    t: t0,
                    step: step0,
                    kind: EventKind::ShapeSwitch {
                        shape: model.shapes[shape].name.clone(),
                        active,
                    },
                });
            }
        }
        let record = self.stepper.step(model, &mut self.state, &self.actuation)?;
        // A brake acts inside the step: the event carries the impulse actually transferred
        // (a brake held engaged in later steps is not a new event).
        for ev in &self.control_events {
            if let ControlEvent::Brake { body, other } = *ev {
                let lock = record
                    .locks
                    .iter()
                    .find(|l| (l.body, l.other) == (body, other));
                self.events.push(Event {
                    t: record.t,
                    step: record.step,
                    kind: EventKind::Brake {
                        impulse: lock.map_or(0.0, |l| l.impulse.abs()),
                    },
                });
            }
        }
        self.loaded = record.in_contact();
        // A switchable shape's contact (the cane's tip) starting to carry load.
        self.loaded_now.fill(false);
        for c in record
            .contacts
            .iter()
            .filter(|c| c.state != ContactState::Open)
        {
            self.loaded_now[c.contact] = true;
        }
        for (i, c) in model.contacts.iter().enumerate() {
            if self.switchable_contact[i] && self.loaded_now[i] && !self.was_loaded[i] {
                self.events.push(Event {
                    t: record.t,
                    step: record.step,
                    kind: EventKind::ShapeContact {
                        contact: c.name.clone(),
                    },
                });
            }
        }
        std::mem::swap(&mut self.was_loaded, &mut self.loaded_now);
        let (step, min_gap) = (record.step, record.min_gap);
        match self.flight.update(self.state.t, step, self.loaded, min_gap) {
            Some(FlightEvent::TakeOff { t, step }) => self.events.push(Event {
                t,
                step,
                kind: EventKind::TakeOff,
            }),
            Some(FlightEvent::Touchdown { t, step }) => {
                let contact = record
                    .contacts
                    .iter()
                    .max_by(|a, b| a.impulse_normal.total_cmp(&b.impulse_normal))
                    .map(|c| model.contacts[c.contact].name.clone())
                    .unwrap_or_default();
                self.events.push(Event {
                    t,
                    step,
                    kind: EventKind::Touchdown { contact },
                })
            }
            None => {}
        }
        observer.on_step(&self.view())
    }

    /// Shows the state before the first step to `observer` ([`Observer::on_start`]).
    pub fn start(&self, observer: &mut dyn Observer) -> Result<(), RunError> {
        observer.on_start(&self.view())
    }

    /// What observers see of the last step (or of the initial state before any).
    pub fn view(&self) -> StepView<'_> {
        StepView {
            model: &self.scene.model,
            state: &self.state,
            kinematics: self.stepper.kinematics(),
            record: self.stepper.record(),
            events: &self.events,
            shapes_active: &self.shapes_active,
            torque: self.actuation.torques.first().map_or(0.0, |t| t.torque),
        }
    }
}
