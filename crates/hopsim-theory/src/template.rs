//! The impulsive eccentric-wheel template (docs/physics.md §5.1, thesis ch. 3).
//!
//! One rigid body `q = (x, y, φ)`: mass `m`, inertia `I` about the centre of mass, a
//! circular foot of radius `R` whose centre sits at `CoM + (−a sin φ, a cos φ)` with
//! eccentricity `a = R − l` (`l`: leg length, CoM to rim). One hop maps take-off state to
//! take-off state through four maps:
//!
//! 1. [`takeoff_impulse`]: at `φ = φ_TO` an impulse `ζ = ‖ζ‖ ρ`,
//!    `ρ = (−sin(φ_TO + τ), cos(φ_TO + τ))`, acts at the contact point and raises the kinetic
//!    energy by exactly `ΔE` ([3.6], [`crate::impact::impulse_for_energy_gain`]).
//! 2. [`flight`]: ballistic flight until the foot touches the ground again, the first
//!    positive root of `g_N(t) = y(t) + a cos φ(t) − R` [2.3, 3.10].
//! 3. [`touchdown`]: restitution-0, no-slip impact through the collision matrix (§3).
//! 4. [`stance`]: energy-conserving rolling (the §2 ODE with `T = 0`) until `φ` reaches
//!    `φ_TO` again moving forward, or "no gait" when it cannot.
//!
//! Sign convention (docs/physics.md §1): `x` to the right, `φ` counter-clockwise. Rolling
//! without slip gives `ẋ = φ̇ (a cos φ − R)`, so with `a < R` forward motion (`ẋ > 0`) means
//! clockwise rotation, `φ̇ < 0`. With `φ_TO < 0` the centre of mass is behind the contact
//! point at take-off and `ρ` leans forward when `φ_TO + τ < 0`: the template hops towards
//! `+x`. A take-off is triggered when `φ` passes `φ_TO` (modulo `2π`) while decreasing.

use crate::error::{require_finite, require_positive, AnalysisError, Result};
use crate::grid::{par_map, CellDone};
use crate::impact;
use crate::numerics::{
    brent, dormand_prince_step, error_norm, first_sign_change_lipschitz, linspace, sinc,
};
use crate::STANDARD_GRAVITY;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt;

/// Parameters of one template run (SI units, angles in radians; serialised with the
/// units in the names: `radius_m`, `energy_input_J`, …).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TemplateParams {
    /// Foot (disc) radius `R` [m].
    #[serde(rename = "radius_m")]
    pub radius: f64,
    /// Leg length `l` [m]: distance from the centre of mass to the rim; `a = R − l`.
    #[serde(rename = "leg_length_m")]
    pub leg_length: f64,
    /// Mass `m` [kg].
    #[serde(rename = "mass_kg")]
    pub mass: f64,
    /// Moment of inertia `I` about the centre of mass [kg m²].
    #[serde(rename = "inertia_kg_m2")]
    pub inertia: f64,
    /// Take-off angle `φ_TO` [rad].
    #[serde(rename = "takeoff_angle_rad")]
    pub takeoff_angle: f64,
    /// Energy added by each take-off impulse `ΔE` [J].
    #[serde(rename = "energy_input_J")]
    pub energy_input: f64,
    /// Impulse tilt `τ` [rad]: `ρ = (−sin(φ_TO + τ), cos(φ_TO + τ))`.
    #[serde(rename = "impulse_tilt_rad")]
    pub impulse_tilt: f64,
    /// Number of hops to simulate (docs/physics.md: 100).
    pub hops: usize,
    /// Hops at the end of the run that the averages are taken over (docs/physics.md: 10).
    pub window: usize,
    /// Gravitational acceleration [m/s²].
    #[serde(rename = "gravity_mps2")]
    pub gravity: f64,
    /// A gait is "converged" when the per-hop speeds of the window differ by at most this
    /// fraction of their mean.
    pub convergence_tolerance: f64,
}

/// The most hops of one template run (each hop is four closed-form maps).
pub const MAX_HOPS: usize = 1_000_000;

impl TemplateParams {
    /// Eccentricity `a = R − l` [m].
    pub fn eccentricity(&self) -> f64 {
        self.radius - self.leg_length
    }

    /// Checks every parameter's physical range.
    pub fn validate(&self) -> Result<()> {
        require_positive("radius", self.radius)?;
        require_positive("leg-length", self.leg_length)?;
        require_positive("mass", self.mass)?;
        require_positive("inertia", self.inertia)?;
        require_positive("gravity", self.gravity)?;
        require_finite("takeoff-angle", self.takeoff_angle)?;
        require_finite("tau", self.impulse_tilt)?;
        if !(self.energy_input.is_finite() && self.energy_input >= 0.0) {
            return Err(AnalysisError::invalid(
                "energy",
                self.energy_input,
                "must be finite and ≥ 0",
            ));
        }
        if self.leg_length >= 2.0 * self.radius {
            return Err(AnalysisError::invalid(
                "leg-length",
                self.leg_length,
                "must be below 2 R (the centre of mass must lie inside the foot disc)",
            ));
        }
        if self.takeoff_angle.abs() >= PI {
            return Err(AnalysisError::invalid(
                "takeoff-angle",
                self.takeoff_angle,
                "must lie in (−π, π)",
            ));
        }
        if self.hops > MAX_HOPS {
            return Err(AnalysisError::invalid(
                "hops",
                self.hops as f64,
                &format!("must be at most {MAX_HOPS}"),
            ));
        }
        if self.window == 0 {
            return Err(AnalysisError::invalid(
                "window",
                0.0,
                "must be at least 1 (hops averaged at the end of the run)",
            ));
        }
        if self.hops < self.window {
            return Err(AnalysisError::invalid(
                "window",
                self.window as f64,
                &format!(
                    "must not exceed the number of hops (`hops` = {})",
                    self.hops
                ),
            ));
        }
        if !(self.convergence_tolerance.is_finite() && self.convergence_tolerance > 0.0) {
            return Err(AnalysisError::invalid(
                "tolerance",
                self.convergence_tolerance,
                "must be a finite number > 0",
            ));
        }
        Ok(())
    }
}

