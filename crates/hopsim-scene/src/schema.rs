//! Words and SI units of the numeric scene keys a sweep or `--set` may vary
//! (docs/scene-format.md), for axis labels and legends: `controller.torque` is
//! "motor torque T (N m)".
//!
//! Keys inside arrays of tables are written with `*` for the table's name or index:
//! `bodies.*.mass` covers `bodies.disc.mass` and `bodies.0.mass`.

/// What a scene key means, in words, and its unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyInfo {
    /// The quantity in words, with its symbol where the docs use one (`impulse limit ζ0`).
    pub words: &'static str,
    /// The unit on an axis (`"N m"`; `""` for a dimensionless number).
    pub unit: &'static str,
    /// The unit after a single value in a legend (`"N m"`; `""` if the value reads alone,
    /// e.g. a fraction of the motor period).
    pub value_unit: &'static str,
}

const fn info(words: &'static str, unit: &'static str, value_unit: &'static str) -> KeyInfo {
    KeyInfo {
        words,
        unit,
        value_unit,
    }
}

/// The numeric scene keys and their meaning (units as in docs/scene-format.md).
const KEYS: &[(&str, KeyInfo)] = &[
    ("simulation.duration", info("duration", "s", "s")),
    ("simulation.dt", info("time step Δt", "s", "s")),
    ("simulation.gravity", info("gravity g", "m/s²", "m/s²")),
    ("simulation.record_rate", info("record rate", "Hz", "Hz")),
    ("summary.speed_window", info("speed window", "s", "s")),
    (
        "summary.cube_restitution",
        info("cube restitution ε", "", ""),
    ),
    ("environment.height", info("ground height", "m", "m")),
    ("environment.angle", info("incline angle", "rad", "rad")),
    ("environment.step_x", info("step position", "m", "m")),
    ("environment.step_height", info("step height", "m", "m")),
    (
        "environment.friction",
        info("friction coefficient μ", "", ""),
    ),
    (
        "environment.restitution",
        info("normal restitution ε_N", "", ""),
    ),
    (
        "environment.tangential_restitution",
        info("tangential restitution ε_T", "", ""),
    ),
    ("bodies.*.mass", info("mass", "kg", "kg")),
    (
        "bodies.*.armature",
        info("joint armature", "kg m² or kg", "kg m² or kg"),
    ),
    (
        "bodies.*.dry_friction",
        info("joint dry friction", "N m or N", "N m or N"),
    ),
    (
        "simulation.gravity_x",
        info("gravity along x", "m/s²", "m/s²"),
    ),
    (
        "bodies.*.inertia",
        info("moment of inertia", "kg m²", "kg m²"),
    ),
    ("shapes.*.radius", info("radius", "m", "m")),
    ("actuators.*.gear", info("actuator gear", "", "")),
    (
        "actuators.*.kp",
        info("servo stiffness k_p", "N m/rad or N/m", ""),
    ),
    (
        "actuators.*.kv",
        info("servo damping k_v", "N m s/rad or N s/m", ""),
    ),
    (
        "actuators.*.control.value",
        info("actuator control", "", ""),
    ),
    (
        "actuators.*.control.amplitude",
        info("control amplitude", "", ""),
    ),
    (
        "actuators.*.control.frequency",
        info("control frequency", "Hz", "Hz"),
    ),
    ("shapes.*.semi_x", info("semi-axis along x", "m", "m")),
    ("shapes.*.semi_y", info("semi-axis along y", "m", "m")),
    ("shapes.*.friction", info("friction coefficient μ", "", "")),
    (
        "shapes.*.restitution",
        info("normal restitution ε_N", "", ""),
    ),
    (
        "springs.*.stiffness",
        info("spring stiffness k", "N/m", "N/m"),
    ),
    (
        "springs.*.rest_length",
        info("spring rest length L0", "m", "m"),
    ),
    (
        "springs.*.damping",
        info("spring damping c", "N s/m", "N s/m"),
    ),
    ("controller.torque", info("motor torque T", "N m", "N m")),
    ("controller.force", info("motor force F", "N", "N")),
    (
        "controller.impulse_limit",
        info("impulse limit ζ0", "N m s", "N m s"),
    ),
    ("controller.rearm_timeout", info("re-arm timeout", "s", "s")),
    ("controller.off_time", info("motor off time", "s", "s")),
    (
        "controller.pulse_duration",
        info("pulse duration", "s", "s"),
    ),
    ("controller.period", info("motor period P", "s", "s")),
    ("controller.frequency", info("motor frequency", "Hz", "Hz")),
    (
        "controller.cane_delay",
        info("cane delay CD", "fraction of the motor period", ""),
    ),
    (
        "controller.cane_duration",
        info("cane duration CDC", "fraction of the motor period", ""),
    ),
];

