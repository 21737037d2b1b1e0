//! Contacts between bodies (docs/physics.md §7) in the step: two discs colliding head-on and
//! obliquely against the closed-form impact map with restitution `ε` and friction `μ`
//! (docs/physics.md §3), momentum conservation, energy dissipation, and a disc on a fixed body
//! moving exactly as on the same terrain.

mod common;

use hopsim_model::{
    Body, ContactMaterial, Joint, JointKind, Model, ModelBuilder, Shape, ShapeInstance, Terrain,
    Vec2,
};
use hopsim_step::{Actuation, State, StepSettings, Stepper};

/// Two free discs (no gravity, the terrain far below): A (`m1`, `I1`, `r1`) and B
/// (`m2`, `I2`, `r2`), paired with `material`.
struct Discs {
    m: [f64; 2],
    inertia: [f64; 2],
    r: [f64; 2],
}

impl Discs {
    fn model(&self, material: ContactMaterial) -> Model {
        let shape = |b: usize| ShapeInstance {
            name: format!("disc{b}"),
            body: b,
            shape: Shape::Circle {
                center: Vec2::zeros(),
                radius: self.r[b],
            },
        };
        let mut builder = ModelBuilder::new(
            vec![
                Body::base("a", self.m[0], self.inertia[0]),
                Body::base("b", self.m[1], self.inertia[1]),
            ],
            vec![shape(0), shape(1)],
            Terrain::flat(-100.0),
            vec![],
            Vec2::zeros(),
            ContactMaterial::default(),
        )
        .unwrap();
        builder.add_body_contacts(0, 1, material).unwrap();
        builder.build()
    }

    /// The closed-form impact map of one frictional contact between the discs (docs/physics.md
    /// §3 with the §4 laws, `ε_T = 0`), with the normal `n` (A → B) from the centres at
    /// the step's midpoint `q^M = q^A + Δt/2 u^A`. For discs `G_NT = 0`:
    /// `Λ_N = −(1 + ε) γ_N / G_NN`; sticking `Λ_T = −γ_T / G_TT` if `|Λ_T| ≤ μ Λ_N`, else
    /// sliding `Λ_T = −sign(γ_T) μ Λ_N`; with `γ_T = t·(v_B − v_A) + r_A ω_A + r_B ω_B`,
    /// `G_NN = 1/m_A + 1/m_B`, `G_TT = G_NN + r_A²/I_A + r_B²/I_B`.
    /// Returns the end velocities and whether the contact sticks.
    fn impact(&self, q: &[f64], u: &[f64], dt: f64, mu: f64, eps: f64) -> ([f64; 6], bool) {
        let centre = |b: usize| {
            Vec2::new(
                q[3 * b] + 0.5 * dt * u[3 * b],
                q[3 * b + 1] + 0.5 * dt * u[3 * b + 1],
            )
        };
        let d = centre(1) - centre(0);
        let n = d.normalize();
        let t = Vec2::new(n.y, -n.x);
        let v = |b: usize| Vec2::new(u[3 * b], u[3 * b + 1]);
        let (m, i) = (self.m, self.inertia);
        // The contact point is the probe's, disc 0's `c_0 + r_0 n`: its lever is its
        // radius, disc 1's is `|p − c_1| = r_1 + g` (docs/physics.md §7.3).
        let gap = d.norm() - self.r[0] - self.r[1];
        let r = [self.r[0], self.r[1] + gap];
        let gamma_n = n.dot(&(v(1) - v(0)));
        let gamma_t = t.dot(&(v(1) - v(0))) + r[0] * u[2] + r[1] * u[5];
        let g_nn = 1.0 / m[0] + 1.0 / m[1];
        let g_tt = g_nn + r[0] * r[0] / i[0] + r[1] * r[1] / i[1];
        let lambda_n = -(1.0 + eps) * gamma_n / g_nn;
        let stick = -gamma_t / g_tt;
        let sticks = stick.abs() <= mu * lambda_n;
        let lambda_t = if sticks {
            stick
        } else {
            -gamma_t.signum() * mu * lambda_n
        };
        let p = lambda_n * n + lambda_t * t;
        let u = [
            u[0] - p.x / m[0],
            u[1] - p.y / m[0],
            u[2] + r[0] * lambda_t / i[0],
            u[3] + p.x / m[1],
            u[4] + p.y / m[1],
            u[5] + r[1] * lambda_t / i[1],
        ];
        (u, sticks)
    }
}

fn state(q: [f64; 6], u: [f64; 6]) -> State {
    common::state(&q, &u)
}

/// Steps until the first step whose LCP carries a body–body percussion; returns the state
/// before and after it.
fn first_impact(model: &Model, start: &State, dt: f64) -> (State, State) {
    let mut stepper = Stepper::new(model, StepSettings::strict(dt));
    let mut s = start.clone();
    stepper.start(model, &s);
    for _ in 0..10_000 {
        let before = s.clone();
        let rec = stepper.step(model, &mut s, &Actuation::default()).unwrap();
        if rec.pair_contacts.iter().any(|c| c.impulse_normal > 0.0) {
            assert!(rec.contacts.is_empty(), "the terrain is far away");
            return (before, s);
        }
    }
    panic!("no impact");
}

