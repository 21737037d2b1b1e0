//! MuJoCo as an oracle: a Python script of this crate's `tests/` (with the `mujoco`
//! package) reads one JSON request on stdin and prints one JSON answer, or `{"skip": why}`
//! when it cannot answer.
#![allow(dead_code)]

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

use serde_json::Value;

/// The answer of `tests/<script>` to `request`, or why it cannot answer. Runs `python3`
/// (or `HOPSIM_PYTHON`) in a scratch folder (MuJoCo writes MUJOCO_LOG.TXT into its working
/// directory).
pub fn ask(script: &str, request: &Value) -> Result<Value, String> {
    let python = std::env::var("HOPSIM_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(script);
    let scratch = tempfile::tempdir().map_err(|e| e.to_string())?;
    let mut child = Command::new(&python)
        .arg(&script)
        .current_dir(scratch.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run {python}: {e}"))?;
    child
        .stdin
        .take()
        .expect("piped stdin")
        .write_all(request.to_string().as_bytes())
        .map_err(|e| e.to_string())?;
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let answer: Value = serde_json::from_slice(&out.stdout).expect("the oracle prints JSON");
    match answer["skip"].as_str() {
        Some(why) => Err(why.to_string()),
        None => Ok(answer),
    }
}

/// A notice that the oracle is missing, or a failure when HOPSIM_REQUIRE_PYTHON=1.
pub fn unavailable(why: &str) {
    let required = std::env::var("HOPSIM_REQUIRE_PYTHON").is_ok_and(|v| v == "1");
    assert!(
        !required,
        "the MuJoCo oracle is unavailable: {why} (HOPSIM_REQUIRE_PYTHON=1)"
    );
    eprintln!("notice: MuJoCo oracle skipped: {why}; install them with `python3 -m pip install mujoco gymnasium dm_control`");
}

/// A JSON list of numbers.
pub fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("a list")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// The largest difference relative to the largest entry of MuJoCo's.
pub fn relative(mine: &[f64], theirs: &[f64]) -> f64 {
    let scale = theirs.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let worst = mine
        .iter()
        .zip(theirs)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    worst / scale.max(f64::MIN_POSITIVE)
}
