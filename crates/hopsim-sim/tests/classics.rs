//! The classic gallery scenes (`scenes/classic/`) against their closed forms
//! (docs/classics.md §2, §3; docs/physics.md §7): a pendulum pinned to the world hitting a joint
//! stop, and a point-foot hopper on a prismatic spring leg. Each result is checked at the
//! scene's step and at a coarser one, against a tolerance proportional to `Δt` fitted to
//! the measured errors: the scheme is first order (docs/physics.md §4.6), so an error that did
//! not shrink with `Δt` fails.

mod common;

use common::{sampled, scene, starts};
use hopsim_sim::StepView;

/// What one step left behind.
struct Sample {
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    /// Sum of the contacts' normal percussions, N s.
    contact_impulse: f64,
    /// Sum of the joint stops' percussions (N s or N m s).
    limit_impulse: f64,
    contact_work: f64,
    limit_work: f64,
}

impl Sample {
    fn of(v: &StepView<'_>) -> Self {
        Sample {
            t: v.state.t,
            q: v.state.q.as_slice().to_vec(),
            u: v.state.u.as_slice().to_vec(),
            contact_impulse: v.record.contacts.iter().map(|c| c.impulse_normal).sum(),
            limit_impulse: v.record.limits.iter().map(|l| l.impulse).sum(),
            contact_work: v.record.energy.contact_work,
            limit_work: v.record.energy.limit_work,
        }
    }
}

/// Runs the gallery scene `name` with overrides and returns every step's sample.
fn run(name: &str, overrides: &[&str]) -> (Vec<Sample>, f64) {
    let scene = scene(&format!("classic/{name}"), overrides);
    (sampled(&scene, Sample::of), scene.settings.dt)
}

/// `|found − expected| ≤ per_dt Δt`, with a message naming the quantity.
fn check(what: &str, found: f64, expected: f64, per_dt: f64, dt: f64, failures: &mut Vec<String>) {
    let error = (found - expected).abs();
    if error > per_dt * dt {
        failures.push(format!(
            "{what} at Δt = {dt:e}: {found:.7} vs {expected:.7} (error {error:.2e} > {:.2e})",
            per_dt * dt
        ));
    }
}

