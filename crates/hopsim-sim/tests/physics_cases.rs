//! Results a physicist would check first (docs/physics.md §2.1, §4.7–§4.9): a stiff damper
//! that only ever removes energy, an impact whose Newton law adds energy and is reported, a
//! self-locking contact resolved without a jam, a sled stopped by a step's face.

use hopsim_record::EventKind;
use hopsim_scene::Scene;
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use std::path::Path;

fn scene(text: &str, overrides: &[&str]) -> Scene {
    let overrides: Vec<_> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::parse(text, Path::new("case.toml"), &overrides).unwrap()
}

/// Every step's view, as a closure sees it.
struct Each<F>(F);

impl<F: FnMut(&StepView<'_>)> Observer for Each<F> {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        (self.0)(view);
        Ok(())
    }
}

/// A wheel pinned at its centre of mass (gravity does no work) with a joint damper
/// `c = 0.5 N m s` on `I = 1e-4 kg m²`, spun at 10 rad/s.
const DAMPED_WHEEL: &str = r#"
[simulation]
duration = 0.02
dt = 1e-3

[[bodies]]
name = "wheel"
base = "pinned"
pivot = [0.0, 1.0]
mass = 0.1
inertia = 1e-4
damping = 0.5

[initial]
q = [0.0]
u = [10.0]
"#;

/// At `c Δt / I` = 5, 0.5 and 0.05 the damper only removes energy, in every step and by
/// exactly its booked work; the speed decays monotonically; at 0.05 it follows
/// `ω0 exp(−c t / I)` (explicitly, 5 ran away in a few steps).
#[test]
fn a_stiff_damper_decays_at_every_step_size() {
    for (dt, steps) in [(1e-3, 100), (1e-4, 400), (1e-5, 200)] {
        let s = scene(DAMPED_WHEEL, &[&format!("simulation.dt={dt}")]);
        let mut sim = Simulation::new(&s);
        let (c, inertia) = (0.5, 1e-4);
        let mut last = (10.0_f64, sim.stepper().record().energy.total(), 0.0);
        for _ in 0..steps {
            sim.step(&mut ()).unwrap();
            let omega = sim.state().u[0];
            let e = sim.stepper().record().energy;
            assert!(
                omega.abs() <= last.0.abs(),
                "Δt = {dt}: |ω| {} → {omega}",
                last.0
            );
            assert!(
                e.total() <= last.1,
                "Δt = {dt}: energy {} → {}",
                last.1,
                e.total()
            );
            assert!(
                e.damping_work <= last.2,
                "Δt = {dt}: the damper added energy"
            );
            assert!(e.balance_error().abs() <= 1e-12 * 5e-3, "Δt = {dt}: {e:?}");
            last = (omega, e.total(), e.damping_work);
        }
        if dt == 1e-5 {
            let t = sim.state().t;
            let exact = 10.0 * (-c * t / inertia).exp();
            assert!(
                (sim.state().u[0] / exact - 1.0).abs() < 1e-2,
                "ω({t}) = {} vs {exact}",
                sim.state().u[0]
            );
        }
    }
}

/// A rod strikes the ground on one end, spinning, with `ε_N = 0.9` and a sticking tangential
/// target `ε_T = 0` (μ = 2): Newton's law with `ε_T ≠ ε_N` adds energy in that impact
/// (docs/physics.md §4.7), and the run says how much: its `energy_created` event carries
/// the contact's work, which is the step's change of energy less gravity's work. With
/// `ε_T = ε_N` the same impact loses energy and nothing is reported.
#[test]
fn an_impact_that_adds_energy_is_reported() {
    let rod = r#"
[simulation]
duration = 0.15
dt = 1e-4

[environment]
friction = 2.0
restitution = 0.9
tangential_restitution = 0.0

[[bodies]]
name = "rod"
mass = 1.0
inertia = 0.02

[[shapes]]
name = "rod"
body = "rod"
type = "box"
half_width = 0.25
half_height = 0.01

[initial]
q = [0.0, 0.3, 0.2]
u = [1.0, -2.0, 10.0]
"#;
    for (tangential, adds) in [("0.0", true), ("0.9", false)] {
        let s = scene(
            rod,
            &[&format!("environment.tangential_restitution={tangential}")],
        );
        let mut sim = Simulation::new(&s);
        let mut reported = Vec::new();
        let mut before = sim.stepper().record().energy;
        let mut largest_gain = f64::NEG_INFINITY;
        for _ in 0..1500 {
            let mut seen = Vec::new();
            sim.step(&mut Each(|v: &StepView<'_>| {
                for ev in v.events {
                    if let EventKind::EnergyCreated { energy, .. } = ev.kind {
                        seen.push(energy);
                    }
                }
            }))
            .unwrap();
            let after = sim.stepper().record().energy;
            let contact = after.contact_work - before.contact_work;
            let change = after.total() - before.total();
            largest_gain = largest_gain.max(contact);
            for energy in seen {
                // No actuator: the step's change is the contacts' work and the scheme's
                // own balance error (nJ here).
                assert!((energy - contact).abs() < 1e-9, "{energy} vs {contact}");
                assert!((change - contact).abs() < 1e-6, "{change} vs {contact}");
                reported.push(energy);
            }
            before = after;
        }
        if adds {
            assert_eq!(reported.len(), 1, "{reported:?}");
            assert!(reported[0] > 0.5, "{reported:?} J");
        } else {
            assert!(reported.is_empty(), "{reported:?}");
            assert!(largest_gain < 1e-6, "a contact added {largest_gain} J");
        }
    }
}

