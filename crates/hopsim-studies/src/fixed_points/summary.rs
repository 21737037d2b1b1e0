//! What the fixed-point study reports of the robot, of each section state and of the
//! time-stepper cross-check, in SI units (the `--json` objects and the CSV rows).

use crate::robbit_gait::{BrakeEvent, GaitConvergence, StepperRun};
use hopsim_theory::fixed_points::{FixedPoint, GridPoint};
use hopsim_theory::numerics::Complex;
use hopsim_theory::robbit::RobbitParams;
use serde::Serialize;

/// Robbit's parameters (docs/physics.md §5.3, Table 5.1).
#[derive(Clone, Debug, Serialize)]
pub struct RobotParameters {
    pub radius_m: f64,
    pub eccentricity_m: f64,
    /// `m_S` [kg].
    pub body_mass_kg: f64,
    /// `m_R` [kg].
    pub flywheel_mass_kg: f64,
    /// `I_S` [kg m²].
    pub body_inertia_kg_m2: f64,
    /// `I_R` [kg m²].
    pub flywheel_inertia_kg_m2: f64,
    /// `μ`.
    pub friction: f64,
    pub gravity_mps2: f64,
    /// `locked` or `free`.
    pub flywheel_at_touchdown: &'static str,
    /// `I_red = I_S I_R / (I_S + I_R)` [kg m²].
    pub reduced_inertia_kg_m2: f64,
}

impl From<&RobbitParams> for RobotParameters {
    fn from(p: &RobbitParams) -> Self {
        RobotParameters {
            radius_m: p.radius,
            eccentricity_m: p.eccentricity,
            body_mass_kg: p.body_mass,
            flywheel_mass_kg: p.flywheel_mass,
            body_inertia_kg_m2: p.body_inertia,
            flywheel_inertia_kg_m2: p.flywheel_inertia,
            friction: p.friction,
            gravity_mps2: p.gravity,
            flywheel_at_touchdown: p.touchdown.name(),
            reduced_inertia_kg_m2: p.reduced_inertia(),
        }
    }
}

/// An eigenvalue of the return-map Jacobian `∂P/∂z`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Eigenvalue {
    pub re: f64,
    pub im: f64,
    /// `|λ|`.
    pub modulus: f64,
    /// `arg λ` [rad].
    pub argument: f64,
}

impl From<&Complex> for Eigenvalue {
    fn from(l: &Complex) -> Self {
        Eigenvalue {
            re: l.re,
            im: l.im,
            modulus: l.modulus(),
            argument: l.argument(),
        }
    }
}

/// A fixed point `β* = (T*, ζ0*)`, its stability and its gait (docs/physics.md §5.3 [5.18]).
#[derive(Clone, Debug, Default, Serialize)]
pub struct FixedPointSummary {
    /// `T*` [N m].
    #[serde(rename = "torque_Nm")]
    pub torque: f64,
    /// `ζ0*` [N m s].
    #[serde(rename = "impulse_limit_Nms")]
    pub impulse_limit: f64,
    pub residual_rad: f64,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// `∂P/∂z`, rows `(∂φ'/∂φ, ∂φ'/∂φ̇)`, `(∂φ̇'/∂φ, ∂φ̇'/∂φ̇)`.
    pub jacobian: [[f64; 2]; 2],
    /// Largest modulus first.
    pub eigenvalues: [Eigenvalue; 2],
    /// `max |λ|` (stable below 1).
    pub max_abs_eigenvalue: f64,
    pub speed_mps: f64,
    pub stride_m: f64,
    pub period_s: f64,
    pub flight_time_s: f64,
    pub touchdown_angle_rad: f64,
    pub stance_time_s: f64,
    /// Sign changes of `φ̇` in stance.
    pub stance_reversals: usize,
    /// [J].
    #[serde(rename = "brake_loss_J")]
    pub brake_loss: f64,
    /// [J].
    #[serde(rename = "touchdown_loss_J")]
    pub touchdown_loss: f64,
    /// [J].
    #[serde(rename = "motor_work_J")]
    pub motor_work: f64,
    /// `ζ0* / stride` [N m s per m].
    #[serde(rename = "impulse_per_distance_Nms_per_m")]
    pub impulse_per_distance: f64,
    /// [N s].
    #[serde(rename = "touchdown_normal_percussion_Ns")]
    pub touchdown_normal_percussion: f64,
    /// [N s].
    #[serde(rename = "touchdown_tangential_percussion_Ns")]
    pub touchdown_tangential_percussion: f64,
    /// [N].
    #[serde(rename = "min_stance_normal_force_N")]
    pub min_stance_normal_force: f64,
    pub max_stance_friction_ratio: f64,
    /// Where the no-slip, closed-contact model fails on this gait (empty: consistent).
    pub warnings: Vec<String>,
}

