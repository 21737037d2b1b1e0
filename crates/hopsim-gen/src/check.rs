//! What every run of a generated mechanism must satisfy (docs/reliability.md, "Generated
//! mechanisms"): no panic; the run ends or stops with a typed error; in every step whose
//! LCP was certified the percussions obey the contact laws they were solved for
//! (Signorini, Coulomb, the stops' Newton law), checked from the step records alone; every
//! reported number is finite; and the energy account is kept.

use crate::Mechanism;
use hopsim_record::EventKind;
use hopsim_scene::Scene;
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use hopsim_step::{ContactRecord, ContactState, Resolution, STATE_MARGIN};
use std::path::Path;

/// How a generated mechanism's run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Every step was taken.
    Ran(RunFigures),
    /// The run stopped with a typed error (non-finite or runaway state, a strict LCP
    /// failure, a singular mass matrix); its text.
    Stopped(String),
    /// The scene was refused (its start overlaps the terrain or another body even after
    /// lifting it); the error's text.
    Rejected(String),
}

/// Figures of a run that went to its end.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunFigures {
    pub steps: u64,
    /// Steps whose frictional LCP was not certified (frictionless fallback).
    pub lcp_failures: u64,
    /// Largest `|balance error|` of the energy account (docs/physics.md §6.1), J.
    pub max_balance_error: f64,
    /// Largest signed balance error, J: energy the scheme added beyond what the account
    /// explains (a negative error is energy the scheme lost).
    pub max_balance_gain: f64,
    /// The run's energy scale: the largest `E_kin + |V − V_0| + V_s` and `|work|` seen, J.
    pub energy_scale: f64,
    /// Mechanical energy at the end minus at the start minus the actuators' work, J
    /// (`−dissipated + balance error`).
    pub energy_gain: f64,
    /// Largest increment of the damping work in one step, J (a damper never adds energy:
    /// `≤ 0`).
    pub max_damping_gain: f64,
    /// The scene's warnings (`hopsim_scene::warnings`): springs, dampers or impacts beyond
    /// the accurate range of `Δt`, materials whose impacts can add energy.
    pub warnings: usize,
    /// Energy added by impacts as the run reported it (`energy_created` events), J.
    pub created_in_impacts: f64,
}

/// A broken contact law, a non-finite number, or a panic: what makes a generated case fail.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation(pub String);

/// Checks every step's records (see the module doc) and collects [`RunFigures`].
#[derive(Default)]
struct Checker {
    figures: RunFigures,
    potential0: Option<f64>,
    last_damping_work: f64,
    violation: Option<String>,
}

/// The contact laws are checked to [`STATE_MARGIN`] times the step's resolution (the
/// certificate's tolerances, [`Resolution`]): `(velocity, impulse)`.
fn tolerances(resolution: Resolution) -> (f64, f64) {
    (
        STATE_MARGIN * resolution.velocity,
        STATE_MARGIN * resolution.impulse,
    )
}

impl Checker {
    fn fail(&mut self, step: u64, what: String) {
        if self.violation.is_none() {
            self.violation = Some(format!("step {step}: {what}"));
        }
    }

    fn fail_contact(&mut self, step: u64, c: &ContactRecord, mu: f64, what: String) {
        self.fail(step, format!("{what}\n  μ = {mu}, record {c:?}"));
    }

    fn contact(&mut self, view: &StepView<'_>, c: &ContactRecord, pair: bool) {
        let (tol, impulse_tol) = tolerances(view.record.resolution);
        let step = view.record.step;
        let (material, name) = if pair {
            let i = view.model.contacts().len() + c.contact;
            (view.model.material(i), view.model.contact_name(i))
        } else {
            (
                view.model.material(c.contact),
                view.model.contact_name(c.contact),
            )
        };
        let values = [
            c.gap,
            c.impulse_normal,
            c.impulse_tangent,
            c.slip_velocity,
            c.normal_velocity,
        ];
        if values.iter().any(|v| !v.is_finite()) {
            return self.fail(
                step,
                format!("contact {name}: a non-finite record {values:?}"),
            );
        }
        if view.record.lcp_failed {
            return;
        }
        let (ln, lt) = (c.impulse_normal, c.impulse_tangent);
        let mu = material.friction;
        if ln < 0.0 || lt.abs() > mu * ln + impulse_tol {
            return self.fail_contact(
                step,
                c,
                mu,
                format!("contact {name}: Λ_N = {ln:e}, Λ_T = {lt:e} outside the cone μ = {mu}"),
            );
        }
        if c.normal_velocity < -tol {
            return self.fail_contact(
                step,
                c,
                mu,
                format!(
                    "contact {name}: ξ_N = {:e} < 0 (penetrating)",
                    c.normal_velocity
                ),
            );
        }
        if c.state != ContactState::Open && c.normal_velocity > tol {
            return self.fail_contact(
                step,
                c,
                mu,
                format!(
                    "contact {name}: Λ_N = {ln:e} while separating at ξ_N = {:e}",
                    c.normal_velocity
                ),
            );
        }
        if c.state == ContactState::Stick && c.slip_velocity.abs() > tol {
            return self.fail_contact(
                step,
                c,
                mu,
                format!("contact {name}: sticking but ξ_T = {:e}", c.slip_velocity),
            );
        }
        if c.slip_velocity.abs() > tol && lt * c.slip_velocity > 0.0 && mu * ln > 0.0 {
            self.fail_contact(
                step,
                c,
                mu,
                format!(
                    "contact {name}: friction Λ_T = {lt:e} along the slip ξ_T = {:e}",
                    c.slip_velocity
                ),
            );
        }
    }
}

