//! Robbit in the time-stepper (physics.md §4, §5.3): the cross-check of the reduced model
//! of `hopsim_analysis::robbit` and `hopsim_analysis::fixed_points`.
//!
//! [`robbit_model`] builds the two-body model (disc + flywheel pivoting at the CoM) for
//! `hopsim-step`; [`simulate_from_rest`] runs it from rest on the ground under
//! hopsim-control's `MomentumImpulse` controller with a control `β` ([`simulate`] from any
//! state) and records the state at every brake (the Poincaré section of the reduced
//! model); [`compare`] measures how the recorded take-off states approach a predicted
//! fixed point.
//!
//! `MomentumImpulse` locks the flywheel for the one step of the brake and leaves it free
//! afterwards, which is [`FlywheelAtTouchdown::Free`]. For [`FlywheelAtTouchdown::Locked`]
//! its `hold_brake` option repeats the lock every step from the brake until the controller
//! switches the motor on again (the step after touchdown): the touchdown impact then acts
//! on the locked pair, as in the reduced model.

use crate::error::{Result, StudyError};
use hopsim_analysis::fixed_points::FixedPoint;
use hopsim_analysis::robbit::{Control, FlywheelAtTouchdown, RobbitParams, SectionState};
use hopsim_analysis::AnalysisError;
use hopsim_control::{
    ControlEvent, ControlInput, Controller, MomentumImpulse, MomentumImpulseConfig,
};
use hopsim_model::{Body, ContactMaterial, Model, Shape, ShapeInstance, Terrain, Vec2};
use hopsim_step::{Actuation, State, StepSettings, Stepper};
use nalgebra::DVector;
use serde::Serialize;
use std::f64::consts::PI;

/// Index of the flywheel body in [`robbit_model`].
pub const FLYWHEEL: usize = 1;

/// Robbit for the time-stepper: body 0 the disc (mass `m_S`, inertia `I_S`, circle of
/// radius `R` centred `a` above the CoM at `φ = 0`), body 1 the flywheel (`m_R`, `I_R`)
/// on an absolute-angle joint at the disc's CoM, flat ground, `ε = 0`, friction `μ`.
///
/// The disc's CoM is the robot's CoM because the flywheel's mass sits on it, so the
/// mass matrix is `diag(m, m, I_S, I_R)` as in physics.md §5.3.
pub fn robbit_model(p: &RobbitParams) -> Result<Model> {
    p.validate()?;
    Model::new(
        vec![
            Body::base("disc", p.body_mass, p.body_inertia),
            Body::flywheel("flywheel", p.flywheel_mass, p.flywheel_inertia, 0),
        ],
        vec![ShapeInstance {
            name: "disc".into(),
            body: 0,
            shape: Shape::Circle {
                center: Vec2::new(0.0, p.eccentricity),
                radius: p.radius,
            },
        }],
        Terrain::flat(0.0),
        vec![],
        Vec2::new(0.0, -p.gravity),
        ContactMaterial::inelastic(p.friction),
    )
    .map_err(StudyError::from)
}

/// Settings of a time-stepper run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepperSettings {
    /// Step `Δt` [s] (physics.md §5.3: 2e-4).
    pub dt: f64,
    /// Simulated time [s] (physics.md §5.3: 20).
    pub duration: f64,
    /// The controller's rearm timeout [s]: a brake without a following touchdown restarts
    /// the cycle after this time.
    pub rearm_timeout: f64,
}

impl Default for StepperSettings {
    /// `Δt = 2e-4 s`, 20 s, rearm after 1 s.
    fn default() -> Self {
        StepperSettings {
            dt: 2e-4,
            duration: 20.0,
            rearm_timeout: 1.0,
        }
    }
}

/// The state at the start of a step in which the controller braked.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BrakeEvent {
    /// Time [s].
    pub t: f64,
    /// CoM position `x` [m].
    pub x: f64,
    /// `(φ, φ̇)` (angle not wrapped).
    pub state: SectionState,
    /// `ζ = I_red (ψ̇ − φ̇)` when the brake fired [N m s].
    pub stored_impulse: f64,
    /// Angular impulse of the lock on the disc in that step [N m s].
    pub lock_impulse: f64,
}

/// A time-stepper run of Robbit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepperRun {
    /// The control.
    pub control: Control,
    /// Settings.
    pub settings: StepperSettings,
    /// Every brake, in order.
    pub brakes: Vec<BrakeEvent>,
    /// Final CoM position `x` [m].
    pub final_x: f64,
    /// Largest penetration of any step [m].
    pub max_penetration: f64,
    /// Energy-ledger balance error at the end [J].
    pub energy_balance_error: f64,
    /// Motor and brake work at the end [J] (the ledger's actuator and lock work).
    pub actuator_work: f64,
}

