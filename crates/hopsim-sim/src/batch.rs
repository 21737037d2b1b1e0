//! Many simulations of one model stepped together: a [`Batch`].
//!
//! Each copy is a [`Simulation`] of its own [`Setup`] (usually one setup shared by all,
//! its model behind one `Arc`), with its own state, controls (docs/physics.md §7.4) and
//! controller. A batch step splits the copies into contiguous chunks, one per thread of a
//! fixed pool; each thread sets its copies' controls from the batch's array, steps those
//! that are not done and writes their rows of the batch's flat arrays. A copy never sees another, so copy `i` equals a
//! single [`Simulation`] with the same inputs bit for bit, whatever the thread count.
//! Brakes and shape switches ([`Batch::set_commands`]) are velocity locks between two
//! bodies (docs/physics.md §4.4) and contact shapes (a cane) engaged per copy from masks, as
//! a caller's [`Simulation::step_with`].

use crate::{Observer, RunError, Setup, Simulation, StateProblem};
use hopsim_control::ControlEvent;
use hopsim_step::{Actuation, ActuationError, State};
use std::sync::Arc;

/// Why a batch cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    #[error("a batch needs at least one copy")]
    Empty,
    #[error("a batch needs at least one thread")]
    NoThreads,
    #[error(
        "copy {copy} has {coordinates} coordinates and {actuators} actuators, copy 0 \
         {expected_coordinates} and {expected_actuators}: every copy must have the same sizes"
    )]
    Sizes {
        copy: usize,
        coordinates: usize,
        actuators: usize,
        expected_coordinates: usize,
        expected_actuators: usize,
    },
    #[error(
        "copy {copy} has {shapes} shapes, copy 0 {expected}: every copy must have the same shapes"
    )]
    Shapes {
        copy: usize,
        shapes: usize,
        expected: usize,
    },
    #[error("cannot start {threads} threads: {message}")]
    Threads { threads: usize, message: String },
    #[error("copy {copy} is out of range: the batch has {copies} copies")]
    NoSuchCopy { copy: usize, copies: usize },
    #[error("copy {copy}: {problem}")]
    State { copy: usize, problem: StateProblem },
    #[error("brakes and switches: {0}")]
    Brake(ActuationError),
    #[error("copy {copy} is watched by an observer (a recording): detach it first")]
    Observed { copy: usize },
    #[error("copy {copy}: {error}")]
    Run { copy: usize, error: RunError },
}

/// The brakes and switchable shapes of a batch ([`Batch::set_commands`]).
#[derive(Clone, Copy)]
struct Commands<'a> {
    brakes: &'a [(usize, usize)],
    switches: &'a [usize],
}

/// What watches a copy of a batch, on the thread that steps it.
pub type BatchObserver = Box<dyn Observer + Send>;

/// One copy: its simulation, the error that stopped it, what watches it, its engaged
/// brakes and the shape switches of its next step.
struct Lane {
    sim: Simulation,
    error: Option<RunError>,
    observer: Option<BatchObserver>,
    /// The locks of the brakes engaged in this copy's steps (buffers reused: no
    /// allocation once grown to the batch's brakes and switches).
    locks: Actuation,
    switching: Vec<ControlEvent>,
}

impl Lane {
    fn new(setup: Arc<Setup>) -> Self {
        let mut sim = Simulation::shared(setup);
        // Observers of a batch see no energies; the state does not depend on the account.
        sim.set_ledger(false);
        Self {
            sim,
            error: None,
            observer: None,
            locks: Actuation::default(),
            switching: Vec::new(),
        }
    }

