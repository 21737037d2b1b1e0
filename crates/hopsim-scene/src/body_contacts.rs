//! `[body_contacts]` and `[[contact_pairs]]`: contacts between shapes of two bodies
//! (docs/physics.md §7, `docs/scene-format.md`).

use crate::bodies::{Names, ShapeSpec};
use crate::error::SceneError;
use crate::reader::{Num, Table};
use crate::scene::MAX_CONTACTS;
use hopsim_model::{ContactMaterial, Model, ModelBuilder, ModelError};
use std::collections::HashSet;

/// Collision groups: 32, numbered 0–31.
pub(crate) const GROUPS: u32 = 32;

/// A shape's collision filter: its group (one bit) and the groups it collides with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Filter {
    pub group: u32,
    pub mask: u32,
}

impl Filter {
    /// Whether two shapes' filters let them collide (each accepts the other's group).
    fn accepts(self, other: Filter) -> bool {
        self.mask & other.group != 0 && other.mask & self.group != 0
    }
}

/// `group` (default 0) and `collides_with` (default every group) of a `[[shapes]]` table.
pub(crate) fn read_filter(t: &Table<'_>) -> Result<Filter, SceneError> {
    let groups = Num::range(0.0, f64::from(GROUPS - 1), "");
    let bit = |key: &'static str, v: f64| {
        if v.fract() == 0.0 {
            Ok(1u32 << (v as u32))
        } else {
            Err(t.error_at_key(
                key,
                format!(
                    "expected a whole group number from 0 to {}, found {v}",
                    GROUPS - 1
                ),
            ))
        }
    };
    let group = bit("group", t.f64_or("group", 0.0, groups)?)?;
    let mask = match t.opt_f64_list("collides_with", None, groups)? {
        None => u32::MAX,
        Some(list) => list
            .into_iter()
            .try_fold(0, |mask, v| bit("collides_with", v).map(|b| mask | b))?,
    };
    Ok(Filter { group, mask })
}

/// The default material of a pair: `[body_contacts]`' values where given, else the mean
/// of the two shapes' (docs/physics.md §7).
fn pair_material(
    defaults: &[Option<f64>; 3],
    a: &ContactMaterial,
    b: &ContactMaterial,
) -> ContactMaterial {
    let mean = |x: f64, y: f64, given: Option<f64>| given.unwrap_or(0.5 * (x + y));
    ContactMaterial {
        friction: mean(a.friction, b.friction, defaults[0]),
        restitution_normal: mean(a.restitution_normal, b.restitution_normal, defaults[1]),
        restitution_tangent: mean(a.restitution_tangent, b.restitution_tangent, defaults[2]),
    }
}

/// Adds the body–body contacts of `[body_contacts]` (`all`, default materials) and
/// `[[contact_pairs]]` (explicit pairs with their own materials) to `model`.
///
/// An explicit pair is always added, even between joined bodies or filtered groups;
/// `all = true` adds every other two shapes of different bodies that are not joined by a
/// joint, not both fixed, not switchable, whose filters accept each other and which hopsim
/// can compute exactly (see `hopsim_model::pair_features`).
pub(crate) fn read_body_contacts(
    top: &Table<'_>,
    shapes: &[ShapeSpec],
    names: &Names,
    builder: &mut ModelBuilder,
) -> Result<(), SceneError> {
    let settings = top.table_or_empty("body_contacts")?;
    let all = settings.bool_or("all", false)?;
    let defaults = [
        settings.opt_f64("friction", Num::non_negative(""))?,
        settings.opt_f64("restitution", Num::range(0.0, 1.0, ""))?,
        settings.opt_f64("tangential_restitution", Num::range(-1.0, 1.0, ""))?,
    ];
    settings.finish()?;
    let mut listed = HashSet::new();
    for t in top.tables("contact_pairs")? {
        let pair = t
            .opt_str_list("shapes", Some(2))?
            .ok_or_else(|| t.error_at_key("shapes", "missing; expected [\"shape\", \"shape\"]"))?;
        let a = names.index(&t, "shapes", pair[0])?;
        let b = names.index(&t, "shapes", pair[1])?;
        let bad = |reason: String| t.error_at_key("shapes", reason);
        if a == b {
            return Err(bad(format!("the pair names the shape '{}' twice", pair[0])));
        }
        if let Some(&s) = [a, b].iter().find(|&&s| shapes[s].switchable) {
            return Err(bad(format!(
                "the shape '{}' is switchable (a cane): it touches the terrain only",
                names.get(s)
            )));
        }
        if !listed.insert((a.min(b), a.max(b))) {
            return Err(bad(format!(
                "the pair '{}', '{}' is listed twice",
                pair[0], pair[1]
            )));
        }
        let base = pair_material(&defaults, &shapes[a].material, &shapes[b].material);
        let material = crate::environment::read_material(&t, base)?;
        t.finish()?;
        builder
            .add_body_contacts(a, b, material)
            .map_err(|e| match e {
                ModelError::BadPair { reason, .. } => bad(reason),
                other => bad(other.to_string()),
            })?;
        check_count(builder.model(), &t, "shapes")?;
    }
    if all {
        for a in 0..shapes.len() {
            for b in a + 1..shapes.len() {
                let (body_a, body_b) = (shapes[a].instance.body, shapes[b].instance.body);
                let skip = body_a == body_b
                    || listed.contains(&(a, b))
                    || builder.model().joined(body_a, body_b)
                    || (builder.model().bodies()[body_a].is_fixed()
                        && builder.model().bodies()[body_b].is_fixed())
                    || shapes[a].switchable
                    || shapes[b].switchable
                    || !shapes[a].filter.accepts(shapes[b].filter)
                    || hopsim_model::pair_features(
                        &shapes[a].instance.shape,
                        &shapes[b].instance.shape,
                    )
                    .is_err();
                if skip {
                    continue;
                }
                let material = pair_material(&defaults, &shapes[a].material, &shapes[b].material);
                builder
                    .add_body_contacts(a, b, material)
                    .map_err(|e| settings.error_at_key("all", e.to_string()))?;
                check_count(builder.model(), &settings, "all")?;
            }
        }
    }
    Ok(())
}

/// The scene's contact limit ([`MAX_CONTACTS`]) over terrain and body–body contacts, as
/// an error at `key` of `table` (where the pair that crossed it was added).
fn check_count(model: &Model, table: &Table<'_>, key: &str) -> Result<(), SceneError> {
    if model.contact_count() <= MAX_CONTACTS {
        return Ok(());
    }
    Err(table.error_at_key(
        key,
        format!(
            "the shapes make more than {MAX_CONTACTS} potential contacts with the terrain and \
             between bodies ({} terrain contacts); a scene may have at most {MAX_CONTACTS}",
            model.contacts().len()
        ),
    ))
}
