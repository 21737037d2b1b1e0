//! `.rrd` recordings: produced atomically, start with the RRD magic, and load in the
//! matching Rerun CLI (`rerun rrd verify`, `rerun rrd print`) when it is installed.
//! Without the CLI the external check is skipped with a notice, unless
//! HOPSIM_REQUIRE_PYTHON=1 (CI installs `rerun-sdk==0.36.3`).

mod common;

use common::{events, feed, files_in, frames, info, run, skip_or_fail};
use hopsim_record::{Recorder, RerunRecorder};
use std::path::Path;
use std::process::Command;

/// Magic bytes at the start of an RRD file written by Rerun 0.36.
const RRD_MAGIC: &[u8; 4] = b"RRF2";

fn rerun(args: &[&str], file: &Path) -> Option<std::process::Output> {
    run(Command::new("rerun")
        .args(args)
        .arg(file)
        .env("RERUN_ANALYTICS", "0"))
}

#[test]
fn rrd_file_is_complete_and_loads_in_the_rerun_cli() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.rrd");
    let mut recorder = Box::new(RerunRecorder::save(&path, &info()).unwrap());
    feed(recorder.as_mut(), &frames(120), &events());
    recorder.finish().unwrap();

    assert_eq!(files_in(dir.path()), ["run.rrd"], "no temporary file left");
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.len() > 1000, "{} bytes", bytes.len());
    assert_eq!(&bytes[..4], RRD_MAGIC);

    let Some(verify) = rerun(&["rrd", "verify"], &path) else {
        return skip_or_fail("the `rerun` CLI is not on PATH");
    };
    let log = |o: &std::process::Output| {
        format!(
            "{}\n{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        )
    };
    assert!(
        verify.status.success(),
        "rerun rrd verify failed:\n{}",
        log(&verify)
    );
    let print = rerun(&["rrd", "print", "--verbose"], &path).unwrap();
    assert!(
        print.status.success(),
        "rerun rrd print failed:\n{}",
        log(&print)
    );
    let listing = log(&print);
    for entity in [
        "/world/terrain",
        "/world/com/bodies/disc/outline",
        "/world/com/bodies/disc/points",
        "/world/com/bodies/flywheel/spoke",
        "/world/com/view",
        "/world/springs",
        "/world/trail/0",
        "/world/contacts/normal_force",
        "/world/contacts",
        "/plots/energy_J",
        "/events",
    ] {
        assert!(
            listing.contains(entity),
            "{entity} missing from:\n{listing}"
        );
    }
    // Columnar logging: the 120 frames of a time series or a body's transform are one
    // chunk (beside a static one with the series' names and colours, or the marker), not
    // one per frame; the contacts' impulses and force arrows share theirs.
    let stats = rerun(&["rrd", "stats"], &path).unwrap();
    let stats = log(&stats);
    for (entity, chunks) in [
        ("/plots/energy_J", 2),
        ("/world/com/bodies/disc", 1),
        ("/world/com", 2),
        ("/world/contacts", 3),
    ] {
        assert!(
            stats.contains(&format!("{entity}: {chunks}\n")),
            "{entity} not in {chunks} chunks:\n{stats}"
        );
    }
}
