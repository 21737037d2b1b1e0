//! The immutable model: bodies, shapes, terrain, springs, and the equations of motion
//! `M(q) u̇ = h(q, u, t) + W λ` (physics.md §1).

use crate::contact::{contact_geometry, ContactCandidate, ContactGeometry, ContactMaterial};
use crate::forces::separation;
use crate::{rotate, Body, ShapeFeature, ShapeInstance, Spring, Terrain, Vec2, Workspace};
use nalgebra::{DMatrix, DVector, DVectorViewMut};

/// The two parts of the smooth forces, kept apart for the energy balance.
#[derive(Clone, Copy, PartialEq, Eq)]
enum ForcePart {
    /// Gravity, centripetal terms and elastic spring forces.
    Conservative,
    /// Joint and spring damping.
    Dissipative,
}

/// What makes a model impossible to build.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ModelError {
    #[error("a model needs at least one body")]
    NoBodies,
    #[error("body '{body}': {what} must be positive and finite, got {value}")]
    NonPositive {
        body: String,
        what: &'static str,
        value: f64,
    },
    #[error("body '{body}': the floating base (first body) cannot have a joint")]
    BaseWithJoint { body: String },
    #[error("body '{body}': every body after the first needs a joint")]
    MissingJoint { body: String },
    #[error("body '{body}': joint parent {parent} must be an earlier body")]
    BadParent { body: String, parent: usize },
    #[error("{owner} '{name}': refers to body {body}, but the model has {count} bodies")]
    UnknownBody {
        owner: &'static str,
        name: String,
        body: usize,
        count: usize,
    },
    #[error("shape '{shape}': {reason}")]
    BadShape { shape: String, reason: String },
    #[error("spring '{spring}': {reason}")]
    BadSpring { spring: String, reason: String },
}

/// A planar multibody model; immutable once built (see [`Workspace`] for the buffers).
#[derive(Clone, Debug)]
pub struct Model {
    /// Body 0 is the floating base with coordinates `(x, y, φ)`; body `b ≥ 1` adds
    /// coordinate `2 + b`.
    pub bodies: Vec<Body>,
    /// Contact shapes on the bodies.
    pub shapes: Vec<ShapeInstance>,
    /// The environment.
    pub terrain: Terrain,
    /// Every potential contact (shape feature × terrain feature).
    pub contacts: Vec<ContactCandidate>,
    /// Springs between points on bodies.
    pub springs: Vec<Spring>,
    /// Gravitational acceleration, m/s² (default `(0, -9.81)`).
    pub gravity: Vec2,
}

impl Model {
    /// Builds and checks a model; every shape feature is paired with every terrain
    /// feature it can touch, all with `material`.
    pub fn new(
        bodies: Vec<Body>,
        shapes: Vec<ShapeInstance>,
        terrain: Terrain,
        springs: Vec<Spring>,
        gravity: Vec2,
        material: ContactMaterial,
    ) -> Result<Self, ModelError> {
        check_bodies(&bodies)?;
        check_shapes(&shapes, bodies.len())?;
        check_springs(&springs, bodies.len())?;
        let contacts = candidates(&shapes, &terrain, material);
        Ok(Self {
            bodies,
            shapes,
            terrain,
            contacts,
            springs,
            gravity,
        })
    }

    /// Number of generalised coordinates: 3 for the base plus one per joint.
    pub fn dof(&self) -> usize {
        self.bodies.len() + 2
    }

    /// Total mass, kg.
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    /// Mass matrix `M = Σ_b J_bᵀ diag(m_b, m_b, I_b) J_b` (needs `ws.update` first).
    pub fn mass_matrix(&self, ws: &Workspace, m: &mut DMatrix<f64>) {
        let n = self.dof();
        m.fill(0.0);
        for (b, body) in self.bodies.iter().enumerate() {
            let weights = [body.mass, body.mass, body.inertia];
            for (k, w) in weights.iter().enumerate() {
                let row = 3 * b + k;
                for i in 0..n {
                    let ji = ws.jacobian[(row, i)];
                    if ji == 0.0 {
                        continue;
                    }
                    for j in 0..n {
                        m[(i, j)] += w * ji * ws.jacobian[(row, j)];
                    }
                }
            }
        }
    }

    /// Smooth forces `h(q, u)`: gravity, centripetal terms, springs and damping, plus the
    /// generalised actuator forces `applied` (needs `ws.update` first).
    pub fn forces(&self, ws: &Workspace, applied: &DVector<f64>, h: &mut DVector<f64>) {
        h.copy_from(applied);
        self.add_forces(ws, h, ForcePart::Conservative);
        self.add_forces(ws, h, ForcePart::Dissipative);
    }

