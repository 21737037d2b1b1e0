//! `hopsim scene check FILE`, and the scene argument shared by `run` and `sweep`.

use clap::{Args, Subcommand};
use hopsim_control::ControllerConfig;
use hopsim_scene::{Override, Scene};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A scene file with `--set` overrides.
#[derive(Args, Clone)]
pub struct SceneArgs {
    /// The scene file (TOML), e.g. scenes/robbit.toml (format: docs/scene-format.md), or a
    /// MuJoCo model (.xml), imported as its scene (docs/mjcf.md).
    pub scene: PathBuf,
    /// Override any scene value (a number, string, bool or array), e.g. --set controller.torque=0.2 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<Override>,
}

impl SceneArgs {
    /// Loads the scene with the `--set` overrides and then `extra`; an invalid scene is a
    /// [`hopsim_scene::SceneError`] (exit code 2).
    pub fn load(&self, extra: &[Override]) -> anyhow::Result<Scene> {
        let mut overrides = self.overrides.clone();
        overrides.extend_from_slice(extra);
        Ok(hopsim_scene::load(&self.scene, &overrides)?)
    }
}

/// The scene of a study whose runs all take `--duration` (if given), and the overrides
/// every run gets: the `--set`s, then the duration's.
pub fn load_for_runs(
    scene: &SceneArgs,
    duration: Option<f64>,
) -> anyhow::Result<(Scene, Vec<Override>)> {
    let timing = TimingArgs { duration, dt: None };
    let extra = timing.overrides();
    let loaded = scene.load(&extra)?;
    let mut base = scene.overrides.clone();
    base.extend(extra);
    Ok((loaded, base))
}

/// `out` if given, else `out/<scene's file stem>-<study>`.
pub fn output_folder(out: Option<&Path>, scene: &Scene, study: &str) -> PathBuf {
    out.map_or_else(
        || {
            let stem = scene
                .path
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy());
            PathBuf::from("out").join(format!("{stem}-{study}"))
        },
        Path::to_path_buf,
    )
}

/// `--duration` and `--dt` of a command that runs a scene.
#[derive(Args, Clone, Debug, Default)]
pub struct TimingArgs {
    /// Simulated time in seconds (overrides simulation.duration).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = super::finite)]
    pub duration: Option<f64>,
    /// Step size in seconds (overrides simulation.dt).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = super::finite)]
    pub dt: Option<f64>,
}

impl TimingArgs {
    /// The overrides these options set, each naming its option in errors.
    pub fn overrides(&self) -> Vec<Override> {
        let duration = self
            .duration
            .map(|d| Override::from_flag("--duration", "simulation.duration", format!("{d:?}")));
        let dt = self
            .dt
            .map(|dt| Override::from_flag("--dt", "simulation.dt", format!("{dt:?}")));
        duration.into_iter().chain(dt).collect()
    }
}

/// Scene files: validate without running.
#[derive(Args)]
pub struct SceneCommandArgs {
    #[command(subcommand)]
    pub command: SceneCommand,
}

#[derive(Subcommand)]
pub enum SceneCommand {
    /// Validate a scene file (and overrides) and describe what it contains.
    Check(SceneArgs),
}

pub fn run(args: SceneCommandArgs) -> anyhow::Result<ExitCode> {
    let SceneCommand::Check(args) = args.command;
    let scene = args.load(&[])?;
    println!("{}: ok", args.scene.display());
    print!("{}", describe(&scene));
    for notice in &scene.notices {
        println!("notice: {notice}");
    }
    for warning in hopsim_scene::warnings(&scene) {
        println!("warning: {warning}");
    }
    Ok(ExitCode::SUCCESS)
}

/// A few lines about a valid scene.
fn describe(scene: &Scene) -> String {
    let m = &scene.model;
    let s = &scene.settings;
    let names = |it: &mut dyn Iterator<Item = &str>| it.collect::<Vec<_>>().join(", ");
    let controller = match &scene.controller {
        ControllerConfig::Passive => "passive".to_string(),
        ControllerConfig::MomentumImpulse(c) => format!(
            "momentum-stored impulse on '{}' (T = {} N m, ζ0 = {} N m s), {}",
            m.bodies()[c.flywheel].name,
            c.torque,
            c.impulse_limit,
            c.release
        ),
        ControllerConfig::Pulse(c) => {
            let (what, unit) = if c.drives_force(m) {
                ("force", "N")
            } else {
                ("torque", "N m")
            };
            format!(
                "{what} pulse on '{}' (±{} {unit} for {} s every {:.4} s), cane {}",
                m.bodies()[c.joint_body].name,
                c.torque,
                c.pulse_duration,
                c.period,
                c.cane
            )
        }
    };
    // Only a scene with actuators lists them (in the order of their controls).
    let actuators: String = m
        .actuators()
        .iter()
        .map(|a| {
            format!(
                "{} ({} on '{}')",
                a.name,
                a.kind.name(),
                m.bodies()[a.body].name
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    let actuators = if actuators.is_empty() {
        String::new()
    } else {
        format!("  actuators    {actuators}\n")
    };
    format!(
        "  title        {}\n  bodies       {} ({} coordinates: {})\n  shapes       {}\n  \
         contacts     {} potential\n  springs      {}\n  controller   {controller}\n{actuators}  \
         simulation   {} s in steps of {} s, recorded at {} Hz\n",
        scene.title,
        names(&mut m.bodies().iter().map(|b| b.name.as_str())),
        scene.coordinates.len(),
        scene.coordinates.join(", "),
        names(&mut m.shapes().iter().map(|s| s.name.as_str())),
        m.contacts().len(),
        m.springs().len(),
        s.duration,
        s.dt,
        s.record_rate,
    )
}
