//! `remove_temporary_files` deletes this process's uncommitted temporary outputs and
//! nothing else (its own test binary: the registry is process-wide).

use hopsim_io::{remove_temporary_files, AtomicFile, AtomicPath};
use std::io::Write;

#[test]
fn uncommitted_temporary_files_are_removed_and_committed_ones_stay() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("old.csv"), "old").unwrap();
    let pending = AtomicPath::create(&dir.path().join("a.png")).unwrap();
    let mut writing = AtomicFile::create(&dir.path().join("old.csv")).unwrap();
    writing.write_all(b"new, unfinished").unwrap();
    writing.flush().unwrap();
    let committed = AtomicFile::create(&dir.path().join("b.csv")).unwrap();
    committed.commit().unwrap();
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 4);
    remove_temporary_files();
    assert!(!pending.temporary().exists());
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["b.csv", "old.csv"]);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("old.csv")).unwrap(),
        "old"
    );
}
