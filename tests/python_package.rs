//! The Python package (`python/`, docs/python.md) as a user installs it: a virtual
//! environment under the cargo target directory, `pip install ./python` (the wheel built
//! with its own cargo target directory, so that it never waits on this build's lock), the
//! pytest suite `python/tests` (against this build's `hopsim` binary) and the notebook
//! notebooks `examples/robbit.ipynb` and `examples/learning.ipynb` executed with nbclient, on a machine without system fonts (an
//! empty fontconfig, a fresh matplotlib cache): matplotlib draws with the fonts it bundles.
//!
//! Needs `python3` (≥ 3.9) with `venv` and a reachable package index. Without them the
//! test is skipped with a notice, unless HOPSIM_REQUIRE_PYTHON=1 (CI), which makes it fail.
//! Once the environment is there, a failed wheel build, test or notebook always fails.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The packages the tests and the notebook use besides `hopsim` itself.
const TEST_PACKAGES: &[&str] = &[
    "numpy",
    "pytest",
    "mcap",
    "dask[distributed]",
    "pandas",
    "matplotlib",
    "nbclient",
    "nbformat",
    "ipykernel",
    // hopsim.envs; MuJoCo only as the oracle of the Hopper environment's definitions.
    "gymnasium[mujoco]",
];

fn python_required() -> bool {
    std::env::var("HOPSIM_REQUIRE_PYTHON").is_ok_and(|v| v == "1")
}

/// Skips (with a notice) or fails, following HOPSIM_REQUIRE_PYTHON.
fn skip_or_fail(what: &str) {
    assert!(
        !python_required(),
        "{what}; HOPSIM_REQUIRE_PYTHON=1 requires it (python3 ≥ 3.9 with venv, and pip able to install packages)"
    );
    eprintln!("notice: skipping the Python package tests: {what} (set HOPSIM_REQUIRE_PYTHON=1 to make this an error)");
}

/// Runs `command`, echoing its output; whether it succeeded (`None`: program missing).
fn run(command: &mut Command) -> Option<bool> {
    match command.status() {
        Ok(status) => Some(status.success()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => panic!("could not run {command:?}: {e}"),
    }
}

/// The cargo target directory of this build: the `hopsim` binary is `<target>/<profile>/hopsim`.
fn target_dir() -> PathBuf {
    let bin = Path::new(env!("CARGO_BIN_EXE_hopsim"));
    bin.parent()
        .and_then(Path::parent)
        .expect("the hopsim binary lies in <target>/<profile>/")
        .to_path_buf()
}

#[test]
fn python_package_installs_and_passes_its_tests_and_notebook() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = target_dir();
    let venv = target.join("python-venv");
    let python = std::env::var("HOPSIM_PYTHON").unwrap_or_else(|_| "python3".into());
    let version_ok = run(Command::new(&python).args([
        "-c",
        "import sys, venv; sys.exit(sys.version_info < (3, 9))",
    ]));
    if version_ok != Some(true) {
        return skip_or_fail(&format!("{python} (≥ 3.9, with venv) is not available"));
    }
    let venv_python = venv.join("bin").join("python");
    if !venv_python.exists()
        && run(Command::new(&python).args(["-m", "venv"]).arg(&venv)) != Some(true)
    {
        return skip_or_fail(&format!(
            "cannot create a virtual environment at {}",
            venv.display()
        ));
    }
    let pip = |args: &[&str]| {
        let mut c = Command::new(&venv_python);
        c.args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
        ])
        .args(args);
        c
    };
    if run(&mut pip(TEST_PACKAGES)) != Some(true) {
        return skip_or_fail(&format!("pip cannot install {}", TEST_PACKAGES.join(", ")));
    }
    // The package itself: a failure here is a failure of this repository. Built with its
    // test hooks (`HOPSIM_PANIC_IN`, python/Cargo.toml), which the tests of its panic
    // boundary need.
    let installed = run(pip(&["--force-reinstall", "--no-deps"])
        .arg(repo.join("python"))
        .env("CARGO_TARGET_DIR", target.join("python-wheel"))
        .env("MATURIN_PEP517_ARGS", "--features test-hooks"));
    assert_eq!(installed, Some(true), "pip install ./python failed");

    let pytest = run(Command::new(&venv_python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(repo.join("python").join("tests"))
        .env("HOPSIM_BIN", env!("CARGO_BIN_EXE_hopsim"))
        .current_dir(repo));
    assert_eq!(pytest, Some(true), "the Python tests failed");

    for notebook in ["robbit.ipynb", "learning.ipynb"] {
        run_notebook(&venv_python, repo, &repo.join("examples").join(notebook));
    }
}

/// Executes `notebook` with nbclient in the virtual environment of `python`, without
/// system fonts.
fn run_notebook(python: &Path, repo: &Path, notebook: &Path) {
    let execute = format!(
        "import nbformat, nbclient\n\
         nb = nbformat.read({path:?}, as_version=4)\n\
         nbclient.NotebookClient(nb, timeout=300, kernel_name='python3',\n\
             resources={{'metadata': {{'path': {dir:?}}}}}).execute()\n\
         print('notebook ran:', len(nb.cells), 'cells')\n",
        path = notebook.display().to_string(),
        // Not the notebook's own folder: it finds the scenes from any folder of the
        // repository (not python/, whose source package would shadow the installed one).
        dir = repo.join("docs").display().to_string(),
    );
    // No system fonts: an empty fontconfig, and a matplotlib cache built under it.
    let fontless = tempfile::tempdir().expect("a folder for the fontless configuration");
    let fontconfig = fontless.path().join("empty-fonts.conf");
    std::fs::write(
        &fontconfig,
        "<?xml version=\"1.0\"?>\n<fontconfig></fontconfig>\n",
    )
    .expect("write an empty fontconfig");
    let ran = run(Command::new(python)
        .args(["-c", &execute])
        .env("FONTCONFIG_FILE", &fontconfig)
        .env("MPLCONFIGDIR", fontless.path())
        .current_dir(repo));
    assert_eq!(ran, Some(true), "{} failed to run", notebook.display());
}
