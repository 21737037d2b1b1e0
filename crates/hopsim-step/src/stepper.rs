//! One step of the Moreau midpoint scheme, steps 1-5 of physics.md §4.

use crate::linalg::{cholesky_in_place, cholesky_solve, col_dot, col_dot_vec, mat_vec};
use crate::{
    Actuation, ContactRecord, ContactState, EnergyLedger, ImpulseCommand, LcpStats, LockRecord,
    State, StepRecord,
};
use hopsim_lcp::{LcpStatus, LemkeOptions, LemkeSolver};
use hopsim_model::{ContactGeometry, Model, Workspace};
use nalgebra::{DMatrix, DVector};

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
}

impl Default for StepSettings {
    fn default() -> Self {
        Self {
            dt: 1e-3,
            strict: false,
            max_speed: 1e4,
            lcp: LemkeOptions::default(),
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
    #[error("step {step} (t = {t:.6} s): the mass matrix is not positive definite")]
    SingularMassMatrix { step: u64, t: f64 },
    #[error("step {step} (t = {t:.6} s): the velocity locks are redundant or singular")]
    SingularLocks { step: u64, t: f64 },
    #[error("step {step} (t = {t:.6} s): contact LCP of size {size} ended with {status} ({contacts} closed contacts)")]
    Lcp {
        step: u64,
        t: f64,
        size: usize,
        contacts: usize,
        status: &'static str,
    },
}

/// The time-stepper: reused buffers for one model, so a step allocates nothing.
pub struct Stepper {
    settings: StepSettings,
    enabled: Vec<bool>,
    ws: Workspace,
    mass: DMatrix<f64>,
    chol: DMatrix<f64>,
    /// `G = M⁻¹`, projected onto the velocity locks when there are any.
    g: DMatrix<f64>,
    h: DVector<f64>,
    damping: DVector<f64>,
    applied: DVector<f64>,
    impulse: DVector<f64>,
    u_tilde: DVector<f64>,
    q_mid: DVector<f64>,
    u_end: DVector<f64>,
    scratch: Vec<f64>,
    scratch2: Vec<f64>,
    // Velocity locks: B (n × l), G B, the factor of S = Bᵀ G B.
    b_lock: DMatrix<f64>,
    gb_lock: DMatrix<f64>,
    s_lock: DMatrix<f64>,
    // Contacts of the index set: their indices, geometry, W_N, W_T, G W_N, G W_T.
    active: Vec<usize>,
    geometry: Vec<ContactGeometry>,
    w_n: DMatrix<f64>,
    w_t: DMatrix<f64>,
    gw_n: DMatrix<f64>,
    gw_t: DMatrix<f64>,
    gamma_n: Vec<f64>,
    gamma_t: Vec<f64>,
    lambda_n: Vec<f64>,
    lambda_t: Vec<f64>,
    /// `ξ_T` of each closed contact (NaN after the frictionless fallback).
    slip: Vec<f64>,
    lcp_a: DMatrix<f64>,
    lcp_b: DVector<f64>,
    lcp: LemkeSolver,
    record: StepRecord,
    stats: LcpStats,
}

impl Stepper {
    /// A stepper for `model`, with every contact enabled.
    pub fn new(model: &Model, settings: StepSettings) -> Self {
        let n = model.dof();
        let k = model.contacts.len();
        let locks = model.bodies.len();
        Self {
            lcp: LemkeSolver::new(settings.lcp.clone()),
            settings,
            enabled: vec![true; k],
            ws: Workspace::new(model),
            mass: DMatrix::zeros(n, n),
            chol: DMatrix::zeros(n, n),
            g: DMatrix::zeros(n, n),
            h: DVector::zeros(n),
            damping: DVector::zeros(n),
            applied: DVector::zeros(n),
            impulse: DVector::zeros(n),
            u_tilde: DVector::zeros(n),
            q_mid: DVector::zeros(n),
            u_end: DVector::zeros(n),
            scratch: vec![0.0; n.max(locks)],
            scratch2: vec![0.0; n.max(locks)],
            b_lock: DMatrix::zeros(n, locks),
            gb_lock: DMatrix::zeros(n, locks),
            s_lock: DMatrix::zeros(locks, locks),
            active: Vec::with_capacity(k),
            geometry: Vec::with_capacity(k),
            w_n: DMatrix::zeros(n, k),
            w_t: DMatrix::zeros(n, k),
            gw_n: DMatrix::zeros(n, k),
            gw_t: DMatrix::zeros(n, k),
            gamma_n: vec![0.0; k],
            gamma_t: vec![0.0; k],
            lambda_n: vec![0.0; k],
            lambda_t: vec![0.0; k],
            slip: vec![0.0; k],
            lcp_a: DMatrix::zeros(3 * k, 3 * k),
            lcp_b: DVector::zeros(3 * k),
            record: StepRecord {
                contacts: Vec::with_capacity(k),
                locks: Vec::with_capacity(locks),
                ..StepRecord::default()
            },
            stats: LcpStats::default(),
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
    pub fn workspace(&self) -> &Workspace {
        &self.ws
    }

    /// Resets the record and energy account to `state` at the start of a run.
    pub fn start(&mut self, model: &Model, state: &State) -> &StepRecord {
        self.ws.update(model, &state.q, &state.u);
        let mut energy = EnergyLedger::default();
        self.fill_energies(model, &mut energy);
        energy.initial = energy.total();
        self.record.step = 0;
        self.record.t = state.t;
        self.record.contacts.clear();
        self.record.locks.clear();
        self.record.energy = energy;
        self.record.lcp_pivots = 0;
        self.record.lcp_failed = false;
        self.record.max_penetration = self.max_penetration(model);
        self.stats = LcpStats::default();
        &self.record
    }

    fn fill_energies(&self, model: &Model, energy: &mut EnergyLedger) {
        energy.kinetic = model.kinetic_energy(&self.ws);
        energy.potential = model.potential_energy(&self.ws);
        energy.spring = model.spring_energy(&self.ws);
    }

    fn max_penetration(&self, model: &Model) -> f64 {
        (0..model.contacts.len())
            .filter(|&i| self.enabled[i])
            .filter_map(|i| model.contact_geometry(&self.ws, i))
            .map(|g| -g.gap)
            .fold(0.0, f64::max)
    }

    /// Advances `state` by one step `Δt` under `actuation` (physics.md §4, steps 1-5).
    pub fn step(
        &mut self,
        model: &Model,
        state: &mut State,
        actuation: &Actuation,
    ) -> Result<&StepRecord, StepError> {
        let step = self.record.step + 1;
        let dt = self.settings.dt;
        let n = model.dof();
        let err_t = state.t;
        // 1. Midpoint.
        self.q_mid.copy_from(&state.q);
        self.q_mid.axpy(0.5 * dt, &state.u, 1.0);
        // 2. M(q^M), h(q^M, u^A), actuation.
        self.ws.update(model, &self.q_mid, &state.u);
        model.mass_matrix(&self.ws, &mut self.mass);
        self.applied.fill(0.0);
        for t in &actuation.torques {
            self.ws
                .add_torque(t.body, t.reaction, t.torque, &mut self.applied);
        }
        model.forces(&self.ws, &self.applied, &mut self.h);
        model.damping_forces(&self.ws, &mut self.damping);
        self.impulse.fill(0.0);
        for imp in &actuation.impulses {
            match *imp {
                ImpulseCommand::Point {
                    body,
                    offset,
                    impulse,
                } => self
                    .ws
                    .add_point_force(body, offset, impulse, &mut self.impulse),
                ImpulseCommand::Rotational {
                    body,
                    reaction,
                    impulse,
                } => self
                    .ws
                    .add_torque(body, reaction, impulse, &mut self.impulse),
            }
        }
        // G = M⁻¹ and ũ = u^A + G (h Δt + impulses).
        self.chol.copy_from(&self.mass);
        if !cholesky_in_place(&mut self.chol, n) {
            return Err(StepError::SingularMassMatrix { step, t: err_t });
        }
        for j in 0..n {
            self.scratch[..n].fill(0.0);
            self.scratch[j] = 1.0;
            cholesky_solve(&self.chol, n, &mut self.scratch);
            for i in 0..n {
                self.g[(i, j)] = self.scratch[i];
            }
        }
        for i in 0..n {
            self.scratch2[i] = self.h[i] * dt + self.impulse[i];
        }
        mat_vec(&self.g, n, n, &self.scratch2, &mut self.scratch);
        for i in 0..n {
            self.u_tilde[i] = state.u[i] + self.scratch[i];
        }
        let locks = actuation.locks.len();
        if locks > 0 {
            self.project_locks(model, actuation, step, err_t)?;
        }
        // Index set H: enabled contacts with g_N(q^M) ≤ 0, and their W_N, W_T.
        self.collect_active(model);
        let k = self.active.len();
        self.record.contacts.clear();
        self.record.lcp_pivots = 0;
        self.record.lcp_failed = false;
        if k > 0 {
            self.solve_contacts(model, state, step, err_t)?;
        }
        // 4. u^E = ũ + G (W_N Λ_N + W_T Λ_T).
        self.u_end.copy_from(&self.u_tilde);
        for c in 0..k {
            for i in 0..n {
                self.u_end[i] +=
                    self.gw_n[(i, c)] * self.lambda_n[c] + self.gw_t[(i, c)] * self.lambda_t[c];
            }
        }
        self.account_energy(model, state, actuation);
        // 5. q^E = q^M + Δt/2 u^E.
        state.q.copy_from(&self.q_mid);
        state.q.axpy(0.5 * dt, &self.u_end, 1.0);
        state.u.copy_from(&self.u_end);
        state.t += dt;
        self.check_state(state, step, err_t)?;
        self.ws.update(model, &state.q, &state.u);
        let mut energy = self.record.energy;
        self.fill_energies(model, &mut energy);
        self.record.energy = energy;
        self.record.max_penetration = self.max_penetration(model);
        self.record.step = step;
        self.record.t = state.t;
        Ok(&self.record)
    }

    /// Replaces `G` by `G - G B S⁻¹ Bᵀ G` and `ũ` by `ũ - G B S⁻¹ Bᵀ ũ`, `S = Bᵀ G B`
    /// (physics.md §4, impulsive equality constraints).
    fn project_locks(
        &mut self,
        model: &Model,
        actuation: &Actuation,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        let n = model.dof();
        let l = actuation.locks.len();
        for (c, &(a, b)) in actuation.locks.iter().enumerate() {
            for i in 0..n {
                self.b_lock[(i, c)] =
                    self.ws.jacobian[(3 * a + 2, i)] - self.ws.jacobian[(3 * b + 2, i)];
            }
        }
        for c in 0..l {
            for i in 0..n {
                self.gb_lock[(i, c)] = (0..n).map(|j| self.g[(i, j)] * self.b_lock[(j, c)]).sum();
            }
        }
        for r in 0..l {
            for c in 0..l {
                self.s_lock[(r, c)] = col_dot(&self.b_lock, r, &self.gb_lock, c, n);
            }
        }
        if !cholesky_in_place(&mut self.s_lock, l) {
            return Err(StepError::SingularLocks { step, t });
        }
        // ũ ← ũ - G B S⁻¹ Bᵀ ũ.
        for c in 0..l {
            self.scratch[c] = col_dot_vec(&self.b_lock, c, &self.u_tilde);
        }
        cholesky_solve(&self.s_lock, l, &mut self.scratch);
        for c in 0..l {
            for i in 0..n {
                self.u_tilde[i] -= self.gb_lock[(i, c)] * self.scratch[c];
            }
        }
        // G ← G - (G B) S⁻¹ (G B)ᵀ, column by column.
        for j in 0..n {
            for c in 0..l {
                self.scratch[c] = self.gb_lock[(j, c)];
            }
            cholesky_solve(&self.s_lock, l, &mut self.scratch);
            for i in 0..n {
                let mut s = 0.0;
                for c in 0..l {
                    s += self.gb_lock[(i, c)] * self.scratch[c];
                }
                self.g[(i, j)] -= s;
            }
        }
        Ok(())
    }

    fn collect_active(&mut self, model: &Model) {
        self.active.clear();
        self.geometry.clear();
        for i in 0..model.contacts.len() {
            if !self.enabled[i] {
                continue;
            }
            if let Some(geom) = model.contact_geometry(&self.ws, i) {
                if geom.gap <= 0.0 {
                    self.active.push(i);
                    self.geometry.push(geom);
                }
            }
        }
    }

    /// Builds and solves the contact LCP of physics.md §4 for the index set.
    fn solve_contacts(
        &mut self,
        model: &Model,
        state: &State,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        let n = model.dof();
        let k = self.active.len();
        for (c, (&i, geom)) in self.active.iter().zip(&self.geometry).enumerate() {
            model.contact_directions(
                &self.ws,
                i,
                geom,
                self.w_n.column_mut(c).rows_mut(0, n),
                self.w_t.column_mut(c).rows_mut(0, n),
            );
            self.gamma_n[c] = col_dot_vec(&self.w_n, c, &state.u);
            self.gamma_t[c] = col_dot_vec(&self.w_t, c, &state.u);
            for i in 0..n {
                let (mut sn, mut st) = (0.0, 0.0);
                for j in 0..n {
                    sn += self.g[(i, j)] * self.w_n[(j, c)];
                    st += self.g[(i, j)] * self.w_t[(j, c)];
                }
                self.gw_n[(i, c)] = sn;
                self.gw_t[(i, c)] = st;
            }
        }
        let size = 3 * k;
        self.lcp_a.view_mut((0, 0), (size, size)).fill(0.0);
        for r in 0..k {
            let mat_r = &model.contacts[self.active[r]].material;
            for c in 0..k {
                let mu_c = model.contacts[self.active[c]].material.friction;
                let g_nn = col_dot(&self.w_n, r, &self.gw_n, c, n);
                let g_nt = col_dot(&self.w_n, r, &self.gw_t, c, n);
                let g_tn = col_dot(&self.w_t, r, &self.gw_n, c, n);
                let g_tt = col_dot(&self.w_t, r, &self.gw_t, c, n);
                self.lcp_a[(r, c)] = g_nn - g_nt * mu_c;
                self.lcp_a[(r, k + c)] = g_nt;
                self.lcp_a[(k + r, c)] = g_tn - g_tt * mu_c;
                self.lcp_a[(k + r, k + c)] = g_tt;
            }
            self.lcp_a[(k + r, 2 * k + r)] = 1.0;
            self.lcp_a[(2 * k + r, r)] = 2.0 * mat_r.friction;
            self.lcp_a[(2 * k + r, k + r)] = -1.0;
            self.lcp_b[r] = col_dot_vec(&self.w_n, r, &self.u_tilde)
                + mat_r.restitution_normal * self.gamma_n[r];
            self.lcp_b[k + r] = col_dot_vec(&self.w_t, r, &self.u_tilde)
                + mat_r.restitution_tangent * self.gamma_t[r];
            self.lcp_b[2 * k + r] = 0.0;
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
        self.stats.solves += 1;
        self.stats.max_pivots = self.stats.max_pivots.max(solution.pivots);
        self.stats.total_pivots += solution.pivots as u64;
        self.record.lcp_pivots = solution.pivots;
        if solution.status == LcpStatus::Solved {
            for c in 0..k {
                let mu = model.contacts[self.active[c]].material.friction;
                self.lambda_n[c] = solution.z[c];
                self.lambda_t[c] = solution.z[k + c] - mu * solution.z[c];
                self.slip[c] = solution.w[k + c] - solution.z[2 * k + c];
            }
        } else {
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
            self.solve_frictionless(k, n, step, t)?;
        }
        self.fill_contact_records(model, k, n);
        Ok(())
    }

    /// Fallback after an uncertified frictional solve: the normal-contact LCP
    /// `(W_Nᵀ G W_N) Λ_N + W_Nᵀ ũ + ε_N γ_N^A ⟂ Λ_N` with friction dropped for this step.
    fn solve_frictionless(
        &mut self,
        k: usize,
        n: usize,
        step: u64,
        t: f64,
    ) -> Result<(), StepError> {
        for r in 0..k {
            for c in 0..k {
                self.lcp_a[(r, c)] = col_dot(&self.w_n, r, &self.gw_n, c, n);
            }
        }
        let solution = self
            .lcp
            .solve(self.lcp_a.view((0, 0), (k, k)), self.lcp_b.rows(0, k))
            .map_err(|_| StepError::NonFinite {
                step,
                t,
                what: "the contact LCP",
            })?;
        if solution.status != LcpStatus::Solved {
            return Err(StepError::Lcp {
                step,
                t,
                size: k,
                contacts: k,
                status: solution.status.as_str(),
            });
        }
        for c in 0..k {
            self.lambda_n[c] = solution.z[c];
            self.lambda_t[c] = 0.0;
            self.slip[c] = f64::NAN;
        }
        Ok(())
    }

    fn fill_contact_records(&mut self, model: &Model, k: usize, n: usize) {
        let scale = 1e-9;
        for c in 0..k {
            let (ln, lt) = (self.lambda_n[c], self.lambda_t[c]);
            let mut xi_t = self.slip[c];
            if xi_t.is_nan() {
                // Frictionless fallback: the slip is the end tangential velocity.
                xi_t = (0..n)
                    .map(|i| self.w_t[(i, c)] * self.u_end_estimate(i, k))
                    .sum();
            }
            let mu = model.contacts[self.active[c]].material.friction;
            let state = if ln <= scale * (1.0 + ln.abs()) {
                ContactState::Open
            } else if xi_t.abs() > 1e-8 && lt.abs() >= mu * ln * (1.0 - 1e-9) {
                ContactState::Slip
            } else {
                ContactState::Stick
            };
            let geom = self.geometry[c];
            self.record.contacts.push(ContactRecord {
                contact: self.active[c],
                gap: geom.gap,
                point: geom.point,
                normal: geom.normal,
                impulse_normal: ln,
                impulse_tangent: lt,
                slip_velocity: xi_t,
                state,
            });
        }
    }

    /// `u^E_i` from `ũ` and the percussions (before `u_end` is assembled).
    fn u_end_estimate(&self, i: usize, k: usize) -> f64 {
        self.u_tilde[i]
            + (0..k)
                .map(|c| {
                    self.gw_n[(i, c)] * self.lambda_n[c] + self.gw_t[(i, c)] * self.lambda_t[c]
                })
                .sum::<f64>()
    }

    /// Adds the step's works to the ledger: each impulse times `(u^A + u^E)/2`, and the
    /// velocity-lock impulses `P = -S⁻¹ Bᵀ (u^A + G(hΔt + WΛ) )` to the record.
    fn account_energy(&mut self, model: &Model, state: &State, actuation: &Actuation) {
        let n = model.dof();
        let dt = self.settings.dt;
        let k = self.active.len();
        let mean = |i: usize| 0.5 * (state.u[i] + self.u_end[i]);
        let mut energy = self.record.energy;
        for i in 0..n {
            let m = mean(i);
            energy.actuator_work += (self.applied[i] * dt + self.impulse[i]) * m;
            energy.damping_work += self.damping[i] * dt * m;
            let contact: f64 = (0..k)
                .map(|c| self.w_n[(i, c)] * self.lambda_n[c] + self.w_t[(i, c)] * self.lambda_t[c])
                .sum();
            energy.contact_work += contact * m;
        }
        // The lock impulses follow from M (u^E - u^A) = hΔt + impulses + WΛ + B P.
        self.record.locks.clear();
        let locks = actuation.locks.len();
        if locks > 0 {
            for i in 0..n {
                let mut rhs = -(self.h[i] * dt + self.impulse[i]);
                for c in 0..k {
                    rhs -=
                        self.w_n[(i, c)] * self.lambda_n[c] + self.w_t[(i, c)] * self.lambda_t[c];
                }
                for j in 0..n {
                    rhs += self.mass[(i, j)] * (self.u_end[j] - state.u[j]);
                }
                self.scratch2[i] = rhs;
            }
            // B P = rhs; P = (Bᵀ B)⁻¹ Bᵀ rhs (exact, since rhs lies in the range of B).
            for r in 0..locks {
                for c in 0..locks {
                    self.s_lock[(r, c)] = col_dot(&self.b_lock, r, &self.b_lock, c, n);
                }
                self.scratch[r] = (0..n).map(|i| self.b_lock[(i, r)] * self.scratch2[i]).sum();
            }
            if cholesky_in_place(&mut self.s_lock, locks) {
                cholesky_solve(&self.s_lock, locks, &mut self.scratch);
            }
            for (c, &(body, other)) in actuation.locks.iter().enumerate() {
                self.record.locks.push(LockRecord {
                    body,
                    other,
                    impulse: self.scratch[c],
                });
            }
            energy.lock_work += (0..n).map(|i| self.scratch2[i] * mean(i)).sum::<f64>();
        }
        self.record.energy = energy;
    }

    fn check_state(&self, state: &State, step: u64, t: f64) -> Result<(), StepError> {
        if state.q.iter().any(|v| !v.is_finite()) {
            return Err(StepError::NonFinite { step, t, what: "q" });
        }
        if let Some((index, speed)) = state
            .u
            .iter()
            .map(|v| v.abs())
            .enumerate()
            .find(|(_, v)| !v.is_finite() || *v > self.settings.max_speed)
        {
            if !speed.is_finite() {
                return Err(StepError::NonFinite { step, t, what: "u" });
            }
            return Err(StepError::Runaway {
                step,
                t,
                index,
                speed,
                limit: self.settings.max_speed,
            });
        }
        Ok(())
    }
}
