//! `[[bodies]]`, `[[shapes]]` and `[[springs]]`: the multibody model (docs/physics.md §1).

use crate::body_contacts::{read_filter, Filter};
use crate::environment::read_material;
use crate::error::{number, short_list, suggestion, SceneError};
use crate::reader::{Num, Table};
use crate::tree::Origin;
use hopsim_model::{
    Body, ContactMaterial, Joint, JointCoordinate, JointKind, JointLimits, Shape, ShapeInstance,
    Spring, Vec2,
};
use std::collections::{HashMap, HashSet};

/// Most bodies a scene may have: the model's per-body Jacobians are dense (`3B × n` with
/// `n = B + 2`), so memory grows with the square of the body count (24 MB at this limit;
/// 20 000 bodies would need 9.6 GB).
pub const MAX_BODIES: usize = 1000;
/// Most shapes a scene may have.
pub const MAX_SHAPES: usize = 1000;
/// Most springs a scene may have.
pub const MAX_SPRINGS: usize = 1000;
/// Most names listed in a message.
const LISTED: usize = 12;

/// Names of things a scene refers to (bodies, shapes), with their indices.
pub(crate) struct Names {
    /// What the names are, for messages: singular and plural ("body", "bodies").
    what: (&'static str, &'static str),
    names: Vec<String>,
    index: HashMap<String, usize>,
    /// Where each name was written, and the dotted key holding it.
    written: Vec<(Origin, String)>,
}

impl Names {
    pub fn new(what: (&'static str, &'static str)) -> Self {
        Self {
            what,
            names: Vec::new(),
            index: HashMap::new(),
            written: Vec::new(),
        }
    }

    /// Registers `name` read from `key` of `table`; empty names, names that would break
    /// the CSV files and channels they label, and duplicates are errors. When an override
    /// made the clash, the error names the override.
    pub fn add(&mut self, table: &Table<'_>, key: &str, name: &str) -> Result<usize, SceneError> {
        check_name(table, key, name)?;
        let origin = table.origin_of(key);
        if let Some(&first) = self.index.get(name) {
            let (first_origin, first_key) = &self.written[first];
            let unique = format!(
                "a {} named '{name}' already exists; names must be unique",
                self.what.0
            );
            let by_override = |o: &Origin| matches!(o, Origin::Override(_));
            return Err(match (by_override(first_origin), by_override(&origin)) {
                (true, false) => SceneError::Invalid {
                    location: table.locate(first_origin),
                    key: first_key.clone(),
                    message: format!(
                        "a {} named '{name}' already exists at {} ({}); names must be unique",
                        self.what.0,
                        table.locate(&origin),
                        table.key_path(key)
                    ),
                },
                (false, true) => table.error_at_key(
                    key,
                    format!(
                        "a {} named '{name}' already exists at {} ({first_key}); names must be \
                         unique",
                        self.what.0,
                        table.locate(first_origin)
                    ),
                ),
                _ => table.error_at_key(key, unique),
            });
        }
        self.index.insert(name.to_string(), self.names.len());
        self.names.push(name.to_string());
        self.written.push((origin, table.key_path(key)));
        Ok(self.names.len() - 1)
    }

    /// Index of the thing named by the string at `key` of `table`.
    pub fn resolve(&self, table: &Table<'_>, key: &'static str) -> Result<usize, SceneError> {
        let name = table.str(key)?;
        self.index(table, key, name)
    }

    /// Index of `name` (read from `key` of `table`).
    pub fn index(&self, table: &Table<'_>, key: &str, name: &str) -> Result<usize, SceneError> {
        self.index.get(name).copied().ok_or_else(|| {
            let hint = suggestion(name, self.names.iter().map(String::as_str));
            let known = if hint.is_empty() {
                format!(
                    "; the {} are: {}{}",
                    self.what.1,
                    short_list(self.names.iter().map(String::as_str), LISTED),
                    self.renamed()
                )
            } else {
                hint
            };
            table.error_at_key(
                key,
                format!("there is no {} named '{name}'{known}", self.what.0),
            )
        })
    }

