//! Atomic output: a recorder dropped without `finish` leaves neither the target file nor
//! a temporary file; a finished one leaves exactly its files; a failed `write_atomically`
//! keeps the previous file.

mod common;

use common::{events, feed, files_in, frames, info};
use hopsim_record::{
    write_atomically, CsvRecorder, McapRecorder, Recorder, RecorderSet, RerunRecorder,
};
use std::path::Path;

type Create = fn(&Path) -> Box<dyn Recorder>;

fn recorders() -> [(&'static str, Create, &'static [&'static str]); 3] {
    [
        (
            "run.mcap",
            |p| Box::new(McapRecorder::create(p, &info()).unwrap()),
            &["run.mcap"],
        ),
        (
            "run.csv",
            |p| Box::new(CsvRecorder::create(p, &info()).unwrap()),
            &["run.csv", "run.events.csv"],
        ),
        (
            "run.rrd",
            |p| Box::new(RerunRecorder::save(p, &info()).unwrap()),
            &["run.rrd"],
        ),
    ]
}

#[test]
fn a_recorder_dropped_without_finish_leaves_no_file() {
    for (name, create, _) in recorders() {
        let dir = tempfile::tempdir().unwrap();
        let mut recorder = create(&dir.path().join(name));
        feed(recorder.as_mut(), &frames(5), &events());
        assert_eq!(
            files_in(dir.path()).len(),
            if name == "run.csv" { 2 } else { 1 }
        );
        let temporary = |f: &String| f.starts_with('.') && f.contains(".partial-");
        assert!(
            files_in(dir.path()).iter().all(temporary),
            "{name}: only temporary files"
        );
        drop(recorder);
        assert_eq!(
            files_in(dir.path()),
            Vec::<String>::new(),
            "{name}: nothing left"
        );
    }
}

#[test]
fn a_finished_recorder_leaves_exactly_its_files_in_a_new_folder() {
    for (name, create, expected) in recorders() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out/nested");
        let mut set = RecorderSet::default();
        assert!(set.is_empty());
        set.push(create(&out.join(name)));
        assert!(!set.is_empty());
        for f in frames(5) {
            set.frame(&f.frame()).unwrap();
        }
        set.event(&events()[0]).unwrap();
        set.finish().unwrap();
        assert_eq!(files_in(&out), expected, "{name}");
        assert!(std::fs::metadata(out.join(name)).unwrap().len() > 0);
        assert_plain_permissions(&out, name);
    }
}

/// The file at `dir/name` has the permissions a plain `File::create` gives in `dir` (the
/// process umask applied), not a temporary file's private 0600.
#[cfg(unix)]
fn assert_plain_permissions(dir: &Path, name: &str) {
    use std::os::unix::fs::PermissionsExt;
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let plain = dir.join("plain");
    std::fs::File::create(&plain).unwrap();
    assert_eq!(mode(&dir.join(name)), mode(&plain), "{name}: permissions");
    std::fs::remove_file(plain).unwrap();
}

#[cfg(not(unix))]
fn assert_plain_permissions(_: &Path, _: &str) {}

#[test]
fn write_atomically_replaces_only_on_success() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("summary.json");
    write_atomically(&path, |w| w.write_all(b"{\"ok\": 1}")).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "{\"ok\": 1}");
    let err = write_atomically(&path, |w| {
        w.write_all(b"{\"half")?;
        Err(std::io::Error::other("disk full"))
    })
    .unwrap_err();
    assert!(err.to_string().contains("summary.json") && err.to_string().contains("disk full"));
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "{\"ok\": 1}",
        "old file kept"
    );
    assert_eq!(files_in(dir.path()), ["summary.json"]);
}

#[test]
fn a_frame_that_does_not_match_the_recording_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    for (name, create, _) in recorders() {
        let mut recorder = create(&dir.path().join(name));
        let mut bad = frames(1).remove(0);
        bad.q.pop();
        let e = recorder.frame(&bad.frame()).unwrap_err().to_string();
        assert!(e.contains("3 q entries") && e.contains('4'), "{name}: {e}");
        let mut bad = frames(1).remove(0);
        bad.contacts[0].contact = 9;
        assert!(recorder.frame(&bad.frame()).is_err(), "{name}");
    }
}
