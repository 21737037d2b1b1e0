//! Warnings about a valid scene whose results a physicist should not trust as they are:
//! springs, dampers (servos among them) and impacts beyond the accurate range of the step
//! `Δt`, and materials whose impacts can add energy (docs/physics.md §4.7, §4.9). Each names the key and the
//! setting that avoids it; `hopsim scene check` lists them and `hopsim run` prints them once.

use crate::Scene;
use hopsim_model::{ContactMaterial, Kinematics, Model, Shape};
use nalgebra::{DMatrix, DVector};

/// A spring (or joint spring) with `ω Δt` above this is beyond the scheme's accurate range
/// (fewer than about 30 steps per period).
pub const SPRING_OMEGA_DT: f64 = 0.2;
/// A damper with `c Δt / I` above this is: its decay per step is no longer close to
/// `exp(−c Δt / I)` (beyond 2 it even alternates in sign, though it never adds energy).
pub const DAMPER_RATIO: f64 = 1.0;
/// A contact reaching the terrain faster than this fraction of the smallest shape per
/// step penetrates a large part of it in the impact step.
pub const IMPACT_TRAVEL: f64 = 0.05;
/// A body that the scene's energy could turn by more than this angle per step, rad, is
/// beyond the accurate range of the velocity-product terms taken at the step's start.
pub const TURN_PER_STEP: f64 = 0.1;

/// The warnings of `scene`, each a sentence naming the key and what would avoid it.
pub fn warnings(scene: &Scene) -> Vec<String> {
    let model = &scene.model;
    let dt = scene.settings.dt;
    let mut out = Vec::new();
    let mut ws = Kinematics::new(model);
    ws.update(model, &scene.initial.q, &scene.initial.u);
    let Some(mobility) = Mobility::at(model, &ws) else {
        return out;
    };
    let n = model.dof();
    let mut row = vec![0.0; n];
    for (b, body) in model.bodies().iter().enumerate() {
        let Some(joint) = body.joint.as_ref().filter(|j| j.has_coordinate()) else {
            continue;
        };
        row.fill(0.0);
        model.add_joint_force_to(&ws, b, 1.0, &mut row);
        let g = mobility.along(&row);
        let key = |what: &str| format!("bodies.{}.{what}", body.name);
        spring_and_damper(&mut out, dt, g, joint.stiffness, joint.damping, key);
    }
    // A servo is a spring `gear² k_p` and a damper `gear² k_v` in its joint (§7.4).
    for a in model.actuators() {
        let [_, b1, b2] = a.bias();
        if b1 == 0.0 && b2 == 0.0 {
            continue;
        }
        row.fill(0.0);
        model.add_joint_force_to(&ws, a.body, 1.0, &mut row);
        let g = mobility.along(&row);
        let square = a.gear * a.gear;
        let key = |what: &str| {
            let gain = if what == "stiffness" { "kp" } else { "kv" };
            format!("actuators.{}.{gain}", a.name)
        };
        spring_and_damper(&mut out, dt, g, -b1 * square, -b2 * square, key);
    }
    for (s, spring) in model.springs().iter().enumerate() {
        let mut row = vec![0.0; n];
        let (a, b) = model.spring_ends(&ws, s);
        let dir = (a - b).try_normalize(1e-12).unwrap_or_default();
        let offset = |body: usize, p: hopsim_model::Vec2| p - ws.position(body);
        ws.add_point_force_to(spring.body_a, offset(spring.body_a, a), dir, &mut row);
        ws.add_point_force_to(spring.body_b, offset(spring.body_b, b), -dir, &mut row);
        let g = mobility.along(&row);
        let key = |what: &str| format!("springs.{}.{what}", spring.name);
        spring_and_damper(&mut out, dt, g, spring.stiffness, spring.damping, key);
    }
    if let Some(w) = impact_warning(scene, dt) {
        out.push(w);
    }
    out.extend(turn_warning(model, &ws, &mobility, dt));
    out.extend(restitution_warnings(model));
    out
}

