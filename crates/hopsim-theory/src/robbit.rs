//! Robbit, the off-centred disc with a flywheel (docs/physics.md §5.3, thesis ch. 5), as a
//! reduced model: one hopping cycle maps the Poincaré-section state just before the brake
//! to the next one.
//!
//! Coordinates `q = (x, y, φ, ψ)`, `M = diag(m, m, I_S, I_R)`, `m = m_S + m_R`; the disc
//! centre sits at `CoM + (−a sin φ, a cos φ)` (§2) and the flywheel pivots at the CoM.
//! Section state `z = (φ, φ̇)`: the disc rolls on flat ground and the brake is about to fire,
//! `ζ = I_S I_R/(I_S + I_R) (ψ̇ − φ̇) = ζ0` [5.7–5.9], so `ψ̇ = φ̇ + ζ0 / I_red` is fixed by `z`
//! and the control `β = (T, ζ0)`. One cycle ([`cycle`]):
//!
//! 1. [`brake`]: the inelastic lock `ψ̇⁺ = φ̇⁺` (row `B = (0, 0, 1, −1)`) solved together with
//!    the unilateral no-slip ground contact as the stepper's LCP would: the contact stays
//!    closed only if its normal percussion is ≥ 0; otherwise it opens and only the lock acts.
//!    With the contact open the body gains the angular impulse `ζ0`: `φ̇⁺ = φ̇ + ζ0 / I_S`.
//! 2. Flight: ballistic until the first positive root of `g_N = y + a cos φ − R` [3.10]
//!    ([`crate::template::flight`]: the braked robot is the template's rigid eccentric
//!    wheel with `m = m_S + m_R`, `I = I_S + I_R`).
//! 3. [`touchdown`]: restitution-0, no-slip impact (collision matrix, §3) with the flywheel
//!    locked to the body (rows `w_T, w_N, B`; [`FlywheelAtTouchdown::Locked`]) or free
//!    (rows `w_T, w_N`; the stepper's one-step brake, [`FlywheelAtTouchdown::Free`]).
//! 4. [`stance`]: rolling without slip with `+T` on the flywheel and `−T` on the body, [5.15]
//!    `φ̈ = −(T + m g a sin φ + m a R φ̇² sin φ) / (m R² + m a² + I_S − 2 m R a cos φ)`,
//!    `I_R ψ̈ = T`, integrated (Dormand–Prince) until `ζ` reaches `ζ0`: the next section state.
//!
//! Sign conventions (docs/physics.md §1): `φ` counter-clockwise, forward is `+x`, so forward
//! rolling is `φ̇ < 0`. The brake adds `ζ0 > 0` counter-clockwise: a backward-rotating hop,
//! which lifts the disc only when the CoM is behind the contact point, `sin φ < 0`.
//! `docs/analysis.md` §9 has the derivation.

use crate::error::{require_positive, AnalysisError, Result};
use crate::impact;
use crate::numerics::{integrate_to_event, OdeEnd, OdeSettings};
use crate::template::{self, BodyState, NoGaitReason, TemplateParams};
use crate::STANDARD_GRAVITY;
use nalgebra::{DMatrix, SMatrix, SVector};
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt;

/// What the flywheel does at touchdown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FlywheelAtTouchdown {
    /// The brake still holds: the touchdown impact acts on body and flywheel as one rigid
    /// body (`I_S + I_R`), and the stance starts with `ζ = 0`.
    Locked,
    /// The brake released right after locking (hopsim-control's `MomentumImpulse` locks for
    /// one step): the impact changes only `φ̇`, the flywheel keeps its speed.
    Free,
}

impl FlywheelAtTouchdown {
    /// CLI name (`locked`, `free`).
    pub fn name(self) -> &'static str {
        match self {
            FlywheelAtTouchdown::Locked => "locked",
            FlywheelAtTouchdown::Free => "free",
        }
    }
}

