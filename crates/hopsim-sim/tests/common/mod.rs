//! Helpers shared by the scene-level tests: bundled scenes, runs, first-second traces.
#![allow(dead_code)]

use hopsim_record::ImpulseTrace;
use hopsim_scene::{Override, Scene};
use hopsim_sim::{Observer, RunError, Simulation, StepView, Summary};
use std::path::{Path, PathBuf};

/// A path relative to the repository root.
pub fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// A bundled scene with `--set`-style overrides (`"key=value"`).
pub fn scene(name: &str, overrides: &[&str]) -> Scene {
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::load(&repo(&format!("scenes/{name}")), &overrides)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Indices of the steps that start a run of steps with `active` true (an impact).
pub fn starts<T>(samples: &[T], active: impl Fn(&T) -> bool) -> Vec<usize> {
    (0..samples.len())
        .filter(|&i| active(&samples[i]) && (i == 0 || !active(&samples[i - 1])))
        .collect()
}

/// Runs `scene` for its duration, step by step, and returns what `sample` takes from each
/// step.
pub fn sampled<T>(scene: &Scene, sample: impl FnMut(&StepView<'_>) -> T) -> Vec<T> {
    struct Collect<T, F>(Vec<T>, F);
    impl<T, F: FnMut(&StepView<'_>) -> T> Observer for Collect<T, F> {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            self.0.push((self.1)(v));
            Ok(())
        }
    }
    let steps = (scene.settings.duration / scene.settings.dt).round() as u64;
    let mut sim = Simulation::new(scene);
    let mut collect = Collect(Vec::new(), sample);
    for _ in 0..steps {
        sim.step(&mut collect).expect("step");
    }
    collect.0
}

/// Runs `scene` to its end, showing every step to `observer`.
pub fn run(scene: &Scene, observer: &mut dyn Observer) -> Summary {
    hopsim_sim::run(scene, observer).expect("run completes")
}

/// The contact and lock percussions of every step of the scene's first second.
pub fn first_second(scene: &Scene) -> ImpulseTrace {
    struct Collect(ImpulseTrace);
    impl Observer for Collect {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), RunError> {
            self.0.push_record(v.model, v.record);
            Ok(())
        }
    }
    let steps = (1.0 / scene.settings.dt).round() as u64;
    let mut sim = Simulation::new(scene);
    let mut collect = Collect(ImpulseTrace::default());
    for _ in 0..steps {
        sim.step(&mut collect).expect("step");
    }
    collect.0
}
