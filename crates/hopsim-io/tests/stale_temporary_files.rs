//! The temporary files of a killed run (named with its process id) are removed by the next
//! run that writes the same output; those of a process still running are left alone.

use hopsim_io::AtomicFile;

#[cfg(unix)]
#[test]
fn a_killed_runs_temporary_files_are_removed_by_the_next_writer() {
    let dir = tempfile::tempdir().unwrap();
    // A process that has ended: its id is free (until reused, when its file would stay).
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    let stale = dir.path().join(format!(".run.mcap.partial-{dead}-abc123"));
    let live = dir
        .path()
        .join(format!(".run.mcap.partial-{}-def456", std::process::id()));
    let other = dir
        .path()
        .join(format!(".other.mcap.partial-{dead}-ghi789"));
    for f in [&stale, &live, &other] {
        std::fs::write(f, "unfinished").unwrap();
    }
    let file = AtomicFile::create(&dir.path().join("run.mcap")).unwrap();
    assert!(!stale.exists(), "the killed run's file stays");
    assert!(live.exists(), "a running process's file was removed");
    assert!(other.exists(), "another output's file was removed");
    file.commit().unwrap();
}
