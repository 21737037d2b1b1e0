//! The immutable model: bodies, shapes, terrain, springs, and the equations of motion
//! `M(q) u̇ = h(q, u, t) + W λ` (docs/physics.md §1).

use crate::contact::{contact_geometry, ContactCandidate, ContactGeometry, ContactMaterial};
use crate::forces::separation;
use crate::loops::{check_loop, LoopJoint};
use crate::pairs::{
    pair_candidates, pair_directions_to, pair_geometry, PairCandidate, PairGeometry, Pose,
};
use crate::structure::Structure;
use crate::{
    Actuator, Body, Joint, JointCoordinate, JointKind, Kinematics, Shape, ShapeFeature,
    ShapeInstance, Spring, Terrain, Vec2,
};
use nalgebra::{DMatrix, DVector, DVectorViewMut};

/// What makes a model impossible to build.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ModelError {
    #[error("a model needs at least one body")]
    NoBodies,
    #[error("a model needs at least one body that is not fixed (no generalised coordinate)")]
    NoCoordinates,
    #[error("body '{body}': {what} must be positive and finite, got {value}")]
    NonPositive {
        body: String,
        what: &'static str,
        value: f64,
    },
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
    #[error("loop '{name}': {reason}")]
    BadLoop { name: String, reason: String },
    #[error("actuator '{actuator}': {reason}")]
    BadActuator { actuator: String, reason: String },
    #[error("contact between shapes '{first}' and '{second}': {reason}")]
    BadPair {
        first: String,
        second: String,
        reason: String,
    },
}

/// One end stop of a joint (docs/physics.md §7): the unilateral constraint
/// `g = s − lower ≥ 0` or `g = upper − s ≥ 0` on the joint position `s` of `body`.
#[derive(Clone, Debug, PartialEq)]
pub struct LimitCandidate {
    /// Name in records: `<body>/lower` or `<body>/upper`.
    pub name: String,
    /// The body whose joint the stop limits.
    pub body: usize,
    /// `true` for the upper stop (`g = upper − s`), `false` for the lower (`g = s − lower`).
    pub upper: bool,
    /// The stop's position, rad or m.
    pub bound: f64,
    /// Its Newton restitution `ε`.
    pub restitution: f64,
}

impl LimitCandidate {
    /// The gap `g` at joint position `s`: `s − lower` or `upper − s` (≤ 0: closed).
    #[inline]
    pub fn gap(&self, s: f64) -> f64 {
        if self.upper {
            self.bound - s
        } else {
            s - self.bound
        }
    }

    /// `∂g/∂s`: `+1` for a lower stop, `−1` for an upper one.
    #[inline]
    pub fn sign(&self) -> f64 {
        if self.upper {
            -1.0
        } else {
            1.0
        }
    }
}

/// A planar multibody model, built once by a [`ModelBuilder`] (or [`Model::new`]) and
/// immutable afterwards (evaluated at a state into a [`Kinematics`]).
///
/// The bodies are listed parents before children. A body without a joint is a floating
/// base with coordinates `(x, y, φ)`; a body on a joint adds one coordinate (none when
/// fixed). Coordinates are numbered in body order, so one floating tree has
/// `q = (x, y, φ, q_1, q_2, …)` (docs/physics.md §1, §7). Everything the structure decides
/// once (the Jacobian's sparsity and constancy, the bodies that need a rotation, contact
/// shortcuts) is computed when it is built.
#[derive(Clone, Debug)]
pub struct Model {
    bodies: Vec<Body>,
    shapes: Vec<ShapeInstance>,
    terrain: Terrain,
    contacts: Vec<ContactCandidate>,
    springs: Vec<Spring>,
    gravity: Vec2,
    limits: Vec<LimitCandidate>,
    pairs: Vec<PairCandidate>,
    /// Loop joints (docs/physics.md §8) and their number of rows.
    pub(crate) loops: Vec<LoopJoint>,
    pub(crate) loop_rows: usize,
    /// The actuators (`crate::actuators`), in control order.
    pub(crate) actuators: Vec<Actuator>,
    /// First generalised coordinate of each body (for a fixed body: the next body's).
    pub(crate) first_coordinate: Vec<usize>,
    /// Number of generalised coordinates.
    dof: usize,
    /// The per-model constants (`crate::structure`).
    pub(crate) structure: Structure,
}

