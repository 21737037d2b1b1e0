//! `[controller]`: which controller runs and its parameters (docs/physics.md §5.3, §5.4).

use crate::bodies::{Names, ShapeSpec};
use crate::error::{number, SceneError};
use crate::reader::{Num, Table, MAX_MAGNITUDE};
use hopsim_control::{CaneMode, ControllerConfig, MomentumImpulseConfig, PulseConfig, Release};
use hopsim_model::{Body, JointKind};

/// Default of `controller.rearm_timeout`, s.
const DEFAULT_REARM_TIMEOUT: f64 = 1.0;

/// `controller.release` and the timing key of the chosen mode; the other mode's key is an
/// error (it would be silently ignored).
fn read_release(c: &Table<'_>) -> Result<Release, SceneError> {
    let mode = c.choice("release", &["touchdown", "off_time"], Some("touchdown"))?;
    // The timing key of the other mode, and that mode.
    let (other_key, other_mode) = match mode {
        "touchdown" => ("off_time", "off_time"),
        _ => ("rearm_timeout", "touchdown"),
    };
    if c.get(other_key).is_some() {
        return Err(c.error_at_key(
            other_key,
            format!(
                "applies to release = \"{other_mode}\" only, and this controller has release = \"{mode}\""
            ),
        ));
    }
    Ok(match mode {
        "touchdown" => Release::Touchdown {
            rearm_timeout: c.f64_or("rearm_timeout", DEFAULT_REARM_TIMEOUT, Num::positive("s"))?,
        },
        _ => Release::OffTime {
            off_time: c.f64("off_time", Num::non_negative("s"))?,
        },
    })
}

/// The pulse's magnitude: `torque` (N m) for a revolute joint, `force` (N) along the axis
/// for a prismatic one (docs/physics.md §7); the key of the other kind is an error.
fn read_pulse_magnitude(c: &Table<'_>, body: &Body, name: &str) -> Result<f64, SceneError> {
    let prismatic = matches!(
        body.joint.as_ref().map(|j| j.kind),
        Some(JointKind::Prismatic { .. })
    );
    let (key, num, other, kind) = if prismatic {
        (
            "force",
            Num::any("N"),
            "torque",
            "a prismatic joint: its motor pushes along the axis; give force in N",
        )
    } else {
        (
            "torque",
            Num::any("N m"),
            "force",
            "a revolute joint: its motor turns; give torque in N m",
        )
    };
    if c.get(other).is_some() {
        return Err(c.error_at_key(other, format!("'{name}' is on {kind}")));
    }
    c.f64(key, num)
}

