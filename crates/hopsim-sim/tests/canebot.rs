//! CaneBot (docs/physics.md §5.4) through the whole run loop: the scene files, the joint's
//! springs and motor against closed-form mechanics, the cane's switching rules and energy,
//! the periodicity of the gaits, and a golden contact-impulse trace.
//!
//! docs/canebot.md describes the model and the experiments these tests guard.

mod common;

use common::{first_second, repo, run, scene};
use hopsim_control::{shape_gap, CaneMode, ControllerConfig, Pulse, PulseConfig};
use hopsim_model::{Kinematics, Model, Vec2};
use hopsim_record::EventKind;
use hopsim_record::TraceTolerance;
use hopsim_scene::Scene;
use hopsim_sim::{Observer, PeriodicityOptions, PoincareSection, RunError, Simulation, StepView};
use nalgebra::DVector;

fn pulse_config(scene: &Scene) -> &PulseConfig {
    match &scene.controller {
        ControllerConfig::Pulse(c) => c,
        other => panic!("{}: not a pulse controller: {other:?}", scene.title),
    }
}

fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

fn rotate(theta: f64, v: Vec2) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

// ---------------------------------------------------------------------------------------
// The three scene files describe one robot.

#[test]
fn the_three_scenes_describe_the_same_robot() {
    let base = scene("canebot.toml", &[]);
    let b = pulse_config(&base);
    assert_eq!(b.cane, CaneMode::Retracted);
    for (name, mode) in [
        ("canebot-cane.toml", CaneMode::Extended),
        (
            "canebot-timed.toml",
            CaneMode::Timed {
                delay: 0.1,
                duration: 0.5,
            },
        ),
    ] {
        let s = scene(name, &[]);
        let (m, m0) = (&s.model, &base.model);
        assert_eq!(m.bodies(), m0.bodies(), "{name}: bodies");
        assert_eq!(m.shapes(), m0.shapes(), "{name}: shapes");
        assert_eq!(m.springs(), m0.springs(), "{name}: springs");
        assert_eq!(
            m.contacts(),
            m0.contacts(),
            "{name}: contacts and materials"
        );
        assert_eq!(m.terrain(), m0.terrain(), "{name}: terrain");
        assert_eq!(m.gravity(), m0.gravity(), "{name}: gravity");
        assert_eq!(s.settings, base.settings, "{name}: [simulation]");
        assert_eq!(s.initial, base.initial, "{name}: [initial]");
        assert_eq!(s.switchable, base.switchable, "{name}: switchable shapes");
        let c = pulse_config(&s);
        assert_eq!(c.cane, mode, "{name}: cane mode");
        assert_eq!(
            PulseConfig {
                cane: b.cane,
                ..c.clone()
            },
            *b,
            "{name}: controller"
        );
    }
    // The robot of docs/physics.md §5.4: two bodies, ±0.4 N m for 0.1 s each, P = 1/2.8 s.
    assert_eq!(base.model.bodies().len(), 2);
    assert_eq!((b.torque, b.pulse_duration), (0.4, 0.1));
    assert!((b.period - 1.0 / 2.8).abs() < 1e-15);
    assert_eq!(base.settings.duration, 10.0);
}

// ---------------------------------------------------------------------------------------
// Springs and motor, robot in the air with gravity off.
//
// The joint's rotational stiffness: each spring i runs from a on the lower body to b on the
// upper body, both measured from the joint, with length L, rest length L0 and stiffness k.
// With θ the joint angle, L L' = a × b =: L h (h is the spring line's lever arm about the
// joint) and L'² + L L'' = a · b, so V = ½ k (L − L0)² has
//
//     k_θ = V'' = Σ k (h² + (L − L0)(a · b − h²) / L),
//
// the first term from the springs' axial stiffness, the second from their pre-tension.
//
// The effective inertia: in the air with zero momentum the centre of mass stays put and the
// angular momentum about it stays zero. With r1, r2 the two centres of mass measured from
// the joint and μ = m1 m2 / (m1 + m2), the kinetic energy about the centre of mass is
// ½ (J1 ω1² + J2 ω2² + 2 J12 ω1 ω2) with J1 = I1 + μ r1², J2 = I2 + μ r2², J12 = −μ r1 · r2;
// zero angular momentum, (J1 + J12) ω1 + (J2 + J12) ω2 = 0, leaves one degree of freedom
// θ̇ = ω2 − ω1 with
//
//     I_eff = (J1 J2 − J12²) / (J1 + J2 + 2 J12),   f = sqrt(k_θ / I_eff) / 2π.