/// Builds a [`Model`]: checks the bodies, shapes and springs, pairs every shape feature
/// with every terrain feature it can touch, takes the contacts between bodies and the
/// shapes' own materials, and computes the model's constants in [`ModelBuilder::build`].
#[derive(Clone, Debug)]
pub struct ModelBuilder {
    model: Model,
}

impl ModelBuilder {
    /// Checks the parts and makes the terrain contacts, all with `material`.
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
        let contacts = candidates(&bodies, &shapes, &terrain, material);
        let mut first_coordinate = Vec::with_capacity(bodies.len());
        let mut dof = 0;
        for body in &bodies {
            first_coordinate.push(dof);
            dof += body.coordinate_count();
        }
        let limits = limit_candidates(&bodies);
        Ok(Self {
            model: Model {
                bodies,
                shapes,
                terrain,
                contacts,
                springs,
                gravity,
                limits,
                pairs: Vec::new(),
                loops: Vec::new(),
                loop_rows: 0,
                actuators: Vec::new(),
                first_coordinate,
                dof,
                structure: Structure::empty(),
            },
        })
    }

    /// The model so far (its constants not yet computed: evaluate it only once built).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Gives shape `shape`'s terrain contacts `material`.
    pub fn set_shape_material(&mut self, shape: usize, material: ContactMaterial) {
        for c in self.model.contacts.iter_mut().filter(|c| c.shape == shape) {
            c.material = material;
        }
    }

    /// Adds the potential contacts between shape `a` and shape `b` (indices into the
    /// shapes, on two different bodies that are not both fixed) with `material`
    /// (docs/physics.md §7); returns how many candidates the pair makes (see
    /// [`crate::pair_features`]). Joined bodies are allowed: filtering is the caller's.
    pub fn add_body_contacts(
        &mut self,
        a: usize,
        b: usize,
        material: ContactMaterial,
    ) -> Result<usize, ModelError> {
        let model = &mut self.model;
        let count = model.shapes.len();
        for s in [a, b] {
            if s >= count {
                return Err(ModelError::BadPair {
                    first: a.to_string(),
                    second: b.to_string(),
                    reason: format!("shape {s} does not exist (the model has {count} shapes)"),
                });
            }
        }
        let bad = |reason: &str| ModelError::BadPair {
            first: model.shapes[a].name.clone(),
            second: model.shapes[b].name.clone(),
            reason: reason.to_string(),
        };
        let (body_a, body_b) = (model.shapes[a].body, model.shapes[b].body);
        if body_a == body_b {
            return Err(bad("both shapes are on the same body"));
        }
        if model.bodies[body_a].is_fixed() && model.bodies[body_b].is_fixed() {
            return Err(bad("both shapes are on fixed bodies, which never move"));
        }
        if !material.friction.is_finite()
            || material.friction < 0.0
            || !(0.0..=1.0).contains(&material.restitution_normal)
            || !(-1.0..=1.0).contains(&material.restitution_tangent)
        {
            return Err(bad(
                "friction must be finite and >= 0, restitution in [0, 1], tangential restitution in [-1, 1]",
            ));
        }
        let new = pair_candidates(&model.shapes, a, b, material).map_err(bad)?;
        let added = new.len();
        model.pairs.extend(new);
        Ok(added)
    }

    /// Adds a loop joint (docs/physics.md §8), checked: its bodies exist, differ and are
    /// not both without coordinates; a distance is positive, a slot's axis non-zero.
    pub fn add_loop(&mut self, joint: LoopJoint) -> Result<(), ModelError> {
        let model = &mut self.model;
        let bodies = &model.bodies;
        let joint = check_loop(joint, bodies.len(), |b| bodies[b].is_fixed())?;
        model.loop_rows += joint.kind.rows();
        model.loops.push(joint);
        Ok(())
    }

    /// Adds an actuator (docs/physics.md §7.4), checked against the model: a body with a
    /// joint, a name of its own, finite gains, a non-zero gear, ordered ranges. Returns its
    /// index, the index of its control.
    pub fn add_actuator(&mut self, actuator: Actuator) -> Result<usize, ModelError> {
        crate::actuators::check_actuator(&actuator, &self.model)?;
        self.model.actuators.push(actuator);
        Ok(self.model.actuators.len() - 1)
    }

    /// The model, with its constants (docs/physics.md §7: the Jacobian's sparsity and
    /// whether it is constant, and then the generalised weight; the contact shortcuts).
    pub fn build(self) -> Model {
        let mut model = self.model;
        model.structure = Structure::of(&model);
        if model.structure.jacobian_constant {
            // A constant Jacobian, evaluated anywhere: `Σ_b J_bᵀ m_b g`.
            let n = model.dof;
            let mut kinematics = Kinematics::new(&model);
            kinematics.update_slices(&model, &vec![0.0; n], &vec![0.0; n]);
            let mut weight = vec![0.0; n];
            for (b, body) in model.bodies.iter().enumerate() {
                kinematics.add_point_force_to(
                    b,
                    Vec2::zeros(),
                    body.mass * model.gravity,
                    &mut weight,
                );
            }
            model.structure.constant_weight = Some(weight);
        }
        model
    }
}