/// Ranges of Table 3.1 for the parameters given there as ranges (the Cargo grid and the
/// animals); the named case uses their midpoints.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CaseRanges {
    /// `R` range [m] (equal ends when fixed).
    pub radius: (f64, f64),
    /// `φ_TO` range [rad].
    pub takeoff_angle: (f64, f64),
    /// `ΔE` range [J].
    pub energy_input: (f64, f64),
}

/// The parameter sets of Table 3.1 (docs/physics.md §5.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TemplateCase {
    /// Cargo trajectory 1: R 0.42, l 0.288, m 130, φ_TO −0.07, ΔE 33.6, τ −0.15, I 4.1.
    Cargo1,
    /// Cargo trajectory 2: R 0.42, l 0.288, m 130, φ_TO −0.10, ΔE 37.6, τ −0.22, I 4.1.
    Cargo2,
    /// Tammar wallaby: R 1.39, l 0.305, m 6.6, φ_TO −0.01…−0.24, ΔE 5.66…10.3, τ 0, I 0.19.
    Wallaby,
    /// Kangaroo rat: R 0.35, l 0.063, m 0.11, φ_TO −0.09…−0.12, ΔE 3.1e-3…4.3e-3, τ 0, I 1.35e-5.
    KangarooRat,
}

/// Base parameters of the Cargo grid (Table 3.1, first row): `R` and `φ_TO` are the grid axes.
pub const CARGO_GRID_RANGES: CaseRanges = CaseRanges {
    radius: (0.3, 5.8),
    takeoff_angle: (-0.2, -0.01),
    energy_input: (35.0, 35.0),
};

fn midpoint(range: (f64, f64)) -> f64 {
    0.5 * (range.0 + range.1)
}

impl TemplateCase {
    /// Every case, in Table 3.1's order.
    pub const ALL: [TemplateCase; 4] = [
        TemplateCase::Cargo1,
        TemplateCase::Cargo2,
        TemplateCase::Wallaby,
        TemplateCase::KangarooRat,
    ];

    /// The CLI name (`cargo-1`, `cargo-2`, `wallaby`, `kangaroo-rat`).
    pub fn name(self) -> &'static str {
        match self {
            TemplateCase::Cargo1 => "cargo-1",
            TemplateCase::Cargo2 => "cargo-2",
            TemplateCase::Wallaby => "wallaby",
            TemplateCase::KangarooRat => "kangaroo-rat",
        }
    }

    /// The case called `name`, or an error listing the valid names.
    pub fn from_name(name: &str) -> Result<Self> {
        TemplateCase::ALL
            .into_iter()
            .find(|c| c.name() == name)
            .ok_or_else(|| AnalysisError::InvalidParameter {
                name: "case".into(),
                value: name.into(),
                reason: format!(
                    "unknown case; valid names: {}",
                    TemplateCase::ALL.map(TemplateCase::name).join(", ")
                ),
            })
    }

    /// The Table-3.1 ranges of this case (fixed values have equal ends).
    pub fn ranges(self) -> CaseRanges {
        match self {
            TemplateCase::Cargo1 => CaseRanges {
                radius: (0.42, 0.42),
                takeoff_angle: (-0.07, -0.07),
                energy_input: (33.6, 33.6),
            },
            TemplateCase::Cargo2 => CaseRanges {
                radius: (0.42, 0.42),
                takeoff_angle: (-0.10, -0.10),
                energy_input: (37.6, 37.6),
            },
            TemplateCase::Wallaby => CaseRanges {
                radius: (1.39, 1.39),
                takeoff_angle: (-0.24, -0.01),
                energy_input: (5.66, 10.3),
            },
            TemplateCase::KangarooRat => CaseRanges {
                radius: (0.35, 0.35),
                takeoff_angle: (-0.12, -0.09),
                energy_input: (3.1e-3, 4.3e-3),
            },
        }
    }

    /// The parameters of this case; a parameter given in Table 3.1 as a range takes the
    /// range's midpoint. 100 hops, averages over the last 10, `g = 9.81`.
    pub fn params(self) -> TemplateParams {
        let ranges = self.ranges();
        let (leg_length, mass, impulse_tilt, inertia) = match self {
            TemplateCase::Cargo1 => (0.288, 130.0, -0.15, 4.1),
            TemplateCase::Cargo2 => (0.288, 130.0, -0.22, 4.1),
            TemplateCase::Wallaby => (0.305, 6.6, 0.0, 0.19),
            TemplateCase::KangarooRat => (0.063, 0.11, 0.0, 1.35e-5),
        };
        TemplateParams {
            radius: midpoint(ranges.radius),
            leg_length,
            mass,
            inertia,
            takeoff_angle: midpoint(ranges.takeoff_angle),
            energy_input: midpoint(ranges.energy_input),
            impulse_tilt,
            hops: 100,
            window: 10,
            gravity: STANDARD_GRAVITY,
            convergence_tolerance: 1e-3,
        }
    }
}

/// Configuration `q = (x, y, φ)` and velocities `u = (ẋ, ẏ, φ̇)` of the body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BodyState {
    /// `(x, y, φ)`: centre-of-mass position [m] and angle [rad].
    pub q: [f64; 3],
    /// `(ẋ, ẏ, φ̇)` [m/s, m/s, rad/s].
    pub u: [f64; 3],
}

