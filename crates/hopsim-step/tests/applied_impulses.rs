//! Applied impulses in free flight (docs/physics.md §3, [2.22]): a step changes the velocities
//! by gravity `g Δt` plus exactly `M⁻¹ Jᵀ ζ`, with `M` and the Jacobians written out by
//! hand here for a single rigid body and for Robbit (a flywheel on an absolute joint).

mod common;

use hopsim_model::{Body, Model, Shape, ShapeInstance, Terrain, Vec2};
use hopsim_step::{Actuation, ImpulseCommand, State};

/// Small deterministic generator (xorshift), uniform in `[lo, hi)`.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// `r × ζ` (the z component).
fn cross(r: Vec2, f: Vec2) -> f64 {
    r.x * f.y - r.y * f.x
}

/// One step of `model` from `start` under `act`; asserts free flight (no contact).
fn step(model: &Model, start: &State, act: &Actuation, dt: f64) -> State {
    let mut stepper = common::stepper(model, dt);
    let mut s = start.clone();
    stepper.start(model, &s);
    let rec = stepper.step(model, &mut s, act).expect("step");
    assert!(rec.contacts.is_empty(), "free flight expected: {rec:?}");
    s
}

/// Asserts `u^E = u^A + expected_du` entrywise to `1e-12`, and `q^E = q^A + Δt/2 (u^A +
/// u^E)` (the midpoint rule); returns the largest velocity error.
/// Steps `start` once per case with that case's impulses and checks the velocity change;
/// the worst error.
fn worst_of_cases<const N: usize>(
    model: &Model,
    start: &State,
    dt: f64,
    case: usize,
    cases: [(&str, Vec<ImpulseCommand>, Vec<f64>); N],
) -> f64 {
    let mut worst: f64 = 0.0;
    for (name, impulses, du) in cases {
        let act = Actuation {
            impulses,
            ..Actuation::default()
        };
        let end = step(model, start, &act, dt);
        worst = worst.max(check(start, &end, &du, dt, &format!("case {case} {name}")));
    }
    worst
}

fn check(start: &State, end: &State, expected_du: &[f64], dt: f64, what: &str) -> f64 {
    let mut worst: f64 = 0.0;
    for (i, du) in expected_du.iter().enumerate() {
        let expected = start.u[i] + du;
        let err = (end.u[i] - expected).abs();
        assert!(
            err <= 1e-12,
            "{what}: u[{i}] = {}, expected {expected} (error {err:e})",
            end.u[i]
        );
        worst = worst.max(err);
        let q = start.q[i] + 0.5 * dt * (start.u[i] + end.u[i]);
        assert!((end.q[i] - q).abs() <= 1e-12, "{what}: q[{i}]");
    }
    worst
}

/// One body, `q = (x, y, φ)`, `M = diag(m, m, I)`: a point impulse `ζ` at world offset
/// `r` from the centre of mass gives `Δv = ζ/m`, `Δω = (r × ζ)/I`; a rotational impulse
/// `τ` gives `Δω = τ/I`; several impulses in one step add up. Gravity adds `g Δt` to `v_y`.
#[test]
fn single_body_point_and_rotational_impulses() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut worst: f64 = 0.0;
    for case in 0..200 {
        let (m, inertia) = (rng.uniform(0.1, 5.0), rng.uniform(1e-3, 0.5));
        let shape = Shape::Point {
            position: Vec2::new(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2)),
        };
        let model = common::single_body(
            m,
            inertia,
            shape,
            Terrain::flat(0.0),
            common::material(1.0, 0.0),
        );
        let dt = [1e-4, 1e-3, 5e-3][case % 3];
        let q = [
            rng.uniform(-1.0, 1.0),
            rng.uniform(2.0, 3.0),
            rng.uniform(-4.0, 4.0),
        ];
        let u = [
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-10.0, 10.0),
        ];
        let start = common::state(&q, &u);
        let r = Vec2::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
        let zeta = Vec2::new(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
        let tau = rng.uniform(-0.5, 0.5);
        let g = -common::G * dt;
        let point = ImpulseCommand::Point {
            body: 0,
            offset: r,
            impulse: zeta,
        };
        let rotational = ImpulseCommand::Rotational {
            body: 0,
            reaction: None,
            impulse: tau,
        };
        let cases: [(&str, Vec<ImpulseCommand>, [f64; 3]); 4] = [
            ("none", vec![], [0.0, g, 0.0]),
            (
                "point",
                vec![point],
                [zeta.x / m, g + zeta.y / m, cross(r, zeta) / inertia],
            ),
            ("rotational", vec![rotational], [0.0, g, tau / inertia]),
            (
                "both",
                vec![point, rotational],
                [zeta.x / m, g + zeta.y / m, (cross(r, zeta) + tau) / inertia],
            ),
        ];
        let cases = cases.map(|(name, impulses, du)| (name, impulses, du.to_vec()));
        worst = worst.max(worst_of_cases(&model, &start, dt, case, cases));
    }
    println!("single body: worst velocity error {worst:e}");
}

