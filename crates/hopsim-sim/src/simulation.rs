//! One step of a scene: controller → actuation → step → events → observers.

use crate::{
    panic_message, FlightEvent, FlightTracker, Observer, RunError, Setup, StateProblem, StepView,
};
use hopsim_control::{ControlEvent, ControlInput, Controller};
use hopsim_record::{recorded_time, Event, EventKind};
use hopsim_step::{
    check_controls, Actuation, ActuationError, ContactState, ImpulseCommand, State, StepRecord,
    Stepper,
};
use std::sync::Arc;

/// A [`Setup`] being simulated: the stepper, the controller and the state.
pub struct Simulation {
    setup: Arc<Setup>,
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
    /// Whether any contact does (without, no step looks for a shape's first contact).
    any_switchable: bool,
    /// Per contact: whether it carried load in the previous step, and in this one.
    was_loaded: Vec<bool>,
    loaded_now: Vec<bool>,
    /// The contacts resolved without friction, for `indeterminate_friction` events.
    friction_indeterminate: Onsets,
    /// `(step, t, message)` of a step that panicked: every later step returns that
    /// internal error again.
    failed: Option<(u64, f64, String)>,
    /// Test hook: the step that panics on purpose ([`PANIC_AT_STEP`]).
    panic_at: Option<u64>,
}

/// A contact approaching faster than this many steps of free fall give is an impact
/// ([`Simulation`]'s `energy_created` events).
pub const IMPACT_STEPS: f64 = 10.0;

/// Work of an impact's percussions above which it counts as having added energy, J.
pub const CREATED_ENERGY: f64 = 1e-9;

/// Environment variable naming a step in which every [`Simulation`] created afterwards
/// panics on purpose: a test hook for the panic boundary (docs/reliability.md, "Panics").
pub const PANIC_AT_STEP: &str = "HOPSIM_PANIC_AT_STEP";

/// The step of [`PANIC_AT_STEP`], if set to a whole number.
fn panic_at_step() -> Option<u64> {
    std::env::var(PANIC_AT_STEP).ok()?.trim().parse().ok()
}

impl Simulation {
    /// A simulation of `setup` at its initial state; switchable shapes start switched off.
    /// The setup is copied (its model is shared: an `Arc`); a scene is a setup.
    pub fn new(setup: &Setup) -> Self {
        Self::shared(Arc::new(setup.clone()))
    }

    /// A simulation of a setup shared with other owners (many simulations of one setup, a
    /// front end that keeps them apart from its lifetime), at the setup's initial state.
    pub fn shared(setup: Arc<Setup>) -> Self {
        Self::with_setup(setup)
    }

    fn with_setup(scene: Arc<Setup>) -> Self {
        let model = &scene.model;
        let mut stepper = Stepper::new(model, scene.step_settings());
        let mut shapes_active = vec![true; model.shapes().len()];
        for &s in &scene.switchable {
            shapes_active[s] = false;
        }
        for (i, c) in model.contacts().iter().enumerate() {
            stepper.set_contact_enabled(i, shapes_active[c.shape]);
        }
        stepper.start(model, &scene.initial);
        let controller = scene.controller.build(model);
        let state = scene.initial.clone();
        let switchable_contact: Vec<bool> = model
            .contacts()
            .iter()
            .map(|c| scene.switchable.contains(&c.shape))
            .collect();
        let contacts = model.contacts().len();
        let contact_count = model.contact_count();
        let flight = FlightTracker::starting(stepper.record().min_gap);
        let controls = vec![0.0; model.actuators().len()];
        Self {
            setup: scene,
            controller,
            stepper,
            state,
            actuation: Actuation {
                controls,
                ..Actuation::default()
            },
            control_events: Vec::new(),
            events: Vec::new(),
            shapes_active,
            loaded: !flight.airborne(),
            flight,
            any_switchable: switchable_contact.contains(&true),
            switchable_contact,
            was_loaded: vec![false; contacts],
            loaded_now: vec![false; contacts],
            friction_indeterminate: Onsets::new(contact_count),
            failed: None,
            panic_at: panic_at_step(),
        }
    }