impl Model {
    /// Builds and checks a model without contacts between bodies; every shape feature is
    /// paired with every terrain feature it can touch, all with `material` (see
    /// [`ModelBuilder`] for more).
    pub fn new(
        bodies: Vec<Body>,
        shapes: Vec<ShapeInstance>,
        terrain: Terrain,
        springs: Vec<Spring>,
        gravity: Vec2,
        material: ContactMaterial,
    ) -> Result<Self, ModelError> {
        Ok(ModelBuilder::new(bodies, shapes, terrain, springs, gravity, material)?.build())
    }

    /// The same model under gravity `gravity`, m/s² (a model is immutable: this builds
    /// another, with its constants).
    pub fn with_gravity(&self, gravity: Vec2) -> Model {
        let mut model = self.clone();
        model.gravity = gravity;
        ModelBuilder { model }.build()
    }

    /// The bodies, parents before children.
    #[inline]
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The contact shapes on the bodies.
    #[inline]
    pub fn shapes(&self) -> &[ShapeInstance] {
        &self.shapes
    }

    /// The environment.
    #[inline]
    pub fn terrain(&self) -> &Terrain {
        &self.terrain
    }

    /// Every potential contact with the terrain (shape feature × terrain feature).
    #[inline]
    pub fn contacts(&self) -> &[ContactCandidate] {
        &self.contacts
    }

    /// Springs between points on bodies.
    #[inline]
    pub fn springs(&self) -> &[Spring] {
        &self.springs
    }

    /// Gravitational acceleration, m/s² (default `(0, -9.81)`).
    #[inline]
    pub fn gravity(&self) -> Vec2 {
        self.gravity
    }

    /// Every finite joint stop (docs/physics.md §7), two per joint with both limits.
    #[inline]
    pub fn limits(&self) -> &[LimitCandidate] {
        &self.limits
    }

    /// Every potential contact between shapes of two bodies (docs/physics.md §7). In the
    /// stepper's numbering they follow the terrain contacts: body–body contact `p` is
    /// contact `contacts().len() + p`.
    #[inline]
    pub fn pairs(&self) -> &[PairCandidate] {
        &self.pairs
    }

    /// The sorted columns where Jacobian row `row` (`3b + k`, `k` = x, y, θ) can be
    /// non-zero.
    #[inline]
    pub fn jacobian_pattern(&self, row: usize) -> &[usize] {
        let s = &self.structure;
        &s.pattern[s.pattern_start[row]..s.pattern_start[row + 1]]
    }

    /// Whether every body's Jacobian, hence `M`, is the same at every `q` (docs/physics.md
    /// §7): no lever arm turns with a coordinate, as for a floating base with bodies
    /// pivoting at its centre of mass (Robbit) or bodies sliding on the world's axes.
    #[inline]
    pub fn jacobian_is_constant(&self) -> bool {
        self.structure.jacobian_constant
    }

