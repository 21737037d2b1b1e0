//! What one step reports: contact percussions, lock impulses, energies, LCP statistics.

use hopsim_model::Vec2;

/// Contact status over a step (docs/physics.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactState {
    /// In the index set but carrying no normal percussion: separating.
    Open,
    /// Normal percussion and no tangential slip.
    Stick,
    /// Normal percussion and slip, friction on the Coulomb limit.
    Slip,
}

impl ContactState {
    /// Lower-case name for logs and files.
    pub fn as_str(self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Stick => "stick",
            ContactState::Slip => "slip",
        }
    }
}

/// One contact of the step's index set (`g_N(q^M) ≤ 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactRecord {
    /// Index into the model's contact candidates.
    pub contact: usize,
    /// Gap at the midpoint `g_N(q^M)`, m (≤ 0).
    pub gap: f64,
    /// Contact point on the body at the midpoint, world frame, m.
    pub point: Vec2,
    /// Contact normal (terrain towards body).
    pub normal: Vec2,
    /// Normal percussion `Λ_N`, N s.
    pub impulse_normal: f64,
    /// Tangential percussion `Λ_T` along `t = (n_y, -n_x)`, N s.
    pub impulse_tangent: f64,
    /// Tangential contact velocity law value `ξ_T` at the end of the step, m/s.
    pub slip_velocity: f64,
    /// Normal contact velocity law value `ξ_N = γ_N^E + ε_N γ_N^A` at the end of the step,
    /// m/s: `≥ 0`, and `0` where `Λ_N > 0` (docs/physics.md §4).
    pub normal_velocity: f64,
    /// Normal contact velocity at the start of the step `γ_N^A`, m/s (< 0: approaching).
    pub approach_velocity: f64,
    /// The work of the contact's percussions over the step's mean velocity,
    /// `Λ_N (γ_N^A + γ_N^E)/2 + Λ_T (γ_T^A + γ_T^E)/2`, J: its share of the ledger's
    /// contact work (docs/physics.md §6.1); positive when the contact added energy.
    pub work: f64,
    /// Whether its tangential row depended on its normal one in this step, so that it was
    /// resolved without friction (docs/physics.md §4.8).
    pub dependent: bool,
    /// Open, stick or slip.
    pub state: ContactState,
}

/// How finely a step's contact answer is resolved: the tolerances its LCP certificate
/// holds it to (docs/lcp.md), in the units of the contact laws. Below them a percussion or
/// a velocity is round-off, which is what the contact states are decided against.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Resolution {
    /// Velocities `ξ_N`, `ξ_T`: the certificate's tolerance, m/s (or rad/s).
    pub velocity: f64,
    /// Percussions `Λ`: the larger of the tolerance over `‖A‖_∞` (for `Λ_N`, `Λ_R`, unknowns
    /// of the LCP) and the tolerance over the cone rows' scale (for `Λ_L`, which enters `w`
    /// scaled, docs/physics.md §4.3), N s (or N m s).
    pub impulse: f64,
}

/// A percussion or a velocity counts as non-zero beyond this many times the step's
/// [`Resolution`] (the contact states of [`ContactState`]).
pub const STATE_MARGIN: f64 = 10.0;

impl ContactState {
    /// The state of a contact with normal percussion `normal`, tangential percussion
    /// `tangent` and slip `ξ_T` = `slip`, at Coulomb `μ` = `friction`, in a step resolved to
    /// `resolution`: open without a normal percussion beyond [`STATE_MARGIN`] times the
    /// resolution; slipping when `ξ_T` is beyond it and friction is on the cone (to the
    /// same margin); sticking otherwise.
    pub fn classify(
        normal: f64,
        tangent: f64,
        slip: f64,
        friction: f64,
        resolution: Resolution,
    ) -> Self {
        let impulse = STATE_MARGIN * resolution.impulse;
        if normal <= impulse {
            ContactState::Open
        } else if slip.abs() > STATE_MARGIN * resolution.velocity
            && tangent.abs() >= friction * normal - impulse
        {
            ContactState::Slip
        } else {
            ContactState::Stick
        }
    }
}