/// `M(q)⁻¹` at a state: the mobility `w M⁻¹ wᵀ` of a row `w` (the inverse of the inertia a
/// spring or damper along `w` moves).
struct Mobility(DMatrix<f64>);

impl Mobility {
    fn at(model: &Model, ws: &Kinematics) -> Option<Self> {
        let n = model.dof();
        let mut m = DMatrix::zeros(n, n);
        model.mass_matrix(ws, &mut m);
        m.try_inverse().map(Mobility)
    }

    fn along(&self, row: &[f64]) -> f64 {
        let w = DVector::from_column_slice(row);
        w.dot(&(&self.0 * &w))
    }
}

/// The warnings of one spring–damper of stiffness `k`, damping `c`, along a row of
/// mobility `g` (1/kg or 1/(kg m²)).
fn spring_and_damper(
    out: &mut Vec<String>,
    dt: f64,
    g: f64,
    k: f64,
    c: f64,
    key: impl Fn(&str) -> String,
) {
    if !(g > 0.0 && g.is_finite()) {
        return;
    }
    let omega = (k * g).sqrt();
    if omega * dt > SPRING_OMEGA_DT {
        out.push(format!(
            "{}: the spring's ω Δt = {:.3} (ω = {omega:.4e} rad/s with the inertia it moves) \
             is beyond the accurate range ω Δt ≤ {SPRING_OMEGA_DT}: its energy is not kept; \
             simulation.dt ≤ {:.3e} s would be accurate",
            key("stiffness"),
            omega * dt,
            SPRING_OMEGA_DT / omega
        ));
    }
    let ratio = c * g * dt;
    if ratio > DAMPER_RATIO {
        out.push(format!(
            "{}: the damper's c Δt / I = {ratio:.3} is beyond the accurate range (≤ \
             {DAMPER_RATIO}): it still only removes energy, but not at its rate; \
             simulation.dt ≤ {:.3e} s would be accurate",
            key("damping"),
            DAMPER_RATIO / (c * g)
        ));
    }
}