    /// `" (--set … changed bodies[0].name)"` when an override set one of the names (a
    /// name the file refers to may be the one it changed), else nothing.
    fn renamed(&self) -> String {
        self.written
            .iter()
            .find_map(|(origin, key)| match origin {
                Origin::Override(text) => Some(format!(" ({text} changed {key})")),
                Origin::File(_) => None,
            })
            .unwrap_or_default()
    }

    /// Index of `name`, if registered.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    pub fn get(&self, i: usize) -> &str {
        &self.names[i]
    }
}

/// A name labels files, CSV columns and channels: it must not be empty (or blank) and must
/// not hold commas or control characters.
fn check_name(table: &Table<'_>, key: &str, name: &str) -> Result<(), SceneError> {
    if name.trim().is_empty() {
        return Err(table.error_at_key(key, format!("expected a non-empty name, found \"{name}\"")));
    }
    if name.chars().any(|c| c == ',' || c.is_control()) {
        return Err(table.error_at_key(
            key,
            format!(
                "expected a name without commas or control characters (names label CSV \
                 columns), found {name:?}"
            ),
        ));
    }
    Ok(())
}

/// Contact names are `<shape>[#k]/terrain<i>` and `<probe>[#k]/<target>`
/// (docs/scene-format.md): so that every contact's name is unique, a shape's name holds no
/// `/` or `#` and is not `terrain` followed by digits.
fn check_shape_name(t: &Table<'_>, name: &str) -> Result<(), SceneError> {
    let terrain_like = name
        .strip_prefix("terrain")
        .is_some_and(|rest| !rest.is_empty() && rest.chars().all(|c| c.is_ascii_digit()));
    if name.contains(['/', '#']) || terrain_like {
        let origin = if t.get("name").is_some() {
            "name"
        } else {
            "body"
        };
        return Err(t.error_at_key(
            origin,
            format!(
                "the shape name '{name}' would make contact names ambiguous: shape names \
                 may not hold '/' or '#' nor be 'terrain' followed by digits (a shape \
                 without a name is named '<body>_<type>')"
            ),
        ));
    }
    Ok(())
}

