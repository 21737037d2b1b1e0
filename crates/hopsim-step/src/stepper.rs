//! One step of the Moreau midpoint scheme of docs/physics.md §4, as a pipeline of named stages
//! (see [`Stepper::step`]).

use crate::linalg::{axpy, dot, Factor, PivotedFactor};
use crate::{
    Actuation, ContactRecord, ContactState, EnergyLedger, ImpulseCommand, LcpStats, LimitRecord,
    LockRecord, Resolution, State, StepRecord,
};
use hopsim_lcp::{LcpStatus, LemkeOptions, LemkeSolver, SolveMethod, WarmStart};
use hopsim_model::{ContactGeometry, Kinematics, Model};
use nalgebra::{DMatrix, DVector};

mod actuators;
mod dry_friction;
mod layout;
mod loops;
mod pairs;

use dry_friction::DryFriction;
use layout::{at, Layout};
pub use loops::LOOP_TOLERANCE;
use loops::{LoopProjection, DEPENDENT_LOOP_ROWS};

/// Settings of the stepper.
#[derive(Clone, Debug)]
pub struct StepSettings {
    /// Step size `Δt`, s.
    pub dt: f64,
    /// Stop with an error on the first LCP without a certified solution.
    pub strict: bool,
    /// A generalised velocity above this magnitude stops the run as a runaway state.
    pub max_speed: f64,
    /// Options of the Lemke solver.
    pub lcp: LemkeOptions,
    /// Try the previous step's complementary basis before Lemke's method
    /// ([`LemkeSolver::solve_warm`]; the answer is certified either way). On by default.
    pub warm_start: bool,
}

impl StepSettings {
    /// Defaults with step size `dt` that stop on the first uncertified LCP.
    pub fn strict(dt: f64) -> Self {
        Self {
            dt,
            strict: true,
            ..Self::default()
        }
    }
}

impl Default for StepSettings {
    fn default() -> Self {
        Self {
            dt: 1e-3,
            strict: false,
            max_speed: 1e4,
            lcp: LemkeOptions::default(),
            warm_start: true,
        }
    }
}

/// Why a step could not be taken.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StepError {
    #[error("step {step} (t = {t:.6} s): {what} is not finite")]
    NonFinite {
        step: u64,
        t: f64,
        what: &'static str,
    },
    #[error(
        "step {step} (t = {t:.6} s): runaway state, |u_{index}| = {speed:.3e} exceeds {limit:.1e}"
    )]
    Runaway {
        step: u64,
        t: f64,
        index: usize,
        speed: f64,
        limit: f64,
    },
    #[error("step {step} (t = {t:.6} s): the state has {q} coordinates and {u} velocities, the model {dof}")]
    StateSize {
        step: u64,
        t: f64,
        q: usize,
        u: usize,
        dof: usize,
    },
    #[error("step {step} (t = {t:.6} s): the mass matrix is not positive definite")]
    SingularMassMatrix { step: u64, t: f64 },
    #[error("step {step} (t = {t:.6} s): the velocity locks are redundant or singular")]
    SingularLocks { step: u64, t: f64 },
    /// A loop joint's rows lost rank (the mechanism reached a singular configuration) or
    /// the projection onto its closure did not converge (docs/physics.md §8.4). The loop is
    /// an index into `Model::loops` (plain data, so that a step's `Result` stays cheap);
    /// the run loop names it (`hopsim_sim::RunError::Loop`).
    #[error("step {step} (t = {t:.6} s): loop joint {loop_index} {}, loop error {error:.3e}", loop_failure(*.singular))]
    Loop {
        step: u64,
        t: f64,
        loop_index: usize,
        singular: bool,
        error: f64,
    },
    #[error("step {step} (t = {t:.6} s): contact LCP of size {size} ended with {status} ({contacts} closed contacts)")]
    Lcp {
        step: u64,
        t: f64,
        size: usize,
        contacts: usize,
        status: &'static str,
    },
}

/// What went wrong with a loop joint, in words (see [`StepError::Loop`]).
pub fn loop_failure(singular: bool) -> &'static str {
    if singular {
        "reached a singular configuration (its rows lost rank)"
    } else {
        "could not be closed (the projection did not converge)"
    }
}

/// The time-stepper: reused buffers for one model, so a step allocates nothing.
///
/// One [`Stepper::step`] is docs/physics.md §4 as a pipeline of stages, listed in its doc. `M` is
/// factored as `L D Lᵀ`, never inverted: only the products `G W` and `G (h Δt + …)` are
/// needed, so they are computed by solves with that factor; impulsive locks `Bᵀ u^E = 0`
/// replace `G = M⁻¹` by `G − G B (Bᵀ G B)⁻¹ Bᵀ G` and `ũ` by its projection. The
/// frictional LCP in `z = (Λ_N, Λ_R, ξ_L)`, `w = (ξ_N, ξ_R, Λ_L)` with the restitution
/// terms `ε_N γ_N^A`, `ε_T γ_T^A` is solved by Lemke's method; it is the only dense matrix
/// built (`3k × 3k`).
///
/// **LCP failures** are never silent. A step whose frictional LCP has no certified
/// solution is counted in [`LcpStats::failures`] and flagged in
/// [`StepRecord::lcp_failed`]. In strict mode ([`StepSettings::strict`]) it is a
/// [`StepError::Lcp`]. Otherwise the step falls back to the frictionless normal-contact LCP
/// (`G_NN Λ_N + W_Nᵀ ũ + ε_N γ_N^A ⟂ Λ_N ≥ 0`, a symmetric positive semi-definite problem
/// Lemke's method always certifies when the contacts are not degenerate): the contacts
/// still keep the bodies out of the ground (the percussions are not zeroed) and, without
/// friction and with `ε = 0`, the step cannot add energy; only friction is lost for that
/// one step, which the flag and the counter report. If that LCP fails too, the step is a
/// [`StepError::Lcp`] in either mode.
pub struct Stepper {
    settings: StepSettings,
    /// Time of the run's start state: step `k` ends at `t_start + k Δt` (computed, not
    /// accumulated, so times stay on the grid of step sizes).
    t_start: f64,
    enabled: Vec<bool>,
    /// The body–body contacts with a fixed body (`Model::pair_touches_world`).
    world_pairs: Vec<usize>,
    /// Kinematics at `(q^M, u^A)` during a step, at the end state after it.
    kinematics: Kinematics,
    /// Generalised coordinates `n`.
    n: usize,
    /// `M(q^M)`, row-major `n × n`, and its `L D Lᵀ` factor.
    mass: Vec<f64>,
    factor: Factor,
    /// `M` and its factor are those of every `q` (see [`Model::jacobian_is_constant`])
    /// and already built: stage 2 keeps them.
    mass_fixed: bool,
    h: Vec<f64>,
    /// The explicit damping force `−C u^A` (part of `h`).
    damping: Vec<f64>,
    /// The dampers acting in this step (docs/physics.md §4.9): their coefficients `c` and
    /// rows `w` (row-major `d × n`), `C = Σ c w wᵀ`.
    damper_count: usize,
    damper_c: Vec<f64>,
    damper_rows: Vec<f64>,
    applied: Vec<f64>,
    impulse: Vec<f64>,
    /// `h Δt + impulses`.
    force: Vec<f64>,
    /// Right-hand sides solved with `M` together, rows of length `n`: `h Δt + impulses`,
    /// then `w_N` and `w_T` of each closed contact; after the solve `M⁻¹ (h Δt + …)`, and
    /// `G w_N`, `G w_T` (projected onto the locks).
    solved: Vec<f64>,
    u_tilde: Vec<f64>,
    q_mid: Vec<f64>,
    /// `u^A`, the velocity at the start of the step.
    u_start: Vec<f64>,
    u_end: Vec<f64>,
    scratch: Vec<f64>,
    locks: Locks,
    // Contacts of the index set: their indices, geometry; row-major `k × n`: `w_N`, `w_T`.
    active: Vec<usize>,
    geometry: Vec<ContactGeometry>,
    w_n: Vec<f64>,
    w_t: Vec<f64>,
    gamma_n: Vec<f64>,
    gamma_t: Vec<f64>,
    lambda_n: Vec<f64>,
    lambda_t: Vec<f64>,
    /// The friction coefficient each closed contact has in this step's LCP: its material's
    /// `μ`, or 0 when its tangential row depends on its normal one (`dependent`,
    /// docs/physics.md §4.8).
    friction: Vec<f64>,
    dependent: Vec<bool>,
    /// `ξ_T` of each closed contact (NaN after the frictionless fallback, until `u^E`).
    slip: Vec<f64>,
    /// Closed joint stops (docs/physics.md §7): their indices into `Model::limits`, gaps, rows
    /// `w = ±∂s/∂q` (row-major `l × n`), `γ^A = wᵀ u^A` and percussions.
    active_limits: Vec<usize>,
    limit_gap: Vec<f64>,
    w_limit: Vec<f64>,
    gamma_limit: Vec<f64>,
    lambda_limit: Vec<f64>,
    /// `w G w` of each closed stop before the locks' projection (with locks only), and
    /// whether the locks fix its velocity in this step.
    limit_mobility: Vec<f64>,
    limit_locked: Vec<bool>,
    /// The joints with dry friction and their rows (docs/physics.md §7.5).
    dry: DryFriction,
    lcp_a: DMatrix<f64>,
    lcp_b: DVector<f64>,
    lcp: LemkeSolver,
    /// The basis of the last frictional LCP's answer (see [`StepSettings::warm_start`]).
    warm: WarmStart,
    record: StepRecord,
    stats: LcpStats,
    /// Whether stage 9 keeps the energy account (see [`Stepper::set_ledger`]).
    ledger: bool,
    /// The projection onto the loop joints' closure (docs/physics.md §8.4); `None` for a
    /// tree model, whose steps skip every loop stage.
    loops: Option<LoopProjection>,
}

