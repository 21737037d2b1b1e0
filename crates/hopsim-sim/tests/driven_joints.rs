//! A pulse controller driving a prismatic joint (docs/scene-format.md `[controller]`,
//! docs/physics.md §7): its force acts along the axis with the reaction on the parent, and
//! the motion matches the closed form of a constant force switched on a step grid.

mod common;

use common::sampled;
use hopsim_scene::Scene;
use hopsim_sim::{Observer, RunError, StepView};
use std::path::Path;

/// A slider of mass `m` on a horizontal prismatic joint, driven by a pulse of `force` N for
/// `τ` = 0.05 s, then `−force` for `τ`, every `P` = 0.25 s; `parent` is the parent body's
/// table (a fixed rail, or a floating cart).
fn slider_scene(parent: &str, overrides: &[&str]) -> Scene {
    let text = format!(
        r#"
[simulation]
duration = 1.0
dt = 1e-3
gravity = 0.0

{parent}

[[bodies]]
name = "slider"
parent = "rail"
joint = "prismatic"
axis = [1.0, 0.0]
mass = 2.0
inertia = 0.01

[controller]
type = "pulse"
joint = "slider"
force = 3.0
pulse_duration = 0.05
period = 0.25
"#
    );
    let overrides: Vec<_> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::parse(&text, Path::new("slider.toml"), &overrides).unwrap()
}

/// One step's time, state, kinetic energy, actuator work and commanded force.
struct Sample {
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    kinetic: f64,
    work: f64,
    commanded: f64,
}

impl Sample {
    fn of(v: &StepView<'_>) -> Self {
        let e = &v.record.energy;
        Sample {
            t: v.state.t,
            q: v.state.q.as_slice().to_vec(),
            u: v.state.u.as_slice().to_vec(),
            kinetic: e.kinetic,
            work: e.actuator_work,
            commanded: v.torque,
        }
    }
}

fn run(scene: &Scene) -> Vec<Sample> {
    sampled(scene, Sample::of)
}

/// Under a constant force `F` on the relative coordinate with reduced mass `μ` the midpoint
/// scheme is exact (the velocity is linear in time and `q^E = q^A + Δt (u^A + u^E)/2`), and
/// the pulse switches on the step grid (`Δt` divides `τ` and `P`). From rest:
/// `s(kP + τ) = k F τ²/μ + F τ²/(2μ)`, `ṡ = F τ/μ`, and at `(k + 1) P` the slider rests again
/// at `s = (k + 1) F τ²/μ`; the actuator's work `F τ² F/(2μ)` at the end of the push is the
/// kinetic energy, and the pull takes it back. A fixed rail: `μ = m`; a floating cart of
/// mass `M` (no gravity): `μ = m M/(m + M)`, and the total momentum stays zero.
#[test]
fn a_pulse_on_a_prismatic_joint_moves_the_slider_as_the_closed_form_says() {
    let (force, tau, period, m) = (3.0f64, 0.05f64, 0.25f64, 2.0f64);
    let rail = "[[bodies]]\nname = \"rail\"\nbase = \"fixed\"\nposition = [0.0, 1.0]\n\n[initial]\nq = [0.0]";
    let cart = "[[bodies]]\nname = \"rail\"\nmass = 6.0\ninertia = 0.5\n\n[initial]\nq = [0.0, 1.0, 0.0, 0.0]";
    for (parent, mu, s_index) in [(rail, m, 0), (cart, m * 6.0 / (m + 6.0), 3)] {
        let scene = slider_scene(parent, &[]);
        let steps = run(&scene);
        let dt = scene.settings.dt;
        let at = |t: f64| &steps[(t / dt).round() as usize - 1];
        // Round-off of a thousand steps of numbers of order 1: measured ≤ 1.6e-17 m for `s`.
        let tol = 1e-12;
        let mut worst = 0.0f64;
        for k in 0..4 {
            let k = k as f64;
            let Sample {
                t,
                q,
                u,
                kinetic,
                work,
                commanded,
            } = at(k * period + tau);
            assert!((t - (k * period + tau)).abs() < 1e-12);
            let pushed = k * force * tau * tau / mu + force * tau * tau / (2.0 * mu);
            worst = worst.max((q[s_index] - pushed).abs());
            assert!(
                (q[s_index] - pushed).abs() < tol,
                "s = {} vs {pushed}",
                q[s_index]
            );
            assert!(
                (u[s_index] - force * tau / mu).abs() < tol,
                "ṡ = {}",
                u[s_index]
            );
            let energy = force * force * tau * tau / (2.0 * mu);
            assert!(
                (kinetic - energy).abs() < tol,
                "kinetic {kinetic} vs {energy}"
            );
            assert!((work - energy).abs() < tol, "work {work} vs {energy}");
            // The force is what the recordings show as the commanded actuation (N).
            assert_eq!(*commanded, force);
            let Sample {
                q,
                u,
                kinetic,
                work,
                ..
            } = at((k + 1.0) * period);
            let rest = (k + 1.0) * force * tau * tau / mu;
            worst = worst.max((q[s_index] - rest).abs());
            assert!(
                (q[s_index] - rest).abs() < tol,
                "s = {} vs {rest}",
                q[s_index]
            );
            assert!(u[s_index].abs() < tol && kinetic.abs() < tol && work.abs() < tol);
            println!("μ = {mu} kg: largest error of s {worst:e} m");
            if s_index == 3 {
                // Momentum: the cart (6 kg) recoils, m (ẋ + ṡ) + M ẋ = 0 at every step.
                for Sample { u, .. } in &steps {
                    assert!((6.0 * u[0] + m * (u[0] + u[3])).abs() < tol);
                    assert!(u[1].abs() < tol && u[2].abs() < tol);
                }
            }
        }
    }
}