    /// The generalised weight `Σ_b J_bᵀ m_b g` when the Jacobian is constant
    /// ([`Model::jacobian_is_constant`]); `None` otherwise. With a constant Jacobian
    /// `J̇ = 0`, so the bias accelerations vanish and this vector is every body's whole
    /// share of `h` (docs/physics.md §1, §7).
    #[inline]
    pub fn constant_weight(&self) -> Option<&[f64]> {
        self.structure.constant_weight.as_deref()
    }

    /// Whether `M(q)` is diagonal at every `q`: every Jacobian row touches at most one
    /// coordinate (a base with bodies pivoting at their own centres of mass, as Robbit).
    pub fn mass_matrix_is_diagonal(&self) -> bool {
        self.structure
            .pattern_start
            .windows(2)
            .all(|w| w[1] - w[0] <= 1)
    }

    /// Whether body–body contact `p` touches a fixed body: the world, like the terrain, for
    /// flight phases and the smallest gap (docs/physics.md §6).
    pub fn pair_touches_world(&self, p: usize) -> bool {
        let pair = &self.pairs[p];
        [pair.probe, pair.target]
            .iter()
            .any(|&s| self.bodies[self.shapes[s].body].is_fixed())
    }

    /// Whether bodies `a` and `b` are joined by a joint (one is the other's parent).
    pub fn joined(&self, a: usize, b: usize) -> bool {
        let parent = |x: usize| self.bodies[x].joint.as_ref().and_then(|j| j.parent);
        parent(a) == Some(b) || parent(b) == Some(a)
    }

    /// Number of potential contacts in the stepper's numbering: terrain contacts, then
    /// body–body contacts.
    #[inline]
    pub fn contact_count(&self) -> usize {
        self.contacts.len() + self.pairs.len()
    }

    /// The material of contact `i` in the stepper's numbering (see [`Model::pairs`]).
    #[inline]
    pub fn material(&self, i: usize) -> &ContactMaterial {
        match self.contacts.get(i) {
            Some(c) => &c.material,
            None => &self.pairs[i - self.contacts.len()].material,
        }
    }

    /// The name of contact `i` in the stepper's numbering (see [`Model::pairs`]).
    pub fn contact_name(&self, i: usize) -> &str {
        match self.contacts.get(i) {
            Some(c) => &c.name,
            None => &self.pairs[i - self.contacts.len()].name,
        }
    }

    /// Geometry of body–body contact `p` (needs `kinematics.update` first).
    #[inline]
    pub fn pair_geometry(&self, kinematics: &Kinematics, p: usize) -> Option<PairGeometry> {
        let pair = &self.pairs[p];
        let pose = |s: usize| {
            let b = self.shapes[s].body;
            Pose {
                position: kinematics.position(b),
                rotation: kinematics.rotation(b),
            }
        };
        pair_geometry(
            &self.shapes[pair.probe].shape,
            pair.feature,
            pose(pair.probe),
            &self.shapes[pair.target].shape,
            pose(pair.target),
        )
    }

