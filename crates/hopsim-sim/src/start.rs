//! Checks of a start state (docs/scene-format.md, `[initial]`): its values
//! ([`check_state`]: one per coordinate, finite, within the run's bounds) and its geometry
//! ([`check_start`]: no shape inside the terrain, no two shapes that can touch
//! overlapping, complete overlaps included, no joint past one of its stops). Shared by the
//! scene reader and by every front end that sets a state (`Simulation::set_state`, the
//! Python package's `set_state`).

use crate::{Setup, MAX_COORDINATE, MAX_MAGNITUDE};
use hopsim_io::number;
use hopsim_model::{Kinematics, Model, Shape, Vec2};
use hopsim_step::State;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query::contact;
use parry2d_f64::shape::{Ball, Capsule, ConvexPolygon, SharedShape};
use std::f64::consts::TAU;

/// Gaps below `-PENETRATION_TOL` at a start state are refused, m (or rad for a stop).
pub const PENETRATION_TOL: f64 = 1e-9;

/// Overlaps of the solids (parry2d's depth, to about 1e-7 m for polygons, and ellipses and
/// arcs as inscribed polygons) beyond this are refused, m.
const SOLID_OVERLAP_TOL: f64 = 1e-6;

/// What is wrong with the values of a state given for a scene, or with its start.
#[derive(Clone, Debug, PartialEq)]
pub enum StateProblem {
    /// `q` and `u` do not hold one entry per generalised coordinate.
    Size {
        coordinates: Vec<String>,
        q: usize,
        u: usize,
    },
    /// `name` (`t`, `q[i] (x)`, `u[i] (x)`) is `value`; `expected` says what it must be.
    Value {
        name: String,
        value: f64,
        expected: String,
    },
    /// The geometry of the start ([`check_start`]).
    Start(StartProblem),
}

impl std::fmt::Display for StateProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StateProblem::Size { coordinates, q, u } => write!(
                f,
                "q and u must have {} entries ({}), got {q} and {u}",
                coordinates.len(),
                coordinates.join(", ")
            ),
            StateProblem::Value {
                name,
                value,
                expected,
            } => write!(f, "{name} = {}: expected {expected}", number(*value)),
            StateProblem::Start(problem) => problem.fmt(f),
        }
    }
}

impl std::error::Error for StateProblem {}

impl From<StartProblem> for StateProblem {
    fn from(problem: StartProblem) -> Self {
        StateProblem::Start(problem)
    }
}

/// Checks the values of `state` for `setup` as the scene reader checks `[initial]`: one
/// entry of `q` and `u` per coordinate, each finite, `|q_i| ≤` [`MAX_COORDINATE`],
/// `|u_i| ≤ simulation.max_speed`, and `|t| ≤` [`MAX_MAGNITUDE`] s. The geometry is
/// [`check_start`]'s.
pub fn check_state(setup: &Setup, state: &State) -> Result<(), StateProblem> {
    let names = &setup.coordinates;
    let (q, u) = (state.q.as_slice(), state.u.as_slice());
    if q.len() != names.len() || u.len() != names.len() {
        return Err(StateProblem::Size {
            coordinates: names.clone(),
            q: q.len(),
            u: u.len(),
        });
    }
    let check = |name: &dyn Fn() -> String, value: f64, unit: &str, max: f64| match bound_problem(
        value, unit, max,
    ) {
        None => Ok(()),
        Some(expected) => Err(StateProblem::Value {
            name: name(),
            value,
            expected,
        }),
    };
    check(&|| "t".into(), state.t, "s", MAX_MAGNITUDE)?;
    let speed = setup.settings.max_speed;
    for (i, name) in names.iter().enumerate() {
        check(
            &|| format!("q[{i}] ({name})"),
            q[i],
            "m or rad",
            MAX_COORDINATE,
        )?;
        check(&|| format!("u[{i}] ({name})"), u[i], "m/s or rad/s", speed)?;
    }
    Ok(())
}