/// A slider strikes a hook on its own arm (tests/scenes/physics/slider-jam.toml): its
/// rows are parallel and the contact self-locking, with ε_N ≠ ε_T. It is resolved without
/// friction (docs/physics.md §4.8): an `indeterminate_friction` event at each new impact,
/// Newton's law `γ_N^E = −0.5 γ_N^A` on the slide, finite percussions, no energy added.
#[test]
fn a_self_locking_contact_is_resolved_and_reported_not_jammed() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/scenes/physics/slider-jam.toml");
    let s = hopsim_scene::load(&path, &[]).unwrap();
    let mut sim = Simulation::new(&s);
    let (mut events, mut impacts, mut largest) = (0, 0, 0.0_f64);
    let steps = (s.settings.duration / s.settings.dt).round() as usize;
    for _ in 0..steps {
        sim.step(&mut Each(|v: &StepView<'_>| {
            for ev in v.events {
                match &ev.kind {
                    EventKind::IndeterminateFriction { contact, .. } => {
                        assert_eq!(contact, "hook/block");
                        events += 1;
                    }
                    EventKind::EnergyCreated { .. } => panic!("energy created: {ev:?}"),
                    _ => {}
                }
            }
            for c in &v.record.pair_contacts {
                assert!(c.dependent, "{c:?}");
                assert_eq!(c.impulse_tangent, 0.0);
                largest = largest.max(c.impulse_normal);
                if c.impulse_normal > 0.0 && c.approach_velocity < -1e-3 {
                    impacts += 1;
                    assert!(c.work <= 0.0, "{c:?}");
                    // ξ_N = γ_N^E + 0.5 γ_N^A = 0 to the LCP's tolerance.
                    assert!(c.normal_velocity.abs() < 1e-9, "{c:?}");
                }
            }
        }))
        .unwrap();
    }
    assert!(
        events >= 3 && impacts >= 3,
        "{events} events, {impacts} impacts"
    );
    // The slider (0.4 kg) never moves faster than a few m/s along the arm.
    assert!(largest < 5.0, "largest percussion {largest} N s");
}

