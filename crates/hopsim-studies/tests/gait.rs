//! The gait analysis (`hopsim_studies::gait`): on synthetic traces whose cycles are known
//! exactly, and on runs of the Robbit scenes, simulated and recorded (MCAP).

use hopsim_record::{Event, EventKind, McapRecorder, RecorderSet, StateSample};
use hopsim_scene::{Override, Scene};
use hopsim_sim::{recording_info, RecordingObserver};
use hopsim_studies::gait::{
    analyze, balanced_rotors, trace_of_recording, trace_of_scene, CycleSplit, GaitParams,
    GaitReport, GaitTrace,
};
use hopsim_studies::{Report, StudyError};
use std::path::{Path, PathBuf};

const G: f64 = 9.81;
const DT: f64 = 1e-3;

/// One kind of synthetic cycle: period, flight (starting 0.02 s after the cycle start, a
/// ballistic arc), motor off for `motor_off` after the start, forward speed, and `φ` at the
/// start.
#[derive(Clone, Copy)]
struct Shape {
    period: f64,
    flight: f64,
    motor_off: f64,
    speed: f64,
    angle: f64,
}

const LIFT_OFF: f64 = 0.02;
const GROUND: f64 = 0.1;

/// `cycles` cycles alternating `shapes[0]`, `shapes[1]`, each started by a brake event,
/// sampled every `DT`; `ψ` winds at 50 rad/s throughout (a balanced rotor).
fn synthetic(shapes: [Shape; 2], cycles: usize) -> GaitTrace {
    // Cycle starts on the sample grid, `n DT` exactly as the samples' times.
    let start_steps: Vec<u64> = std::iter::once(0)
        .chain((0..cycles).scan(0, |n, i| {
            *n += (shapes[i % 2].period / DT).round() as u64;
            Some(*n)
        }))
        .collect();
    let starts: Vec<f64> = start_steps.iter().map(|&n| n as f64 * DT).collect();
    let steps = start_steps[cycles];
    let mut events = Vec::new();
    let event = |t: f64, kind: EventKind| Event {
        t,
        step: (t / DT).round() as u64,
        kind,
    };
    for (i, &s) in starts[..cycles].iter().enumerate() {
        let shape = shapes[i % 2];
        events.push(event(s, EventKind::Brake { impulse: 0.05 }));
        events.push(event(s + LIFT_OFF, EventKind::TakeOff));
        events.push(event(
            s + LIFT_OFF + shape.flight,
            EventKind::Touchdown {
                contact: "disc/terrain0".into(),
            },
        ));
    }
    let states = (0..=steps)
        .map(|k| {
            let t = k as f64 * DT;
            let i = starts[1..].partition_point(|&s| s < t).min(cycles - 1);
            let (shape, next) = (shapes[i % 2], shapes[(i + 1) % 2]);
            let tau = t - starts[i];
            let x_start: f64 = (0..i)
                .map(|j| shapes[j % 2].speed * shapes[j % 2].period)
                .sum();
            let in_air = tau - LIFT_OFF;
            let y = if in_air > 0.0 && in_air < shape.flight {
                GROUND + 0.5 * G * in_air * (shape.flight - in_air)
            } else {
                GROUND
            };
            let slope = (next.angle - shape.angle) / shape.period;
            // A sample's torque stands for the interval since the previous sample.
            let motor_on = tau > shape.motor_off + 1e-9 || (tau == 0.0 && k > 0);
            StateSample {
                step: k,
                t,
                q: vec![
                    x_start + shape.speed * tau,
                    y,
                    shape.angle + slope * tau,
                    50.0 * t,
                ],
                u: vec![shape.speed, 0.0, slope, 50.0],
                actuator_torque: if motor_on { 0.2 } else { 0.0 },
            }
        })
        .collect();
    GaitTrace {
        title: "synthetic".into(),
        source: "test".into(),
        coordinates: ["x", "y", "phi", "psi"].map(String::from).to_vec(),
        cyclic: vec![3],
        translations: vec![0],
        states,
        events,
        natural_split: CycleSplit::event("brake"),
    }
}