/// The joint's geometry read from the model: spring ends and centres of mass from the joint.
struct JointModel {
    /// Per spring: end on the lower body (lower frame), end on the upper body (upper
    /// frame), both from the joint; stiffness; rest length.
    springs: Vec<(Vec2, Vec2, f64, f64)>,
    /// Lower and upper centre of mass from the joint, each in its own frame.
    r1: Vec2,
    r2: Vec2,
    m: (f64, f64),
    inertia: (f64, f64),
}

impl JointModel {
    fn of(model: &Model) -> Self {
        let upper = &model.bodies()[1];
        let joint = upper
            .joint
            .as_ref()
            .expect("the upper body hangs on the joint");
        assert_eq!(joint.parent, Some(0));
        let pivot = joint.pivot_in_parent;
        let springs = model
            .springs()
            .iter()
            .map(|s| {
                assert_eq!(
                    (s.body_a, s.body_b),
                    (0, 1),
                    "springs run from the lower body to the upper"
                );
                (
                    s.point_a - pivot,
                    s.point_b + joint.com_in_child,
                    s.stiffness,
                    s.rest_length,
                )
            })
            .collect();
        Self {
            springs,
            r1: -pivot,
            r2: joint.com_in_child,
            m: (model.bodies()[0].mass, upper.mass),
            inertia: (model.bodies()[0].inertia, upper.inertia),
        }
    }

    /// Spring torque on the upper body about the joint at joint angle `theta`, N m.
    fn torque(&self, theta: f64) -> f64 {
        self.springs
            .iter()
            .map(|&(a, b0, k, l0)| {
                let b = rotate(theta, b0);
                let l = (b - a).norm();
                let tension = (k * (l - l0)).max(0.0);
                -tension * cross(a, b) / l
            })
            .sum()
    }

    /// The joint angle where the springs balance (no gravity), by Newton's method.
    fn equilibrium(&self) -> f64 {
        let mut theta = 0.0;
        for _ in 0..50 {
            theta += self.torque(theta) / self.stiffness(theta);
        }
        assert!(self.torque(theta).abs() < 1e-12);
        theta
    }

    /// k_θ at `theta` (closed form above).
    fn stiffness(&self, theta: f64) -> f64 {
        self.springs
            .iter()
            .map(|&(a, b0, k, l0)| {
                let b = rotate(theta, b0);
                let l = (b - a).norm();
                let h = cross(a, b) / l;
                k * (h * h + (l - l0) * (a.dot(&b) - h * h) / l)
            })
            .sum()
    }

    /// I_eff of the free two-body system at `theta` (closed form above).
    fn free_inertia(&self, theta: f64) -> f64 {
        let ((m1, m2), (i1, i2)) = (self.m, self.inertia);
        let mu = m1 * m2 / (m1 + m2);
        let r2 = rotate(theta, self.r2);
        let j1 = i1 + mu * self.r1.norm_squared();
        let j2 = i2 + mu * r2.norm_squared();
        let j12 = -mu * self.r1.dot(&r2);
        (j1 * j2 - j12 * j12) / (j1 + j2 + 2.0 * j12)
    }
}

