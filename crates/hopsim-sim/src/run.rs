//! A whole run: the scene's duration step by step, with the summary watching.

use crate::summary::SummaryCollector;
use crate::{Observer, RunError, Simulation, Summary};
use hopsim_scene::Scene;
use std::time::Instant;

/// Runs `scene` for its duration, showing every step to `observer` (after the summary has
/// seen it), and returns the run summary. On an error the observer has seen every step
/// before it.
pub fn run(scene: &Scene, observer: &mut dyn Observer) -> Result<Summary, RunError> {
    let steps = (scene.settings.duration / scene.settings.dt).round() as u64;
    let mut sim = Simulation::new(scene);
    let mut summary = SummaryCollector::new(scene);
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