/// What a finite number in `unit` of magnitude at most `max` should have been, unless
/// `value` is one (the scene reader's wording).
fn bound_problem(value: f64, unit: &str, max: f64) -> Option<String> {
    if !value.is_finite() {
        Some(format!("a finite number in {unit}"))
    } else if value.abs() > max {
        Some(format!(
            "a finite number in {unit} of magnitude at most {}",
            number(max)
        ))
    } else {
        None
    }
}

/// What is wrong with a start state.
#[derive(Clone, Debug, PartialEq)]
pub enum StartProblem {
    /// A shape starts inside the terrain, by `depth` m (its deepest contact `contact`).
    InTerrain {
        shape: String,
        contact: String,
        depth: f64,
    },
    /// Two shapes that can touch overlap by `depth` m: as their contact `contact` sees it,
    /// or (`None`) with no corner or centre inside the other shape (crossing bars, two
    /// discs with one centre), as the solids' overlap.
    Overlap {
        first: String,
        second: String,
        contact: Option<String>,
        depth: f64,
    },
    /// The joint of body `body` starts at `position` (in `unit`, rad or m), `depth` past
    /// its lower (`upper = false`) or upper stop at `bound`.
    PastStop {
        body: String,
        upper: bool,
        position: f64,
        bound: f64,
        depth: f64,
        unit: &'static str,
    },
}

impl std::fmt::Display for StartProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StartProblem::InTerrain {
                shape,
                contact,
                depth,
            } => write!(
                f,
                "the shape '{shape}' starts {depth:.6e} m inside the terrain (contact '{contact}')"
            ),
            StartProblem::Overlap {
                first,
                second,
                contact,
                depth,
            } => {
                write!(
                    f,
                    "the shapes '{first}' and '{second}' overlap by {depth:.6e} m at the start"
                )?;
                match contact {
                    Some(contact) => write!(f, " (contact '{contact}')"),
                    None => write!(f, " (one inside the other)"),
                }
            }
            StartProblem::PastStop {
                body,
                upper,
                position,
                bound,
                depth,
                unit,
            } => {
                let (side, beyond) = if *upper {
                    ("upper", "above")
                } else {
                    ("lower", "below")
                };
                write!(
                    f,
                    "the joint of '{body}' starts at {position} {unit}, {depth:.6e} {unit} \
                     {beyond} its {side} stop at {bound} {unit}"
                )
            }
        }
    }
}

/// The first problem of `state` for `model` (terrain, then stops, then overlaps), or
/// `Ok`. Switchable shapes (`inactive[s]`) are not checked against the terrain.
pub fn check_start(model: &Model, state: &State, inactive: &[bool]) -> Result<(), StartProblem> {
    let mut ws = Kinematics::new(model);
    ws.update(model, &state.q, &state.u);
    if let Some((gap, contact)) = deepest_terrain_contact(model, &ws, inactive) {
        if gap < -PENETRATION_TOL {
            return Err(StartProblem::InTerrain {
                shape: model.shapes()[model.contacts()[contact].shape].name.clone(),
                contact: model.contacts()[contact].name.clone(),
                depth: -gap,
            });
        }
    }
    for limit in model.limits() {
        let position = ws.joint_position(limit.body);
        let gap = limit.gap(position);
        if gap < -PENETRATION_TOL {
            let prismatic = model.bodies()[limit.body]
                .joint
                .as_ref()
                .is_some_and(|j| matches!(j.kind, hopsim_model::JointKind::Prismatic { .. }));
            return Err(StartProblem::PastStop {
                body: model.bodies()[limit.body].name.clone(),
                upper: limit.upper,
                position,
                bound: limit.bound,
                depth: -gap,
                unit: if prismatic { "m" } else { "rad" },
            });
        }
    }
    // The contacts' exact gaps first, then the solids for what no contact sees.
    for (p, pair) in model.pairs().iter().enumerate() {
        let Some(geometry) = model.pair_geometry(&ws, p) else {
            continue;
        };
        if geometry.gap < -PENETRATION_TOL {
            return Err(StartProblem::Overlap {
                first: model.shapes()[pair.probe].name.clone(),
                second: model.shapes()[pair.target].name.clone(),
                contact: Some(pair.name.clone()),
                depth: -geometry.gap,
            });
        }
    }
    let mut checked: Vec<(usize, usize)> = Vec::new();
    for pair in model.pairs() {
        let key = (pair.probe.min(pair.target), pair.probe.max(pair.target));
        if checked.contains(&key) {
            continue;
        }
        checked.push(key);
        let depth = overlap(model, &ws, key.0, key.1);
        if depth > SOLID_OVERLAP_TOL {
            return Err(StartProblem::Overlap {
                first: model.shapes()[key.0].name.clone(),
                second: model.shapes()[key.1].name.clone(),
                contact: None,
                depth,
            });
        }
    }
    Ok(())
}

