//! The sweep study (docs/sweeps.md): what it refuses before running, the order and content
//! of its rows, its text and its files.

use hopsim_scene::{Override, Scene};
use hopsim_studies::progress::Silent;
use hopsim_studies::sweep::{metric_name, Sweep, SweepInputError, SweepParams};
use hopsim_studies::Report;
use std::path::Path;

fn robbit(duration: &str) -> (Scene, Vec<Override>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robbit.toml");
    let base = vec![Override::new("simulation.duration", duration)];
    (hopsim_scene::load(&path, &base).unwrap(), base)
}

fn params(axes: &[&str], baselines: &[&str]) -> SweepParams {
    SweepParams {
        axes: axes.iter().map(|a| a.parse().unwrap()).collect(),
        baselines: baselines.iter().map(|b| b.parse().unwrap()).collect(),
        y: Some("distance_per_hop_m".into()),
        max_runs: hopsim_studies::sweep::DEFAULT_MAX_RUNS,
    }
}

#[test]
fn repeated_names_and_invalid_runs_are_refused_before_running() {
    let (scene, base) = robbit("0.1");
    let check = |axes: &[&str], baselines: &[&str]| {
        Sweep::new(&scene, &base, params(axes, baselines)).err()
    };
    let twice = check(&["controller.torque=0.1,0.2", "controller.torque=0.3"], &[]);
    assert!(
        matches!(&twice, Some(SweepInputError::RepeatedAxis(k)) if k == "controller.torque"),
        "{twice:?}"
    );
    let taken = check(&["controller.torque=0.1"], &["grid:controller.torque=0.2"]);
    assert!(
        matches!(taken, Some(SweepInputError::TakenName(_))),
        "{taken:?}"
    );
    let taken = check(
        &["controller.torque=0.1"],
        &["a:controller.torque=0.2", "a:controller.torque=0.3"],
    );
    assert!(
        matches!(taken, Some(SweepInputError::TakenName(_))),
        "{taken:?}"
    );
    let misspelt = check(&["controller.torqe=0.1,0.2"], &[]);
    assert!(
        matches!(&misspelt, Some(SweepInputError::InvalidRun { what, .. }) if what == "the grid's first point"),
        "{misspelt:?}"
    );
    let baseline = check(&["controller.torque=0.1"], &["b:controller.torqe=1"]);
    assert!(
        matches!(&baseline, Some(SweepInputError::InvalidRun { what, .. }) if what == "baseline 'b'"),
        "{baseline:?}"
    );
    // Only the first point is checked: a bad value further on is a failed run, not an error.
    assert!(check(&["bodies.disc.mass=1.0,-1.0"], &[]).is_none());
    assert!(metric_name("mean_speed_mps").is_ok());
    assert!(metric_name("speed")
        .unwrap_err()
        .contains("one of: distance_m"));
}

#[test]
fn rows_follow_the_grid_then_the_baselines_and_failed_runs_keep_their_error() {
    let (scene, base) = robbit("0.2");
    let sweep = Sweep::new(
        &scene,
        &base,
        params(
            &["controller.torque=0.2,0.3", "bodies.disc.mass=1.0,-1.0"],
            &["light:bodies.disc.mass=0.5"],
        ),
    )
    .unwrap();
    assert_eq!(sweep.runs(), 5);
    let report = sweep.run(&Silent);
    let places: Vec<(&str, &[f64])> = report
        .runs
        .iter()
        .map(|r| (r.label.as_str(), r.values.as_slice()))
        .collect();
    assert_eq!(
        places,
        [
            ("grid", &[0.2, 1.0][..]),
            ("grid", &[0.2, -1.0]),
            ("grid", &[0.3, 1.0]),
            ("grid", &[0.3, -1.0]),
            ("light", &[]),
        ]
    );
    assert_eq!(report.failed(), 2);
    for (i, r) in report.runs.iter().enumerate() {
        let negative_mass = i == 1 || i == 3;
        assert_eq!(r.summary.is_none(), negative_mass, "{i}");
        assert_eq!(r.error.is_some(), negative_mass, "{i}");
    }
    assert!(report.runs[1].error.as_ref().unwrap().contains("mass"));
    let fastest = report.fastest().unwrap();
    let speed =
        |r: &hopsim_studies::sweep::SweepRun| r.summary.as_ref().unwrap().summary.mean_speed_mps;
    assert!(report
        .runs
        .iter()
        .filter(|r| r.summary.is_some())
        .all(|r| speed(r) <= speed(fastest)));

    let text = report.text();
    assert!(text.starts_with("5 runs, 2 failed\n"), "{text}");
    assert_eq!(text.lines().count(), 6, "{text}");
    assert!(text.contains("  controller.torque=0.2000 bodies.disc.mass=-1.0000: error: "));
    assert!(text.contains("  light: "), "{text}");

    let csv = report.table().to_csv_string();
    let header = csv.lines().next().unwrap();
    assert_eq!(
        header,
        "label,controller.torque,bodies.disc.mass,status,error,distance_m,mean_speed_mps,hops,\
         distance_per_hop_m,impulses_count,impulses_total_Nms,impulse_per_distance_Nms_per_m,\
         brakes_per_s,window_impulse_per_distance_Nms_per_m,gait_period,gait_residual,\
         max_penetration_m,energy_balance_error_J,lcp_failures,wall_time_s"
    );
    assert!(
        csv.lines().nth(5).unwrap().starts_with("light,,,ok,,"),
        "{csv}"
    );
    let json = serde_json::to_value(&report).unwrap();
    assert!(
        json["cube"]["cube"]["diagonal"].is_number(),
        "{}",
        json["cube"]
    );
    assert_eq!(json["runs"][4]["label"], "light");

    let dir = tempfile::tempdir().unwrap();
    let written = hopsim_studies::write_files(dir.path(), &report.files()).unwrap();
    assert!(written.missing_figures.is_empty());
    let names: Vec<String> = written
        .files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["sweep.csv", "sweep.png", "sweep.svg"]);
}

