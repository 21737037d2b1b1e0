//! `hopsim optimize` end to end (docs/optimize.md): its files, its refusals, and a search
//! killed with SIGKILL and resumed with `--resume`, whose evaluations equal those of the
//! uninterrupted search.

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// The thrown point mass of the optimisation tests (docs/optimize.md), stepped at 2e-5 s.
fn projectile() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/optimize/projectile.toml")
}

fn command(scene: &Path, out: &Path, generations: usize) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_hopsim"));
    c.arg("optimize")
        .arg(scene)
        .args([
            "--param",
            "initial.u.0=0:2.5",
            "--param",
            "initial.u.1=0:2.5",
        ])
        .args([
            "--maximize",
            "distance_m",
            "--constraint",
            "energy.dissipated=:2",
        ])
        .args(["--population", "4", "--seed", "9", "--quiet"])
        .args(["--generations", &generations.to_string()])
        .arg("--out")
        .arg(out);
    c
}

fn run(c: &mut Command) -> Output {
    c.output().expect("hopsim runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn writes_every_evaluation_a_figure_and_a_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let scene = projectile();
    let out = dir.path().join("out");
    let o = run(&mut command(&scene, &out, 3));
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("evaluations.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("generation,index,initial.u.0,initial.u.1,status,objective,best_so_far,error")
    );
    assert_eq!(lines.count(), 12);
    for file in ["convergence.png", "convergence.svg", "checkpoint.json"] {
        assert!(out.join(file).exists(), "{file}");
    }
    // The folder holds a checkpoint: refused without --resume.
    let again = run(&mut command(&scene, &out, 3));
    assert_eq!(again.status.code(), Some(2));
    assert!(
        stderr(&again).contains("pass --resume"),
        "{}",
        stderr(&again)
    );
    // Another problem (another bound) does not resume this checkpoint.
    let other = run(command(&scene, &out, 3)
        .args(["--param", "initial.q.1=0:0.1"])
        .arg("--resume"));
    assert_eq!(other.status.code(), Some(2));
    assert!(
        stderr(&other).contains("another search"),
        "{}",
        stderr(&other)
    );
    // More generations extend it: the evaluations of a search planned for 4.
    let extended = run(command(&scene, &out, 4).arg("--resume"));
    assert!(extended.status.success(), "{}", stderr(&extended));
    let planned_out = dir.path().join("planned");
    assert!(run(&mut command(&scene, &planned_out, 4)).status.success());
    let rows = |dir: &Path| std::fs::read_to_string(dir.join("evaluations.csv")).unwrap();
    assert_eq!(rows(&out).lines().count(), 1 + 16);
    assert_eq!(rows(&out), rows(&planned_out));
    // A misspelt key is one error before any run.
    let bad = run(Command::new(env!("CARGO_BIN_EXE_hopsim"))
        .arg("optimize")
        .arg(&scene)
        .args(["--param", "initial.v.0=0:1", "--minimize", "hops"])
        .arg("--out")
        .arg(dir.path().join("bad")));
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("nothing was run"), "{}", stderr(&bad));
}

/// Killed (SIGKILL) once its first checkpoint is written, then resumed: the evaluations
/// are those of the search run without a stop, row for row.
#[test]
fn a_killed_search_resumes_to_the_uninterrupted_result() {
    let dir = tempfile::tempdir().unwrap();
    let scene = projectile();
    let generations = 25;
    let whole = dir.path().join("whole");
    let o = run(&mut command(&scene, &whole, generations));
    assert!(o.status.success(), "{}", stderr(&o));

    let killed = dir.path().join("killed");
    let mut child = command(&scene, &killed, generations).spawn().unwrap();
    let checkpoint = killed.join("checkpoint.json");
    let started = Instant::now();
    while !checkpoint.exists() {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no checkpoint"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(running, "the search ended before it could be killed");
    assert!(!killed.join("evaluations.csv").exists());

    let resumed = run(command(&scene, &killed, generations).arg("--resume"));
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    let read = |d: &Path| std::fs::read_to_string(d.join("evaluations.csv")).unwrap();
    assert_eq!(read(&killed), read(&whole));
    assert_eq!(read(&whole).lines().count(), 1 + 4 * generations);
}