impl FixedPointSummary {
    /// Whether the gait leaves the friction cone of `μ = friction`: a touchdown percussion
    /// with `|Λ_T| > μ Λ_N` (for `Λ_N ≥ 0`) or a stance with `max |F_T|/F_N > μ`, as in
    /// the model's warnings (docs/analysis.md).
    pub fn leaves_friction_cone(&self, friction: f64) -> bool {
        let (normal, tangential) = (
            self.touchdown_normal_percussion,
            self.touchdown_tangential_percussion,
        );
        (normal >= 0.0 && tangential.abs() > friction * normal)
            || self.max_stance_friction_ratio > friction
    }

    /// The summary of `fp` for the robot `p` (its `μ` decides the warnings).
    pub fn new(p: &RobbitParams, fp: &FixedPoint) -> Self {
        let c = &fp.cycle;
        FixedPointSummary {
            torque: fp.control.torque,
            impulse_limit: fp.control.impulse_limit,
            residual_rad: fp.residual,
            iterations: fp.iterations,
            jacobian: fp.jacobian,
            eigenvalues: [(&fp.eigenvalues[0]).into(), (&fp.eigenvalues[1]).into()],
            max_abs_eigenvalue: fp.spectral_radius,
            speed_mps: fp.speed(),
            stride_m: c.stride,
            period_s: c.period,
            flight_time_s: c.flight_time,
            touchdown_angle_rad: c.touchdown_angle,
            stance_time_s: c.stance.duration,
            stance_reversals: c.stance.reversals,
            brake_loss: c.brake.energy_loss,
            touchdown_loss: c.touchdown.energy_loss,
            motor_work: c.stance.motor_work,
            impulse_per_distance: fp.impulse_per_distance(),
            touchdown_normal_percussion: c.touchdown.normal_percussion,
            touchdown_tangential_percussion: c.touchdown.tangential_percussion,
            min_stance_normal_force: c.stance.min_normal_force,
            max_stance_friction_ratio: c.stance.max_friction_ratio,
            warnings: fp.warnings(p),
        }
    }
}

/// One section state `z = (φ_TO, φ̇_TO)` and its fixed point, or why it has none.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PointSummary {
    pub takeoff_angle_rad: f64,
    /// `E_TO` [J].
    #[serde(rename = "takeoff_energy_J")]
    pub takeoff_energy: f64,
    pub takeoff_rate_rad_s: f64,
    /// Whether a fixed point was found.
    pub fixed_point: bool,
    /// Found and `max |λ| < 1`.
    pub stable: bool,
    /// Why there is no fixed point, in words.
    pub reason: Option<String>,
    /// Its kind (`solver-failed`, `no-lift-off`, …: `NoFixedPoint::kind`).
    pub reason_kind: Option<&'static str>,
    /// The fixed point's fields, when found.
    #[serde(flatten)]
    pub details: Option<FixedPointSummary>,
}

impl PointSummary {
    /// The summary of a solved grid point for the robot `p`.
    pub fn new(p: &RobbitParams, q: &GridPoint) -> Self {
        PointSummary {
            takeoff_angle_rad: q.angle,
            takeoff_energy: q.energy,
            takeoff_rate_rad_s: q.angular_velocity,
            fixed_point: q.fixed_point.is_some(),
            stable: q.fixed_point.as_ref().is_some_and(|f| f.stable),
            reason: q.no_fixed_point.as_ref().map(ToString::to_string),
            reason_kind: q.no_fixed_point.as_ref().map(|r| r.kind()),
            details: q.fixed_point.as_ref().map(|f| FixedPointSummary::new(p, f)),
        }
    }

    /// A fixed point without model warnings (the no-slip, closed-contact model holds).
    pub fn consistent(&self) -> bool {
        self.details.as_ref().is_some_and(|f| f.warnings.is_empty())
    }
}

/// The predicted gait of the cross-check.
#[derive(Clone, Debug, Serialize)]
pub struct PredictedGait {
    pub takeoff_angle_rad: f64,
    pub takeoff_rate_rad_s: f64,
    pub speed_mps: f64,
    pub period_s: f64,
    pub max_abs_eigenvalue: f64,
}

/// The time-stepper's gait at the end of the cross-check (`None` without two brakes).
#[derive(Clone, Debug, Serialize)]
pub struct SimulatedGait {
    pub last_takeoff_angle_rad: Option<f64>,
    pub last_takeoff_rate_rad_s: Option<f64>,
    pub speed_mps: Option<f64>,
    pub period_s: Option<f64>,
}