/// The smallest gap over the terrain contacts of active shapes, and its contact.
pub(crate) fn deepest_terrain_contact(
    model: &Model,
    ws: &Kinematics,
    inactive: &[bool],
) -> Option<(f64, usize)> {
    (0..model.contacts().len())
        .filter(|&i| !inactive[model.contacts()[i].shape])
        .filter_map(|i| model.contact_geometry(ws, i).map(|g| (g.gap, i)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// How deep shapes `a` and `b` overlap (`≤ 0`: they do not), m: the depth of parry2d's
/// contact query on the solids (an arc as its circular segment, an ellipse as an inscribed
/// 64-gon), which also sees overlaps without a corner inside the other shape (two crossing
/// bars, two discs with one centre).
fn overlap(model: &Model, ws: &Kinematics, a: usize, b: usize) -> f64 {
    let solid = |s: usize| {
        let inst = &model.shapes()[s];
        let (position, angle) = (ws.position(inst.body), ws.angle(inst.body));
        let (offset, shape) = solid_of(&inst.shape)?;
        let at = position + hopsim_model::rotate(angle, offset);
        Some((Pose::new(Vector::new(at.x, at.y), angle), shape))
    };
    let (Some((pa, sa)), Some((pb, sb))) = (solid(a), solid(b)) else {
        return 0.0;
    };
    match contact(&pa, &*sa, &pb, &*sb, 0.0) {
        Ok(Some(c)) => -c.dist,
        _ => 0.0,
    }
}

/// The solid of a shape for the overlap test, about an offset in its body's frame (the
/// centre of a disc, the point itself; zero for the others, whose corners are in the body
/// frame).
fn solid_of(shape: &Shape) -> Option<(Vec2, SharedShape)> {
    let hull = |points: Vec<Vector>| {
        ConvexPolygon::from_convex_hull(&points).map(|p| (Vec2::zeros(), SharedShape::new(p)))
    };
    let around = |center: Vec2, semi_x: f64, semi_y: f64, from: f64, to: f64, count: usize| {
        (0..count)
            .map(|i| from + (to - from) * i as f64 / (count - 1) as f64)
            .map(|t| Vector::new(center.x + semi_x * t.cos(), center.y + semi_y * t.sin()))
            .collect::<Vec<_>>()
    };
    match shape {
        Shape::Circle { center, radius } => Some((*center, SharedShape::new(Ball::new(*radius)))),
        Shape::Point { position } => Some((*position, SharedShape::new(Ball::new(0.0)))),
        Shape::Capsule { from, to, radius } => Some((
            Vec2::zeros(),
            SharedShape::new(Capsule::new(
                Vector::new(from.x, from.y),
                Vector::new(to.x, to.y),
                *radius,
            )),
        )),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => hull(around(*center, *radius, *radius, *start, *end, 65)),
        Shape::Ellipse {
            center,
            semi_x,
            semi_y,
        } => hull(around(*center, *semi_x, *semi_y, 0.0, TAU, 65)),
        Shape::Polygon { vertices } => {
            hull(vertices.iter().map(|v| Vector::new(v.x, v.y)).collect())
        }
    }
}
