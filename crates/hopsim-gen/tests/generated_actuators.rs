//! Random actuators on generated mechanisms (docs/physics.md §7.4): any kind, gear, gains
//! and ranges on any joint, driven by random controls inside and far outside their ranges,
//! never panic; a refused actuator or control is an error, and a run either completes or
//! stops with a step error (a runaway state), never an internal one.

use hopsim_gen::{genes, scene_of, Mechanism};
use hopsim_sim::{Observer, RunError, Simulation, StepView};
use proptest::prelude::*;
use std::path::Path;

/// The most steps each case runs.
const STEPS: u64 = 400;

/// One actuator's draw: which joint (a fraction of the jointed bodies), kind, gear, gains,
/// ranges, its controls, and whether to damage it.
#[derive(Clone, Debug)]
struct Draw {
    joint: f64,
    kind: u8,
    gear: f64,
    kp: f64,
    kv: f64,
    ctrl_range: Option<(f64, f64)>,
    force_range: Option<(f64, f64)>,
    controls: Vec<f64>,
    damage: Option<u8>,
}

fn magnitude() -> impl Strategy<Value = f64> {
    (-6.0f64..6.0, any::<bool>())
        .prop_map(|(e, neg)| if neg { -(10f64.powf(e)) } else { 10f64.powf(e) })
}

fn draw() -> impl Strategy<Value = Draw> {
    (
        0.0f64..1.0,
        0u8..3,
        magnitude(),
        (0.0f64..1e4, 0.0f64..1e3),
        proptest::option::of((magnitude(), magnitude())),
        proptest::option::of((magnitude(), magnitude())),
        proptest::collection::vec(magnitude(), 4),
        proptest::option::weighted(0.1, 0u8..4),
    )
        .prop_map(
            |(joint, kind, gear, (kp, kv), ctrl_range, force_range, controls, damage)| Draw {
                joint,
                kind,
                gear,
                kp,
                kv,
                ctrl_range,
                force_range,
                controls,
                damage,
            },
        )
}

fn sorted((a, b): (f64, f64)) -> (f64, f64) {
    (a.min(b), a.max(b))
}

/// The `[[actuators]]` table of `d` on body `joint` (a damaged one: gear 0, an inverted
/// control range, a negative gain, or an unknown joint).
fn table(i: usize, joint: &str, d: &Draw) -> String {
    let kind = match d.damage {
        Some(2) => 1,
        _ => d.kind as usize,
    };
    let gear = if d.damage == Some(0) { 0.0 } else { d.gear };
    let joint = if d.damage == Some(3) {
        "no such body"
    } else {
        joint
    };
    let mut t = format!(
        "[[actuators]]\nname = \"a{i}\"\njoint = \"{joint}\"\nkind = \"{}\"\ngear = {gear:?}\n",
        ["motor", "position", "velocity"][kind]
    );
    let kv = if d.damage == Some(2) { -1.0 } else { d.kv };
    match kind {
        1 => t += &format!("kp = {:?}\nkv = {kv:?}\n", d.kp),
        2 => t += &format!("kv = {kv:?}\n"),
        _ => {}
    }
    let ctrl = d.ctrl_range.map(sorted).map(|(lo, hi)| match d.damage {
        Some(1) => (hi + 1.0, lo),
        _ => (lo, hi),
    });
    let ctrl = if d.damage == Some(1) {
        ctrl.or(Some((1.0, 0.0)))
    } else {
        ctrl
    };
    if let Some((lo, hi)) = ctrl {
        t += &format!("ctrl_range = [{lo:?}, {hi:?}]\n");
    }
    if let Some((lo, hi)) = d.force_range.map(sorted) {
        t += &format!("force_range = [{lo:?}, {hi:?}]\n");
    }
    t + "\n"
}

struct Nothing;
impl Observer for Nothing {
    fn on_step(&mut self, _: &StepView<'_>) -> Result<(), RunError> {
        Ok(())
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_actuators_never_panic(g in genes(), draws in proptest::collection::vec(draw(), 1..4)) {
        let mechanism = Mechanism::from_genes(&g);
        let Ok(Ok(scene)) = scene_of(&mechanism) else {
            return Ok(());
        };
        let jointed: Vec<&str> = scene
            .model
            .bodies()
            .iter()
            .filter(|b| b.joint.as_ref().is_some_and(|j| j.has_coordinate()))
            .map(|b| b.name.as_str())
            .collect();
        if jointed.is_empty() {
            return Ok(());
        }
        let mut text = scene.text.clone();
        for (i, d) in draws.iter().enumerate() {
            let joint = jointed[((d.joint * jointed.len() as f64) as usize).min(jointed.len() - 1)];
            text += &table(i, joint, d);
        }
        let damaged = draws.iter().any(|d| d.damage.is_some());
        let scene = match hopsim_scene::parse(&text, Path::new("generated.toml"), &[]) {
            Ok(scene) => {
                prop_assert!(!damaged, "a damaged actuator was accepted:\n{text}");
                scene
            }
            Err(e) => {
                // Huge numbers may be refused as out of the scene's bounds too.
                let message = e.to_string();
                prop_assert!(message.contains("actuators"), "{message}\n{text}");
                return Ok(());
            }
        };
        let mut sim = Simulation::new(&scene);
        prop_assert!(sim.set_control(0, f64::NAN).is_err());
        prop_assert!(sim.set_control(draws.len(), 0.0).is_err());
        let steps = STEPS.min(mechanism.steps);
        for k in 0..steps {
            if k % 100 == 0 {
                let round = (k / 100) as usize % 4;
                let controls: Vec<f64> = draws.iter().map(|d| d.controls[round]).collect();
                sim.set_controls(&controls).unwrap();
            }
            match sim.step(&mut Nothing) {
                Ok(()) => {}
                Err(RunError::Step(_)) => break,
                Err(e) => prop_assert!(false, "{e}\n{text}"),
            }
        }
    }
}