/// Robbit's parameters (Table 5.1 of the thesis, docs/physics.md §5.3), SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RobbitParams {
    /// Disc radius `R` [m].
    pub radius: f64,
    /// Eccentricity `a` [m]: CoM to disc centre.
    pub eccentricity: f64,
    /// Main body mass `m_S` [kg].
    pub body_mass: f64,
    /// Flywheel mass `m_R` [kg] (its pivot is at the CoM).
    pub flywheel_mass: f64,
    /// Main body inertia about the CoM `I_S` [kg m²].
    pub body_inertia: f64,
    /// Flywheel inertia `I_R` [kg m²].
    pub flywheel_inertia: f64,
    /// Friction coefficient `μ`: not used by the no-slip model, only checked against.
    pub friction: f64,
    /// Gravitational acceleration [m/s²].
    pub gravity: f64,
    /// The flywheel at touchdown.
    pub touchdown: FlywheelAtTouchdown,
}

impl Default for RobbitParams {
    /// Table 5.1: `R = 0.2, a = 0.1, m_S = 0.974, m_R = 0.431, I_S = 3.004e-3,
    /// I_R = 1.543e-3, μ = 1`, `g = 9.81`, flywheel locked at touchdown.
    fn default() -> Self {
        RobbitParams {
            radius: 0.2,
            eccentricity: 0.1,
            body_mass: 0.974,
            flywheel_mass: 0.431,
            body_inertia: 3.004e-3,
            flywheel_inertia: 1.543e-3,
            friction: 1.0,
            gravity: STANDARD_GRAVITY,
            touchdown: FlywheelAtTouchdown::Locked,
        }
    }
}

/// The control `β = (T, ζ0)` of the momentum-stored impulse (docs/physics.md §5.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Control {
    /// Stance torque `T` [N m]: `+T` on the flywheel, `−T` on the body.
    pub torque: f64,
    /// Impulse limit `ζ0` [N m s]: brake when `ζ ≥ ζ0`.
    pub impulse_limit: f64,
}

/// Poincaré-section state `z = (φ, φ̇)` just before the brake (the disc rolls; `ζ = ζ0`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SectionState {
    /// `φ_TO` [rad].
    pub angle: f64,
    /// `φ̇_TO` [rad/s] (forward rolling: negative).
    pub angular_velocity: f64,
}

impl RobbitParams {
    /// Checks every parameter's physical range.
    pub fn validate(&self) -> Result<()> {
        require_positive("radius", self.radius)?;
        require_positive("body-mass", self.body_mass)?;
        require_positive("flywheel-mass", self.flywheel_mass)?;
        require_positive("body-inertia", self.body_inertia)?;
        require_positive("flywheel-inertia", self.flywheel_inertia)?;
        require_positive("friction", self.friction)?;
        require_positive("gravity", self.gravity)?;
        if !(self.eccentricity.is_finite()
            && self.eccentricity > 0.0
            && self.eccentricity < self.radius)
        {
            return Err(AnalysisError::invalid(
                "eccentricity",
                self.eccentricity,
                "must lie in (0, R): the centre of mass inside the disc, off its centre",
            ));
        }
        Ok(())
    }

    /// `m = m_S + m_R` [kg].
    pub fn total_mass(&self) -> f64 {
        self.body_mass + self.flywheel_mass
    }

    /// `I_red = I_S I_R / (I_S + I_R)` [kg m²]: `ζ = I_red (ψ̇ − φ̇)` [5.7–5.9].
    pub fn reduced_inertia(&self) -> f64 {
        self.body_inertia * self.flywheel_inertia / (self.body_inertia + self.flywheel_inertia)
    }

    /// `m R² + m a² + I_S − 2 m R a cos φ`: the body's inertia about the contact point while
    /// rolling (the denominator of [5.15]).
    pub fn rolling_inertia(&self, phi: f64) -> f64 {
        self.rolling_inertia_at(phi.cos())
    }

    /// [`RobbitParams::rolling_inertia`] from `cos φ`.
    fn rolling_inertia_at(&self, cos: f64) -> f64 {
        let (r, a) = (self.radius, self.eccentricity);
        self.total_mass() * (r * r + a * a - 2.0 * r * a * cos) + self.body_inertia
    }

    /// CoM height while the disc touches the ground, `y = R − a cos φ`.
    pub fn stance_height(&self, phi: f64) -> f64 {
        self.radius - self.eccentricity * phi.cos()
    }

    /// Rolling velocities `(ẋ, ẏ) = φ̇ (a cos φ − R, a sin φ)` [3.16].
    pub fn rolling_velocity(&self, phi: f64, phi_dot: f64) -> [f64; 2] {
        let a = self.eccentricity;
        [
            phi_dot * (a * phi.cos() - self.radius),
            phi_dot * a * phi.sin(),
        ]
    }

