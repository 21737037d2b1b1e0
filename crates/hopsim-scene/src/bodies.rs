//! `[[bodies]]`, `[[shapes]]` and `[[springs]]`: the multibody model (physics.md §1).

use crate::environment::read_material;
use crate::error::{suggestion, SceneError};
use crate::reader::{Num, Table};
use hopsim_model::{
    Body, ContactMaterial, Joint, JointCoordinate, Shape, ShapeInstance, Spring, Vec2,
};

/// Names of things a scene refers to (bodies, shapes), with their indices.
pub(crate) struct Names {
    /// What the names are, for messages: singular and plural ("body", "bodies").
    what: (&'static str, &'static str),
    names: Vec<String>,
}

impl Names {
    pub fn new(what: (&'static str, &'static str)) -> Self {
        Self {
            what,
            names: Vec::new(),
        }
    }

    /// Registers `name` read from `key` of `table`; duplicates are errors.
    pub fn add(&mut self, table: &Table<'_>, key: &str, name: &str) -> Result<usize, SceneError> {
        if self.names.iter().any(|n| n == name) {
            return Err(table.error_at_key(
                key,
                format!(
                    "a {} named '{name}' already exists; names must be unique",
                    self.what.0
                ),
            ));
        }
        self.names.push(name.to_string());
        Ok(self.names.len() - 1)
    }

    /// Index of the thing named by the string at `key` of `table`.
    pub fn resolve(&self, table: &Table<'_>, key: &'static str) -> Result<usize, SceneError> {
        let name = table.str(key)?;
        self.index(table, key, name)
    }

    /// Index of `name` (read from `key` of `table`).
    pub fn index(&self, table: &Table<'_>, key: &str, name: &str) -> Result<usize, SceneError> {
        self.names.iter().position(|n| n == name).ok_or_else(|| {
            let hint = suggestion(name, self.names.iter().map(String::as_str));
            let known = if hint.is_empty() {
                format!("; the {} are: {}", self.what.1, self.names.join(", "))
            } else {
                hint
            };
            table.error_at_key(
                key,
                format!("there is no {} named '{name}'{known}", self.what.0),
            )
        })
    }

    pub fn get(&self, i: usize) -> &str {
        &self.names[i]
    }
}

/// The bodies and the names of the generalised coordinates (`x, y, phi`, then one per
/// child body).
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
    let mut bodies = Vec::with_capacity(tables.len());
    let mut coordinates: Vec<String> = ["x", "y", "phi"].map(String::from).to_vec();
    for (b, t) in tables.iter().enumerate() {
        let name = t.str("name")?;
        names.add(t, "name", name)?;
        let mass = t.f64("mass", Num::positive("kg"))?;
        let inertia = t.f64("inertia", Num::positive("kg m²"))?;
        let parent = t.opt_str("parent")?;
        let joint = match (b, parent) {
            (0, None) => None,
            (0, Some(_)) => {
                return Err(t.error_at_key(
                    "parent",
                    "the first body is the floating base (x, y, phi) and cannot have a parent",
                ))
            }
            (_, None) => {
                return Err(t.error_at_key(
                    "parent",
                    format!(
                        "missing; every body after the first hangs on a revolute joint on a \
                         parent body (one of: {})",
                        (0..b).map(|i| names.get(i)).collect::<Vec<_>>().join(", ")
                    ),
                ))
            }
            (_, Some(p)) => {
                let parent = names.index(t, "parent", p)?;
                if parent == b {
                    return Err(t.error_at_key("parent", "a body cannot be its own parent"));
                }
                let coordinate =
                    match t.choice("coordinate", &["relative", "absolute"], Some("relative"))? {
                        "absolute" => JointCoordinate::Absolute,
                        _ => JointCoordinate::Relative,
                    };
                let coordinate_name = match t.opt_str("coordinate_name")? {
                    Some(c) => c.to_string(),
                    None => format!("theta_{name}"),
                };
                check_coordinate_name(t, &coordinate_name, &coordinates)?;
                coordinates.push(coordinate_name);
                Some(Joint {
                    parent,
                    pivot_in_parent: vec2(t.vec2("pivot", Some([0.0; 2]), "m")?),
                    com_in_child: vec2(t.vec2("com", Some([0.0; 2]), "m")?),
                    coordinate,
                    damping: t.f64_or("damping", 0.0, Num::non_negative("N m s/rad"))?,
                })
            }
        };
        if joint.is_none() && t.opt_str("coordinate_name")?.is_some() {
            return Err(t.error_at_key(
                "coordinate_name",
                "the floating base's coordinates are always x, y, phi",
            ));
        }
        t.finish()?;
        bodies.push(Body {
            name: name.to_string(),
            mass,
            inertia,
            joint,
        });
    }
    Ok((bodies, coordinates))
}