/// Robbit with its disc high above the ground: `q = (x, y, φ, ψ)`, the flywheel on an
/// absolute joint at the disc's centre of mass, so `M = diag(m_S + m_R, m_S + m_R, I_S,
/// I_R)`. The flywheel's Jacobian: position rows `(1, 0, 0, 0)`, `(0, 1, 0, 0)`, angle
/// row `(0, 0, 0, 1)`. A rotational impulse `τ` on the flywheel with its reaction on the
/// disc gives `Δφ̇ = −τ/I_S`, `Δψ̇ = τ/I_R`; without a reaction only `Δψ̇`; a point
/// impulse `ζ` on the flywheel at offset `r` gives `Δv = ζ/(m_S + m_R)`,
/// `Δψ̇ = (r × ζ)/I_R` and leaves `φ̇` alone; on the disc, `Δφ̇ = (r × ζ)/I_S`.
#[test]
fn robbit_flywheel_and_disc_impulses() {
    let model = common::robbit();
    let (m, i_s, i_r) = (0.974 + 0.431, 3.004e-3, 1.543e-3);
    assert_eq!(model.bodies()[0].inertia, i_s);
    assert_eq!(model.bodies()[1].inertia, i_r);
    let mut rng = Rng(0xfeed_beef_cafe_f00d);
    let mut worst: f64 = 0.0;
    for case in 0..200 {
        let dt = [2e-4, 1e-3][case % 2];
        let q = [
            rng.uniform(-1.0, 1.0),
            rng.uniform(2.0, 3.0),
            rng.uniform(-4.0, 4.0),
            rng.uniform(-4.0, 4.0),
        ];
        let u = [
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(-30.0, 30.0),
        ];
        let start = common::state(&q, &u);
        let r = Vec2::new(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
        let zeta = Vec2::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        let tau = rng.uniform(-0.1, 0.1);
        let g = -common::G * dt;
        let cases: [(&str, ImpulseCommand, [f64; 4]); 4] = [
            (
                "rotational with reaction",
                ImpulseCommand::Rotational {
                    body: 1,
                    reaction: Some(0),
                    impulse: tau,
                },
                [0.0, g, -tau / i_s, tau / i_r],
            ),
            (
                "rotational alone",
                ImpulseCommand::Rotational {
                    body: 1,
                    reaction: None,
                    impulse: tau,
                },
                [0.0, g, 0.0, tau / i_r],
            ),
            (
                "point on the flywheel",
                ImpulseCommand::Point {
                    body: 1,
                    offset: r,
                    impulse: zeta,
                },
                [zeta.x / m, g + zeta.y / m, 0.0, cross(r, zeta) / i_r],
            ),
            (
                "point on the disc",
                ImpulseCommand::Point {
                    body: 0,
                    offset: r,
                    impulse: zeta,
                },
                [zeta.x / m, g + zeta.y / m, cross(r, zeta) / i_s, 0.0],
            ),
        ];
        let cases = cases.map(|(name, impulse, du)| (name, vec![impulse], du.to_vec()));
        worst = worst.max(worst_of_cases(&model, &start, dt, case, cases));
    }
    println!("Robbit: worst velocity error {worst:e}");
}

/// Two bodies on an absolute joint with an offset pivot (so `M` is not diagonal), gravity
/// off: the change against the same step without the impulse is `M⁻¹ Jᵀ ζ`, with `M` at
/// the midpoint configuration written out here. Base `(x, y, φ)` with mass `m₀`,
/// inertia `I₀`; child of mass `m₁`, inertia `I₁` pivoting at `p` (base frame) with its
/// centre of mass at the pivot, absolute angle `ψ`. Child CoM `x₁ = x + R(φ) p`, so
/// `J₁ = [[1, 0, −(R p)_y, 0], [0, 1, (R p)_x, 0]]`, angle row `(0, 0, 0, 1)`, and
/// `M = m₀ J₀ᵀJ₀ + I₀ e₃e₃ᵀ + m₁ J₁ᵀJ₁ + I₁ e₄e₄ᵀ`.
#[test]
fn two_body_point_impulse_with_offset_pivot() {
    use hopsim_model::{Joint, JointCoordinate};
    use nalgebra::{DMatrix, DVector};
    let (m0, i0, m1, i1) = (1.1, 0.02, 0.6, 0.004);
    let pivot = Vec2::new(0.07, -0.05);
    let child = Body {
        name: "child".into(),
        mass: m1,
        inertia: i1,
        joint: Some(Joint {
            coordinate: JointCoordinate::Absolute,
            ..Joint::revolute(Some(0), pivot, Vec2::zeros())
        }),
    };
    let model = Model::new(
        vec![Body::base("base", m0, i0), child],
        vec![ShapeInstance {
            name: "tip".into(),
            body: 1,
            shape: Shape::Point {
                position: Vec2::new(0.0, -0.1),
            },
        }],
        Terrain::flat(0.0),
        vec![],
        Vec2::zeros(),
        common::material(1.0, 0.0),
    )
    .unwrap();
    let mut rng = Rng(0x0bad_5eed_1234_4321);
    let mut worst: f64 = 0.0;
    for case in 0..200 {
        let dt = 1e-3;
        let q = [
            rng.uniform(-1.0, 1.0),
            rng.uniform(2.0, 3.0),
            rng.uniform(-4.0, 4.0),
            rng.uniform(-4.0, 4.0),
        ];
        let u = [
            rng.uniform(-2.0, 2.0),
            rng.uniform(-2.0, 2.0),
            rng.uniform(-10.0, 10.0),
            rng.uniform(-10.0, 10.0),
        ];
        let start = common::state(&q, &u);
        // The impulse acts at the midpoint configuration q^M = q^A + Δt/2 u^A.
        let phi_mid = q[2] + 0.5 * dt * u[2];
        let (s, c) = phi_mid.sin_cos();
        let rp = Vec2::new(c * pivot.x - s * pivot.y, s * pivot.x + c * pivot.y);
        let j1 = DMatrix::from_row_slice(2, 4, &[1.0, 0.0, -rp.y, 0.0, 0.0, 1.0, rp.x, 0.0]);
        let j0 = DMatrix::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        let mut mass = j0.transpose() * &j0 * m0 + j1.transpose() * &j1 * m1;
        mass[(2, 2)] += i0;
        mass[(3, 3)] += i1;
        let r = Vec2::new(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
        let zeta = Vec2::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        // Generalised impulse of ζ at offset r on the child: J₁ᵀζ plus (r × ζ) on ψ.
        let mut gen = j1.transpose() * DVector::from_row_slice(&[zeta.x, zeta.y]);
        gen[3] += cross(r, zeta);
        let du = mass.clone().lu().solve(&gen).unwrap();
        // Cross-check the solve: M Δu = Jᵀ ζ.
        assert!((&mass * &du - &gen).amax() < 1e-14);
        let act = Actuation {
            impulses: vec![ImpulseCommand::Point {
                body: 1,
                offset: r,
                impulse: zeta,
            }],
            ..Actuation::default()
        };
        let end = step(&model, &start, &act, dt);
        // h (the pivot's velocity-product term) acts in both steps: the step is linear
        // in the impulse, so u^E − u^E(no impulse) = M⁻¹ Jᵀ ζ.
        let free = step(&model, &start, &Actuation::default(), dt);
        let mut diff = [0.0; 4];
        for i in 0..4 {
            diff[i] = du[i] + (free.u[i] - start.u[i]);
        }
        worst = worst.max(check(&start, &end, &diff, dt, &format!("case {case}")));
    }
    println!("two bodies: worst velocity error {worst:e}");
}