fn momentum(discs: &Discs, u: &[f64]) -> Vec2 {
    discs.m[0] * Vec2::new(u[0], u[1]) + discs.m[1] * Vec2::new(u[3], u[4])
}

fn kinetic(discs: &Discs, u: &[f64]) -> f64 {
    (0..2)
        .map(|b| {
            0.5 * discs.m[b] * (u[3 * b].powi(2) + u[3 * b + 1].powi(2))
                + 0.5 * discs.inertia[b] * u[3 * b + 2].powi(2)
        })
        .sum()
}

/// Head-on: the one-dimensional Newton collision, `v_A' = v_A − (1 + ε) m_B/(m_A + m_B)
/// (v_A − v_B)`, for unequal masses and `ε = 0, ½, 1`; the loss is
/// `½ m_A m_B/(m_A + m_B) (1 − ε²) (v_A − v_B)²`.
#[test]
fn head_on_collision_follows_newtons_law() {
    let discs = Discs {
        m: [1.0, 3.0],
        inertia: [0.004, 0.03],
        r: [0.1, 0.15],
    };
    let dt = 1e-3;
    for eps in [0.0, 0.5, 1.0] {
        let model = discs.model(ContactMaterial {
            friction: 0.4,
            restitution_normal: eps,
            restitution_tangent: 0.0,
        });
        // A at the origin moving at 2 m/s, B 0.3 m further (gap 0.05 m) moving at −0.5 m/s.
        let start = state(
            [0.0, 1.0, 0.0, 0.3, 1.0, 0.0],
            [2.0, 0.0, 0.0, -0.5, 0.0, 0.0],
        );
        let (_, after) = first_impact(&model, &start, dt);
        let (va, vb, mr) = (2.0, -0.5, 1.0 * 3.0 / 4.0);
        let expected_a = va - (1.0 + eps) * 3.0 / 4.0 * (va - vb);
        let expected_b = vb + (1.0 + eps) * 1.0 / 4.0 * (va - vb);
        let u = after.u.as_slice();
        // The LCP is solved to round-off: 1e-12 m/s.
        assert!(
            (u[0] - expected_a).abs() < 1e-12,
            "ε = {eps}: v_A {} vs {expected_a}",
            u[0]
        );
        assert!(
            (u[3] - expected_b).abs() < 1e-12,
            "ε = {eps}: v_B {} vs {expected_b}",
            u[3]
        );
        assert!(u[1].abs() + u[2].abs() + u[4].abs() + u[5].abs() < 1e-12);
        let loss = kinetic(&discs, start.u.as_slice()) - kinetic(&discs, u);
        let expected_loss = 0.5 * mr * (1.0 - eps * eps) * (va - vb).powi(2);
        assert!(
            (loss - expected_loss).abs() < 1e-12,
            "ε = {eps}: loss {loss} vs {expected_loss}"
        );
        assert!((momentum(&discs, u) - momentum(&discs, start.u.as_slice())).norm() < 1e-12);
    }
}

/// Oblique impacts of spinning discs, sticking (large `μ`) and sliding (small `μ`), with
/// `ε = 0, 0.7`: every velocity as the closed-form map gives, momentum kept, energy lost.
#[test]
fn oblique_collision_follows_the_frictional_impact_map() {
    let discs = Discs {
        m: [1.0, 2.0],
        inertia: [0.005, 0.02],
        r: [0.1, 0.12],
    };
    let dt = 1e-3;
    let mut sticking = 0;
    let mut sliding = 0;
    for (mu, eps) in [(0.05, 0.0), (0.05, 0.7), (2.0, 0.0), (2.0, 0.7), (0.3, 0.5)] {
        let model = discs.model(ContactMaterial {
            friction: mu,
            restitution_normal: eps,
            restitution_tangent: 0.0,
        });
        // B above and to the right of A, both spinning, approaching at an angle.
        let start = state(
            [0.0, 1.0, 0.0, 0.2, 1.16, 0.5],
            [1.5, 0.8, 4.0, -0.3, -0.2, -6.0],
        );
        let (before, after) = first_impact(&model, &start, dt);
        let (expected, sticks) =
            discs.impact(before.q.as_slice(), before.u.as_slice(), dt, mu, eps);
        let u = after.u.as_slice();
        for i in 0..6 {
            assert!(
                (u[i] - expected[i]).abs() < 1e-11,
                "μ = {mu}, ε = {eps}: u[{i}] = {} vs {}",
                u[i],
                expected[i]
            );
        }
        assert!((momentum(&discs, u) - momentum(&discs, before.u.as_slice())).norm() < 1e-12);
        let (t0, t1) = (kinetic(&discs, before.u.as_slice()), kinetic(&discs, u));
        assert!(t1 < t0, "μ = {mu}, ε = {eps}: kinetic energy {t0} → {t1}");
        // Both regimes must be exercised.
        if sticks {
            sticking += 1;
        } else {
            sliding += 1;
        }
    }
    assert!(
        sticking > 0 && sliding > 0,
        "{sticking} sticking, {sliding} sliding"
    );
}

