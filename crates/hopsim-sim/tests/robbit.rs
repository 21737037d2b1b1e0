//! Robbit (docs/physics.md §5.3) through the whole run loop: scene file, momentum-impulse
//! controller, brakes, flight detection and summary.

mod common;

use common::{first_second, repo, run, scene};
use hopsim_record::EventKind;
use hopsim_record::TraceTolerance;
use hopsim_sim::{Observer, RunError, StepView};

/// Velocities before each step, to look at what a step changed.
#[derive(Default)]
struct Previous {
    q: Vec<f64>,
    u: Vec<f64>,
}

/// At each brake: the rates are equal after it; the flywheel's angular momentum changes
/// by exactly the logged impulse; the robot's total angular momentum about its centre of
/// mass changes by exactly the moment of the logged contact percussions; and a brake
/// whose step carries no contact percussion transfers exactly the stored impulse
/// `ζ = I_S I_R/(I_S + I_R)(ψ̇ − φ̇)` of docs/physics.md [5.7-5.9].
struct BrakeCheck {
    prev: Previous,
    dt: f64,
    inertia: (f64, f64),
    brakes: usize,
    free_brakes: usize,
    failures: Vec<String>,
}

impl Observer for BrakeCheck {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        let (q, u) = (v.state.q.as_slice(), v.state.u.as_slice());
        // A brake's engagement is an event; a held brake also locks later steps.
        let engaged = v.events.iter().find_map(|e| match e.kind {
            EventKind::Brake { impulse } => Some(impulse),
            _ => None,
        });
        if let (Some(event), Some(lock)) = (engaged, v.record.locks.first()) {
            let (i_s, i_r) = self.inertia;
            let (qa, ua) = (&self.prev.q, &self.prev.u);
            self.brakes += 1;
            let t = v.state.t;
            let mut fail = |what: String| self.failures.push(format!("t = {t:.4}: {what}"));
            if (u[2] - u[3]).abs() > 1e-9 {
                fail(format!(
                    "rates differ after the brake: {} vs {}",
                    u[2], u[3]
                ));
            }
            let flywheel_change = i_r * (u[3] - ua[3]);
            if (flywheel_change + lock.impulse).abs() > 1e-12 {
                fail(format!(
                    "flywheel momentum change {flywheel_change} ≠ −{}",
                    lock.impulse
                ));
            }
            // Moments of the contact percussions about the CoM at the midpoint q^M.
            let com = [qa[0] + 0.5 * self.dt * ua[0], qa[1] + 0.5 * self.dt * ua[1]];
            let moment: f64 = v
                .record
                .contacts
                .iter()
                .map(|c| {
                    let r = [c.point.x - com[0], c.point.y - com[1]];
                    let t = [c.normal.y, -c.normal.x];
                    let f = [
                        c.normal.x * c.impulse_normal + t[0] * c.impulse_tangent,
                        c.normal.y * c.impulse_normal + t[1] * c.impulse_tangent,
                    ];
                    r[0] * f[1] - r[1] * f[0]
                })
                .sum();
            let total_change = i_s * (u[2] - ua[2]) + flywheel_change;
            if (total_change - moment).abs() > 1e-12 {
                fail(format!(
                    "angular momentum change {total_change} ≠ contact moment {moment}"
                ));
            }
            if event != lock.impulse.abs() {
                fail(format!(
                    "brake event {event} ≠ logged impulse {}",
                    lock.impulse
                ));
            }
            if v.record.contacts.iter().all(|c| c.impulse_normal == 0.0) {
                self.free_brakes += 1;
                let zeta = i_s * i_r / (i_s + i_r) * (ua[3] - ua[2]);
                if (lock.impulse.abs() - zeta).abs() > 1e-12 * zeta {
                    fail(format!(
                        "free brake transferred {} ≠ stored ζ {zeta}",
                        lock.impulse
                    ));
                }
            }
        }
        self.prev.q.clear();
        self.prev.q.extend_from_slice(q);
        self.prev.u.clear();
        self.prev.u.extend_from_slice(u);
        Ok(())
    }
}

