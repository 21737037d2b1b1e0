//! Gallery scenes with contacts between bodies and the Painlevé paradox
//! (docs/classics.md §1, §4, §5, §6; docs/physics.md §7): Newton's cradle of 3 and 5 balls
//! against Moreau's simultaneous impact law and, with gaps between the balls, against
//! sequential binary collisions; Painlevé's rod above the critical friction against the
//! closed-form solution of its one-step LCP; the slider–crank with clearance against an
//! independent re-implementation of the step; the woodpecker toy's limit cycle, impacts and
//! jam angle.

mod common;

use common::{sampled, scene, starts};
use hopsim_sim::{Simulation, StepView};

/// What one step left behind.
struct Sample {
    /// Time at the end of the step, s.
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    /// Body–body contacts of the step's index set: `(index into Model::pairs, Λ_N)`.
    pairs: Vec<(usize, f64)>,
    /// Terrain contacts: `(Λ_N, Λ_T)` of each.
    contacts: Vec<(f64, f64)>,
    lcp_failed: bool,
}

impl Sample {
    /// Largest body–body normal percussion of the step, N s.
    fn pair_impulse(&self) -> f64 {
        self.pairs.iter().map(|p| p.1).fold(0.0, f64::max)
    }

    /// Whether the body–body contact `pair` is in the step's index set.
    fn touches(&self, pair: usize) -> bool {
        self.pairs.iter().any(|p| p.0 == pair)
    }
}

impl Sample {
    fn of(v: &StepView<'_>) -> Self {
        Sample {
            t: v.state.t,
            q: v.state.q.as_slice().to_vec(),
            u: v.state.u.as_slice().to_vec(),
            pairs: v
                .record
                .pair_contacts
                .iter()
                .map(|c| (c.contact, c.impulse_normal))
                .collect(),
            contacts: v
                .record
                .contacts
                .iter()
                .map(|c| (c.impulse_normal, c.impulse_tangent))
                .collect(),
            lcp_failed: v.record.lcp_failed,
        }
    }
}

/// Runs the gallery scene `name` with overrides to its end: every step's sample, and the
/// initial velocities.
fn run(name: &str, overrides: &[&str]) -> (Vec<Sample>, Vec<f64>) {
    let scene = scene(&format!("classic/{name}"), overrides);
    (
        sampled(&scene, Sample::of),
        scene.initial.u.as_slice().to_vec(),
    )
}

/// The balls' `x` velocities (every third generalised velocity).
fn x_velocities(u: &[f64]) -> Vec<f64> {
    u.iter().step_by(3).copied().collect()
}

/// docs/classics.md §1: with the inner gaps exactly zero every ball–ball contact is in the
/// impact step's LCP, and Moreau's law gives `Λ_i = (1 + ε) m v (n − i)/n`,
/// `u₁⁺ = v [1 − (n − 1)(1 + ε)/n]`, `u_k⁺ = (1 + ε) v/n` in one step; momentum is kept
/// and `T⁺/T⁻ = 1 − (1 − ε²)(n − 1)/n`. The LCP is solved to round-off: measured errors
/// ≤ 2.8e-16 v over all eight cases; the bound is 1e-9 v.
#[test]
fn cradle_follows_moreaus_simultaneous_impact_law() {
    let v = 1.0;
    for n in [3usize, 5] {
        for eps in [1.0, 0.9, 0.5, 0.0] {
            let (samples, u0) = run(
                &format!("cradle-{n}.toml"),
                &[&format!("body_contacts.restitution={eps}")],
            );
            assert_eq!(u0[0], v);
            let impacts: Vec<usize> = (0..samples.len())
                .filter(|&i| samples[i].pair_impulse() > 1e-12)
                .collect();
            assert_eq!(
                impacts.len(),
                1,
                "n = {n}, ε = {eps}: impact steps {impacts:?}"
            );
            let nf = n as f64;
            let mut expected = vec![(1.0 + eps) * v / nf; n];
            expected[0] = v * (1.0 - (nf - 1.0) * (1.0 + eps) / nf);
            // Right after the impact and at the end of the run (no later impact).
            for u in [&samples[impacts[0]].u, &samples[samples.len() - 1].u] {
                let found = x_velocities(u);
                for (k, (f, e)) in found.iter().zip(&expected).enumerate() {
                    assert!(
                        (f - e).abs() < 1e-9 * v,
                        "n = {n}, ε = {eps}: u{} = {f} vs {e}",
                        k + 1
                    );
                }
                let momentum: f64 = found.iter().sum();
                assert!((momentum - v).abs() < 1e-12, "momentum {momentum}");
                let ratio: f64 = found.iter().map(|u| u * u).sum::<f64>() / (v * v);
                let expected_ratio = 1.0 - (1.0 - eps * eps) * (nf - 1.0) / nf;
                assert!((ratio - expected_ratio).abs() < 1e-9, "T⁺/T⁻ {ratio}");
            }
        }
    }
}