const LONG: Shape = Shape {
    period: 0.3,
    flight: 0.1,
    motor_off: 0.12,
    speed: 0.5,
    angle: -0.8,
};
const SHORT: Shape = Shape {
    period: 0.2,
    flight: 0.06,
    motor_off: 0.08,
    speed: 0.4,
    angle: -0.6,
};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// Alternating cycles: every cycle's period, distance, fractions, apex and hop are the
/// known ones; over the last 8 the time-weighted figures; and period 2 on the section.
#[test]
fn a_synthetic_period_2_gait_is_recovered() {
    let trace = synthetic([LONG, SHORT], 40);
    let r = analyze(&trace, &GaitParams::default()).unwrap();
    assert_eq!(
        r.cycles.len(),
        39,
        "the last brake starts no complete cycle"
    );
    for c in &r.cycles {
        let s = if c.index % 2 == 0 { LONG } else { SHORT };
        assert!(close(c.period, s.period, 1e-12), "{c:?}");
        assert!(close(c.distance, s.speed * s.period, 1e-12), "{c:?}");
        assert!(
            close(c.flight_fraction, s.flight / s.period, 1e-12),
            "{c:?}"
        );
        assert!(
            close(c.stance_fraction, 1.0 - s.flight / s.period, 1e-12),
            "{c:?}"
        );
        let motor = (s.period - s.motor_off) / s.period;
        assert!(close(c.motor_on_fraction, motor, 1e-9), "{c:?}");
        // The ballistic apex, g F²/8 above the ground, falls on a sample.
        assert!(
            close(c.apex_height, GROUND + G * s.flight * s.flight / 8.0, 1e-12),
            "{c:?}"
        );
        assert_eq!(c.hops, 1);
    }
    let last = &r.last;
    assert_eq!(last.cycles, 8);
    let time = 4.0 * (LONG.period + SHORT.period);
    assert!(close(last.mean_period, 0.25, 1e-12));
    assert!(close(last.min_period, SHORT.period, 1e-12));
    assert!(close(last.max_period, LONG.period, 1e-12));
    let distance = 4.0 * (LONG.speed * LONG.period + SHORT.speed * SHORT.period);
    assert!(close(last.speed, distance / time, 1e-12));
    assert!(close(
        last.flight_fraction,
        4.0 * (LONG.flight + SHORT.flight) / time,
        1e-12
    ));
    assert_eq!(r.periodicity.period, Some(2), "{}", r.periodicity);
    assert!(r.periodicity.residuals[0] > 10.0, "{}", r.periodicity);
    assert_eq!(
        r.section,
        ["y", "phi", "x_dot", "y_dot", "phi_dot", "psi_dot"]
    );
}

/// The same cycle over and over is period 1, and its overlaid cycles all equal their mean.
#[test]
fn a_synthetic_period_1_gait_overlays_on_its_mean() {
    let trace = synthetic([LONG, LONG], 30);
    let r = analyze(&trace, &GaitParams::default()).unwrap();
    assert_eq!(r.periodicity.period, Some(1), "{}", r.periodicity);
    let p = &r.profiles;
    assert_eq!(p.cycles, (21..29).collect::<Vec<_>>());
    assert_eq!((p.progress[0], p.progress[100]), (0.0, 100.0));
    for (rows, mean) in [(&p.x, &p.mean_x), (&p.y, &p.mean_y), (&p.phi, &p.mean_phi)] {
        for row in rows {
            for (a, b) in row.iter().zip(mean) {
                assert!(close(*a, *b, 1e-9), "{a} vs {b}");
            }
        }
    }
    // x from the cycle start to its end: the stride; φ starts at the cycle's start angle.
    assert!(close(p.mean_x[100], LONG.speed * LONG.period, 1e-12));
    assert!(close(p.mean_phi[0], LONG.angle, 1e-12));
}