/// One simulated take-off minus the prediction.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TakeoffError {
    /// Brake number (0-based).
    pub brake: usize,
    pub t_s: f64,
    /// `φ − φ*`, wrapped to `(−π, π]`.
    pub angle_error_rad: f64,
    /// `φ̇ − φ̇*`.
    pub rate_error_rad_s: f64,
}

/// A section state `(φ_TO, E_TO)` and its fixed-point control `β* = (T*, ζ0*)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SectionControl {
    pub takeoff_angle_rad: f64,
    /// [J].
    #[serde(rename = "takeoff_energy_J")]
    pub takeoff_energy: f64,
    /// `T*` [N m].
    #[serde(rename = "torque_Nm")]
    pub torque: f64,
    /// `ζ0*` [N m s].
    #[serde(rename = "impulse_limit_Nms")]
    pub impulse_limit: f64,
}

impl SectionControl {
    /// The section state of `fp` (robot `p`) and its control.
    pub fn of(p: &RobbitParams, fp: &FixedPoint) -> Self {
        SectionControl {
            takeoff_angle_rad: fp.state.angle,
            takeoff_energy: fp.state.energy(p),
            torque: fp.control.torque,
            impulse_limit: fp.control.impulse_limit,
        }
    }
}

/// The time-stepper from rest with a stable `β*` against the predicted gait
/// ([`crate::robbit_gait`]).
#[derive(Clone, Debug, Serialize)]
pub struct GaitCheck {
    #[serde(flatten)]
    pub point: SectionControl,
    pub dt_s: f64,
    pub duration_s: f64,
    /// Brakes in the run.
    pub brakes: usize,
    pub predicted: PredictedGait,
    pub simulated: SimulatedGait,
    /// Brakes compared at the end of the run.
    pub window: Option<usize>,
    pub max_angle_error_rad: Option<f64>,
    pub max_rate_error_rad_s: Option<f64>,
    /// Both maxima within their tolerances.
    pub converged: bool,
    pub angle_tolerance_rad: Option<f64>,
    pub rate_tolerance_rad_s: Option<f64>,
    pub max_penetration_m: f64,
    /// [J].
    #[serde(rename = "energy_balance_error_J")]
    pub energy_balance_error: f64,
    pub elapsed_s: f64,
    pub takeoff_errors: Option<Vec<TakeoffError>>,
    /// The state at every brake (the take-offs CSV).
    #[serde(skip)]
    pub brake_states: Vec<BrakeEvent>,
}

impl GaitCheck {
    /// The check of `fp` (robot `p`) by `run`, with its `convergence` to the prediction.
    pub fn new(
        p: &RobbitParams,
        fp: &FixedPoint,
        run: StepperRun,
        convergence: Option<&GaitConvergence>,
        elapsed_s: f64,
    ) -> Self {
        let c = convergence;
        let last = run.brakes.last().map(|b| b.state);
        GaitCheck {
            point: SectionControl::of(p, fp),
            dt_s: run.settings.dt,
            duration_s: run.settings.duration,
            brakes: run.brakes.len(),
            predicted: PredictedGait {
                takeoff_angle_rad: fp.state.angle,
                takeoff_rate_rad_s: fp.state.angular_velocity,
                speed_mps: fp.speed(),
                period_s: fp.cycle.period,
                max_abs_eigenvalue: fp.spectral_radius,
            },
            simulated: SimulatedGait {
                last_takeoff_angle_rad: last.map(|s| s.angle),
                last_takeoff_rate_rad_s: last.map(|s| s.angular_velocity),
                speed_mps: c.map(|c| c.simulated_speed),
                period_s: c.map(|c| c.simulated_period),
            },
            window: c.map(|c| c.window),
            max_angle_error_rad: c.map(|c| c.max_angle_error),
            max_rate_error_rad_s: c.map(|c| c.max_rate_error),
            converged: c.is_some_and(|c| c.converged),
            angle_tolerance_rad: c.map(|c| c.angle_tolerance),
            rate_tolerance_rad_s: c.map(|c| c.rate_tolerance),
            max_penetration_m: run.max_penetration,
            energy_balance_error: run.energy_balance_error,
            elapsed_s,
            takeoff_errors: c.map(|c| {
                c.takeoffs
                    .iter()
                    .map(|d| TakeoffError {
                        brake: d.index,
                        t_s: d.t,
                        angle_error_rad: d.angle_error,
                        rate_error_rad_s: d.rate_error,
                    })
                    .collect()
            }),
            brake_states: run.brakes,
        }
    }
}