/// Robbit at rest on the ground with its mass straight below the disc centre:
/// `q = (0, R − a, 0, 0)`, `u = 0`.
pub fn rest_state(p: &RobbitParams) -> State {
    State {
        t: 0.0,
        q: DVector::from_vec(vec![0.0, p.radius - p.eccentricity, 0.0, 0.0]),
        u: DVector::zeros(4),
    }
}

/// The stepper state of a section state `z` with impulse limit `ζ0`: rolling on the ground
/// at `x = 0`, `ψ = 0`, `ψ̇ = φ̇ + ζ0 / I_red` (so `ζ = ζ0`, [`SectionState::velocities`]).
pub fn section_state(p: &RobbitParams, z: &SectionState, impulse_limit: f64) -> State {
    let [vx, vy, w, psi_dot] = z.velocities(p, impulse_limit);
    State {
        t: 0.0,
        q: DVector::from_vec(vec![0.0, p.stance_height(z.angle), z.angle, 0.0]),
        u: DVector::from_vec(vec![vx, vy, w, psi_dot]),
    }
}

/// Runs Robbit from rest on the ground ([`rest_state`]) under the momentum-stored-impulse
/// controller with `control` ([`simulate`]).
pub fn simulate_from_rest(
    p: &RobbitParams,
    control: &Control,
    settings: &StepperSettings,
) -> Result<StepperRun> {
    simulate(p, control, settings, rest_state(p))
}

/// Runs Robbit from `initial` (its controller starting in stance, motor on) under the
/// momentum-stored-impulse controller with `control`, strict LCP solves, and records every
/// brake. The flywheel is held braked until the motor restarts when `p.touchdown` is
/// [`FlywheelAtTouchdown::Locked`] (module docs).
pub fn simulate(
    p: &RobbitParams,
    control: &Control,
    settings: &StepperSettings,
    initial: State,
) -> Result<StepperRun> {
    let model = robbit_model(p)?;
    for (name, value) in [
        ("dt", settings.dt),
        ("duration", settings.duration),
        ("rearm-timeout", settings.rearm_timeout),
        ("torque", control.torque),
        ("impulse-limit", control.impulse_limit),
    ] {
        hopsim_analysis::error::require_positive(name, value)?;
    }
    if initial.q.len() != model.dof() || initial.u.len() != model.dof() {
        return Err(AnalysisError::Dimension(format!(
            "Robbit's state has {} coordinates",
            model.dof()
        ))
        .into());
    }
    let mut stepper = Stepper::new(&model, StepSettings::strict(settings.dt));
    let mut controller = MomentumImpulse::new(
        MomentumImpulseConfig {
            flywheel: FLYWHEEL,
            torque: control.torque,
            impulse_limit: control.impulse_limit,
            rearm_timeout: settings.rearm_timeout,
            hold_brake: p.touchdown == FlywheelAtTouchdown::Locked,
        },
        &model,
    );
    let mut state = initial;
    stepper.start(&model, &state);
    let shapes_active = vec![true; model.shapes.len()];
    let mut actuation = Actuation::default();
    let mut events = Vec::new();
    let mut in_contact = true;
    let mut brakes = Vec::new();
    let mut max_penetration: f64 = 0.0;
    let i_red = p.reduced_inertia();
    let steps = (settings.duration / settings.dt).round() as u64;
    for _ in 0..steps {
        actuation.clear();
        events.clear();
        let input = ControlInput {
            model: &model,
            state: &state,
            dt: settings.dt,
            kinematics: stepper.workspace(),
            in_contact,
            shapes_active: &shapes_active,
        };
        controller.control(&input, &mut actuation, &mut events);
        let braked = events
            .iter()
            .any(|e| matches!(e, ControlEvent::Brake { .. }));
        let before = (state.t, state.q[0], state.q[2], state.u[2], state.u[3]);
        let record = stepper
            .step(&model, &mut state, &actuation)
            .map_err(hopsim_sim::RunError::from)?;
        in_contact = record.in_contact();
        max_penetration = max_penetration.max(record.max_penetration);
        if braked {
            let (t, x, phi, phi_dot, psi_dot) = before;
            brakes.push(BrakeEvent {
                t,
                x,
                state: SectionState {
                    angle: phi,
                    angular_velocity: phi_dot,
                },
                stored_impulse: i_red * (psi_dot - phi_dot),
                lock_impulse: record.locks.first().map_or(0.0, |l| l.impulse),
            });
        }
    }
    let energy = stepper.record().energy;
    Ok(StepperRun {
        control: *control,
        settings: *settings,
        brakes,
        final_x: state.q[0],
        max_penetration,
        energy_balance_error: energy.balance_error(),
        actuator_work: energy.actuator_work,
    })
}