/// The robot in the air: gravity off, lower body level 1 m up, joint at `theta`, at rest.
#[allow(dead_code)]
fn floating(theta: f64, torque: f64) -> Scene {
    floating_with(theta, torque, &[])
}

/// [`floating`] with more overrides.
fn floating_with(theta: f64, torque: f64, more: &[&str]) -> Scene {
    let mut overrides = vec![
        "simulation.gravity=0".to_string(),
        "initial.rest_on_ground=false".to_string(),
        format!("initial.q=[0.0, 1.0, 0.0, {theta:?}]"),
        format!("controller.torque={torque:?}"),
    ];
    overrides.extend(more.iter().map(|o| o.to_string()));
    let overrides: Vec<&str> = overrides.iter().map(String::as_str).collect();
    scene("canebot.toml", &overrides)
}

/// The joint angle and the total angular momentum about the centre of mass after every
/// step, and the largest drift of the centre of mass.
#[derive(Default)]
struct JointLog {
    t: Vec<f64>,
    theta: Vec<f64>,
    max_momentum: f64,
    /// Largest Σ_b |angular momentum of body b about the centre of mass|: the scale.
    momentum_scale: f64,
    com0: Option<Vec2>,
    max_com_drift: f64,
}

impl Observer for JointLog {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        let (m, ws) = (v.model, v.kinematics);
        let com = m.center_of_mass(ws);
        let parts: Vec<f64> = (0..m.bodies().len())
            .map(|b| {
                let body = &m.bodies()[b];
                body.inertia * ws.angular_velocity(b)
                    + body.mass * cross(ws.position(b) - com, ws.velocity(b))
            })
            .collect();
        let momentum: f64 = parts.iter().sum();
        self.max_momentum = self.max_momentum.max(momentum.abs());
        self.momentum_scale = self.momentum_scale.max(parts.iter().map(|p| p.abs()).sum());
        let com0 = *self.com0.get_or_insert(com);
        self.max_com_drift = self.max_com_drift.max((com - com0).norm());
        self.t.push(v.state.t);
        self.theta.push(v.state.q[3]);
        Ok(())
    }
}

/// Times where `x` crosses `level` upwards, interpolated between samples.
fn upward_crossings(t: &[f64], x: &[f64], level: f64) -> Vec<f64> {
    (1..x.len())
        .filter(|&i| x[i - 1] < level && x[i] >= level)
        .map(|i| t[i - 1] + (level - x[i - 1]) / (x[i] - x[i - 1]) * (t[i] - t[i - 1]))
        .collect()
}