impl Stepper {
    /// A stepper for `model`, with every contact enabled (terrain contacts, then
    /// body–body contacts: see [`Model::pairs`]).
    pub fn new(model: &Model, settings: StepSettings) -> Self {
        let n = model.dof();
        let k = model.contact_count();
        let limits = model.limits().len();
        let loop_rows = model.loop_row_count();
        // Equality rows: the brakes' (at most one per body), then the loops'.
        let locks = model.bodies().len() + loop_rows;
        let vector = |len: usize| vec![0.0; len];
        let mut lcp = LemkeSolver::new(settings.lcp.clone());
        let kinematics = Kinematics::new(model);
        let dampers = model.damper_capacity() + model.actuator_damper_capacity();
        // `M + Δt/2 C` is diagonal only without dampers.
        let diagonal = model.mass_matrix_is_diagonal() && dampers == 0;
        // The largest problem: every contact and every stop closed.
        let dry = DryFriction::new(model, settings.dt);
        let most = Layout {
            contacts: k,
            limits,
            frictions: dry.count(),
        };
        lcp.reserve(most.size());
        Self {
            lcp,
            warm: WarmStart::with_capacity(most.size()),
            settings,
            t_start: 0.0,
            enabled: vec![true; k],
            world_pairs: (0..model.pairs().len())
                .filter(|&p| model.pair_touches_world(p))
                .collect(),
            kinematics,
            n,
            mass: vector(n * n),
            factor: Factor::new(n, diagonal),
            mass_fixed: false,
            h: vector(n),
            damping: vector(n),
            damper_count: 0,
            damper_c: vector(dampers),
            damper_rows: vector(dampers * n),
            applied: vector(n),
            impulse: vector(n),
            force: vector(n),
            solved: vector(most.solved_rows() * n),
            u_tilde: vector(n),
            q_mid: vector(n),
            u_start: vector(n),
            u_end: vector(n),
            scratch: vector(n.max(locks)),
            locks: Locks {
                count: 0,
                n,
                b: vector(locks * n),
                y: vector(locks * n),
                s: vector(locks * locks),
                s_factor: Factor::new(locks, false),
                p: vector(locks),
                brakes: 0,
                loop_rows,
                pivoted: PivotedFactor::new(locks),
                loop_rank: loop_rows,
            },
            active: Vec::with_capacity(k),
            geometry: Vec::with_capacity(k),
            w_n: vector(k * n),
            w_t: vector(k * n),
            gamma_n: vector(k),
            gamma_t: vector(k),
            lambda_n: vector(k),
            lambda_t: vector(k),
            slip: vector(k),
            friction: vector(k),
            dependent: vec![false; k],
            active_limits: Vec::with_capacity(limits),
            limit_gap: vector(limits),
            w_limit: vector(limits * n),
            gamma_limit: vector(limits),
            lambda_limit: vector(limits),
            limit_mobility: vector(limits),
            limit_locked: vec![false; limits],
            dry,
            lcp_a: DMatrix::zeros(most.size(), most.size()),
            lcp_b: DVector::zeros(most.size()),
            record: StepRecord {
                contacts: Vec::with_capacity(k),
                pair_contacts: Vec::with_capacity(model.pairs().len()),
                limits: Vec::with_capacity(limits),
                locks: Vec::with_capacity(locks),
                ..StepRecord::default()
            },
            stats: LcpStats::default(),
            ledger: true,
            loops: LoopProjection::new(model),
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &StepSettings {
        &self.settings
    }

    /// Switches potential contact `i` on or off (e.g. a retracted cane).
    pub fn set_contact_enabled(&mut self, i: usize, enabled: bool) {
        self.enabled[i] = enabled;
    }

    /// Whether potential contact `i` is switched on.
    pub fn contact_enabled(&self, i: usize) -> bool {
        self.enabled[i]
    }

    /// LCP statistics so far.
    pub fn lcp_stats(&self) -> LcpStats {
        self.stats
    }

    /// The record of the last step (or of [`Stepper::start`]).
    pub fn record(&self) -> &StepRecord {
        &self.record
    }

    /// Kinematics at the end of the last step (or at the start state).
    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }

    /// Keeps the energy account of the record ([`StepRecord::energy`]: the energies at the
    /// end of each step and the cumulative works, docs/physics.md §6.1) or not (on by default).
    /// Nothing in a step reads it, so a run that nobody watches for energies can skip its
    /// cost; switched off, `record().energy` keeps the values of [`Stepper::start`]. The
    /// gaps and the lock impulses of the record are kept either way. Switch it before a
    /// run: the works are sums over every step since the start.
    pub fn set_ledger(&mut self, on: bool) {
        self.ledger = on;
    }

    /// Switches the energy account on and starts it anew at the current state (the
    /// energies of the current kinematics, no works yet): for a run that kept none
    /// ([`Stepper::set_ledger`]) and is watched for energies from now on. The rest of the
    /// record, the statistics and the warm start are kept.
    pub fn restart_ledger(&mut self, model: &Model) {
        self.ledger = true;
        self.record.energy = EnergyLedger::default();
        self.fill_energies(model);
        self.record.energy.initial = self.record.energy.total();
    }

    /// Resets the record and energy account to `state` at the start of a run.
    pub fn start(&mut self, model: &Model, state: &State) -> &StepRecord {
        self.kinematics.update(model, &state.q, &state.u);
        self.record.energy = EnergyLedger::default();
        self.fill_energies(model);
        self.record.energy.initial = self.record.energy.total();
        self.record.step = 0;
        self.record.t = state.t;
        self.t_start = state.t;
        self.record.contacts.clear();
        self.record.pair_contacts.clear();
        self.record.limits.clear();
        self.record.locks.clear();
        self.record.lcp_pivots = 0;
        self.record.lcp_failed = false;
        self.fill_gaps(model);
        self.stats = LcpStats::default();
        self.warm.forget();
        if let Some(loops) = &mut self.loops {
            loops.start(model, &self.kinematics);
            self.locks.loop_rank = loops.rank;
            self.record.loop_error = model.loop_error(&self.kinematics, &mut self.scratch);
        }
        &self.record
    }

    /// Moves `state` onto the loop joints' closure (docs/physics.md §8.4): the nearest
    /// positions in the mass-matrix metric, the velocities onto the closure's tangent
    /// space; returns the loop error it found (m, rad for a weld's angle). A tree model's
    /// state is left as it is (error 0). A state the projection cannot close is a
    /// [`StepError::Loop`] at step 0.
    pub fn assemble(&mut self, model: &Model, state: &mut State) -> Result<f64, StepError> {
        let Some(loops) = self.loops.as_mut() else {
            return Ok(0.0);
        };
        self.kinematics.update(model, &state.q, &state.u);
        let gap = model.loop_error(&self.kinematics, &mut self.scratch);
        // No rank to keep yet: the rank is taken at the start of the run.
        loops.rank = 0;
        let (q, u) = (state.q.as_mut_slice(), state.u.as_mut_slice());
        loops
            .project(model, &mut self.kinematics, q, u)
            .map_err(|failure| failure.into_error(0, state.t))?;
        Ok(gap)
    }

    /// The energies at the current kinematics into the record's account, field by field
    /// (the account is not copied: its fields were just written one by one).
    fn fill_energies(&mut self, model: &Model) {
        let energies = model.energies(&self.kinematics);
        let energy = &mut self.record.energy;
        energy.kinetic = energies.kinetic;
        energy.potential = energies.potential;
        energy.spring = energies.spring;
    }

    /// `min_gap` and `max_penetration` of the record over the enabled contacts with the
    /// world (the terrain's and those with shapes of fixed bodies), in one pass.
    fn fill_gaps(&mut self, model: &Model) {
        let mut min_gap = f64::INFINITY;
        for i in 0..model.contacts().len() {
            if self.enabled[i] {
                if let Some(g) = model.contact_geometry(&self.kinematics, i) {
                    min_gap = min_gap.min(g.gap);
                }
            }
        }
        for &p in &self.world_pairs {
            if self.enabled[model.contacts().len() + p] {
                if let Some(g) = model.pair_geometry(&self.kinematics, p) {
                    min_gap = min_gap.min(g.gap);
                }
            }
        }
        self.record.min_gap = min_gap;
        self.record.max_penetration = (-min_gap).max(0.0);
    }

    /// Advances `state` by one step `Δt` under `actuation`: docs/physics.md §4 as nine stages,
    /// run in this order and numbered the same in the body (`// Stage k`), in each stage's
    /// doc and in docs/architecture.md ("One step, in order"):
    ///
    /// 1. `midpoint`: `q^M = q^A + Δt/2 u^A` (§4.1 step 1).
    /// 2. `dynamics`: kinematics at `(q^M, u^A)`, `M(q^M)` factored as `L D Lᵀ`,
    ///    `h(q^M, u^A)` with the motor torques and the actuators' forces (§4.1 step 2,
    ///    §7.4).
    /// 3. `impulses_and_locks`: the applied impulses (§3) and the velocity locks
    ///    `Bᵀ u^E = 0` (§4.4).
    /// 4. `index_set`: the closed contacts `H` with their `W_N`, `W_T` and `γ^A` at `q^M`
    ///    (§4.1 step 2).
    /// 5. `free_velocity`: `ũ = u^A + G (h Δt + impulses)` and `G W_N`, `G W_T`, with `G`
    ///    and `ũ` projected onto the locks (§4.3, §4.4).
    /// 6. `solve_contact_lcp`: the frictional LCP for the percussions `Λ_N`, `Λ_T`
    ///    (§4.1 step 3, §4.3; failures and the fallback §4.5).
    /// 7. `end_velocity`: `u^E = ũ + G (W_N Λ_N + W_T Λ_T)` and the contact records
    ///    (§4.1 step 4).
    /// 8. `integrate`: `q^E = q^M + Δt/2 u^E` and `t^E` into `state`, checked; the
    ///    kinematics at the end of the step (§4.1 step 5).
    /// 9. `ledger`, for observers only (no later stage or step reads it): the works of
    ///    every percussion, the lock impulses, the energies and gaps at the end (§6.1).
    pub fn step(
        &mut self,
        model: &Model,
        state: &mut State,
        actuation: &Actuation,
    ) -> Result<&StepRecord, StepError> {
        // One copy of the stages per small number of coordinates, so that their loops
        // over `n` have fixed trip counts; `0`: any `n`.
        match self.n {
            3 => self.step_sized::<3>(model, state, actuation)?,
            4 => self.step_sized::<4>(model, state, actuation)?,
            5 => self.step_sized::<5>(model, state, actuation)?,
            6 => self.step_sized::<6>(model, state, actuation)?,
            _ => self.step_sized::<0>(model, state, actuation)?,
        }
        Ok(&self.record)
    }

    /// [`Stepper::step`] through the stages compiled for any `n`: the generic path that the
    /// copies for `n` = 3…6 are checked against, bit for bit
    /// (crates/hopsim-gen/tests/sized_steps.rs).
    #[doc(hidden)]
    pub fn step_generic(
        &mut self,
        model: &Model,
        state: &mut State,
        actuation: &Actuation,
    ) -> Result<&StepRecord, StepError> {
        self.step_sized::<0>(model, state, actuation)?;
        Ok(&self.record)
    }

    /// [`Stepper::step`] for `n = N` coordinates (`N = 0`: any `n`).
    fn step_sized<const N: usize>(
        &mut self,
        model: &Model,
        state: &mut State,
        actuation: &Actuation,
    ) -> Result<(), StepError> {
        let step = self.record.step + 1;
        // Errors name the step and the time at its start.
        let t = state.t;
        check_state(state, dof::<N>(self.n), step, t, f64::INFINITY, true)?;
        // Stage 1: midpoint.
        self.midpoint::<N>(state);
        // Stage 2: kinematics, mass matrix and its factor, forces.
        self.dynamics::<N>(model, actuation, step, t)?;
        // Stage 3: applied impulses and velocity locks.
        self.impulses_and_locks::<N>(model, actuation, step, t)?;
        // Stage 4: index set.
        let k = self.index_set::<N>(model);
        // Stage 5: free velocity ũ and G W.
        self.free_velocity::<N>(k);
        // Stage 6: contact LCP.
        self.solve_contact_lcp::<N>(model, step, t)?;
        // Stage 7: end velocity u^E and contact records.
        self.end_velocity::<N>(model, k);
        // Stage 8: end position q^E and time.
        self.integrate::<N>(model, state, step, t)?;
        if self.loops.is_some() {
            // Stage 8b: the end state onto the loops' closure.
            self.close_loops(model, state, step, t)?;
        }
        // Stage 9: energy ledger and gaps (observers only).
        self.ledger::<N>(model, actuation);
        Ok(())
    }

    /// The layout of this step's problem with `k` closed contacts and the closed stops.
    #[inline(always)]
    fn layout(&self, k: usize) -> Layout {
        Layout {
            contacts: k,
            limits: self.active_limits.len(),
            frictions: self.dry.count(),
        }
    }

    /// Stage 1, docs/physics.md §4.1 step 1: the midpoint `q^M = q^A + Δt/2 u^A`; keeps `u^A`
    /// for the later stages (the state is overwritten in stage 8).
    #[inline]
    fn midpoint<const N: usize>(&mut self, state: &State) {
        let (n, dt) = (dof::<N>(self.n), self.settings.dt);
        let (q, u) = (&state.q.as_slice()[..n], &state.u.as_slice()[..n]);
        for ((m, q), u) in self.q_mid[..n].iter_mut().zip(q).zip(u) {
            *m = q + 0.5 * dt * u;
        }
        self.u_start[..n].copy_from_slice(u);
    }

    /// Stage 2, docs/physics.md §4.1 step 2: the kinematics at `(q^M, u^A)`, `M(q^M)` and its
    /// `L D Lᵀ` factor (built once when `M` does not depend on `q`), `h(q^M, u^A)` split into
    /// the damping forces and the rest, with the motor torques and the actuators' forces
    /// (§7.4) as the applied forces.
    #[inline]
    fn dynamics<const N: usize>(
        &mut self,
        model: &Model,
        actuation: &Actuation,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        self.kinematics
            .update_slices(model, &self.q_mid, &self.u_start);
        if !self.damper_c.is_empty() {
            self.damper_count =
                model.damper_rows_to(&self.kinematics, &mut self.damper_c, &mut self.damper_rows);
        }
        let applied = &mut self.applied[..dof::<N>(self.n)];
        applied.fill(0.0);
        for torque in &actuation.torques {
            self.kinematics
                .add_torque_to(torque.body, torque.reaction, torque.torque, applied);
        }
        for force in &actuation.joint_forces {
            model.add_joint_force_to(&self.kinematics, force.body, force.force, applied);
        }
        let model_dampers = self.damper_count;
        if !model.actuators().is_empty() {
            self.damper_count += self.actuator_forces::<N>(model, actuation);
        }
        if !self.mass_fixed {
            model.mass_matrix_to(&self.kinematics, &mut self.mass);
            self.add_damping_to_mass::<N>();
            if !self.factor.factor(&self.mass, self.n) {
                return Err(StepError::SingularMassMatrix { step, t });
            }
            // Servo dampers come and go with their force's clamping: `M + Δt/2 C` changes.
            self.mass_fixed = model.jacobian_is_constant()
                && model.damping_rows_follow_jacobian()
                && model.actuator_damper_capacity() == 0;
        }
        let n = dof::<N>(self.n);
        model.forces_split(
            &self.kinematics,
            &self.applied[..n],
            &mut self.h[..n],
            &mut self.damping[..n],
        );
        if self.damper_count > model_dampers {
            self.explicit_actuator_damping::<N>(model_dampers);
        }
        Ok(())
    }

    /// The damping taken at the step's mean velocity (docs/physics.md §4.9): with the
    /// explicit `−C u^A` in `h`, the step's matrix is `M + Δt/2 C`, so that the damping
    /// force over the step is `−C (u^A + u^E)/2` and its work `−Δt ūᵀ C ū ≤ 0` at any `Δt`.
    #[inline]
    fn add_damping_to_mass<const N: usize>(&mut self) {
        let n = dof::<N>(self.n);
        let half_dt = 0.5 * self.settings.dt;
        for d in 0..self.damper_count {
            let w = row(&self.damper_rows, n, d);
            let c = half_dt * self.damper_c[d];
            for (i, &w_i) in w.iter().enumerate() {
                if w_i != 0.0 {
                    axpy(c * w_i, w, &mut self.mass[i * n..(i + 1) * n]);
                }
            }
        }
    }

    /// Stage 3: the generalised applied impulses at `q^M` (docs/physics.md §3, `J_iᵀ ζ`) and the
    /// velocity locks `Bᵀ u^E = 0`, prepared for eliminating their percussion (§4.4).
    #[inline]
    fn impulses_and_locks<const N: usize>(
        &mut self,
        model: &Model,
        actuation: &Actuation,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        self.impulse[..dof::<N>(self.n)].fill(0.0);
        for command in &actuation.impulses {
            match *command {
                ImpulseCommand::Point {
                    body,
                    offset,
                    impulse,
                } => self
                    .kinematics
                    .add_point_force_to(body, offset, impulse, &mut self.impulse),
                ImpulseCommand::Rotational {
                    body,
                    reaction,
                    impulse,
                } => self
                    .kinematics
                    .add_torque_to(body, reaction, impulse, &mut self.impulse),
            }
        }
        self.locks.brakes = actuation.locks.len();
        self.locks.count = self.locks.brakes + self.locks.loop_rows;
        if self.locks.count > 0 {
            if let Err(row) =
                self.locks
                    .prepare(model, &self.kinematics, &self.factor, &actuation.locks)
            {
                return Err(self.singular_equalities(model, row, step, t));
            }
        }
        Ok(())
    }

    /// The error of a step whose equality row `row` is dependent on the others: a loop's
    /// (a singular configuration, docs/physics.md §8.3) or a brake's (redundant locks).
    #[cold]
    #[inline(never)]
    fn singular_equalities(&mut self, model: &Model, row: usize, step: u64, t: f64) -> StepError {
        match row.checked_sub(self.locks.brakes) {
            Some(r) => StepError::Loop {
                step,
                t,
                loop_index: model.loop_of_row(r),
                singular: true,
                error: model.loop_error(&self.kinematics, &mut self.scratch),
            },
            None => StepError::SingularLocks { step, t },
        }
    }

    /// Stage 4, docs/physics.md §4.1 step 2: the index set `H` (enabled contacts with
    /// `g_N(q^M) ≤ 0`) with each contact's `w_N`, `w_T` and `γ_N^A`, `γ_T^A`, and the closed
    /// joint stops (`g(q^M) ≤ 0`, §7) with their rows `w = ±∂s/∂q` and `γ^A`; returns the
    /// number `k` of closed contacts.
    fn index_set<const N: usize>(&mut self, model: &Model) -> usize {
        let n = dof::<N>(self.n);
        self.active.clear();
        self.geometry.clear();
        for i in 0..model.contacts().len() {
            if !self.enabled[i] {
                continue;
            }
            let Some(geom) = model.contact_geometry(&self.kinematics, i) else {
                continue;
            };
            if geom.gap > 0.0 {
                continue;
            }
            let c = self.active.len();
            let rows = c * n..(c + 1) * n;
            model.contact_directions_to(
                &self.kinematics,
                i,
                &geom,
                &mut self.w_n[rows.clone()],
                &mut self.w_t[rows],
            );
            self.close_contact::<N>(i, geom);
        }
        if !model.pairs().is_empty() {
            self.pair_index_set(model);
        }
        self.active_limits.clear();
        for (j, limit) in model.limits().iter().enumerate() {
            let gap = limit.gap(self.kinematics.joint_position(limit.body));
            if gap > 0.0 {
                continue;
            }
            let r = self.active_limits.len();
            let w = &mut self.w_limit[r * n..(r + 1) * n];
            w.fill(0.0);
            model.add_joint_force_to(&self.kinematics, limit.body, limit.sign(), w);
            self.gamma_limit[r] = dot(w, &self.u_start);
            self.limit_gap[r] = gap;
            self.active_limits.push(j);
        }
        if self.dry.count() > 0 {
            self.dry_friction_rows::<N>(model);
        }
        self.active.len()
    }

    /// Adds contact `i`, whose `w_N`, `w_T` are written in the next rows, to the index set
    /// with its `γ_N^A`, `γ_T^A` and `geometry`.
    #[inline]
    fn close_contact<const N: usize>(&mut self, i: usize, geometry: ContactGeometry) {
        let n = dof::<N>(self.n);
        let c = self.active.len();
        let rows = c * n..(c + 1) * n;
        self.gamma_n[c] = dot(&self.w_n[rows.clone()], &self.u_start[..n]);
        self.gamma_t[c] = dot(&self.w_t[rows], &self.u_start[..n]);
        self.active.push(i);
        self.geometry.push(geometry);
    }

    /// Stage 5, docs/physics.md §4.3 and §4.4: `ũ = u^A + G (h Δt + impulses)` and `G W_N`,
    /// `G W_T` of the `k` closed contacts (and `G w` of the closed joint stops) in one solve with `M`'s factor, then projected
    /// onto the locks (`G ← G − G B (Bᵀ G B)⁻¹ Bᵀ G`, `ũ` likewise).
    #[inline]
    fn free_velocity<const N: usize>(&mut self, k: usize) {
        let (n, dt) = (dof::<N>(self.n), self.settings.dt);
        let layout = self.layout(k);
        let solved = &mut self.solved[..layout.solved_rows() * n];
        let (first, rest) = solved.split_at_mut(n);
        // Into `force` and the first right-hand side in one pass (no reload of `force`).
        let (force, h, impulse) = (&mut self.force[..n], &self.h[..n], &self.impulse[..n]);
        for (((f, s), h), p) in force.iter_mut().zip(first.iter_mut()).zip(h).zip(impulse) {
            *f = h * dt + p;
            *s = *f;
        }
        let (normals, rest) = rest.split_at_mut(k * n);
        let (tangents, rest) = rest.split_at_mut(k * n);
        let (limits, frictions) = rest.split_at_mut(layout.limits * n);
        // Row by row: rows of a length known when compiling are copied in place.
        for (to, from) in [
            (normals, &self.w_n[..k * n]),
            (tangents, &self.w_t[..k * n]),
            (limits, &self.w_limit[..layout.limits * n]),
        ] {
            for (to, from) in to.chunks_exact_mut(n).zip(from.chunks_exact(n)) {
                to.copy_from_slice(from);
            }
        }
        if layout.frictions > 0 {
            frictions.copy_from_slice(&self.dry.w[..layout.frictions * n]);
        }
        self.factor.solve_sized::<N>(solved);
        if self.locks.count > 0 {
            // The stops' mobility `w G w` before the locks, to tell a stop whose velocity
            // they fix (see `limit_rows`).
            let stops = &solved[layout.solved_limit(0) * n..layout.solved_friction(0) * n];
            for (r, row) in stops.chunks_exact(n).enumerate() {
                self.limit_mobility[r] = dot(&self.w_limit[r * n..(r + 1) * n], row);
            }
            for row in solved[n..].chunks_exact_mut(n) {
                self.locks.project(row);
            }
        }
        for ((ut, a), g) in self.u_tilde[..n]
            .iter_mut()
            .zip(&self.u_start[..n])
            .zip(&self.solved[..n])
        {
            *ut = a + g;
        }
        if self.locks.count > 0 {
            self.locks.project(&mut self.u_tilde);
        }
    }

    /// Stage 6, docs/physics.md §4.1 step 3: builds and solves the frictional contact LCP of
    /// §4.3 for the index set (nothing to solve when it is empty); an uncertified solve
    /// falls back to [`Stepper::solve_frictionless_lcp`] or, in strict mode, is an error
    /// (§4.5).
    fn solve_contact_lcp<const N: usize>(
        &mut self,
        model: &Model,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        self.record.lcp_pivots = 0;
        self.record.lcp_failed = false;
        self.record.resolution = Resolution::default();
        let n = dof::<N>(self.n);
        let layout = self.layout(self.active.len());
        let (k, l) = (layout.contacts, layout.limits);
        let size = layout.size();
        if size == 0 {
            return Ok(());
        }
        // A (column-major, leading dimension `ld`) and b of docs/physics.md §4.3.
        let ld = self.lcp_a.nrows();
        // Every entry of the `size × size` block is written once below (the zeros too), so
        // nothing is cleared first.
        let scale = self.contact_friction::<N>(model, layout);
        let a = self.lcp_a.as_mut_slice();
        let b = self.lcp_b.as_mut_slice();
        for r in 0..k {
            let mat_r = &model.material(self.active[r]);
            let mu_r = self.friction[r];
            let (w_n, w_t) = (row(&self.w_n, n, r), row(&self.w_t, n, r));
            let (rn, rs, rc) = (layout.normal(r), layout.sliding(r), layout.cone(r));
            for c in 0..k {
                let mu_c = self.friction[c];
                let (gw_n, gw_t) = (
                    row(&self.solved, n, layout.solved_normal(c)),
                    row(&self.solved, n, layout.solved_tangent(c)),
                );
                let g_nn = dot(w_n, gw_n);
                let g_nt = dot(w_n, gw_t);
                let g_tn = dot(w_t, gw_n);
                let g_tt = dot(w_t, gw_t);
                let (cn, cs, cc) = (layout.normal(c), layout.sliding(c), layout.cone(c));
                a[at(ld, rn, cn)] = g_nn - g_nt * mu_c;
                a[at(ld, rn, cs)] = g_nt;
                a[at(ld, rs, cn)] = g_tn - g_tt * mu_c;
                a[at(ld, rs, cs)] = g_tt;
                // The rows and columns of `ξ_L`: only contact `r`'s own are non-zero, scaled
                // by `s` (unknown `ξ_L / s`, row `s Λ_L`, docs/physics.md §4.3).
                let own = r == c;
                a[at(ld, rn, cc)] = 0.0;
                a[at(ld, rs, cc)] = if own { scale } else { 0.0 };
                a[at(ld, rc, cn)] = if own { 2.0 * mu_r * scale } else { 0.0 };
                a[at(ld, rc, cs)] = if own { -scale } else { 0.0 };
                a[at(ld, rc, cc)] = 0.0;
            }
            b[rn] = dot(w_n, &self.u_tilde[..n]) + mat_r.restitution_normal * self.gamma_n[r];
            b[rs] = dot(w_t, &self.u_tilde[..n]) + mat_r.restitution_tangent * self.gamma_t[r];
            b[rc] = 0.0;
        }
        if l > 0 {
            self.limit_rows::<N>(model, layout);
        }
        if layout.frictions > 0 {
            self.dry_friction_lcp_rows::<N>(layout, scale);
        }
        let (a, b) = (
            self.lcp_a.view((0, 0), (size, size)),
            self.lcp_b.rows(0, size),
        );
        let solution = if self.settings.warm_start {
            self.lcp.solve_warm(a, b, &mut self.warm)
        } else {
            self.lcp.solve(a, b)
        }
        .map_err(|_| StepError::NonFinite {
            step,
            t,
            what: "the contact LCP",
        })?;
        self.stats.solves += 1;
        self.stats.warm_starts += u64::from(solution.method == SolveMethod::WarmStart);
        self.stats.max_pivots = self.stats.max_pivots.max(solution.pivots);
        self.stats.total_pivots += solution.pivots as u64;
        self.record.lcp_pivots = solution.pivots;
        self.record.resolution = Resolution {
            velocity: solution.certificate.tolerance,
            impulse: impulse_resolution(&solution.certificate, scale),
        };
        if solution.status == LcpStatus::Solved {
            // Λ_T = Λ_R − μ Λ_N, ξ_T = ξ_R − ξ_L. The certified solution meets the LCP to
            // its tolerance (`rel_tol` of its scale); projecting the percussions onto the
            // Coulomb cone (Λ_N ≥ 0, |Λ_T| ≤ μ Λ_N) moves them within that tolerance and
            // keeps friction from doing positive work through round-off (e.g. at μ = 0).
            let (z, w) = (&solution.z, &solution.w);
            for c in 0..k {
                let mu = self.friction[c];
                let (normal, sliding) = (layout.normal(c), layout.sliding(c));
                let limit = mu * z[normal].max(0.0);
                self.lambda_n[c] = z[normal].max(0.0);
                self.lambda_t[c] = (z[sliding] - mu * z[normal]).clamp(-limit, limit);
                self.slip[c] = w[sliding] - scale * z[layout.cone(c)];
            }
            for r in 0..l {
                self.lambda_limit[r] = z[layout.limit(r)].max(0.0);
            }
            self.dry.percussions(layout, z.as_slice());
            return Ok(());
        }
        self.stats.failures += 1;
        self.record.lcp_failed = true;
        if self.settings.strict {
            return Err(StepError::Lcp {
                step,
                t,
                size,
                contacts: k,
                status: solution.status.as_str(),
            });
        }
        self.solve_frictionless_lcp(layout, step, t)
    }

    /// Each closed contact's friction coefficient in this step (docs/physics.md §4.8): its
    /// material's `μ`, unless its rows `w_N`, `w_T` are dependent in the metric `G` (the
    /// bodies can move relative to each other along one direction only there, e.g. a
    /// prismatic child against its parent, any contact of a one-coordinate mechanism): then
    /// friction cannot act on its own, Coulomb's law leaves its percussions indeterminate
    /// (and Newton's law with `ε_T ≠ ε_N` contradicts itself), and the contact is a
    /// frictionless one, which moves the bodies exactly as the consistent law would.
    ///
    /// Returns the scale `s` of the friction-cone rows (docs/physics.md §4.3): the largest
    /// diagonal Delassus entry `G_NN`, `G_TT` of the closed contacts (1 where there is none),
    /// so that every row of the LCP is a velocity and its certificate bounds the cone's
    /// violation in the same units as the contact velocities.
    fn contact_friction<const N: usize>(&mut self, model: &Model, layout: Layout) -> f64 {
        let n = dof::<N>(self.n);
        let mut scale: f64 = 0.0;
        for c in 0..layout.contacts {
            let (w_n, w_t) = (row(&self.w_n, n, c), row(&self.w_t, n, c));
            let (gw_n, gw_t) = (
                row(&self.solved, n, layout.solved_normal(c)),
                row(&self.solved, n, layout.solved_tangent(c)),
            );
            let (g_nn, g_nt, g_tt) = (dot(w_n, gw_n), dot(w_n, gw_t), dot(w_t, gw_t));
            let dependent = g_nn * g_tt - g_nt * g_nt <= DEPENDENT_ROWS * g_nn * g_tt;
            self.dependent[c] = dependent;
            self.friction[c] = if dependent {
                0.0
            } else {
                model.material(self.active[c]).friction
            };
            scale = scale.max(g_nn).max(g_tt);
        }
        if layout.frictions > 0 {
            scale = scale.max(self.dry_friction_scale::<N>(layout));
        }
        if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            1.0
        }
    }

