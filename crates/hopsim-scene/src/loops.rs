//! `[[loops]]`: loop joints closing kinematic loops between the bodies' trees
//! (docs/scene-format.md, docs/physics.md §8), and the start state's closure.

use crate::bodies::{check_count, Names};
use crate::error::SceneError;
use crate::reader::{Num, Table};
use hopsim_model::{Kinematics, LoopJoint, LoopKind, Model, ModelBuilder, Vec2};
use hopsim_step::{State, StepSettings, Stepper};

/// Most loop joints a scene may have.
pub const MAX_LOOPS: usize = 1000;
/// The largest loop error (m or rad) and loop velocity (m/s or rad/s) a start state may
/// have; within it the start is assembled exactly, beyond it the scene is refused.
pub const START_LOOP_TOLERANCE: f64 = 1e-6;
/// The word `body_b` takes for the world (unless a body has that name).
const WORLD: &str = "world";

/// Reads `[[loops]]` and adds each loop joint to `builder`; an error names the table and
/// key it is about.
pub(crate) fn read_loops(
    tables: &[Table<'_>],
    bodies: &Names,
    builder: &mut ModelBuilder,
) -> Result<(), SceneError> {
    check_count(tables, MAX_LOOPS, "loops", "")?;
    let mut names = Names::new(("loop", "loops"));
    for (i, t) in tables.iter().enumerate() {
        let name = t
            .opt_str("name")?
            .map_or(format!("loop{i}"), str::to_string);
        names.add(t, "name", &name)?;
        let kind = match t.choice("type", &["revolute", "distance", "weld", "slot"], None)? {
            "revolute" => LoopKind::Revolute,
            "distance" => LoopKind::Distance {
                length: t.f64("length", Num::positive("m").coordinate())?,
            },
            "weld" => LoopKind::Weld {
                angle: t.f64_or("angle", 0.0, Num::any("rad").coordinate())?,
            },
            _ => {
                let axis = t.vec2("axis", None, "m")?;
                if axis == [0.0, 0.0] {
                    return Err(t.error_at_key("axis", "expected a non-zero direction [x, y]"));
                }
                LoopKind::Slot {
                    axis: Vec2::new(axis[0], axis[1]),
                }
            }
        };
        let body_b = match t.opt_str("body_b")? {
            None => None,
            Some(WORLD) if bodies.find(WORLD).is_none() => None,
            Some(_) => Some(bodies.resolve(t, "body_b")?),
        };
        let point = |key| {
            t.vec2(key, Some([0.0; 2]), "m")
                .map(|p| Vec2::new(p[0], p[1]))
        };
        let joint = LoopJoint {
            name,
            body_a: bodies.resolve(t, "body_a")?,
            point_a: point("point_a")?,
            body_b,
            point_b: point("point_b")?,
            kind,
        };
        builder
            .add_loop(joint)
            .map_err(|e| t.error_at_key("body_b", e.to_string()))?;
        for key in ["length", "angle", "axis"] {
            if t.get(key).is_some() && !expects(kind, key) {
                return Err(t.error_at_key(key, format!("a {} loop has no '{key}'", kind.as_str())));
            }
        }
        t.finish()?;
    }
    Ok(())
}

/// Whether a loop of `kind` reads `key`.
fn expects(kind: LoopKind, key: &str) -> bool {
    matches!(
        (kind, key),
        (LoopKind::Distance { .. }, "length")
            | (LoopKind::Weld { .. }, "angle")
            | (LoopKind::Slot { .. }, "axis")
    )
}

/// The start `state` closed onto the loops (docs/physics.md §8.4): a start whose loop
/// error or loop velocity exceeds [`START_LOOP_TOLERANCE`] is an error at `[initial]` with
/// the gap, the loop and the assembled start (when the projection finds one); a start
/// within it is assembled exactly.
pub(crate) fn close_start(
    init: &Table<'_>,
    model: &Model,
    state: &mut State,
) -> Result<(), SceneError> {
    if model.loops().is_empty() {
        return Ok(());
    }
    let (n, m) = (model.dof(), model.loop_row_count());
    let mut kinematics = Kinematics::new(model);
    kinematics.update(model, &state.q, &state.u);
    let mut phi = vec![0.0; m];
    model.loop_residuals_to(&kinematics, &mut phi);
    let mut rows = vec![0.0; m * n];
    model.loop_rows_to(&kinematics, &mut rows);
    let rates: Vec<f64> = rows
        .chunks_exact(n)
        .map(|r| r.iter().zip(state.u.iter()).map(|(a, b)| a * b).sum())
        .collect();
    let worst = |values: &[f64]| {
        (0..m)
            .max_by(|&a, &b| values[a].abs().total_cmp(&values[b].abs()))
            .map_or((0.0, 0), |r| (values[r].abs(), r))
    };
    let (gap, gap_row) = worst(&phi);
    let (rate, rate_row) = worst(&rates);
    let mut assembled = state.clone();
    let closed = Stepper::new(model, StepSettings::default()).assemble(model, &mut assembled);
    if gap <= START_LOOP_TOLERANCE && rate <= START_LOOP_TOLERANCE && closed.is_ok() {
        *state = assembled;
        return Ok(());
    }
    let list = |v: &nalgebra::DVector<f64>| {
        let items: Vec<String> = v.iter().map(|x| format!("{x:.9}")).collect();
        format!("[{}]", items.join(", "))
    };
    let (key, message) = if gap > START_LOOP_TOLERANCE || closed.is_err() {
        let name = &model.loops()[model.loop_of_row(gap_row)].name;
        let offer = match &closed {
            Ok(_) => format!("; an assembled start is q = {}", list(&assembled.q)),
            Err(_) => "; no assembled start was found near it (the projection onto the \
                       closure did not converge: is the mechanism near a singular \
                       configuration?)"
                .to_string(),
        };
        (
            "q",
            format!(
                "loop '{name}' is open by {gap:.3e} at the start (m, or rad for a weld's \
                 angle), more than {START_LOOP_TOLERANCE:e}{offer}"
            ),
        )
    } else {
        let name = &model.loops()[model.loop_of_row(rate_row)].name;
        (
            "u",
            format!(
                "loop '{name}' opens at {rate:.3e} m/s (or rad/s) at the start, more than \
                 {START_LOOP_TOLERANCE:e}; the velocities that keep it closed nearest to \
                 these (in the mass matrix's metric) are u = {}",
                list(&assembled.u)
            ),
        )
    };
    let key = if init.get(key).is_some() { key } else { "q" };
    Err(init.error_at_key(key, message))
}