    /// Writes `w_N`, `w_T` of body–body contact `p` at `geometry` (docs/physics.md §7) into
    /// slices of length `n`.
    #[inline]
    pub fn pair_directions_to(
        &self,
        kinematics: &Kinematics,
        p: usize,
        geometry: &PairGeometry,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) {
        let pair = &self.pairs[p];
        pair_directions_to(
            kinematics,
            self.shapes[pair.probe].body,
            self.shapes[pair.target].body,
            geometry,
            w_n,
            w_t,
        );
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

    /// Number of generalised coordinates: 3 per floating base plus one per joint that is
    /// not fixed.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The first generalised coordinate of body `b` (`x` of a floating base, the joint
    /// coordinate of a jointed body); `None` for a fixed body.
    #[inline]
    pub fn coordinate(&self, b: usize) -> Option<usize> {
        (self.bodies[b].coordinate_count() > 0).then(|| self.first_coordinate[b])
    }

    /// The `x` coordinate of every floating base: the directions a gait travels along, in
    /// which a periodic gait does not repeat (docs/physics.md §7.1).
    pub fn horizontal_positions(&self) -> Vec<usize> {
        (0..self.bodies.len())
            .filter(|&b| self.bodies[b].joint.is_none())
            .map(|b| self.first_coordinate[b])
            .collect()
    }

    /// Whether generalised coordinate `i` is a length in metres (a floating base's `x` or
    /// `y`, a prismatic joint's extension); otherwise it is an angle in radians
    /// (docs/physics.md §7.1).
    pub fn coordinate_is_length(&self, i: usize) -> bool {
        self.bodies.iter().enumerate().any(|(b, body)| {
            let first = self.first_coordinate[b];
            match (&body.joint, body.coordinate_count()) {
                (None, _) => i == first || i == first + 1,
                (Some(joint), 1) => i == first && matches!(joint.kind, JointKind::Prismatic { .. }),
                _ => false,
            }
        })
    }

    /// The root of body `b`'s tree.
    pub fn root(&self, mut b: usize) -> usize {
        while let Some(p) = self.bodies[b].joint.as_ref().and_then(|j| j.parent) {
            b = p;
        }
        b
    }

    /// Adds a generalised force `value` acting in the joint of body `b` to `out`: a torque
    /// on `b` with its reaction on the parent (revolute, N m) or a force along the axis on
    /// `b` and its reaction on the parent (prismatic, N), i.e. `value ∂s/∂q` with `s` the
    /// joint position (docs/physics.md §7). Nothing for a floating or fixed body.
    #[inline]
    pub fn add_joint_force_to(
        &self,
        kinematics: &Kinematics,
        b: usize,
        value: f64,
        out: &mut [f64],
    ) {
        let Some(joint) = self.bodies[b].joint.as_ref() else {
            return;
        };
        match joint.kind {
            // A clockwise coordinate's force is a clockwise torque.
            JointKind::Revolute if joint.coordinate == JointCoordinate::Clockwise => {
                kinematics.add_torque_to(b, joint.parent, -value, out)
            }
            JointKind::Revolute => kinematics.add_torque_to(b, joint.parent, value, out),
            JointKind::Prismatic { .. } => out[self.first_coordinate[b]] += value,
            JointKind::Fixed { .. } => {}
        }
    }

    /// The joints with dry friction (docs/physics.md §7.5): each as its child body and the
    /// largest torque (N m) or force (N) the joint transmits before slipping. The joint's
    /// rate is `wᵀ u` with `w` from [`Model::add_joint_force_to`] at value 1.
    pub fn dry_frictions(&self) -> &[(usize, f64)] {
        &self.structure.dry_frictions
    }

    /// Total mass of the bodies that move (fixed bodies excluded), kg.
    pub fn total_mass(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|b| !b.is_fixed())
            .map(|b| b.mass)
            .sum()
    }