/// A shape as the scene describes it, with its contact material and switchability.
pub(crate) struct ShapeSpec {
    pub instance: ShapeInstance,
    pub material: ContactMaterial,
    /// Switched on and off by the controller (a cane); starts switched off.
    pub switchable: bool,
}

pub(crate) fn read_shapes(
    tables: &[Table<'_>],
    bodies: &Names,
    shapes: &mut Names,
    base_material: ContactMaterial,
) -> Result<Vec<ShapeSpec>, SceneError> {
    let mut out = Vec::with_capacity(tables.len());
    for t in tables {
        let body = bodies.resolve(t, "body")?;
        let kind = t.choice(
            "type",
            &["circle", "arc", "ellipse", "point", "polygon", "box"],
            None,
        )?;
        let name = match t.opt_str("name")? {
            Some(n) => n.to_string(),
            None => format!("{}_{kind}", bodies.get(body)),
        };
        shapes.add(t, "name", &name)?;
        let shape = read_geometry(t, kind)?;
        let material = read_material(t, base_material)?;
        let switchable = t.bool_or("switchable", false)?;
        t.finish()?;
        out.push(ShapeSpec {
            instance: ShapeInstance { name, body, shape },
            material,
            switchable,
        });
    }
    Ok(out)
}

fn read_geometry(t: &Table<'_>, kind: &str) -> Result<Shape, SceneError> {
    let center = || Ok::<_, SceneError>(vec2(t.vec2("center", Some([0.0; 2]), "m")?));
    Ok(match kind {
        "circle" => Shape::Circle {
            center: center()?,
            radius: t.f64("radius", Num::positive("m"))?,
        },
        "arc" => {
            let center = center()?;
            let radius = t.f64("radius", Num::positive("m"))?;
            let start = t.f64("start", Num::any("rad"))?;
            let end = t.f64("end", Num::any("rad"))?;
            if !(end > start && end - start <= std::f64::consts::TAU) {
                return Err(t.error_at_key(
                    "end",
                    format!(
                        "the arc must run counter-clockwise from start to end with \
                         0 < end - start <= 2π; found start = {start}, end = {end}"
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
            semi_x: t.f64("semi_x", Num::positive("m"))?,
            semi_y: t.f64("semi_y", Num::positive("m"))?,
        },
        "point" => Shape::Point {
            position: vec2(t.vec2("position", None, "m")?),
        },
        "box" => {
            let c = center()?;
            let (w, h) = (
                t.f64("half_width", Num::positive("m"))?,
                t.f64("half_height", Num::positive("m"))?,
            );
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

/// A polygon must have at least three vertices, counter-clockwise, strictly convex.
fn check_convex_ccw(t: &Table<'_>, v: &[Vec2]) -> Result<(), SceneError> {
    if v.len() < 3 {
        return Err(t.error_at_key(
            "vertices",
            format!("a polygon needs at least 3 vertices, found {}", v.len()),
        ));
    }
    let n = v.len();
    for i in 0..n {
        let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
        let e1 = b - a;
        let e2 = c - b;
        if e1.x * e2.y - e1.y * e2.x <= 0.0 {
            return Err(t.error_at_key(
                "vertices",
                format!(
                    "the polygon must be convex with vertices counter-clockwise; the turn at \
                     vertex {} is clockwise or straight",
                    (i + 1) % n
                ),
            ));
        }
    }
    Ok(())
}

pub(crate) fn read_springs(
    tables: &[Table<'_>],
    bodies: &Names,
) -> Result<Vec<Spring>, SceneError> {
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
            rest_length: t.f64("rest_length", Num::non_negative("m"))?,
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

/// A joint coordinate's name labels recorded columns and fields: it must be an identifier
/// (letters, digits, `_`, not starting with a digit) and differ from every other
/// coordinate's name (`x`, `y`, `phi` included).
fn check_coordinate_name(t: &Table<'_>, name: &str, taken: &[String]) -> Result<(), SceneError> {
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
    if taken.iter().any(|c| c == name) {
        return Err(t.error_at_key(
            "coordinate_name",
            format!(
                "the coordinate '{name}' already exists (coordinates so far: {}); names must be unique",
                taken.join(", ")
            ),
        ));
    }
    Ok(())
}
