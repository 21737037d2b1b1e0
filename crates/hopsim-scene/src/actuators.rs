//! `[[actuators]]`: motors and servos in the bodies' joints, each with an optional
//! open-loop control signal (docs/scene-format.md, docs/physics.md §7.4).

use crate::bodies::{check_count, Names};
use crate::error::SceneError;
use crate::reader::{Num, Table};
use hopsim_control::ControlSignal;
use hopsim_model::{Actuator, ActuatorKind, Body};
use std::path::Path;

/// Most actuators a scene may have.
pub const MAX_ACTUATORS: usize = 100;

/// Largest CSV control file read, bytes.
pub const MAX_CONTROL_FILE_BYTES: u64 = 8 << 20;

/// The actuators of a scene, in order, and their control signals `(actuator, signal)`.
pub(crate) type Actuators = (Vec<Actuator>, Vec<(usize, ControlSignal)>);

/// The actuators of `tables`; a CSV file is read relative to `base` (the scene's folder).
pub(crate) fn read_actuators(
    tables: &[Table<'_>],
    bodies: &[Body],
    body_names: &Names,
    base: &Path,
) -> Result<Actuators, SceneError> {
    check_count(tables, MAX_ACTUATORS, "actuators", "")?;
    let mut names = Names::new(("actuator", "actuators"));
    let mut actuators = Vec::with_capacity(tables.len());
    let mut signals = Vec::new();
    for (i, t) in tables.iter().enumerate() {
        let name = match t.opt_str("name")? {
            Some(n) => n.to_string(),
            None => format!("actuator{i}"),
        };
        names.add(t, "name", &name)?;
        let body = body_names.resolve(t, "joint")?;
        if !bodies[body]
            .joint
            .as_ref()
            .is_some_and(|j| j.has_coordinate())
        {
            return Err(t.error_at_key(
                "joint",
                format!(
                    "body '{}' has no joint with a coordinate to drive (it is a floating or \
                     fixed base); expected a body on a revolute or prismatic joint, or a \
                     pinned base",
                    bodies[body].name
                ),
            ));
        }
        let gain = Num::non_negative("N m/rad or N/m (per unit of length)");
        let damping = Num::non_negative("N m s/rad or N s/m (per unit of velocity)");
        let kind = match t.choice("kind", &["motor", "position", "velocity"], None)? {
            "motor" => ActuatorKind::Motor,
            "position" => ActuatorKind::Position {
                kp: t.f64("kp", gain)?,
                kv: t.f64_or("kv", 0.0, damping)?,
            },
            _ => ActuatorKind::Velocity {
                kv: t.f64("kv", damping)?,
            },
        };
        let gear = t.f64_or("gear", 1.0, Num::any(""))?;
        if gear == 0.0 {
            return Err(t.error_at_key("gear", "expected a non-zero number, found 0"));
        }
        let actuator = Actuator {
            name,
            body,
            kind,
            gear,
            ctrl_range: range(t, "ctrl_range", Num::any(""))?,
            force_range: range(t, "force_range", Num::any("N m or N"))?,
        };
        if let Some(c) = t.opt_table("control")? {
            signals.push((i, read_signal(&c, base)?));
        }
        t.finish()?;
        actuators.push(actuator);
    }
    Ok((actuators, signals))
}

/// An optional `[lower, upper]` with `lower ≤ upper`.
fn range(t: &Table<'_>, key: &'static str, num: Num) -> Result<Option<[f64; 2]>, SceneError> {
    match t.opt_f64_list(key, Some(2), num)? {
        None => Ok(None),
        Some(v) if v[0] <= v[1] => Ok(Some([v[0], v[1]])),
        Some(v) => Err(t.error_at_key(
            key,
            format!(
                "expected [lower, upper] with lower <= upper, found [{}, {}]",
                v[0], v[1]
            ),
        )),
    }
}

/// `[actuators.control]`: one of the signal kinds with its parameters.
fn read_signal(c: &Table<'_>, base: &Path) -> Result<ControlSignal, SceneError> {
    let any = Num::any("");
    let kinds = ["constant", "sine", "pulse", "table", "csv"];
    let signal = match c.choice("kind", &kinds, None)? {
        "constant" => ControlSignal::Constant {
            value: c.f64("value", any)?,
        },
        "sine" => ControlSignal::Sine {
            amplitude: c.f64("amplitude", any)?,
            frequency: c.f64("frequency", Num::non_negative("Hz"))?,
            phase: c.f64_or("phase", 0.0, Num::any("rad"))?,
            offset: c.f64_or("offset", 0.0, any)?,
        },
        "pulse" => {
            let period = c.f64("period", Num::positive("s"))?;
            let width = c.f64("width", Num::range(0.0, period, "s"))?;
            ControlSignal::Pulse {
                period,
                width,
                value: c.f64("value", any)?,
            }
        }
        "table" => {
            let times = c
                .opt_f64_list("times", None, Num::any("s"))?
                .ok_or_else(|| {
                    c.error_at_key("times", "missing key; expected an array of times (s)")
                })?;
            let values = c
                .opt_f64_list("values", Some(times.len()), any)?
                .ok_or_else(|| {
                    c.error_at_key(
                        "values",
                        "missing key; expected an array of values, one per time",
                    )
                })?;
            ControlSignal::Table { times, values }
        }
        _ => {
            let file = c.str("file")?;
            read_csv(c, &base.join(file))?
        }
    };
    if let Some(problem) = signal.problem() {
        return Err(c.error_here(problem));
    }
    c.finish()?;
    Ok(signal)
}

/// A CSV control file: rows `time,value` (a header line first is allowed), times strictly
/// increasing; errors name the file and line, placed at the `file` key.
fn read_csv(c: &Table<'_>, path: &Path) -> Result<ControlSignal, SceneError> {
    let text = hopsim_io::read_text_bounded(path, MAX_CONTROL_FILE_BYTES, "control files")
        .map_err(|e| c.error_at_key("file", format!("cannot read {}: {e}", path.display())))?;
    let (mut times, mut values) = (Vec::new(), Vec::new());
    let mut first = true;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let header = std::mem::replace(&mut first, false);
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let numbers: Option<Vec<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
        let bad = |what: &str| {
            c.error_at_key(
                "file",
                format!(
                    "{}:{}: expected two finite numbers `time,value`, found `{line}` ({what})",
                    path.display(),
                    i + 1
                ),
            )
        };
        match numbers {
            Some(n) if n.len() == 2 && n.iter().all(|v| v.is_finite()) => {
                if times.last().is_some_and(|&last| n[0] <= last) {
                    return Err(bad("times must increase strictly"));
                }
                times.push(n[0]);
                values.push(n[1]);
            }
            // A header: the first line that is not numbers.
            None if header && fields.len() == 2 => {}
            _ => return Err(bad("not two finite numbers")),
        }
    }
    if times.is_empty() {
        return Err(c.error_at_key("file", format!("{}: no rows `time,value`", path.display())));
    }
    Ok(ControlSignal::Table { times, values })
}