    /// The rows and columns of the `l` closed joint stops in the LCP of §4.3 (docs/physics.md
    /// §7): unknowns `Λ_J` after `(Λ_N, Λ_R, ξ_L)`, frictionless normal rows
    /// `ξ_J = w_Jᵀ u^E + ε γ_J^A ⟂ Λ_J`, with `u^E = ũ + G (W_N Λ_N + W_T Λ_T + W_J Λ_J)`.
    fn limit_rows<const N: usize>(&mut self, model: &Model, layout: Layout) {
        let n = dof::<N>(self.n);
        let ld = self.lcp_a.nrows();
        let a = self.lcp_a.as_mut_slice();
        let b = self.lcp_b.as_mut_slice();
        for r in 0..layout.limits {
            let w_j = row(&self.w_limit, n, r);
            let gw_j = row(&self.solved, n, layout.solved_limit(r));
            let rj = layout.limit(r);
            for c in 0..layout.contacts {
                let mu_c = self.friction[c];
                let (gw_n, gw_t) = (
                    row(&self.solved, n, layout.solved_normal(c)),
                    row(&self.solved, n, layout.solved_tangent(c)),
                );
                let (cn, cs, cc) = (layout.normal(c), layout.sliding(c), layout.cone(c));
                // The stop's row: Λ_T = Λ_R − μ Λ_N enters through the Λ_N and Λ_R columns.
                let g_jt = dot(w_j, gw_t);
                a[at(ld, rj, cn)] = dot(w_j, gw_n) - g_jt * mu_c;
                a[at(ld, rj, cs)] = g_jt;
                // The stop's column in the contacts' normal and tangential rows.
                a[at(ld, cn, rj)] = dot(row(&self.w_n, n, c), gw_j);
                a[at(ld, cs, rj)] = dot(row(&self.w_t, n, c), gw_j);
                // No `ξ_L` in the stop's row, no stop in the friction-cone rows.
                a[at(ld, rj, cc)] = 0.0;
                a[at(ld, cc, rj)] = 0.0;
            }
            for c in 0..layout.limits {
                let gw_c = row(&self.solved, n, layout.solved_limit(c));
                a[at(ld, rj, layout.limit(c))] = dot(w_j, gw_c);
            }
            let restitution = model.limits()[self.active_limits[r]].restitution;
            b[rj] = dot(w_j, &self.u_tilde) + restitution * self.gamma_limit[r];
            // A stop whose velocity this step's locks fix (a braked joint: its mobility
            // gone with the projection) cannot move it: it takes no percussion, whatever its
            // restitution asks (docs/physics.md §4.4).
            let own = a[at(ld, rj, rj)];
            self.limit_locked[r] =
                self.locks.count > 0 && own <= DEPENDENT_ROWS * self.limit_mobility[r];
            if self.limit_locked[r] {
                b[rj] = b[rj].max(0.0);
            }
        }
    }

