//! What observers of a run see after every step, and how several watch one run.

use crate::RunError;
use hopsim_model::{Kinematics, Model};
use hopsim_record::Event;
use hopsim_step::{State, StepRecord};
use std::sync::atomic::{AtomicBool, Ordering};

/// One finished step, as observers see it.
pub struct StepView<'a> {
    pub model: &'a Model,
    /// State at the end of the step.
    pub state: &'a State,
    /// Kinematics at the end of the step.
    pub kinematics: &'a Kinematics,
    /// The stepper's record (contact percussions, lock impulses, energies).
    pub record: &'a StepRecord,
    /// Discrete events of this step.
    pub events: &'a [Event],
    /// Whether each shape is switched on.
    pub shapes_active: &'a [bool],
    /// Motor torque commanded in this step, N m (the first torque command; without one, the
    /// first joint force: N on a prismatic joint, docs/physics.md §7).
    pub torque: f64,
    /// The controls of the model's actuators in this step (docs/physics.md §7.4; empty
    /// without actuators).
    pub controls: &'a [f64],
}

/// Something that watches a run: recorders, the summary, golden-trace collectors.
pub trait Observer {
    /// Called after every step.
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError>;

    /// Called once before the first step with the initial state (`record.step == 0`, no
    /// contacts, no events); recorders record it as the first frame.
    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        let _ = view;
        Ok(())
    }
}

impl<T: Observer + ?Sized> Observer for &mut T {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        (**self).on_step(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        (**self).on_start(view)
    }
}

impl Observer for () {
    fn on_step(&mut self, _: &StepView<'_>) -> Result<(), RunError> {
        Ok(())
    }
}

/// Two observers watching one run: each step goes to the first, then to the second.
impl<A: Observer, B: Observer> Observer for (A, B) {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.0.on_step(view)?;
        self.1.on_step(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.0.on_start(view)?;
        self.1.on_start(view)
    }
}

/// An observer that may be absent.
impl<O: Observer> Observer for Option<O> {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.as_mut().map_or(Ok(()), |o| o.on_step(view))
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.as_mut().map_or(Ok(()), |o| o.on_start(view))
    }
}

/// Stops a run with [`RunError::Interrupted`] at the first step after its flag is set (by
/// another thread: a front end that saw Ctrl-C, for the runs of a sweep).
pub struct StopFlag<'a>(pub &'a AtomicBool);

impl Observer for StopFlag<'_> {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        if self.0.load(Ordering::Relaxed) {
            return Err(RunError::Interrupted { t: view.state.t });
        }
        Ok(())
    }
}