/// At most `max` tables of `key`, else an error at the first one too many.
pub(crate) fn check_count(
    tables: &[Table<'_>],
    max: usize,
    what: &str,
    why: &str,
) -> Result<(), SceneError> {
    match tables.get(max) {
        None => Ok(()),
        Some(extra) => Err(extra.error_here(format!(
            "a scene may have at most {max} {what}{why}; found {}",
            tables.len()
        ))),
    }
}

/// Why `parent` (the name `b`'s table gives) is not an earlier body: it is the body
/// itself, a later body (with the cycle it closes, if any), or no body at all.
fn parent_error(
    tables: &[Table<'_>],
    b: usize,
    parent: &str,
    names: &Names,
    all: &HashMap<&str, usize>,
    parents: &[Option<&str>],
) -> SceneError {
    let t = &tables[b];
    let own = names.get(b);
    if parent == own {
        return t.error_at_key("parent", "a body cannot be its own parent");
    }
    let Some(&later) = all.get(parent) else {
        // Neither earlier nor later: a typo. Suggest among the other bodies.
        let others = all.keys().copied().filter(|n| *n != own);
        let hint = suggestion(parent, others);
        let known = if hint.is_empty() {
            let mut sorted: Vec<(&str, usize)> = all.iter().map(|(n, &i)| (*n, i)).collect();
            sorted.sort_by_key(|&(_, i)| i);
            format!(
                "; the bodies are: {}{}",
                short_list(sorted.iter().map(|&(n, _)| n).filter(|n| *n != own), LISTED),
                names.renamed()
            )
        } else {
            hint
        };
        return t.error_at_key(
            "parent",
            format!("there is no body named '{parent}'{known}"),
        );
    };
    // Follow the later body's parents: back to this body is a cycle.
    let mut chain = vec![own, parent];
    let mut seen = HashSet::from([b, later]);
    let mut at = later;
    while let Some(next) = parents[at] {
        let Some(&i) = all.get(next) else { break };
        chain.push(next);
        if i == b {
            return t.error_at_key(
                "parent",
                format!(
                    "cycle {}: a body cannot hang on its own descendants",
                    chain.join(" → ")
                ),
            );
        }
        if !seen.insert(i) {
            // A cycle among later bodies: report it where it starts.
            let start = chain.iter().position(|n| *n == next).unwrap_or(0);
            return tables[i].error_at_key(
                "parent",
                format!(
                    "cycle {}: a body cannot hang on its own descendants",
                    chain[start..].join(" → ")
                ),
            );
        }
        at = i;
    }
    t.error_at_key(
        "parent",
        format!(
            "parent '{parent}' is defined after '{own}' (bodies[{later}] at {}): list parents \
             first",
            t.locate(&tables[later].origin_of("name"))
        ),
    )
}

/// The bodies and the names of the generalised coordinates (`x, y, phi` of the first
/// body when it is a floating base, then those each further body adds).
pub(crate) fn read_bodies(
    top: &Table<'_>,
    tables: &[Table<'_>],
    names: &mut Names,
) -> Result<(Vec<Body>, Vec<String>), SceneError> {
    if tables.is_empty() {
        return Err(top.error_at_key(
            "bodies",
            "a scene needs at least one [[bodies]] table (the first is the floating base)",
        ));
    }
    check_count(
        tables,
        MAX_BODIES,
        "bodies",
        " (the model's Jacobians grow with the square of the body count)",
    )?;
    // Every body's name and parent, to tell a parent listed later from a missing one.
    let mut all: HashMap<&str, usize> = HashMap::new();
    let mut parents = Vec::with_capacity(tables.len());
    for (b, t) in tables.iter().enumerate() {
        if let Ok(Some(name)) = t.opt_str("name") {
            all.entry(name).or_insert(b);
        }
        parents.push(t.opt_str("parent").ok().flatten());
    }
    let mut bodies = Vec::with_capacity(tables.len());
    let mut coordinates = Coordinates::default();
    for (b, t) in tables.iter().enumerate() {
        let name = t.str("name")?;
        names.add(t, "name", name)?;
        let parent = t.opt_str("parent")?;
        let base = match t.get("base") {
            Some(_) => Some(t.choice("base", &["floating", "pinned", "fixed"], None)?),
            None => None,
        };
        let fixed = base == Some("fixed");
        // A link on a joint (not a floating base) with children.
        let floating = (b == 0 && base.is_none()) || base == Some("floating");
        let has_child = !floating && parents.iter().skip(b + 1).any(|p| *p == Some(name));
        let (mass, inertia) = if fixed {
            // A fixed base only carries shapes: its mass and inertia are optional.
            (
                t.f64_or("mass", 0.0, Num::non_negative("kg"))?,
                t.f64_or("inertia", 0.0, Num::non_negative("kg m²"))?,
            )
        } else if has_child {
            // A link with children may be massless: their masses carry its coordinate.
            (
                t.f64("mass", Num::non_negative("kg"))?,
                t.f64("inertia", Num::non_negative("kg m²"))?,
            )
        } else {
            (
                t.f64("mass", Num::positive("kg").at_least(1e-9))?,
                t.f64("inertia", Num::positive("kg m²").at_least(1e-12))?,
            )
        };
        let joint =
            match (b, parent, base) {
                (_, Some(_), Some(_)) => {
                    return Err(t.error_at_key(
                        "base",
                        "a body with a parent hangs on a joint; 'base' belongs to a tree's root \
                     (a body without a parent)",
                    ))
                }
                (0, Some(_), None) => return Err(t.error_at_key(
                    "parent",
                    "the first body is the floating base (x, y, phi) and cannot have a parent; \
                     parents come before their children",
                )),
                (0, None, None) | (_, None, Some("floating")) => {
                    coordinates.floating(t, b, name)?;
                    None
                }
                (_, None, None) => {
                    return Err(t.error_at_key(
                        "parent",
                        format!(
                        "missing; every body after the first hangs on a joint on a parent body \
                         (one of: {}) or starts a tree of its own with base = \"floating\", \
                         \"pinned\" or \"fixed\"",
                        short_list((0..b).map(|i| names.get(i)), LISTED)
                    ),
                    ))
                }
                (_, None, Some("fixed")) => {
                    if t.get("coordinate_name").is_some() {
                        return Err(t.error_at_key(
                            "coordinate_name",
                            "a fixed body has no coordinate to name",
                        ));
                    }
                    Some(Joint {
                        kind: JointKind::Fixed {
                            angle: t.f64_or("angle", 0.0, Num::any("rad").coordinate())?,
                        },
                        ..Joint::revolute(
                            None,
                            vec2(t.vec2("position", Some([0.0; 2]), "m")?),
                            Vec2::zeros(),
                        )
                    })
                }
                (_, None, Some(_)) => {
                    // Pinned: a revolute joint to the world point `pivot`.
                    let pivot = vec2(t.vec2("pivot", Some([0.0; 2]), "m")?);
                    Some(read_joint(t, name, None, pivot, &mut coordinates)?)
                }
                (_, Some(p), None) => {
                    let parent = match names.find(p) {
                        Some(i) if i < b => i,
                        _ => return Err(parent_error(tables, b, p, names, &all, &parents)),
                    };
                    let pivot = vec2(t.vec2("pivot", Some([0.0; 2]), "m")?);
                    Some(read_joint(t, name, Some(parent), pivot, &mut coordinates)?)
                }
            };
        t.finish()?;
        bodies.push(Body {
            name: name.to_string(),
            mass,
            inertia,
            joint,
        });
    }
    Ok((bodies, coordinates.names))
}

/// The generalised coordinates' names, in order, and the names taken.
#[derive(Default)]
struct Coordinates {
    names: Vec<String>,
    taken: HashSet<String>,
}

impl Coordinates {
    /// Adds `name` (checked: an identifier, unique), read from `coordinate_name` of `t`.
    fn add(&mut self, t: &Table<'_>, name: String) -> Result<(), SceneError> {
        check_coordinate_name(t, &name, &self.taken, &self.names)?;
        self.taken.insert(name.clone());
        self.names.push(name);
        Ok(())
    }

    /// A floating base's three coordinates: `x, y, phi` for the first body, else suffixed
    /// with the body's name.
    fn floating(&mut self, t: &Table<'_>, b: usize, body: &str) -> Result<(), SceneError> {
        if t.get("coordinate_name").is_some() {
            return Err(t.error_at_key(
                "coordinate_name",
                if b == 0 {
                    "the floating base's coordinates are always x, y, phi".to_string()
                } else {
                    format!(
                        "a floating base's coordinates are always x_{body}, y_{body}, phi_{body}"
                    )
                },
            ));
        }
        for axis in ["x", "y", "phi"] {
            let name = if b == 0 {
                axis.to_string()
            } else {
                format!("{axis}_{body}")
            };
            self.add(t, name)?;
        }
        Ok(())
    }
}

/// A revolute or prismatic joint on `parent` (`None`: the world, a pinned base) at `pivot`,
/// with its coordinate's name, damping, spring and limits (docs/physics.md §7).
fn read_joint(
    t: &Table<'_>,
    name: &str,
    parent: Option<usize>,
    pivot: Vec2,
    coordinates: &mut Coordinates,
) -> Result<Joint, SceneError> {
    let kind = if parent.is_some() {
        t.choice("joint", &["revolute", "prismatic"], Some("revolute"))?
    } else {
        t.choice("joint", &["revolute"], Some("revolute"))?
    };
    let prismatic = kind == "prismatic";
    let (kind, unit, prefix) = if prismatic {
        let axis = t.vec2("axis", None, "m").map_err(|e| match t.get("axis") {
            None => t.error_at_key(
                "joint",
                "a prismatic joint needs 'axis = [x, y]', the direction (in the parent's \
                 frame) along which the child slides",
            ),
            Some(_) => e,
        })?;
        let axis = vec2(axis);
        let length = axis.norm();
        if length <= 1e-9 {
            return Err(t.error_at_key(
                "axis",
                "expected a non-zero direction [x, y] (it is scaled to unit length)",
            ));
        }
        (
            JointKind::Prismatic {
                axis: axis / length,
            },
            ("m", "N s/m", "N/m"),
            "s",
        )
    } else {
        if t.get("axis").is_some() {
            return Err(t.error_at_key("axis", "only a prismatic joint has an axis"));
        }
        (
            JointKind::Revolute,
            ("rad", "N m s/rad", "N m/rad"),
            "theta",
        )
    };
    let (position_unit, damping_unit, stiffness_unit) = unit;
    let coordinate = if prismatic {
        JointCoordinate::Relative
    } else {
        let choices: &[&str] = match parent {
            Some(_) => &["relative", "clockwise", "absolute"],
            None => &["relative", "clockwise"],
        };
        match t.choice("coordinate", choices, Some("relative"))? {
            "absolute" => JointCoordinate::Absolute,
            "clockwise" => JointCoordinate::Clockwise,
            _ => JointCoordinate::Relative,
        }
    };
    let armature_unit = if prismatic { "kg" } else { "kg m²" };
    let dry_friction_unit = if prismatic { "N" } else { "N m" };
    let armature = t.f64_or("armature", 0.0, Num::non_negative(armature_unit))?;
    if armature != 0.0 && coordinate == JointCoordinate::Absolute {
        return Err(t.error_at_key(
            "armature",
            "an armature adds to the joint coordinate's diagonal of the mass matrix; an \
             absolute angle is not the joint's position (use coordinate = \"relative\")",
        ));
    }
    let coordinate_name = match t.opt_str("coordinate_name")? {
        Some(c) => c.to_string(),
        None => format!("{prefix}_{name}"),
    };
    coordinates.add(t, coordinate_name)?;
    let limits = match t.opt_f64_list("limits", Some(2), Num::any(position_unit).coordinate())? {
        None => {
            if t.get("limit_restitution").is_some() {
                return Err(t.error_at_key(
                    "limit_restitution",
                    "a joint without 'limits = [lower, upper]' has no stops to bounce on",
                ));
            }
            None
        }
        Some(v) => {
            if v[0] >= v[1] {
                return Err(t.error_at_key(
                    "limits",
                    format!(
                        "expected [lower, upper] with lower < upper in {position_unit}, found \
                         lower = {}, upper = {}",
                        number(v[0]),
                        number(v[1])
                    ),
                ));
            }
            Some(JointLimits {
                lower: v[0],
                upper: v[1],
                restitution: t.f64_or("limit_restitution", 0.0, Num::range(0.0, 1.0, ""))?,
            })
        }
    };
    Ok(Joint {
        parent,
        pivot_in_parent: pivot,
        com_in_child: vec2(t.vec2("com", Some([0.0; 2]), "m")?),
        coordinate,
        kind,
        damping: t.f64_or("damping", 0.0, Num::non_negative(damping_unit))?,
        stiffness: t.f64_or("stiffness", 0.0, Num::non_negative(stiffness_unit))?,
        rest_position: t.f64_or("rest_position", 0.0, Num::any(position_unit).coordinate())?,
        limits,
        armature,
        dry_friction: t.f64_or("dry_friction", 0.0, Num::non_negative(dry_friction_unit))?,
    })
}

/// A shape as the scene describes it, with its contact material and switchability.
pub(crate) struct ShapeSpec {
    pub instance: ShapeInstance,
    pub material: ContactMaterial,
    /// Switched on and off by the controller (a cane); starts switched off.
    pub switchable: bool,
    /// Collision group and mask for `[body_contacts] all = true`.
    pub filter: Filter,
}

pub(crate) fn read_shapes(
    tables: &[Table<'_>],
    bodies: &Names,
    shapes: &mut Names,
    base_material: ContactMaterial,
) -> Result<Vec<ShapeSpec>, SceneError> {
    check_count(tables, MAX_SHAPES, "shapes", "")?;
    let mut out = Vec::with_capacity(tables.len());
    for t in tables {
        let body = bodies.resolve(t, "body")?;
        let kind = t.choice(
            "type",
            &[
                "circle", "arc", "ellipse", "point", "polygon", "box", "capsule",
            ],
            None,
        )?;
        let name = match t.opt_str("name")? {
            Some(n) => n.to_string(),
            None => format!("{}_{kind}", bodies.get(body)),
        };
        check_shape_name(t, &name)?;
        shapes.add(t, "name", &name)?;
        let shape = read_geometry(t, kind)?;
        let material = read_material(t, base_material)?;
        let switchable = t.bool_or("switchable", false)?;
        let filter = read_filter(t)?;
        t.finish()?;
        out.push(ShapeSpec {
            instance: ShapeInstance { name, body, shape },
            material,
            switchable,
            filter,
        });
    }
    Ok(out)
}

fn read_geometry(t: &Table<'_>, kind: &str) -> Result<Shape, SceneError> {
    let center = || Ok::<_, SceneError>(vec2(t.vec2("center", Some([0.0; 2]), "m")?));
    let length = Num::positive("m").coordinate();
    Ok(match kind {
        "circle" => Shape::Circle {
            center: center()?,
            radius: t.f64("radius", length)?,
        },
        "arc" => {
            let center = center()?;
            let radius = t.f64("radius", length)?;
            let start = t.f64("start", Num::any("rad").coordinate())?;
            let end = t.f64("end", Num::any("rad").coordinate())?;
            if !(end > start && end - start <= std::f64::consts::TAU) {
                return Err(t.error_at_key(
                    "end",
                    format!(
                        "the arc must run counter-clockwise from start to end with \
                         0 < end - start <= 2π; found start = {}, end = {}",
                        number(start),
                        number(end)
                    ),
                ));
            }
            Shape::Arc {
                center,
                radius,
                start,
                end,
            }
        }
        "ellipse" => Shape::Ellipse {
            center: center()?,
            semi_x: t.f64("semi_x", length)?,
            semi_y: t.f64("semi_y", length)?,
        },
        "point" => Shape::Point {
            position: vec2(t.vec2("position", None, "m")?),
        },
        "capsule" => Shape::Capsule {
            from: vec2(t.vec2("from", None, "m")?),
            to: vec2(t.vec2("to", None, "m")?),
            radius: t.f64("radius", length)?,
        },
        "box" => {
            let c = center()?;
            let (w, h) = (t.f64("half_width", length)?, t.f64("half_height", length)?);
            Shape::Polygon {
                vertices: [(-w, -h), (w, -h), (w, h), (-w, h)]
                    .map(|(x, y)| c + Vec2::new(x, y))
                    .to_vec(),
            }
        }
        _ => {
            let vertices: Vec<Vec2> = t
                .vec2_list("vertices", "m")?
                .into_iter()
                .map(vec2)
                .collect();
            check_convex_ccw(t, &vertices)?;
            Shape::Polygon { vertices }
        }
    })
}

/// A polygon must have at least three vertices, counter-clockwise, strictly convex, and
/// wind around its inside once (a star's corners all turn left, yet it crosses itself):
/// the same test as the model's, so the model never rejects a polygon the scene accepted.
fn check_convex_ccw(t: &Table<'_>, v: &[Vec2]) -> Result<(), SceneError> {
    if v.len() < 3 {
        return Err(t.error_at_key(
            "vertices",
            format!("a polygon needs at least 3 vertices, found {}", v.len()),
        ));
    }
    let n = v.len();
    let mut winding = 0.0;
    for i in 0..n {
        let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
        let e1 = b - a;
        let e2 = c - b;
        let cross = e1.x * e2.y - e1.y * e2.x;
        if cross <= 0.0 || !cross.is_finite() {
            return Err(t.error_at_key(
                "vertices",
                format!(
                    "the polygon must be convex with vertices counter-clockwise; the turn at \
                     vertex {} is clockwise or straight",
                    (i + 1) % n
                ),
            ));
        }
        winding += cross.atan2(e1.dot(&e2));
    }
    let turns = winding / std::f64::consts::TAU;
    if (winding - std::f64::consts::TAU).abs() >= 1e-6 {
        return Err(t.error_at_key(
            "vertices",
            format!(
                "the polygon intersects itself: its edges wind {} times around its inside; \
                 a convex polygon's vertices go once around it, counter-clockwise",
                turns.round()
            ),
        ));
    }
    Ok(())
}

pub(crate) fn read_springs(
    tables: &[Table<'_>],
    bodies: &Names,
) -> Result<Vec<Spring>, SceneError> {
    check_count(tables, MAX_SPRINGS, "springs", "")?;
    let mut out = Vec::with_capacity(tables.len());
    let mut names = Names::new(("spring", "springs"));
    for (i, t) in tables.iter().enumerate() {
        let name = match t.opt_str("name")? {
            Some(n) => n.to_string(),
            None => format!("spring{i}"),
        };
        names.add(t, "name", &name)?;
        let spring = Spring {
            name,
            body_a: bodies.resolve(t, "body_a")?,
            point_a: vec2(t.vec2("point_a", Some([0.0; 2]), "m")?),
            body_b: bodies.resolve(t, "body_b")?,
            point_b: vec2(t.vec2("point_b", Some([0.0; 2]), "m")?),
            stiffness: t.f64("stiffness", Num::non_negative("N/m"))?,
            rest_length: t.f64("rest_length", Num::non_negative("m").coordinate())?,
            damping: t.f64_or("damping", 0.0, Num::non_negative("N s/m"))?,
            tension_only: t.bool_or("tension_only", false)?,
        };
        if spring.body_a == spring.body_b {
            return Err(t.error_at_key("body_b", "a spring must join two different bodies"));
        }
        t.finish()?;
        out.push(spring);
    }
    Ok(out)
}

fn vec2(v: [f64; 2]) -> Vec2 {
    Vec2::new(v[0], v[1])
}

/// Names a coordinate may not take: its recorded column would be one the recordings
/// already have (`<name>_m`: the centre of mass's `com_x_m`, `com_y_m`).
const RESERVED_COORDINATE_NAMES: [&str; 2] = ["com_x", "com_y"];

/// A joint coordinate's name labels recorded columns and fields: it must be an identifier
/// (letters, digits, `_`, not starting with a digit) and differ from every other
/// coordinate's name (`x`, `y`, `phi` included).
fn check_coordinate_name(
    t: &Table<'_>,
    name: &str,
    taken: &HashSet<String>,
    in_order: &[String],
) -> Result<(), SceneError> {
    let identifier = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !identifier {
        return Err(t.error_at_key(
            "coordinate_name",
            format!(
                "expected a name of letters, digits and '_' not starting with a digit, found '{name}'"
            ),
        ));
    }
    if RESERVED_COORDINATE_NAMES.contains(&name) {
        return Err(t.error_at_key(
            "coordinate_name",
            format!(
                "'{name}' is the name of a recorded quantity (the centre of mass's columns \
                 com_x_m, com_y_m); choose another name"
            ),
        ));
    }
    if taken.contains(name) {
        return Err(t.error_at_key(
            "coordinate_name",
            format!(
                "the coordinate '{name}' already exists (coordinates so far: {}); names must be unique",
                short_list(in_order.iter().map(String::as_str), LISTED)
            ),
        ));
    }
    Ok(())
}
