//! `hopsim analyze gait SCENE|RECORDING`: a gait cycle by cycle (docs/physics.md §5.3, §5.4),
//! computed by [`hopsim_studies::gait`].

use clap::Args;
use hopsim_scene::Override;
use hopsim_studies::gait::{self, CycleSplit, GaitParams, GaitTrace, EVENT_KINDS};
use std::path::PathBuf;

use super::common::{invalid, OutputArgs};
use crate::cmd::render::render;
use crate::cmd::scene::TimingArgs;

/// Cuts a run into cycles (at Robbit's brakes, CaneBot's motor periods, or any event) and
/// reports per cycle its period, distance, flight, stance and motor-on (spin-up) fractions
/// and apex height; the gait's period on the Poincaré section at the cycle starts; and
/// with --out the cycles' x, y, φ against cycle progress, the last ones overlaid with
/// their mean (the thesis' Fig. 5.11).
#[derive(Args)]
pub struct GaitArgs {
    /// A scene file (run for its duration) or an MCAP recording of `hopsim run --mcap`
    /// (a file ending in .mcap).
    pub input: PathBuf,
    /// Override a scene value, e.g. --set controller.torque=0.3 (scenes only; repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<Override>,
    /// --duration, --dt: scenes only.
    #[command(flatten)]
    pub timing: TimingArgs,
    /// Where cycles start: an event kind (brake, take-off, touchdown, shape-switch,
    /// shape-contact, applied-impulse) or `period` (every motor period). Default: brake for
    /// the momentum-impulse controller, period for the pulse controller, else take-off.
    #[arg(long, value_name = "KIND")]
    pub split: Option<String>,
    /// The period of --split period [s] (default: the scene's motor period).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = crate::cmd::finite)]
    pub period: Option<f64>,
    /// Cycles at the end of the run in the statistics and the overlay.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..))]
    pub last: u32,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(args: GaitArgs) -> anyhow::Result<()> {
    let trace = trace(&args)?;
    let params = GaitParams {
        split: split(&args, &trace)?,
        last: args.last as usize,
        ..GaitParams::default()
    };
    render(&gait::analyze(&trace, &params)?, &args.output)
}

/// The run to analyse: the scene run for its duration, or the recording read back.
fn trace(args: &GaitArgs) -> anyhow::Result<GaitTrace> {
    let recording = args.input.extension().is_some_and(|e| e == "mcap");
    let mut overrides = args.overrides.clone();
    overrides.extend(args.timing.overrides());
    if recording {
        if !overrides.is_empty() {
            return invalid(format!(
                "{}: --set, --duration and --dt apply to scenes, not to recordings",
                args.input.display()
            ));
        }
        return Ok(gait::trace_of_recording(&args.input)?);
    }
    match hopsim_scene::load(&args.input, &overrides) {
        Ok(scene) => Ok(gait::trace_of_scene(&scene)?),
        Err(err) => invalid(err.to_string()),
    }
}

/// The split `--split` and `--period` ask for (`None`: the run's own).
fn split(args: &GaitArgs, trace: &GaitTrace) -> anyhow::Result<Option<CycleSplit>> {
    let kind = args.split.as_deref().map(|k| k.replace('-', "_"));
    match (kind.as_deref(), args.period) {
        (None, None) => Ok(None),
        (None | Some("period"), Some(period)) => {
            if period <= 0.0 {
                return invalid(format!("--period must be > 0, got {period}"));
            }
            let t0 = match &trace.natural_split {
                CycleSplit::Period { t0, .. } => *t0,
                CycleSplit::Event { .. } => trace.states.first().map_or(0.0, |s| s.t),
            };
            Ok(Some(CycleSplit::Period { period, t0 }))
        }
        (Some("period"), None) => match &trace.natural_split {
            split @ CycleSplit::Period { .. } => Ok(Some(split.clone())),
            CycleSplit::Event { .. } => invalid(format!(
                "{}: the scene has no motor period; give one with --period SECONDS",
                args.input.display()
            )),
        },
        (Some(kind), None) if EVENT_KINDS.contains(&kind) => Ok(Some(CycleSplit::event(kind))),
        (Some(kind), None) => invalid(format!(
            "--split {kind}: expected period or an event kind ({})",
            EVENT_KINDS.join(", ").replace('_', "-")
        )),
        (Some(_), Some(_)) => invalid("--period applies to --split period only"),
    }
}