/// Mass matrix `M = diag(m, m, I)`.
pub fn mass_matrix(p: &TemplateParams) -> DMatrix<f64> {
    DMatrix::from_diagonal(&DVector::from_vec(vec![p.mass, p.mass, p.inertia]))
}

/// Contact Jacobian at the lowest point of the foot, rows `w_Tᵀ = (1, 0, R − a cos φ)` and
/// `w_Nᵀ = (0, 1, −a sin φ)` [2.5–2.7]: `J u` is the contact point's velocity `(γ_T, γ_N)`.
pub fn contact_jacobian(p: &TemplateParams, phi: f64) -> DMatrix<f64> {
    let a = p.eccentricity();
    DMatrix::from_row_slice(
        2,
        3,
        &[1.0, 0.0, p.radius - a * phi.cos(), 0.0, 1.0, -a * phi.sin()],
    )
}

/// Centre-of-mass height while the foot touches flat ground: `y = R − a cos φ` (`g_N = 0`).
pub fn stance_height(p: &TemplateParams, phi: f64) -> f64 {
    p.radius - p.eccentricity() * phi.cos()
}

/// Gap `g_N = y + a cos φ − R` [2.3].
pub fn gap(p: &TemplateParams, y: f64, phi: f64) -> f64 {
    y + p.eccentricity() * phi.cos() - p.radius
}

/// Velocities of rolling without slip: `u = φ̇ (a cos φ − R, a sin φ, 1)` [3.16].
pub fn rolling_velocity(p: &TemplateParams, phi: f64, phi_dot: f64) -> [f64; 3] {
    let a = p.eccentricity();
    [
        phi_dot * (a * phi.cos() - p.radius),
        phi_dot * a * phi.sin(),
        phi_dot,
    ]
}

/// Effective inertia about the contact point while rolling:
/// `m R² + m a² + I − 2 m R a cos φ` (the kinetic energy is `½ (…) φ̇²`).
pub fn rolling_inertia(p: &TemplateParams, phi: f64) -> f64 {
    let a = p.eccentricity();
    p.mass * (p.radius * p.radius + a * a - 2.0 * p.radius * a * phi.cos()) + p.inertia
}

/// Angular acceleration while rolling with no torque (docs/physics.md §2 with `T = 0`):
/// `φ̈ = −(m g a sin φ + m a R φ̇² sin φ) / (m R² + m a² + I − 2 m R a cos φ)`.
pub fn stance_acceleration(p: &TemplateParams, phi: f64, phi_dot: f64) -> f64 {
    let a = p.eccentricity();
    -(p.mass * a * phi.sin() * (p.gravity + p.radius * phi_dot * phi_dot)) / rolling_inertia(p, phi)
}

/// Total mechanical energy `½ m (ẋ² + ẏ²) + ½ I φ̇² + m g y` [J].
pub fn mechanical_energy(p: &TemplateParams, state: &BodyState) -> f64 {
    let [vx, vy, w] = state.u;
    0.5 * p.mass * (vx * vx + vy * vy) + 0.5 * p.inertia * w * w + p.mass * p.gravity * state.q[1]
}

/// Energy of a rolling state from `(φ, φ̇)` alone: `½ (m R² + m a² + I − 2mRa cos φ) φ̇² + m g (R − a cos φ)`.
pub fn rolling_energy(p: &TemplateParams, phi: f64, phi_dot: f64) -> f64 {
    0.5 * rolling_inertia(p, phi) * phi_dot * phi_dot + p.mass * p.gravity * stance_height(p, phi)
}

/// The take-off impulse direction `ρ = (−sin(φ_TO + τ), cos(φ_TO + τ))`.
pub fn impulse_direction(p: &TemplateParams) -> [f64; 2] {
    let angle = p.takeoff_angle + p.impulse_tilt;
    [-angle.sin(), angle.cos()]
}

/// Why the template has no gait.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum NoGaitReason {
    /// The take-off impulse does not lift the foot: the contact point's normal velocity
    /// after the impulse is not positive.
    NoLiftOff {
        /// `γ_N⁺` [m/s].
        normal_velocity: f64,
    },
    /// After touchdown the stance energy is below the potential energy at `φ_TO`: the
    /// wheel rocks back before it reaches the take-off angle.
    StanceFallsShort {
        /// Energy after touchdown [J].
        stance_energy: f64,
        /// `m g (R − a cos φ_TO)` [J].
        required_energy: f64,
    },
    /// The stance never passes `φ_TO` moving forward (it rolls over backwards).
    StanceNeverReturns,
    /// The converged motion goes backwards (mean speed ≤ 0).
    MovesBackward {
        /// Mean speed over the window [m/s].
        mean_speed: f64,
    },
    /// A numerical failure (non-finite state, no touchdown root).
    Numerical {
        /// What failed.
        message: String,
    },
}

impl fmt::Display for NoGaitReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NoGaitReason::NoLiftOff { normal_velocity } => write!(
                f,
                "the take-off impulse does not lift the foot off the ground (normal contact velocity {normal_velocity:.3e} m/s ≤ 0)"
            ),
            NoGaitReason::StanceFallsShort {
                stance_energy,
                required_energy,
            } => write!(
                f,
                "stance cannot reach the take-off angle: energy after touchdown {stance_energy:.4} J is below the potential energy {required_energy:.4} J at φ_TO"
            ),
            NoGaitReason::StanceNeverReturns => {
                write!(f, "stance never passes the take-off angle moving forward (the wheel rolls over backwards)")
            }
            NoGaitReason::MovesBackward { mean_speed } => {
                write!(f, "the motion goes backwards (mean speed {mean_speed:.4} m/s)")
            }
            NoGaitReason::Numerical { message } => write!(f, "numerical failure: {message}"),
        }
    }
}