    /// [5.15]: `φ̈ = −(T + m g a sin φ + m a R φ̇² sin φ) / (m R² + m a² + I_S − 2 m R a cos φ)`.
    pub fn stance_acceleration(&self, torque: f64, phi: f64, phi_dot: f64) -> f64 {
        self.stance_acceleration_at(torque, phi.sin_cos(), phi_dot)
    }

    /// [`RobbitParams::stance_acceleration`] from `(sin φ, cos φ)`.
    fn stance_acceleration_at(&self, torque: f64, (sin, cos): (f64, f64), phi_dot: f64) -> f64 {
        let m = self.total_mass();
        let a = self.eccentricity;
        -(torque + m * a * sin * (self.gravity + self.radius * phi_dot * phi_dot))
            / self.rolling_inertia_at(cos)
    }

    /// Ground force while rolling, `(F_T, F_N) = m (ẍ, ÿ + g)` [N], from the rolling
    /// kinematics at `(φ, φ̇, φ̈)`.
    pub fn ground_force(&self, phi: f64, phi_dot: f64, phi_ddot: f64) -> [f64; 2] {
        self.ground_force_at(phi.sin_cos(), phi_dot, phi_ddot)
    }

    /// [`RobbitParams::ground_force`] from `(sin φ, cos φ)`.
    fn ground_force_at(&self, (s, c): (f64, f64), phi_dot: f64, phi_ddot: f64) -> [f64; 2] {
        let m = self.total_mass();
        let (a, r) = (self.eccentricity, self.radius);
        [
            m * (phi_ddot * (a * c - r) - a * s * phi_dot * phi_dot),
            m * (self.gravity + a * c * phi_dot * phi_dot + a * s * phi_ddot),
        ]
    }

    /// `M = diag(m, m, I_S, I_R)`.
    pub fn mass_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(4, 4, mass_matrix_fixed(self).as_slice())
    }

    /// Contact rows `w_Tᵀ = (1, 0, R − a cos φ, 0)`, `w_Nᵀ = (0, 1, −a sin φ, 0)` [2.5–2.7],
    /// plus the brake row `B = (0, 0, 1, −1)` when `locked`.
    pub fn constraint_rows(&self, phi: f64, contact: bool, locked: bool) -> DMatrix<f64> {
        let mut rows = Vec::new();
        if contact {
            rows.extend(contact_rows(self, phi).transpose().iter());
        }
        if locked {
            rows.extend(BRAKE_ROW.iter());
        }
        DMatrix::from_row_slice(rows.len() / 4, 4, &rows)
    }

    /// The braked robot as the template's rigid eccentric wheel (§5.1): `R`, `l = R − a`,
    /// `m = m_S + m_R`, `I = I_S + I_R`, `g`; the template's run settings are unused.
    pub fn locked_template(&self) -> TemplateParams {
        TemplateParams {
            radius: self.radius,
            leg_length: self.radius - self.eccentricity,
            mass: self.total_mass(),
            inertia: self.body_inertia + self.flywheel_inertia,
            takeoff_angle: 0.0,
            energy_input: 0.0,
            impulse_tilt: 0.0,
            hops: 1,
            window: 1,
            gravity: self.gravity,
            convergence_tolerance: 1.0,
        }
    }
}

impl SectionState {
    /// The forward-rolling (`φ̇ < 0`) section state at `φ` with take-off energy `E_TO`
    /// ([`SectionState::energy`]): `φ̇ = −sqrt(2 E_TO / (m R² + m a² + I_S − 2 m R a cos φ))`.
    pub fn from_energy(p: &RobbitParams, angle: f64, energy: f64) -> Result<Self> {
        if !angle.is_finite() {
            return Err(AnalysisError::invalid(
                "takeoff-angle",
                angle,
                "must be finite",
            ));
        }
        if !(energy.is_finite() && energy >= 0.0) {
            return Err(AnalysisError::invalid(
                "takeoff-energy",
                energy,
                "must be finite and ≥ 0",
            ));
        }
        Ok(SectionState {
            angle,
            angular_velocity: -(2.0 * energy / p.rolling_inertia(angle)).sqrt(),
        })
    }

