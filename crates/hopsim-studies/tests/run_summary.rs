//! The run summary of `hopsim run --summary`: the controller's sections (Robbit's figures
//! and cube baselines, docs/physics.md §5.3; the gait's period, §5.4) and the JSON keys.

use hopsim_scene::{Override, Scene};
use hopsim_sim::Simulation;
use hopsim_studies::run_summary::{run_scene, run_simulation, RunReport, RunWatch};
use std::path::Path;

/// A bundled scene with `--set`-style overrides (`"key=value"`).
fn scene(name: &str, overrides: &[&str]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::load(&path, &overrides).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(scene: &Scene) -> RunReport {
    run_scene(scene, &mut ()).expect("run completes")
}

/// Robbit's figures are the window's totals per second and per metre, and the cube
/// baseline is [5.21] `ζ/x = g (m l² + I_S)(1 − ε)/(2 l u_x sin α)`, `l = 2(R − a)`,
/// `α = π/4`, written out with Table 5.1's values (scenes/robbit.toml) at the summary's
/// mean speed, for `ε = 0` and the scene's `cube_restitution = 0.5`. `m` is the robot's
/// mass `m_S + m_R`: the flywheel rides on a free pivot at the CoM, so about the cube's edge
/// it adds its mass but not `I_R`.
#[test]
fn summary_figures_follow_from_the_run_and_the_cube_formula() {
    let report = run(&scene("robbit.toml", &[]));
    let (s, w) = (&report.summary, &report.summary.window);
    let r = report
        .robbit
        .as_ref()
        .expect("Robbit figures in the summary");
    assert!(report.gait.is_none());
    assert!(w.brakes >= 5 && w.distance_m > 0.0, "{w:?}");
    assert_eq!(r.brakes_per_s, w.brakes as f64 / s.speed_window_s);
    assert_eq!(r.impulse_per_distance, w.impulse / w.distance_m);

    // Table 5.1 (scenes/robbit.toml): R, a, m_S, m_R, I_S; g = 9.81.
    let (radius, ecc, m_s, m_r, i_s, g) = (0.2, 0.1, 0.974, 0.431, 3.004e-3, 9.81);
    let (m, l, alpha) = (m_s + m_r, 2.0 * (radius - ecc), std::f64::consts::FRAC_PI_4);
    let u_x = s.mean_speed_mps;
    assert!(u_x > 0.0);
    assert_eq!(r.cube_baseline.len(), 2);
    for (cube, eps) in r.cube_baseline.iter().zip([0.0, 0.5]) {
        let expected = g * (m * l * l + i_s) * (1.0 - eps) / (2.0 * l * u_x * alpha.sin());
        eprintln!(
            "cube ε = {eps}: {:.6} (formula {expected:.6}) per m",
            cube.impulse_per_distance
        );
        assert_eq!(cube.restitution, eps);
        assert!(
            (cube.impulse_per_distance - expected).abs() <= 1e-9 * expected,
            "cube ε = {eps}: {} vs {expected}",
            cube.impulse_per_distance
        );
    }
}

/// A pulse-driven scene reports its gait on the section at the start of every motor
/// period (one sample per period started, `t = 0` included) and no Robbit figures.
#[test]
fn pulse_scenes_report_their_gait() {
    let scene = scene("canebot.toml", &[]);
    let hopsim_control::ControllerConfig::Pulse(pulse) = &scene.controller else {
        panic!("canebot.toml runs the pulse controller");
    };
    let report = run(&scene);
    assert!(report.robbit.is_none());
    let gait = report
        .gait
        .as_ref()
        .expect("pulse scenes report their gait");
    let periods = (scene.settings.duration / pulse.period).floor() as usize;
    assert_eq!(gait.sections, periods + 1, "{gait}");
    assert_eq!(gait.period, Some(1), "{gait}");
    assert!(report.to_string().contains("  gait               period 1"));
}

/// The JSON keeps the run-summary contract's keys (docs/recording.md): the run loop's
/// figures at the top level, `robbit` and `gait` only where they apply, and nothing of the
/// window totals.
#[test]
fn the_json_keeps_its_keys() {
    let report = run(&scene("robbit.toml", &["simulation.duration=4"]));
    let json = serde_json::to_value(&report).unwrap();
    for key in [
        "scene",
        "duration_s",
        "dt_s",
        "steps",
        "distance_m",
        "mean_speed_mps",
        "speed_window_s",
        "hops",
        "distance_per_hop_m",
        "impulse_per_distance_Ns_per_m",
        "max_penetration_m",
        "wall_time_s",
        "steps_per_s",
        "warnings",
    ] {
        assert!(json.get(key).is_some(), "{key}: {json}");
    }
    // Robbit's account closes to round-off: nothing to warn about.
    assert_eq!(json["warnings"], serde_json::json!([]), "{json}");
    assert!(json["energy"]["scale_J"].as_f64().unwrap() > 1.0, "{json}");
    assert!(json["impulses"]["total_Ns"].is_number(), "{json}");
    assert_eq!(json["impulses"]["unit"], "N m s");
    assert!(json["energy"]["max_abs_balance_error"].is_number());
    assert!(json["energy"]["kinetic"].is_number());
    assert!(json["lcp"]["solves"].is_number());
    assert!(json["robbit"]["brakes_per_s"].is_number(), "{json}");
    assert!(json["robbit"]["cube_baseline"].is_array(), "{json}");
    assert!(json.get("gait").is_none() && json.get("window").is_none());
    let keys = json.as_object().unwrap().len();
    assert_eq!(keys, 18, "{json}");
}

/// The summary's JSON without the wall-clock figures.
fn figures(report: &RunReport) -> serde_json::Value {
    let mut json = hopsim_io::to_json_value(report).unwrap();
    let object = json.as_object_mut().unwrap();
    object.remove("wall_time_s").unwrap();
    object.remove("steps_per_s").unwrap();
    json
}

/// A run stepped by its caller and watched by `RunWatch`, whose speed window is placed at
/// the end once the run stops, has the summary of the same span run by `run_simulation`,
/// whose window is placed before it starts: Robbit (brakes in the window, its figures),
/// CaneBot (the gait's section), a span shorter than the window and a span from a state
/// reached mid-run.
#[test]
fn a_run_stepped_by_its_caller_has_the_summary_of_the_same_span() {
    let cases = [
        ("robbit.toml", 0.0, None),
        ("robbit.toml", 1.3, Some(2.7)),
        ("canebot.toml", 0.0, None),
        ("robbit.toml", 0.0, Some(0.05)),
    ];
    for (name, before, duration) in cases {
        let scene = scene(name, &[]);
        let duration = duration.unwrap_or(scene.settings.duration);
        let mut planned = Simulation::new(&scene);
        let mut stepped = Simulation::new(&scene);
        let steps_before = (before / scene.settings.dt).round() as u64;
        for _ in 0..steps_before {
            planned.step(&mut ()).unwrap();
            stepped.step(&mut ()).unwrap();
        }
        let expected = run_simulation(&mut planned, duration, &mut ()).unwrap();
        let mut watch = RunWatch::new(&stepped);
        stepped.start(&mut watch).unwrap();
        for _ in 0..(duration / scene.settings.dt).round() as u64 {
            stepped.step(&mut watch).unwrap();
        }
        let report = watch.finish(&stepped).unwrap();
        assert!(report.summary.steps > 0);
        assert_eq!(
            figures(&report),
            figures(&expected),
            "{name} from {before} s"
        );
        assert_eq!(report.summary.window.brakes, expected.summary.window.brakes);
    }
}