    /// Fallback after an uncertified frictional solve (see [`Stepper`]): the normal-contact
    /// LCP `(W_Nᵀ G W_N) Λ_N + W_Nᵀ ũ + ε_N γ_N^A ⟂ Λ_N` with friction dropped for this step.
    fn solve_frictionless_lcp(
        &mut self,
        layout: Layout,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        let n = self.n;
        let (k, l) = (layout.contacts, layout.limits);
        if layout.frictions > 0 {
            // The joints' friction goes with the contacts' (their percussions are 0).
            self.shift_rows_by_bounds(layout, 1.0);
            self.dry.lambda.fill(0.0);
        }
        // Normal-type rows: the contacts' `w_N`, then the stops' `w_J`; `G w` of each.
        let normal = |i: usize| {
            if i < k {
                (
                    row(&self.w_n, n, i),
                    row(&self.solved, n, layout.solved_normal(i)),
                )
            } else {
                (
                    row(&self.w_limit, n, i - k),
                    row(&self.solved, n, layout.solved_limit(i - k)),
                )
            }
        };
        let size = layout.fallback_size();
        for r in 0..size {
            for c in 0..size {
                self.lcp_a[(r, c)] = dot(normal(r).0, normal(c).1);
            }
        }
        // The contacts' normal right-hand sides stay where they are; the stops' follow them.
        if l > 0 {
            let stops = layout.limit(0)..layout.limit(0) + l;
            self.lcp_b
                .as_mut_slice()
                .copy_within(stops, layout.fallback_limit(0));
        }
        let solution = self
            .lcp
            .solve(
                self.lcp_a.view((0, 0), (size, size)),
                self.lcp_b.rows(0, size),
            )
            .map_err(|_| StepError::NonFinite {
                step,
                t,
                what: "the contact LCP",
            })?;
        self.stats.total_pivots += solution.pivots as u64;
        if solution.status != LcpStatus::Solved {
            return Err(StepError::Lcp {
                step,
                t,
                size,
                contacts: k,
                status: solution.status.as_str(),
            });
        }
        self.record.resolution = Resolution {
            velocity: solution.certificate.tolerance,
            impulse: impulse_resolution(&solution.certificate, f64::INFINITY),
        };
        for c in 0..k {
            self.lambda_n[c] = solution.z[layout.normal(c)].max(0.0);
            self.lambda_t[c] = 0.0;
            self.slip[c] = f64::NAN;
        }
        for r in 0..l {
            self.lambda_limit[r] = solution.z[layout.fallback_limit(r)].max(0.0);
        }
        Ok(())
    }

