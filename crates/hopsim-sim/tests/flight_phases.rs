//! Flight phases (docs/physics.md §6): a hop counts only when no contact with the world
//! carries load and every shape clears it, so a dropped robot's fall is no hop and a body
//! resting on a fixed body is on the ground.

use hopsim_scene::Scene;
use hopsim_sim::{run, Simulation};
use std::path::Path;

fn scene(text: &str) -> Scene {
    hopsim_scene::parse(text, Path::new("flight.toml"), &[]).unwrap()
}

const BOX: &str = r#"
[simulation]
duration = 1.0
dt = 1e-3

[[bodies]]
name = "box"
mass = 1.0
inertia = 0.01

[[shapes]]
body = "box"
type = "box"
half_width = 0.1
half_height = 0.1
"#;

/// A box dropped from 0.5 m lands once and stays: no hop, one touchdown.
#[test]
fn a_dropped_box_does_not_hop() {
    let s = scene(&format!("{BOX}\n[initial]\nq = [0.0, 0.6, 0.0]\n"));
    let sim = Simulation::new(&s);
    assert!(!sim.in_contact(), "a start in the air touches nothing");
    let summary = run(&s, &mut ()).unwrap();
    assert_eq!(summary.hops, 0);
}

/// A box thrown up from the ground hops once.
#[test]
fn a_box_thrown_up_hops_once() {
    let s = scene(&format!(
        "{BOX}\n[initial]\nq = [0.0, 0.1, 0.0]\nu = [0.0, 2.0, 0.0]\n"
    ));
    assert_eq!(run(&s, &mut ()).unwrap().hops, 1);
}

/// A box resting on a fixed table (a body–body contact with a fixed body) for a second is
/// loaded in every step: no hop, and the smallest gap is the table's.
#[test]
fn a_box_on_a_fixed_table_is_on_the_ground() {
    let s = scene(
        r#"
[simulation]
duration = 1.0
dt = 1e-3

[[bodies]]
name = "table"
base = "fixed"
position = [0.0, 0.5]

[[bodies]]
name = "box"
base = "floating"
mass = 1.0
inertia = 0.01

[[shapes]]
body = "table"
type = "box"
half_width = 0.5
half_height = 0.1

[[shapes]]
body = "box"
type = "box"
half_width = 0.1
half_height = 0.1

[body_contacts]
all = true

[initial]
q = [0.0, 0.7, 0.0]
"#,
    );
    let mut sim = Simulation::new(&s);
    assert!(sim.in_contact());
    for _ in 0..1000 {
        sim.step(&mut ()).unwrap();
        assert!(sim.in_contact(), "t = {}", sim.state().t);
        assert!(sim.stepper().record().min_gap.abs() < 1e-6);
    }
    assert_eq!(sim.hops(), 0);
}