    /// Mass matrix `M = Σ_b J_bᵀ diag(m_b, m_b, I_b) J_b + diag(armature)` (needs
    /// `kinematics.update` first).
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
                match self.jacobian_pattern(3 * b + k) {
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
        for &(b, armature) in &self.structure.armatures {
            let i = self.first_coordinate[b];
            m[i * n + i] += armature;
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
    /// `n`: `h = applied + conservative + damping`, `damping` alone. Inlined, so a caller
    /// whose slices have a length known when compiling copies and sums them in place.
    #[inline]
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
    /// docs/physics.md §1) to `conservative` and joint and spring damping to `dissipative`.
    fn add_forces(
        &self,
        kinematics: &Kinematics,
        conservative: Option<&mut [f64]>,
        dissipative: Option<&mut [f64]>,
    ) {
        if let Some(h) = conservative {
            match self.constant_weight() {
                Some(weight) => {
                    for (h, w) in h.iter_mut().zip(weight) {
                        *h += w;
                    }
                }
                None => self.add_body_weights(kinematics, h),
            }
            for (b, body) in self.bodies.iter().enumerate() {
                let Some(joint) = body.joint.as_ref().filter(|j| j.stiffness != 0.0) else {
                    continue;
                };
                let stretch = kinematics.joint_position(b) - joint.rest_position;
                self.add_joint_force_to(kinematics, b, -joint.stiffness * stretch, h);
            }
            for spring in self.springs.iter().filter(|s| s.stiffness != 0.0) {
                let (ra, rb) = self.spring_offsets(kinematics, spring);
                let pa = kinematics.position(spring.body_a) + ra;
                let pb = kinematics.position(spring.body_b) + rb;
                let (dir, length) = separation(pa, pb);
                let (elastic, _) = spring.tension(length, 0.0);
                if elastic != 0.0 {
                    let f = -elastic * dir;
                    kinematics.add_point_force_to(spring.body_a, ra, f, h);
                    kinematics.add_point_force_to(spring.body_b, rb, -f, h);
                }
            }
        }
        if let Some(h) = dissipative {
            for damper in self.dampers(kinematics) {
                let force = -damper.coefficient() * damper.rate(self, kinematics);
                damper.add_row_to(self, kinematics, force, h);
            }
        }
    }

    /// Adds `Σ J_bᵀ m_b (g − J̇_b u)` to `h`: the weights with the velocity-product terms,
    /// which enter as the centripetal "bias" accelerations of each centre of mass
    /// (docs/physics.md §1). With a constant Jacobian they vanish and the sum is
    /// [`Model::constant_weight`], which [`Model::add_forces`] adds instead.
    #[inline(never)]
    fn add_body_weights(&self, kinematics: &Kinematics, h: &mut [f64]) {
        for (b, body) in self.bodies.iter().enumerate() {
            let f = body.mass * (self.gravity - kinematics.bias(b));
            kinematics.add_point_force_to(b, Vec2::zeros(), f, h);
        }
    }

    /// World offsets of a spring's two ends from their bodies' centres of mass.
    pub(crate) fn spring_offsets(&self, kinematics: &Kinematics, spring: &Spring) -> (Vec2, Vec2) {
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
            kinematics.position(spring.body_a) + ra,
            kinematics.position(spring.body_b) + rb,
        )
    }

    /// Geometry of potential contact `i` (needs `kinematics.update` first). A circle on a
    /// line without ends takes the shortcut the model resolved for it when built, with
    /// the same result bit for bit (docs/physics.md §2).
    #[inline]
    pub fn contact_geometry(&self, kinematics: &Kinematics, i: usize) -> Option<ContactGeometry> {
        if let Some(disc) = self
            .structure
            .discs_on_lines
            .get(i)
            .and_then(Option::as_ref)
        {
            let body = disc.body;
            return disc.geometry(kinematics.position(body), kinematics.rotation(body));
        }
        let c = &self.contacts[i];
        let inst = &self.shapes[c.shape];
        contact_geometry(
            &inst.shape,
            c.feature,
            kinematics.position(inst.body),
            kinematics.rotation(inst.body),
            &self.terrain.features,
            c.terrain,
        )
    }

    /// Writes the generalised normal and tangential directions `w_N = J_Pᵀ n`,
    /// `w_T = J_Pᵀ t` of contact `i` at `geometry` (docs/physics.md §1, [2.5-2.7]).
    pub fn contact_directions(
        &self,
        kinematics: &Kinematics,
        i: usize,
        geometry: &ContactGeometry,
        w_n: DVectorViewMut<'_, f64>,
        w_t: DVectorViewMut<'_, f64>,
    ) {
        let body = self.shapes[self.contacts[i].shape].body;
        let r = geometry.point - kinematics.position(body);
        kinematics.point_force_direction(body, r, geometry.normal, w_n);
        kinematics.point_force_direction(body, r, geometry.tangent(), w_t);
    }

    /// [`Model::contact_directions`] into slices of length `n`.
    #[inline(always)]
    pub fn contact_directions_to(
        &self,
        kinematics: &Kinematics,
        i: usize,
        geometry: &ContactGeometry,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) {
        let body = self.shapes[self.contacts[i].shape].body;
        let r = geometry.point - kinematics.position(body);
        kinematics.frame_directions_to(body, r, (geometry.normal, geometry.tangent()), w_n, w_t);
    }

    /// Kinetic energy `½ Σ (m_b |v_b|² + I_b ω_b²) + ½ Σ armature q̇²` = `½ uᵀ M u`.
    pub fn kinetic_energy(&self, kinematics: &Kinematics) -> f64 {
        self.energies(kinematics).kinetic
    }

    /// Gravitational potential energy `-Σ m_b g · p_b` (zero at the origin).
    pub fn potential_energy(&self, kinematics: &Kinematics) -> f64 {
        self.energies(kinematics).potential
    }

    /// Energy stored in the springs and the joint springs.
    pub fn spring_energy(&self, kinematics: &Kinematics) -> f64 {
        self.energies(kinematics).spring
    }

    /// The kinetic, potential and spring energies in one pass over the bodies
    /// (docs/physics.md §6.1).
    pub fn energies(&self, kinematics: &Kinematics) -> Energies {
        let mut spring: f64 = (0..self.springs.len())
            .map(|s| {
                let (a, b) = self.spring_ends(kinematics, s);
                self.springs[s].energy((a - b).norm())
            })
            .sum();
        let (mut kinetic, mut potential) = (0.0, 0.0);
        for (b, body) in self.bodies.iter().enumerate() {
            let (v, w, p) = (
                kinematics.velocity(b),
                kinematics.angular_velocity(b),
                kinematics.position(b),
            );
            kinetic += 0.5 * (body.mass * v.norm_squared() + body.inertia * w * w);
            potential += -body.mass * self.gravity.dot(&p);
            if let Some(j) = body.joint.as_ref().filter(|j| j.stiffness != 0.0) {
                let stretch = kinematics.joint_position(b) - j.rest_position;
                spring += 0.5 * j.stiffness * stretch * stretch;
            }
        }
        for &(b, armature) in &self.structure.armatures {
            let rate = kinematics.joint_rate(b);
            kinetic += 0.5 * armature * rate * rate;
        }
        Energies {
            kinetic,
            potential,
            spring,
        }
    }

    /// Centre of mass of the bodies that move (fixed bodies excluded), m.
    pub fn center_of_mass(&self, kinematics: &Kinematics) -> Vec2 {
        let weighted: Vec2 = self
            .bodies
            .iter()
            .enumerate()
            .filter(|(_, body)| !body.is_fixed())
            .map(|(b, body)| body.mass * kinematics.position(b))
            .sum();
        weighted / self.total_mass()
    }
}

/// The energies of a model at one state, J (see [`Model::energies`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// `½ uᵀ M u`.
    pub kinetic: f64,
    /// `-Σ m_b g · p_b` (zero at the origin).
    pub potential: f64,
    /// Stored in the springs and the joint springs.
    pub spring: f64,
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
    if bodies.is_empty() {
        return Err(ModelError::NoBodies);
    }
    if bodies.iter().all(|b| b.coordinate_count() == 0) {
        return Err(ModelError::NoCoordinates);
    }
    // A link on a joint carrying a child whose coordinate it moves (not an absolute angle).
    let carries_child = |b: usize| {
        bodies[b].joint.is_some()
            && bodies.iter().any(|c| {
                c.joint.as_ref().is_some_and(|j| {
                    j.parent == Some(b) && j.coordinate != JointCoordinate::Absolute
                })
            })
    };
    for (b, body) in bodies.iter().enumerate() {
        if body.is_fixed() || carries_child(b) {
            // A fixed base only carries shapes, and a link with children may be massless
            // (their masses carry its coordinate, as MuJoCo's root slide–slide–hinge
            // chain): its mass and inertia may be zero.
            for (what, value) in [("mass", body.mass), ("inertia", body.inertia)] {
                if !(value >= 0.0 && value.is_finite()) {
                    return Err(ModelError::NonPositive {
                        body: body.name.clone(),
                        what,
                        value,
                    });
                }
            }
        } else {
            positive(body, "mass", body.mass)?;
            positive(body, "inertia", body.inertia)?;
        }
        let Some(joint) = body.joint.as_ref() else {
            continue;
        };
        if let Some(parent) = joint.parent.filter(|&p| p >= b) {
            return Err(ModelError::BadParent {
                body: body.name.clone(),
                parent,
            });
        }
        if let Some(reason) = joint_problem(joint) {
            return Err(ModelError::BadJoint {
                body: body.name.clone(),
                reason: reason.into(),
            });
        }
    }
    Ok(())
}