    /// Stage 7, docs/physics.md §4.1 step 4: `u^E = ũ + G (W_N Λ_N + W_T Λ_T + W_J Λ_J)` and the
    /// records of the `k` closed contacts and the closed joint stops.
    #[inline]
    fn end_velocity<const N: usize>(&mut self, model: &Model, k: usize) {
        let n = dof::<N>(self.n);
        let layout = self.layout(k);
        self.u_end[..n].copy_from_slice(&self.u_tilde[..n]);
        for c in 0..k {
            let normal = row(&self.solved, n, layout.solved_normal(c));
            axpy(self.lambda_n[c], normal, &mut self.u_end);
            let tangent = row(&self.solved, n, layout.solved_tangent(c));
            axpy(self.lambda_t[c], tangent, &mut self.u_end);
        }
        let l = layout.limits;
        for r in 0..l {
            let stop = row(&self.solved, n, layout.solved_limit(r));
            axpy(self.lambda_limit[r], stop, &mut self.u_end);
        }
        if layout.frictions > 0 {
            self.add_dry_friction_velocity::<N>(layout);
        }
        self.record.contacts.clear();
        self.record.pair_contacts.clear();
        if k > 0 {
            self.fill_contact_records::<N>(model, k);
        }
        self.record.limits.clear();
        for r in 0..l {
            let j = self.active_limits[r];
            self.record.limits.push(LimitRecord {
                limit: j,
                body: model.limits()[j].body,
                gap: self.limit_gap[r],
                velocity_before: self.gamma_limit[r],
                velocity_after: dot(row(&self.w_limit, n, r), &self.u_end),
                impulse: self.lambda_limit[r],
                locked: self.limit_locked[r],
            });
        }
    }