    /// Only the dissipative part of `h`: joint and spring damping (for energy bookkeeping).
    pub fn damping_forces(&self, ws: &Workspace, out: &mut DVector<f64>) {
        out.fill(0.0);
        self.add_forces(ws, out, ForcePart::Dissipative);
    }

    fn add_forces(&self, ws: &Workspace, h: &mut DVector<f64>, part: ForcePart) {
        let conservative = part == ForcePart::Conservative;
        for (b, body) in self.bodies.iter().enumerate() {
            if conservative {
                let f = body.mass * (self.gravity - ws.bias[b]);
                ws.add_point_force(b, Vec2::zeros(), f, h);
            } else if let Some(joint) = body.joint.as_ref().filter(|j| j.damping != 0.0) {
                let rate = ws.angular_velocity[b] - ws.angular_velocity[joint.parent];
                ws.add_torque(b, Some(joint.parent), -joint.damping * rate, h);
            }
        }
        for spring in &self.springs {
            let (ra, rb) = self.spring_offsets(ws, spring);
            let pa = ws.position[spring.body_a] + ra;
            let pb = ws.position[spring.body_b] + rb;
            let (dir, length) = separation(pa, pb);
            let rate = dir.dot(
                &(ws.point_velocity(spring.body_a, ra) - ws.point_velocity(spring.body_b, rb)),
            );
            let (elastic, damping) = spring.tension(length, rate);
            let f = -(if conservative { elastic } else { damping }) * dir;
            ws.add_point_force(spring.body_a, ra, f, h);
            ws.add_point_force(spring.body_b, rb, -f, h);
        }
    }

    /// World offsets of a spring's two ends from their bodies' centres of mass.
    fn spring_offsets(&self, ws: &Workspace, spring: &Spring) -> (Vec2, Vec2) {
        (
            rotate(ws.angle[spring.body_a], spring.point_a),
            rotate(ws.angle[spring.body_b], spring.point_b),
        )
    }

    /// World end points of spring `s`.
    pub fn spring_ends(&self, ws: &Workspace, s: usize) -> (Vec2, Vec2) {
        let spring = &self.springs[s];
        let (ra, rb) = self.spring_offsets(ws, spring);
        (
            ws.position[spring.body_a] + ra,
            ws.position[spring.body_b] + rb,
        )
    }

    /// Geometry of potential contact `i` (needs `ws.update` first).
    pub fn contact_geometry(&self, ws: &Workspace, i: usize) -> Option<ContactGeometry> {
        let c = &self.contacts[i];
        let inst = &self.shapes[c.shape];
        contact_geometry(
            &inst.shape,
            c.feature,
            ws.position[inst.body],
            ws.angle[inst.body],
            &self.terrain.features[c.terrain],
        )
    }

    /// Writes the generalised normal and tangential directions `w_N = J_Pᵀ n`,
    /// `w_T = J_Pᵀ t` of contact `i` at `geometry` (physics.md §1, [2.5-2.7]).
    pub fn contact_directions(
        &self,
        ws: &Workspace,
        i: usize,
        geometry: &ContactGeometry,
        w_n: DVectorViewMut<'_, f64>,
        w_t: DVectorViewMut<'_, f64>,
    ) {
        let body = self.shapes[self.contacts[i].shape].body;
        let r = geometry.point - ws.position[body];
        ws.point_force_direction(body, r, geometry.normal, w_n);
        ws.point_force_direction(body, r, geometry.tangent(), w_t);
    }

    /// Kinetic energy `½ Σ (m_b |v_b|² + I_b ω_b²)` = `½ uᵀ M u`.
    pub fn kinetic_energy(&self, ws: &Workspace) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(b, body)| {
                0.5 * (body.mass * ws.velocity[b].norm_squared()
                    + body.inertia * ws.angular_velocity[b].powi(2))
            })
            .sum()
    }

    /// Gravitational potential energy `-Σ m_b g · p_b` (zero at the origin).
    pub fn potential_energy(&self, ws: &Workspace) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(b, body)| -body.mass * self.gravity.dot(&ws.position[b]))
            .sum()
    }

    /// Energy stored in the springs.
    pub fn spring_energy(&self, ws: &Workspace) -> f64 {
        (0..self.springs.len())
            .map(|s| {
                let (a, b) = self.spring_ends(ws, s);
                self.springs[s].energy((a - b).norm())
            })
            .sum()
    }

    /// Centre of mass of the whole robot, m.
    pub fn center_of_mass(&self, ws: &Workspace) -> Vec2 {
        let weighted: Vec2 = self
            .bodies
            .iter()
            .enumerate()
            .map(|(b, body)| body.mass * ws.position[b])
            .sum();
        weighted / self.total_mass()
    }
}