    /// What is being simulated.
    pub fn setup(&self) -> &Setup {
        &self.setup
    }

    /// Restarts the run at `state` (time, `q`, `u`): the stepper starts anew there (its
    /// step count, energy ledger and LCP statistics restart), flight phases are counted
    /// afresh; the controller and the shapes switched on stay as they are. `state` is
    /// checked as a scene's `[initial]` is: its values ([`crate::check_state`]) and
    /// its geometry ([`crate::check_start`]: no active shape inside the terrain or
    /// another body, no joint past a stop). On an error nothing changes.
    pub fn set_state(&mut self, state: State) -> Result<(), StateProblem> {
        crate::check_state(&self.setup, &state)?;
        let inactive: Vec<bool> = self.shapes_active.iter().map(|a| !a).collect();
        crate::check_start(&self.setup.model, &state, &inactive)?;
        self.restart_at(state);
        Ok(())
    }

    /// [`Simulation::set_state`] for a state a simulation of the scene reached: only its
    /// values are checked, since the time-stepping leaves contacts and stops in load
    /// slightly penetrated (no position correction, docs/physics.md §4.6).
    pub fn restore_state(&mut self, state: State) -> Result<(), StateProblem> {
        crate::check_state(&self.setup, &state)?;
        self.restart_at(state);
        Ok(())
    }

    fn restart_at(&mut self, state: State) {
        self.state = state;
        self.stepper.start(&self.setup.model, &self.state);
        self.actuation.clear();
        self.events.clear();
        self.flight = FlightTracker::starting(self.stepper.record().min_gap);
        self.loaded = !self.flight.airborne();
        self.was_loaded.fill(false);
        self.friction_indeterminate = Onsets::new(self.setup.model.contact_count());
    }

    /// Keeps the stepper's energy account or not ([`Stepper::set_ledger`]; on by default):
    /// a run whose observers read no energies can switch it off before its first step.
    pub fn set_ledger(&mut self, on: bool) {
        self.stepper.set_ledger(on);
    }

    /// Switches the energy account on, started anew at the current state
    /// ([`hopsim_step::Stepper::restart_ledger`]): for a simulation run without it and
    /// watched for energies from now on.
    pub fn restart_ledger(&mut self) {
        self.stepper.restart_ledger(&self.setup.model);
    }

    /// The actuation of the last step (the controller's or the caller's).
    pub fn actuation(&self) -> &Actuation {
        &self.actuation
    }

    /// Whether the world (the terrain, or a shape of a fixed body) carried a normal
    /// percussion in the last step (what a controller sees as `in_contact`); before the
    /// first step, whether the start touches the world.
    pub fn in_contact(&self) -> bool {
        self.loaded
    }

    /// Per shape (in the model's order), from the last step's contacts: whether it carried
    /// a normal percussion, into `loaded` (one flag per shape), and its contacts'
    /// percussions per unit time `Λ_N / Δt` and `Λ_T / Δt` (the mean forces over the
    /// step, N), into `forces` (two numbers per shape: normal, tangential). Each contact
    /// counts along its own normal, which points into the shape's body, and its tangent
    /// `t = (n_y, -n_x)` (docs/physics.md §4); a body–body contact counts for both its
    /// shapes, each in its own frame, so with the same two numbers (§7.3). Allocates
    /// nothing.
    pub fn shape_contacts_to(&self, loaded: &mut [bool], forces: &mut [f64]) {
        let model = &self.setup.model;
        let record = self.stepper.record();
        let per_second = 1.0 / self.setup.settings.dt;
        loaded.fill(false);
        forces.fill(0.0);
        let mut add = |shape: usize, c: &hopsim_step::ContactRecord| {
            loaded[shape] |= c.impulse_normal > 0.0;
            forces[2 * shape] += c.impulse_normal * per_second;
            forces[2 * shape + 1] += c.impulse_tangent * per_second;
        };
        for c in &record.contacts {
            add(model.contacts()[c.contact].shape, c);
        }
        for c in &record.pair_contacts {
            let pair = &model.pairs()[c.contact];
            add(pair.probe, c);
            add(pair.target, c);
        }
    }