/// "No gait", with the hop (0-based) at which it was detected.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoGait {
    /// Hop index (0-based) at which the cycle failed.
    pub hop: usize,
    /// Why.
    pub reason: NoGaitReason,
}

impl fmt::Display for NoGait {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "no gait (hop {}): {}", self.hop + 1, self.reason)
    }
}

fn numerical(err: AnalysisError) -> NoGaitReason {
    NoGaitReason::Numerical {
        message: err.to_string(),
    }
}

/// Map 1: the take-off impulse.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Takeoff {
    /// Velocities after the impulse.
    pub velocity_after: [f64; 3],
    /// Impulse magnitude `‖ζ‖` [N s].
    pub impulse: f64,
    /// Impulse vector `‖ζ‖ ρ` [N s].
    pub impulse_vector: [f64; 2],
    /// Normal velocity of the contact point after the impulse, `γ_N⁺` [m/s].
    pub normal_velocity: f64,
}

/// Map 1 [3.6]: the impulse along `ρ` at the contact point that raises the kinetic energy
/// by `ΔE`, applied as `u⁺ = u⁻ + M⁻¹ Jᵀ ζ` [2.22].
pub fn takeoff_impulse(p: &TemplateParams, state: &BodyState) -> Result<Takeoff> {
    let mass = mass_matrix(p);
    let jac = contact_jacobian(p, state.q[2]);
    let rho = impulse_direction(p);
    let direction = DVector::from_row_slice(&rho);
    let u = DVector::from_row_slice(&state.u);
    let magnitude = impact::impulse_for_energy_gain(&mass, &jac, &direction, &u, p.energy_input)?;
    let impulse = &direction * magnitude;
    let after = impact::apply_impulse(&mass, &jac, &u, &impulse)?;
    let normal_velocity = (&jac * &after)[1];
    Ok(Takeoff {
        velocity_after: [after[0], after[1], after[2]],
        impulse: magnitude,
        impulse_vector: [impulse[0], impulse[1]],
        normal_velocity,
    })
}

/// Ballistic state a time `t` after `start` (no contact).
pub fn flight_state(p: &TemplateParams, start: &BodyState, t: f64) -> BodyState {
    let [x, y, phi] = start.q;
    let [vx, vy, w] = start.u;
    BodyState {
        q: [
            x + vx * t,
            y + vy * t - 0.5 * p.gravity * t * t,
            phi + w * t,
        ],
        u: [vx, vy - p.gravity * t, w],
    }
}

/// Map 2: ballistic flight from a state on the ground (`g_N = 0`) with the foot lifting off.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Flight {
    /// Flight time [s].
    pub duration: f64,
    /// State just before touchdown.
    pub touchdown: BodyState,
}

/// Map 2: the first positive root of `g_N(t) = y(t) + a cos φ(t) − R` with `y` quadratic and
/// `φ` linear in `t` [3.10]. `start` must be on the ground (`g_N = 0`).
///
/// The root at `t = 0` is divided out analytically:
/// `g_N(t)/t = ẏ − ½ g t − a ω sin(φ₀ + ωt/2) sinc(ωt/2)`, which equals `γ_N⁺ > 0` at
/// `t = 0`. Since `|a (cos φ(t) − cos φ₀)| ≤ 2|a|`, the root lies before
/// `t_max = (ẏ + sqrt(ẏ² + 4 g |a|)) / g`; `[0, t_max]` is scanned with steps of 0.05 rad
/// of rotation (at most `t_max/256`), or longer where `|g_N/t|` divided by its slope bound
/// `g + |a| ω²` shows that no root is nearer, and the first sign change is refined by
/// Brent's method.
pub fn flight(p: &TemplateParams, start: &BodyState) -> std::result::Result<Flight, NoGaitReason> {
    let a = p.eccentricity();
    let phi0 = start.q[2];
    let [_, vy, w] = start.u;
    let normal_velocity = vy - a * phi0.sin() * w;
    if normal_velocity.is_nan() || normal_velocity <= 0.0 {
        return Err(NoGaitReason::NoLiftOff { normal_velocity });
    }
    let g = p.gravity;
    let gap_over_t =
        |t: f64| vy - 0.5 * g * t - a * w * (phi0 + 0.5 * w * t).sin() * sinc(0.5 * w * t);
    let t_max = (vy + (vy * vy + 4.0 * g * a.abs()).sqrt()) / g * (1.0 + 1e-9) + 1e-12;
    let steps = ((w.abs() * t_max / 0.05).ceil() as usize).clamp(256, 1_000_000);
    // |d/dt (g_N/t)| ≤ max |g_N''| ≤ g + |a| ω²: g_N/t is the mean of g_N' over [0, t].
    let lipschitz = g + a.abs() * w * w;
    let tolerance = 1e-15 * t_max.max(1e-6);
    let duration = first_sign_change_lipschitz(gap_over_t, 0.0, t_max, steps, lipschitz, tolerance)
        .ok_or_else(|| NoGaitReason::Numerical {
            message: format!("no touchdown found within {t_max:.4e} s of flight"),
        })?;
    Ok(Flight {
        duration,
        touchdown: flight_state(p, start, duration),
    })
}

/// Map 3: the touchdown impact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Touchdown {
    /// Velocities after the impact (rolling: `J u⁺ = 0`).
    pub velocity_after: [f64; 3],
    /// Kinetic energy lost, `−½ u⁻ᵀ M_c u⁻ ≥ 0` [J].
    pub energy_loss: f64,
    /// Percussion `(Λ_T, Λ_N)` [N s].
    pub percussion: [f64; 2],
}

