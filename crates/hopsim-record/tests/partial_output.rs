//! Recordings of a run that stopped early: kept under partial names
//! (`run.partial.mcap`, …) with the stop in their metadata; the complete names are not
//! written.

mod common;

use common::{events, files_in, frames, info, run, skip_or_fail};
use hopsim_record::{
    CsvRecorder, McapRecorder, McapRecording, RecorderSet, RerunRecorder, Stop, STOP_METADATA_NAME,
};
use std::process::Command;

#[test]
fn a_stopped_run_keeps_every_recording_under_its_partial_name() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name);
    let mut set = RecorderSet::default();
    set.push(Box::new(
        McapRecorder::create(&p("run.mcap"), &info()).unwrap(),
    ));
    set.push(Box::new(
        RerunRecorder::save(&p("run.rrd"), &info()).unwrap(),
    ));
    set.push(Box::new(
        CsvRecorder::create(&p("run.csv"), &info()).unwrap(),
    ));
    let frames = frames(30);
    let mut recorders = set;
    for f in &frames {
        for e in events().iter().filter(|e| e.step == f.step) {
            recorders.event(e).unwrap();
        }
        recorders.frame(&f.frame()).unwrap();
    }
    let last = frames.last().unwrap();
    let stop = Stop {
        reason: "step 302 (t = 0.060400 s): runaway state".into(),
        step: last.step + 4,
        t: last.t + 4.0 * info().dt,
    };
    let mut kept = recorders.finish_partial(&stop).unwrap();
    kept.sort();
    let expected = [
        "run.partial.csv",
        "run.partial.events.csv",
        "run.partial.mcap",
        "run.partial.rrd",
    ];
    assert_eq!(kept, expected.map(p));
    assert_eq!(
        files_in(dir.path()),
        expected,
        "nothing else, no complete name"
    );

    let rec = McapRecording::read(&p("run.partial.mcap")).unwrap();
    assert_eq!(rec.states.len(), frames.len());
    assert_eq!(
        rec.stop.as_ref(),
        Some(&stop),
        "the reader gives the stop record back"
    );
    let bytes = std::fs::read(p("run.partial.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let index = summary
        .metadata_indexes
        .iter()
        .find(|m| m.name == STOP_METADATA_NAME)
        .expect("a stop record");
    let record = mcap::read::metadata(&bytes, index).unwrap();
    assert_eq!(record.metadata["reason"], stop.reason);
    assert_eq!(record.metadata["step"], stop.step.to_string());
    assert_eq!(record.metadata["t_s"].parse::<f64>().unwrap(), stop.t);

    let events = std::fs::read_to_string(p("run.partial.events.csv")).unwrap();
    let last_event = events.lines().last().unwrap();
    assert_eq!(
        last_event,
        format!(
            "{:?},{},stopped,reason=step 302 (t = 0.060400 s): runaway state",
            stop.t, stop.step
        )
    );
    let csv = std::fs::read_to_string(p("run.partial.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + frames.len());

    let Some(verify) = run(Command::new("rerun")
        .args(["rrd", "verify"])
        .arg(p("run.partial.rrd"))
        .env("RERUN_ANALYTICS", "0"))
    else {
        return skip_or_fail("the `rerun` CLI is not on PATH");
    };
    assert!(
        verify.status.success(),
        "{}",
        String::from_utf8_lossy(&verify.stderr)
    );
}