    /// Take-off energy `E_TO = ½ (m R² + m a² + I_S − 2 m R a cos φ) φ̇²`: the kinetic energy
    /// of the rolling robot just before the brake without the flywheel's spin (the
    /// translation of both bodies and the rotation of the main body).
    pub fn energy(&self, p: &RobbitParams) -> f64 {
        0.5 * p.rolling_inertia(self.angle) * self.angular_velocity * self.angular_velocity
    }

    /// Generalised velocities `(ẋ, ẏ, φ̇, ψ̇)` on the section: rolling, `ψ̇ = φ̇ + ζ0 / I_red`.
    pub fn velocities(&self, p: &RobbitParams, impulse_limit: f64) -> [f64; 4] {
        let [vx, vy] = p.rolling_velocity(self.angle, self.angular_velocity);
        [
            vx,
            vy,
            self.angular_velocity,
            self.angular_velocity + impulse_limit / p.reduced_inertia(),
        ]
    }
}

/// Why a cycle of the return map does not exist.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum NoCycle {
    /// The brake does not lift the disc: with the contact closed the normal percussion
    /// would be ≥ 0 (the CoM is not behind the contact point, `sin φ ≥ 0`).
    NoLiftOff {
        /// Normal percussion of the brake with the contact kept closed [N s].
        normal_percussion: f64,
    },
    /// The stance turned more than two revolutions without reaching `ζ0`: the robot rolls
    /// away instead of hopping.
    RollsAway {
        /// Stance time when it was given up [s].
        duration: f64,
    },
    /// The stance did not reach `ζ0` within [`STANCE_MAX_TIME`].
    NeverBrakes {
        /// `ζ` when it was given up [N m s].
        stored_impulse: f64,
    },
    /// A numerical failure (no touchdown root, non-finite state, singular impact).
    Numerical {
        /// What failed.
        message: String,
    },
}

impl fmt::Display for NoCycle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NoCycle::NoLiftOff { normal_percussion } => write!(
                f,
                "the brake does not lift the disc off (normal percussion {normal_percussion:.3e} N s ≥ 0 with the contact closed)"
            ),
            NoCycle::RollsAway { duration } => write!(
                f,
                "the stance rolls more than two revolutions without reaching ζ0 (after {duration:.3} s)"
            ),
            NoCycle::NeverBrakes { stored_impulse } => write!(
                f,
                "the stance never reaches ζ0 within {STANCE_MAX_TIME} s (ζ = {stored_impulse:.4} N m s)"
            ),
            NoCycle::Numerical { message } => write!(f, "numerical failure: {message}"),
        }
    }
}

impl NoCycle {
    /// The variant's name as serialised (`kind`): `no-lift-off`, `rolls-away`,
    /// `never-brakes`, `numerical`.
    pub fn kind(&self) -> &'static str {
        match self {
            NoCycle::NoLiftOff { .. } => "no-lift-off",
            NoCycle::RollsAway { .. } => "rolls-away",
            NoCycle::NeverBrakes { .. } => "never-brakes",
            NoCycle::Numerical { .. } => "numerical",
        }
    }
}

fn numerical(err: impl fmt::Display) -> NoCycle {
    NoCycle::Numerical {
        message: err.to_string(),
    }
}

type CycleResult<T> = std::result::Result<T, NoCycle>;

/// The brake (map 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Brake {
    /// `(ẋ, ẏ, φ̇, ψ̇)` after the brake (contact open).
    pub velocity_after: [f64; 4],
    /// Angular impulse the brake transfers to the body [N m s] (equals `ζ0`).
    pub impulse: f64,
    /// Kinetic energy the brake dissipates [J].
    pub energy_loss: f64,
    /// Normal velocity of the contact point after the brake `γ_N⁺ > 0` [m/s].
    pub normal_velocity: f64,
}

/// The contact rows `(w_Tᵀ; w_Nᵀ)` at angle `phi` (see [`RobbitParams::constraint_rows`]),
/// on the stack.
fn contact_rows(p: &RobbitParams, phi: f64) -> SMatrix<f64, 2, 4> {
    let a = p.eccentricity;
    let (sin, cos) = phi.sin_cos();
    SMatrix::<f64, 2, 4>::new(1.0, 0.0, p.radius - a * cos, 0.0, 0.0, 1.0, -a * sin, 0.0)
}

/// The brake row `B = (0, 0, 1, −1)`.
const BRAKE_ROW: SMatrix<f64, 1, 4> = SMatrix::<f64, 1, 4>::new(0.0, 0.0, 1.0, -1.0);

