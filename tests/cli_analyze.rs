//! `hopsim analyze …` end to end: JSON fields, output files, argument errors.

use std::path::Path;
use std::process::{Command, Output};

fn hopsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(args)
        .output()
        .expect("run hopsim")
}

/// Runs `hopsim ARGS` and asserts that it succeeds.
fn hopsim_ok(args: &[&str]) -> Output {
    let out = hopsim(args);
    assert!(
        out.status.success(),
        "hopsim {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_slice(&hopsim_ok(args).stdout).expect("one JSON object on stdout")
}

/// Asserts that each argument list exits with code 2 and a clear error, not a panic.
fn assert_invalid_input(cases: &[&[&str]]) {
    for args in cases {
        let out = hopsim(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error:"), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

fn finite(value: &serde_json::Value, field: &str) -> f64 {
    let x = value[field]
        .as_f64()
        .unwrap_or_else(|| panic!("{field} missing or not a number in {value}"));
    assert!(x.is_finite(), "{field} = {x}");
    x
}

#[test]
fn template_cargo_2_json_has_finite_gait_fields() {
    let v = json(&["analyze", "template", "--case", "cargo-2", "--json"]);
    assert_eq!(v["case"], "cargo-2");
    assert_eq!(v["gait"], true);
    let speed = finite(&v, "mean_speed_mps");
    let stride = finite(&v, "stride_m");
    let frequency = finite(&v, "hop_frequency_hz");
    let cot = finite(&v, "cost_of_transport");
    assert!(speed > 0.0 && stride > 0.0 && frequency > 0.0 && cot > 0.0);
    // Internal consistency of the reported gait: u = stride × f, CoT = ΔE / (m g stride).
    assert!((speed - stride * frequency).abs() < 1e-9 * speed);
    let p = &v["parameters"];
    let expected_cot = p["energy_input_J"].as_f64().unwrap()
        / (p["mass_kg"].as_f64().unwrap() * p["gravity_mps2"].as_f64().unwrap() * stride);
    assert!((cot - expected_cot).abs() < 1e-12);
}

#[test]
fn template_overrides_change_the_parameters() {
    let v = json(&[
        "analyze",
        "template",
        "--case",
        "cargo-1",
        "--energy",
        "40",
        "--takeoff-angle",
        "-0.08",
        "--hops",
        "30",
        "--json",
    ]);
    assert_eq!(v["parameters"]["energy_input_J"], 40.0);
    assert_eq!(v["parameters"]["takeoff_angle_rad"], -0.08);
    assert_eq!(v["hops_completed"], 30);
}

#[test]
fn impulsive_wheel_3_5_json() {
    let v = json(&["analyze", "impulsive-wheel", "--impulse", "3.5", "--json"]);
    let phi = finite(&v, "fixed_point_rad");
    let lambda = finite(&v, "eigenvalue");
    assert_eq!(v["stable"], true);
    // The fixed point is a fixed point of the map with φ̇_S T_C = 1, c = 3.5² / 9.81.
    let c = 3.5f64.powi(2) / 9.81;
    assert!((c * (2.0 * phi).sin() - 1.0).abs() < 1e-12);
    assert!(lambda.abs() < 1.0);
    let interval = v["stable_impulse_interval_Ns"].as_array().unwrap();
    assert!(interval[0].as_f64().unwrap() < 3.5 && 3.5 < interval[1].as_f64().unwrap());
}

#[test]
fn obstacle_json_reports_three_strategies() {
    let v = json(&[
        "analyze",
        "obstacle",
        "--froude",
        "2",
        "--height-ratio",
        "0.3",
        "--json",
    ]);
    assert!(finite(&v["costs_per_mgr"], "rolling") > 0.0);
    assert!((finite(&v["costs_per_mgr"], "trivial_hop") - 0.3).abs() < 1e-12);
    assert!(v["cheapest"].is_string());
}

fn assert_files(dir: &Path, names: &[&str]) {
    for name in names {
        let path = dir.join(name);
        let bytes = std::fs::read(&path).unwrap_or_else(|_| panic!("{} missing", path.display()));
        assert!(bytes.len() > 100, "{} too small", path.display());
        if name.ends_with(".png") {
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        }
        if name.ends_with(".svg") {
            assert!(String::from_utf8_lossy(&bytes).contains("<svg"));
        }
    }
    // Atomic writes leave no temporary files.
    for entry in std::fs::read_dir(dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with('.'), "temporary file left: {name}");
    }
}

/// Runs `hopsim ARGS --out DIR`, asserts that it succeeds and that DIR holds `names`
/// ([`assert_files`]).
fn assert_writes(dir: &Path, args: &[&str], names: &[&str]) {
    let mut args = args.to_vec();
    args.extend(["--out", dir.to_str().unwrap()]);
    hopsim_ok(&args);
    assert_files(dir, names);
}

#[test]
fn out_dir_receives_csv_png_svg() {
    let dir = tempfile::tempdir().unwrap();
    let case_dir = dir.path().join("case");
    assert_writes(
        &case_dir,
        &["analyze", "template", "--case", "kangaroo-rat"],
        &[
            "trajectory.csv",
            "hops.csv",
            "trajectory.png",
            "trajectory.svg",
            "hop_speed.png",
            "hop_speed.svg",
        ],
    );
    let trajectory = std::fs::read_to_string(case_dir.join("trajectory.csv")).unwrap();
    assert!(trajectory.starts_with("t_s,hop,phase,x_m,y_m"));

    let grid_dir = dir.path().join("grid");
    assert_writes(
        &grid_dir,
        &[
            "analyze",
            "template",
            "--grid",
            "cargo",
            "--resolution",
            "6",
        ],
        &[
            "cargo_grid.csv",
            "cargo_grid_cost_of_transport.png",
            "cargo_grid_cost_of_transport.svg",
            "cargo_grid_speed.png",
            "cargo_grid_speed.svg",
        ],
    );
    let csv = std::fs::read_to_string(grid_dir.join("cargo_grid.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 36);

    assert_writes(
        &dir.path().join("wheel"),
        &["analyze", "impulsive-wheel", "--series", "3.0,3.5,3.9"],
        &[
            "bifurcation.csv",
            "bifurcation.png",
            "bifurcation.svg",
            "series.csv",
            "series.png",
            "series.svg",
        ],
    );

    assert_writes(
        &dir.path().join("obstacle"),
        &[
            "analyze",
            "obstacle",
            "--resolution",
            "8",
            "--map-height-ratios",
            "0.2",
        ],
        &[
            "costs_vs_speed.csv",
            "costs_vs_speed.png",
            "region_alpha_froude_h0p20.csv",
            "region_alpha_froude_h0p20.png",
            "region_alpha_froude_h0p20.svg",
            "region_mass_speed_h0p20.png",
            "region_mass_speed_h0p20.svg",
        ],
    );
}

#[test]
fn bad_case_name_lists_the_valid_names() {
    let out = hopsim(&["analyze", "template", "--case", "cargo-3"]);
    assert!(!out.status.success());
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    for name in ["cargo-1", "cargo-2", "wallaby", "kangaroo-rat"] {
        assert!(stderr.contains(name), "{stderr}");
    }
}

#[test]
fn bad_numbers_are_clear_errors_not_panics() {
    assert_invalid_input(&[
        &["analyze", "template", "--case", "cargo-2", "--mass", "-3"],
        &[
            "analyze",
            "template",
            "--case",
            "cargo-2",
            "--leg-length",
            "2",
        ],
        &["analyze", "impulsive-wheel", "--inertia", "0"],
        &["analyze", "impulsive-wheel", "--impulse", "nan"],
        &["analyze", "obstacle", "--height-ratio", "1.5"],
        &["analyze", "template", "--grid", "cargo", "--radius", "1"],
        // Sizes that would exhaust memory or time are refused before any work.
        &["analyze", "template", "--hops", "1000000000000"],
        &[
            "analyze",
            "impulsive-wheel",
            "--iterations",
            "1000000000000",
        ],
        &[
            "analyze",
            "impulsive-wheel",
            "--bifurcation-points",
            "1000000000",
            "--out",
            "target/never-written",
        ],
        &["analyze", "fixed-points", "--simulate", "--duration", "1e6"],
    ]);
    // Magnitudes that would overflow the models are refused, and printed short.
    for args in [
        &["analyze", "impulsive-wheel", "--impulse", "1e308"][..],
        &["analyze", "impulsive-wheel", "--initial-angle", "1e308"],
        &["analyze", "obstacle", "--speed", "1e308"],
        &["analyze", "template", "--mass", "1e308"],
    ] {
        let out = hopsim(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains("= 1e308: "), "{args:?}: {stderr}");
    }
}

/// `fixed-points --json` on the default 30 × 30 grid: every point is a fixed point with
/// finite fields or has a reason; stability is max |λ| < 1; a stable point exists.
#[test]
fn fixed_points_default_grid_json() {
    let v = json(&["analyze", "fixed-points", "--json"]);
    assert_eq!(v["analysis"], "fixed-points");
    assert_eq!(v["mode"], "grid");
    let points = v["points"].as_array().expect("points");
    assert_eq!(points.len(), 900);
    assert_eq!(v["points_total"], 900);
    let found = v["fixed_points"].as_u64().unwrap();
    let stable = v["stable_points"].as_u64().unwrap();
    assert_eq!(found + v["no_fixed_point"].as_u64().unwrap(), 900);
    assert!(
        stable > 0,
        "no stable point in the default grid: {}",
        v["no_fixed_point_reasons"]
    );
    let mut counted = 0;
    for q in points {
        finite(q, "takeoff_angle_rad");
        assert!(finite(q, "takeoff_energy_J") >= 0.0);
        assert!(finite(q, "takeoff_rate_rad_s") <= 0.0, "forward rolling");
        if q["fixed_point"] == true {
            assert!(finite(q, "torque_Nm") > 0.0 && finite(q, "impulse_limit_Nms") > 0.0);
            let moduli: Vec<f64> = q["eigenvalues"]
                .as_array()
                .unwrap()
                .iter()
                .map(|l| finite(l, "modulus"))
                .collect();
            let max = finite(q, "max_abs_eigenvalue");
            assert_eq!(max, moduli[0].max(moduli[1]));
            assert_eq!(q["stable"], max < 1.0);
            assert!(finite(q, "residual_rad") <= 1e-9);
            assert!(finite(q, "speed_mps") > 0.0);
            counted += usize::from(q["stable"] == true);
        } else {
            assert!(q["reason"].as_str().is_some_and(|r| !r.is_empty()), "{q}");
        }
    }
    assert_eq!(counted as u64, stable);
    let best = &v["most_stable"];
    assert!(finite(best, "max_abs_eigenvalue") < 1.0);
}

/// One section state with `--simulate`: the fixed point's fields, and the time-stepper
/// from rest converging to it (the tolerances are reported with the verdict).
#[test]
fn fixed_points_single_point_simulates() {
    let v = json(&[
        "analyze",
        "fixed-points",
        "--takeoff-angle",
        "-0.8",
        "--takeoff-energy",
        "0.08",
        "--simulate",
        "--json",
    ]);
    assert_eq!(v["mode"], "point");
    assert_eq!(v["fixed_point"], true);
    assert_eq!(v["takeoff_angle_rad"], -0.8);
    assert_eq!(v["takeoff_energy_J"], 0.08);
    assert!(finite(&v, "max_abs_eigenvalue") < 1.0);
    let sim = &v["simulation"];
    assert_eq!(sim["converged"], true, "{sim}");
    assert!(finite(sim, "max_angle_error_rad") <= finite(sim, "angle_tolerance_rad"));
    assert!(finite(sim, "max_rate_error_rad_s") <= finite(sim, "rate_tolerance_rad_s"));
    let predicted = finite(&sim["predicted"], "speed_mps");
    let simulated = finite(&sim["simulated"], "speed_mps");
    assert!((predicted - simulated).abs() < 0.02 * predicted);
    assert_eq!(finite(sim, "dt_s"), 2e-4);
}

#[test]
fn fixed_points_out_dir_and_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let grid_dir = dir.path().join("fp");
    assert_writes(
        &grid_dir,
        &[
            "analyze",
            "fixed-points",
            "--grid",
            "4x3",
            "--angle-min",
            "-1.2",
            "--angle-max",
            "-0.3",
            "--body-mass",
            "1.0",
            "--touchdown",
            "free",
        ],
        &[
            "fixed_points.csv",
            "fixed_points_torque.png",
            "fixed_points_torque.svg",
            "fixed_points_impulse_limit.png",
            "fixed_points_impulse_limit.svg",
            "fixed_points_max_eigenvalue.png",
            "fixed_points_max_eigenvalue.svg",
        ],
    );
    let csv = std::fs::read_to_string(grid_dir.join("fixed_points.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + 12);
    assert!(lines[0].starts_with("takeoff_angle_rad,takeoff_energy_J,"));
    for column in [
        "torque_Nm",
        "impulse_limit_Nms",
        "max_abs_lambda",
        "stable",
        "reason",
    ] {
        assert!(lines[0].split(',').any(|c| c == column), "{column}");
    }
    let v = json(&[
        "analyze",
        "fixed-points",
        "--angle-points",
        "2",
        "--energy-points",
        "1",
        "--energy-min",
        "0.05",
        "--eccentricity",
        "0.08",
        "--touchdown",
        "free",
        "--json",
    ]);
    assert_eq!(v["parameters"]["eccentricity_m"], 0.08);
    assert_eq!(v["parameters"]["flywheel_at_touchdown"], "free");
    assert_eq!(v["points_total"], 2);
    assert_eq!(v["energies_J"][0], 0.05);
}

#[test]
fn fixed_points_bad_input_exits_2() {
    assert_invalid_input(&[
        &["analyze", "fixed-points", "--grid", "0x5"],
        &["analyze", "fixed-points", "--grid", "big"],
        &["analyze", "fixed-points", "--eccentricity", "0.3"],
        &["analyze", "fixed-points", "--flywheel-inertia", "-1"],
        &[
            "analyze",
            "fixed-points",
            "--angle-min",
            "0.2",
            "--angle-max",
            "-0.2",
        ],
        &["analyze", "fixed-points", "--takeoff-angle", "-0.5"],
        &[
            "analyze",
            "fixed-points",
            "--takeoff-angle",
            "-0.5",
            "--takeoff-energy",
            "-1",
        ],
    ]);
}

/// Every object key of `value` (recursively), with its path for messages.
fn keys(value: &serde_json::Value, path: &str, out: &mut Vec<String>) {
    match value {
        serde_json::Value::Object(map) => {
            for (k, v) in map {
                out.push(format!("{path}.{k}"));
                keys(v, &format!("{path}.{k}"), out);
            }
        }
        serde_json::Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                keys(v, &format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}

/// A unit suffix in lower case where the SI symbol is upper case: `_ns` reads as
/// nanoseconds. N s, N m s, N m, J and N are written `_Ns`, `_Nms`, `_Nm`, `_J`, `_N`.
fn lower_case_si_suffix(name: &str) -> bool {
    let last = name.rsplit(['.', '_']).next().unwrap_or("");
    name.contains('_') && ["ns", "nms", "nm", "j", "n"].contains(&last)
}

#[test]
fn machine_readable_names_spell_units_with_si_symbols() {
    let dir = tempfile::tempdir().unwrap();
    let runs: &[&[&str]] = &[
        &["analyze", "template", "--case", "cargo-2"],
        &[
            "analyze",
            "template",
            "--grid",
            "cargo",
            "--resolution",
            "3",
        ],
        &[
            "analyze",
            "template",
            "--grid",
            "wallaby",
            "--resolution",
            "2",
        ],
        &["analyze", "impulsive-wheel", "--bifurcation-points", "4"],
        &[
            "analyze",
            "obstacle",
            "--resolution",
            "2",
            "--map-height-ratios",
            "0.2",
        ],
        &[
            "analyze",
            "fixed-points",
            "--takeoff-angle",
            "-0.8",
            "--takeoff-energy",
            "0.08",
            "--simulate",
            "--duration",
            "2",
        ],
        &["analyze", "fixed-points", "--grid", "2x2"],
    ];
    for (i, args) in runs.iter().enumerate() {
        let out = dir.path().join(i.to_string());
        let mut with_json = args.to_vec();
        with_json.extend(["--json", "--out", out.to_str().unwrap()]);
        let mut names = Vec::new();
        keys(&json(&with_json), "", &mut names);
        for entry in std::fs::read_dir(&out).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "csv") {
                let text = std::fs::read_to_string(&path).unwrap();
                let header = text.lines().next().unwrap_or("");
                names.extend(
                    header
                        .split(',')
                        .map(|c| format!("{}: {c}", path.display())),
                );
            }
        }
        let bad: Vec<&String> = names.iter().filter(|n| lower_case_si_suffix(n)).collect();
        assert!(bad.is_empty(), "{args:?}: {bad:?}");
    }
    // The names the issue fixed stay as they are.
    let v = json(&["analyze", "impulsive-wheel", "--json"]);
    for key in ["fixed_point_rad", "eigenvalue", "stable", "impulse_Ns"] {
        assert!(v.get(key).is_some(), "{key}");
    }
    assert_eq!(v["stable_impulse_interval_Ns"].as_array().unwrap().len(), 2);
    let v = json(&["analyze", "template", "--json"]);
    for key in [
        "mean_speed_mps",
        "stride_m",
        "hop_frequency_hz",
        "cost_of_transport",
        "impulse_Ns",
        "touchdown_loss_J",
        "min_stance_normal_force_N",
    ] {
        assert!(v.get(key).is_some(), "{key}");
    }
}

#[test]
fn template_window_errors_name_the_window() {
    for (args, expected) in [
        (&["--window", "0"][..], "invalid parameter `window` = 0"),
        (&["--window", "200"][..], "invalid parameter `window` = 200"),
        (
            &["--hops", "20", "--window", "30"][..],
            "invalid parameter `window` = 30",
        ),
        (&["--hops", "5"][..], "invalid parameter `hops` = 5"),
    ] {
        let mut all = vec!["analyze", "template"];
        all.extend(args);
        let out = hopsim(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
    let v = json(&[
        "analyze", "template", "--hops", "20", "--window", "1", "--json",
    ]);
    assert_eq!(v["parameters"]["window"], 1);
}

#[test]
fn obstacle_table_names_the_rolling_path_as_the_json_does() {
    for froude in ["0.5", "5"] {
        let args = ["analyze", "obstacle", "--froude", froude];
        let path = json(&[&args[..], &["--json"]].concat())["rolling"]["path"]
            .as_str()
            .expect("rolling.path")
            .to_string();
        let table = String::from_utf8(hopsim_ok(&args).stdout).unwrap();
        assert!(table.contains(&format!("path {path}")), "{path}: {table}");
        assert!(
            !table.contains("PivotOver") && !table.contains("FlewOff"),
            "{table}"
        );
    }
}

/// The fixed-points table, the CSV and the JSON say "solver failed" alike.
#[test]
fn fixed_points_solver_failure_reads_the_same_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "analyze",
        "fixed-points",
        "--angle-points",
        "1",
        "--energy-points",
        "1",
        "--angle-min",
        "-0.15",
        "--energy-min",
        "0.005",
    ];
    let table = String::from_utf8(hopsim_ok(&args).stdout).unwrap();
    assert!(table.contains("1 solver failed"), "{table}");
    let v = json(
        &[
            &args[..],
            &["--json", "--out", dir.path().to_str().unwrap()],
        ]
        .concat(),
    );
    assert_eq!(v["no_fixed_point_reasons"]["solver-failed"], 1, "{v}");
    let point = &v["points"][0];
    assert_eq!(point["reason_kind"], "solver-failed");
    assert!(point["reason"]
        .as_str()
        .unwrap()
        .starts_with("solver failed: residual"));
    let csv = std::fs::read_to_string(dir.path().join("fixed_points.csv")).unwrap();
    assert!(
        csv.lines()
            .nth(1)
            .unwrap()
            .contains("solver failed: residual"),
        "{csv}"
    );
}

#[test]
fn quiet_prints_nothing_but_keeps_json_and_files() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &[
            "analyze",
            "template",
            "--grid",
            "cargo",
            "--resolution",
            "3",
        ][..],
        &["analyze", "impulsive-wheel"][..],
        &[
            "analyze",
            "obstacle",
            "--resolution",
            "2",
            "--map-height-ratios",
            "0.2",
        ][..],
        &["analyze", "fixed-points", "--grid", "2x2"][..],
        &["analyze", "gait", "scenes/robbit.toml", "--duration", "2"][..],
    ] {
        let out = dir.path().join(args[1]);
        let quiet = hopsim_ok(&[args, &["-q", "--out", out.to_str().unwrap()]].concat());
        assert!(quiet.stdout.is_empty(), "{args:?}: {:?}", quiet.stdout);
        assert!(quiet.stderr.is_empty(), "{args:?}: {:?}", quiet.stderr);
        assert!(std::fs::read_dir(&out).unwrap().count() > 0, "{args:?}");
        let v = json(&[args, &["--quiet", "--json"]].concat());
        assert!(v["analysis"].is_string(), "{args:?}");
    }
}

/// `hopsim analyze gait` on a scene and on its MCAP recording: the report's keys, its files,
/// and the same cycles from both (the brake events are recorded exactly).
#[test]
fn gait_of_a_scene_and_of_its_recording() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let scene = "scenes/robbit-experiment.toml";
    let v = json(&[
        "analyze",
        "gait",
        scene,
        "--duration",
        "3",
        "--last",
        "4",
        "--json",
        "--out",
        &p("out"),
    ]);
    assert_eq!(v["analysis"], "gait");
    assert_eq!(v["split"]["kind"], "event");
    assert_eq!(v["split"]["event"], "brake");
    assert!((finite(&v, "duration_s") - 3.0).abs() < 1e-9);
    let cycles = v["cycles"].as_array().unwrap();
    assert!(cycles.len() >= 8, "{} cycles in 3 s", cycles.len());
    for key in [
        "start_s",
        "period_s",
        "distance_m",
        "speed_mps",
        "flight_fraction",
        "stance_fraction",
        "motor_on_fraction",
        "apex_height_m",
    ] {
        finite(&cycles[0], key);
    }
    assert_eq!(v["last"]["cycles"], 4);
    for key in [
        "mean_period_s",
        "speed_mps",
        "flight_fraction",
        "motor_on_fraction",
    ] {
        finite(&v["last"], key);
    }
    assert!(v["periodicity"]["residuals"].as_array().unwrap().len() == 4);
    assert!(v["periodicity"].get("period").is_some());
    assert_eq!(
        v["profiles"]["progress_percent"].as_array().unwrap().len(),
        101
    );
    assert_eq!(v["profiles"]["y_m"].as_array().unwrap().len(), 4);
    let files: Vec<&str> = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    for name in [
        "gait_cycles.csv",
        "gait_profiles.csv",
        "gait_profiles.png",
        "gait_profiles.svg",
        "gait_periodicity.png",
        "gait_periodicity.svg",
    ] {
        assert!(
            files.iter().any(|f| f.ends_with(name)),
            "{name} not in {files:?}"
        );
        assert!(Path::new(&p("out")).join(name).is_file(), "{name}");
    }
    let csv = std::fs::read_to_string(Path::new(&p("out")).join("gait_cycles.csv")).unwrap();
    assert_eq!(csv.lines().count(), cycles.len() + 1);

    hopsim_ok(&[
        "run",
        scene,
        "--duration",
        "3",
        "--mcap",
        &p("run.mcap"),
        "-q",
    ]);
    let r = json(&["analyze", "gait", &p("run.mcap"), "--last", "4", "--json"]);
    assert_eq!(r["source"], p("run.mcap"));
    let recorded = r["cycles"].as_array().unwrap();
    assert_eq!(recorded.len(), cycles.len());
    for (a, b) in cycles.iter().zip(recorded) {
        assert_eq!(a["start_s"], b["start_s"]);
        assert_eq!(a["period_s"], b["period_s"]);
    }
}

/// CaneBot's cycles are its motor periods unless another split is asked for.
#[test]
fn gait_splits_canebot_at_its_motor_period() {
    let canebot = |split: &[&str]| {
        let scene = [
            "analyze",
            "gait",
            "scenes/canebot.toml",
            "--duration",
            "3",
            "--json",
        ];
        json(&[&scene[..], split].concat())
    };
    let v = canebot(&[]);
    assert_eq!(v["split"]["kind"], "period");
    let period = finite(&v["split"], "period_s");
    assert!((period - 1.0 / 2.8).abs() < 1e-12);
    let v = canebot(&["--split", "take-off"]);
    assert_eq!(v["split"]["event"], "take_off");
}

#[test]
fn gait_rejects_bad_input_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("missing.mcap").display().to_string();
    let not_mcap = dir.path().join("text.mcap");
    std::fs::write(&not_mcap, "not a recording").unwrap();
    let not_mcap = not_mcap.display().to_string();
    fn robbit<'a>(args: &[&'a str]) -> Vec<&'a str> {
        [&["analyze", "gait", "scenes/robbit.toml"][..], args].concat()
    }
    let cases = [
        robbit(&["--split", "hop"]),
        robbit(&["--split", "period"]),
        robbit(&["--split", "period", "--period", "0"]),
        robbit(&["--split", "brake", "--period", "0.3"]),
        robbit(&["--last", "0"]),
        robbit(&["--duration", "0.2"]),
        robbit(&["--set", "controller.off_time=0.1"]),
        vec!["analyze", "gait", "tests/scenes/invalid/negative_mass.toml"],
        vec!["analyze", "gait", "scenes/no-such-scene.toml"],
        vec!["analyze", "gait", &mcap],
        vec!["analyze", "gait", &not_mcap],
        vec![
            "analyze",
            "gait",
            &not_mcap,
            "--set",
            "controller.torque=0.3",
        ],
    ];
    let cases: Vec<&[&str]> = cases.iter().map(Vec::as_slice).collect();
    assert_invalid_input(&cases);
}