/// One velocity lock (brake) of a step: `θ̇_body = θ̇_other` enforced at the step's end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockRecord {
    /// Body whose rotation is locked to `other`'s.
    pub body: usize,
    /// The other body of the pair.
    pub other: usize,
    /// Angular impulse on `body` (its opposite acts on `other`), N m s.
    pub impulse: f64,
}

/// One closed joint stop of a step (`g(q^M) ≤ 0`, docs/physics.md §7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitRecord {
    /// Index into the model's joint stops (`Model::limits`).
    pub limit: usize,
    /// The body whose joint it limits.
    pub body: usize,
    /// Gap at the midpoint `g(q^M)`, rad or m (≤ 0).
    pub gap: f64,
    /// `γ^A = wᵀ u^A`, the stop's opening velocity at the start of the step, rad/s or m/s.
    pub velocity_before: f64,
    /// `γ^E = wᵀ u^E` at the end of the step.
    pub velocity_after: f64,
    /// Percussion `Λ_J` (≥ 0), N m s or N s.
    pub impulse: f64,
    /// Whether the step's velocity locks (a brake on this joint) fixed its velocity, so
    /// that it took no percussion whatever its restitution asked (docs/physics.md §4.4).
    pub locked: bool,
}

/// Running energy account of a simulation (docs/physics.md §6), J.
///
/// `kinetic + potential + spring - initial = actuator_work + contact_work + limit_work +
/// lock_work + loop_work + damping_work + dry_friction_work + projection + balance_error`, the works being those of the step impulses over the
/// step's mean velocity `(u^A + u^E)/2`; the error is the midpoint scheme's own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyLedger {
    /// Kinetic energy at the end of the step.
    pub kinetic: f64,
    /// Gravitational potential energy at the end of the step.
    pub potential: f64,
    /// Energy stored in springs at the end of the step.
    pub spring: f64,
    /// Total mechanical energy at the start of the run.
    pub initial: f64,
    /// Cumulative work of actuator torques and applied impulses.
    pub actuator_work: f64,
    /// Cumulative work of contact percussions (≤ 0 for passive contacts).
    pub contact_work: f64,
    /// Cumulative work of joint-stop percussions (≤ 0 for `ε ≤ 1`).
    pub limit_work: f64,
    /// Cumulative work of velocity locks such as brakes (≤ 0).
    pub lock_work: f64,
    /// Cumulative work of joint and spring damping (≤ 0).
    pub damping_work: f64,
    /// Cumulative work of the joints' dry friction (docs/physics.md §7.5; 0 without).
    pub dry_friction_work: f64,
    /// Cumulative work of the loop joints' percussions (docs/physics.md §8.2; 0 without
    /// loops).
    pub loop_work: f64,
    /// Cumulative change of mechanical energy by the projections onto the loops' closure
    /// after each step (docs/physics.md §8.4; 0 without loops).
    pub projection: f64,
}

impl EnergyLedger {
    /// Mechanical energy now.
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.spring
    }

    /// Energy dissipated so far by impacts, friction, joint stops, locks, loop joints and
    /// damping (≥ 0 when passive).
    pub fn dissipated(&self) -> f64 {
        -(self.contact_work
            + self.limit_work
            + self.lock_work
            + self.damping_work
            + self.dry_friction_work
            + self.loop_work)
    }

    /// What the account fails to explain: `ΔE - W_actuators + dissipated - projection`.
    pub fn balance_error(&self) -> f64 {
        self.total() - self.initial - self.actuator_work + self.dissipated() - self.projection
    }

    /// The energy the account is measured against (docs/physics.md §6.1), J: the largest of
    /// `kinetic + |potential − potential_start| + spring` and the magnitudes of the
    /// cumulative works (`potential_start`: the potential energy at the run's start, so that
    /// the choice of the potential's zero does not matter).
    pub fn scale(&self, potential_start: f64) -> f64 {
        [
            self.actuator_work,
            self.contact_work,
            self.limit_work,
            self.lock_work,
            self.damping_work,
            self.dry_friction_work,
            self.loop_work,
            self.projection,
        ]
        .iter()
        .fold(
            self.kinetic + (self.potential - potential_start).abs() + self.spring,
            |m, w| m.max(w.abs()),
        )
    }
}

