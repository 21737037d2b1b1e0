//! `hopsim lcp solve`: JSON and text output on the bundled problems, an unsolvable LCP
//! (a result, exit 0) and malformed or missing files (exit 2, the file named on stderr).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/lcp")
        .join(name)
}

fn hopsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(args)
        .output()
        .expect("run hopsim")
}

fn json_lines(out: &Output) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn json_output_for_the_bundled_problems() {
    let files = ["lcp_trivial.dat", "lcp_deudeu.dat", "lcp_exp_murty.dat"].map(data);
    let mut args = vec!["lcp", "solve", "--json"];
    args.extend(files.iter().map(|p| p.to_str().unwrap()));
    let out = hopsim(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 3);
    for (line, file) in lines.iter().zip(&files) {
        assert_eq!(line["file"], file.display().to_string());
        assert_eq!(line["status"], "solved");
        assert!(line["pivots"].as_u64().unwrap() > 0);
        let c = &line["certificate"];
        for key in ["complementarity", "most_negative", "residual", "tolerance"] {
            assert!(c[key].is_f64(), "certificate.{key} in {line}");
        }
        assert!(c["residual"].as_f64().unwrap() <= c["tolerance"].as_f64().unwrap());
        assert_eq!(floats(&line["w"]).len(), floats(&line["z"]).len());
        assert!(line.get("median_solve_ns").is_none());
    }
    let z = floats(&lines[0]["z"]);
    for (i, zi) in z.iter().enumerate() {
        assert!((zi - 1.0 / (i + 1) as f64).abs() < 1e-12);
    }
    let z = floats(&lines[1]["z"]);
    assert!((z[0] - 4.0 / 3.0).abs() < 1e-12 && (z[1] - 7.0 / 3.0).abs() < 1e-12);
    assert_eq!(floats(&lines[2]["z"]), vec![1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(lines[2]["pivots"], 64);
}

#[test]
fn repeat_reports_a_median_solve_time() {
    let file = data("lcp_deudeu.dat");
    let out = hopsim(&[
        "lcp",
        "solve",
        "--json",
        "--repeat",
        "50",
        file.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let line = &json_lines(&out)[0];
    let ns = line["median_solve_ns"].as_f64().unwrap();
    assert!(ns > 0.0 && ns < 1e7, "median_solve_ns = {ns}");
    let text = hopsim(&["lcp", "solve", "--repeat", "5", file.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&text.stdout).contains("median solve"));
}

#[test]
fn text_output_shows_status_vectors_pivots_and_certificate() {
    let out = hopsim(&["lcp", "solve", data("lcp_deudeu.dat").to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "lcp_deudeu.dat",
        "status           solved",
        "pivots",
        "z                1.333",
        "w                0  0",
        "certificate      holds (tolerance",
        "residual",
    ] {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
}

#[test]
fn unsolvable_problem_is_a_ray_termination_with_exit_zero() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no_solution.dat");
    // w = −z − 1 < 0 for every z ≥ 0.
    std::fs::write(&path, "2\n0\n2\n2\n2 2\n-1 0\n0 -1\n-1 -1\n").unwrap();
    let out = hopsim(&["lcp", "solve", "--json", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "an unsolvable LCP is a result, not an error"
    );
    let line = &json_lines(&out)[0];
    assert_eq!(line["status"], "ray_termination");
    assert_eq!(line["certificate"]["holds"], false);
}

#[test]
fn malformed_and_missing_files_exit_2_naming_the_file_and_others_still_solve() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken_problem.dat");
    std::fs::write(&bad, "2 0 2 2 2 2\n1 2\n3 oops\n-1 -1\n").unwrap();
    let missing = dir.path().join("missing_problem.dat");
    let good = data("lcp_deudeu.dat");
    let out = hopsim(&[
        "lcp",
        "solve",
        "--json",
        bad.to_str().unwrap(),
        good.to_str().unwrap(),
        missing.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("broken_problem.dat") && stderr.contains("'oops'"),
        "{stderr}"
    );
    assert!(stderr.contains("missing_problem.dat"), "{stderr}");
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 3);
    assert!(lines[0]["error"]
        .as_str()
        .unwrap()
        .contains("broken_problem.dat"));
    assert_eq!(lines[1]["status"], "solved");
    assert!(lines[2]["error"].is_string());
}

#[test]
fn help_is_available_for_the_lcp_commands() {
    for args in [&["lcp", "--help"][..], &["lcp", "solve", "--help"][..]] {
        let out = hopsim(args);
        assert!(out.status.success());
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("--json") || text.contains("solve"), "{text}");
    }
}