/// The complete elliptic integral of the first kind `K(k)`, by the arithmetic–geometric
/// mean: `K = π / (2 AGM(1, √(1 − k²)))`.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-15 * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// docs/classics.md §3: a uniform rod (1 kg, 1 m) pinned at one end, released at rest from
/// 90° onto a stop at θ = 0 with ε = 0.5. Closed forms, with `Ω² = m g d / I_O`:
/// `ω⁻ = −√(2 Ω² (cos θ_s − cos θ₀))`, `ω⁺ = −ε ω⁻`,
/// `cos θ₁ = cos θ_s − ε² (cos θ_s − cos θ₀)`; for the stop at 0 the n-th rebound peak
/// has `1 − cos θ_n = ε^{2n} (1 − cos θ₀)`, the release-to-impact time is
/// `K(sin(θ₀/2))/Ω` and the time between impacts `n` and `n + 1` is `2 K(sin(θ_n/2))/Ω`;
/// three quarters (`1 − ε²`) of the energy is lost at the first impact.
#[test]
fn pendulum_rebounds_from_its_joint_stop_as_the_closed_form_says() {
    let (m, g, d, inertia, eps) = (1.0f64, 9.81f64, 0.5f64, 1.0f64 / 3.0, 0.5f64);
    let theta0 = std::f64::consts::FRAC_PI_2;
    let omega2 = m * g * d / inertia;
    let rebound = |stop: f64| 2.0 * omega2 * (stop.cos() - theta0.cos());
    let peak_after = |stop: f64| (stop.cos() - eps * eps * (stop.cos() - theta0.cos())).acos();
    let mut failures = Vec::new();
    for dt in [1e-4, 4e-4] {
        let (samples, dt) = run("pendulum-stop.toml", &[&format!("simulation.dt={dt}")]);
        let hits = starts(&samples, |s| s.limit_impulse > 0.0);
        assert!(hits.len() >= 5, "{} stop hits", hits.len());
        let first = &samples[hits[0]];
        let omega_after = eps * rebound(0.0).sqrt();
        check(
            "ω⁺ (rad/s)",
            first.u[0],
            omega_after,
            1e-3,
            dt,
            &mut failures,
        );
        // Impact times: the impact step ends at most Δt after the impact.
        let to_first = elliptic_k((0.5 * theta0).sin()) / omega2.sqrt();
        check(
            "first impact (s)",
            first.t,
            to_first,
            1.5,
            dt,
            &mut failures,
        );
        let peaks: Vec<f64> = (1..=4)
            .map(|n| (1.0 - eps.powi(2 * n) * (1.0 - theta0.cos())).acos())
            .collect();
        let between = 2.0 * elliptic_k((0.5 * peaks[0]).sin()) / omega2.sqrt();
        let found = samples[hits[1]].t - first.t;
        check("impact 1 → 2 (s)", found, between, 1.5, dt, &mut failures);
        for (n, window) in hits.windows(2).take(4).enumerate() {
            let peak = samples[window[0]..window[1]]
                .iter()
                .map(|s| s.q[0])
                .fold(f64::NEG_INFINITY, f64::max);
            check(
                &format!("rebound peak {} (rad)", n + 1),
                peak,
                peaks[n],
                1e-3,
                dt,
                &mut failures,
            );
        }
        // The stop's work at the first impact: −(1 − ε²) of E₀ = m g d (1 − cos θ₀).
        let lost = samples[hits[0] - 1].limit_work - first.limit_work;
        let e0 = m * g * d * (1.0 - theta0.cos());
        check(
            "impact 1 loss / E₀",
            lost / e0,
            1.0 - eps * eps,
            1e-3,
            dt,
            &mut failures,
        );
        // A stop at −30°: the impact step starts up to Δt before the impact, where gravity
        // still accelerates the rod (|θ̈| = Ω² sin 30°), and its midpoint is up to
        // |ω| Δt/2 past the stop, which shifts θ₁ by up to (1 − ε²) sin 30° |ω| Δt / sin θ₁
        // (≈ 2.5 rad/s × Δt, 143°/s × Δt).
        let stop = -std::f64::consts::FRAC_PI_6;
        let (samples, dt) = run(
            "pendulum-stop.toml",
            &[
                &format!("simulation.dt={dt}"),
                "simulation.duration=2.0",
                &format!("bodies.rod.limits=[{stop}, 3.0]"),
            ],
        );
        let hits = starts(&samples, |s| s.limit_impulse > 0.0);
        let first = &samples[hits[0]];
        let omega_after = eps * rebound(stop).sqrt();
        check(
            "offset stop ω⁺ (rad/s)",
            first.u[0],
            omega_after,
            3.0,
            dt,
            &mut failures,
        );
        let end = hits.get(1).copied().unwrap_or(samples.len());
        let peak = samples[hits[0]..end]
            .iter()
            .map(|s| s.q[0])
            .fold(f64::NEG_INFINITY, f64::max);
        check(
            "offset stop θ₁ (rad)",
            peak,
            peak_after(stop),
            2.5,
            dt,
            &mut failures,
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// docs/classics.md §2: a 1 kg body on a 1000 N/m prismatic spring leg (rest length and
/// stop 0.5 m) with a point foot of 0.01 kg (the scene) and 0.05 kg, dropped from 0.1 m foot
/// clearance. Closed forms: stance `[π + 2 arctan(g/(ω v))]/ω`, maximum compression
/// `mg/k + √((mg/k)² + v²/ω²)`, flight `2 v'/g` with `v' = m v/(m + m_f)` after the plastic
/// stop at lift-off, apex clearance ×`(m/(m + m_f))²` per hop; touchdown loss `½ m_f v²`,
/// lift-off loss `½ v² m m_f/(m + m_f)`.
#[test]
fn spring_legged_hopper_hops_as_the_spring_mass_closed_form_says() {
    let mut failures = Vec::new();
    for (m_f, dt) in [(0.01, 1e-5), (0.01, 4e-5), (0.05, 1e-5), (0.05, 4e-5)] {
        hopper_against_closed_forms(m_f, dt, &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Bound on the compression error per unit step, m/s (measured: 0.26 and 0.27 m/s × Δt at
/// Δt = 1e-5 and 4e-5 s, either foot mass).
const COMPRESSION_PER_DT: f64 = 0.35;

/// The checks of [`spring_legged_hopper_hops_as_the_spring_mass_closed_form_says`] for one
/// foot mass `m_f` and step `dt`.
fn hopper_against_closed_forms(m_f: f64, dt: f64, failures: &mut Vec<String>) {
    let (m, k, rest, g) = (1.0f64, 1000.0f64, 0.5f64, 9.81f64);
    let omega = (k / m).sqrt();
    let ratio = m / (m + m_f);
    // Touchdown speeds of hops 1–3, and what follows from them.
    let v: Vec<f64> = (0..3)
        .map(|n| (2.0 * g * 0.1).sqrt() * ratio.powi(n))
        .collect();
    let stance = |v: f64| (std::f64::consts::PI + 2.0 * (g / (omega * v)).atan()) / omega;
    let compression = |v: f64| m * g / k + ((m * g / k).powi(2) + (v / omega).powi(2)).sqrt();
    let label = |what: String| format!("m_f = {m_f} kg: {what}");
    // The impacts' losses and the apexes depend on where in its step the foot lands or the
    // stop closes: errors of the order of the foot's momentum change in one step. Bounds:
    // losses `2 m_f v g Δt` (measured ≤ 0.14 and 0.65 W × Δt for m_f = 0.01 and 0.05 kg),
    // apexes `6 m_f Δt` m/s (measured ≤ 0.03 and 0.2 m/s × Δt).
    let loss_per_dt = 2.0 * m_f * v[0] * g;
    let apex_per_dt = 6.0 * m_f;
    {
        let overrides = [
            format!("simulation.dt={dt}"),
            format!("bodies.foot.mass={m_f}"),
        ];
        let (samples, dt) = run("hopper.toml", &[&overrides[0], &overrides[1]]);
        let loaded = |s: &Sample| s.contact_impulse > 0.0;
        let touchdowns = starts(&samples, loaded);
        let take_offs = starts(&samples, |s| !loaded(s))
            .into_iter()
            .filter(|&i| i > touchdowns[0])
            .collect::<Vec<_>>();
        assert!(touchdowns.len() >= 3 && take_offs.len() >= 3);
        for hop in 0..3 {
            let (td, to) = (touchdowns[hop], take_offs[hop]);
            // Stance: from the end of the touchdown step to the end of the last loaded one.
            let stance_found = samples[to - 1].t - samples[td].t;
            check(
                &label(format!("stance {} (s)", hop + 1)),
                stance_found,
                stance(v[hop]),
                1.5,
                dt,
                failures,
            );
            // The leg's shortest length in the stance (the foot rests on the ground).
            let shortest = samples[td..to]
                .iter()
                .map(|s| s.q[3])
                .fold(f64::INFINITY, f64::min);
            check(
                &label(format!("compression {} (m)", hop + 1)),
                rest - shortest,
                compression(v[hop]),
                COMPRESSION_PER_DT,
                dt,
                failures,
            );
            let touchdown_loss = samples[td - 1].contact_work - samples[td].contact_work;
            check(
                &label(format!("touchdown loss {} (J)", hop + 1)),
                touchdown_loss,
                0.5 * m_f * v[hop].powi(2),
                loss_per_dt,
                dt,
                failures,
            );
            let stop_loss = samples[to - 5].limit_work - samples[to + 5].limit_work;
            check(
                &label(format!("lift-off stop loss {} (J)", hop + 1)),
                stop_loss,
                0.5 * v[hop].powi(2) * m * m_f / (m + m_f),
                loss_per_dt,
                dt,
                failures,
            );
            if hop + 1 < touchdowns.len() {
                let next = touchdowns[hop + 1];
                let flight = samples[next].t - samples[to - 1].t;
                check(
                    &label(format!("flight {} (s)", hop + 1)),
                    flight,
                    2.0 * ratio * v[hop] / g,
                    2.5,
                    dt,
                    failures,
                );
                let apex = samples[to..next]
                    .iter()
                    .map(|s| s.q[1])
                    .fold(f64::NEG_INFINITY, f64::max);
                let clearance = 0.1 * ratio.powi(2 * (hop as i32 + 1));
                check(
                    &label(format!("apex {} (m)", hop + 1)),
                    apex,
                    rest + clearance,
                    apex_per_dt,
                    dt,
                    failures,
                );
            }
        }
        // The body stays upright and in place: no rotation, no drift.
        let drift = samples
            .iter()
            .map(|s| s.q[0].abs().max(s.q[2].abs()))
            .fold(0.0, f64::max);
        assert!(drift < 1e-12, "x or φ moved by {drift:e}");
    }
}