/// The contact rows with the brake row below them.
fn contact_and_brake_rows(p: &RobbitParams, phi: f64) -> SMatrix<f64, 3, 4> {
    let mut rows = SMatrix::<f64, 3, 4>::zeros();
    rows.fixed_rows_mut::<2>(0).copy_from(&contact_rows(p, phi));
    rows.fixed_rows_mut::<1>(2).copy_from(&BRAKE_ROW);
    rows
}

/// `M = diag(m, m, I_S, I_R)` on the stack.
fn mass_matrix_fixed(p: &RobbitParams) -> SMatrix<f64, 4, 4> {
    let m = p.total_mass();
    SMatrix::<f64, 4, 4>::from_diagonal(&SVector::<f64, 4>::new(
        m,
        m,
        p.body_inertia,
        p.flywheel_inertia,
    ))
}

/// Map 1: the brake at the section state `z` with impulse limit `ζ0`, resolved with the
/// unilateral ground contact (docs/physics.md §3, §4): first with the contact closed (rows
/// `w_T, w_N, B`); if its normal percussion is ≥ 0 the disc stays on the ground
/// ([`NoCycle::NoLiftOff`]), otherwise the contact opens and only the lock acts.
pub fn brake(p: &RobbitParams, z: &SectionState, impulse_limit: f64) -> CycleResult<Brake> {
    let mass = mass_matrix_fixed(p);
    let u = SVector::<f64, 4>::from(z.velocities(p, impulse_limit));
    let (_, closed, _) =
        impact::inelastic_impact_fixed(&mass, &contact_and_brake_rows(p, z.angle), &u)
            .map_err(numerical)?;
    let normal_percussion = closed[1];
    if normal_percussion >= 0.0 {
        return Err(NoCycle::NoLiftOff { normal_percussion });
    }
    let (after, lock, energy_change) =
        impact::inelastic_impact_fixed(&mass, &BRAKE_ROW, &u).map_err(numerical)?;
    let normal_velocity = (contact_rows(p, z.angle) * after)[1];
    if normal_velocity.is_nan() || normal_velocity <= 0.0 {
        return Err(NoCycle::NoLiftOff { normal_percussion });
    }
    Ok(Brake {
        velocity_after: after.into(),
        impulse: lock[0],
        energy_loss: -energy_change,
        normal_velocity,
    })
}

/// The touchdown impact (map 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Touchdown {
    /// `(ẋ, ẏ, φ̇, ψ̇)` after the impact (rolling).
    pub velocity_after: [f64; 4],
    /// Kinetic energy lost [J].
    pub energy_loss: f64,
    /// Tangential percussion `Λ_T` [N s].
    pub tangential_percussion: f64,
    /// Normal percussion `Λ_N` [N s] (negative: the no-slip impact pulls the disc down).
    pub normal_percussion: f64,
}

/// Map 3: restitution-0, no-slip touchdown at angle `phi` through the collision matrix
/// (docs/physics.md §3), rows `w_T, w_N` plus the brake row `B` when the flywheel is locked.
pub fn touchdown(p: &RobbitParams, phi: f64, velocity_before: &[f64; 4]) -> Result<Touchdown> {
    let mass = mass_matrix_fixed(p);
    let u = SVector::<f64, 4>::from(*velocity_before);
    let (after, percussion, energy_change) = if p.touchdown == FlywheelAtTouchdown::Locked {
        let (after, percussion, energy) =
            impact::inelastic_impact_fixed(&mass, &contact_and_brake_rows(p, phi), &u)?;
        (after, [percussion[0], percussion[1]], energy)
    } else {
        let (after, percussion, energy) =
            impact::inelastic_impact_fixed(&mass, &contact_rows(p, phi), &u)?;
        (after, [percussion[0], percussion[1]], energy)
    };
    Ok(Touchdown {
        velocity_after: after.into(),
        energy_loss: -energy_change,
        tangential_percussion: percussion[0],
        normal_percussion: percussion[1],
    })
}

/// The longest stance the model integrates before giving up [s].
pub const STANCE_MAX_TIME: f64 = 20.0;

