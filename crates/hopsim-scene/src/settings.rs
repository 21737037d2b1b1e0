//! `[meta]` and `[simulation]`.

use crate::error::{number, SceneError};
use crate::reader::{Num, Table};

/// The free `[meta]` table: title, source of the parameters, notes, and any other keys.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Meta {
    /// Title shown in summaries and viewers (default: the file name without extension).
    pub title: String,
    /// Where the parameters come from.
    pub source: Option<String>,
    /// Free notes (rationale of parameter choices, …).
    pub notes: Option<String>,
}

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

pub(crate) fn read_meta(meta: Option<Table<'_>>, default_title: &str) -> Result<Meta, SceneError> {
    let Some(meta) = meta else {
        return Ok(Meta {
            title: default_title.to_string(),
            ..Meta::default()
        });
    };
    let text = |key: &'static str| -> Result<Option<String>, SceneError> {
        Ok(meta.opt_str(key)?.map(str::to_string))
    };
    let out = Meta {
        title: text("title")?.unwrap_or_else(|| default_title.to_string()),
        source: text("source")?,
        notes: text("notes")?,
    };
    // [meta] is free-form: other keys stay in the file unchecked (no `finish`).
    Ok(out)
}

/// Smallest step size, s: with durations up to `1e9` s the step count stays far below
/// `u64::MAX`.
pub const MIN_DT: f64 = 1e-9;

/// Default of `simulation.max_steps`: the most steps a run may take unless the scene allows
/// more (a bound on run time that a typo in `duration` or `dt` cannot exceed).
pub const DEFAULT_MAX_STEPS: f64 = 1e8;

/// Reads `[simulation]` and `[summary]`.
pub(crate) fn read_settings(sim: &Table<'_>, summary: &Table<'_>) -> Result<Settings, SceneError> {
    let duration = sim.f64("duration", Num::positive("s"))?;
    let dt = sim.f64("dt", Num::positive("s").at_least(MIN_DT))?;
    let max_steps = sim.f64_or(
        "max_steps",
        DEFAULT_MAX_STEPS,
        Num::positive("steps").at_least(1.0),
    )?;
    if let Err(e) = check_steps(duration, dt, max_steps as u64) {
        return Err(sim.error_at_key(
            "duration",
            format!(
                "{e}; raise simulation.max_steps (e.g. --set simulation.max_steps={}) to run \
                 this long",
                number(e.steps)
            ),
        ));
    }
    if dt >= duration {
        return Err(sim.error_at_key(
            "dt",
            format!(
                "the step size {} s must be smaller than the duration {} s",
                number(dt),
                number(duration)
            ),
        ));
    }
    // A window longer than the run (e.g. after `--duration 5`) is the whole run; one
    // shorter than a step holds no motion to average (its mean speed would be 0/0).
    let window = summary.opt_f64("speed_window", Num::positive("s"))?;
    if let Some(w) = window.filter(|&w| w < dt) {
        return Err(summary.error_at_key(
            "speed_window",
            format!(
                "the speed window {} s is shorter than the step size {} s; expected at least \
                 one step",
                number(w),
                number(dt)
            ),
        ));
    }
    let speed_window = window.unwrap_or((duration / 2.0).max(dt)).min(duration);
    Ok(Settings {
        duration,
        dt,
        gravity: sim.f64_or("gravity", 9.81, Num::non_negative("m/s²"))?,
        gravity_x: sim.f64_or("gravity_x", 0.0, Num::any("m/s²"))?,
        record_rate: sim.f64_or("record_rate", 1000.0, Num::positive("Hz"))?,
        speed_window,
        cube_restitution: summary.f64_or("cube_restitution", 0.5, Num::range(0.0, 1.0, ""))?,
        strict: sim.bool_or("strict", false)?,
        warm_start: sim.bool_or("warm_start", true)?,
        max_speed: sim.f64_or("max_speed", 1e4, Num::positive("m/s or rad/s"))?,
        max_steps: max_steps as u64,
    })
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
