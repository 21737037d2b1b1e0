//! `hopsim run SCENE`: simulate a scene, record it, print the summary.

use anyhow::Context;
use clap::Args;
use hopsim_record::{AtomicFile, CsvRecorder, McapRecorder, Pace, RecorderSet, RerunRecorder};
use hopsim_scene::Override;
use hopsim_sim::{recording_info, RecordingObserver, RunError};
use hopsim_step::StepError;
use hopsim_studies::run_summary::run_scene;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use super::exit;
use super::interrupt::{self, StopOnSignal};
use super::progress::RunProgress;
use super::scene::{SceneArgs, TimingArgs};

/// Simulate a scene file, record the trajectory and print the run summary.
#[derive(Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub timing: TimingArgs,
    /// Write an MCAP recording (Foxglove, Python `mcap` reader).
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Write a Rerun recording (.rrd), to open with `rerun FILE`.
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
    /// Stream to a live Rerun viewer (needs the `rerun` viewer on PATH).
    #[arg(long)]
    pub spawn: bool,
    /// Pace of the live stream: simulated seconds per second of wall-clock time (1: real
    /// time, 0.25: four times slower), or `max` for as fast as the simulation runs.
    #[arg(
        long,
        value_name = "FACTOR|max",
        requires = "spawn",
        default_value = "1"
    )]
    pub speed: Pace,
    /// Write the recorded frames as CSV (events go to FILE's stem + .events.csv).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the run summary as JSON.
    #[arg(long, value_name = "FILE")]
    pub summary: Option<PathBuf>,
    /// Print nothing but errors (no progress bar, no summary).
    #[arg(long, short)]
    pub quiet: bool,
    /// Stop on the first contact LCP without a certified solution.
    #[arg(long)]
    pub strict: bool,
}

pub fn run(args: RunArgs) -> anyhow::Result<ExitCode> {
    let mut extra = args.timing.overrides();
    if args.strict {
        extra.push(Override::from_flag("--strict", "simulation.strict", "true"));
    }
    let scene = args.scene.load(&extra)?;
    let extension_warnings = match check_output_paths(&args, &scene.path) {
        Ok(warnings) => warnings,
        Err(message) => return exit::invalid(message),
    };
    if !args.quiet {
        for warning in extension_warnings {
            eprintln!("warning: {warning}");
        }
        for notice in &scene.notices {
            eprintln!("notice: {notice}");
        }
        for warning in hopsim_scene::warnings(&scene) {
            eprintln!("warning: {}: {warning}", scene.path.display());
        }
    }
    let info = recording_info(&scene);
    let mut recorders = RecorderSet::default();
    if let Some(path) = &args.mcap {
        recorders.push(Box::new(McapRecorder::create(path, &info)?));
    }
    if let Some(path) = &args.rrd {
        recorders.push(Box::new(RerunRecorder::save(path, &info)?));
    }
    if args.spawn {
        recorders.push(Box::new(RerunRecorder::spawn(&info, args.speed)?));
    }
    if let Some(path) = &args.csv {
        recorders.push(Box::new(CsvRecorder::create(path, &info)?));
    }
    // Opened before the run, so that an unwritable path fails before the simulation.
    let summary_file = args
        .summary
        .as_deref()
        .map(AtomicFile::create)
        .transpose()?;
    let mut observer = RecordingObserver::new(recorders, &scene);
    let mut progress = (!args.quiet).then(|| RunProgress::new(&scene, "simulating"));
    interrupt::stop_gracefully();
    let result = run_scene(&scene, &mut StopOnSignal((&mut observer, &mut progress)));
    drop(progress);
    let summary = match result {
        Ok(summary) => summary,
        Err(err) => {
            // Recorders dropped unfinished leave no output file behind.
            eprintln!("error: {}: {err}", scene.path.display());
            if let RunError::Step(StepError::Runaway { index, .. }) = &err {
                let name = scene.coordinates.get(*index).map_or("?", String::as_str);
                eprintln!(
                    "note: u_{index} is the rate of '{name}' (simulation.max_speed sets the limit)"
                );
            }
            interrupt::keeping_partial_outputs(|| {
                report_partial_outputs(observer, &err, summary_file.is_some())
            });
            return Ok(ExitCode::from(exit::of_run_error(&err)));
        }
    };
    observer.finish()?;
    if let Some(mut file) = summary_file {
        let path = file.path().to_path_buf();
        hopsim_io::to_json_value(&summary)
            .and_then(|json| serde_json::to_writer_pretty(&mut file, &json))
            .map_err(std::io::Error::from)
            .and_then(|()| file.write_all(b"\n"))
            .with_context(|| format!("writing the summary to {}", path.display()))?;
        file.commit()?;
    }
    if !args.quiet {
        println!("{summary}");
    }
    Ok(ExitCode::SUCCESS)
}

