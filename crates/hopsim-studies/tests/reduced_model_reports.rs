//! The reports of the reduced-model studies (template, obstacle, impulsive wheel) keep the
//! keys and file names of `hopsim analyze … --json` / `--out`, which scripts read.

use hopsim_studies::impulsive_wheel::{impulsive_wheel, BifurcationParams, ImpulsiveWheelParams};
use hopsim_studies::obstacle::{obstacle, MapParams, ObstacleParams};
use hopsim_studies::progress::Silent;
use hopsim_studies::template::{
    animal_sweeps, cargo_grid, template_case, AnimalSweepsParams, CargoGridParams, CaseParams,
};
use hopsim_studies::{Report, ReportFile};
use hopsim_theory::impulsive_wheel::ImpulsiveWheel;
use hopsim_theory::obstacle::Wheel;
use hopsim_theory::template::{CargoGrid, TemplateCase, TemplateParams};
use serde::Serialize;

/// The sorted keys of the object `report` serialises to.
fn keys(report: &impl Serialize) -> Vec<String> {
    object_keys(&serde_json::to_value(report).unwrap())
}

fn object_keys(value: &serde_json::Value) -> Vec<String> {
    let mut keys: Vec<String> = value
        .as_object()
        .expect("an object")
        .keys()
        .cloned()
        .collect();
    keys.sort_unstable();
    keys
}

/// The names the report's files are written under (`stem.png` and `stem.svg` per figure).
fn file_names(report: &impl Report) -> Vec<String> {
    report
        .files()
        .iter()
        .flat_map(|f| match f {
            ReportFile::Csv { name, .. } => vec![name.clone()],
            ReportFile::Figure { stem, .. } => vec![format!("{stem}.png"), format!("{stem}.svg")],
        })
        .collect()
}

const PARAMETERS: [&str; 12] = [
    "convergence_tolerance",
    "eccentricity_m",
    "energy_input_J",
    "gravity_mps2",
    "hops",
    "impulse_tilt_rad",
    "inertia_kg_m2",
    "leg_length_m",
    "mass_kg",
    "radius_m",
    "takeoff_angle_rad",
    "window",
];

#[test]
fn template_case_report() {
    for energy in [37.6, 0.0] {
        let p = CaseParams {
            case: TemplateCase::Cargo2,
            params: TemplateParams {
                energy_input: energy,
                hops: 20,
                ..TemplateCase::Cargo2.params()
            },
            record_trajectory: true,
        };
        let report = template_case(&p).unwrap();
        // Without a gait (ΔE = 0) the gait's keys stay, as nulls.
        assert_eq!(
            keys(&report),
            [
                "analysis",
                "case",
                "converged",
                "cost_of_transport",
                "dimensionless_speed",
                "flight_time_s",
                "froude_number",
                "gait",
                "hop_frequency_hz",
                "hops_completed",
                "impulse_Ns",
                "mean_speed_mps",
                "min_stance_normal_force_N",
                "no_gait",
                "no_gait_reason",
                "parameters",
                "speed_spread",
                "stride_m",
                "touchdown_angle_rad",
                "touchdown_loss_J",
                "warnings",
            ]
        );
        let v = serde_json::to_value(&report).unwrap();
        assert_eq!(object_keys(&v["parameters"]), PARAMETERS);
        assert_eq!(
            (v["case"].as_str(), v["gait"].as_bool()),
            (Some("cargo-2"), Some(energy > 0.0))
        );
        assert_eq!(
            file_names(&report),
            [
                "trajectory.csv",
                "hops.csv",
                "trajectory.png",
                "trajectory.svg",
                "hop_speed.png",
                "hop_speed.svg"
            ]
        );
    }
}