/// A start whose fall (a floating first body, from its height above the terrain) or
/// initial speed brings a shape to the terrain faster than [`IMPACT_TRAVEL`] of the
/// smallest shape of a moving body per step.
fn impact_warning(scene: &Scene, dt: f64) -> Option<String> {
    let model = &scene.model;
    let (name, size) = model
        .shapes()
        .iter()
        .enumerate()
        .filter(|(i, s)| !scene.switchable.contains(i) && !model.bodies()[s.body].is_fixed())
        .map(|(_, s)| (s.name.as_str(), shape_size(&s.shape)))
        .filter(|(_, size)| *size > 0.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let mut ws = Kinematics::new(model);
    ws.update(model, &scene.initial.q, &scene.initial.u);
    let height = (0..model.contacts().len())
        .filter_map(|i| model.contact_geometry(&ws, i).map(|g| g.gap))
        .fold(f64::INFINITY, f64::min);
    let floats = model.bodies()[0].joint.is_none();
    let fall = if floats && height.is_finite() && height > 0.0 {
        (2.0 * model.gravity().norm() * height).sqrt()
    } else {
        0.0
    };
    let speed = (0..model.bodies().len())
        .map(|b| ws.velocity(b).norm())
        .fold(fall, f64::max);
    (speed * dt > IMPACT_TRAVEL * size).then(|| {
        format!(
            "simulation.dt: shapes reach the terrain at about {speed:.3} m/s (falling from the \
             start or moving), {:.3e} m per step, more than {:.0} % of the smallest shape \
             '{name}' ({size:.3e} m): the impact step penetrates that deep; simulation.dt ≤ \
             {:.3e} s would keep it below",
            speed * dt,
            100.0 * IMPACT_TRAVEL,
            IMPACT_TRAVEL * size / speed
        )
    })
}

/// The body its tree's energy could turn fastest, if by more than [`TURN_PER_STEP`] per
/// step: with all of `E` (its tree's kinetic energy at the start and the energy of the
/// springs in or attached to it; gravity's is left out, since what holds a body up, a
/// pole or the ground, also keeps it from turning that energy into spin) in its rotation,
/// `ω = √(2 E g)` with `g` the mobility of its angle.
fn turn_warning(model: &Model, ws: &Kinematics, mobility: &Mobility, dt: f64) -> Option<String> {
    let count = model.bodies().len();
    let mut tree_energy = vec![0.0; count];
    for (b, body) in model
        .bodies()
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.is_fixed())
    {
        let (v, w) = (ws.velocity(b), ws.angular_velocity(b));
        let mut e = 0.5 * (body.mass * v.norm_squared() + body.inertia * w * w);
        if let Some(j) = body.joint.as_ref() {
            let stretch = ws.joint_position(b) - j.rest_position;
            e += 0.5 * j.stiffness * stretch * stretch;
        }
        tree_energy[model.root(b)] += e;
    }
    for (s, spring) in model.springs().iter().enumerate() {
        let (a, b) = model.spring_ends(ws, s);
        let e = spring.energy((a - b).norm());
        let (ra, rb) = (model.root(spring.body_a), model.root(spring.body_b));
        tree_energy[ra] += e;
        if rb != ra {
            tree_energy[rb] += e;
        }
    }
    let mut row = vec![0.0; model.dof()];
    let (body, omega, energy) = (0..count)
        .filter(|&b| !model.bodies()[b].is_fixed())
        .map(|b| {
            row.fill(0.0);
            ws.add_torque_to(b, None, 1.0, &mut row);
            let energy = tree_energy[model.root(b)];
            (b, (2.0 * energy * mobility.along(&row)).sqrt(), energy)
        })
        .filter(|(_, w, _)| w.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    (omega * dt > TURN_PER_STEP).then(|| {
        format!(
            "simulation.dt: the {energy:.4e} J of its tree (kinetic and spring energy at the \
             start) could turn body '{}' at up to {omega:.4e} rad/s, {:.3} rad per step, \
             beyond the accurate range ({TURN_PER_STEP} rad per step) of the velocity-product \
             terms: energy is then not kept; simulation.dt ≤ {:.3e} s would be accurate",
            model.bodies()[body].name,
            omega * dt,
            TURN_PER_STEP / omega
        )
    })
}

/// A shape's smallest extent, m (none for a point).
fn shape_size(shape: &Shape) -> f64 {
    match shape {
        Shape::Circle { radius, .. }
        | Shape::Arc { radius, .. }
        | Shape::Capsule { radius, .. } => *radius,
        Shape::Ellipse { semi_x, semi_y, .. } => semi_x.min(*semi_y),
        Shape::Point { .. } => 0.0,
        Shape::Polygon { vertices } => {
            let count = vertices.len();
            (0..count)
                .map(|i| (vertices[(i + 1) % count] - vertices[i]).norm())
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// One warning per material (terrain and body contacts) with friction and a tangential
/// restitution different from the normal one: Newton's law then can add energy in a
/// frictional impact (docs/physics.md §4.7).
fn restitution_warnings(model: &Model) -> Vec<String> {
    let mut seen: Vec<ContactMaterial> = Vec::new();
    let mut out = Vec::new();
    for i in 0..model.contact_count() {
        let m = *model.material(i);
        let risky = m.friction > 0.0 && m.restitution_tangent != m.restitution_normal;
        if !risky || seen.contains(&m) {
            continue;
        }
        seen.push(m);
        out.push(format!(
            "contact '{}' (and any with the same material): friction μ = {} with tangential \
             restitution {} ≠ normal restitution {}: impacts can add energy (Newton's law, \
             docs/physics.md §4.7; reported as energy_created events); setting \
             tangential_restitution equal to restitution avoids it",
            model.contact_name(i),
            m.friction,
            m.restitution_tangent,
            m.restitution_normal
        ));
    }
    out
}
