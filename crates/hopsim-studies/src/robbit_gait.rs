//! Robbit in the time-stepper (docs/physics.md §4, §5.3): the cross-check of the reduced model
//! of `hopsim_theory::robbit` and `hopsim_theory::fixed_points`.
//!
//! [`robbit_scene`] is `scenes/robbit.toml` (Robbit's one model) with the parameters, the
//! control and the start of a run set as overrides; [`simulate_from_rest`] runs it from rest
//! on the ground in `hopsim_sim::Simulation` under hopsim-control's `MomentumImpulse`
//! controller with a control `β` ([`simulate`] from any state) and records the state at
//! every brake (the Poincaré section of the reduced model);
//! [`convergence_to_prediction`] measures how the recorded take-off states approach a
//! predicted fixed point.
//!
//! `MomentumImpulse` locks the flywheel for the one step of the brake and leaves it free
//! afterwards, which is [`FlywheelAtTouchdown::Free`]. For [`FlywheelAtTouchdown::Locked`]
//! its `hold_brake` option repeats the lock every step from the brake until the controller
//! switches the motor on again (the step after touchdown): the touchdown impact then acts
//! on the locked pair, as in the reduced model.

use crate::error::Result;
use hopsim_record::EventKind;
use hopsim_scene::{Override, Scene};
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use hopsim_step::State;
use hopsim_theory::fixed_points::FixedPoint;
use hopsim_theory::robbit::{Control, FlywheelAtTouchdown, RobbitParams, SectionState};
use nalgebra::DVector;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;

/// `scenes/robbit.toml`, the scene [`robbit_scene`] starts from.
const SCENE_TEXT: &str = include_str!("../../../scenes/robbit.toml");
/// Where [`SCENE_TEXT`] comes from (named in scene errors).
const SCENE_PATH: &str = "scenes/robbit.toml";
/// The option named in errors about the overrides of [`robbit_scene`].
const OVERRIDE_SOURCE: &str = "Robbit's gait check";

/// Settings of a time-stepper run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepperSettings {
    /// Step `Δt` [s] (docs/physics.md §5.3: 2e-4).
    pub dt: f64,
    /// Simulated time [s] (docs/physics.md §5.3: 20).
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

/// A number as TOML text (shortest round-trip form, so the scene reads back the same `f64`).
fn toml_number(value: f64) -> String {
    format!("{value:?}")
}

/// A list of numbers as a TOML array.
fn toml_array(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| toml_number(v)).collect();
    format!("[{}]", items.join(", "))
}