/// Gravity off, in the air, motor off, damping off: released 0.01 rad from the springs'
/// equilibrium, the joint oscillates at sqrt(k_θ / I_eff) / 2π with k_θ from the spring
/// geometry and I_eff of both bodies (closed forms above), within 0.2 %. The frequency with
/// the foot held still, sqrt(k_θ / (I_u + m_u r_u²)) / 2π, is more than 30 % away: the
/// measurement tells the two apart. The springs are internal: the centre of mass stays put
/// (to 1 µm) and the angular momentum about it zero (to 1e-4 of the bodies' own momenta;
/// the midpoint scheme conserves both to O(Δt²) per step).
#[test]
fn joint_oscillates_at_the_frequency_of_the_springs_and_both_inertias() {
    let base = scene("canebot.toml", &[]);
    let joint = JointModel::of(&base.model);
    let theta_eq = joint.equilibrium();
    let k_theta = joint.stiffness(theta_eq);
    let predicted = (k_theta / joint.free_inertia(theta_eq)).sqrt() / std::f64::consts::TAU;
    let held_inertia = joint.inertia.1 + joint.m.1 * joint.r2.norm_squared();
    let held = (k_theta / held_inertia).sqrt() / std::f64::consts::TAU;

    let mut s = floating_with(theta_eq + 0.01, 0.0, &["bodies.upper.damping=0"]);
    s.settings.duration = 3.0;
    let mut log = JointLog::default();
    let summary = run(&s, &mut log);
    let crossings = upward_crossings(&log.t, &log.theta, theta_eq);
    let cycles = crossings.len() - 1;
    let measured = cycles as f64 / (crossings[cycles] - crossings[0]);
    let amplitude = log
        .theta
        .iter()
        .map(|th| (th - theta_eq).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "in the air: θ_eq = {theta_eq:.5} rad, k_θ = {k_theta:.5} N m/rad, I_eff = {:.4e} kg m²: \
         predicted {predicted:.5} Hz, measured {measured:.5} Hz over {cycles} cycles \
         (foot held: {held:.4} Hz); amplitude {amplitude:.4} rad",
        joint.free_inertia(theta_eq)
    );
    assert!(cycles >= 8, "{cycles} cycles");
    assert!(
        (measured - predicted).abs() < 2e-3 * predicted,
        "measured {measured} Hz, predicted {predicted} Hz"
    );
    assert!(
        (measured - held).abs() > 0.3 * held,
        "foot-held {held} Hz is too close"
    );
    // Undamped and passive: the amplitude neither grows nor decays.
    assert!((amplitude - 0.01).abs() < 1e-4, "amplitude {amplitude}");
    // The midpoint scheme keeps the momenta to O(Δt²) per step, not exactly: the velocity
    // update conserves them at q^M, the position update moves q^M on to q^E.
    assert!(
        log.max_momentum < 1e-4 * log.momentum_scale,
        "angular momentum {} of {}",
        log.max_momentum,
        log.momentum_scale
    );
    assert!(
        log.max_com_drift < 1e-6,
        "centre of mass moved {} m",
        log.max_com_drift
    );
    // Passive and undamped: the energy account closes to 1e-4 of the oscillation's energy.
    let energy = 0.5 * k_theta * 0.01 * 0.01;
    assert!(
        summary.energy.max_abs_balance_error < 1e-4 * energy,
        "{:?}",
        summary.energy
    );
}

/// Gravity off, in the air, joint damping off: a small pulse (±0.02 N m, 0.1 s each) from the
/// springs' equilibrium drives the joint as the linear oscillator I_eff θ̈ + k_θ θ = τ(t):
/// θ(t) − θ_eq = Σ_j ΔT_j / k_θ (1 − cos ω (t − t_j)) over the torque steps ΔT_j at t_j
/// (+T at 0, −2T at 0.1 s, +T at 0.2 s), within 1 % of its peak over the first motor
/// period (the remainder is the springs' geometric nonlinearity at 0.06 rad); the motor's
/// torque pair leaves the angular momentum at zero (to 1e-4 of the bodies' own momenta).
#[test]
fn motor_pulse_drives_the_joint_as_the_linear_oscillator_predicts() {
    let base = scene("canebot.toml", &[]);
    let joint = JointModel::of(&base.model);
    let theta_eq = joint.equilibrium();
    let k_theta = joint.stiffness(theta_eq);
    let omega = (k_theta / joint.free_inertia(theta_eq)).sqrt();
    let torque = 0.02;
    let mut s = floating_with(theta_eq, torque, &["bodies.upper.damping=0"]);
    let period = pulse_config(&s).period;
    let tau = pulse_config(&s).pulse_duration;
    s.settings.duration = period;
    let mut log = JointLog::default();
    let summary = run(&s, &mut log);
    let linear = |t: f64| {
        [(0.0, torque), (tau, -2.0 * torque), (2.0 * tau, torque)]
            .iter()
            .filter(|(tj, _)| t > *tj)
            .map(|(tj, dt)| dt / k_theta * (1.0 - (omega * (t - tj)).cos()))
            .sum::<f64>()
    };
    let peak = log.t.iter().map(|&t| linear(t).abs()).fold(0.0, f64::max);
    let worst = log
        .t
        .iter()
        .zip(&log.theta)
        .map(|(&t, th)| (th - theta_eq - linear(t)).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "motor pulse in the air: peak {peak:.5} rad, largest deviation from the linear \
         oscillator {worst:.3e} rad, actuator work {:.3e} J, balance error {:.2e} J",
        summary.energy.at_end.actuator_work, summary.energy.max_abs_balance_error
    );
    assert!(peak > 1.5 * torque / k_theta, "peak {peak}");
    assert!(
        worst < 0.01 * peak,
        "deviation {worst} rad vs peak {peak} rad"
    );
    assert!(
        log.max_momentum < 1e-4 * log.momentum_scale,
        "angular momentum {} of {}",
        log.max_momentum,
        log.momentum_scale
    );
    let e = &summary.energy;
    assert!(
        e.max_abs_balance_error < 1e-3 * e.at_end.actuator_work.abs(),
        "{e:?}"
    );
}