#[test]
fn template_grid_reports() {
    let grid = cargo_grid(
        &CargoGridParams {
            base: CargoGrid::table_3_1_base(),
            resolution: 2,
        },
        &Silent,
    )
    .unwrap();
    assert_eq!(
        keys(&grid),
        [
            "analysis",
            "base_parameters",
            "cells",
            "cells_converged",
            "cells_total",
            "cells_with_gait",
            "elapsed_s",
            "grid",
            "leg_over_radius",
            "max_speed",
            "min_cost_of_transport",
            "takeoff_angles_rad",
        ]
    );
    let v = serde_json::to_value(&grid).unwrap();
    assert_eq!(v["cells"].as_array().unwrap().len(), 4);
    assert_eq!(
        object_keys(&v["cells"][0]),
        [
            "converged",
            "cost_of_transport",
            "hop_frequency_hz",
            "leg_over_radius",
            "mean_speed_mps",
            "no_gait_reason",
            "radius_m",
            "stride_m",
            "takeoff_angle_rad",
        ]
    );
    assert_eq!(
        file_names(&grid),
        [
            "cargo_grid.csv",
            "cargo_grid_cost_of_transport.png",
            "cargo_grid_cost_of_transport.svg",
            "cargo_grid_speed.png",
            "cargo_grid_speed.svg"
        ]
    );

    let animals = animal_sweeps(
        &AnimalSweepsParams {
            animals: [TemplateCase::Wallaby, TemplateCase::KangarooRat]
                .map(|c| {
                    (
                        c,
                        TemplateParams {
                            hops: 20,
                            ..c.params()
                        },
                    )
                })
                .to_vec(),
            energies: 2,
        },
        &Silent,
    )
    .unwrap();
    assert_eq!(keys(&animals), ["analysis", "elapsed_s", "sweeps"]);
    let v = serde_json::to_value(&animals).unwrap();
    let sweep = &v["sweeps"][1];
    assert_eq!(sweep["case"], "kangaroo-rat");
    assert_eq!(object_keys(sweep), ["base_parameters", "case", "points"]);
    assert_eq!(sweep["points"].as_array().unwrap().len(), 5 * 2);
    assert_eq!(
        object_keys(&sweep["points"][0]),
        [
            "converged",
            "dimensionless_speed",
            "energy_input_J",
            "mean_speed_mps",
            "no_gait_reason",
            "stride_m",
            "takeoff_angle_rad",
        ]
    );
    assert_eq!(
        file_names(&animals),
        [
            "wallaby_sweep.csv",
            "wallaby_stride_vs_speed.png",
            "wallaby_stride_vs_speed.svg",
            "kangaroo-rat_sweep.csv",
            "kangaroo-rat_stride_vs_speed.png",
            "kangaroo-rat_stride_vs_speed.svg"
        ]
    );
}

#[test]
fn obstacle_report() {
    let wheel = Wheel {
        mass: 1.0,
        radius: 0.5,
        inertia: 0.125,
        gravity: 9.81,
    };
    let p = ObstacleParams {
        wheel,
        speed_mps: wheel.speed_from_froude(1.0),
        height_m: 0.1,
        maps: Some(MapParams {
            height_ratios: vec![0.2],
            resolution: 2,
        }),
    };
    let report = obstacle(&p, &Silent).unwrap();
    assert_eq!(
        keys(&report),
        [
            "analysis",
            "cheapest",
            "costs_per_mgr",
            "energy_unit_J",
            "froude",
            "height_m",
            "height_ratio",
            "inertia_factor",
            "map_timings_s",
            "rolling",
            "rotational_hop",
            "speed_mps",
            "trivial_hop_J",
            "wheel",
        ]
    );
    let v = serde_json::to_value(&report).unwrap();
    assert_eq!(
        object_keys(&v["wheel"]),
        ["gravity_mps2", "inertia_kg_m2", "mass_kg", "radius_m"]
    );
    assert_eq!(
        object_keys(&v["costs_per_mgr"]),
        ["rolling", "rotational_hop", "trivial_hop"]
    );
    assert_eq!(object_keys(&v["map_timings_s"][1]), ["elapsed_s", "map"]);
    assert_eq!(
        file_names(&report),
        [
            "costs_vs_speed.csv",
            "costs_vs_speed.png",
            "costs_vs_speed.svg",
            "region_alpha_froude_h0p20.csv",
            "region_alpha_froude_h0p20.png",
            "region_alpha_froude_h0p20.svg",
            "region_mass_speed_h0p20.csv",
            "region_mass_speed_h0p20.png",
            "region_mass_speed_h0p20.svg"
        ]
    );
}

#[test]
fn impulsive_wheel_report() {
    let p = ImpulsiveWheelParams {
        wheel: ImpulsiveWheel::default(),
        impulse_n_s: 3.5,
        series_impulses_n_s: vec![3.0, 3.9],
        iterations: 5,
        initial_angle_rad: 0.1,
        bifurcation: Some(BifurcationParams {
            impulse_min_n_s: 2.0,
            impulse_max_n_s: 5.0,
            points: 4,
        }),
    };
    let report = impulsive_wheel(&p).unwrap();
    assert_eq!(
        keys(&report),
        [
            "analysis",
            "coupling",
            "drift_rad",
            "eigenvalue",
            "fixed_point_rad",
            "impulse_Ns",
            "parameters",
            "rolling_speed_rad_s",
            "series",
            "stable",
            "stable_impulse_interval_Ns",
        ]
    );
    let v = serde_json::to_value(&report).unwrap();
    assert_eq!(
        object_keys(&v["parameters"]),
        [
            "cycle_time",
            "gravity",
            "inertia",
            "mass",
            "radius",
            "rolling_energy"
        ]
    );
    assert_eq!(
        object_keys(&v["series"][1]),
        ["impulse_Ns", "takeoff_angles_rad"]
    );
    assert_eq!(v["stable_impulse_interval_Ns"].as_array().unwrap().len(), 2);
    assert_eq!(
        file_names(&report),
        [
            "bifurcation.csv",
            "bifurcation.png",
            "bifurcation.svg",
            "series.csv",
            "series.png",
            "series.svg"
        ]
    );
}