/// One simulated take-off compared with the predicted fixed point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TakeoffDifference {
    /// Brake number (0-based).
    pub index: usize,
    /// Time [s].
    pub t: f64,
    /// `φ − φ*`, wrapped to `(−π, π]` [rad].
    pub angle_error: f64,
    /// `φ̇ − φ̇*` [rad/s].
    pub rate_error: f64,
}

/// How the time-stepper's take-off states compare with a fixed point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GaitComparison {
    /// Predicted `z* = (φ*, φ̇*)`.
    pub predicted: SectionState,
    /// Predicted speed `stride / period` [m/s].
    pub predicted_speed: f64,
    /// Predicted period [s].
    pub predicted_period: f64,
    /// Every brake's difference.
    pub takeoffs: Vec<TakeoffDifference>,
    /// Largest `|φ − φ*|` over the last `window` brakes [rad].
    pub max_angle_error: f64,
    /// Largest `|φ̇ − φ̇*|` over the last `window` brakes [rad/s].
    pub max_rate_error: f64,
    /// Speed over the last `window` cycles: Δx / Δt between brakes [m/s].
    pub simulated_speed: f64,
    /// Mean time between the last `window` brakes [s].
    pub simulated_period: f64,
    /// Brakes compared at the end of the run.
    pub window: usize,
    /// Tolerance on `|φ − φ*|` [rad].
    pub angle_tolerance: f64,
    /// Tolerance on `|φ̇ − φ̇*|` [rad/s].
    pub rate_tolerance: f64,
    /// Both maxima within their tolerances over the last `window` brakes.
    pub converged: bool,
}

/// Tolerances of [`compare`]: how close the time-stepper's take-off states must come to
/// the predicted fixed point to count as "converged to the predicted gait".
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GaitTolerance {
    /// On `|φ − φ*|` [rad].
    pub angle: f64,
    /// On `|φ̇ − φ̇*|` [rad/s].
    pub rate: f64,
}

impl Default for GaitTolerance {
    /// 0.02 rad and 0.05 rad/s: the midpoint stepper at `Δt = 2e-4 s` brakes up to one step
    /// late and resolves impacts to first order in `Δt`; on the Table-5.1 robot its take-off
    /// states settle within about 0.008 rad and 0.012 rad/s of the reduced model's stable
    /// fixed points (docs/analysis.md §10.3), and these tolerances leave a margin of 2.5–4.
    fn default() -> Self {
        GaitTolerance {
            angle: 0.02,
            rate: 0.05,
        }
    }
}

/// `φ − φ*` wrapped to `(−π, π]`.
fn wrapped(angle: f64, reference: f64) -> f64 {
    let d = (angle - reference).rem_euclid(2.0 * PI);
    if d > PI {
        d - 2.0 * PI
    } else {
        d
    }
}

/// Compares the brakes of `run` with `fixed_point` over the last `window` brakes (all but
/// the first when there are fewer); `None` without at least two brakes.
pub fn compare(
    fixed_point: &FixedPoint,
    run: &StepperRun,
    window: usize,
    tolerance: &GaitTolerance,
) -> Option<GaitComparison> {
    let z = fixed_point.state;
    let takeoffs: Vec<TakeoffDifference> = run
        .brakes
        .iter()
        .enumerate()
        .map(|(index, b)| TakeoffDifference {
            index,
            t: b.t,
            angle_error: wrapped(b.state.angle, z.angle),
            rate_error: b.state.angular_velocity - z.angular_velocity,
        })
        .collect();
    if takeoffs.len() < 2 {
        return None;
    }
    let window = window.clamp(1, takeoffs.len() - 1);
    let last = &takeoffs[takeoffs.len() - window..];
    let (first, final_brake) = (
        &run.brakes[run.brakes.len() - 1 - window],
        &run.brakes[run.brakes.len() - 1],
    );
    let elapsed = final_brake.t - first.t;
    let max_angle_error = last.iter().map(|d| d.angle_error.abs()).fold(0.0, f64::max);
    let max_rate_error = last.iter().map(|d| d.rate_error.abs()).fold(0.0, f64::max);
    Some(GaitComparison {
        predicted: z,
        predicted_speed: fixed_point.speed(),
        predicted_period: fixed_point.cycle.period,
        max_angle_error,
        max_rate_error,
        simulated_speed: (final_brake.x - first.x) / elapsed,
        simulated_period: elapsed / window as f64,
        takeoffs,
        window,
        angle_tolerance: tolerance.angle,
        rate_tolerance: tolerance.rate,
        converged: max_angle_error <= tolerance.angle && max_rate_error <= tolerance.rate,
    })
}