/// A winding rotor angle left in the section hides the period; the balanced rotor of the
/// Robbit scenes is recognised (the flywheel), CaneBot has none.
#[test]
fn balanced_rotors_stay_out_of_the_section() {
    let mut trace = synthetic([LONG, LONG], 30);
    trace.cyclic.clear();
    let r = analyze(&trace, &GaitParams::default()).unwrap();
    assert_eq!(r.periodicity.period, None, "{}", r.periodicity);
    assert_eq!(balanced_rotors(&scene("robbit.toml", &[]).model), [3]);
    assert!(balanced_rotors(&scene("canebot.toml", &[]).model).is_empty());
}

/// The section leaves out the coordinates a gait travels along, the `x` of each floating
/// base, and keeps every other: the hopper on a vertical guide (no floating base) keeps
/// its height, whose first coordinate it is; three free balls leave out their three `x`.
#[test]
fn only_floating_bases_travel() {
    let travels = |name: &str| scene(name, &[]).model.horizontal_positions();
    assert_eq!(travels("robbit.toml"), [0]);
    assert_eq!(travels("canebot.toml"), [0]);
    assert!(travels("classic/hopper-driven.toml").is_empty());
    assert!(travels("classic/pendulum-stop.toml").is_empty());
    assert_eq!(travels("classic/cradle-3.toml"), [0, 3, 6]);
    assert!(balanced_rotors(&scene("classic/hopper-driven.toml", &[]).model).is_empty());
}

/// Cycles at the motor period: every cycle one period long, from `t0`.
#[test]
fn a_period_split_cuts_every_period() {
    let trace = synthetic([LONG, LONG], 20);
    let params = GaitParams {
        split: Some(CycleSplit::Period {
            period: 0.25,
            t0: 0.1,
        }),
        ..GaitParams::default()
    };
    let r = analyze(&trace, &params).unwrap();
    assert_eq!(r.cycles.len(), 23, "(6 s − 0.1 s) / 0.25 s");
    for (k, c) in r.cycles.iter().enumerate() {
        assert!(close(c.start, 0.1 + 0.25 * k as f64, 1e-12), "{c:?}");
        assert!(close(c.period, 0.25, 1e-12), "{c:?}");
    }
}

/// What the analysis cannot do is an input error, with the reason.
#[test]
fn too_few_cycles_and_unknown_events_are_input_errors() {
    let trace = synthetic([LONG, LONG], 10);
    for (split, expected) in [
        (CycleSplit::event("shape_switch"), "0 cycle starts"),
        (CycleSplit::event("hop"), "no event kind 'hop'"),
        (
            CycleSplit::Period {
                period: 0.0,
                t0: 0.0,
            },
            "positive number",
        ),
    ] {
        let params = GaitParams {
            split: Some(split),
            ..GaitParams::default()
        };
        let err = analyze(&trace, &params).unwrap_err();
        assert!(
            matches!(err, StudyError::Input(_)) && err.is_invalid_input(),
            "{err}"
        );
        assert!(err.to_string().contains(expected), "{err}");
    }
}

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn scene(name: &str, overrides: &[&str]) -> Scene {
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::load(&repo(&format!("scenes/{name}")), &overrides).unwrap()
}

/// Runs `scene` with an MCAP recording into `dir` and reads it back.
fn recorded(scene: &Scene, dir: &Path) -> GaitTrace {
    let file = dir.join("run.mcap");
    let mut set = RecorderSet::default();
    set.push(Box::new(
        McapRecorder::create(&file, &recording_info(scene)).unwrap(),
    ));
    let mut observer = RecordingObserver::new(set, scene);
    hopsim_sim::run(scene, &mut observer).unwrap();
    observer.finish().unwrap();
    trace_of_recording(&file).unwrap()
}