// ---------------------------------------------------------------------------------------
// The cane.

/// Checks, every step, the cane rules of docs/physics.md §5.4 and the energy account:
/// - a cane is extended only when the schedule wants it and its tip is clear of the ground
///   (gap > 0 at the start of the step), and a scheduled extension is held back only while
///   the tip is not clear;
/// - a retracted cane carries no percussion (it leaves contact the step it retracts);
/// - contacts do no positive work in a switch step, and over the run their positive
///   per-step works (the midpoint ledger's `O(Δt²)` per step in persistent contacts, where
///   `(γ^A + γ^E)/2` is not exactly zero) add up to a small fraction of the dissipated
///   energy;
/// - the energy balance changes across a switch step by no more than across the ordinary
///   steps (the midpoint scheme's own error): switching never injects energy.
struct CaneCheck {
    pulse: Pulse,
    cane: usize,
    dt: f64,
    prev_q: DVector<f64>,
    prev_u: DVector<f64>,
    prev_active: bool,
    ws: Kinematics,
    prev_balance: f64,
    prev_contact_work: f64,
    switches: usize,
    blocked_steps: usize,
    cane_impulse_steps: usize,
    max_switch_jump: f64,
    max_ordinary_jump: f64,
    max_contact_work: f64,
    /// Sum of the positive per-step contact works (the midpoint ledger's own error in
    /// persistent contacts: `Λ · (γ^A + γ^E)/2` with `γ^E = 0` and `γ^A = O(Δt)`).
    positive_contact_work: f64,
    max_switch_contact_work: f64,
    failures: Vec<String>,
}

impl CaneCheck {
    fn new(scene: &Scene) -> Self {
        let c = pulse_config(scene);
        let mut ws = Kinematics::new(&scene.model);
        ws.update(&scene.model, &scene.initial.q, &scene.initial.u);
        Self {
            pulse: Pulse::new(c.clone()),
            cane: c.cane_shape.expect("a cane"),
            dt: scene.settings.dt,
            prev_q: scene.initial.q.clone(),
            prev_u: scene.initial.u.clone(),
            prev_active: false,
            ws,
            prev_balance: 0.0,
            prev_contact_work: 0.0,
            switches: 0,
            blocked_steps: 0,
            cane_impulse_steps: 0,
            max_switch_jump: 0.0,
            max_ordinary_jump: 0.0,
            max_contact_work: f64::NEG_INFINITY,
            positive_contact_work: 0.0,
            max_switch_contact_work: f64::NEG_INFINITY,
            failures: Vec::new(),
        }
    }
}