/// Map 3: restitution-0, no-slip touchdown through the collision matrix (§3).
pub fn touchdown(p: &TemplateParams, state: &BodyState) -> Result<Touchdown> {
    let mass = mass_matrix(p);
    let jac = contact_jacobian(p, state.q[2]);
    let hit = impact::inelastic_impact(&mass, &jac, &DVector::from_row_slice(&state.u))?;
    let v = &hit.velocity_after;
    Ok(Touchdown {
        velocity_after: [v[0], v[1], v[2]],
        energy_loss: -hit.energy_change,
        percussion: [hit.percussion[0], hit.percussion[1]],
    })
}

/// One accepted step of the stance integration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StanceSample {
    /// Time since touchdown [s].
    pub t: f64,
    /// Angle [rad] (continuous, not wrapped).
    pub phi: f64,
    /// Angular velocity [rad/s].
    pub phi_dot: f64,
}

/// Map 4: the rolling stance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stance {
    /// Stance time [s].
    pub duration: f64,
    /// Rolling state at `φ = φ_TO` (before the next take-off impulse), `φ` wrapped to `φ_TO`.
    pub takeoff: BodyState,
    /// Accepted integration steps (including the start and the final state), when recorded.
    pub samples: Vec<StanceSample>,
    /// Smallest normal ground force during stance, `m (g + ÿ)` [N]; negative values mean
    /// the rolling constraint would need the ground to pull (the template ignores this).
    pub min_normal_force: f64,
    /// Full forward revolutions rolled before reaching `φ_TO` again (`φ` ended at
    /// `φ_TO − 2π·revolutions`): the wheel rolled over the top ("wheel mode").
    pub revolutions: i64,
}

const STANCE_RTOL: f64 = 1e-11;
const STANCE_ATOL: f64 = 1e-12;
const STANCE_MAX_STEPS: usize = 200_000;

/// Map 4: integrates the rolling ODE (docs/physics.md §2, `T = 0`) from the post-touchdown state
/// until `φ` passes `φ_TO + 2πk` while decreasing (forward rolling), with an adaptive
/// Dormand–Prince 5(4) method (relative tolerance 1e-11); the crossing is located by
/// Brent's method on the step size. `x` follows the rolling constraint in closed form,
/// `x(φ) = x_TD + a (sin φ − sin φ_TD) − R (φ − φ_TD)`, `y = R − a cos φ`.
///
/// Fails with [`NoGaitReason::StanceFallsShort`] when the energy is below `V(φ_TO)` and with
/// [`NoGaitReason::StanceNeverReturns`] when the wheel has turned more than 4 revolutions
/// without a forward crossing.
pub fn stance(
    p: &TemplateParams,
    start: &BodyState,
    record: bool,
) -> std::result::Result<Stance, NoGaitReason> {
    let a = p.eccentricity();
    let phi0 = start.q[2];
    let w0 = start.u[2];
    let x0 = start.q[0];
    let energy = rolling_energy(p, phi0, w0);
    let required = p.mass * p.gravity * stance_height(p, p.takeoff_angle);
    if !energy.is_finite() || energy < required {
        return Err(NoGaitReason::StanceFallsShort {
            stance_energy: energy,
            required_energy: required,
        });
    }
    let f = |_t: f64, y: &[f64; 2]| [y[1], stance_acceleration(p, y[0], y[1])];
    let normal_force = |phi: f64, w: f64| {
        let acc = stance_acceleration(p, phi, w);
        p.mass * (p.gravity + a * phi.cos() * w * w + a * phi.sin() * acc)
    };
    let time_scale = (p.radius / p.gravity).sqrt();
    let h_max = 0.05 * time_scale;
    let mut h = 1e-3 * time_scale;
    let mut t = 0.0;
    let mut y = [phi0, w0];
    let mut travelled = 0.0;
    let mut samples = Vec::new();
    if record {
        samples.push(StanceSample {
            t,
            phi: y[0],
            phi_dot: y[1],
        });
    }
    let mut min_normal_force = normal_force(y[0], y[1]);
    for _ in 0..STANCE_MAX_STEPS {
        if travelled > 8.0 * PI {
            return Err(NoGaitReason::StanceNeverReturns);
        }
        let (y_new, err) = dormand_prince_step(&f, t, &y, h);
        let norm = error_norm(&y, &y_new, &err, STANCE_RTOL, STANCE_ATOL);
        if !norm.is_finite() {
            return Err(NoGaitReason::Numerical {
                message: "non-finite state in stance".into(),
            });
        }
        if norm > 1.0 {
            h *= (0.9 * norm.powf(-0.2)).max(0.2);
            continue;
        }
        if y_new[0] < y[0] {
            let k = ((y[0] - p.takeoff_angle) / (2.0 * PI)).floor();
            let target = p.takeoff_angle + 2.0 * PI * k;
            if target > y_new[0] {
                let (t_start, y_start) = (t, y);
                let s = brent(
                    |s| {
                        if s == 0.0 {
                            y_start[0] - target
                        } else {
                            dormand_prince_step(&f, t_start, &y_start, s).0[0] - target
                        }
                    },
                    0.0,
                    h,
                    1e-15 * time_scale,
                )
                .unwrap_or(h);
                let y_end = if s == 0.0 {
                    y_start
                } else {
                    dormand_prince_step(&f, t_start, &y_start, s).0
                };
                let duration = t_start + s;
                let w_end = y_end[1];
                min_normal_force = min_normal_force.min(normal_force(target, w_end));
                if record {
                    samples.push(StanceSample {
                        t: duration,
                        phi: target,
                        phi_dot: w_end,
                    });
                }
                let x_end = x0 + a * (target.sin() - phi0.sin()) - p.radius * (target - phi0);
                let phi_wrapped = p.takeoff_angle;
                return Ok(Stance {
                    duration,
                    takeoff: BodyState {
                        q: [x_end, stance_height(p, phi_wrapped), phi_wrapped],
                        u: rolling_velocity(p, phi_wrapped, w_end),
                    },
                    samples,
                    min_normal_force,
                    revolutions: -(k as i64),
                });
            }
        }
        travelled += (y_new[0] - y[0]).abs();
        t += h;
        y = y_new;
        min_normal_force = min_normal_force.min(normal_force(y[0], y[1]));
        if record {
            samples.push(StanceSample {
                t,
                phi: y[0],
                phi_dot: y[1],
            });
        }
        h = (h * (0.9 * norm.max(1e-10).powf(-0.2)).min(5.0)).min(h_max);
    }
    Err(NoGaitReason::Numerical {
        message: format!("stance did not finish within {STANCE_MAX_STEPS} steps"),
    })
}