/// A sweep run in parts (chunks spread over processes) gives the rows of the whole sweep,
/// in order; a part past the end is cut to the runs.
#[test]
fn parts_of_a_sweep_give_its_rows() {
    let (scene, base) = robbit("0.5");
    let p = params(
        &[
            "controller.torque=0.1,0.2",
            "controller.impulse_limit=0.05,0.06",
        ],
        &["slow:controller.torque=0.05"],
    );
    let sweep = || Sweep::new(&scene, &base, p.clone()).unwrap();
    let whole = sweep().run(&Silent);
    assert_eq!(whole.runs.len(), 5);
    let parts: Vec<_> = [0..2, 2..4, 4..9]
        .into_iter()
        .flat_map(|part| sweep().run_part(part, &Silent).runs)
        .collect();
    let key = |r: &hopsim_studies::sweep::SweepRun| {
        let s = r
            .summary
            .as_ref()
            .map(|s| (s.summary.steps, s.summary.distance_m));
        (r.label.clone(), r.values.clone(), s, r.error.clone())
    };
    let whole: Vec<_> = whole.runs.iter().map(key).collect();
    let parts: Vec<_> = parts.iter().map(key).collect();
    assert_eq!(parts, whole);
    assert!(sweep().run_part(7..9, &Silent).runs.is_empty());
}

fn classic(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/classic")
        .join(name);
    hopsim_scene::load(&path, &[]).unwrap()
}

/// A robot hopping in place: its distances are round-off (far below a nanometre against
/// its 7 cm shapes), drawn as zero, never as data; by default the plot shows the first
/// figure that varies over the grid (here its hops, on whole numbers); the x axis names its
/// scene key in words with the unit.
#[test]
fn a_robot_hopping_in_place_plots_what_varies_and_no_round_off() {
    use hopsim_studies::plot::Scale;
    let scene = classic("hopper.toml");
    let mut p = params(&["bodies.body.mass=1,1.5,2"], &[]);
    p.y = None;
    let report = Sweep::new(&scene, &[], p.clone()).unwrap().run(&Silent);
    assert!((report.length_scale_m - 0.05 * 2f64.sqrt()).abs() < 1e-12);
    let hops: Vec<u64> = (report.runs.iter())
        .map(|r| r.summary.as_ref().unwrap().summary.hops)
        .collect();
    assert!(hops.iter().any(|h| *h != hops[0]), "{hops:?}");
    assert_eq!(report.y, "hops");
    let figure = report.figure();
    assert_eq!(
        (figure.x_label.as_str(), figure.y_label.as_str()),
        ("body mass (kg)", "hops")
    );
    assert_eq!(figure.y_scale, Scale::Integer);

    p.y = Some("distance_per_hop_m".into());
    let report = Sweep::new(&scene, &[], p).unwrap().run(&Silent);
    for run in &report.runs {
        let d = run.summary.as_ref().unwrap().summary.distance_per_hop_m;
        assert!(d.abs() < 1e-9 * report.length_scale_m, "{d}");
    }
    let figure = report.figure();
    let ys: Vec<f64> = figure.series[0].points.iter().map(|p| p.1).collect();
    assert_eq!(ys, [0.0, 0.0, 0.0]);
    // The pulse of the guided hopper's prismatic leg is a force, in newtons.
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/classic/hopper-driven.toml");
    let base = vec![Override::new("simulation.duration", "0.2")];
    let guided = hopsim_scene::load(&path, &base).unwrap();
    let p = params(&["controller.force=1,2"], &[]);
    let report = Sweep::new(&guided, &base, p).unwrap().run(&Silent);
    assert_eq!(report.figure().x_label, "motor force F (N)");
}

/// A sweep whose stop flag is set stops every run at its next step: each is a row with
/// its error, and the table is complete.
#[test]
fn a_stopped_sweep_still_has_a_row_per_run() {
    let (scene, base) = robbit("0.1");
    let stop = std::sync::atomic::AtomicBool::new(true);
    let sweep = Sweep::new(&scene, &base, params(&["controller.torque=0.1,0.2"], &[]))
        .unwrap()
        .stopped_by(&stop);
    let report = sweep.run(&Silent);
    assert_eq!(report.runs.len(), 2);
    for run in &report.runs {
        assert!(run.summary.is_none());
        assert_eq!(
            run.error.as_deref(),
            Some("interrupted at t = 0.000200 s"),
            "the first step of 0.2 ms"
        );
    }
}
