//! `[environment]`: the terrain and the default contact material.

use crate::error::SceneError;
use crate::reader::{Num, Table};
use hopsim_model::{ContactMaterial, Terrain};

/// Reads the terrain and the default contact material (docs/physics.md §4: `μ`, `ε_N`, `ε_T`).
pub(crate) fn read_environment(env: &Table<'_>) -> Result<(Terrain, ContactMaterial), SceneError> {
    let kinds = ["flat", "incline", "step", "none"];
    let terrain = match env.choice("terrain", &kinds, Some("flat"))? {
        "none" => Terrain { features: vec![] },
        "flat" => Terrain::flat(env.f64_or("height", 0.0, Num::any("m").coordinate())?),
        "incline" => {
            let half_pi = std::f64::consts::FRAC_PI_2;
            Terrain::incline(env.f64("angle", Num::range(-half_pi, half_pi, "rad"))?)
        }
        _ => Terrain::step(
            env.f64("step_x", Num::any("m").coordinate())?,
            env.f64("step_height", Num::positive("m").coordinate())?,
        ),
    };
    let material = read_material(env, ContactMaterial::default())?;
    Ok((terrain, material))
}

/// `friction`, `restitution`, `tangential_restitution` of a table, defaulting to `base`.
pub(crate) fn read_material(
    table: &Table<'_>,
    base: ContactMaterial,
) -> Result<ContactMaterial, SceneError> {
    Ok(ContactMaterial {
        friction: table.f64_or("friction", base.friction, Num::non_negative(""))?,
        restitution_normal: table.f64_or(
            "restitution",
            base.restitution_normal,
            Num::range(0.0, 1.0, ""),
        )?,
        restitution_tangent: table.f64_or(
            "tangential_restitution",
            base.restitution_tangent,
            Num::range(-1.0, 1.0, ""),
        )?,
    })
}
