//! `hopsim run SCENE`: simulate a scene, record it, print the summary.

use anyhow::Context;
use clap::Args;
use hopsim_record::{CsvRecorder, McapRecorder, RecorderSet, RerunRecorder};
use hopsim_scene::Override;
use hopsim_sim::{recording_info, RecordingObserver, RunError, RunOptions};
use hopsim_step::StepError;
use std::path::PathBuf;
use std::process::ExitCode;

use super::{exit, scene::SceneArgs};

/// Simulate a scene file, record the trajectory and print the run summary.
#[derive(Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Simulated time in seconds (overrides simulation.duration).
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Step size in seconds (overrides simulation.dt).
    #[arg(long, value_name = "SECONDS")]
    pub dt: Option<f64>,
    /// Write an MCAP recording (Foxglove, Python `mcap` reader).
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Write a Rerun recording (.rrd), to open with `rerun FILE`.
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
    /// Stream to a live Rerun viewer (needs the `rerun` viewer on PATH).
    #[arg(long)]
    pub spawn: bool,
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
    let mut extra = Vec::new();
    let mut set = |key: &str, value: String| {
        extra.push(Override {
            key: key.into(),
            value,
        })
    };
    if let Some(d) = args.duration {
        set("simulation.duration", format!("{d:?}"));
    }
    if let Some(dt) = args.dt {
        set("simulation.dt", format!("{dt:?}"));
    }
    if args.strict {
        set("simulation.strict", "true".into());
    }
    let scene = match args.scene.load(&extra) {
        Ok(scene) => scene,
        Err(code) => return Ok(code),
    };
    let info = recording_info(&scene);
    let mut recorders = RecorderSet::default();
    if let Some(path) = &args.mcap {
        recorders.push(Box::new(McapRecorder::create(path, &info)?));
    }
    if let Some(path) = &args.rrd {
        recorders.push(Box::new(RerunRecorder::save(path, &info)?));
    }
    if args.spawn {
        recorders.push(Box::new(RerunRecorder::spawn(&info)?));
    }
    if let Some(path) = &args.csv {
        recorders.push(Box::new(CsvRecorder::create(path, &info)?));
    }
    let mut observer = RecordingObserver::new(recorders, &scene);
    let options = RunOptions {
        progress: (!args.quiet)
            .then(|| super::progress::bar(scene.settings.duration, "simulating")),
    };
    let summary = match hopsim_sim::run(&scene, &options, &mut observer) {
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
            if observer.records_anything() {
                eprintln!("error: no recording was written: the run did not finish");
            }
            return Ok(ExitCode::from(exit::SIMULATION_FAILED));
        }
    };
    observer.finish()?;
    if let Some(path) = &args.summary {
        let json = serde_json::to_string_pretty(&summary)?;
        hopsim_record::write_atomically(path, |w| w.write_all(json.as_bytes()))
            .with_context(|| format!("writing the summary to {}", path.display()))?;
    }
    if !args.quiet {
        println!("{summary}");
    }
    Ok(ExitCode::SUCCESS)
}