/// A scene may not give a pulse on a prismatic joint as a torque, nor one on a revolute
/// joint as a force; both errors name the key and the unit to use.
#[test]
fn a_pulse_takes_the_unit_of_its_joint() {
    let rail = "[[bodies]]\nname = \"rail\"\nbase = \"fixed\"\nposition = [0.0, 1.0]\n\n[initial]\nq = [0.0]";
    let text =
        |key: &str, joint: &str| {
            format!(
            "[simulation]\nduration = 1.0\ndt = 1e-3\n\n{rail}\n\n[[bodies]]\nname = \"slider\"\n\
             parent = \"rail\"\njoint = \"{joint}\"\n{axis}mass = 2.0\ninertia = 0.01\n\n\
             [controller]\ntype = \"pulse\"\njoint = \"slider\"\n{key} = 3.0\n\
             pulse_duration = 0.05\nperiod = 0.25\n",
            axis = if joint == "prismatic" { "axis = [1.0, 0.0]\n" } else { "" }
        )
        };
    let error = |key: &str, joint: &str| {
        hopsim_scene::parse(&text(key, joint), Path::new("s.toml"), &[])
            .unwrap_err()
            .to_string()
    };
    let e = error("torque", "prismatic");
    assert!(
        e.contains("controller.torque: 'slider' is on a prismatic joint")
            && e.contains("give force in N"),
        "{e}"
    );
    let e = error("force", "revolute");
    assert!(
        e.contains("controller.force: 'slider' is on a revolute joint")
            && e.contains("give torque in N m"),
        "{e}"
    );
}

/// docs/classics.md §2: the hopper on a vertical guide whose leg gets a thrust pulse
/// (`+2 N` for 0.05 s, then `−2 N` for 0.05 s, every 0.38 s) keeps hopping, where the
/// passive hopper loses the factor 0.980296 of its apex clearance per hop (the collision-
/// matrix loss of the point foot at touchdown): 20 passive hops from the first apex,
/// 0.0831 m, end at 0.0558 m, while every driven apex stays within [0.075, 0.1] m (measured
/// 0.0785–0.0982 m over the 21 hops of 8 s). The pulse's work, summed from the trajectory as `Σ F (s^E − s^A)` over the
/// steps, is the mechanical energy gained plus what the foot's impacts, the stop and the
/// ground dissipated (the ledger, docs/physics.md §6).
#[test]
fn the_driven_hopper_keeps_hopping_and_the_pulse_pays_for_the_losses() {
    let scene = common::scene("classic/hopper-driven.toml", &[]);
    #[derive(Default)]
    struct Hops {
        /// `(t, h, s)` of every step.
        states: Vec<(f64, f64, f64)>,
        work: f64,
        last_s: Option<f64>,
        energy: Option<hopsim_step::EnergyLedger>,
    }
    impl Observer for Hops {
        fn on_start(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            self.last_s = Some(v.state.q[1]);
            Ok(())
        }
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            let (h, s) = (v.state.q[0], v.state.q[1]);
            self.work += v.torque * (s - self.last_s.unwrap());
            self.last_s = Some(s);
            self.states.push((v.state.t, h, s));
            self.energy = Some(v.record.energy);
            Ok(())
        }
    }
    let mut hops = Hops::default();
    let summary = common::run(&scene, &mut hops);
    // Apexes: the foot's clearance `h − s` at the body's highest points.
    let apexes: Vec<f64> = hops
        .states
        .windows(3)
        .filter(|w| w[1].1 >= w[0].1 && w[1].1 > w[2].1)
        .map(|w| w[1].1 - w[1].2)
        .collect();
    println!("{} apexes: {apexes:.4?}", apexes.len());
    assert!(apexes.len() >= 20, "{} hops", apexes.len());
    // The passive hopper from the same first apex, after as many hops.
    let passive = apexes[0] * 0.980296f64.powi(apexes.len() as i32 - 1);
    assert!(passive < 0.06, "{passive}");
    assert!(
        apexes.iter().all(|&a| (0.075..0.1).contains(&a)),
        "apexes {apexes:?}"
    );
    let e = hops.energy.unwrap();
    let gained = e.total() - e.initial;
    let explained = gained + e.dissipated();
    println!(
        "pulse work {} J, energy gained {gained} J, dissipated {} J, summary hops {}",
        hops.work,
        e.dissipated(),
        summary.hops
    );
    // The work equals the ledger's to round-off (the midpoint rule moves `s` by
    // `Δt (ṡ^A + ṡ^E)/2`); what the energy account leaves unexplained is the scheme's own
    // balance error, measured 2e-8 of the work (0.522039 J).
    assert!((hops.work - e.actuator_work).abs() < 1e-9 * e.actuator_work.abs());
    assert!(
        (hops.work - explained).abs() < 1e-6 * hops.work,
        "work {} vs ΔE + dissipated {explained}",
        hops.work
    );
}
