//! Progress bars on standard error, drawn only on a terminal: a run's bar over simulated
//! time (an observer of the run, shown once the run has taken longer than a second), and
//! count bars over the cells or runs of a study.

use hopsim_scene::Scene;
use hopsim_sim::{Observer, RunError, StepView};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::time::{Duration, Instant};

/// A run's progress bar: watches the steps and shows the simulated time in milliseconds,
/// from the first update after a second of wall time on. Cleared when dropped.
pub struct RunProgress {
    bar: ClearOnDrop,
    started: Instant,
    revealed: bool,
    /// The bar is updated every `every` steps (a thousand updates per run).
    every: u64,
    steps: u64,
}

/// Wall time after which a run's bar appears.
const REVEAL_AFTER: Duration = Duration::from_secs(1);

impl RunProgress {
    /// A bar over the duration of `scene`, labelled `what`.
    pub fn new(scene: &Scene, what: &str) -> Self {
        let s = &scene.settings;
        let bar = ProgressBar::with_draw_target(
            Some((s.duration * 1e3) as u64),
            ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} ms simulated, {elapsed_precise} elapsed, eta {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_message(what.to_string());
        let steps = (s.duration / s.dt).round() as u64;
        Self {
            bar: ClearOnDrop(bar),
            started: Instant::now(),
            revealed: false,
            every: (steps / 1000).max(1),
            steps: 0,
        }
    }
}

impl Observer for RunProgress {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.steps += 1;
        if !(self.steps - 1).is_multiple_of(self.every) {
            return Ok(());
        }
        if !self.revealed && self.started.elapsed() > REVEAL_AFTER {
            self.bar.0.set_draw_target(ProgressDrawTarget::stderr());
            self.revealed = true;
        }
        self.bar.0.set_position((view.state.t * 1e3) as u64);
        Ok(())
    }
}

/// A bar over `len` items (e.g. the runs of a sweep), on stderr unless `quiet`; indicatif
/// draws nothing when stderr is not a terminal.
pub fn count_bar(len: u64, unit: &str, quiet: bool) -> ProgressBar {
    let target = if quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let bar = ProgressBar::with_draw_target(Some(len), target);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{msg}} [{{bar:40}}] {{pos}}/{{len}} {unit}, {{elapsed_precise}} elapsed, eta {{eta}}"
        ))
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}

/// A study's progress as count bars: one bar per task, labelled with the task's name,
/// counting `unit`s (hidden when `quiet`), cleared when the task ends.
pub struct CountBars {
    pub unit: &'static str,
    pub quiet: bool,
}

impl hopsim_studies::progress::Progress for CountBars {
    fn task(&self, cells: usize, label: &str) -> hopsim_studies::progress::Tick<'_> {
        let bar = count_bar(cells as u64, self.unit, self.quiet);
        bar.set_message(label.to_string());
        let bar = ClearOnDrop(bar);
        Box::new(move || bar.0.inc(1))
    }
}

/// A bar cleared when dropped.
struct ClearOnDrop(ProgressBar);

impl Drop for ClearOnDrop {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}
