//! The run summary of a run whose end is not known when it starts (a front end that steps
//! a simulation itself and stops when it likes): the summary of [`crate::run_for`] with
//! the speed window placed at the end once the end is known.

use crate::summary::SummaryCollector;
use crate::{Observer, RunError, Simulation, StepView, Summary};
use hopsim_record::EventKind;
use std::collections::VecDeque;
use std::time::Instant;

/// Watches a run step by step ([`Observer`]) and, at [`OpenSummary::finish`], gives the
/// [`Summary`] that [`crate::run_for`] gives for a run of that length: the speed window
/// is the last `summary.speed_window` seconds before the last step seen (at most the whole
/// run).
///
/// It keeps the centre of mass's abscissa of every step within one speed window of the
/// latest step, and the actuator impulses within it: memory grows with the steps in a
/// window, not with the run (a queue that stops growing once a window is full).
pub struct OpenSummary {
    collector: SummaryCollector,
    speed_window: f64,
    dt: f64,
    t_start: f64,
    x_start: f64,
    /// `(t, x_com)` of the steps of the last speed window, and the latest step before it.
    positions: VecDeque<(f64, f64)>,
    /// `(t, magnitude, brake)` of the actuator impulses of the last speed window.
    impulses: VecDeque<(f64, f64, bool)>,
    started: Instant,
}

impl OpenSummary {
    /// Starts watching `sim` at its current state (nothing is shown to the summary yet:
    /// the next step is its first).
    pub fn new(sim: &Simulation) -> Self {
        let setup = sim.setup();
        let start = sim.state();
        let view = sim.view();
        let x_start = setup.model.center_of_mass(view.kinematics).x;
        Self {
            // A window that never starts: the window's figures are set at the end.
            collector: SummaryCollector::new(setup, start, f64::INFINITY),
            speed_window: setup.settings.speed_window,
            dt: setup.settings.dt,
            t_start: start.t,
            x_start,
            positions: VecDeque::new(),
            impulses: VecDeque::new(),
            started: Instant::now(),
        }
    }

    /// The summary of the steps seen, at `sim`'s last step (the simulation this summary
    /// watched). Errors as [`crate::run_for`]: a figure that is not finite.
    pub fn finish(self, sim: &Simulation) -> Result<Summary, RunError> {
        let wall_time_s = self.started.elapsed().as_secs_f64();
        let end = sim.view();
        // As `run_for` places it for a run of this duration.
        let duration = end.state.t - self.t_start;
        let window_start = self.t_start + (duration - self.speed_window);
        let x_window = match window_start <= self.t_start {
            true => Some(self.x_start),
            false => self
                .positions
                .iter()
                .find(|(t, _)| *t >= window_start)
                .map(|&(_, x)| x),
        };
        let (mut impulse, mut brakes) = (0.0, 0);
        for &(_, magnitude, brake) in self.impulses.iter().filter(|(t, ..)| *t > window_start) {
            impulse += magnitude;
            brakes += u64::from(brake);
        }
        let mut collector = self.collector;
        collector.set_window(window_start, x_window, impulse, brakes);
        let summary = collector.finish(&end, sim.stepper().lcp_stats(), wall_time_s);
        match summary.first_non_finite() {
            Some((figure, value)) => Err(RunError::NotFinite { figure, value }),
            None => Ok(summary),
        }
    }
}

impl Observer for OpenSummary {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.collector.on_step(view)?;
        let t = view.state.t;
        let x = view.model.center_of_mass(view.kinematics).x;
        // Keep the steps from one step before the window's earliest possible start.
        let oldest = t - self.speed_window - self.dt;
        while self.positions.len() > 1 && self.positions[1].0 <= oldest {
            self.positions.pop_front();
        }
        self.positions.push_back((t, x));
        while self.impulses.front().is_some_and(|i| i.0 <= oldest) {
            self.impulses.pop_front();
        }
        for ev in view.events {
            match ev.kind {
                EventKind::Brake { impulse } => self.impulses.push_back((t, impulse, true)),
                EventKind::AppliedImpulse { magnitude } => {
                    self.impulses.push_back((t, magnitude, false))
                }
                _ => {}
            }
        }
        Ok(())
    }
}