/// LCP statistics of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LcpStats {
    /// LCPs solved (steps with at least one closed contact).
    pub solves: u64,
    /// Solves that ended without a certified solution.
    pub failures: u64,
    /// Largest pivot count of a single solve.
    pub max_pivots: usize,
    /// Sum of pivots.
    pub total_pivots: u64,
    /// Solves answered by the previous step's basis, without pivots
    /// ([`crate::StepSettings::warm_start`]).
    pub warm_starts: u64,
}

/// Everything one step produced. Its buffers are reused from step to step.
#[derive(Clone, Debug)]
pub struct StepRecord {
    /// Steps taken so far (1 after the first step).
    pub step: u64,
    /// Time at the end of the step, s.
    pub t: f64,
    /// The terrain contacts of the index set (`contact` indexes `Model::contacts`).
    pub contacts: Vec<ContactRecord>,
    /// The body–body contacts of the index set (docs/physics.md §7): `contact` indexes
    /// `Model::pairs`, `point` is the probe's point `p_B`, `normal` points from the target
    /// (A) to the probe (B), and the percussions act on B (their opposites on A).
    pub pair_contacts: Vec<ContactRecord>,
    /// The closed joint stops of the step.
    pub limits: Vec<LimitRecord>,
    /// The velocity locks (brakes) of this step with their impulses, in the order of
    /// [`crate::Actuation::locks`].
    pub locks: Vec<LockRecord>,
    /// Energy account after the step.
    pub energy: EnergyLedger,
    /// Pivots of this step's LCP (0 without contacts).
    pub lcp_pivots: usize,
    /// Whether this step's LCP ended without a certified solution (the step then used the
    /// frictionless normal-contact LCP).
    pub lcp_failed: bool,
    /// The resolution of this step's contact answer (zero without contacts).
    pub resolution: Resolution,
    /// Largest penetration `max(-g_N, 0)` over the enabled contacts with the world (the
    /// terrain's, and those with shapes of fixed bodies) at the end of the step, m.
    pub max_penetration: f64,
    /// Smallest gap `g_N` over the enabled contacts with the world at the end of the step
    /// (`+∞` when none can touch), m; computed in the same pass as `max_penetration`.
    pub min_gap: f64,
    /// The largest loop-joint residual `|φ|` at the end of the step (m, rad for a weld's
    /// angle), after the projection (docs/physics.md §8.4); 0 without loops.
    pub loop_error: f64,
}

impl Default for StepRecord {
    /// Before any step: no contacts, nothing can touch (`min_gap = +∞`).
    fn default() -> Self {
        Self {
            step: 0,
            t: 0.0,
            contacts: Vec::new(),
            pair_contacts: Vec::new(),
            limits: Vec::new(),
            locks: Vec::new(),
            energy: EnergyLedger::default(),
            lcp_pivots: 0,
            lcp_failed: false,
            resolution: Resolution::default(),
            max_penetration: 0.0,
            min_gap: f64::INFINITY,
            loop_error: 0.0,
        }
    }
}

impl StepRecord {
    /// Sum of normal percussions of the step, N s.
    pub fn total_normal_impulse(&self) -> f64 {
        self.contacts.iter().map(|c| c.impulse_normal).sum()
    }

    /// Whether any contact carried a normal percussion this step.
    pub fn in_contact(&self) -> bool {
        self.contacts.iter().any(|c| c.state != ContactState::Open)
    }
}
