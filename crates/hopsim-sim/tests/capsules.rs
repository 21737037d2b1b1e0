//! Capsules in the step (docs/physics.md §2.1, §7.3): a capsule dropped tilted onto flat
//! ground comes to rest lying on both end caps, its centre at its radius above the ground,
//! the caps' percussions carrying its weight; a capsule dropped onto a capsule fixed to
//! the world comes to rest on it, its axis the two radii above the other's, the pair's
//! percussions carrying its weight. Moreau's midpoint scheme closes a contact at the
//! step's midpoint and does not push positions back (§4.1): an impact leaves the shape at
//! most one step's travel `v Δt` inside, and resting it sinks no further.

mod common;

use common::sampled;
use hopsim_scene::Scene;
use std::path::Path;

const G: f64 = 9.81;
const DT: f64 = 1e-3;

fn scene(text: &str) -> Scene {
    hopsim_scene::parse(text, Path::new("capsules.toml"), &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// What a step leaves: `q`, `u`, the smallest gap with the world, and the normal
/// percussions of the terrain and of the body–body contacts.
struct Sample {
    q: Vec<f64>,
    u: Vec<f64>,
    gap: f64,
    terrain: Vec<f64>,
    pairs: Vec<f64>,
}

fn run(scene: &Scene) -> Vec<Sample> {
    sampled(scene, |v| Sample {
        q: v.state.q.as_slice().to_vec(),
        u: v.state.u.as_slice().to_vec(),
        gap: v.record.min_gap,
        terrain: v.record.contacts.iter().map(|c| c.impulse_normal).collect(),
        pairs: v
            .record
            .pair_contacts
            .iter()
            .map(|c| c.impulse_normal)
            .collect(),
    })
}

/// Checks the rest at the end: each end of the segment (`half` from the centre) at the
/// height `y_rest` less at most one step's travel of the capsule's fastest point, still,
/// the contacts carrying the weight `m g Δt` per step, and no sinking over the last
/// second.
fn check_rest(
    samples: &[Sample],
    y_rest: f64,
    half: f64,
    radius: f64,
    mass: f64,
    impulses: fn(&Sample) -> &[f64],
) {
    let end = samples.last().unwrap();
    let travel = samples
        .iter()
        .map(|s| s.u[0].hypot(s.u[1]) + s.u[2].abs() * (half + radius))
        .fold(0.0, f64::max)
        * DT;
    for side in [-1.0, 1.0] {
        let sunk = y_rest - (end.q[1] + side * half * end.q[2].sin());
        assert!(
            (-1e-12..=travel).contains(&sunk),
            "an end sank {sunk:e} (q = {:?}), one step's travel {travel:e}",
            end.q
        );
    }
    assert!(end.q[2].cos() > 0.0, "turned over: phi = {}", end.q[2]);
    assert!(end.u.iter().all(|u| u.abs() < 1e-9), "u = {:?}", end.u);
    let second_ago = &samples[samples.len() - 1 - (1.0 / DT) as usize];
    assert!(
        (second_ago.gap - end.gap).abs() < 1e-12,
        "sank from {} to {}",
        second_ago.gap,
        end.gap
    );
    assert!(
        samples.iter().all(|s| s.gap > -travel),
        "deeper than one step's travel"
    );
    // Both ends carry it, together its weight per step.
    let carried = impulses(end);
    assert_eq!(carried.len(), 2, "{carried:?}");
    let total: f64 = carried.iter().sum();
    let weight = mass * G * DT;
    assert!(
        (total - weight).abs() < 1e-9 * weight,
        "Σ Λ_N = {total} vs m g Δt = {weight}"
    );
    assert!(carried.iter().all(|l| *l > 0.1 * weight), "{carried:?}");
}

#[test]
fn a_capsule_dropped_tilted_rests_on_both_caps() {
    let (mass, radius) = (2.0, 0.05);
    let scene = scene(&format!(
        r#"
[simulation]
duration = 3.0
dt = {DT}
[environment]
friction = 0.8
[[bodies]]
name = "rod"
mass = {mass}
inertia = 0.02
[[shapes]]
body = "rod"
name = "rod"
type = "capsule"
from = [-0.3, 0.0]
to = [0.3, 0.0]
radius = {radius}
[initial]
q = [0.0, 0.4, 0.5]
"#
    ));
    let samples = run(&scene);
    check_rest(&samples, radius, 0.3, radius, mass, |s| &s.terrain);
    assert!(samples.last().unwrap().pairs.is_empty());
}

#[test]
fn a_capsule_dropped_on_a_fixed_capsule_rests_on_it() {
    let (mass, r_low, r_high) = (1.5, 0.06, 0.04);
    let scene = scene(&format!(
        r#"
[simulation]
duration = 2.0
dt = {DT}
[environment]
friction = 0.8
[[bodies]]
name = "beam"
base = "fixed"
position = [0.0, 0.5]
[[bodies]]
name = "rod"
base = "floating"
mass = {mass}
inertia = 0.01
[[shapes]]
body = "beam"
name = "beam"
type = "capsule"
from = [-0.5, 0.0]
to = [0.5, 0.0]
radius = {r_low}
[[shapes]]
body = "rod"
name = "rod"
type = "capsule"
from = [-0.2, 0.0]
to = [0.2, 0.0]
radius = {r_high}
[body_contacts]
all = true
[initial]
q = [0.1, 0.7, 0.2]
"#
    ));
    let samples = run(&scene);
    check_rest(&samples, 0.5 + r_low + r_high, 0.2, r_high, mass, |s| {
        &s.pairs
    });
    assert!(samples.last().unwrap().terrain.is_empty());
}