/// Keeps the recordings of a run stopped by `err` under their partial names and says
/// where they are (a recording that failed itself is not kept); the summary is not written.
fn report_partial_outputs(observer: RecordingObserver, err: &RunError, summary: bool) {
    let kept = match err {
        RunError::Record(_) => Ok(Vec::new()),
        _ if observer.records_anything() => observer.finish_partial(err),
        _ => Ok(Vec::new()),
    };
    match kept {
        Ok(kept) if !kept.is_empty() => {
            let names: Vec<String> = kept.iter().map(|p| p.display().to_string()).collect();
            eprintln!(
                "note: the recordings up to the stop are kept, with the reason in their \
                 metadata: {}",
                names.join(", ")
            );
        }
        Ok(_) => {}
        Err(e) => eprintln!("error: the recordings up to the stop could not be kept: {e}"),
    }
    if summary {
        eprintln!("error: the run summary was not written: the run did not finish");
    }
}

/// The extension of each output's format.
const OUTPUT_EXTENSIONS: [(&str, &str); 4] = [
    ("--mcap", "mcap"),
    ("--rrd", "rrd"),
    ("--csv", "csv"),
    ("--summary", "json"),
];

/// Output files must differ from each other and from the scene file: a summary written
/// over the scene, or a CSV over the MCAP, would silently lose one of them. A path ending
/// in another output's extension (`--rrd out.mcap`) is refused: the file would not be what
/// its name says. Returns a warning for each path with an extension of no output format.
fn check_output_paths(args: &RunArgs, scene: &Path) -> Result<Vec<String>, String> {
    let mut outputs: Vec<(&str, PathBuf)> = Vec::new();
    let flags = [
        ("--mcap", &args.mcap),
        ("--rrd", &args.rrd),
        ("--csv", &args.csv),
        ("--summary", &args.summary),
    ];
    for (flag, path) in flags {
        if let Some(path) = path {
            outputs.push((flag, path.clone()));
        }
    }
    if let Some(csv) = &args.csv {
        outputs.push(("--csv (events)", CsvRecorder::events_path(csv)));
    }
    let same = |a: &Path, b: &Path| match (std::path::absolute(a), std::path::absolute(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    for (i, (flag, path)) in outputs.iter().enumerate() {
        if same(path, scene) {
            return Err(format!(
                "{flag} {}: that is the scene file; choose another output path",
                path.display()
            ));
        }
        if let Some((other, _)) = outputs[..i].iter().find(|(_, p)| same(p, path)) {
            return Err(format!(
                "{flag} {} is also the {other} output; each output needs its own path",
                path.display()
            ));
        }
    }
    let mut warnings = Vec::new();
    for (flag, path) in outputs {
        let Some(&(_, expected)) = OUTPUT_EXTENSIONS.iter().find(|(f, _)| *f == flag) else {
            continue;
        };
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let extension = extension.to_ascii_lowercase();
        if extension == expected {
            continue;
        }
        let other = OUTPUT_EXTENSIONS.iter().find(|(_, e)| *e == extension);
        match other {
            Some((other_flag, _)) => {
                return Err(format!(
                    "{flag} {}: a .{extension} name is for {other_flag}; {flag} writes a \
                     .{expected} file (e.g. {flag} {})",
                    path.display(),
                    path.with_extension(expected).display()
                ))
            }
            None => warnings.push(format!(
                "{flag} {}: {flag} writes a .{expected} file, and this name does not end in \
                 .{expected}",
                path.display()
            )),
        }
    }
    Ok(warnings)
}
