//! Figures never cost data (docs/reliability.md): on a machine without system fonts (an
//! empty fontconfig) `hopsim sweep` and every `hopsim analyze … --out` write the same files,
//! byte for byte, as with them; and a figure that cannot be written is a warning naming
//! its missing files, while the tables are written and the exit code stays 0.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A scene of the repository.
fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

/// Every study that writes figures, small enough for the test suite: its name and the
/// arguments before `--out DIR`.
fn studies() -> Vec<(&'static str, Vec<String>)> {
    let args = |list: &[&str]| list.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    let hopper = scene("classic/hopper-driven.toml");
    let robbit = scene("robbit.toml");
    vec![
        (
            "sweep",
            args(&["sweep", &hopper, "--duration", "1", "-q"])
                .into_iter()
                .chain(args(&["--grid", "controller.force=10:40:3"]))
                .collect(),
        ),
        (
            "template case",
            args(&["analyze", "template", "--case", "kangaroo-rat"]),
        ),
        (
            "template cargo grid",
            args(&[
                "analyze",
                "template",
                "--grid",
                "cargo",
                "--resolution",
                "4",
            ]),
        ),
        (
            "template animals",
            args(&[
                "analyze",
                "template",
                "--grid",
                "animals",
                "--resolution",
                "4",
            ]),
        ),
        (
            "impulsive wheel",
            args(&["analyze", "impulsive-wheel", "--series", "3.0,3.5"]),
        ),
        (
            "obstacle",
            args(&[
                "analyze",
                "obstacle",
                "--resolution",
                "6",
                "--map-height-ratios",
                "0.2",
            ]),
        ),
        (
            "fixed points",
            args(&[
                "analyze",
                "fixed-points",
                "--grid",
                "3x2",
                "--simulate",
                "--simulate-all",
                "--duration",
                "2",
            ]),
        ),
        (
            "gait",
            args(&["analyze", "gait", &robbit, "--duration", "4"]),
        ),
    ]
}

/// Runs `hopsim ARGS --out OUT`, with `FONTCONFIG_FILE` set for the child when given.
fn hopsim(args: &[String], out: &Path, fontconfig: Option<&Path>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_hopsim"));
    command.args(args).arg("--out").arg(out);
    if let Some(config) = fontconfig {
        command.env("FONTCONFIG_FILE", config);
    }
    command.output().expect("run hopsim")
}

/// The files of `dir` by name; CSV files without their wall-time columns (which differ
/// from run to run).
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let bytes = std::fs::read(&path).unwrap();
            let bytes = match name.ends_with(".csv") {
                true => without_wall_times(&String::from_utf8(bytes).unwrap()).into_bytes(),
                false => bytes,
            };
            (name, bytes)
        })
        .collect()
}

/// `csv` without its `wall_time…` columns (no quoted commas in these tables' numbers).
fn without_wall_times(csv: &str) -> String {
    let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
    let keep: Vec<bool> = header.iter().map(|c| !c.starts_with("wall_time")).collect();
    if keep.iter().all(|k| *k) {
        return csv.to_string();
    }
    csv.lines()
        .map(|line| {
            let cells = line.split(',').zip(&keep).filter(|(_, k)| **k);
            cells.map(|(c, _)| c).collect::<Vec<_>>().join(",") + "\n"
        })
        .collect()
}

/// An empty fontconfig in `dir`: no font directories, so no system font can be found.
fn empty_fontconfig(dir: &Path) -> PathBuf {
    let path = dir.join("empty-fonts.conf");
    std::fs::write(
        &path,
        "<?xml version=\"1.0\"?>\n<fontconfig></fontconfig>\n",
    )
    .unwrap();
    path
}

#[test]
fn every_study_writes_the_same_files_without_system_fonts() {
    let dir = tempfile::tempdir().unwrap();
    let fontconfig = empty_fontconfig(dir.path());
    for (i, (name, args)) in studies().iter().enumerate() {
        let outputs = [None, Some(fontconfig.as_path())].map(|config| {
            let out = dir.path().join(format!("{i}-{}", config.is_some()));
            let run = hopsim(args, &out, config);
            let stderr = String::from_utf8_lossy(&run.stderr);
            assert!(run.status.success(), "{name}: {stderr}");
            assert!(!stderr.contains("warning"), "{name}: {stderr}");
            contents(&out)
        });
        let [with_fonts, without] = &outputs;
        let names: Vec<&String> = with_fonts.keys().collect();
        assert!(
            names.iter().any(|n| n.ends_with(".csv"))
                && names.iter().any(|n| n.ends_with(".png"))
                && names.iter().any(|n| n.ends_with(".svg")),
            "{name}: {names:?}"
        );
        assert_eq!(
            without.keys().collect::<Vec<_>>(),
            names,
            "{name}: the files without fonts"
        );
        for (file, bytes) in with_fonts {
            assert!(
                without[file] == *bytes,
                "{name}: {file} differs without fonts"
            );
        }
    }
}

/// A figure whose file cannot be written (a folder where `sweep.png` goes) leaves both of
/// its files out, with a warning that names them; the CSV is written and the sweep
/// succeeds. With `--json` the missing figure is part of the report.
#[test]
fn a_figure_that_cannot_be_written_is_a_warning_and_the_table_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let (name, args) = &studies()[0];
    assert_eq!(*name, "sweep");
    let out = dir.path().join("sweep");
    std::fs::create_dir_all(out.join("sweep.png")).unwrap();
    let run = hopsim(args, &out, None);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.starts_with("warning: the figure `sweep` could not be drawn"),
        "{stderr}"
    );
    for file in ["sweep.png", "sweep.svg", "is a folder"] {
        assert!(stderr.contains(file), "{file}: {stderr}");
    }
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3, "{csv}");
    assert!(!out.join("sweep.svg").exists());

    // A study's JSON lists the figure as missing, beside the files written.
    let out = dir.path().join("wheel");
    std::fs::create_dir_all(out.join("series.svg")).unwrap();
    let mut args = studies()[4].1.clone();
    args.push("--json".into());
    let run = hopsim(&args, &out, None);
    assert!(run.status.success());
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let written: Vec<&str> = (v["files"].as_array().unwrap().iter())
        .map(|f| f.as_str().unwrap().rsplit('/').next().unwrap())
        .collect();
    assert_eq!(
        written,
        [
            "bifurcation.csv",
            "series.csv",
            "bifurcation.png",
            "bifurcation.svg"
        ]
    );
    let missing = &v["missing_figures"][0];
    assert_eq!(missing["figure"], "series");
    assert_eq!(missing["files"].as_array().unwrap().len(), 2);
    assert!(missing["reason"].as_str().unwrap().contains("series.svg"));
}
