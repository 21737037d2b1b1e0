//! Every broken scene in `tests/scenes/invalid/` yields its own message. Each fixture states
//! what it must produce in its first lines: `# expect: <text the error contains>` and
//! `# expect-line: <line the error points at>`.

use std::path::{Path, PathBuf};

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/scenes/invalid");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}

fn directive<'a>(text: &'a str, name: &str) -> Option<&'a str> {
    let prefix = format!("# {name}: ");
    text.lines().find_map(|l| l.strip_prefix(prefix.as_str()))
}

#[test]
fn each_invalid_scene_gets_its_specific_message() {
    let files = fixtures();
    assert!(
        files.len() >= 15,
        "expected the fixtures folder, found {files:?}"
    );
    let mut failures = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap();
        let expect = directive(&text, "expect").expect("fixture without '# expect:'");
        let message = match hopsim_scene::load(path, &[]) {
            Ok(_) => {
                failures.push(format!("{}: loaded without error", path.display()));
                continue;
            }
            Err(e) => e.to_string(),
        };
        if !message.contains(expect) {
            failures.push(format!(
                "{}:\n  expected: {expect}\n  got:      {message}",
                path.display()
            ));
        }
        if let Some(line) = directive(&text, "expect-line") {
            let at = format!("{}:{line}:", path.display());
            if !message.starts_with(&at) {
                failures.push(format!(
                    "{}: expected the error at line {line}, got: {message}",
                    path.display()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