impl Observer for Checker {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        let record = view.record;
        let (tol, _) = tolerances(record.resolution);
        for c in &record.contacts {
            self.contact(view, c, false);
        }
        for c in &record.pair_contacts {
            self.contact(view, c, true);
        }
        if !record.lcp_failed {
            for l in record.limits.iter().filter(|l| !l.locked) {
                let e = view.model.limits()[l.limit].restitution;
                let xi = l.velocity_after + e * l.velocity_before;
                if l.impulse < 0.0 || xi < -tol || (l.impulse > 0.0 && xi > tol) {
                    self.fail(
                        record.step,
                        format!(
                            "stop {}: Λ = {:e} with ξ = {xi:e}",
                            view.model.limits()[l.limit].name,
                            l.impulse
                        ),
                    );
                }
            }
        }
        let e = &record.energy;
        let potential0 = *self.potential0.get_or_insert(e.potential);
        let scale = e.scale(potential0);
        if !scale.is_finite() {
            self.fail(record.step, format!("a non-finite energy account {e:?}"));
        }
        let f = &mut self.figures;
        f.steps = record.step;
        f.lcp_failures += u64::from(record.lcp_failed);
        f.energy_scale = f.energy_scale.max(scale);
        f.max_balance_error = f.max_balance_error.max(e.balance_error().abs());
        f.max_balance_gain = f.max_balance_gain.max(e.balance_error());
        f.energy_gain = e.total() - e.initial - e.actuator_work;
        f.max_damping_gain = f
            .max_damping_gain
            .max(e.damping_work - self.last_damping_work);
        self.last_damping_work = e.damping_work;
        for ev in view.events {
            if let EventKind::EnergyCreated { energy, .. } = ev.kind {
                f.created_in_impacts += energy;
            }
        }
        Ok(())
    }
}

/// The scene of `mechanism`, lifted (up to three times, 0.5 m each) while its start
/// overlaps the terrain or another body; the last refusal's text otherwise. Any other
/// refusal is a [`Violation`]: the generator writes only valid scenes.
pub fn scene_of(mechanism: &Mechanism) -> Result<Result<Scene, String>, Violation> {
    let mut mechanism = mechanism.clone();
    let mut last = String::new();
    for _ in 0..4 {
        let text = mechanism.to_toml();
        match hopsim_scene::parse(&text, Path::new("generated.toml"), &[]) {
            Ok(scene) => return Ok(Ok(scene)),
            Err(e) => {
                last = e.to_string();
                if !(last.contains("inside the terrain") || last.contains("overlap")) {
                    return Err(Violation(format!(
                        "a generated scene was refused: {last}\n{text}"
                    )));
                }
            }
        }
        mechanism.lift(0.5);
    }
    Ok(Err(last))
}

/// Runs `mechanism` for its steps and checks it (see the module doc).
pub fn run_and_check(mechanism: &Mechanism) -> Result<Outcome, Violation> {
    let scene = match scene_of(mechanism)? {
        Ok(scene) => scene,
        Err(reason) => return Ok(Outcome::Rejected(reason)),
    };
    let mut sim = Simulation::new(&scene);
    let mut checker = Checker::default();
    checker.figures.warnings = hopsim_scene::warnings(&scene).len();
    let mut result = sim.start(&mut checker);
    for _ in 0..mechanism.steps {
        if result.is_err() {
            break;
        }
        result = sim.step(&mut checker);
    }
    if let Some(what) = checker.violation {
        return Err(Violation(what));
    }
    match result {
        Ok(()) => Ok(Outcome::Ran(checker.figures)),
        Err(RunError::Step(e)) => Ok(Outcome::Stopped(e.to_string())),
        Err(e) => Err(Violation(format!("the run ended with {e}"))),
    }
}