impl Observer for CaneCheck {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        let t0 = v.state.t - self.dt;
        let model = v.model;
        // Kinematics at the start of the step, as the controller saw them.
        self.ws.update(model, &self.prev_q, &self.prev_u);
        let gap = shape_gap(model, &self.ws, self.cane);
        let active = v.shapes_active[self.cane];
        let switched = v
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::ShapeSwitch { .. }));
        // The controller reads its schedule at the step's midpoint time (docs/physics.md §4).
        let wanted = self.pulse.cane_wanted(t0 + 0.5 * self.dt);
        let mut fail = |what: String| self.failures.push(format!("t = {t0:.5}: {what}"));
        if switched != (active != self.prev_active) {
            fail(format!(
                "switch event {switched} but active {} → {active}",
                self.prev_active
            ));
        }
        if active && !self.prev_active && !(wanted && gap > 0.0) {
            fail(format!(
                "extended with wanted = {wanted}, tip gap {gap:.3e} m"
            ));
        }
        if !active && wanted {
            self.blocked_steps += 1;
            if gap > 0.0 {
                fail(format!(
                    "held back although the tip is clear by {gap:.3e} m"
                ));
            }
        }
        if active && !wanted {
            fail("extended outside its schedule".into());
        }
        let cane_loaded = v
            .record
            .contacts
            .iter()
            .any(|c| model.contacts()[c.contact].shape == self.cane && c.impulse_normal > 0.0);
        if cane_loaded && !active {
            fail("a retracted cane carries a percussion".into());
        }
        self.cane_impulse_steps += usize::from(cane_loaded);
        let e = v.record.energy;
        let jump = (e.balance_error() - self.prev_balance).abs();
        if switched {
            self.switches += 1;
            self.max_switch_jump = self.max_switch_jump.max(jump);
        } else {
            self.max_ordinary_jump = self.max_ordinary_jump.max(jump);
        }
        let dw = e.contact_work - self.prev_contact_work;
        self.positive_contact_work += dw.max(0.0);
        if switched {
            self.max_switch_contact_work = self.max_switch_contact_work.max(dw);
        }
        self.max_contact_work = self.max_contact_work.max(dw);
        self.prev_balance = e.balance_error();
        self.prev_contact_work = e.contact_work;
        self.prev_active = active;
        self.prev_q.copy_from(&v.state.q);
        self.prev_u.copy_from(&v.state.u);
        Ok(())
    }
}

/// The timed scene and five other cane timings (including wrapping windows and the always
/// extended cane), 10 s each: the cane follows its schedule and is held back exactly while
/// its tip is in the ground; a retracted cane carries nothing; contacts do no positive work
/// in switch steps (and less than 1e-3 of the dissipated energy in all steps); and the
/// energy balance moves across the switch steps by no more than across ordinary steps,
/// while the account closes over the run to 1e-3 of the actuator work (the scheme's O(Δt)
/// error in persistent contacts, as in hopsim-step's energy_balance test; it halves with Δt).
#[test]
fn cane_switches_follow_the_rules_and_never_inject_energy() {
    let cases: [(&str, &[&str]); 6] = [
        ("canebot-timed.toml", &[]),
        ("canebot-timed.toml", &["controller.cane_delay=0.0"]),
        ("canebot-timed.toml", &["controller.cane_delay=0.35"]),
        ("canebot-timed.toml", &["controller.cane_delay=0.8"]),
        (
            "canebot-timed.toml",
            &["controller.cane_delay=0.6", "controller.cane_duration=0.25"],
        ),
        ("canebot-cane.toml", &[]),
    ];
    let (mut loaded_cases, mut blocked_cases) = (0, 0);
    for (name, overrides) in cases {
        let s = scene(name, overrides);
        let mut check = CaneCheck::new(&s);
        let summary = run(&s, &mut check);
        let e = &summary.energy;
        eprintln!(
            "{name} {overrides:?}: {} switches, {} steps held back, {} steps with cane \
             percussions; balance jump at switches ≤ {:.2e} J, elsewhere ≤ {:.2e} J; \
             contact work per step ≤ {:.2e} J ({:.2e} J at switches, {:.2e} J positive in \
             all); max |balance error| {:.2e} J of {:.3} J flows",
            check.switches,
            check.blocked_steps,
            check.cane_impulse_steps,
            check.max_switch_jump,
            check.max_ordinary_jump,
            check.max_contact_work,
            check.max_switch_contact_work,
            check.positive_contact_work,
            e.max_abs_balance_error,
            e.at_end.actuator_work
        );
        let what = format!("{name} {overrides:?}");
        assert!(
            check.failures.is_empty(),
            "{what}:\n{}",
            check.failures.join("\n")
        );
        assert!(
            check.max_switch_contact_work <= 1e-12,
            "{what}: contact work {} in a switch step",
            check.max_switch_contact_work
        );
        assert!(
            check.positive_contact_work < 1e-3 * e.at_end.dissipated,
            "{what}: contacts did {} J of positive work",
            check.positive_contact_work
        );
        assert!(
            check.max_switch_jump <= check.max_ordinary_jump,
            "{what}: balance jumps by {} at a switch, at most {} elsewhere",
            check.max_switch_jump,
            check.max_ordinary_jump
        );
        assert!(
            e.max_abs_balance_error < 1e-3 * e.at_end.actuator_work,
            "{what}: balance {e:?}"
        );
        assert_eq!(summary.lcp.failures, 0, "{what}");
        assert!(
            summary.max_penetration_m < 1e-3,
            "{what}: penetration {}",
            summary.max_penetration_m
        );
        loaded_cases += usize::from(check.cane_impulse_steps > 0);
        blocked_cases += usize::from(check.blocked_steps > 0);
        if name == "canebot-timed.toml" {
            assert!(
                check.switches >= 2 * 20,
                "{what}: {} switches",
                check.switches
            );
        }
    }
    // The cases exercise both rules: canes that carry load and extensions held back.
    assert!(loaded_cases >= 2, "only {loaded_cases} cases load the cane");
    assert!(
        blocked_cases >= 2,
        "only {blocked_cases} cases hold an extension back"
    );
}