    /// The contact records of the step (after `u^E` is known).
    fn fill_contact_records<const N: usize>(&mut self, model: &Model, k: usize) {
        let n = dof::<N>(self.n);
        let resolution = self.record.resolution;
        for c in 0..k {
            let (ln, lt) = (self.lambda_n[c], self.lambda_t[c]);
            let material = model.material(self.active[c]);
            let mut xi_t = self.slip[c];
            if xi_t.is_nan() {
                // Frictionless fallback: ξ_T = γ_T^E + ε_T γ_T^A.
                xi_t = dot(&self.w_t[c * n..(c + 1) * n], &self.u_end)
                    + material.restitution_tangent * self.gamma_t[c];
            }
            let gamma_n_end = dot(&self.w_n[c * n..(c + 1) * n], &self.u_end);
            let gamma_t_end = dot(&self.w_t[c * n..(c + 1) * n], &self.u_end);
            let xi_n = gamma_n_end + material.restitution_normal * self.gamma_n[c];
            let work =
                0.5 * (ln * (self.gamma_n[c] + gamma_n_end) + lt * (self.gamma_t[c] + gamma_t_end));
            let state = ContactState::classify(ln, lt, xi_t, self.friction[c], resolution);
            let geom = self.geometry[c];
            // Terrain contacts, then body–body contacts (numbered from 0 in their list).
            let terrain = model.contacts().len();
            let (records, contact) = match self.active[c].checked_sub(terrain) {
                Some(p) => (&mut self.record.pair_contacts, p),
                None => (&mut self.record.contacts, self.active[c]),
            };
            records.push(ContactRecord {
                contact,
                gap: geom.gap,
                point: geom.point,
                normal: geom.normal,
                impulse_normal: ln,
                impulse_tangent: lt,
                slip_velocity: xi_t,
                normal_velocity: xi_n,
                approach_velocity: self.gamma_n[c],
                work,
                dependent: self.dependent[c],
                state,
            });
        }
    }

