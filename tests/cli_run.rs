//! `hopsim run`, `hopsim scene check` and `hopsim sweep` as a user runs them: outputs,
//! summaries, exit codes and messages.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn hopsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("hopsim runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

/// `hopsim run scenes/robbit.toml` with `extra` and every output (`r.mcap`, `r.rrd`,
/// `r.csv`, `r.json`) in `dir`.
fn run_robbit_with_every_output(dir: &Path, extra: &[&str]) -> Output {
    let p = |name: &str| dir.join(name).display().to_string();
    let outputs = [
        "--mcap".to_string(),
        p("r.mcap"),
        "--rrd".into(),
        p("r.rrd"),
        "--csv".into(),
        p("r.csv"),
        "--summary".into(),
        p("r.json"),
    ];
    let mut args = vec!["run", "scenes/robbit.toml"];
    args.extend(extra);
    args.extend(outputs.iter().map(String::as_str));
    hopsim(&args)
}

#[test]
fn run_writes_every_output_and_a_complete_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_robbit_with_every_output(dir.path(), &["--duration", "1.5"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("mean speed") && stdout.contains("LCP"),
        "{stdout}"
    );
    for f in ["r.mcap", "r.rrd", "r.csv", "r.events.csv", "r.json"] {
        let meta = std::fs::metadata(dir.path().join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(meta.len() > 0, "{f} is empty");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("r.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "duration_s",
        "dt_s",
        "steps",
        "distance_m",
        "mean_speed_mps",
        "hops",
        "impulse_per_distance_Ns_per_m",
        "max_penetration_m",
        "wall_time_s",
        "steps_per_s",
    ] {
        assert!(json.get(key).is_some(), "summary lacks {key}: {json}");
    }
    assert_eq!(json["steps"], 7500);
    assert!((json["duration_s"].as_f64().unwrap() - 1.5).abs() < 1e-12);
    for key in ["count", "total_Ns"] {
        assert!(json["impulses"].get(key).is_some(), "impulses.{key}");
    }
    assert_eq!(
        json["impulses"]["unit"], "N m s",
        "brakes transfer angular impulse"
    );
    for key in [
        "kinetic",
        "potential",
        "spring",
        "actuator_work",
        "dissipated",
        "balance_error",
    ] {
        assert!(json["energy"][key].is_number(), "energy.{key}");
    }
    for key in ["solves", "failures", "max_pivots", "warm_starts"] {
        assert!(json["lcp"][key].is_number(), "lcp.{key}");
    }
    for key in [
        "brakes_per_s",
        "impulse_per_distance_Nms_per_m",
        "cube_baseline",
    ] {
        assert!(json["robbit"].get(key).is_some(), "robbit.{key}");
    }
    // The recording stores the scene file so that it can be rerun.
    let rec = hopsim_record::McapRecording::read(&dir.path().join("r.mcap")).unwrap();
    let scene = std::fs::read_to_string("scenes/robbit.toml").unwrap();
    assert_eq!(rec.scene.map(|s| s.text), Some(scene));
}

/// `simulation.warm_start = false` solves every contact LCP from scratch; the default
/// answers most of Robbit's stance steps from the previous step's basis, and both give
/// the same run up to round-off (one solution per LCP).
#[test]
fn warm_start_can_be_switched_off() {
    let summary = |extra: &[&str]| -> serde_json::Value {
        let dir = tempfile::tempdir().unwrap();
        let json = dir.path().join("r.json").display().to_string();
        let mut args = vec!["run", "scenes/robbit.toml", "--duration", "3", "--quiet"];
        args.extend(extra);
        args.extend(["--summary", json.as_str()]);
        let out = hopsim(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap()
    };
    let warm = summary(&[]);
    let cold = summary(&["--set", "simulation.warm_start=false"]);
    let solves = warm["lcp"]["solves"].as_u64().unwrap();
    assert_eq!(cold["lcp"]["solves"].as_u64(), Some(solves));
    assert_eq!(cold["lcp"]["warm_starts"].as_u64(), Some(0));
    let warm_starts = warm["lcp"]["warm_starts"].as_u64().unwrap();
    assert!(warm_starts * 10 > solves * 9, "{warm_starts} of {solves}");
    let (a, b) = (&warm["distance_m"], &cold["distance_m"]);
    let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
    assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{a} against {b}");
    assert_eq!(warm["hops"], cold["hops"]);
}

/// Every gallery scene (`scenes/classic/`) runs from the command line and records to MCAP
/// and Rerun; the MCAP holds the scene's states and names its coordinates.
#[test]
fn every_gallery_scene_runs_and_records() {
    let scenes: Vec<PathBuf> = files_in(Path::new("scenes/classic"))
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    assert!(
        scenes.iter().any(|p| p.ends_with("woodpecker.toml")),
        "{scenes:?}"
    );
    let dir = tempfile::tempdir().unwrap();
    for scene in &scenes {
        let (mcap, rrd) = (dir.path().join("r.mcap"), dir.path().join("r.rrd"));
        let out = hopsim(&[
            "run",
            &scene.display().to_string(),
            "--duration",
            "0.05",
            "--quiet",
            "--mcap",
            &mcap.display().to_string(),
            "--rrd",
            &rrd.display().to_string(),
        ]);
        assert!(
            out.status.success(),
            "{}: {}",
            scene.display(),
            text(&out.stderr)
        );
        assert!(
            std::fs::metadata(&rrd).unwrap().len() > 0,
            "{}",
            scene.display()
        );
        let rec = hopsim_record::McapRecording::read(&mcap).unwrap();
        assert!(!rec.states.is_empty(), "{}", scene.display());
    }
}

/// The five-bar leg hopper (a closed chain, docs/classics.md §8) hops from the command
/// line: at least 20 hops in 20 s, no LCP failure, its loop closed to 1e-10 m and its energy
/// account closed to 1 % of the run's energy scale.
#[test]
fn the_five_bar_hopper_hops_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("r.json").display().to_string();
    let out = hopsim(&[
        "run",
        "scenes/classic/five-bar-hopper.toml",
        "--quiet",
        "--summary",
        json.as_str(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let number = |v: &serde_json::Value| v.as_f64().unwrap();
    assert!(summary["hops"].as_u64().unwrap() >= 20, "{summary}");
    assert_eq!(summary["lcp"]["failures"].as_u64(), Some(0));
    assert!(number(&summary["max_loop_error_m"]) <= 1e-10, "{summary}");
    let energy = &summary["energy"];
    assert!(
        number(&energy["max_abs_balance_error"]) <= 1e-2 * number(&energy["scale_J"]),
        "{summary}"
    );
}

#[test]
fn quiet_prints_nothing() {
    let out = hopsim(&["run", "scenes/robbit.toml", "--duration", "0.2", "--quiet"]);
    assert!(out.status.success());
    assert!(out.stdout.is_empty() && out.stderr.is_empty());
}

#[test]
fn an_invalid_scene_exits_2_with_its_location() {
    let out = hopsim(&["run", "tests/scenes/invalid/negative_mass.toml"]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(
        err.contains("negative_mass.toml:") && err.contains("bodies[1].mass: expected a positive"),
        "{err}"
    );
    let out = hopsim(&[
        "run",
        "scenes/robbit.toml",
        "--set",
        "controller.torque=fast",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--set controller.torque=fast"));
    let out = hopsim(&["run", "scenes/no_such_scene.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("no_such_scene.toml"));
}

#[test]
fn scene_check_describes_a_valid_scene_and_rejects_a_broken_one() {
    let out = hopsim(&["scene", "check", "scenes/robbit.toml"]);
    assert!(out.status.success());
    let s = text(&out.stdout);
    assert!(
        s.contains("ok") && s.contains("x, y, phi, psi") && s.contains("momentum"),
        "{s}"
    );
    let out = hopsim(&[
        "scene",
        "check",
        "tests/scenes/invalid/unknown_key_typo.toml",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("did you mean 'mass'"));
}

#[test]
fn sweep_writes_a_row_per_run_in_grid_order_and_a_plot() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("sweep");
    let out = hopsim(&[
        "sweep",
        "scenes/robbit.toml",
        "--grid",
        "controller.torque=0.2,0.3",
        "--grid",
        "controller.impulse_limit=0.05:0.06:2",
        "--grid",
        "bodies.disc.mass=1.0,-1.0",
        "--duration",
        "1",
        "--out",
        &out_dir.display().to_string(),
        "--quiet",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let csv = std::fs::read_to_string(out_dir.join("sweep.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 1 + 8, "{csv}");
    assert!(rows[0].starts_with(
        "label,controller.torque,controller.impulse_limit,bodies.disc.mass,status,error,"
    ));
    // Row-major: the last axis varies fastest; an invalid value is a row with its error.
    assert!(rows[1].starts_with("grid,0.2,0.05,1,ok,,"), "{}", rows[1]);
    assert!(
        rows[2].starts_with("grid,0.2,0.05,-1,error,"),
        "{}",
        rows[2]
    );
    assert!(rows[2].contains("bodies[0].mass"), "{}", rows[2]);
    assert!(rows[8].starts_with("grid,0.3,0.06,-1,error"), "{}", rows[8]);
    for f in ["sweep.png", "sweep.svg"] {
        assert!(
            std::fs::metadata(out_dir.join(f)).unwrap().len() > 1000,
            "{f}"
        );
    }
}

/// `--speed` paces a live stream: a positive factor or `max`, and only with `--spawn`.
#[test]
fn speed_needs_spawn_and_a_positive_factor() {
    let out = hopsim(&["run", "scenes/robbit.toml", "--speed", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("--spawn"),
        "{}",
        text(&out.stderr)
    );
    for bad in ["0", "fast"] {
        let out = hopsim(&["run", "scenes/robbit.toml", "--spawn", "--speed", bad]);
        assert_eq!(out.status.code(), Some(2));
        let err = text(&out.stderr);
        assert!(
            err.contains("positive factor") && err.contains("max"),
            "{err}"
        );
    }
}

#[test]
fn help_is_available_for_every_command() {
    for args in [
        &["--help"][..],
        &["run", "--help"],
        &["sweep", "--help"],
        &["scene", "check", "--help"],
        &["compare", "--help"],
    ] {
        let out = hopsim(args);
        assert!(out.status.success(), "{args:?}");
        assert!(text(&out.stdout).contains("Usage"), "{args:?}");
    }
}

#[test]
fn outputs_on_one_path_or_on_the_scene_are_refused_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("robbit.toml");
    std::fs::copy("scenes/robbit.toml", &scene).unwrap();
    let original = std::fs::read_to_string(&scene).unwrap();
    let s = scene.display().to_string();
    let csv = dir.path().join("a.csv").display().to_string();
    let mcap = dir.path().join("a.mcap").display().to_string();
    for (args, expect) in [
        (vec!["--summary", s.as_str()], "that is the scene file"),
        (
            vec!["--csv", csv.as_str(), "--summary", csv.as_str()],
            "is also the --csv output",
        ),
        (
            vec!["--rrd", mcap.as_str()],
            "a .mcap name is for --mcap; --rrd writes a .rrd file",
        ),
    ] {
        let mut all = vec!["run", s.as_str(), "--duration", "0.2", "-q"];
        all.extend(args);
        let out = hopsim(&all);
        assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
        assert!(text(&out.stderr).contains(expect), "{}", text(&out.stderr));
    }
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), original);
    assert_eq!(files_in(dir.path()), [scene]);
    // A name of no output format is written, with a warning.
    let odd = dir.path().join("a.rerun").display().to_string();
    let out = hopsim(&[
        "run",
        s.as_str(),
        "--duration",
        "0.01",
        "--rrd",
        odd.as_str(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("--rrd writes a .rrd file, and this name does not end in .rrd"),
        "{}",
        text(&out.stderr)
    );
    assert!(Path::new(&odd).is_file());
}

/// Starts a long recorded run in a fresh folder, waits until its recorders have created
/// their temporary files, sends `signals` 50 ms apart and returns the output and the files
/// left in the folder.
#[cfg(unix)]
fn interrupted_run(signals: &[libc::c_int]) -> (std::process::Output, Vec<PathBuf>) {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let child = Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args(["run", "scenes/robbit.toml", "--duration", "2000", "-q"])
        .args([
            "--mcap",
            &p("a.mcap"),
            "--rrd",
            &p("a.rrd"),
            "--csv",
            &p("a.csv"),
        ])
        .args(["--summary", &p("a.json")])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while files_in(dir.path()).len() < 5 && started.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    for &signal in signals {
        // SAFETY: sends a signal to the child we spawned.
        unsafe {
            libc::kill(child.id() as libc::pid_t, signal);
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let out = child.wait_with_output().unwrap();
    let left = files_in(dir.path());
    (out, left)
}

/// The recordings of an interrupted run (`interrupted_run` writes `a.*`).
const PARTIAL_RECORDINGS: [&str; 4] = [
    "a.partial.csv",
    "a.partial.events.csv",
    "a.partial.mcap",
    "a.partial.rrd",
];

fn names(paths: &[PathBuf]) -> Vec<String> {
    paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}

/// Ctrl-C, SIGHUP and SIGTERM stop the run at the next step (exit 128 + the signal): the
/// recordings up to there are kept under partial names with the reason, no complete
/// output, summary or temporary file is left.
#[cfg(unix)]
#[test]
fn an_interrupted_run_keeps_its_recordings_under_partial_names() {
    for (signal, code) in [
        (libc::SIGINT, 130),
        (libc::SIGHUP, 129),
        (libc::SIGTERM, 143),
    ] {
        let (out, left) = interrupted_run(&[signal]);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{signal}: {err}");
        assert!(err.contains("interrupted at t ="), "{err}");
        assert_eq!(names(&left), PARTIAL_RECORDINGS, "{signal}");
        assert!(
            err.contains("a.partial.mcap") && err.contains("summary was not written"),
            "{err}"
        );
    }
}

/// A second Ctrl-C 50 ms after the first ends the process at once, but not while the
/// run keeps its recordings: they are all kept or none is (never a subset), and nothing
/// complete-looking or temporary is left.
#[cfg(unix)]
#[test]
fn repeated_interrupts_leave_no_complete_or_temporary_file() {
    for _ in 0..3 {
        let (out, left) = interrupted_run(&[libc::SIGINT, libc::SIGINT]);
        assert_eq!(out.status.code(), Some(130), "{}", text(&out.stderr));
        let left = names(&left);
        assert!(
            left.is_empty() || left == PARTIAL_RECORDINGS,
            "left {left:?}: {}",
            text(&out.stderr)
        );
    }
}

/// A panic inside a step (forced with the test hook `HOPSIM_PANIC_AT_STEP`) is an internal
/// error: exit code 4, the step named, the recordings up to it kept under partial names.
#[test]
fn a_panic_in_a_step_is_an_internal_error_that_keeps_the_recordings() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("r.mcap").display().to_string();
    let out = Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args([
            "run",
            "scenes/robbit.toml",
            "--duration",
            "1",
            "--mcap",
            &mcap,
        ])
        .env("HOPSIM_PANIC_AT_STEP", "300")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(4), "{err}");
    assert!(
        err.contains("internal error in step 300") && err.contains("please report"),
        "{err}"
    );
    assert_eq!(names(&files_in(dir.path())), ["r.partial.mcap"], "{err}");
}

/// A run of a sweep that panics is one failed row; the others and the table are complete.
#[test]
fn a_panic_in_one_sweep_run_is_one_failed_row() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("sweep");
    // At Δt = 2e-4 s the 0.1 s run takes 500 steps and ends before step 1000; the
    // 0.5 s run panics there.
    let out = Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .args([
            "sweep",
            "scenes/robbit.toml",
            "--grid",
            "simulation.duration=0.1,0.5",
        ])
        .args(["--out", &out_dir.display().to_string(), "--quiet"])
        .env("HOPSIM_PANIC_AT_STEP", "1000")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let csv = std::fs::read_to_string(out_dir.join("sweep.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 3, "{csv}");
    assert!(rows[1].starts_with("grid,0.1,ok,"), "{}", rows[1]);
    assert!(
        rows[2].starts_with("grid,0.5,error,") && rows[2].contains("internal error in step 1000"),
        "{}",
        rows[2]
    );
}

/// A pulse on a prismatic joint is a force everywhere: `scene check` says so in N, and the
/// CSV column is `actuator_force_N`.
#[test]
fn a_prismatic_pulse_is_a_force() {
    let check = hopsim(&["scene", "check", "scenes/classic/hopper-driven.toml"]);
    let stdout = text(&check.stdout);
    assert!(stdout.contains("force pulse on 'foot' (±2 N"), "{stdout}");
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("h.csv");
    let out = hopsim(&[
        "run",
        "scenes/classic/hopper-driven.toml",
        "--duration",
        "0.01",
        "--csv",
        &csv.display().to_string(),
        "-q",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let header = std::fs::read_to_string(&csv).unwrap();
    let header = header.lines().next().unwrap();
    assert!(header.ends_with(",actuator_force_N"), "{header}");
}

#[test]
fn a_sweep_refuses_repeated_axes_and_fails_when_every_run_fails() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().display().to_string();
    let sweep = |extra: &[&str]| {
        let mut args = vec!["sweep", "scenes/robbit.toml", "--duration", "0.5", "-q"];
        args.extend(["--out", out_dir.as_str()]);
        args.extend(extra);
        hopsim(&args)
    };
    let twice = sweep(&[
        "--grid",
        "controller.torque=0.1,0.2",
        "--grid",
        "controller.torque=0.3",
    ]);
    assert_eq!(twice.status.code(), Some(2));
    assert!(
        text(&twice.stderr).contains("given twice"),
        "{}",
        text(&twice.stderr)
    );
    let bad_baseline = sweep(&[
        "--grid",
        "controller.torque=0.1",
        "--baseline",
        "b:controller.torqe=1",
    ]);
    assert_eq!(bad_baseline.status.code(), Some(2));
    assert!(text(&bad_baseline.stderr).contains("baseline 'b' is invalid"));
    let all_fail = sweep(&[
        "--grid",
        "controller.torque=0.1,0.2",
        "--set",
        "simulation.max_speed=1",
    ]);
    assert_eq!(
        all_fail.status.code(),
        Some(3),
        "{}",
        text(&all_fail.stderr)
    );
    assert!(text(&all_fail.stderr).contains("every run failed"));
    let csv = std::fs::read_to_string(dir.path().join("sweep.csv")).unwrap();
    assert_eq!(
        csv.lines().filter(|l| l.contains(",error,\"step ")).count(),
        2,
        "{csv}"
    );
}

/// Numbers that cannot be meant are refused before any work, exit 2, with a message that
/// names the option and what was expected: non-finite or negative durations and steps, a
/// run longer than `simulation.max_steps` (with the option that allows it), negative or
/// NaN comparison tolerances, an unbounded `--repeat`.
#[test]
fn unreasonable_numbers_are_refused_with_the_option_named() {
    let a = "tests/golden/robbit_first_second.csv";
    for (args, expected) in [
        (
            &["run", "scenes/robbit.toml", "--duration", "nan"][..],
            "finite",
        ),
        (
            &["run", "scenes/robbit.toml", "--duration", "-1"],
            "--duration",
        ),
        (&["run", "scenes/robbit.toml", "--dt", "inf"], "finite"),
        (
            &["run", "scenes/robbit.toml", "--duration", "1e6"],
            "simulation.max_steps",
        ),
        (
            &[
                "sweep",
                "scenes/robbit.toml",
                "--duration",
                "nan",
                "--grid",
                "controller.torque=0.1,0.2",
            ],
            "finite",
        ),
        (&["compare", a, a, "--abs-tol", "nan"], "--abs-tol"),
        (&["compare", a, a, "--rel-tol", "-1"], "≥ 0"),
        (&["compare", a, a, "--state-tol", "inf"], "finite"),
        (
            &[
                "lcp",
                "solve",
                "tests/data/lcp/lcp_trivial.dat",
                "--repeat",
                "1000000000",
            ],
            "--repeat",
        ),
        (
            &[
                "sweep",
                "scenes/robbit.toml",
                "--grid",
                "controller.torque=0.1:0.3:1000000000",
            ],
            "from 1 to 100000",
        ),
        (
            &[
                "sweep",
                "scenes/robbit.toml",
                "--grid",
                "controller.torque=0.3,0.4",
                "--baseline",
                "b:nosuch=1",
            ],
            "--baseline (nosuch=1)",
        ),
        (
            &[
                "sweep",
                "scenes/robbit.toml",
                "--grid",
                "controller.torque=0.1:0.3:1000",
                "--grid",
                "controller.impulse_limit=0.04:0.07:1000",
            ],
            "--max-runs",
        ),
    ] {
        let out = hopsim(args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("-- -1"), "{args:?}: {stderr}");
    }
    // The limit can be raised: the same run is then refused only by its own numbers.
    let raised = hopsim(&[
        "scene",
        "check",
        "scenes/robbit.toml",
        "--set",
        "simulation.max_steps=1e9",
        "--set",
        "simulation.duration=1e5",
    ]);
    assert_eq!(raised.status.code(), Some(0), "{}", text(&raised.stderr));
}

/// Skips (with a notice) or, with HOPSIM_REQUIRE_PYTHON=1 (CI), fails.
fn skip_or_fail(what: &str) {
    assert!(
        std::env::var("HOPSIM_REQUIRE_PYTHON").as_deref() != Ok("1"),
        "{what}; HOPSIM_REQUIRE_PYTHON=1 requires it (pip install mcap rerun-sdk==0.36.3)"
    );
    eprintln!("notice: skipping: {what} (set HOPSIM_REQUIRE_PYTHON=1 to make this an error)");
}

/// Reads an MCAP recording with the Python `mcap` reader: the `hopsim_stop` metadata, the
/// number of states and the last state's step. Exit 77 without the package.
const READ_MCAP: &str = r#"
import json, sys
try:
    from mcap.reader import make_reader
except ImportError as e:
    print(e, file=sys.stderr)
    sys.exit(77)
with open(sys.argv[1], "rb") as f:
    reader = make_reader(f)
    steps = [json.loads(m.data)["step"]
             for _, _, m in reader.iter_messages(topics=["/hopsim/state"])]
    metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
print(json.dumps({"steps": steps, "stop": metadata.get("hopsim_stop")}))
"#;

/// Robbit with a speed limit its flywheel passes within a tenth of a second of motor
/// torque: the run stops with a runaway state at a step the error names.
#[test]
fn a_runaway_keeps_the_recordings_up_to_the_step_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let out = run_robbit_with_every_output(dir.path(), &["--set", "simulation.max_speed=5"]);
    assert_eq!(out.status.code(), Some(3));
    let err = text(&out.stderr);
    assert!(err.contains("runaway state"), "{err}");
    // "step N (t = …): runaway state": the failing step.
    let failed: u64 = err
        .split("step ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no step in {err}"));
    assert_eq!(
        names(&files_in(dir.path())),
        [
            "r.partial.csv",
            "r.partial.events.csv",
            "r.partial.mcap",
            "r.partial.rrd"
        ],
        "only partial recordings, no summary"
    );
    assert!(err.contains(&p("r.partial.mcap")), "{err}");

    // The Rust reader opens the partial MCAP: states up to the step before the failure,
    // the last within one recording interval (1 ms = 5 steps of 0.2 ms) of it.
    let rec = hopsim_record::McapRecording::read(&dir.path().join("r.partial.mcap")).unwrap();
    let last = rec.states.last().unwrap().step;
    assert!(
        last < failed && last + 5 >= failed - 1,
        "{last} vs {failed}"
    );

    // CSV: the frames up to there; the events end with the stop.
    let csv = std::fs::read_to_string(dir.path().join("r.partial.csv")).unwrap();
    let last_row = csv.lines().last().unwrap();
    assert_eq!(last_row.split(',').nth(1), Some(last.to_string().as_str()));
    let events = std::fs::read_to_string(dir.path().join("r.partial.events.csv")).unwrap();
    let stop = events.lines().last().unwrap();
    assert!(
        stop.contains(&format!(",{},stopped,", failed - 1)) && stop.contains("runaway state"),
        "{stop}"
    );

    // The Python reader: the same states and the stop in the metadata.
    let script = dir.path().join("read.py");
    std::fs::write(&script, READ_MCAP).unwrap();
    let mcap = dir.path().join("r.partial.mcap");
    let python = match Command::new("python3").arg(&script).arg(&mcap).output() {
        Ok(o) if o.status.code() == Some(77) => return skip_or_fail("Python package mcap missing"),
        Ok(o) => o,
        Err(_) => return skip_or_fail("python3 is not installed"),
    };
    assert!(python.status.success(), "{}", text(&python.stderr));
    let read: serde_json::Value = serde_json::from_slice(&python.stdout).unwrap();
    let steps = read["steps"].as_array().unwrap();
    assert_eq!(steps.len(), rec.states.len());
    assert_eq!(steps.last().unwrap(), last);
    assert_eq!(read["stop"]["step"], (failed - 1).to_string());
    let reason = read["stop"]["reason"].as_str().unwrap();
    assert!(
        reason.contains("runaway state") && reason.contains(&format!("step {failed}")),
        "{reason}"
    );

    // The Rerun CLI loads the partial .rrd.
    let rrd = dir.path().join("r.partial.rrd");
    match Command::new("rerun")
        .args(["rrd", "verify"])
        .arg(&rrd)
        .env("RERUN_ANALYTICS", "0")
        .output()
    {
        Ok(o) => assert!(o.status.success(), "{}", text(&o.stderr)),
        Err(_) => skip_or_fail("the `rerun` CLI is not on PATH"),
    }
}