pub(crate) fn read_controller(
    c: &Table<'_>,
    bodies: &[Body],
    body_names: &Names,
    shapes: &[ShapeSpec],
    shape_names: &Names,
) -> Result<ControllerConfig, SceneError> {
    let kind = c.choice(
        "type",
        &["passive", "momentum_impulse", "pulse"],
        Some("passive"),
    )?;
    // The body on the joint a controller drives. `revolute_only`: the momentum-impulse
    // controller's motor and brake act on a relative rotation, so its flywheel must turn
    // on a revolute joint whose parent is a body (a brake locks two bodies), not the
    // world; the pulse drives any revolute or prismatic joint, pinned bases included.
    let jointed = |key: &'static str, revolute_only: bool| -> Result<usize, SceneError> {
        let b = body_names.resolve(c, key)?;
        let name = body_names.get(b);
        let problem = match &bodies[b].joint {
            None => Some(format!(
                "'{name}' is a floating base; the motor acts between a body and its parent"
            )),
            Some(j) if matches!(j.kind, JointKind::Fixed { .. }) => Some(format!(
                "'{name}' is a fixed base; it has no joint to drive"
            )),
            Some(j) if revolute_only && j.kind != JointKind::Revolute => Some(format!(
                "'{name}' slides on a prismatic joint; the flywheel's motor and brake act on \
                 a relative rotation (a revolute joint)"
            )),
            Some(j) if revolute_only && j.parent.is_none() => Some(format!(
                "'{name}' is pinned to the world; the flywheel's motor and brake act between \
                 two bodies"
            )),
            Some(_) => None,
        };
        match problem {
            Some(message) => Err(c.error_at_key(key, message)),
            None => Ok(b),
        }
    };
    let config = match kind {
        "passive" => ControllerConfig::Passive,
        "momentum_impulse" => ControllerConfig::MomentumImpulse(MomentumImpulseConfig {
            flywheel: jointed("flywheel", true)?,
            torque: c.f64("torque", Num::any("N m"))?,
            impulse_limit: c.f64("impulse_limit", Num::positive("N m s"))?,
            release: read_release(c)?,
            hold_brake: c.bool_or("hold_brake", false)?,
        }),
        _ => {
            let joint_body = jointed("joint", false)?;
            let torque = read_pulse_magnitude(c, &bodies[joint_body], body_names.get(joint_body))?;
            let pulse_duration = c.f64("pulse_duration", Num::positive("s"))?;
            let period = match (
                c.opt_f64("period", Num::positive("s"))?,
                c.opt_f64(
                    "frequency",
                    Num::positive("Hz").at_least(1.0 / MAX_MAGNITUDE),
                )?,
            ) {
                (Some(p), None) => p,
                (None, Some(f)) => 1.0 / f,
                (Some(_), Some(_)) => {
                    return Err(
                        c.error_at_key("frequency", "give either period or frequency, not both")
                    )
                }
                (None, None) => {
                    return Err(c.error_at_key(
                        "period",
                        "missing; give the motor period in s (or frequency in Hz)",
                    ))
                }
            };
            if 2.0 * pulse_duration > period {
                return Err(c.error_at_key(
                    "pulse_duration",
                    format!(
                        "two pulses of {} s do not fit in the period of {} s",
                        number(pulse_duration),
                        number(period)
                    ),
                ));
            }
            let cane_shape = match c.opt_str("cane")? {
                None => None,
                Some(name) => {
                    let s = shape_names.index(c, "cane", name)?;
                    if !shapes[s].switchable {
                        return Err(c.error_at_key(
                            "cane",
                            format!("the shape '{name}' must have switchable = true to be a cane"),
                        ));
                    }
                    Some(s)
                }
            };
            let fraction = Num::range(0.0, 1.0, "fraction of the period");
            let delay = c.opt_f64("cane_delay", fraction)?;
            let duration = c.opt_f64("cane_duration", fraction)?;
            let timed = |key, v: Option<f64>| {
                v.ok_or_else(|| c.error_at_key(key, "missing; required when cane_mode = \"timed\""))
            };
            // Read for every mode, so that `--set controller.cane_mode=…` works on any scene.
            let schedule = c.choice("cane_schedule", &["windowed", "thesis"], Some("windowed"))?;
            let cane = match c.choice(
                "cane_mode",
                &["retracted", "extended", "timed"],
                Some("retracted"),
            )? {
                "retracted" => CaneMode::Retracted,
                "extended" => CaneMode::Extended,
                _ => {
                    let (delay, duration) = (
                        timed("cane_delay", delay)?,
                        timed("cane_duration", duration)?,
                    );
                    match schedule {
                        "thesis" => CaneMode::Triggered { delay, duration },
                        _ => CaneMode::Timed { delay, duration },
                    }
                }
            };
            if cane != CaneMode::Retracted && cane_shape.is_none() {
                return Err(c.error_at_key(
                    "cane_mode",
                    "a cane mode other than \"retracted\" needs cane = \"<shape name>\"",
                ));
            }
            ControllerConfig::Pulse(PulseConfig {
                joint_body,
                torque,
                pulse_duration,
                period,
                cane_shape,
                cane,
            })
        }
    };
    c.finish()?;
    Ok(config)
}