/// Integration settings of the stance: relative tolerance 1e-10, steps ≤ `0.1 sqrt(R/g)`.
fn stance_settings(p: &RobbitParams) -> OdeSettings {
    let time_scale = (p.radius / p.gravity).sqrt();
    OdeSettings {
        rtol: 1e-10,
        atol: 1e-12,
        initial_step: 1e-3 * time_scale,
        max_step: 0.1 * time_scale,
        max_steps: 1_000_000,
    }
}

/// The stance (map 4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stance {
    /// Stance time until `ζ = ζ0` [s].
    pub duration: f64,
    /// `(φ, φ̇)` when `ζ` reaches `ζ0` (angle not wrapped).
    pub end: SectionState,
    /// Flywheel speed `ψ̇` at the end [rad/s].
    pub flywheel_speed: f64,
    /// `ζ` at touchdown [N m s] (0 with a locked flywheel).
    pub initial_impulse: f64,
    /// Work of the motor `T Δ(ψ − φ)` [J].
    pub motor_work: f64,
    /// Smallest ground normal force [N] (negative: the rolling constraint pulls).
    pub min_normal_force: f64,
    /// Largest `|F_T| / F_N` while `F_N > 0` (no-slip needs it ≤ μ).
    pub max_friction_ratio: f64,
    /// Sign changes of `φ̇` during the stance (0: the disc rolls one way only; each rocking
    /// swing adds one).
    pub reversals: usize,
}

/// Map 4: rolling from `(φ0, φ̇0)` with flywheel speed `ψ̇0` under the motor torque `T` until
/// `ζ = I_red (ψ̇ − φ̇)` first reaches `ζ0` ([5.15] with `ψ̇ = ψ̇0 + T t / I_R`), by an adaptive
/// Dormand–Prince 8(5,3) method (rtol 1e-10) with the event located by Brent's method.
/// The stance ends at once when `ζ ≥ ζ0` already at touchdown.
pub fn stance(
    p: &RobbitParams,
    control: &Control,
    start: &SectionState,
    flywheel_speed: f64,
) -> CycleResult<Stance> {
    let torque = control.torque;
    let i_red = p.reduced_inertia();
    let i_r = p.flywheel_inertia;
    let psi_dot = |t: f64| flywheel_speed + torque * t / i_r;
    let stored = |t: f64, phi_dot: f64| i_red * (psi_dot(t) - phi_dot);
    // The state carries (cos φ, sin φ) with (cos φ)' = −φ̇ sin φ, (sin φ)' = φ̇ cos φ, so the
    // right-hand side needs no `sin_cos` (half the cost of the stance otherwise): they are
    // integrated to the same tolerance as φ.
    let f = |_t: f64, y: &[f64; 4]| {
        let [_, rate, cos, sin] = *y;
        let acceleration = p.stance_acceleration_at(torque, (sin, cos), rate);
        [rate, acceleration, -rate * sin, rate * cos]
    };
    let mut min_normal_force = f64::INFINITY;
    let mut max_friction_ratio: f64 = 0.0;
    let mut reversals = 0;
    let mut last_rate = start.angular_velocity;
    let mut track = |y: &[f64; 4]| {
        if y[1] != 0.0 {
            if last_rate != 0.0 && y[1].signum() != last_rate.signum() {
                reversals += 1;
            }
            last_rate = y[1];
        }
        // One `sin_cos` for the acceleration and the force.
        let sc = y[0].sin_cos();
        let [ft, fnorm] = p.ground_force_at(sc, y[1], p.stance_acceleration_at(torque, sc, y[1]));
        min_normal_force = min_normal_force.min(fnorm);
        if fnorm > 0.0 {
            max_friction_ratio = max_friction_ratio.max(ft.abs() / fnorm);
        }
    };
    let (sin0, cos0) = start.angle.sin_cos();
    let y0 = [start.angle, start.angular_velocity, cos0, sin0];
    track(&y0);
    let end = integrate_to_event(
        &f,
        0.0,
        y0,
        &stance_settings(p),
        |t, y| stored(t, y[1]) - control.impulse_limit,
        |t, y| {
            track(y);
            if (y[0] - start.angle).abs() > 4.0 * PI {
                Some(NoCycle::RollsAway { duration: t })
            } else if t > STANCE_MAX_TIME {
                Some(NoCycle::NeverBrakes {
                    stored_impulse: stored(t, y[1]),
                })
            } else {
                None
            }
        },
    );
    let (duration, y) = match end {
        OdeEnd::Event { t, y } => (t, y),
        OdeEnd::Stopped { reason, .. } => return Err(reason),
        OdeEnd::StepLimit { t } => {
            return Err(numerical(format!(
                "stance step limit reached at t = {t:.4} s"
            )))
        }
        OdeEnd::NonFinite { t } => {
            return Err(numerical(format!(
                "non-finite stance state at t = {t:.4} s"
            )))
        }
    };
    track(&y);
    let relative_turn =
        flywheel_speed * duration + 0.5 * torque * duration * duration / i_r - (y[0] - start.angle);
    Ok(Stance {
        duration,
        end: SectionState {
            angle: y[0],
            angular_velocity: y[1],
        },
        flywheel_speed: psi_dot(duration),
        initial_impulse: stored(0.0, start.angular_velocity),
        motor_work: torque * relative_turn,
        min_normal_force,
        max_friction_ratio,
        reversals,
    })
}

