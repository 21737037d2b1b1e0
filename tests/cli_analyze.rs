//! `hopsim analyze …` end to end: JSON fields, output files, argument errors.

use std::path::Path;
use std::process::{Command, Output};

fn hopsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(args)
        .output()
        .expect("run hopsim")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = hopsim(args);
    assert!(
        out.status.success(),
        "hopsim {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
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
    let expected_cot = p["energy_input_j"].as_f64().unwrap()
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
    assert_eq!(v["parameters"]["energy_input_j"], 40.0);
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
    let interval = v["stable_impulse_interval_ns"].as_array().unwrap();
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

#[test]
fn out_dir_receives_csv_png_svg() {
    let dir = tempfile::tempdir().unwrap();
    let case_dir = dir.path().join("case");
    let out = hopsim(&[
        "analyze",
        "template",
        "--case",
        "kangaroo-rat",
        "--out",
        case_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_files(
        &case_dir,
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
    let out = hopsim(&[
        "analyze",
        "template",
        "--grid",
        "cargo",
        "--resolution",
        "6",
        "--out",
        grid_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_files(
        &grid_dir,
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

    let wheel_dir = dir.path().join("wheel");
    let out = hopsim(&[
        "analyze",
        "impulsive-wheel",
        "--series",
        "3.0,3.5,3.9",
        "--out",
        wheel_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_files(
        &wheel_dir,
        &[
            "bifurcation.csv",
            "bifurcation.png",
            "bifurcation.svg",
            "series.csv",
            "series.png",
            "series.svg",
        ],
    );

    let obstacle_dir = dir.path().join("obstacle");
    let out = hopsim(&[
        "analyze",
        "obstacle",
        "--resolution",
        "8",
        "--map-height-ratios",
        "0.2",
        "--out",
        obstacle_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_files(
        &obstacle_dir,
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
    for args in [
        &["analyze", "template", "--case", "cargo-2", "--mass", "-3"][..],
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
    ] {
        let out = hopsim(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.starts_with("error:"), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}