#[test]
fn brakes_exchange_angular_momentum_exactly() {
    let scene = scene("robbit.toml", &[]);
    let m = &scene.model;
    let mut check = BrakeCheck {
        prev: Previous {
            q: scene.initial.q.as_slice().to_vec(),
            u: scene.initial.u.as_slice().to_vec(),
        },
        dt: scene.settings.dt,
        inertia: (m.bodies()[0].inertia, m.bodies()[1].inertia),
        brakes: 0,
        free_brakes: 0,
        failures: Vec::new(),
    };
    run(&scene, &mut check);
    assert!(check.failures.is_empty(), "{}", check.failures.join("\n"));
    assert!(check.brakes >= 10, "only {} brakes in 20 s", check.brakes);
    assert!(
        check.free_brakes >= 1,
        "no brake without contact percussion to compare with ζ"
    );
}

/// Take-offs, and the brakes before them.
#[derive(Default)]
struct GaitLog {
    brake_steps: Vec<u64>,
    takeoff_steps: Vec<u64>,
}

impl Observer for GaitLog {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        for e in v.events {
            match e.kind {
                EventKind::Brake { .. } => self.brake_steps.push(e.step),
                EventKind::TakeOff => self.takeoff_steps.push(e.step),
                _ => {}
            }
        }
        Ok(())
    }
}

/// From rest, 20 s of the default scene: forward motion, flight phases, each started by a
/// brake (Robbit has no other way to leave the ground), no LCP failure, penetration below
/// 1 mm and an energy account that closes.
#[test]
fn default_scene_reaches_a_forward_hopping_gait() {
    let scene = scene("robbit.toml", &[]);
    let mut log = GaitLog::default();
    let s = run(&scene, &mut log);
    eprintln!(
        "default scene: {:.4} m/s over the last {} s, {} hops, {} brakes, {:.3e} m max penetration",
        s.mean_speed_mps,
        s.speed_window_s,
        s.hops,
        log.brake_steps.len(),
        s.max_penetration_m
    );
    assert!(s.mean_speed_mps > 0.0, "mean speed {}", s.mean_speed_mps);
    assert!(s.distance_m > 0.0);
    assert!(s.hops >= 3, "{} hops", s.hops);
    assert_eq!(s.hops as usize, log.takeoff_steps.len());
    for &takeoff in &log.takeoff_steps {
        let caused = log
            .brake_steps
            .iter()
            .any(|&b| b <= takeoff && takeoff - b <= 5);
        assert!(
            caused,
            "take-off at step {takeoff} without a brake just before it"
        );
    }
    assert_eq!(s.lcp.failures, 0);
    assert!(
        s.max_penetration_m < 1e-3,
        "penetration {} m",
        s.max_penetration_m
    );
    assert!(
        s.energy.max_abs_balance_error < 1e-9,
        "{}",
        s.energy.max_abs_balance_error
    );
    assert!(s.window.brakes > 0 && s.window.impulse > 0.0);
}

/// The disc and both ellipses hop forward under the shape comparison's controller
/// (T = 0.38 N m, ζ0 = 0.052 N m s): forward progress and at least one hop every 2 s.
#[test]
fn shape_variants_all_hop_forward() {
    for name in [
        "robbit-disc.toml",
        "robbit-ellipse-wide.toml",
        "robbit-ellipse-narrow.toml",
    ] {
        let scene = scene(name, &[]);
        let s = run(&scene, &mut ());
        eprintln!(
            "{name}: {:.4} m/s, {} hops, {:.4} m/hop, {:.3e} m max penetration",
            s.mean_speed_mps, s.hops, s.distance_per_hop_m, s.max_penetration_m
        );
        assert!(
            s.mean_speed_mps > 0.0,
            "{name}: mean speed {}",
            s.mean_speed_mps
        );
        assert!(
            s.hops as f64 >= s.duration_s / 2.0,
            "{name}: {} hops",
            s.hops
        );
        assert_eq!(s.lcp.failures, 0, "{name}");
    }
}

/// Regression on contact impulses: the brake and contact percussions of the default
/// scene's first second, against `tests/golden/robbit_first_second.csv` (tolerance:
/// `TraceTolerance::default()`; regenerate deliberately with `HOPSIM_BLESS=1`).
#[test]
fn golden_brake_and_contact_impulses_of_the_first_second() {
    let trace = first_second(&scene("robbit.toml", &[]));
    assert!(trace.samples.iter().any(|s| s.channel.starts_with("lock:")));
    trace
        .check_golden(
            &repo("tests/golden/robbit_first_second.csv"),
            TraceTolerance::default(),
        )
        .unwrap();
}