/// docs/classics.md §1, sequential model: with gaps `δ = 1/512 m > vΔt` between the
/// resting balls every collision is binary, and equal masses give
/// `u_i, u_j ← (u_i + u_j)/2 ∓ ε (u_i − u_j)/2` per collision: "one ball out" for `ε = 1`
/// (`n − 1` collisions), and for `n = 3`, `ε = 0.9` after the late third collision
/// `(0.047625, 0.049875, 0.9025) v`. Each binary collision is exact to round-off
/// (measured ≤ 4.2e-17 v; bound 1e-9 v).
#[test]
fn cradle_with_gaps_collides_ball_by_ball() {
    let gap = 1.0 / 512.0;
    for (n, eps, collisions, expected) in [
        (3usize, 1.0, 2usize, vec![0.0, 0.0, 1.0]),
        (5, 1.0, 4, vec![0.0, 0.0, 0.0, 0.0, 1.0]),
        (3, 0.9, 3, vec![0.047625, 0.049875, 0.9025]),
    ] {
        // Balls 2…n at x = (k − 2)(2R + δ), 2R = 1/8 m, ball 1 as in the scene.
        let positions: Vec<String> = (2..=n)
            .map(|k| {
                format!(
                    "initial.q.{}={}",
                    3 * (k - 1),
                    (k as f64 - 2.0) * (0.125 + gap)
                )
            })
            .collect();
        let mut overrides: Vec<&str> = positions.iter().map(String::as_str).collect();
        let restitution = format!("body_contacts.restitution={eps}");
        overrides.push(&restitution);
        overrides.push("simulation.duration=2.0");
        let (samples, _) = run(&format!("cradle-{n}.toml"), &overrides);
        let impacts = (0..samples.len())
            .filter(|&i| samples[i].pair_impulse() > 1e-12)
            .count();
        assert_eq!(impacts, collisions, "n = {n}, ε = {eps}");
        let found = x_velocities(&samples[samples.len() - 1].u);
        for (k, (f, e)) in found.iter().zip(&expected).enumerate() {
            assert!(
                (f - e).abs() < 1e-9,
                "n = {n}, ε = {eps}: u{} = {f} vs {e}",
                k + 1
            );
        }
    }
}

