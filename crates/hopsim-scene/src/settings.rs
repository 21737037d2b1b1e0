//! `[meta]` and `[simulation]`.

use crate::error::{number, SceneError};
use crate::reader::{Num, Table};
use hopsim_sim::{check_steps, Settings, DEFAULT_MAX_STEPS, MIN_DT};

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
    let d = Settings::new(duration, dt);
    Ok(Settings {
        gravity: sim.f64_or("gravity", d.gravity, Num::non_negative("m/s²"))?,
        gravity_x: sim.f64_or("gravity_x", d.gravity_x, Num::any("m/s²"))?,
        record_rate: sim.f64_or("record_rate", d.record_rate, Num::positive("Hz"))?,
        speed_window: window.map_or(d.speed_window, |w| w.min(duration)),
        cube_restitution: summary.f64_or(
            "cube_restitution",
            d.cube_restitution,
            Num::range(0.0, 1.0, ""),
        )?,
        strict: sim.bool_or("strict", d.strict)?,
        warm_start: sim.bool_or("warm_start", d.warm_start)?,
        max_speed: sim.f64_or("max_speed", d.max_speed, Num::positive("m/s or rad/s"))?,
        max_steps: max_steps as u64,
        ..d
    })
}
