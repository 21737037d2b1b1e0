//! A run that stops early keeps its recordings up to the stop under names that cannot be
//! mistaken for a complete run (`r.partial.mcap`, …), with the reason and the last step in
//! their metadata; the complete names and the summary are not written.

use std::path::Path;
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

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
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
    let out = hopsim(&[
        "run",
        "scenes/robbit.toml",
        "--set",
        "simulation.max_speed=5",
        "--mcap",
        &p("r.mcap"),
        "--rrd",
        &p("r.rrd"),
        "--csv",
        &p("r.csv"),
        "--summary",
        &p("r.json"),
    ]);
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
        names_in(dir.path()),
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