    /// `steps` steps under `controls` with the brakes whose flag in `engaged` is set and
    /// the switchable shapes active as `active` says, or fewer if one fails (the error is
    /// kept; later calls do nothing). A step with an engaged brake or a shape to switch is
    /// [`Simulation::step_with`] its locks and switches: the setup's controller and
    /// control signals do not act in it.
    fn advance(
        &mut self,
        steps: usize,
        controls: &[f64],
        commands: Commands<'_>,
        engaged: &[bool],
        active: &[bool],
    ) {
        if self.error.is_none() {
            if let Err(e) = self.sim.set_controls(controls) {
                self.error = Some(e.into());
            }
        }
        self.locks.locks.clear();
        self.locks.locks.extend(
            commands
                .brakes
                .iter()
                .zip(engaged)
                .filter_map(|(&lock, &on)| on.then_some(lock)),
        );
        self.switching.clear();
        for (&shape, &on) in commands.switches.iter().zip(active) {
            if self.sim.shapes_active()[shape] != on {
                self.switching
                    .push(ControlEvent::ShapeSwitch { shape, active: on });
            }
        }
        if self.error.is_none() {
            let mut unwatched = ();
            for k in 0..steps {
                let events = match k {
                    0 => self.switching.as_slice(),
                    _ => &[],
                };
                let observer: &mut dyn Observer = match &mut self.observer {
                    Some(observer) => observer.as_mut(),
                    None => &mut unwatched,
                };
                let stepped = match self.locks.locks.is_empty() && events.is_empty() {
                    true => self.sim.step(observer),
                    false => self.sim.step_with(&self.locks, events, observer),
                };
                if let Err(e) = stepped {
                    self.error = Some(e);
                    break;
                }
            }
        }
    }
}

/// Contiguous copies with their rows of the batch's arrays.
struct Part<'a> {
    lanes: &'a mut [Lane],
    t: &'a mut [f64],
    q: &'a mut [f64],
    u: &'a mut [f64],
    controls: &'a mut [f64],
    in_contact: &'a mut [bool],
    done: &'a mut [bool],
    commands: Commands<'a>,
    engaged: &'a [bool],
    active: &'a [bool],
    shape_loaded: &'a mut [bool],
    shape_forces: &'a mut [f64],
    nq: usize,
    nu: usize,
    /// Shapes per copy.
    ns: usize,
}

impl Part<'_> {
    /// Copies `..mid` and `mid..`.
    fn split(self, mid: usize) -> (Self, Self) {
        let (nq, nu, ns) = (self.nq, self.nu, self.ns);
        let (nb, nw) = (self.commands.brakes.len(), self.commands.switches.len());
        let (lanes, lanes_b) = self.lanes.split_at_mut(mid);
        let (t, t_b) = self.t.split_at_mut(mid);
        let (q, q_b) = self.q.split_at_mut(mid * nq);
        let (u, u_b) = self.u.split_at_mut(mid * nq);
        let (controls, controls_b) = self.controls.split_at_mut(mid * nu);
        let (in_contact, in_contact_b) = self.in_contact.split_at_mut(mid);
        let (done, done_b) = self.done.split_at_mut(mid);
        let (engaged, engaged_b) = self.engaged.split_at(mid * nb);
        let (active, active_b) = self.active.split_at(mid * nw);
        let commands = self.commands;
        let (shape_loaded, shape_loaded_b) = self.shape_loaded.split_at_mut(mid * ns);
        let (shape_forces, shape_forces_b) = self.shape_forces.split_at_mut(mid * ns * 2);
        let a = Part {
            lanes,
            t,
            q,
            u,
            controls,
            in_contact,
            done,
            commands,
            engaged,
            active,
            shape_loaded,
            shape_forces,
            nq,
            nu,
            ns,
        };
        let b = Part {
            lanes: lanes_b,
            t: t_b,
            q: q_b,
            u: u_b,
            controls: controls_b,
            in_contact: in_contact_b,
            done: done_b,
            commands,
            engaged: engaged_b,
            active: active_b,
            shape_loaded: shape_loaded_b,
            shape_forces: shape_forces_b,
            nq,
            nu,
            ns,
        };
        (a, b)
    }

    /// `steps` steps of each copy, then its rows from it; with `chunk`, contiguous chunks of
    /// `chunk` copies on the current rayon pool (`rayon::join` halves: no allocation).
    fn step(mut self, steps: usize, chunk: Option<usize>) {
        let n = self.lanes.len();
        if let Some(chunk) = chunk.filter(|&c| n > c) {
            let mid = chunk * n.div_ceil(chunk).div_ceil(2);
            let (a, b) = self.split(mid);
            rayon::join(|| a.step(steps, Some(chunk)), || b.step(steps, Some(chunk)));
            return;
        }
        let nu = self.nu;
        let (nb, nw) = (self.commands.brakes.len(), self.commands.switches.len());
        for i in 0..n {
            self.lanes[i].advance(
                steps,
                &self.controls[i * nu..(i + 1) * nu],
                self.commands,
                &self.engaged[i * nb..(i + 1) * nb],
                &self.active[i * nw..(i + 1) * nw],
            );
            self.gather(i);
        }
    }

    /// Copy `i`'s state, controls (those that acted), contact flags and forces and done
    /// flag into its rows.
    fn gather(&mut self, i: usize) {
        let lane = &self.lanes[i];
        let (nq, nu, ns) = (self.nq, self.nu, self.ns);
        let state = lane.sim.state();
        self.t[i] = state.t;
        self.q[i * nq..(i + 1) * nq].copy_from_slice(state.q.as_slice());
        self.u[i * nq..(i + 1) * nq].copy_from_slice(state.u.as_slice());
        self.controls[i * nu..(i + 1) * nu].copy_from_slice(lane.sim.controls());
        self.in_contact[i] = lane.sim.in_contact();
        self.done[i] = lane.error.is_some();
        lane.sim.shape_contacts_to(
            &mut self.shape_loaded[i * ns..(i + 1) * ns],
            &mut self.shape_forces[i * ns * 2..(i + 1) * ns * 2],
        );
    }
}