/// Bodies of every shape slide at 1 m/s into a 5 cm step without friction: a sled on two
/// point feet, a box (its corners), a rocker on an arc (its smooth side and its ends), a
/// small wheel and an ellipse. The face stops each (to the scheme's `O(v Δt)` penetration:
/// up to `v Δt/2` before the step that finds the contact and `v Δt/2` into it, with the
/// body pitching a little: 3 v Δt bounds it), none sinks into the ground under the step,
/// and each stays on the ground level.
#[test]
fn every_shape_is_stopped_by_a_steps_face() {
    let world = r#"
[simulation]
duration = 1.0
dt = 1e-3

[environment]
terrain = "step"
step_x = 0.5
step_height = 0.05
friction = 0.0

[[bodies]]
name = "body"
mass = 1.0
inertia = 0.01
"#;
    // (shapes, their lowest point below the centre of mass, their front beyond it at rest), m.
    let shapes = [
        (
            "[[shapes]]\nbody = \"body\"\ntype = \"point\"\nposition = [0.1, -0.02]\n\
             [[shapes]]\nbody = \"body\"\ntype = \"point\"\nposition = [-0.1, -0.02]\nname = \"back\"\n",
            0.02,
            0.1,
        ),
        ("[[shapes]]\nbody = \"body\"\ntype = \"box\"\nhalf_width = 0.1\nhalf_height = 0.02\n", 0.02, 0.1),
        (
            "[[shapes]]\nbody = \"body\"\ntype = \"arc\"\ncenter = [0.0, 0.08]\nradius = 0.1\n\
             start = -2.5\nend = -0.64\n",
            0.02,
            0.08,
        ),
        ("[[shapes]]\nbody = \"body\"\ntype = \"circle\"\nradius = 0.02\n", 0.02, 0.02),
        ("[[shapes]]\nbody = \"body\"\ntype = \"ellipse\"\nsemi_x = 0.1\nsemi_y = 0.02\n", 0.02, 0.1),
    ];
    for (shape, below, front) in shapes {
        for dt in [1e-3, 1e-4] {
            let text = format!(
                "{world}{shape}\n[initial]\nq = [0.0, {below}, 0.0]\nu = [1.0, 0.0, 0.0]\n"
            );
            let s = scene(&text, &[&format!("simulation.dt={dt}")]);
            let summary = hopsim_sim::run(&s, &mut ()).unwrap();
            assert!(
                summary.max_penetration_m <= 3.0 * dt,
                "{shape}: {}",
                summary.max_penetration_m
            );
            let mut sim = Simulation::new(&s);
            for _ in 0..(1.0 / dt).round() as usize {
                sim.step(&mut ()).unwrap();
                let q = &sim.state().q;
                assert!(q[1] > below - 3.0 * dt, "{shape}: sank to y = {}", q[1]);
                // Every shape point behind the face or the ground is a gap below zero.
                let r = sim.stepper().record();
                assert!(
                    r.max_penetration <= 3.0 * dt,
                    "{shape}: {}",
                    r.max_penetration
                );
            }
            assert!(
                sim.state().q[0] + front < 0.5 + 0.05,
                "{shape}: beyond the face"
            );
        }
    }
}

/// A light arm pinned at one end (10 g) carries a heavy slider (0.78 kg) on a stiff
/// spring, released 14 cm from rest so that it slides through the pivot at about 10 m/s:
/// the inertia about the pivot collapses and the arm spins up to hundreds of rad/s in a
/// few steps. The midpoint scheme loses energy there (docs/physics.md §6.1), to first order
/// in `Δt`, and the summary says so while the error exceeds 5 % of the run's energy.
const ARM_WITH_A_SLIDER: &str = r#"
[simulation]
duration = 0.02
dt = 1e-4

[[bodies]]
name = "arm"
mass = 0.01
inertia = 3.0e-5
base = "pinned"
pivot = [-0.5, 0.05]
com = [0.0, 0.078]

[[bodies]]
name = "slider"
mass = 0.78
inertia = 8.1e-5
parent = "arm"
joint = "prismatic"
axis = [1.0, 0.0]
com = [0.0247, 0.0]
pivot = [0.0, 0.0]
stiffness = 4777.0
rest_position = 0.039

[initial]
q = [-3.141592653589793, -0.1]
u = [0.0, 0.0]
"#;

#[test]
fn a_step_too_coarse_for_the_motion_is_reported_and_its_error_shrinks_with_the_step() {
    let mut errors = Vec::new();
    for dt in [1e-4, 1e-5] {
        let s = scene(ARM_WITH_A_SLIDER, &[&format!("simulation.dt={dt}")]);
        let summary = hopsim_sim::run(&s, &mut ()).unwrap();
        let e = &summary.energy;
        // Nothing dissipates: the whole account's error is the scheme's.
        assert!(e.at_end.dissipated.abs() < 1e-12, "{e:?}");
        let initial_spring = 0.5 * 4777.0 * (0.1_f64 + 0.039).powi(2);
        assert!(e.scale >= 0.99 * initial_spring, "{e:?}");
        let fraction = e.max_abs_balance_error / e.scale;
        let warned = !summary.warnings.is_empty();
        assert_eq!(
            warned,
            fraction > 0.05,
            "Δt = {dt}: {fraction} {:?}",
            summary.warnings
        );
        if warned {
            assert!(
                summary.warnings[0].contains("too coarse"),
                "{:?}",
                summary.warnings
            );
        }
        errors.push((fraction, e.at_end.balance_error));
    }
    // At Δt = 1e-4 s a fifth of the energy is lost (and reported); ten times smaller steps
    // lose several times less, within the 5 % that goes unreported.
    assert!(errors[0].0 > 0.1 && errors[0].1 < 0.0, "{errors:?}");
    assert!(errors[1].0 < 0.05, "{errors:?}");
    assert!(errors[0].0 / errors[1].0 > 5.0, "{errors:?}");
}