/// What is wrong with a joint's parameters, if anything.
fn joint_problem(joint: &Joint) -> Option<&'static str> {
    let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
    let non_negative = |x: f64| x >= 0.0 && x.is_finite();
    if !finite(joint.pivot_in_parent) || !finite(joint.com_in_child) {
        return Some("the joint's pivot and centre of mass offsets must be finite");
    }
    if !non_negative(joint.damping) {
        return Some("joint damping must be finite and non-negative");
    }
    if !non_negative(joint.stiffness) || !joint.rest_position.is_finite() {
        return Some("the joint spring's stiffness must be finite and non-negative, its rest position finite");
    }
    if !non_negative(joint.armature) {
        return Some("the joint's armature must be finite and non-negative");
    }
    if !non_negative(joint.dry_friction) {
        return Some("the joint's dry friction must be finite and non-negative");
    }
    if joint.dry_friction != 0.0 && !joint.has_coordinate() {
        return Some("dry friction needs a joint that moves (not a fixed body)");
    }
    if joint.armature != 0.0
        && (joint.coordinate == JointCoordinate::Absolute || !joint.has_coordinate())
    {
        return Some("an armature needs a joint whose coordinate is its joint position (not an absolute angle or a fixed body)");
    }
    match joint.kind {
        JointKind::Revolute => {}
        JointKind::Prismatic { axis } => {
            if !finite(axis) || (axis.norm() - 1.0).abs() > 1e-9 {
                return Some("a prismatic joint's axis must be a finite unit vector");
            }
        }
        JointKind::Fixed { angle } => {
            if joint.parent.is_some() {
                return Some("only a tree's root can be fixed (welded to the world)");
            }
            if !angle.is_finite() {
                return Some("a fixed body's angle must be finite");
            }
        }
    }
    if joint.coordinate == JointCoordinate::Absolute && joint.kind != JointKind::Revolute {
        return Some("only a revolute joint can have an absolute-angle coordinate");
    }
    if let Some(l) = joint.limits {
        if !joint.has_coordinate() {
            return Some("a fixed body has no joint position to limit");
        }
        if l.lower.is_nan() || l.upper.is_nan() || l.lower >= l.upper {
            return Some("joint limits need lower < upper");
        }
        if !(0.0..=1.0).contains(&l.restitution) {
            return Some("the joint limits' restitution must be in [0, 1]");
        }
    }
    None
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
            Shape::Circle { radius, .. }
            | Shape::Arc { radius, .. }
            | Shape::Capsule { radius, .. }
                if !positive(*radius) =>
            {
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
            Shape::Capsule { from, to, .. } if !finite(from) || !finite(to) => {
                return bad("the capsule's end points must be finite")
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

/// The finite stops of every joint with limits, lower before upper, in body order.
fn limit_candidates(bodies: &[Body]) -> Vec<LimitCandidate> {
    let mut out = Vec::new();
    for (b, body) in bodies.iter().enumerate() {
        let Some(limits) = body.joint.as_ref().and_then(|j| j.limits) else {
            continue;
        };
        for (upper, bound, side) in [
            (false, limits.lower, "lower"),
            (true, limits.upper, "upper"),
        ] {
            if bound.is_finite() {
                out.push(LimitCandidate {
                    name: format!("{}/{side}", body.name),
                    body: b,
                    upper,
                    bound,
                    restitution: limits.restitution,
                });
            }
        }
    }
    out
}

/// Pairs every shape feature with every terrain feature it can touch: smooth boundaries
/// (circle, arc, ellipse) with lines and corners, vertices (polygon corners, arc ends,
/// points, a capsule's end caps) with lines, a polygon's edges or a capsule's boundary
/// with corners.
fn candidates(
    bodies: &[Body],
    shapes: &[ShapeInstance],
    terrain: &Terrain,
    material: ContactMaterial,
) -> Vec<ContactCandidate> {
    use crate::{Shape, TerrainFeature};
    let mut out = Vec::new();
    // A fixed body's shapes never move: they have no contacts with the terrain.
    for (s, inst) in shapes
        .iter()
        .enumerate()
        .filter(|(_, i)| !bodies[i.body].is_fixed())
    {
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
            } else if matches!(inst.shape, Shape::Polygon { .. } | Shape::Capsule { .. }) {
                push(ShapeFeature::Edges, String::new());
            }
        }
    }
    out
}