/// docs/classics.md §5: a uniform rod (m = 1 kg, half-length l = 0.5 m) at θ = 60° with
/// its lower end on a floor with μ = 2 > μ_c(60°) = (1 + 3cos²θ)/(3 sinθ cosθ) = 1.347,
/// sliding at `v_s` = 1 m/s away from the centre of mass's side. There is no sliding
/// solution; the step's LCP has exactly one solution, sticking, with
/// `Λ_N = (m/4)[(1 + 3s²) g Δt + 3 s c v_s]`, `Λ_T = (m/4)[3 s c g Δt + (1 + 3c²) v_s]`:
/// an impact without collision (`γ_N^A = 0`, `Λ_N ≫ m g Δt`) that stops the end, the
/// kinetic energy falling to 0.278073 J at Δt = 1e-3 s. The stepper (strict: an LCP without
/// a certified solution would stop the run) reports that solution, at two step sizes.
/// Below μ_c (μ = 1) the same step is ordinary sliding,
/// `Λ_N = m g Δt / (1 + 3c² − 3 μ s c)`, `Λ_T = μ Λ_N`.
#[test]
fn painleves_rod_above_the_critical_friction_stops_by_a_tangential_impact() {
    let (m, g, v_s) = (1.0f64, 9.81f64, 1.0f64);
    let theta = std::f64::consts::FRAC_PI_3;
    let (s, c) = theta.sin_cos();
    let mu_c = (1.0 + 3.0 * c * c) / (3.0 * s * c);
    assert!(2.0 > mu_c && 1.0 < mu_c);
    for dt in [1e-3, 1e-5] {
        let (samples, _) = run(
            "painleve.toml",
            &[&format!("simulation.dt={dt}"), "simulation.duration=0.01"],
        );
        let first = &samples[0];
        assert!(!first.lcp_failed);
        let (lambda_n, lambda_t) = first.contacts[0];
        let expected_n = m / 4.0 * ((1.0 + 3.0 * s * s) * g * dt + 3.0 * s * c * v_s);
        let expected_t = m / 4.0 * (3.0 * s * c * g * dt + (1.0 + 3.0 * c * c) * v_s);
        // Solved to round-off (measured ≤ 1.1e-16 N s at both Δt; bound 1e-9 N s); the
        // start's 2e-12 m overlap does not enter the velocities.
        assert!(
            (lambda_n - expected_n).abs() < 1e-9,
            "Λ_N {lambda_n} vs {expected_n}"
        );
        assert!(
            (lambda_t - expected_t).abs() < 1e-9,
            "Λ_T {lambda_t} vs {expected_t}"
        );
        assert!(lambda_n > 30.0 * m * g * dt, "an impact: Λ_N = {lambda_n}");
        // The end A has stopped: x-velocity of A = u_x + l sin θ θ̇ (θ unchanged at q^M).
        let u = &first.u;
        let slip = u[0] + 0.5 * s * u[2];
        assert!(slip.abs() < 1e-12, "slip after the step {slip}");
        if dt == 1e-3 {
            let kinetic = 0.5 * m * (u[0] * u[0] + u[1] * u[1]) + 0.5 / 12.0 * u[2] * u[2];
            assert!(
                (kinetic - 0.278073).abs() < 1e-6,
                "kinetic energy {kinetic}"
            );
        }
        assert!(samples.iter().all(|s| !s.lcp_failed));
    }
    // Below the critical friction: sliding continues.
    let dt = 1e-3;
    let (samples, _) = run(
        "painleve.toml",
        &["environment.friction=1.0", "simulation.duration=0.01"],
    );
    let (lambda_n, lambda_t) = samples[0].contacts[0];
    let expected_n = m * g * dt / (1.0 + 3.0 * c * c - 3.0 * s * c);
    assert!(
        (lambda_n - expected_n).abs() < 1e-12,
        "Λ_N {lambda_n} vs {expected_n}"
    );
    assert!(
        (lambda_t - lambda_n).abs() < 1e-12,
        "Λ_T {lambda_t} = μ Λ_N"
    );
    let u = &samples[0].u;
    assert!(u[0] + 0.5 * s * u[2] < -0.9, "still sliding");
}

/// docs/classics.md §5, Glocker's example: μ = 5/3 below μ_c(31°) = 2.419, the rod
/// slides lower end leading and friction turns it up. Against the contact-maintained
/// sliding ODE (RK4 to 1e-6, docs/classics.md, given to 1e-6 m and 1e-5°): CoM `x` and
/// `θ` at 0.2, 0.4, 0.6 s, at Δt = 1e-3 and 5e-4 s. Measured errors: x ≤ 1.7e-5 m and
/// θ ≤ 1.1e-4° at 1e-3 s, x ≤ 1.9e-5 m and θ ≤ 3.5e-5° at 5e-4 s (relative 1.3e-6 and
/// 3.3e-6, near the reference's own rounding and integration error); the bounds are 5e-5 m
/// and 3e-4°.
#[test]
fn glockers_painleve_rod_slides_as_the_sliding_ode_says() {
    let reference = [
        (0.2, -5.665386, 31.05139f64),
        (0.4, -10.657887, 31.35369),
        (0.6, -14.954702, 32.83548),
    ];
    for dt in [1e-3f64, 5e-4] {
        let scene = scene(
            "classic/painleve-glocker.toml",
            &[&format!("simulation.dt={dt}"), "simulation.duration=0.6"],
        );
        let samples = sampled(&scene, Sample::of);
        for (t, x, theta_deg) in reference {
            let (found_x, found_theta) = samples
                .iter()
                .find(|s| (s.t - t).abs() < 0.5 * dt)
                .map(|s| (s.q[0], s.q[2]))
                .unwrap();
            let (ex, et) = (
                (found_x - x).abs(),
                (found_theta.to_degrees() - theta_deg).abs(),
            );
            assert!(
                ex < 5e-5 && et < 3e-4,
                "Δt = {dt}, t = {t}: x {found_x} (error {ex:.2e}), θ {}° (error {et:.2e})",
                found_theta.to_degrees()
            );
        }
        // Sliding all along: no LCP fails, the end stays on the floor.
        assert!(samples.iter().all(|s| !s.lcp_failed));
        // At most one step whose midpoint gap rounds above zero.
        let open = samples.iter().filter(|s| s.contacts.is_empty()).count();
        assert!(open <= 1, "{open} steps without contact");
    }
}