fn positive(body: &Body, what: &'static str, value: f64) -> Result<(), ModelError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(ModelError::NonPositive {
            body: body.name.clone(),
            what,
            value,
        })
    }
}

fn check_bodies(bodies: &[Body]) -> Result<(), ModelError> {
    let base = bodies.first().ok_or(ModelError::NoBodies)?;
    if base.joint.is_some() {
        return Err(ModelError::BaseWithJoint {
            body: base.name.clone(),
        });
    }
    for (b, body) in bodies.iter().enumerate() {
        positive(body, "mass", body.mass)?;
        positive(body, "inertia", body.inertia)?;
        if b == 0 {
            continue;
        }
        let joint = body
            .joint
            .as_ref()
            .ok_or_else(|| ModelError::MissingJoint {
                body: body.name.clone(),
            })?;
        if joint.parent >= b {
            return Err(ModelError::BadParent {
                body: body.name.clone(),
                parent: joint.parent,
            });
        }
    }
    Ok(())
}

fn check_shapes(shapes: &[ShapeInstance], count: usize) -> Result<(), ModelError> {
    use crate::Shape;
    for s in shapes {
        if s.body >= count {
            return Err(ModelError::UnknownBody {
                owner: "shape",
                name: s.name.clone(),
                body: s.body,
                count,
            });
        }
        let bad = |reason: &str| {
            Err(ModelError::BadShape {
                shape: s.name.clone(),
                reason: reason.to_string(),
            })
        };
        match &s.shape {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } if *radius <= 0.0 => {
                return bad("radius must be positive")
            }
            Shape::Arc { start, end, .. }
                if end.partial_cmp(start) != Some(std::cmp::Ordering::Greater) =>
            {
                return bad("arc end angle must be greater than its start angle")
            }
            Shape::Ellipse { semi_x, semi_y, .. } if *semi_x <= 0.0 || *semi_y <= 0.0 => {
                return bad("semi-axes must be positive")
            }
            Shape::Polygon { vertices } if vertices.len() < 3 => {
                return bad("a polygon needs at least three vertices")
            }
            _ => {}
        }
    }
    Ok(())
}

fn check_springs(springs: &[Spring], count: usize) -> Result<(), ModelError> {
    for s in springs {
        for body in [s.body_a, s.body_b] {
            if body >= count {
                return Err(ModelError::UnknownBody {
                    owner: "spring",
                    name: s.name.clone(),
                    body,
                    count,
                });
            }
        }
        if s.stiffness < 0.0 || s.rest_length < 0.0 || s.damping < 0.0 {
            return Err(ModelError::BadSpring {
                spring: s.name.clone(),
                reason: "stiffness, rest length and damping must be non-negative".into(),
            });
        }
    }
    Ok(())
}

/// Pairs every shape feature with every terrain feature it can touch.
fn candidates(
    shapes: &[ShapeInstance],
    terrain: &Terrain,
    material: ContactMaterial,
) -> Vec<ContactCandidate> {
    use crate::TerrainFeature;
    let mut out = Vec::new();
    for (s, inst) in shapes.iter().enumerate() {
        for (t, feature) in terrain.features.iter().enumerate() {
            let is_line = matches!(feature, TerrainFeature::Line { .. });
            let mut push = |feature: ShapeFeature, label: String| {
                out.push(ContactCandidate {
                    name: format!("{}{label}/terrain{t}", inst.name),
                    shape: s,
                    feature,
                    terrain: t,
                    material,
                })
            };
            let smooth_touches = match inst.shape {
                crate::Shape::Ellipse { .. } => is_line,
                _ => inst.shape.is_smooth(),
            };
            if smooth_touches {
                push(ShapeFeature::Smooth, String::new());
            }
            if is_line {
                let count = inst.shape.vertex_count();
                for k in 0..count {
                    let label = if count > 1 {
                        format!("#{k}")
                    } else {
                        String::new()
                    };
                    push(ShapeFeature::Vertex(k), label);
                }
            }
        }
    }
    out
}