/// Per step: end time, the CoM abscissa `x` and the impulse of a brake engaged in it.
#[derive(Default)]
struct WindowLog {
    steps: Vec<(f64, f64, Option<f64>)>,
    /// Largest `|x − centre of mass|`: `x` is the robot's centre of mass (the flywheel
    /// pivots there, docs/physics.md §5.3).
    max_com_offset: f64,
}

impl Observer for WindowLog {
    fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
        let x = v.state.q[0];
        let com = v.model.center_of_mass(v.kinematics).x;
        self.max_com_offset = self.max_com_offset.max((x - com).abs());
        let brake = v
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Brake { .. }))
            .then(|| v.record.locks[0].impulse.abs());
        assert!(
            !v.events
                .iter()
                .any(|e| matches!(e.kind, EventKind::AppliedImpulse { .. })),
            "Robbit applies no impulses but its brakes"
        );
        self.steps.push((v.state.t, x, brake));
        Ok(())
    }
}

/// The summary's figures over the window (the last `speed_window` s: from the first step
/// ending at or after `duration − speed_window`, brakes in the steps ending after it)
/// recomputed from the run's own states and brakes: mean speed = CoM distance / window, the
/// window's distance, brakes and `Σζ` (docs/physics.md §5.3; hopsim-studies makes Robbit's brakes
/// per second and `Σζ / distance` of them).
#[test]
fn summary_window_figures_follow_from_the_run() {
    let scene = scene("robbit.toml", &[]);
    let mut log = WindowLog::default();
    let s = run(&scene, &mut log);
    assert!(
        log.max_com_offset < 1e-12,
        "x vs CoM {}",
        log.max_com_offset
    );

    let (t_end, x_end, _) = *log.steps.last().unwrap();
    let t0 = scene.settings.duration - scene.settings.speed_window;
    let start = log.steps.iter().position(|&(t, _, _)| t >= t0).unwrap();
    let (_, x0, _) = log.steps[start];
    let window = t_end - t0;
    let distance = x_end - x0;
    let in_window = log.steps.iter().filter(|&&(t, _, _)| t > t0);
    let (brakes, zeta_sum) = in_window
        .filter_map(|&(_, _, b)| b)
        .fold((0u64, 0.0), |(n, sum), z| (n + 1, sum + z));
    let speed = distance / window;
    let w = &s.window;
    eprintln!(
        "window {window} s: {distance:.6} m, {speed:.6} m/s, {brakes} brakes, \
         Σζ {zeta_sum:.6} N m s; summary {:.6} m, {:.6} m/s, {} brakes, Σζ {:.6} N m s",
        w.distance_m, s.mean_speed_mps, w.brakes, w.impulse
    );
    assert!((window - 10.0).abs() < 1e-9 && (s.speed_window_s - window).abs() < 1e-12);
    assert!(brakes >= 5, "{brakes} brakes in the window");
    assert_eq!(w.brakes, brakes);
    let close = |a: f64, b: f64| {
        eprintln!("  relative difference {:.1e}", (a - b).abs() / b.abs());
        (a - b).abs() <= 1e-9 * b.abs()
    };
    assert!(
        close(s.mean_speed_mps, speed),
        "{} vs {speed}",
        s.mean_speed_mps
    );
    assert!(
        close(w.distance_m, distance),
        "{} vs {distance}",
        w.distance_m
    );
    assert!(close(w.impulse, zeta_sum), "{} vs {zeta_sum}", w.impulse);
}

/// A summary whose figures are all finite passes; an overflowed figure (as a state near
/// `1e308` would give) is named with its value, so that `run` reports it as an error
/// instead of printing `inf` or `NaN`; the ratios that are NaN by definition are not
/// figures that overflowed.
#[test]
fn an_overflowed_summary_figure_is_named() {
    let mut s = run(&scene("robbit.toml", &["simulation.duration=0.5"]), &mut ());
    assert_eq!(s.first_non_finite(), None);
    s.distance_per_hop_m = f64::NAN;
    assert_eq!(s.first_non_finite(), None);
    s.energy.at_end.potential = f64::INFINITY;
    assert_eq!(
        s.first_non_finite(),
        Some(("potential energy", f64::INFINITY))
    );
}