    /// Whether each shape is switched on.
    pub fn shapes_active(&self) -> &[bool] {
        &self.shapes_active
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

    /// Takes one step and shows it to `observer`. A panic inside the step (a bug) is
    /// caught and returned as [`RunError::Internal`]; the simulation then refuses further
    /// steps with the same error.
    pub fn step(&mut self, observer: &mut dyn Observer) -> Result<(), RunError> {
        self.guarded(|sim| sim.control_and_advance(observer))
    }

    /// Runs one step `f` behind the panic boundary (see [`Simulation::step`]).
    fn guarded(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<(), RunError>,
    ) -> Result<(), RunError> {
        let internal = |(step, t, message): &(u64, f64, String)| RunError::Internal {
            step: *step,
            t: *t,
            message: message.clone(),
        };
        if let Some(failed) = &self.failed {
            return Err(internal(failed));
        }
        let (step, t) = (self.stepper.record().step + 1, self.state.t);
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(self))) {
            Ok(result) => result,
            Err(payload) => {
                let failed = (step, t, panic_message(payload.as_ref()));
                let error = internal(&failed);
                self.failed = Some(failed);
                Err(error)
            }
        }
    }

    /// The controls of the model's actuators (docs/physics.md §7.4), one each: held from
    /// step to step, set by [`Simulation::set_controls`], [`Simulation::step_with`] or the
    /// setup's control signals. All 0 at the start.
    pub fn controls(&self) -> &[f64] {
        &self.actuation.controls
    }

    /// Sets every actuator's control (one finite number each) for the steps to come.
    pub fn set_controls(&mut self, controls: &[f64]) -> Result<(), ActuationError> {
        let count = self.actuation.controls.len();
        if controls.len() != count {
            return Err(ActuationError::ControlCount {
                given: controls.len(),
                actuators: count,
            });
        }
        check_controls(&self.setup.model, controls)?;
        self.actuation.controls.copy_from_slice(controls);
        Ok(())
    }

    /// Sets actuator `actuator`'s control (a finite number) for the steps to come.
    pub fn set_control(&mut self, actuator: usize, value: f64) -> Result<(), ActuationError> {
        let actuators = self.actuation.controls.len();
        if actuator >= actuators {
            return Err(ActuationError::NoSuchActuator {
                actuator,
                actuators,
            });
        }
        if !value.is_finite() {
            return Err(ActuationError::ControlNotFinite {
                index: actuator,
                name: self.setup.model.actuators()[actuator].name.clone(),
                value,
            });
        }
        self.actuation.controls[actuator] = value;
        Ok(())
    }

    /// Writes the actuators' generalised forces at the current state under the current
    /// controls into `out` (length `n`; MuJoCo's `qfrc_actuator`, docs/physics.md §7.4).
    pub fn actuator_forces_to(&self, out: &mut [f64]) {
        out.fill(0.0);
        self.setup.model.add_actuator_forces_to(
            self.stepper.kinematics(),
            &self.actuation.controls,
            out,
        );
    }

    /// The scene's controller, then the step.
    fn control_and_advance(&mut self, observer: &mut dyn Observer) -> Result<(), RunError> {
        let model = &self.setup.model;
        self.actuation.clear();
        let t_mid = self.state.t + 0.5 * self.setup.settings.dt;
        for (a, signal) in &self.setup.control_signals {
            self.actuation.controls[*a] = signal.value(t_mid);
        }
        self.control_events.clear();
        self.events.clear();
        let input = ControlInput {
            model,
            state: &self.state,
            dt: self.setup.settings.dt,
            kinematics: self.stepper.kinematics(),
            in_contact: self.loaded,
            shapes_active: &self.shapes_active,
        };
        self.controller
            .control(&input, &mut self.actuation, &mut self.control_events);
        self.advance(observer)
    }

    /// Takes one step with `actuation` and `events` (brakes, shape switches) given by the
    /// caller in place of the scene's controller, which is not called in this step (its
    /// own state does not advance). A brake event names the lock of `actuation.locks` it
    /// engages, as the controllers' do. The actuators' controls given in `actuation`
    /// replace the first of the held ones and are held afterwards (empty: the held
    /// controls act; the setup's control signals do not). Commands the model cannot carry out (see
    /// [`hopsim_step::ActuationError`]) are refused before the step: [`RunError::Actuation`].
    /// Reuses the simulation's buffers: no allocation once they have grown to the
    /// commands' sizes.
    pub fn step_with(
        &mut self,
        actuation: &Actuation,
        events: &[ControlEvent],
        observer: &mut dyn Observer,
    ) -> Result<(), RunError> {
        // Field by field into the kept buffers (no allocation); the pattern names every
        // field, so a new kind of command cannot be left out silently.
        let model = &self.setup.model;
        actuation.validate(model)?;
        for e in events {
            e.validate(model)?;
        }
        let Actuation {
            torques,
            joint_forces,
            impulses,
            locks,
            controls,
        } = actuation;
        let own = &mut self.actuation;
        own.torques.clone_from(torques);
        own.joint_forces.clone_from(joint_forces);
        own.impulses.clone_from(impulses);
        own.locks.clone_from(locks);
        // Given controls replace the held ones (the rest keep theirs); none given: all kept.
        own.controls[..controls.len()].copy_from_slice(controls);
        self.control_events.clear();
        self.control_events.extend_from_slice(events);
        self.events.clear();
        self.guarded(|sim| sim.advance(observer))
    }

    /// The step itself, after the actuation and the control events are set.
    fn advance(&mut self, observer: &mut dyn Observer) -> Result<(), RunError> {
        let model = &self.setup.model;
        let (t0, step0) = (self.state.t, self.stepper.record().step);
        for ev in &self.control_events {
            if let ControlEvent::ShapeSwitch { shape, active } = *ev {
                self.shapes_active[shape] = active;
                for (i, c) in model.contacts().iter().enumerate() {
                    if c.shape == shape {
                        self.stepper.set_contact_enabled(i, active);
                    }
                }
                self.events.push(Event {
                    t: t0,
                    step: step0,
                    kind: EventKind::ShapeSwitch {
                        shape: model.shapes()[shape].name.clone(),
                        active,
                    },
                });
            }
        }
        if self.panic_at == Some(step0 + 1) {
            panic!("forced by {PANIC_AT_STEP}={} (a test hook)", step0 + 1);
        }
        let record = self
            .stepper
            .step(model, &mut self.state, &self.actuation)
            .map_err(|e| RunError::of_step(e, model))?;
        // Applied impulses act inside the step, as brakes do (N s for a point impulse,
        // N m s for a rotational one).
        for command in &self.actuation.impulses {
            let magnitude = match *command {
                ImpulseCommand::Point { impulse, .. } => impulse.norm(),
                ImpulseCommand::Rotational { impulse, .. } => impulse.abs(),
            };
            self.events.push(Event {
                t: record.t,
                step: record.step,
                kind: EventKind::AppliedImpulse { magnitude },
            });
        }
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
        // Loaded by the world: the terrain, or shapes of fixed bodies.
        self.loaded = record.in_contact()
            || record
                .pair_contacts
                .iter()
                .any(|c| c.state != ContactState::Open && model.pair_touches_world(c.contact));
        // A switchable shape's contact (the cane's tip) starting to carry load.
        if self.any_switchable {
            self.loaded_now.fill(false);
            for c in record
                .contacts
                .iter()
                .filter(|c| c.state != ContactState::Open)
            {
                self.loaded_now[c.contact] = true;
            }
            for (i, c) in model.contacts().iter().enumerate() {
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
        }
        impacts_creating_energy(model, record, self.setup.settings.dt, &mut self.events);
        self.friction_indeterminate
            .events(model, record, &mut self.events);
        let (step, min_gap) = (record.step, record.min_gap);
        match self.flight.update(self.state.t, step, self.loaded, min_gap) {
            Some(FlightEvent::TakeOff { t, step }) => self.events.push(Event {
                t,
                step,
                kind: EventKind::TakeOff,
            }),
            Some(FlightEvent::Touchdown { t, step }) => {
                let terrain = record.contacts.iter().map(|c| (c, c.contact));
                let world = record
                    .pair_contacts
                    .iter()
                    .filter(|c| model.pair_touches_world(c.contact))
                    .map(|c| (c, model.contacts().len() + c.contact));
                let contact = terrain
                    .chain(world)
                    .max_by(|a, b| a.0.impulse_normal.total_cmp(&b.0.impulse_normal))
                    .map(|(_, i)| model.contact_name(i).to_string())
                    .unwrap_or_default();
                self.events.push(Event {
                    t,
                    step,
                    kind: EventKind::Touchdown { contact },
                })
            }
            None => {}
        }
        for event in &mut self.events {
            event.t = recorded_time(event.t);
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
            model: &self.setup.model,
            state: &self.state,
            kinematics: self.stepper.kinematics(),
            record: self.stepper.record(),
            events: &self.events,
            shapes_active: &self.shapes_active,
            torque: match (
                self.actuation.torques.first(),
                self.actuation.joint_forces.first(),
            ) {
                (Some(t), _) => t.torque,
                (None, Some(f)) => f.force,
                (None, None) => 0.0,
            },
            controls: &self.actuation.controls,
        }
    }
}

