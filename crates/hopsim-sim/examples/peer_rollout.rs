//! hopsim's side of the rollout peer benchmark (`benches/peers/run.sh`): runs a scene
//! (default `scenes/robbit.toml`: 20 s = 100 000 steps of 2e-4 s) step by step through
//! [`Simulation`] with no observers (controller, stepper and events; no recording, no run
//! summary) and prints the median speed in steps per second of wall time:
//!
//! ```text
//! peer_rollout [--runs R] [--batch N --threads T] [--set KEY=VALUE]... [SCENE.toml | MODEL.xml]
//! ```
//!
//! With `--batch N`, `N` copies stepped together by [`hopsim_sim::Batch`] on `T` threads
//! (default 1): the speed is then the copies' steps together per second.
//!
//! One untimed warm-up run, then `R` timed runs (default 5). Prints one JSON line:
//! `{"scene", "steps", "runs", "median_steps_per_s", "steps_per_s": [...], "hops", "distance_m"}`
//! (hops and distance of the centre of mass along x, for comparing the trajectories).

use hopsim_scene::{Override, Scene};
use hopsim_sim::Simulation;
use std::hint::black_box;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn usage() -> ExitCode {
    eprintln!(
        "usage: peer_rollout [--runs R] [--batch N --threads T] [--set KEY=VALUE]... \
         [SCENE.toml | MODEL.xml]"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut runs: usize = 5;
    let (mut batch, mut threads): (usize, usize) = (0, 1);
    let mut overrides: Vec<Override> = Vec::new();
    let mut path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robbit.toml");
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--runs" => match args.next().and_then(|v| v.parse().ok()) {
                Some(r) if r > 0 => runs = r,
                _ => return usage(),
            },
            "--batch" => match args.next().and_then(|v| v.parse().ok()) {
                Some(n) if n > 0 => batch = n,
                _ => return usage(),
            },
            "--threads" => match args.next().and_then(|v| v.parse().ok()) {
                Some(t) if t > 0 => threads = t,
                _ => return usage(),
            },
            "--set" => match args.next().and_then(|v| v.parse().ok()) {
                Some(o) => overrides.push(o),
                None => return usage(),
            },
            "-h" | "--help" => return usage(),
            s if s.starts_with('-') => return usage(),
            _ => path = arg.into(),
        }
    }
    let scene = match hopsim_scene::load(&path, &overrides) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let steps = (scene.settings.duration / scene.settings.dt).round() as u64;
    let copies = batch.max(1) as f64;
    let simulate = |scene: &Scene, steps: u64| {
        if batch == 0 {
            simulate(scene, steps)
        } else {
            simulate_batch(scene, steps, batch, threads)
        }
    };
    let (hops, distance) = match simulate(&scene, steps) {
        Ok(outcome) => outcome,
        Err(e) => {
            eprintln!("error: {}: run failed: {e}", path.display());
            return ExitCode::FAILURE;
        }
    };
    let mut rates: Vec<f64> = Vec::with_capacity(runs);
    for _ in 0..runs {
        let start = Instant::now();
        let outcome = simulate(black_box(&scene), steps).expect("the warm-up run passed");
        let wall = start.elapsed().as_secs_f64();
        black_box(outcome);
        rates.push(copies * steps as f64 / wall);
    }
    let mut sorted = rates.clone();
    sorted.sort_by(f64::total_cmp);
    let mid = sorted.len() / 2;
    let median = if sorted.len() % 2 == 1 {
        sorted[mid]
    } else {
        0.5 * (sorted[mid - 1] + sorted[mid])
    };
    let list: Vec<String> = rates.iter().map(|r| format!("{r:.0}")).collect();
    println!(
        "{{\"scene\": \"{}\", \"steps\": {}, \"runs\": {runs}, \"median_steps_per_s\": {median:.0}, \
         \"steps_per_s\": [{}], \"hops\": {}, \"distance_m\": {:.4}}}",
        path.display(),
        steps,
        list.join(", "),
        hops,
        distance
    );
    ExitCode::SUCCESS
}

/// `copies` copies of the scene stepped `steps` steps together on `threads` threads; the
/// hops and displacement of the first copy.
fn simulate_batch(
    scene: &Scene,
    steps: u64,
    copies: usize,
    threads: usize,
) -> Result<(u64, f64), Box<dyn std::error::Error>> {
    let mut batch = hopsim_sim::Batch::new(scene, copies, threads)?;
    let x0 = batch.q()[0];
    batch.step(steps as usize);
    if let Some(i) = batch.done().iter().position(|&d| d) {
        return Err(format!("copy {i} failed: {:?}", batch.error(i)).into());
    }
    let first = batch.simulation(0).ok_or("no copy 0")?;
    Ok((first.hops(), batch.q()[0] - x0))
}

/// Runs `steps` steps from the scene's initial state with no observer; returns the number
/// of hops and the displacement of the centre of mass along x.
fn simulate(scene: &Scene, steps: u64) -> Result<(u64, f64), Box<dyn std::error::Error>> {
    let mut sim = Simulation::new(scene);
    // Nobody reads the energies: no energy account.
    sim.set_ledger(false);
    sim.start(&mut ())?;
    let x0 = sim.state().q[0];
    for _ in 0..steps {
        sim.step(&mut ())?;
    }
    Ok((sim.hops(), sim.state().q[0] - x0))
}