/// The experiment's controller over 40 s (it needs about 30 s to settle): the simulated
/// and the recorded run give the same cycles (event times are exact in both; the motor's
/// state is sampled at 1 kHz in the recording), period 2, and the motor is off for the
/// off time (0.1 s) of every cycle: its on-fraction is `1 − 0.1 s / period`.
#[test]
fn the_experiment_recorded_and_simulated_is_period_2_with_its_off_time() {
    let scene = scene("robbit-experiment.toml", &["simulation.duration=40"]);
    let dir = tempfile::tempdir().unwrap();
    let params = GaitParams::default();
    let simulated = analyze(&trace_of_scene(&scene).unwrap(), &params).unwrap();
    let recorded = analyze(&recorded(&scene, dir.path()), &params).unwrap();
    for r in [&simulated, &recorded] {
        assert_eq!(
            r.periodicity.period,
            Some(2),
            "{}: {}",
            r.source,
            r.periodicity
        );
        assert!(r.periodicity.residuals[0] > 10.0, "{}", r.periodicity);
    }
    assert_eq!(simulated.cycles.len(), recorded.cycles.len());
    // The recording samples every 5th step: a torque switch is placed within 1 ms.
    let sample = 1e-3;
    for (s, r) in simulated.cycles.iter().zip(&recorded.cycles) {
        assert_eq!((s.start, s.period, s.hops), (r.start, r.period, r.hops));
        assert!(
            close(s.flight_fraction, r.flight_fraction, 1e-12),
            "{s:?} {r:?}"
        );
        assert!(close(s.distance, r.distance, 1e-12), "{s:?} {r:?}");
        let off = 1.0 - 0.1 / s.period;
        assert!(close(s.motor_on_fraction, off, 1e-9), "{s:?}");
        assert!(close(r.motor_on_fraction, off, sample / r.period), "{r:?}");
        assert!(r.apex_height <= s.apex_height + 1e-12, "{s:?} {r:?}");
    }
    print_summary(&simulated);
}

/// The default scene's gait, as its `[meta]` says: a hop in every cycle after the start,
/// period 1 on the brake section, and (the touchdown release) the motor on exactly in stance but for the
/// brake's step and the step after touchdown.
#[test]
fn the_default_scene_hops_periodically() {
    let scene = scene("robbit.toml", &[]);
    let r = analyze(&trace_of_scene(&scene).unwrap(), &GaitParams::default()).unwrap();
    assert_eq!(r.periodicity.period, Some(1), "{}", r.periodicity);
    // From rest, one brake in the first half second lifts the disc by less than the hop
    // clearance (1 mm); from then on every cycle is one hop.
    let later = r.cycles.iter().filter(|c| c.start >= 1.0);
    assert!(later.clone().all(|c| c.hops == 1), "a cycle without a hop");
    let dt = scene.settings.dt;
    for c in &r.cycles[r.cycles.len() - 8..] {
        // Stance runs from the touchdown (the end of the first loaded step) to the end of
        // the brake's step, after which the disc is in the air; the motor runs from the
        // touchdown too, but not in the brake's own step.
        let gap = (c.stance_fraction - c.motor_on_fraction) * c.period;
        assert!(
            close(gap, dt, 1e-9 * dt),
            "stance − motor on = {gap} s: {c:?}"
        );
    }
    print_summary(&r);
}

fn print_summary(r: &GaitReport) {
    eprintln!("{}", r.text());
}

/// CaneBot cut at its motor period: the section the analysis samples at the cycle starts
/// (interpolated between steps) is the stroboscopic section of the run summary, so both
/// give the same residuals, for the gaits of period 1 (cane timed) and 2 (cane extended).
#[test]
fn canebot_at_its_motor_period_has_the_run_summary_s_periodicity() {
    for (name, period) in [("canebot-timed.toml", 1), ("canebot-cane.toml", 2)] {
        let scene = scene(name, &[]);
        let summary = hopsim_studies::run_summary::run_scene(&scene, &mut ()).unwrap();
        let expected = summary
            .gait
            .expect("a pulse-driven scene has a gait section");
        let r = analyze(&trace_of_scene(&scene).unwrap(), &GaitParams::default()).unwrap();
        assert!(
            matches!(r.split, CycleSplit::Period { .. }),
            "{:?}",
            r.split
        );
        assert_eq!(
            r.periodicity.period,
            Some(period),
            "{name}: {}",
            r.periodicity
        );
        assert_eq!(r.periodicity.sections, expected.sections, "{name}");
        for (a, b) in r.periodicity.residuals.iter().zip(&expected.residuals) {
            assert!(close(*a, *b, 1e-9 * b.abs()), "{name}: {a} vs {b}");
        }
    }
}

