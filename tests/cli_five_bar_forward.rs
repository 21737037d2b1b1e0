//! The five-bar leg hopper with two hip servos (`scenes/classic/five-bar-hopper-forward.toml`,
//! docs/classics.md §8) from the command line: it hops forward, and with the leg's sweep
//! taken out of the hips' control signals it hops in place. Each run: at least 20 hops in
//! 20 s, no LCP failure, the loop closed to 1e-10 m and the energy account closed to 1e-4
//! of the actuators' work.

use std::process::Command;

const SCENE: &str = "scenes/classic/five-bar-hopper-forward.toml";

/// The run summary of `hopsim run SCENE` with `sets` (`--set` values).
fn summary(sets: &[&str]) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("r.json");
    let mut args = vec!["run", SCENE, "--quiet", "--summary", json.to_str().unwrap()];
    for s in sets {
        args.extend(["--set", s]);
    }
    let out = Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(&args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("hopsim runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let number = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!(number(&s["duration_s"]), 20.0);
    assert!(s["hops"].as_u64().unwrap() >= 20, "{s}");
    assert_eq!(s["lcp"]["failures"].as_u64(), Some(0), "{s}");
    assert!(number(&s["max_loop_error_m"]) <= 1e-10, "{s}");
    let energy = &s["energy"];
    let work = number(&energy["actuator_work"]);
    assert!(work > 0.0, "{s}");
    assert!(
        number(&energy["max_abs_balance_error"]) <= 1e-4 * work,
        "{s}"
    );
    s
}

#[test]
fn the_servoed_five_bar_hopper_hops_forward() {
    let s = summary(&[]);
    let speed = s["mean_speed_mps"].as_f64().unwrap();
    eprintln!(
        "{} hops, {:.3} m, mean speed {speed:.3} m/s",
        s["hops"],
        s["distance_m"].as_f64().unwrap()
    );
    assert!(speed >= 0.3, "{s}");
    assert!(s["distance_m"].as_f64().unwrap() >= 5.0, "{s}");
}

/// Without the sweep both hips follow the same sine mirrored about the vertical: the leg
/// stays symmetric, so no horizontal force acts and the torso does not travel.
#[test]
fn without_the_sweep_it_hops_in_place() {
    let s = summary(&[
        "actuators.hip_l.control.amplitude=0.3",
        "actuators.hip_l.control.phase=3.141592653589793",
        "actuators.hip_r.control.amplitude=0.3",
        "actuators.hip_r.control.phase=0.0",
    ]);
    assert!(s["distance_m"].as_f64().unwrap().abs() < 1e-6, "{s}");
}
