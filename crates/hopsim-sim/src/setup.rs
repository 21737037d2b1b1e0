//! What a simulation runs, however it was described: a model (shared, immutable), its
//! start, its controller and how it is integrated ([`Setup`], [`Settings`]). A scene file
//! is one way to write it (hopsim-scene's `Scene` is a `Setup` with its file's details);
//! code is another (docs/architecture.md, "Where things plug in").

use hopsim_control::{ControlSignal, ControllerConfig};
use hopsim_io::number;
use hopsim_model::Model;
use hopsim_step::{State, StepSettings};
use std::path::PathBuf;
use std::sync::Arc;

/// Largest magnitude of any number a run's description gives (masses, stiffnesses,
/// torques, times, rates, …) unless a tighter bound applies: far beyond any robot, far
/// below the range where the simulator's derived quantities (energies, mass matrices)
/// overflow.
pub const MAX_MAGNITUDE: f64 = 1e9;
/// Largest magnitude of a position, length or angle, m or rad (a coordinate beyond it
/// makes energies and contact gaps lose all precision or overflow).
pub const MAX_COORDINATE: f64 = 1e6;

/// Smallest step size, s: with durations up to `1e9` s the step count stays far below
/// `u64::MAX`.
pub const MIN_DT: f64 = 1e-9;

/// Default of `simulation.max_steps`: the most steps a run may take unless the scene allows
/// more (a bound on run time that a typo in `duration` or `dt` cannot exceed).
pub const DEFAULT_MAX_STEPS: f64 = 1e8;

/// `[simulation]`: how the scene is integrated and recorded.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Simulated time, s.
    pub duration: f64,
    /// Step size `Δt`, s (docs/physics.md §4).
    pub dt: f64,
    /// Gravitational acceleration along `-y`, m/s².
    pub gravity: f64,
    /// Gravitational acceleration along `+x`, m/s² (0 unless gravity is tilted).
    pub gravity_x: f64,
    /// Frames recorded per second of simulated time, Hz (events are always recorded).
    pub record_rate: f64,
    /// `[summary] speed_window`: the mean speed (and Robbit's brakes per second and impulse
    /// per distance) are taken over the last `speed_window` seconds (at most the whole
    /// run; default: its second half), s.
    pub speed_window: f64,
    /// `[summary] cube_restitution`: the restitution `ε` of the second cube baseline of
    /// docs/physics.md §5.3 (the first is `ε = 0`).
    pub cube_restitution: f64,
    /// Stop on the first contact LCP without a certified solution.
    pub strict: bool,
    /// Try the previous step's complementary basis before Lemke's method (docs/lcp.md).
    pub warm_start: bool,
    /// A generalised velocity above this stops the run as a runaway state (m/s or rad/s).
    pub max_speed: f64,
    /// The most steps one run may take (`simulation.max_steps`, [`check_steps`]).
    pub max_steps: u64,
}

impl Settings {
    /// The settings of a run of `duration` s in steps of `dt` s with every other key at
    /// the scene format's default (docs/scene-format.md): gravity 9.81 m/s² down, frames at
    /// 1000 Hz, the speed window the run's second half, cube baseline `ε = 0.5`, not
    /// strict, warm start on, runaway above 1e4 m/s or rad/s, at most
    /// [`DEFAULT_MAX_STEPS`] steps. For models built in code; the reader starts from it.
    pub fn new(duration: f64, dt: f64) -> Self {
        Self {
            duration,
            dt,
            gravity: 9.81,
            gravity_x: 0.0,
            record_rate: 1000.0,
            speed_window: (duration / 2.0).max(dt).min(duration),
            cube_restitution: 0.5,
            strict: false,
            warm_start: true,
            max_speed: 1e4,
            max_steps: DEFAULT_MAX_STEPS as u64,
        }
    }
}

/// A run longer than `simulation.max_steps` allows.
#[derive(Clone, Debug, PartialEq)]
pub struct TooManySteps {
    /// The run's duration, s.
    pub duration: f64,
    /// The step size, s.
    pub dt: f64,
    /// The steps it would take (`round(duration / dt)`).
    pub steps: f64,
    /// `simulation.max_steps`.
    pub max_steps: u64,
}

impl std::fmt::Display for TooManySteps {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} s in steps of {} s is {} steps, more than simulation.max_steps = {}",
            number(self.duration),
            number(self.dt),
            number(self.steps),
            self.max_steps
        )
    }
}

/// Whether a run of `duration` s in steps of `dt` s, `round(duration / dt)` steps as
/// `hopsim_sim::run_for` takes them, stays within `max_steps` steps: the bound of every run,
/// whether a scene file, `--duration` or a front end asks for it.
pub fn check_steps(duration: f64, dt: f64, max_steps: u64) -> Result<(), TooManySteps> {
    let steps = (duration / dt).round();
    // NaN compares false: a non-finite duration is refused before it gets here.
    if steps > max_steps as f64 {
        return Err(TooManySteps {
            duration,
            dt,
            steps,
            max_steps,
        });
    }
    Ok(())
}

/// A run's description: the model, its start, its controller and its settings, with the
/// names that recordings and summaries show.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Title for summaries and viewers.
    pub title: String,
    /// The file it was read from (empty for a setup built in code), shown in recordings.
    pub path: PathBuf,
    /// The text it was read from (empty for a setup built in code), stored in recordings.
    pub text: String,
    /// How it is integrated, recorded and summarised.
    pub settings: Settings,
    /// The multibody model, shared by every simulation of it.
    pub model: Arc<Model>,
    /// The start state.
    pub initial: State,
    /// The controller's settings.
    pub controller: ControllerConfig,
    /// Shapes the controller switches (canes); they start switched off.
    pub switchable: Vec<usize>,
    /// Open-loop control signals `(actuator, signal)`: before every step that the scene's
    /// controller takes, the actuator's control is the signal at the step's midpoint time
    /// (docs/physics.md §7.4).
    pub control_signals: Vec<(usize, ControlSignal)>,
    /// Names of the generalised coordinates, e.g. `["x", "y", "phi", "psi"]`.
    pub coordinates: Vec<String>,
}

impl Setup {
    /// The stepper's settings.
    pub fn step_settings(&self) -> StepSettings {
        StepSettings {
            dt: self.settings.dt,
            strict: self.settings.strict,
            max_speed: self.settings.max_speed,
            warm_start: self.settings.warm_start,
            ..StepSettings::default()
        }
    }
}