/// A period-2 gait is drawn as two kinds of cycle, never as one mean that matches neither:
/// each kind's mean is its own cycles' profile, its flight is shaded where the synthetic
/// flight is (from 0.02 s after the cycle start, for the flight time), one legend and one x
/// label serve the panels; the periodicity figure ticks whole lags on a logarithmic
/// residual axis with the tolerance line at 1.
#[test]
fn a_period_2_gait_is_drawn_as_two_kinds_of_cycle() {
    use hopsim_studies::plot::Scale;
    let r = analyze(&synthetic([LONG, SHORT], 40), &GaitParams::default()).unwrap();
    assert_eq!(r.cycle_kinds(), 2);
    let figure = r.profile_figure();
    assert!(figure.shared_legend);
    let x_labels: Vec<&str> = figure.panels.iter().map(|p| p.x_label.as_str()).collect();
    assert_eq!(x_labels, ["", "", "cycle progress (%)"]);
    let p = &r.profiles;
    let rows = [&p.x, &p.y, &p.phi];
    let overall = [&p.mean_x, &p.mean_y, &p.mean_phi];
    for (panel, (rows, overall)) in figure.panels.iter().zip(rows.iter().zip(overall)) {
        let means: Vec<_> = panel.series.iter().filter(|s| s.label.is_some()).collect();
        assert_eq!(means.len(), 2);
        for (kind, mean) in means.iter().enumerate() {
            let label = mean.label.as_deref().unwrap();
            assert!(
                label.starts_with(["A: cycles", "B: cycles"][kind]),
                "{label}"
            );
            // A cycle of this kind: the mean is its profile.
            let k = (0..p.cycles.len())
                .find(|&k| p.cycles[k] % 2 == kind)
                .unwrap();
            for ((_, y), expected) in mean.points.iter().zip(&rows[k]) {
                assert!(close(*y, *expected, 1e-12), "{label}: {y} vs {expected}");
            }
        }
        // No series is the mean over both kinds.
        assert!(panel.series.iter().all(|s| {
            s.points
                .iter()
                .zip(overall.iter())
                .any(|((_, y), m)| !close(*y, *m, 1e-9))
        }));
        for (kind, shape) in [LONG, SHORT].iter().enumerate() {
            let name = format!("{}: flight (shaded)", ["A", "B"][kind]);
            let bands: Vec<_> = (panel.bands.iter())
                .filter(|b| b.label.as_deref() == Some(name.as_str()))
                .collect();
            assert!(!bands.is_empty(), "{name}");
            for b in bands {
                let from = 100.0 * LIFT_OFF / shape.period;
                let to = 100.0 * (LIFT_OFF + shape.flight) / shape.period;
                assert!(close(b.from, from, 1e-6) && close(b.to, to, 1e-6), "{b:?}");
            }
        }
    }
    let periodicity = r.periodicity_figure();
    let lags = periodicity.panels.last().unwrap();
    assert_eq!((lags.x_scale, lags.y_scale), (Scale::Integer, Scale::Log));
    let tolerance = (lags.series.iter())
        .find(|s| {
            s.label
                .as_deref()
                .is_some_and(|l| l.starts_with("tolerance"))
        })
        .unwrap();
    assert!(tolerance.points.iter().all(|p| p.1 == 1.0));
    let (lo, hi) = lags.y_range.unwrap();
    assert!(lo < 1.0 && hi > r.periodicity.residuals[0], "{lo} … {hi}");
}

/// A period-1 gait is one kind of cycle with its mean.
#[test]
fn a_period_1_gait_is_one_kind_with_its_mean() {
    let r = analyze(&synthetic([LONG, LONG], 30), &GaitParams::default()).unwrap();
    assert_eq!(r.cycle_kinds(), 1);
    let figure = r.profile_figure();
    for panel in &figure.panels {
        let labels: Vec<&str> = (panel.series.iter())
            .filter_map(|s| s.label.as_deref())
            .collect();
        assert_eq!(labels, ["cycles 21–28 (thin) and their mean (bold)"]);
    }
}
