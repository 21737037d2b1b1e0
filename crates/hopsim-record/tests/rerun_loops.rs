//! The Rerun recording draws loop joints (docs/recording.md): a revolute loop's markers on
//! both bodies (`<body>/loops`), a distance loop's rod per frame (`world/loops`) and its
//! world point (`world/loops/world`), listed by the `rerun` CLI when it is installed
//! (skipped with a notice otherwise, unless HOPSIM_REQUIRE_PYTHON=1).

mod common;

use common::{events, feed, frames, info, run, skip_or_fail};
use hopsim_record::{LoopInfo, LoopInfoKind, Recorder, RerunRecorder};
use std::process::Command;

#[test]
fn loops_are_drawn_as_markers_and_rods() {
    let mut info = info();
    info.loops = vec![
        LoopInfo {
            name: "pin".into(),
            kind: LoopInfoKind::Revolute,
            body_a: 1,
            point_a_m: [0.1, 0.0],
            body_b: Some(0),
            point_b_m: [0.1, 0.0],
        },
        LoopInfo {
            name: "rod".into(),
            kind: LoopInfoKind::Distance { length_m: 0.5 },
            body_a: 0,
            point_a_m: [0.0, 0.1],
            body_b: None,
            point_b_m: [0.0, 0.6],
        },
    ];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.rrd");
    let mut recorder = Box::new(RerunRecorder::save(&path, &info).unwrap());
    feed(recorder.as_mut(), &frames(50), &events());
    recorder.finish().unwrap();
    let Some(print) = run(Command::new("rerun")
        .args(["rrd", "print", "--verbose"])
        .arg(&path)
        .env("RERUN_ANALYTICS", "0"))
    else {
        return skip_or_fail("the `rerun` CLI is not on PATH");
    };
    let listing = format!(
        "{}\n{}",
        String::from_utf8_lossy(&print.stdout),
        String::from_utf8_lossy(&print.stderr)
    );
    assert!(print.status.success(), "{listing}");
    for entity in [
        "/world/com/bodies/disc/loops",
        "/world/com/bodies/flywheel/loops",
        "/world/loops/world",
        "/world/loops",
    ] {
        assert!(
            listing.contains(entity),
            "{entity} missing from:\n{listing}"
        );
    }
}