/// One full cycle of the return map.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cycle {
    /// Section state at the start.
    pub start: SectionState,
    /// The control.
    pub control: Control,
    /// Map 1.
    pub brake: Brake,
    /// Flight time [s].
    pub flight_time: f64,
    /// `φ` at touchdown [rad].
    pub touchdown_angle: f64,
    /// Map 3.
    pub touchdown: Touchdown,
    /// Map 4.
    pub stance: Stance,
    /// The next section state, `φ` shifted by whole turns to lie within `π` of the start.
    pub next: SectionState,
    /// Whole turns removed from the next angle (`φ_end = next.angle + 2π · revolutions`).
    pub revolutions: i64,
    /// Distance travelled by the CoM over the cycle [m] (forward: > 0).
    pub stride: f64,
    /// Cycle time [s].
    pub period: f64,
}

impl Cycle {
    /// Mean forward speed `stride / period` [m/s].
    pub fn speed(&self) -> f64 {
        self.stride / self.period
    }
}

fn from_template(reason: NoGaitReason) -> NoCycle {
    match reason {
        NoGaitReason::NoLiftOff { normal_velocity } => NoCycle::Numerical {
            message: format!("flight starts with normal velocity {normal_velocity:.3e} m/s ≤ 0"),
        },
        other => numerical(other),
    }
}

/// One cycle from the section state `z` under the control `β` (maps 1–4, module docs).
pub fn cycle(p: &RobbitParams, z: &SectionState, control: &Control) -> CycleResult<Cycle> {
    let b = brake(p, z, control.impulse_limit)?;
    let [vx, vy, w, psi_dot] = b.velocity_after;
    let airborne = BodyState {
        q: [0.0, p.stance_height(z.angle), z.angle],
        u: [vx, vy, w],
    };
    let fl = template::flight(&p.locked_template(), &airborne).map_err(from_template)?;
    let [x_td, _, phi_td] = fl.touchdown.q;
    let [vx_td, vy_td, w_td] = fl.touchdown.u;
    let td = touchdown(p, phi_td, &[vx_td, vy_td, w_td, psi_dot]).map_err(numerical)?;
    let st = stance(
        p,
        control,
        &SectionState {
            angle: phi_td,
            angular_velocity: td.velocity_after[2],
        },
        td.velocity_after[3],
    )?;
    let phi_end = st.end.angle;
    let revolutions = ((phi_end - z.angle) / (2.0 * PI)).round();
    let a = p.eccentricity;
    let stance_distance = a * (phi_end.sin() - phi_td.sin()) - p.radius * (phi_end - phi_td);
    let stride = x_td + stance_distance;
    if !(stride.is_finite() && st.end.angular_velocity.is_finite()) {
        return Err(numerical("non-finite state after the stance"));
    }
    Ok(Cycle {
        start: *z,
        control: *control,
        brake: b,
        flight_time: fl.duration,
        touchdown_angle: phi_td,
        touchdown: td,
        stance: st,
        next: SectionState {
            angle: phi_end - 2.0 * PI * revolutions,
            angular_velocity: st.end.angular_velocity,
        },
        revolutions: revolutions as i64,
        stride,
        period: fl.duration + st.duration,
    })
}

/// The return map `P(z; β)`: the next section state ([`cycle`]).
pub fn return_map(
    p: &RobbitParams,
    z: &SectionState,
    control: &Control,
) -> CycleResult<SectionState> {
    cycle(p, z, control).map(|c| c.next)
}