// ---------------------------------------------------------------------------------------
// Gaits.

/// Take-offs after `from` seconds.
struct TakeOffs {
    from: f64,
    count: usize,
}

impl Observer for TakeOffs {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        self.count += v
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::TakeOff) && e.t >= self.from)
            .count();
        Ok(())
    }
}

/// The cane-less robot from rest, 10 s: it hops forward, one flight phase per motor period
/// in the last 5 s, and the state at the start of each motor period repeats: period 1 on
/// the Poincaré section (`PeriodicityOptions::default()`: the last 8 periods agree within
/// 2 % of each variable's excursion), while no other period p ≤ 4 is needed. No LCP
/// failure, penetration below 0.5 mm, and the energy account closes.
#[test]
fn caneless_robot_hops_forward_in_a_period_one_gait() {
    let s = scene("canebot.toml", &[]);
    let period = pulse_config(&s).period;
    let mut takeoffs = TakeOffs {
        from: 5.0,
        count: 0,
    };
    let mut observed = PoincareSection::new(period, s.initial.t);
    let summary = run(&s, &mut (&mut takeoffs, &mut observed));
    let gait = observed.detect(&PeriodicityOptions::default());
    eprintln!(
        "cane retracted: {:.4} m in 10 s, {:.4} m/s, {} hops, {:.4} m per hop; {gait}",
        summary.distance_m, summary.mean_speed_mps, summary.hops, summary.distance_per_hop_m
    );
    assert_eq!(gait.period, Some(1), "{gait}");
    assert!(gait.sections >= 28, "{gait}");
    assert!(summary.distance_m > 0.0 && summary.mean_speed_mps > 0.0);
    assert!(summary.distance_per_hop_m > 0.0);
    let periods = (5.0 / period).floor() as usize;
    assert!(
        takeoffs.count == periods || takeoffs.count == periods + 1,
        "{} take-offs in the last 5 s ({periods} motor periods)",
        takeoffs.count
    );
    assert_eq!(summary.lcp.failures, 0);
    assert!(
        summary.max_penetration_m < 5e-4,
        "penetration {}",
        summary.max_penetration_m
    );
    let e = &summary.energy;
    assert!(
        e.max_abs_balance_error < 1e-4 * e.at_end.actuator_work,
        "{e:?}"
    );
    // The detection is not trivially satisfied: with a tolerance 100 times tighter the same
    // section is not periodic (its jitter is the step grid's, O(Δt); docs/canebot.md).
    let strict = PeriodicityOptions {
        relative_tolerance: 2e-4,
        ..PeriodicityOptions::default()
    };
    // The section observer sees what pushing every state by hand gives.
    let mut section = PoincareSection::new(period, 0.0);
    let mut sim = Simulation::new(&s);
    let steps = (s.settings.duration / s.settings.dt).round() as usize;
    section.push(0.0, s.initial.q.as_slice(), s.initial.u.as_slice());
    for _ in 0..steps {
        sim.step(&mut ()).unwrap();
        section.push(
            sim.state().t,
            sim.state().q.as_slice(),
            sim.state().u.as_slice(),
        );
    }
    assert_eq!(section.detect(&PeriodicityOptions::default()), gait);
    assert_eq!(section.detect(&strict).period, None);
}