/// docs/classics.md §4: the slider–crank with a translational clearance joint (Flores,
/// Leine & Glocker 2010), the slider's box against the guide's walls (two fixed bodies)
/// through body–body contacts. Against the independent §4 re-implementation at the same
/// Δt = 1e-5 s (given to 7 significant digits): E(0.2 s) = 6.923449 J, 2.87152 crank
/// revolutions, ω₁(0.2 s) = 68.869 rad/s; the slider stays parallel to the guide (θ₃ ≡ 0 by
/// symmetry). Measured: |ΔE| = 3.9e-7 J, revolutions 2.871520, ω₁ = 68.86895 rad/s,
/// |θ₃| ≤ 1e-12 rad; the bounds are the references' last digit.
#[test]
fn slider_crank_with_clearance_matches_the_reference_step() {
    let scene = scene("classic/slider-crank.toml", &[]);
    let mut sim = Simulation::new(&scene);
    let mut theta3 = 0.0f64;
    let steps = (scene.settings.duration / scene.settings.dt).round() as u64;
    for _ in 0..steps {
        sim.step(&mut ()).expect("step");
        theta3 = theta3.max(sim.state().q[2].abs());
    }
    assert_eq!(sim.stepper().lcp_stats().failures, 0);
    let view = sim.view();
    let energy = view.record.energy.kinetic + view.record.energy.potential;
    let q = sim.state().q.as_slice();
    let revolutions = q[0] / std::f64::consts::TAU;
    assert!((energy - 6.923449).abs() < 1e-5, "E(0.2 s) = {energy}");
    assert!(
        (revolutions - 2.87152).abs() < 1e-4,
        "{revolutions} revolutions"
    );
    assert!(
        (sim.state().u[0] - 68.869).abs() < 1e-3,
        "ω₁ = {}",
        sim.state().u[0]
    );
    assert!(theta3 < 1e-9, "|θ₃| up to {theta3}");
}

