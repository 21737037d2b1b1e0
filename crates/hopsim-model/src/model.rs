//! The immutable model: bodies, shapes, terrain, springs, and the equations of motion
//! `M(q) u̇ = h(q, u, t) + W λ` (physics.md §1).

use crate::contact::{contact_geometry, ContactCandidate, ContactGeometry, ContactMaterial};
use crate::forces::separation;
use crate::{Body, Kinematics, Shape, ShapeFeature, ShapeInstance, Spring, Terrain, Vec2};
use nalgebra::{DMatrix, DVector, DVectorViewMut};

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
    #[error("body '{body}': {reason}")]
    BadJoint { body: String, reason: String },
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

/// A planar multibody model; immutable once built (evaluated at a state into a [`Kinematics`]).
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

    /// The smallest model: one floating body named `body` carrying one shape named
    /// `shape`, on `terrain`, under gravity `(0, −9.81)` m/s², without springs. Shared by
    /// the tests of the model, the stepper and the reduced models.
    pub fn single_body(
        mass: f64,
        inertia: f64,
        shape: Shape,
        terrain: Terrain,
        material: ContactMaterial,
    ) -> Result<Self, ModelError> {
        Self::new(
            vec![Body::base("body", mass, inertia)],
            vec![ShapeInstance {
                name: "shape".into(),
                body: 0,
                shape,
            }],
            terrain,
            vec![],
            Vec2::new(0.0, -9.81),
            material,
        )
    }

    /// Number of generalised coordinates: 3 for the base plus one per joint.
    pub fn dof(&self) -> usize {
        self.bodies.len() + 2
    }

    /// Total mass, kg.
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    /// Mass matrix `M = Σ_b J_bᵀ diag(m_b, m_b, I_b) J_b` (needs `kinematics.update` first).
    pub fn mass_matrix(&self, kinematics: &Kinematics, m: &mut DMatrix<f64>) {
        // M is symmetric, so its column-major storage equals the row-major one.
        self.mass_matrix_to(kinematics, m.as_mut_slice());
    }

    /// [`Model::mass_matrix`] into the first `n²` entries of `m` (row-major, symmetric).
    pub fn mass_matrix_to(&self, kinematics: &Kinematics, m: &mut [f64]) {
        let n = self.dof();
        let m = &mut m[..n * n];
        m.fill(0.0);
        // Σ over Jacobian rows r of w r rᵀ, over each row's structural non-zeros only.
        for (b, body) in self.bodies.iter().enumerate() {
            for k in 0..3 {
                let w = if k < 2 { body.mass } else { body.inertia };
                let row = kinematics.jacobian_row(3 * b + k);
                match kinematics.jacobian_pattern(3 * b + k) {
                    // A row touching one coordinate (the common case) adds to the diagonal.
                    &[i] => m[i * n + i] += w * row[i] * row[i],
                    pattern => {
                        // Upper triangle: the pattern is sorted.
                        for (a, &i) in pattern.iter().enumerate() {
                            let wi = w * row[i];
                            let m_i = &mut m[i * n..(i + 1) * n];
                            for &j in &pattern[a..] {
                                m_i[j] += wi * row[j];
                            }
                        }
                    }
                }
            }
        }
        for i in 1..n {
            for j in 0..i {
                m[i * n + j] = m[j * n + i];
            }
        }
    }

    /// Smooth forces `h(q, u)`: gravity, centripetal terms, springs and damping, plus the
    /// generalised actuator forces `applied` (needs `kinematics.update` first).
    pub fn forces(&self, kinematics: &Kinematics, applied: &DVector<f64>, h: &mut DVector<f64>) {
        h.copy_from(applied);
        self.add_forces(kinematics, Some(h.as_mut_slice()), None);
        self.add_forces(kinematics, None, Some(h.as_mut_slice()));
    }

    /// Only the dissipative part of `h`: joint and spring damping (for energy bookkeeping).
    pub fn damping_forces(&self, kinematics: &Kinematics, out: &mut DVector<f64>) {
        out.fill(0.0);
        self.add_forces(kinematics, None, Some(out.as_mut_slice()));
    }

    /// [`Model::forces`] and [`Model::damping_forces`] in one pass over slices of length
    /// `n`: `h = applied + conservative + damping`, `damping` alone.
    pub fn forces_split(
        &self,
        kinematics: &Kinematics,
        applied: &[f64],
        h: &mut [f64],
        damping: &mut [f64],
    ) {
        h.copy_from_slice(applied);
        damping.fill(0.0);
        self.add_forces(kinematics, Some(&mut *h), Some(&mut *damping));
        for (h, d) in h.iter_mut().zip(damping.iter()) {
            *h += d;
        }
    }

    /// Adds the conservative forces (gravity, centripetal terms, elastic spring forces;
    /// physics.md §1) to `conservative` and joint and spring damping to `dissipative`.
    fn add_forces(
        &self,
        kinematics: &Kinematics,
        mut conservative: Option<&mut [f64]>,
        mut dissipative: Option<&mut [f64]>,
    ) {
        for (b, body) in self.bodies.iter().enumerate() {
            if let Some(h) = conservative.as_deref_mut() {
                // M u̇ = Σ J_bᵀ m_b (g - J̇_b u): the velocity-product terms enter as the
                // centripetal "bias" accelerations of the body's centre of mass.
                let f = body.mass * (self.gravity - kinematics.bias(b));
                kinematics.add_point_force_to(b, Vec2::zeros(), f, h);
            }
            if let (Some(h), Some(joint)) = (
                dissipative.as_deref_mut(),
                body.joint.as_ref().filter(|j| j.damping != 0.0),
            ) {
                let rate =
                    kinematics.angular_velocity[b] - kinematics.angular_velocity[joint.parent];
                kinematics.add_torque_to(b, Some(joint.parent), -joint.damping * rate, h);
            }
        }
        for spring in &self.springs {
            let (ra, rb) = self.spring_offsets(kinematics, spring);
            let pa = kinematics.position[spring.body_a] + ra;
            let pb = kinematics.position[spring.body_b] + rb;
            let (dir, length) = separation(pa, pb);
            let rate = dir.dot(
                &(kinematics.point_velocity(spring.body_a, ra)
                    - kinematics.point_velocity(spring.body_b, rb)),
            );
            let (elastic, damping) = spring.tension(length, rate);
            for (out, tension) in [
                (conservative.as_deref_mut(), elastic),
                (dissipative.as_deref_mut(), damping),
            ] {
                if let Some(h) = out.filter(|_| tension != 0.0) {
                    let f = -tension * dir;
                    kinematics.add_point_force_to(spring.body_a, ra, f, h);
                    kinematics.add_point_force_to(spring.body_b, rb, -f, h);
                }
            }
        }
    }

    /// World offsets of a spring's two ends from their bodies' centres of mass.
    fn spring_offsets(&self, kinematics: &Kinematics, spring: &Spring) -> (Vec2, Vec2) {
        let offset = |b: usize, p: Vec2| {
            if p == Vec2::zeros() {
                p
            } else {
                kinematics.rotation(b).apply(p)
            }
        };
        (
            offset(spring.body_a, spring.point_a),
            offset(spring.body_b, spring.point_b),
        )
    }

    /// World end points of spring `s`.
    pub fn spring_ends(&self, kinematics: &Kinematics, s: usize) -> (Vec2, Vec2) {
        let spring = &self.springs[s];
        let (ra, rb) = self.spring_offsets(kinematics, spring);
        (
            kinematics.position[spring.body_a] + ra,
            kinematics.position[spring.body_b] + rb,
        )
    }

    /// Geometry of potential contact `i` (needs `kinematics.update` first).
    #[inline]
    pub fn contact_geometry(&self, kinematics: &Kinematics, i: usize) -> Option<ContactGeometry> {
        let c = &self.contacts[i];
        let inst = &self.shapes[c.shape];
        contact_geometry(
            &inst.shape,
            c.feature,
            kinematics.position[inst.body],
            kinematics.rotation(inst.body),
            &self.terrain.features,
            c.terrain,
        )
    }

    /// Writes the generalised normal and tangential directions `w_N = J_Pᵀ n`,
    /// `w_T = J_Pᵀ t` of contact `i` at `geometry` (physics.md §1, [2.5-2.7]).
    pub fn contact_directions(
        &self,
        kinematics: &Kinematics,
        i: usize,
        geometry: &ContactGeometry,
        w_n: DVectorViewMut<'_, f64>,
        w_t: DVectorViewMut<'_, f64>,
    ) {
        let body = self.shapes[self.contacts[i].shape].body;
        let r = geometry.point - kinematics.position[body];
        kinematics.point_force_direction(body, r, geometry.normal, w_n);
        kinematics.point_force_direction(body, r, geometry.tangent(), w_t);
    }

    /// [`Model::contact_directions`] into slices of length `n`.
    #[inline]
    pub fn contact_directions_to(
        &self,
        kinematics: &Kinematics,
        i: usize,
        geometry: &ContactGeometry,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) {
        let body = self.shapes[self.contacts[i].shape].body;
        let r = geometry.point - kinematics.position[body];
        kinematics.point_force_direction_to(body, r, geometry.normal, w_n);
        kinematics.point_force_direction_to(body, r, geometry.tangent(), w_t);
    }

    /// Kinetic energy `½ Σ (m_b |v_b|² + I_b ω_b²)` = `½ uᵀ M u`.
    pub fn kinetic_energy(&self, kinematics: &Kinematics) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(b, body)| {
                0.5 * (body.mass * kinematics.velocity[b].norm_squared()
                    + body.inertia * kinematics.angular_velocity[b].powi(2))
            })
            .sum()
    }

    /// Gravitational potential energy `-Σ m_b g · p_b` (zero at the origin).
    pub fn potential_energy(&self, kinematics: &Kinematics) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(b, body)| -body.mass * self.gravity.dot(&kinematics.position[b]))
            .sum()
    }

    /// Energy stored in the springs.
    pub fn spring_energy(&self, kinematics: &Kinematics) -> f64 {
        (0..self.springs.len())
            .map(|s| {
                let (a, b) = self.spring_ends(kinematics, s);
                self.springs[s].energy((a - b).norm())
            })
            .sum()
    }

    /// Centre of mass of the whole robot, m.
    pub fn center_of_mass(&self, kinematics: &Kinematics) -> Vec2 {
        let weighted: Vec2 = self
            .bodies
            .iter()
            .enumerate()
            .map(|(b, body)| body.mass * kinematics.position[b])
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
        let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
        let reason = if !finite(joint.pivot_in_parent) || !finite(joint.com_in_child) {
            Some("the joint's pivot and centre of mass offsets must be finite")
        } else if !(joint.damping >= 0.0 && joint.damping.is_finite()) {
            Some("joint damping must be finite and non-negative")
        } else {
            None
        };
        if let Some(reason) = reason {
            return Err(ModelError::BadJoint {
                body: body.name.clone(),
                reason: reason.into(),
            });
        }
    }
    Ok(())
}