/// The phase a trajectory sample belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// Ballistic flight.
    Flight,
    /// Rolling stance.
    Stance,
}

impl Phase {
    /// Lower-case name for CSV.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Flight => "flight",
            Phase::Stance => "stance",
        }
    }
}

/// One sample of the centre-of-mass trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrajectorySample {
    /// Hop index (0-based).
    pub hop: usize,
    /// Phase.
    pub phase: Phase,
    /// Time [s].
    pub t: f64,
    /// `(x, y, φ)` and `(ẋ, ẏ, φ̇)`.
    pub state: BodyState,
}

/// One hop: take-off, flight, touchdown and stance back to the next take-off.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HopRecord {
    /// Hop index (0-based).
    pub index: usize,
    /// Time of the take-off impulse [s].
    pub takeoff_time_s: f64,
    /// `x` at take-off [m].
    pub takeoff_x_m: f64,
    /// `φ̇` just before the impulse [rad/s].
    pub takeoff_angular_velocity_rad_s: f64,
    /// `‖ζ‖` [N s].
    #[serde(rename = "impulse_Ns")]
    pub impulse_n_s: f64,
    /// Flight time [s].
    pub flight_time_s: f64,
    /// `φ` at touchdown [rad].
    pub touchdown_angle_rad: f64,
    /// Kinetic energy lost at touchdown [J].
    #[serde(rename = "touchdown_loss_J")]
    pub touchdown_loss_j: f64,
    /// Normal percussion at touchdown [N s] (negative would mean the ground pulls).
    #[serde(rename = "touchdown_normal_percussion_Ns")]
    pub touchdown_normal_percussion_n_s: f64,
    /// Stance time [s].
    pub stance_time_s: f64,
    /// Full forward revolutions in stance (0 in a hopping gait; > 0: the wheel rolled
    /// over the top).
    pub stance_revolutions: i64,
    /// Distance to the next take-off [m].
    pub stride_m: f64,
    /// Time to the next take-off [s].
    pub period_s: f64,
}

/// The converged gait, averaged over the last `window` hops.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GaitSummary {
    /// Mean forward speed: distance over time of the window [m/s].
    pub mean_speed_mps: f64,
    /// Mean stride (distance per hop) [m].
    pub stride_m: f64,
    /// Hops per second [Hz].
    pub hop_frequency_hz: f64,
    /// Cost of transport `ΔE / (m g stride)` (energy per weight per distance).
    pub cost_of_transport: f64,
    /// Dimensionless speed `u / sqrt(g l)`.
    pub dimensionless_speed: f64,
    /// Froude number `u² / (g l)`.
    pub froude_number: f64,
    /// Mean take-off impulse `‖ζ‖` [N s].
    #[serde(rename = "impulse_Ns")]
    pub impulse_n_s: f64,
    /// Mean flight time [s].
    pub flight_time_s: f64,
    /// Mean touchdown angle [rad].
    pub touchdown_angle_rad: f64,
    /// Mean touchdown loss [J] (equals `ΔE` on a converged gait).
    #[serde(rename = "touchdown_loss_J")]
    pub touchdown_loss_j: f64,
    /// `(max − min) / mean` of the per-hop speeds in the window.
    pub speed_spread: f64,
    /// `speed_spread ≤ convergence_tolerance`.
    pub converged: bool,
}

/// A complete template run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TemplateRun {
    /// The parameters.
    pub params: TemplateParams,
    /// Completed hops.
    pub hops: Vec<HopRecord>,
    /// The gait over the window, when all hops completed and it moves forward.
    pub summary: Option<GaitSummary>,
    /// Why there is no gait, otherwise.
    pub no_gait: Option<NoGait>,
    /// Smallest normal ground force in any stance [N] (negative: the template's rolling
    /// constraint needed a pulling ground).
    #[serde(rename = "min_stance_normal_force_N")]
    pub min_stance_normal_force_n: f64,
    /// Centre-of-mass trajectory, when recorded.
    pub trajectory: Vec<TrajectorySample>,
}

/// Samples per flight phase in a recorded trajectory.
const FLIGHT_SAMPLES: usize = 32;