/// The permanently extended cane and the timed cane: their period on the section is
/// detected, not asserted (it is whatever the model gives; docs/canebot.md).
#[test]
fn cane_gaits_report_their_period() {
    for name in ["canebot-cane.toml", "canebot-timed.toml"] {
        let s = scene(name, &[]);
        let mut section = PoincareSection::new(pulse_config(&s).period, s.initial.t);
        let summary = run(&s, &mut section);
        let gait = section.detect(&PeriodicityOptions::default());
        let period = gait.period.map_or("none".to_string(), |p| p.to_string());
        eprintln!(
            "{name}: period {period}; {:.4} m in 10 s, {:.4} m/s, {} hops, {:.4} m per hop; {gait}",
            summary.distance_m, summary.mean_speed_mps, summary.hops, summary.distance_per_hop_m
        );
        let options = PeriodicityOptions::default();
        assert!(
            gait.sections >= options.window + options.max_period,
            "{gait}"
        );
        assert_eq!(gait.residuals.len(), options.max_period);
        assert!(
            gait.residuals.iter().all(|r| r.is_finite() && *r >= 0.0),
            "{gait}"
        );
        assert_eq!(summary.lcp.failures, 0, "{name}");
    }
}

// ---------------------------------------------------------------------------------------
// Golden trace.

/// Regression on contact impulses: every step's Λ_N, Λ_T of the first second of
/// canebot-timed.toml against tests/golden/canebot_timed_first_second.csv
/// (`TraceTolerance::default()`: 1e-9 N s + 1e-6 relative; regenerate deliberately with
/// `HOPSIM_BLESS=1 cargo test -p hopsim-sim --release --test canebot` and review the diff).
/// The comparison can fail: 1 % less friction moves the trace by more than 1e-4 N s.
#[test]
fn golden_contact_impulses_of_the_timed_scene_first_second() {
    let s = scene("canebot-timed.toml", &[]);
    let trace = first_second(&s);
    let channels: std::collections::BTreeSet<&str> =
        trace.samples.iter().map(|x| x.channel.as_str()).collect();
    eprintln!(
        "canebot-timed, first second: {} samples on {channels:?}",
        trace.samples.len()
    );
    assert!(
        channels.iter().any(|c| c.starts_with("foot")),
        "{channels:?}"
    );
    trace
        .check_golden(
            &repo("tests/golden/canebot_timed_first_second.csv"),
            TraceTolerance::default(),
        )
        .unwrap();
    let other = first_second(&scene(
        "canebot-timed.toml",
        &["environment.friction=0.891"],
    ));
    let difference = trace
        .first_difference(&other, TraceTolerance::default())
        .expect("μ = 0.891 differs from μ = 0.9");
    assert!(difference.max_abs > 1e-4, "{difference}");
}