    /// Stage 8, docs/physics.md §4.1 step 5: `q^E = q^M + Δt/2 u^E`, `u^E` and `t^E` into `state`
    /// (`t_start`, the start time `t` of the first step, plus `step Δt`), checked, and the
    /// kinematics at `(q^E, u^E)` (for the controller and the ledger).
    #[inline]
    fn integrate<const N: usize>(
        &mut self,
        model: &Model,
        state: &mut State,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        let (n, dt) = (dof::<N>(self.n), self.settings.dt);
        let (q, u) = (
            &mut state.q.as_mut_slice()[..n],
            &mut state.u.as_mut_slice()[..n],
        );
        // The new state is checked in the same pass (finite, below the runaway speed: `0·v`
        // is NaN exactly for a non-finite `v`), and in full for the error's details.
        let (mut non_finite, mut speed) = (0.0, 0.0_f64);
        for (((q, u), m), v) in q
            .iter_mut()
            .zip(u.iter_mut())
            .zip(&self.q_mid[..n])
            .zip(&self.u_end[..n])
        {
            *q = m + 0.5 * dt * v;
            *u = *v;
            non_finite += 0.0 * *q + 0.0 * v;
            speed = speed.max(v.abs());
        }
        if step == 1 {
            self.t_start = t;
        }
        state.t = self.t_start + step as f64 * dt;
        if !(non_finite == 0.0 && speed <= self.settings.max_speed) {
            check_state(state, n, step, t, self.settings.max_speed, false)?;
        }
        self.kinematics
            .update_slices(model, state.q.as_slice(), state.u.as_slice());
        self.record.step = step;
        self.record.t = state.t;
        Ok(())
    }

    /// Stage 9, for observers only (docs/physics.md §6.1): the step's works and lock impulses
    /// ([`Stepper::add_works`]), then the energies and the gaps at the end of the step;
    /// without the energy account ([`Stepper::set_ledger`]) only the lock impulses and the
    /// gaps.
    #[inline]
    fn ledger<const N: usize>(&mut self, model: &Model, actuation: &Actuation) {
        if self.ledger {
            self.add_works::<N>(actuation);
            self.fill_energies(model);
        } else {
            self.record.locks.clear();
            if !actuation.locks.is_empty() {
                self.lock_force::<N>();
                self.push_lock_records(actuation);
            }
        }
        self.fill_gaps(model);
    }

    /// Adds the step's works to the ledger (docs/physics.md §6.1): each percussion times
    /// `(u^A + u^E)/2`; and the velocity-lock impulses `P` (from
    /// `M (u^E − u^A) = h Δt + impulses + W Λ + B P`, §4.4) to the record.
    fn add_works<const N: usize>(&mut self, actuation: &Actuation) {
        let n = dof::<N>(self.n);
        let dt = self.settings.dt;
        let k = self.active.len();
        let u = &self.u_start[..n];
        // The mean velocity (u^A + u^E)/2.
        let mean = &mut self.scratch[..n];
        for ((m, a), e) in mean.iter_mut().zip(u).zip(&self.u_end[..n]) {
            *m = 0.5 * (a + e);
        }
        let mean = &self.scratch[..n];
        // Field by field in place (a copy of the account would reload fields just stored).
        let energy = &mut self.record.energy;
        energy.actuator_work += dt * dot(&self.applied[..n], mean) + dot(&self.impulse[..n], mean);
        // The damping force over the step is `−C ū` (see `add_damping_to_mass`).
        for d in 0..self.damper_count {
            let rate = dot(row(&self.damper_rows, n, d), mean);
            energy.damping_work -= dt * self.damper_c[d] * rate * rate;
        }
        for c in 0..k {
            let rows = c * n..(c + 1) * n;
            energy.contact_work += self.lambda_n[c] * dot(&self.w_n[rows.clone()], mean)
                + self.lambda_t[c] * dot(&self.w_t[rows], mean);
        }
        let l = self.active_limits.len();
        for r in 0..l {
            energy.limit_work += self.lambda_limit[r] * dot(row(&self.w_limit, n, r), mean);
        }
        if self.dry.count() > 0 {
            self.record.energy.dry_friction_work += self.dry_friction_work::<N>();
        }
        self.record.locks.clear();
        if self.locks.count > 0 {
            self.equality_works::<N>(actuation);
        }
    }

    /// The works of the equality rows' percussions (brakes, loop joints) into the ledger,
    /// and the brakes' impulses into the record (see [`Stepper::add_works`]; the mean
    /// velocity is in `scratch`). Out of line: most steps have no equality rows.
    #[inline(never)]
    fn equality_works<const N: usize>(&mut self, actuation: &Actuation) {
        let n = dof::<N>(self.n);
        self.lock_force::<N>();
        let work = dot(&self.force, &self.scratch[..n]);
        if self.locks.loop_rows == 0 {
            self.record.energy.lock_work += work;
        } else {
            // The brakes' share is their impulses times their rows' mean velocity; the
            // loops' percussions did the rest (docs/physics.md §8.2).
            let brakes = self.brake_work::<N>();
            self.record.energy.lock_work += brakes;
            self.record.energy.loop_work += work - brakes;
        }
        if !actuation.locks.is_empty() {
            self.push_lock_records(actuation);
        }
    }

    /// The brakes' work `Σ P_c b_cᵀ ū` of the step, from the equality force `B P` (in
    /// `force`) and the mean velocity `ū` (in `scratch`).
    fn brake_work<const N: usize>(&mut self) -> f64 {
        let (n, brakes) = (dof::<N>(self.n), self.locks.brakes);
        if brakes == 0 {
            return 0.0;
        }
        self.locks.impulses(&self.force);
        let (mean, locks) = (&self.scratch[..n], &self.locks);
        locks.p[..brakes]
            .iter()
            .zip(locks.b.chunks_exact(n))
            .map(|(p, b)| p * dot(b, mean))
            .sum()
    }

    /// Stage 8b, only for a model with loop joints (docs/physics.md §8.4): the end state
    /// projected onto the loops' closure and its tangent space, the loop error into the
    /// record and, with the energy account, the projection's change of energy. Kept out of
    /// line: a tree model's steps never call it.
    #[inline(never)]
    fn close_loops(
        &mut self,
        model: &Model,
        state: &mut State,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        let Some(loops) = self.loops.as_mut() else {
            return Ok(());
        };
        let energy = |kinematics: &Kinematics| {
            let e = model.energies(kinematics);
            e.kinetic + e.potential + e.spring
        };
        let before = if self.ledger {
            energy(&self.kinematics)
        } else {
            0.0
        };
        let (q, u) = (state.q.as_mut_slice(), state.u.as_mut_slice());
        match loops.project(model, &mut self.kinematics, q, u) {
            Ok(error) => self.record.loop_error = error,
            Err(failure) => return Err(failure.into_error(step, t)),
        }
        if self.ledger {
            self.record.energy.projection += energy(&self.kinematics) - before;
        }
        Ok(())
    }

    /// The generalised lock force `B P = M (u^E − u^A) − h Δt − impulses − W Λ` of the
    /// step (docs/physics.md §4.4), into `force` (which held `h Δt + impulses`).
    fn lock_force<const N: usize>(&mut self) {
        let n = dof::<N>(self.n);
        let k = self.active.len();
        let l = self.active_limits.len();
        for i in 0..n {
            let row = &self.mass[i * n..(i + 1) * n];
            let mut rhs = -self.force[i];
            for (m, (e, a)) in row.iter().zip(self.u_end.iter().zip(&self.u_start)) {
                rhs += m * (e - a);
            }
            for c in 0..k {
                rhs -=
                    self.w_n[c * n + i] * self.lambda_n[c] + self.w_t[c * n + i] * self.lambda_t[c];
            }
            for r in 0..l {
                rhs -= self.w_limit[r * n + i] * self.lambda_limit[r];
            }
            for (j, lambda) in self.dry.lambda.iter().enumerate() {
                rhs -= self.dry.w[j * n + i] * lambda;
            }
            self.force[i] = rhs;
        }
    }

    /// The lock impulses `P` of `B P` (in `force`, [`Stepper::lock_force`]) into the record.
    fn push_lock_records(&mut self, actuation: &Actuation) {
        let impulses = self.locks.impulses(&self.force);
        for (&(body, other), &impulse) in actuation.locks.iter().zip(impulses) {
            self.record.locks.push(LockRecord {
                body,
                other,
                impulse,
            });
        }
    }
}