/// Runs the template from rest in stance at `φ_TO` for `p.hops` hops (docs/physics.md §5.1).
/// With `record_trajectory`, the centre-of-mass trajectory is kept (32 samples per flight,
/// every accepted integration step in stance).
pub fn simulate(p: &TemplateParams, record_trajectory: bool) -> Result<TemplateRun> {
    p.validate()?;
    let mut run = TemplateRun {
        params: *p,
        hops: Vec::with_capacity(p.hops),
        summary: None,
        no_gait: None,
        min_stance_normal_force_n: f64::INFINITY,
        trajectory: Vec::new(),
    };
    let phi_to = p.takeoff_angle;
    let mut state = BodyState {
        q: [0.0, stance_height(p, phi_to), phi_to],
        u: [0.0; 3],
    };
    let mut t = 0.0;
    for hop in 0..p.hops {
        match one_hop(p, hop, &mut state, &mut t, &mut run, record_trajectory) {
            Ok(record) => run.hops.push(record),
            Err(reason) => {
                run.no_gait = Some(NoGait { hop, reason });
                return Ok(run);
            }
        }
    }
    let summary = summarize(p, &run.hops);
    if summary.mean_speed_mps.is_nan() || summary.mean_speed_mps <= 0.0 {
        run.no_gait = Some(NoGait {
            hop: p.hops - 1,
            reason: NoGaitReason::MovesBackward {
                mean_speed: summary.mean_speed_mps,
            },
        });
    } else {
        run.summary = Some(summary);
    }
    Ok(run)
}

fn one_hop(
    p: &TemplateParams,
    hop: usize,
    state: &mut BodyState,
    t: &mut f64,
    run: &mut TemplateRun,
    record: bool,
) -> std::result::Result<HopRecord, NoGaitReason> {
    let takeoff_time = *t;
    let takeoff_x = state.q[0];
    let takeoff_w = state.u[2];
    let kick = takeoff_impulse(p, state).map_err(numerical)?;
    let airborne = BodyState {
        q: state.q,
        u: kick.velocity_after,
    };
    let fl = flight(p, &airborne)?;
    if record {
        for i in 0..FLIGHT_SAMPLES {
            let s = fl.duration * i as f64 / (FLIGHT_SAMPLES - 1) as f64;
            run.trajectory.push(TrajectorySample {
                hop,
                phase: Phase::Flight,
                t: takeoff_time + s,
                state: if i + 1 == FLIGHT_SAMPLES {
                    fl.touchdown
                } else {
                    flight_state(p, &airborne, s)
                },
            });
        }
    }
    let td = touchdown(p, &fl.touchdown).map_err(numerical)?;
    let phi_td = fl.touchdown.q[2];
    let landed = BodyState {
        q: [fl.touchdown.q[0], stance_height(p, phi_td), phi_td],
        u: td.velocity_after,
    };
    let st = stance(p, &landed, record)?;
    run.min_stance_normal_force_n = run.min_stance_normal_force_n.min(st.min_normal_force);
    let stance_start = takeoff_time + fl.duration;
    if record {
        let a = p.eccentricity();
        for s in &st.samples {
            let x = landed.q[0] + a * (s.phi.sin() - phi_td.sin()) - p.radius * (s.phi - phi_td);
            run.trajectory.push(TrajectorySample {
                hop,
                phase: Phase::Stance,
                t: stance_start + s.t,
                state: BodyState {
                    q: [x, stance_height(p, s.phi), s.phi],
                    u: rolling_velocity(p, s.phi, s.phi_dot),
                },
            });
        }
    }
    *t = stance_start + st.duration;
    *state = st.takeoff;
    if !state.q.iter().chain(state.u.iter()).all(|v| v.is_finite()) {
        return Err(NoGaitReason::Numerical {
            message: "non-finite state after stance".into(),
        });
    }
    Ok(HopRecord {
        index: hop,
        takeoff_time_s: takeoff_time,
        takeoff_x_m: takeoff_x,
        takeoff_angular_velocity_rad_s: takeoff_w,
        impulse_n_s: kick.impulse,
        flight_time_s: fl.duration,
        touchdown_angle_rad: phi_td,
        touchdown_loss_j: td.energy_loss,
        touchdown_normal_percussion_n_s: td.percussion[1],
        stance_time_s: st.duration,
        stance_revolutions: st.revolutions,
        stride_m: state.q[0] - takeoff_x,
        period_s: *t - takeoff_time,
    })
}

fn summarize(p: &TemplateParams, hops: &[HopRecord]) -> GaitSummary {
    let window = &hops[hops.len() - p.window..];
    let n = window.len() as f64;
    let distance: f64 = window.iter().map(|h| h.stride_m).sum();
    let time: f64 = window.iter().map(|h| h.period_s).sum();
    let mean = |f: fn(&HopRecord) -> f64| window.iter().map(f).sum::<f64>() / n;
    let speed = distance / time;
    let stride = distance / n;
    let speeds: Vec<f64> = window.iter().map(|h| h.stride_m / h.period_s).collect();
    let (lo, hi) = speeds
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &s| {
            (lo.min(s), hi.max(s))
        });
    let speed_spread = (hi - lo) / speed.abs();
    let dimensionless_speed = speed / (p.gravity * p.leg_length).sqrt();
    GaitSummary {
        mean_speed_mps: speed,
        stride_m: stride,
        hop_frequency_hz: n / time,
        cost_of_transport: p.energy_input / (p.mass * p.gravity * stride),
        dimensionless_speed,
        froude_number: dimensionless_speed * dimensionless_speed,
        impulse_n_s: mean(|h| h.impulse_n_s),
        flight_time_s: mean(|h| h.flight_time_s),
        touchdown_angle_rad: mean(|h| h.touchdown_angle_rad),
        touchdown_loss_j: mean(|h| h.touchdown_loss_j),
        speed_spread,
        converged: speed_spread <= p.convergence_tolerance,
    }
}

/// One cell of the Cargo `l/R × φ_TO` grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridCell {
    /// `l / R`.
    pub leg_over_radius: f64,
    /// `R` [m].
    pub radius: f64,
    /// `φ_TO` [rad].
    pub takeoff_angle: f64,
    /// The gait, when the run completed and moved forward.
    pub summary: Option<GaitSummary>,
    /// The no-gait reason otherwise.
    pub no_gait: Option<String>,
}