/// The meaning of the scene key `key` (a dotted path as `--set` takes it), if it is a
/// numeric key of the scene format.
pub fn key_info(key: &str) -> Option<KeyInfo> {
    let segments: Vec<&str> = key.split('.').map(str::trim).collect();
    KEYS.iter()
        .find(|(pattern, _)| {
            let pattern: Vec<&str> = pattern.split('.').collect();
            pattern.len() == segments.len()
                && pattern
                    .iter()
                    .zip(&segments)
                    .all(|(p, s)| *p == "*" || p == s)
        })
        .map(|(_, info)| *info)
}

/// The table a key inside an array of tables names: its name (`disc` in
/// `bodies.disc.mass`) or, for an index, `body 0`; None for other keys.
fn table_name(key: &str) -> Option<String> {
    let mut segments = key.split('.').map(str::trim);
    let (array, name) = (segments.next()?, segments.next()?);
    segments.next()?;
    let item = match array {
        "bodies" => "body",
        "shapes" => "shape",
        "springs" => "spring",
        "actuators" => "actuator",
        _ => return None,
    };
    Some(match name.parse::<usize>() {
        Ok(i) => format!("{item} {i}"),
        Err(_) => name.to_string(),
    })
}

/// The quantity of `key` in words, prefixed by the table's name inside an array of tables
/// (`disc mass`); the key itself if it is not a known numeric key.
pub fn key_words(key: &str) -> String {
    match (key_info(key), table_name(key)) {
        (Some(info), Some(name)) => format!("{name} {}", info.words),
        (Some(info), None) => info.words.to_string(),
        (None, _) => key.to_string(),
    }
}

/// An axis label for `key`: its words and unit, `motor torque T (N m)`; the key itself
/// if it is not a known numeric key.
pub fn axis_label(key: &str) -> String {
    match key_info(key).map(|i| i.unit) {
        Some("") | None => key_words(key),
        Some(unit) => format!("{} ({unit})", key_words(key)),
    }
}

/// A legend entry for `key = value`: `motor torque T = 0.2 N m`.
pub fn value_label(key: &str, value: f64) -> String {
    match key_info(key).map(|i| i.value_unit) {
        Some("") | None => format!("{} = {value}", key_words(key)),
        Some(unit) => format!("{} = {value} {unit}", key_words(key)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_read_as_words_with_units() {
        assert_eq!(axis_label("controller.torque"), "motor torque T (N m)");
        assert_eq!(axis_label("controller.force"), "motor force F (N)");
        assert_eq!(
            axis_label("controller.cane_delay"),
            "cane delay CD (fraction of the motor period)"
        );
        assert_eq!(
            value_label("controller.cane_duration", 0.5),
            "cane duration CDC = 0.5"
        );
        assert_eq!(axis_label("bodies.disc.mass"), "disc mass (kg)");
        assert_eq!(
            value_label("bodies.0.inertia", 0.003),
            "body 0 moment of inertia = 0.003 kg m²"
        );
        assert_eq!(axis_label("environment.friction"), "friction coefficient μ");
        // Unknown keys stay as they are.
        assert_eq!(axis_label("controller.unknown"), "controller.unknown");
        assert_eq!(axis_label("bodies.disc"), "bodies.disc");
    }
}