/// `n` copies of a model stepped together on a fixed number of threads, their states,
/// controls, contact flags and done mask in flat row-major arrays (copy `i`'s
/// coordinates at `i * nq .. (i + 1) * nq`). Sized at construction: a batch step
/// allocates nothing beyond what its copies' steps do (their events) and, on more than one
/// thread, rayon's queue of jobs sent into the pool (a block per 63 batch steps).
pub struct Batch {
    setups: Vec<Arc<Setup>>,
    lanes: Vec<Lane>,
    nq: usize,
    nu: usize,
    t: Vec<f64>,
    q: Vec<f64>,
    u: Vec<f64>,
    controls: Vec<f64>,
    in_contact: Vec<bool>,
    done: Vec<bool>,
    /// The brakes `(body, other)`, and which are engaged in each copy (`n × brakes`).
    brakes: Vec<(usize, usize)>,
    engaged: Vec<bool>,
    /// The switchable shapes, and which are to be active in each copy (`n × switches`).
    switches: Vec<usize>,
    active: Vec<bool>,
    shape_loaded: Vec<bool>,
    shape_forces: Vec<f64>,
    ns: usize,
    /// `None` for one thread (the copies are stepped on the caller's thread).
    pool: Option<rayon::ThreadPool>,
    threads: usize,
}

impl Batch {
    /// `n` copies of `setup` (one shared model) at its initial state, stepped on `threads`
    /// threads.
    pub fn new(setup: &Setup, n: usize, threads: usize) -> Result<Self, BatchError> {
        let shared = Arc::new(setup.clone());
        Self::of_setups(vec![shared; n], threads)
    }