fn check_shapes(shapes: &[ShapeInstance], count: usize) -> Result<(), ModelError> {
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
        let positive = |x: f64| x > 0.0 && x.is_finite();
        let finite = |v: &Vec2| v.x.is_finite() && v.y.is_finite();
        match &s.shape {
            Shape::Circle { center, .. }
            | Shape::Arc { center, .. }
            | Shape::Ellipse { center, .. }
                if !finite(center) =>
            {
                return bad("the centre must be finite")
            }
            Shape::Point { position } if !finite(position) => {
                return bad("the point must be finite")
            }
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } if !positive(*radius) => {
                return bad("radius must be positive and finite")
            }
            Shape::Arc { start, end, .. }
                if !end.is_finite()
                    || end.partial_cmp(start) != Some(std::cmp::Ordering::Greater) =>
            {
                return bad("arc end angle must be greater than its start angle")
            }
            Shape::Ellipse { semi_x, semi_y, .. } if !positive(*semi_x) || !positive(*semi_y) => {
                return bad("semi-axes must be positive and finite")
            }
            Shape::Polygon { vertices } if vertices.len() < 3 => {
                return bad("a polygon needs at least three vertices")
            }
            Shape::Polygon { vertices } if !is_convex_counter_clockwise(vertices) => return bad(
                "polygon vertices must be finite and run counter-clockwise around a convex polygon",
            ),
            _ => {}
        }
    }
    Ok(())
}