/// `scenes/robbit.toml` with Robbit's parameters `p` (disc `R`, `a`, `m_S`, `I_S`;
/// flywheel `m_R`, `I_R`; `μ`, `g`), the controller's `β`, its touchdown release with the
/// rearm timeout (the reduced model's cycle: motor off until touchdown), `hold_brake`
/// (held when `p.touchdown` is [`FlywheelAtTouchdown::Locked`], module docs), `Δt`, the
/// duration, strict LCP solves (a run stops on the first uncertified contact LCP), and the
/// state `initial`.
pub fn robbit_scene(
    p: &RobbitParams,
    control: &Control,
    settings: &StepperSettings,
    initial: &State,
) -> Result<Scene> {
    p.validate()?;
    let number = |key: &str, value: f64| (key.to_string(), toml_number(value));
    let settings_overrides = [
        number("simulation.dt", settings.dt),
        number("simulation.duration", settings.duration),
        number("simulation.gravity", p.gravity),
        ("simulation.strict".into(), "true".into()),
        number("environment.friction", p.friction),
        number("bodies.disc.mass", p.body_mass),
        number("bodies.disc.inertia", p.body_inertia),
        number("bodies.flywheel.mass", p.flywheel_mass),
        number("bodies.flywheel.inertia", p.flywheel_inertia),
        (
            "shapes.disc.center".into(),
            toml_array(&[0.0, p.eccentricity]),
        ),
        number("shapes.disc.radius", p.radius),
        number("controller.torque", control.torque),
        number("controller.impulse_limit", control.impulse_limit),
        ("controller.release".into(), "touchdown".into()),
        number("controller.rearm_timeout", settings.rearm_timeout),
        (
            "controller.hold_brake".into(),
            (p.touchdown == FlywheelAtTouchdown::Locked).to_string(),
        ),
        ("initial.q".into(), toml_array(initial.q.as_slice())),
        ("initial.u".into(), toml_array(initial.u.as_slice())),
    ];
    let overrides: Vec<Override> = settings_overrides
        .into_iter()
        .map(|(key, value)| Override::from_flag(OVERRIDE_SOURCE, key, value))
        .collect();
    Ok(hopsim_scene::parse(
        SCENE_TEXT,
        Path::new(SCENE_PATH),
        &overrides,
    )?)
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

/// Runs Robbit's scene ([`robbit_scene`]) from `initial` (its controller starting in
/// stance, motor on) under the momentum-stored-impulse controller with `control`, and
/// records every brake.
pub fn simulate(
    p: &RobbitParams,
    control: &Control,
    settings: &StepperSettings,
    initial: State,
) -> Result<StepperRun> {
    for (name, value) in [
        ("dt", settings.dt),
        ("duration", settings.duration),
        ("rearm-timeout", settings.rearm_timeout),
        ("torque", control.torque),
        ("impulse-limit", control.impulse_limit),
    ] {
        hopsim_theory::error::require_positive(name, value)?;
    }
    let scene = robbit_scene(p, control, settings, &initial)?;
    let mut sim = Simulation::new(&scene);
    let mut brakes = BrakeRecorder::new(p);
    sim.start(&mut brakes)?;
    let steps = (settings.duration / settings.dt).round() as u64;
    for _ in 0..steps {
        sim.step(&mut brakes)?;
    }
    let energy = sim.stepper().record().energy;
    Ok(StepperRun {
        control: *control,
        settings: *settings,
        brakes: brakes.brakes,
        final_x: sim.state().q[0],
        max_penetration: brakes.max_penetration,
        energy_balance_error: energy.balance_error(),
        actuator_work: energy.actuator_work,
    })
}

/// `(t, x, φ, φ̇, ψ̇)` of a state.
#[derive(Clone, Copy, Default)]
struct Snapshot {
    t: f64,
    x: f64,
    phi: f64,
    phi_dot: f64,
    psi_dot: f64,
}

impl Snapshot {
    fn of(state: &State) -> Self {
        Snapshot {
            t: state.t,
            x: state.q[0],
            phi: state.q[2],
            phi_dot: state.u[2],
            psi_dot: state.u[3],
        }
    }
}

/// Observes a run of Robbit's scene: the state at the start of every step with a brake
/// event, and the largest penetration.
struct BrakeRecorder {
    /// `I_red = I_S I_R / (I_S + I_R)` [kg m²].
    reduced_inertia: f64,
    /// The state at the start of the step being taken.
    before: Snapshot,
    brakes: Vec<BrakeEvent>,
    max_penetration: f64,
}

impl BrakeRecorder {
    fn new(p: &RobbitParams) -> Self {
        BrakeRecorder {
            reduced_inertia: p.reduced_inertia(),
            before: Snapshot::default(),
            brakes: Vec::new(),
            max_penetration: 0.0,
        }
    }
}

impl Observer for BrakeRecorder {
    fn on_start(&mut self, view: &StepView<'_>) -> std::result::Result<(), RunError> {
        self.before = Snapshot::of(view.state);
        Ok(())
    }

    fn on_step(&mut self, view: &StepView<'_>) -> std::result::Result<(), RunError> {
        let record = view.record;
        self.max_penetration = self.max_penetration.max(record.max_penetration);
        if view
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Brake { .. }))
        {
            let b = self.before;
            self.brakes.push(BrakeEvent {
                t: b.t,
                x: b.x,
                state: SectionState {
                    angle: b.phi,
                    angular_velocity: b.phi_dot,
                },
                stored_impulse: self.reduced_inertia * (b.psi_dot - b.phi_dot),
                lock_impulse: record.locks.first().map_or(0.0, |l| l.impulse),
            });
        }
        self.before = Snapshot::of(view.state);
        Ok(())
    }
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
pub struct GaitConvergence {
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

/// Tolerances of [`convergence_to_prediction`]: how close the time-stepper's take-off states must come to
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

/// How the take-off states at the brakes of `run` approach the predicted `fixed_point`:
/// every brake's difference, and the largest over the last `window` brakes (all but the
/// first when there are fewer) against `tolerance`; `None` without at least two brakes.
pub fn convergence_to_prediction(
    fixed_point: &FixedPoint,
    run: &StepperRun,
    window: usize,
    tolerance: &GaitTolerance,
) -> Option<GaitConvergence> {
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
    Some(GaitConvergence {
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

#[cfg(test)]
mod tests {
    use super::*;
    use hopsim_control::{ControllerConfig, MomentumImpulseConfig, Release};
    use hopsim_model::{ContactMaterial, Shape, Vec2};

    /// Every parameter, the control, the settings and the start reach the scene exactly.
    #[test]
    fn the_scene_carries_every_parameter() {
        let p = RobbitParams {
            radius: 0.25,
            eccentricity: 0.07,
            body_mass: 1.1,
            flywheel_mass: 0.3,
            body_inertia: 4.1e-3,
            flywheel_inertia: 1.3e-3,
            friction: 0.8,
            gravity: 9.7,
            touchdown: FlywheelAtTouchdown::Free,
        };
        let control = Control {
            torque: 0.21,
            impulse_limit: 0.047,
        };
        let settings = StepperSettings {
            dt: 1e-4,
            duration: 2.0,
            rearm_timeout: 0.5,
        };
        let z = SectionState {
            angle: -0.7,
            angular_velocity: -2.1,
        };
        let initial = section_state(&p, &z, control.impulse_limit);
        let scene = robbit_scene(&p, &control, &settings, &initial).unwrap();
        let m = &scene.model;
        let masses: Vec<(f64, f64)> = m.bodies().iter().map(|b| (b.mass, b.inertia)).collect();
        assert_eq!(masses, [(1.1, 4.1e-3), (0.3, 1.3e-3)]);
        assert_eq!(
            m.shapes()[0].shape,
            Shape::Circle {
                center: Vec2::new(0.0, 0.07),
                radius: 0.25
            }
        );
        assert_eq!(m.gravity(), Vec2::new(0.0, -9.7));
        assert!(m
            .contacts()
            .iter()
            .all(|c| c.material == ContactMaterial::inelastic(0.8)));
        let s = scene.step_settings();
        assert_eq!((s.dt, scene.settings.duration, s.strict), (1e-4, 2.0, true));
        assert_eq!(
            scene.controller,
            ControllerConfig::MomentumImpulse(MomentumImpulseConfig {
                flywheel: 1,
                torque: 0.21,
                impulse_limit: 0.047,
                release: Release::Touchdown { rearm_timeout: 0.5 },
                hold_brake: false,
            })
        );
        assert_eq!(scene.initial, initial);
        let locked = RobbitParams {
            touchdown: FlywheelAtTouchdown::Locked,
            ..p
        };
        let scene = robbit_scene(&locked, &control, &settings, &rest_state(&locked)).unwrap();
        assert!(matches!(
            scene.controller,
            ControllerConfig::MomentumImpulse(MomentumImpulseConfig {
                hold_brake: true,
                ..
            })
        ));
        assert_eq!(scene.initial, rest_state(&locked));
    }

    /// Invalid values are typed errors: the model's parameters, the scene's checks.
    #[test]
    fn invalid_runs_are_typed_errors() {
        let p = RobbitParams::default();
        let control = Control {
            torque: 0.2,
            impulse_limit: 0.05,
        };
        let short = StepperSettings {
            dt: 0.5,
            duration: 0.1,
            ..StepperSettings::default()
        };
        let err = simulate_from_rest(&p, &control, &short).unwrap_err();
        assert!(
            matches!(err, crate::StudyError::Scene(_)) && err.is_invalid_input(),
            "{err}"
        );
        let negative = Control {
            torque: -0.2,
            ..control
        };
        let err = simulate_from_rest(&p, &negative, &StepperSettings::default()).unwrap_err();
        assert!(err.is_invalid_input(), "{err}");
    }
}
