//! The stepper's stages are compiled once per small number of coordinates (`n` = 3…6) and
//! once for any `n` (`Stepper::step`): on generated mechanisms of every specialised size,
//! passive, the sized path and the generic one (`Stepper::step_generic`) give the same
//! states, percussions and errors bit for bit.

use hopsim_gen::{genes, scene_of, Mechanism};
use hopsim_step::{Actuation, Stepper};
use proptest::strategy::{Strategy, ValueTree};

#[test]
fn sized_steps_equal_the_generic_step_bit_for_bit() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut compared = [0usize; 7];
    let actuation = Actuation::default();
    for _ in 0..400 {
        let g = genes().new_tree(&mut runner).unwrap().current();
        let Ok(Ok(scene)) = scene_of(&Mechanism::from_genes(&g)) else {
            continue;
        };
        let model = &scene.model;
        let n = model.dof();
        if !(3..=6).contains(&n) || !model.actuators().is_empty() {
            continue;
        }
        let settings = scene.step_settings();
        let (mut sized, mut generic) = (
            Stepper::new(model, settings.clone()),
            Stepper::new(model, settings),
        );
        let (mut a, mut b) = (scene.initial.clone(), scene.initial.clone());
        sized.start(model, &a);
        generic.start(model, &b);
        for step in 0..300 {
            let one = sized.step(model, &mut a, &actuation).cloned();
            let other = generic.step_generic(model, &mut b, &actuation).cloned();
            match (one, other) {
                (Ok(one), Ok(other)) => {
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(
                        bits(a.q.as_slice()),
                        bits(b.q.as_slice()),
                        "n = {n}, step {step}"
                    );
                    assert_eq!(
                        bits(a.u.as_slice()),
                        bits(b.u.as_slice()),
                        "n = {n}, step {step}"
                    );
                    assert_eq!(
                        format!("{:?}", one.contacts),
                        format!("{:?}", other.contacts),
                        "n = {n}, step {step}"
                    );
                    assert_eq!(
                        format!("{:?}", one.energy),
                        format!("{:?}", other.energy),
                        "n = {n}, step {step}"
                    );
                }
                (Err(one), Err(other)) => {
                    assert_eq!(one.to_string(), other.to_string());
                    break;
                }
                (one, other) => panic!("n = {n}, step {step}: {one:?} vs {other:?}"),
            }
        }
        compared[n] += 1;
    }
    println!("mechanisms compared by n: {compared:?}");
    for n in 3..=6 {
        assert!(
            compared[n] >= 5,
            "only {} generated mechanisms with n = {n}: {compared:?}",
            compared[n]
        );
    }
}