    /// One copy per setup (per-copy parameters: masses, friction, controller keys), each
    /// at its setup's initial state. Every setup must have the same numbers of
    /// coordinates and actuators.
    pub fn of_setups(setups: Vec<Arc<Setup>>, threads: usize) -> Result<Self, BatchError> {
        let first = setups.first().ok_or(BatchError::Empty)?;
        if threads == 0 {
            return Err(BatchError::NoThreads);
        }
        let sizes = |s: &Setup| (s.initial.q.len(), s.model.actuators().len());
        let (nq, nu) = sizes(first);
        for (copy, s) in setups.iter().enumerate() {
            let (coordinates, actuators) = sizes(s);
            if (coordinates, actuators) != (nq, nu) {
                return Err(BatchError::Sizes {
                    copy,
                    coordinates,
                    actuators,
                    expected_coordinates: nq,
                    expected_actuators: nu,
                });
            }
        }
        let pool = match threads {
            1 => None,
            _ => Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|e| BatchError::Threads {
                        threads,
                        message: e.to_string(),
                    })?,
            ),
        };
        let n = setups.len();
        let ns = first.model.shapes().len();
        if let Some(copy) = setups.iter().position(|s| s.model.shapes().len() != ns) {
            return Err(BatchError::Shapes {
                copy,
                shapes: setups[copy].model.shapes().len(),
                expected: ns,
            });
        }
        let lanes = setups.iter().map(|s| Lane::new(s.clone())).collect();
        let mut batch = Self {
            setups,
            lanes,
            nq,
            nu,
            t: vec![0.0; n],
            q: vec![0.0; n * nq],
            u: vec![0.0; n * nq],
            controls: vec![0.0; n * nu],
            in_contact: vec![false; n],
            done: vec![false; n],
            brakes: Vec::new(),
            engaged: Vec::new(),
            switches: Vec::new(),
            active: Vec::new(),
            shape_loaded: vec![false; n * ns],
            shape_forces: vec![0.0; n * ns * 2],
            ns,
            pool,
            threads,
        };
        for i in 0..n {
            batch.gather(i);
        }
        Ok(batch)
    }

    /// The number of copies.
    pub fn len(&self) -> usize {
        self.lanes.len()
    }

    /// Whether the batch has no copies (never: a batch has at least one).
    pub fn is_empty(&self) -> bool {
        self.lanes.is_empty()
    }

    /// Coordinates per copy.
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// Actuators (controls) per copy.
    pub fn nu(&self) -> usize {
        self.nu
    }

    /// The threads the copies are stepped on.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Each copy's time, s.
    pub fn t(&self) -> &[f64] {
        &self.t
    }

    /// Coordinates, `n × nq` row-major.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// Velocities, `n × nq` row-major.
    pub fn u(&self) -> &[f64] {
        &self.u
    }

    /// The actuators' controls, `n × nu` row-major: after a step, the controls that acted
    /// in its last step (a setup's control signals replace the given ones).
    pub fn controls(&self) -> &[f64] {
        &self.controls
    }

    /// The controls for the next step, `n × nu` row-major, checked at the step (a
    /// non-finite control stops its copy with [`RunError::Actuation`]).
    pub fn controls_mut(&mut self) -> &mut [f64] {
        &mut self.controls
    }

    /// Whether the world carried a normal percussion in each copy's last step
    /// ([`Simulation::in_contact`]).
    pub fn in_contact(&self) -> &[bool] {
        &self.in_contact
    }

    /// Shapes per copy.
    pub fn shapes(&self) -> usize {
        self.ns
    }

    /// Per copy and shape, `n × shapes` row-major: whether the shape carried a normal
    /// percussion in the copy's last step ([`Simulation::shape_contacts_to`]).
    pub fn shape_in_contact(&self) -> &[bool] {
        &self.shape_loaded
    }

    /// Per copy and shape, `n × shapes × 2` row-major: the shape's normal and tangential
    /// contact forces over the copy's last step, N ([`Simulation::shape_contacts_to`]).
    pub fn shape_contact_forces(&self) -> &[f64] {
        &self.shape_forces
    }

    /// Whether each copy is done (a step of it failed: see [`Batch::error`]); a done copy
    /// is not stepped until it is reset.
    pub fn done(&self) -> &[bool] {
        &self.done
    }

    /// The error that stopped copy `i`, if any.
    pub fn error(&self, i: usize) -> Option<&RunError> {
        self.lanes.get(i)?.error.as_ref()
    }

    /// Copy `i`'s simulation (its stepper, events, hops, setup).
    pub fn simulation(&self, i: usize) -> Option<&Simulation> {
        self.lanes.get(i).map(|l| &l.sim)
    }

    /// Sets the batch's brakes and switchable shapes. A brake `(body, other)` locks
    /// `θ̇_body = θ̇_other` at the end of every step of a copy in which it is engaged
    /// (docs/physics.md §4.4), as the lock of a caller's [`Actuation`]; a switch is a
    /// contact shape (a cane) switched on or off as a copy's flag in
    /// [`Batch::active_mut`] says, at the start of its next step. Every brake starts
    /// disengaged and every flag off. A body or shape out of range, or a brake of a body
    /// on itself, is [`BatchError::Brake`].
    pub fn set_commands(
        &mut self,
        brakes: &[(usize, usize)],
        switches: &[usize],
    ) -> Result<(), BatchError> {
        let model = &self.setups[0].model;
        let check = Actuation {
            locks: brakes.to_vec(),
            ..Actuation::default()
        };
        check.validate(model).map_err(BatchError::Brake)?;
        for &shape in switches {
            ControlEvent::ShapeSwitch {
                shape,
                active: false,
            }
            .validate(model)
            .map_err(BatchError::Brake)?;
        }
        self.brakes = check.locks;
        self.engaged = vec![false; self.len() * brakes.len()];
        self.switches = switches.to_vec();
        self.active = vec![false; self.len() * switches.len()];
        Ok(())
    }

    /// The switchable shapes ([`Batch::set_commands`]).
    pub fn switches(&self) -> &[usize] {
        &self.switches
    }

    /// Whether each copy's switchable shapes are to be active in its next steps,
    /// `n × switches` row-major: a shape whose flag differs from its state is switched
    /// at the start of the copy's next [`Batch::step`] (a step without its controller).
    pub fn active_mut(&mut self) -> &mut [bool] {
        &mut self.active
    }

    /// The flags of [`Batch::active_mut`].
    pub fn active(&self) -> &[bool] {
        &self.active
    }

    /// The brakes `(body, other)` ([`Batch::set_commands`]).
    pub fn brakes(&self) -> &[(usize, usize)] {
        &self.brakes
    }

    /// Which brakes are engaged in each copy's next steps, `n × brakes` row-major (held
    /// over a call of [`Batch::step`]). A step with an engaged brake is the copy's
    /// [`Simulation::step_with`] its locks: the setup's controller and control signals do
    /// not act in it.
    pub fn engaged_mut(&mut self) -> &mut [bool] {
        &mut self.engaged
    }

    /// Which brakes are engaged, `n × brakes` row-major.
    pub fn engaged(&self) -> &[bool] {
        &self.engaged
    }

    /// Takes `steps` steps of every copy that is not done, under the controls of
    /// [`Batch::controls_mut`] (held over the steps). A copy whose step fails is marked
    /// done with its error; the others go on.
    pub fn step(&mut self, steps: usize) {
        let chunk = self.lanes.len().div_ceil(self.threads);
        let pool = self.pool.take();
        match &pool {
            None => self.part().step(steps, None),
            Some(pool) => pool.install(|| self.part().step(steps, Some(chunk))),
        }
        self.pool = pool;
    }

    /// Shows copy `i`'s current state to `observer` ([`Observer::on_start`]) and then
    /// every step of it, with the energy account on, started at the current state (the
    /// copies nobody watches keep none; the states do not depend on it), until
    /// [`Batch::detach`]. A copy being watched is
    /// neither reset nor restarted at another state ([`BatchError::Observed`]).
    pub fn observe(&mut self, i: usize, mut observer: BatchObserver) -> Result<(), BatchError> {
        self.check_unobserved(i)?;
        let lane = &mut self.lanes[i];
        lane.sim.restart_ledger();
        let started = lane.sim.start(observer.as_mut());
        if let Err(error) = started {
            lane.sim.set_ledger(false);
            return Err(BatchError::Run { copy: i, error });
        }
        lane.observer = Some(observer);
        Ok(())
    }

    /// The observer of copy `i`, no longer shown its steps.
    pub fn detach(&mut self, i: usize) -> Option<BatchObserver> {
        let lane = self.lanes.get_mut(i)?;
        lane.sim.set_ledger(false);
        lane.observer.take()
    }

    /// Copy `i` anew at its setup's initial state (its controller and shapes too), not
    /// done.
    pub fn reset(&mut self, i: usize) -> Result<(), BatchError> {
        self.check_unobserved(i)?;
        self.lanes[i] = Lane::new(self.setups[i].clone());
        self.gather(i);
        Ok(())
    }

    /// Every copy anew ([`Batch::reset`]).
    pub fn reset_all(&mut self) -> Result<(), BatchError> {
        if let Some(copy) = self.lanes.iter().position(|l| l.observer.is_some()) {
            return Err(BatchError::Observed { copy });
        }
        for i in 0..self.len() {
            self.lanes[i] = Lane::new(self.setups[i].clone());
            self.gather(i);
        }
        Ok(())
    }

    /// Restarts copy `i` at `state`, checked as [`Simulation::set_state`] does; a done
    /// copy is reset first. On an error nothing changes.
    pub fn set_state(&mut self, i: usize, state: State) -> Result<(), BatchError> {
        self.restart(i, state, Simulation::set_state)
    }

    /// [`Batch::set_state`] for a state a simulation of the model reached (contacts and
    /// stops slightly penetrated): only its values are checked, as
    /// [`Simulation::restore_state`] does.
    pub fn restore_state(&mut self, i: usize, state: State) -> Result<(), BatchError> {
        self.restart(i, state, Simulation::restore_state)
    }

    /// Copy `i` restarted at `state` by `restart` (a done copy anew first); on an error
    /// nothing changes.
    fn restart(
        &mut self,
        i: usize,
        state: State,
        restart: fn(&mut Simulation, State) -> Result<(), StateProblem>,
    ) -> Result<(), BatchError> {
        self.check_unobserved(i)?;
        let problem = |problem| BatchError::State { copy: i, problem };
        if self.lanes[i].error.is_some() {
            let mut lane = Lane::new(self.setups[i].clone());
            restart(&mut lane.sim, state).map_err(problem)?;
            self.lanes[i] = lane;
        } else {
            restart(&mut self.lanes[i].sim, state).map_err(problem)?;
        }
        self.gather(i);
        Ok(())
    }

    /// [`Batch::check`], and no observer on the copy.
    fn check_unobserved(&self, copy: usize) -> Result<(), BatchError> {
        self.check(copy)?;
        match self.lanes[copy].observer {
            Some(_) => Err(BatchError::Observed { copy }),
            None => Ok(()),
        }
    }

    fn check(&self, copy: usize) -> Result<(), BatchError> {
        match copy < self.len() {
            true => Ok(()),
            false => Err(BatchError::NoSuchCopy {
                copy,
                copies: self.len(),
            }),
        }
    }

    /// Every copy with its rows.
    fn part(&mut self) -> Part<'_> {
        Part {
            lanes: &mut self.lanes,
            t: &mut self.t,
            q: &mut self.q,
            u: &mut self.u,
            controls: &mut self.controls,
            in_contact: &mut self.in_contact,
            done: &mut self.done,
            commands: Commands {
                brakes: &self.brakes,
                switches: &self.switches,
            },
            engaged: &self.engaged,
            active: &self.active,
            shape_loaded: &mut self.shape_loaded,
            shape_forces: &mut self.shape_forces,
            nq: self.nq,
            nu: self.nu,
            ns: self.ns,
        }
    }

    /// Copy `i`'s rows of the arrays from it.
    fn gather(&mut self, i: usize) {
        self.part().gather(i);
    }
}