/// docs/classics.md §6: the woodpecker toy with exact planar kinematics (a sleeve on a
/// prismatic joint along the pole, turning on a revolute joint; the bird on a sprung revolute
/// joint; the beak and the sleeve's two bird-side corners as points against the pole's face
/// `x = r_O`), from Leine's initial state, 2 s at Δt = 2e-5 s.
///
/// - Limit cycle, averaged over the 11 cycles from the first beak impact after the
///   transient (0.4 s; at 0.52772 s) to the last one (1.96690 s): period and descent per
///   cycle against the independent §4 re-implementation of the same geometry over the same
///   cycles (`tests/classics/reference/woodpecker_nl.py 2.0`: 0.130834545 s and
///   0.014542898 m; docs/classics.md gives 0.1308 s and 0.01454 m). Its beak impacts fall
///   on the same steps as hopsim's, so the measured errors are 0 s and 8.6e-9 m. An impact
///   one step earlier or later at either end would move the means by `Δt/11` and
///   `|ẏ| Δt/11` (`|ẏ| ≈ 0.22 m/s`): the bounds are `2Δt/11` = 3.6e-6 s (0.003 %) and
///   1e-6 m (0.007 %).
/// - One beak impact per cycle (a cycle: from one upward zero crossing of `φ_S` to the
///   next), and at each beak impact Newton's law with `ε = 0.5`: the beak's normal velocity
///   at the step's end is `−0.5` times that at its start, both taken at the step's midpoint
///   configuration (only the beak is closed then). Measured to 4e-14 m/s (of 0.296 m/s);
///   bound 1e-9 m/s.
/// - The sleeve jams where a corner reaches the pole's face: `r_M cos φ_M ± h_M sin φ_M = r_O`,
///   `|φ_M| = acos(r_O / √(r_M² + h_M²)) − atan2(h_M, r_M) = 0.100901 rad` (the linearised
///   model's `(r_M − r_O)/h_M = 0.103448 rad` is its small-angle value). With `ε = 0` the
///   corner's normal velocity ends at zero, so the step that closes it leaves `|φ_M|` past
///   the jam angle, by less than the angle turned in one step, `|ω_M| Δt`; measured past by
///   1.8e-6 to 2.9e-4 rad, each within its step's `|ω_M| Δt` (1.2e-4 to 4.4e-4 rad).
#[test]
fn woodpecker_descends_on_its_limit_cycle() {
    // Published geometry (docs/classics.md §6), m.
    let (r_o, r_m, h_m) = (0.0025f64, 0.0031f64, 0.0058f64);
    let (l_m, l_g, l_s, h_s) = (0.010f64, 0.015f64, 0.0201f64, 0.02f64);
    let (period_ref, descent_ref, transient) = (0.130834545, 0.014542898, 0.4);
    let scene = scene("classic/woodpecker.toml", &[]);
    let dt = scene.settings.dt;
    let pair = |probe: &str| {
        let name = format!("{probe}/pole");
        scene
            .model
            .pairs()
            .iter()
            .position(|p| p.name == name)
            .unwrap_or_else(|| panic!("no contact {name}"))
    };
    let (beak, corners) = (pair("beak"), [pair("lower_corner"), pair("upper_corner")]);
    let (samples, _) = run("woodpecker.toml", &[]);
    assert!(samples.iter().all(|s| !s.lcp_failed));

    // The limit cycle: beak impacts (the first step of each run with the beak closed).
    let impacts: Vec<usize> = starts(&samples, |s| s.touches(beak))
        .into_iter()
        .filter(|&i| samples[i].t > transient)
        .collect();
    let cycles = impacts.len() - 1;
    assert_eq!(cycles, 11, "cycles after the transient");
    let (first, last) = (&samples[impacts[0]], &samples[impacts[cycles]]);
    let period = (last.t - first.t) / cycles as f64;
    let descent = (first.q[0] - last.q[0]) / cycles as f64;
    assert!(
        (period - period_ref).abs() < 2.0 * dt / cycles as f64,
        "period {period} s vs {period_ref} s"
    );
    assert!(
        (descent - descent_ref).abs() < 1e-6,
        "descent {descent} m per cycle vs {descent_ref} m"
    );

    // One beak impact per cycle, each following Newton's law with ε = 0.5.
    let rising = starts(&samples, |s| s.q[2] > 0.0);
    for w in rising.windows(2).filter(|w| samples[w[0]].t > transient) {
        let inside = impacts.iter().filter(|&&i| w[0] <= i && i < w[1]).count();
        assert_eq!(inside, 1, "beak impacts from t = {} s", samples[w[0]].t);
    }
    for &i in &impacts {
        let (before, after) = (&samples[i - 1], &samples[i]);
        // Midpoint angles and the beak's x velocity there (the pole's normal is +x).
        let phi_m = before.q[1] + 0.5 * dt * before.u[1];
        let phi_s = before.q[2] + 0.5 * dt * before.u[2];
        let normal_velocity = |u: &[f64]| {
            -l_m * phi_m.sin() * u[1] - ((l_g - l_s) * phi_s.sin() + h_s * phi_s.cos()) * u[2]
        };
        let (gamma_a, gamma_e) = (normal_velocity(&before.u), normal_velocity(&after.u));
        assert!(
            gamma_a < 0.0 && after.pairs.len() == 1,
            "t = {} s: {:?}",
            after.t,
            after.pairs
        );
        assert!(
            (gamma_e + 0.5 * gamma_a).abs() < 1e-9,
            "t = {} s: beak γ_N {gamma_a} → {gamma_e} m/s",
            after.t
        );
    }

    // The sleeve jams at the exact angle, within one step's rotation.
    let jam = (r_o / r_m.hypot(h_m)).acos() - h_m.atan2(r_m);
    assert!((jam - 0.100901).abs() < 1e-6);
    let mut jams = 0;
    for &corner in &corners {
        for i in starts(&samples, |s| s.touches(corner)) {
            let past = samples[i].q[1].abs() - jam;
            let turned = samples[i - 1].u[1].abs() * dt;
            assert!(
                (-1e-12..=turned).contains(&past),
                "t = {} s: |φ_M| = {} rad, {past:e} rad past the jam angle (one step: {turned:e})",
                samples[i].t,
                samples[i].q[1].abs()
            );
            jams += 1;
        }
    }
    assert!(jams >= 2 * cycles, "{jams} jams");
}
