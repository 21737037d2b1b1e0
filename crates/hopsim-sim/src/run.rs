//! A whole run: the scene's duration step by step, with the summary watching; or a span
//! of a simulation already under way.

use crate::summary::SummaryCollector;
use crate::Setup;
use crate::{Observer, RunError, Simulation, Summary};
use std::time::Instant;

/// Runs `scene` for its duration, showing every step to `observer` (after the summary has
/// seen it), and returns the run summary. On an error the observer has seen every step
/// before it.
pub fn run(scene: &Setup, observer: &mut dyn Observer) -> Result<Summary, RunError> {
    run_for(
        &mut Simulation::new(scene),
        scene.settings.duration,
        observer,
    )
}

/// Continues `sim` from its current state for `duration` seconds (`round(duration / Δt)`
/// steps of the scene's controller), showing the current state
/// ([`Observer::on_start`]) and then every step to `observer` (after the summary has seen
/// it), and returns the summary of that span. For a simulation at its scene's initial
/// state and the scene's duration this is [`run`]. The LCP figures count every solve
/// since the simulation (re)started.
pub fn run_for(
    sim: &mut Simulation,
    duration: f64,
    observer: &mut dyn Observer,
) -> Result<Summary, RunError> {
    let scene = sim.setup();
    let steps = (duration / scene.settings.dt).round() as u64;
    let mut summary = SummaryCollector::new(scene, sim.state(), duration);
    let started = Instant::now();
    let mut both = (&mut summary, observer);
    sim.start(&mut both)?;
    for _ in 0..steps {
        sim.step(&mut both)?;
    }
    let wall_time_s = started.elapsed().as_secs_f64();
    let summary = summary.finish(&sim.view(), sim.stepper().lcp_stats(), wall_time_s);
    match summary.first_non_finite() {
        Some((figure, value)) => Err(RunError::NotFinite { figure, value }),
        None => Ok(summary),
    }
}