/// An `energy_created` event for every contact of `record` whose impact added energy
/// (docs/physics.md §4.7): it approached faster than [`IMPACT_STEPS`] steps of free fall
/// give (an impact, not lasting contact, whose work over the step's mean velocity is the
/// scheme's `O(Δt²)` either way) and its percussions' work exceeds [`CREATED_ENERGY`].
fn impacts_creating_energy(
    model: &hopsim_model::Model,
    record: &hopsim_step::StepRecord,
    dt: f64,
    events: &mut Vec<Event>,
) {
    let impact = (IMPACT_STEPS * model.gravity().norm() * dt).max(1e-9);
    let terrain = record.contacts.iter().map(|c| (c, c.contact));
    let pairs = record
        .pair_contacts
        .iter()
        .map(|c| (c, model.contacts().len() + c.contact));
    for (c, i) in terrain.chain(pairs) {
        if c.approach_velocity < -impact && c.work > CREATED_ENERGY {
            events.push(Event {
                t: record.t,
                step: record.step,
                kind: EventKind::EnergyCreated {
                    contact: model.contact_name(i).to_string(),
                    energy: c.work,
                },
            });
        }
    }
}

/// Which contacts had a property in the last step, to report when it starts.
struct Onsets {
    before: Vec<bool>,
    now: Vec<bool>,
}

impl Onsets {
    fn new(contacts: usize) -> Self {
        Self {
            before: vec![false; contacts],
            now: vec![false; contacts],
        }
    }

    /// An `indeterminate_friction` event for each frictional contact of `record` that
    /// carries load while its rows are dependent (docs/physics.md §4.8) and did not in the
    /// step before.
    fn events(
        &mut self,
        model: &hopsim_model::Model,
        record: &StepRecord,
        events: &mut Vec<Event>,
    ) {
        self.now.fill(false);
        let terrain = record.contacts.iter().map(|c| (c, c.contact));
        let pairs = record
            .pair_contacts
            .iter()
            .map(|c| (c, model.contacts().len() + c.contact));
        for (c, i) in terrain.chain(pairs) {
            let frictional = model.material(i).friction > 0.0;
            if !(c.dependent && frictional && c.state != ContactState::Open) {
                continue;
            }
            self.now[i] = true;
            if !self.before[i] {
                events.push(Event {
                    t: record.t,
                    step: record.step,
                    kind: EventKind::IndeterminateFriction {
                        contact: model.contact_name(i).to_string(),
                        impulse: c.impulse_normal,
                    },
                });
            }
        }
        std::mem::swap(&mut self.before, &mut self.now);
    }
}