/// The resolution of a certified answer's percussions: `Λ_N`, `Λ_R` are unknowns `z`,
/// certified to the tolerance over `‖A‖_∞`; `Λ_L = 2μΛ_N − Λ_R` enters `w` as `s Λ_L`
/// (the cone rows' scale `cone_scale`, docs/physics.md §4.3), certified to the tolerance
/// over `s` (no cone rows: `s = ∞`). The larger of the two bounds both.
fn impulse_resolution(certificate: &hopsim_lcp::Certificate, cone_scale: f64) -> f64 {
    certificate
        .z_tolerance()
        .max(certificate.tolerance / cone_scale)
}

/// A contact's rows `w_N`, `w_T` are dependent when `G_NN G_TT − G_NT² ≤ DEPENDENT_ROWS
/// G_NN G_TT` (their angle in the metric `G` below about 3e-5 rad; exactly dependent rows
/// leave round-off of about 1e-15): see `Stepper::contact_friction`.
pub const DEPENDENT_ROWS: f64 = 1e-9;

/// The number of coordinates `n` of a stage compiled for `N` of them (`N = 0`: any).
#[inline(always)]
fn dof<const N: usize>(n: usize) -> usize {
    if N == 0 {
        n
    } else {
        N
    }
}

/// Row `i` of a row-major matrix with rows of length `n`: the rows of `w_N`, `w_T` are
/// those of the closed contacts, the rows of `w_limit` those of the closed stops; the rows
/// of `solved` are numbered by [`Layout`] (`solved_normal`, `solved_tangent`,
/// `solved_limit`).
#[inline]
fn row(data: &[f64], n: usize, i: usize) -> &[f64] {
    &data[i * n..(i + 1) * n]
}

/// The equality rows of one step, `Bᵀ u^E = 0`: the velocity locks (brakes, docs/physics.md
/// §4.4), then the loop joints' rows at `q^M` (§8.2). Row-major `l × n` buffers with the
/// rows `b_c` of `Bᵀ` (`∂(θ_body − θ_other)/∂q` for a brake, `∂φ/∂q` for a loop row) and
/// `y_c = M⁻¹ b_c`, the factor of `S = Bᵀ M⁻¹ B` and an `l`-vector. Without loop rows `S`
/// takes the plain `L D Lᵀ` factor (redundant locks are an error); with them the pivoted,
/// rank-revealing one, whose dependent rows take no percussion (§8.3).
struct Locks {
    /// Rows in this step: `brakes + loop_rows`.
    count: usize,
    n: usize,
    b: Vec<f64>,
    y: Vec<f64>,
    s: Vec<f64>,
    s_factor: Factor,
    p: Vec<f64>,
    /// The brakes of this step (the first rows).
    brakes: usize,
    /// The model's loop rows (the last rows of every step).
    loop_rows: usize,
    pivoted: PivotedFactor,
    /// The rank of the loop rows at the run's start.
    loop_rank: usize,
}

impl Locks {
    /// Builds `B`, `Y = M⁻¹ B` (`factor`: that of `M`) and factors `S`; the error is a row
    /// that makes `S` singular (redundant locks, or rows fewer than the loops' rank at the
    /// start independent: a singular configuration).
    fn prepare(
        &mut self,
        model: &Model,
        kinematics: &Kinematics,
        factor: &Factor,
        locks: &[(usize, usize)],
    ) -> Result<(), usize> {
        let (n, l) = (self.n, self.count);
        for (c, &(a, b)) in locks.iter().enumerate() {
            let row = &mut self.b[c * n..(c + 1) * n];
            row.fill(0.0);
            kinematics.add_torque_to(a, Some(b), 1.0, row);
        }
        if self.loop_rows > 0 {
            model.loop_rows_to(kinematics, &mut self.b[self.brakes * n..l * n]);
        }
        self.y[..l * n].copy_from_slice(&self.b[..l * n]);
        factor.solve(&mut self.y[..l * n]);
        for r in 0..l {
            for c in 0..l {
                self.s[r * l + c] = dot(&self.b[r * n..(r + 1) * n], &self.y[c * n..(c + 1) * n]);
            }
        }
        if self.loop_rows == 0 {
            return if self.s_factor.factor(&self.s, l) {
                Ok(())
            } else {
                Err(0)
            };
        }
        let rank = self.pivoted.factor(&self.s, l, DEPENDENT_LOOP_ROWS);
        if rank < self.brakes + self.loop_rank {
            return Err(self.pivoted.dependent().first().copied().unwrap_or(0));
        }
        Ok(())
    }

    /// `S x = p` for the `l`-vector `p` in place (see [`Locks`]).
    fn solve_s(&mut self) {
        let l = self.count;
        if self.loop_rows == 0 {
            self.s_factor.solve(&mut self.p[..l]);
        } else {
            self.pivoted.solve(&mut self.p[..l]);
        }
    }

    /// `x ← x − G B S⁻¹ Bᵀ x` (nothing without locks): applied to `M⁻¹ v` it gives the
    /// projected `(G − G B S⁻¹ Bᵀ G) v`; applied to `ũ`, the projected `ũ`.
    fn project(&mut self, x: &mut [f64]) {
        let (n, l) = (self.n, self.count);
        if l == 0 {
            return;
        }
        for c in 0..l {
            self.p[c] = dot(&self.b[c * n..(c + 1) * n], x);
        }
        self.solve_s();
        for c in 0..l {
            axpy(-self.p[c], &self.y[c * n..(c + 1) * n], x);
        }
    }

    /// The lock impulses `P = (Bᵀ B)⁻¹ Bᵀ (B P)` from the generalised lock force `B P`
    /// (exact, since `B P` lies in the range of `B`; with loop rows a solution of the
    /// pivoted factor, zero on dependent rows); overwrites the factor of `S`.
    fn impulses(&mut self, bp: &[f64]) -> &[f64] {
        let (n, l) = (self.n, self.count);
        for r in 0..l {
            let b_r = &self.b[r * n..(r + 1) * n];
            for c in 0..l {
                self.s[r * l + c] = dot(b_r, &self.b[c * n..(c + 1) * n]);
            }
            self.p[r] = dot(b_r, bp);
        }
        if self.loop_rows > 0 {
            self.pivoted.factor(&self.s, l, DEPENDENT_LOOP_ROWS);
            self.pivoted.solve(&mut self.p[..l]);
        } else if self.s_factor.factor(&self.s, l) {
            self.s_factor.solve(&mut self.p[..l]);
        }
        &self.p[..l]
    }
}

/// A state of the wrong size, a non-finite `q` or `u`, or a speed above `max_speed`, as
/// the step's error; `start`: the state handed to the step (else the one it produced).
fn check_state(
    state: &State,
    n: usize,
    step: u64,
    t: f64,
    max_speed: f64,
    start: bool,
) -> Result<(), StepError> {
    let (q, u) = (state.q.as_slice(), state.u.as_slice());
    if q.len() != n || u.len() != n {
        return Err(StepError::StateSize {
            step,
            t,
            q: q.len(),
            u: u.len(),
            dof: n,
        });
    }
    // Fast path: `0·v` is NaN exactly for a non-finite `v`, so one sum checks them all;
    // `max` of the speeds (NaN-free once the sum is finite) against the limit.
    let non_finite = q
        .iter()
        .chain(u)
        .fold(0.0 * state.t, |acc, v| acc + 0.0 * v);
    let speed = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if non_finite == 0.0 && speed <= max_speed {
        return Ok(());
    }
    if !state.t.is_finite() {
        return Err(StepError::NonFinite { step, t, what: "t" });
    }
    if q.iter().any(|v| !v.is_finite()) {
        let what = if start {
            "q at the start of the step"
        } else {
            "q"
        };
        return Err(StepError::NonFinite { step, t, what });
    }
    for (index, v) in u.iter().enumerate() {
        if !v.is_finite() {
            let what = if start {
                "u at the start of the step"
            } else {
                "u"
            };
            return Err(StepError::NonFinite { step, t, what });
        }
        if v.abs() > max_speed {
            return Err(StepError::Runaway {
                step,
                t,
                index,
                speed: v.abs(),
                limit: max_speed,
            });
        }
    }
    Ok(())
}