/// A long run of two discs bouncing off each other and spinning: the linear momentum stays
/// to round-off, the energy ledger's contact work is never positive and accounts for the
/// whole loss.
#[test]
fn momentum_is_kept_and_energy_only_dissipated() {
    let discs = Discs {
        m: [1.0, 2.0],
        inertia: [0.005, 0.02],
        r: [0.1, 0.12],
    };
    let model = discs.model(ContactMaterial {
        friction: 0.3,
        restitution_normal: 0.6,
        restitution_tangent: 0.0,
    });
    let start = state(
        [0.0, 1.0, 0.0, 0.3, 1.1, 0.0],
        [1.5, 0.3, 4.0, -0.3, -0.2, -6.0],
    );
    let mut stepper = common::stepper(&model, 1e-3);
    let mut s = start.clone();
    let p0 = momentum(&discs, start.u.as_slice());
    let mut impacts = 0;
    let mut last_work = 0.0;
    common::run(&model, &mut stepper, &mut s, 2000, |s, rec| {
        assert!((momentum(&discs, s.u.as_slice()) - p0).norm() < 1e-12);
        impacts += rec
            .pair_contacts
            .iter()
            .filter(|c| c.impulse_normal > 0.0)
            .count();
        assert!(rec.energy.contact_work <= last_work + 1e-15);
        last_work = rec.energy.contact_work;
        assert!(rec.energy.balance_error().abs() < 1e-12, "{:?}", rec.energy);
    });
    assert!(
        impacts >= 1 && last_work < 0.0,
        "{impacts} impacts, work {last_work}"
    );
}

/// docs/physics.md §7: a target fixed to the world reproduces the terrain contacts. A disc
/// dropped spinning onto a fixed body's box, whose top face is `y = 0`, moves exactly as
/// the same disc on flat ground `y = 0` with the same material (bounces, slips, rolls).
#[test]
fn a_disc_on_a_fixed_body_moves_as_on_the_terrain() {
    let material = ContactMaterial {
        friction: 0.3,
        restitution_normal: 0.5,
        restitution_tangent: 0.0,
    };
    let disc = Shape::Circle {
        center: Vec2::zeros(),
        radius: 0.1,
    };
    let ground = common::single_body(1.0, 0.005, disc.clone(), Terrain::flat(0.0), material);
    let mut builder = ModelBuilder::new(
        vec![
            Body::base("disc", 1.0, 0.005),
            Body {
                joint: Some(Joint {
                    kind: JointKind::Fixed { angle: 0.0 },
                    ..Joint::revolute(None, Vec2::new(0.0, -0.5), Vec2::zeros())
                }),
                ..Body::base("floor", 0.0, 0.0)
            },
        ],
        vec![
            ShapeInstance {
                name: "disc".into(),
                body: 0,
                shape: disc,
            },
            ShapeInstance {
                name: "floor".into(),
                body: 1,
                shape: Shape::rectangle(Vec2::zeros(), 10.0, 0.5),
            },
        ],
        Terrain::flat(-100.0),
        vec![],
        Vec2::new(0.0, -common::G),
        material,
    )
    .unwrap();
    builder.add_body_contacts(0, 1, material).unwrap();
    let on_box = builder.build();
    let start = common::state(&[0.0, 0.4, 0.0], &[1.0, 0.0, -20.0]);
    let (mut a, mut b) = (start.clone(), start);
    let (mut sa, mut sb) = (
        common::stepper(&ground, 1e-3),
        common::stepper(&on_box, 1e-3),
    );
    sa.start(&ground, &a);
    sb.start(&on_box, &b);
    let mut touching = 0;
    for _ in 0..1500 {
        let ra = sa.step(&ground, &mut a, &Actuation::default()).unwrap();
        let loaded = ra
            .contacts
            .iter()
            .filter(|c| c.impulse_normal > 0.0)
            .count();
        let rb = sb.step(&on_box, &mut b, &Actuation::default()).unwrap();
        assert_eq!(rb.pair_contacts.len(), ra.contacts.len());
        touching += loaded;
        for i in 0..3 {
            // Same arithmetic up to the order of a few operations: 1e-12.
            assert!(
                (a.q[i] - b.q[i]).abs() < 1e-12 && (a.u[i] - b.u[i]).abs() < 1e-12,
                "t = {}: {:?} vs {:?}",
                a.t,
                a.u,
                b.u
            );
        }
    }
    assert!(touching > 500, "{touching} loaded steps");
}