/// Whether every turn of the closed polyline is strictly to the left (convex, CCW) and it
/// winds once (the turning angles sum to 2π).
fn is_convex_counter_clockwise(vertices: &[Vec2]) -> bool {
    let count = vertices.len();
    let edge = |i: usize| vertices[(i + 1) % count] - vertices[i];
    let mut winding = 0.0;
    for i in 0..count {
        let (a, b) = (edge(i), edge((i + 1) % count));
        let cross = a.x * b.y - a.y * b.x;
        if cross <= 0.0 || !cross.is_finite() {
            return false;
        }
        winding += cross.atan2(a.dot(&b));
    }
    (winding - std::f64::consts::TAU).abs() < 1e-6
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
        let ok = |x: f64| x >= 0.0 && x.is_finite();
        let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
        if !ok(s.stiffness) || !ok(s.rest_length) || !ok(s.damping) {
            return Err(ModelError::BadSpring {
                spring: s.name.clone(),
                reason: "stiffness, rest length and damping must be finite and non-negative".into(),
            });
        }
        if !finite(s.point_a) || !finite(s.point_b) {
            return Err(ModelError::BadSpring {
                spring: s.name.clone(),
                reason: "the end points must be finite".into(),
            });
        }
    }
    Ok(())
}

/// Pairs every shape feature with every terrain feature it can touch: smooth boundaries
/// (circle, arc, ellipse) with lines and corners, vertices (polygon corners, arc ends,
/// points) with lines, a polygon's edges with corners.
fn candidates(
    shapes: &[ShapeInstance],
    terrain: &Terrain,
    material: ContactMaterial,
) -> Vec<ContactCandidate> {
    use crate::{Shape, TerrainFeature};
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
            if inst.shape.is_smooth() {
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
            } else if matches!(inst.shape, Shape::Polygon { .. }) {
                push(ShapeFeature::Edges, String::new());
            }
        }
    }
    out
}