impl GridCell {
    /// The gait if it exists and converged (the heatmaps show only these cells).
    pub fn converged(&self) -> Option<&GaitSummary> {
        self.summary.as_ref().filter(|s| s.converged)
    }
}

/// The Cargo grid of Table 3.1: `l/R` evenly spaced between `l/5.8` and `l/0.3`
/// (`R` from 5.8 m to 0.3 m, `l = 0.288`), `φ_TO` evenly spaced over `−0.2 … −0.01`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CargoGrid {
    /// Base parameters (`R` and `φ_TO` are replaced per cell).
    pub base: TemplateParams,
    /// `l / R` values (x axis).
    pub leg_over_radius: Vec<f64>,
    /// `φ_TO` values (y axis).
    pub takeoff_angles: Vec<f64>,
}

impl CargoGrid {
    /// The base parameters of the Table-3.1 Cargo grid (`R` and `φ_TO` are replaced per
    /// cell).
    pub fn table_3_1_base() -> TemplateParams {
        TemplateParams {
            radius: CARGO_GRID_RANGES.radius.0,
            leg_length: 0.288,
            mass: 130.0,
            inertia: 4.1,
            takeoff_angle: midpoint(CARGO_GRID_RANGES.takeoff_angle),
            energy_input: 35.0,
            impulse_tilt: -0.2,
            ..TemplateCase::Cargo2.params()
        }
    }

    /// The Table-3.1 Cargo grid with `n_ratio × n_angle` cells.
    pub fn table_3_1(n_ratio: usize, n_angle: usize) -> Self {
        Self::table_3_1_around(Self::table_3_1_base(), n_ratio, n_angle)
    }

    /// The Table-3.1 axes around other base parameters: `l/R` from `l/5.8` to `l/0.3` with
    /// the base's leg length `l`, `φ_TO` over `−0.2 … −0.01`.
    pub fn table_3_1_around(base: TemplateParams, n_ratio: usize, n_angle: usize) -> Self {
        let l = base.leg_length;
        CargoGrid {
            base,
            leg_over_radius: linspace(
                l / CARGO_GRID_RANGES.radius.1,
                l / CARGO_GRID_RANGES.radius.0,
                n_ratio,
            ),
            takeoff_angles: linspace(
                CARGO_GRID_RANGES.takeoff_angle.0,
                CARGO_GRID_RANGES.takeoff_angle.1,
                n_angle,
            ),
        }
    }

    /// Cell parameters in row-major order (`φ_TO` outer, `l/R` inner).
    pub fn cells(&self) -> Vec<TemplateParams> {
        let mut out = Vec::with_capacity(self.leg_over_radius.len() * self.takeoff_angles.len());
        for &phi in &self.takeoff_angles {
            for &ratio in &self.leg_over_radius {
                out.push(TemplateParams {
                    radius: self.base.leg_length / ratio,
                    takeoff_angle: phi,
                    ..self.base
                });
            }
        }
        out
    }

    /// Runs every cell in parallel (rayon), calling `progress` per cell. Cells are returned in
    /// row-major order (`φ_TO` outer, `l/R` inner).
    pub fn run(&self, progress: CellDone<'_>) -> Result<Vec<GridCell>> {
        self.base.validate()?;
        for &ratio in &self.leg_over_radius {
            if !(ratio.is_finite() && ratio > 0.0 && ratio < 2.0) {
                return Err(AnalysisError::invalid("l/R", ratio, "must lie in (0, 2)"));
            }
        }
        let cells = self.cells();
        let results = par_map(&cells, progress, |params| {
            let run = simulate(params, false);
            let (summary, no_gait) = match run {
                Ok(run) => (run.summary, run.no_gait.map(|n| n.to_string())),
                Err(err) => (None, Some(err.to_string())),
            };
            GridCell {
                leg_over_radius: params.leg_length / params.radius,
                radius: params.radius,
                takeoff_angle: params.takeoff_angle,
                summary,
                no_gait,
            }
        });
        Ok(results)
    }
}

/// One point of an animal sweep over the Table-3.1 ranges.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnimalPoint {
    /// `φ_TO` [rad].
    pub takeoff_angle: f64,
    /// `ΔE` [J].
    pub energy_input: f64,
    /// The gait, if any.
    pub summary: Option<GaitSummary>,
    /// The no-gait reason otherwise.
    pub no_gait: Option<String>,
}

/// Runs `case` over its Table-3.1 ranges of `φ_TO` (`n_angles` values) and `ΔE`
/// (`n_energies` values), in parallel; points are ordered `φ_TO` outer, `ΔE` inner.
/// `base` overrides the case's other parameters (pass `case.params()` for Table 3.1).
pub fn sweep_case(
    case: TemplateCase,
    base: &TemplateParams,
    n_angles: usize,
    n_energies: usize,
    progress: CellDone<'_>,
) -> Result<Vec<AnimalPoint>> {
    base.validate()?;
    let ranges = case.ranges();
    let mut params = Vec::new();
    for phi in linspace(ranges.takeoff_angle.0, ranges.takeoff_angle.1, n_angles) {
        for energy in linspace(ranges.energy_input.0, ranges.energy_input.1, n_energies) {
            params.push(TemplateParams {
                takeoff_angle: phi,
                energy_input: energy,
                ..*base
            });
        }
    }
    Ok(par_map(&params, progress, |p| {
        let (summary, no_gait) = match simulate(p, false) {
            Ok(run) => (run.summary, run.no_gait.map(|n| n.to_string())),
            Err(err) => (None, Some(err.to_string())),
        };
        AnimalPoint {
            takeoff_angle: p.takeoff_angle,
            energy_input: p.energy_input,
            summary,
            no_gait,
        }
    }))
}
