//! Whole runs through the run loop (controller, stepper, events, summary) and a parallel
//! sweep, for the figure: 900 runs of 20 s of Robbit (the thesis' 30 × 30 grid)
//! in under 2 minutes on 2 cores. `robbit_run_20s` times one such run; the sweep
//! benchmark runs a 4 × 4 grid of 20 s runs on all cores.

use criterion::{criterion_group, criterion_main, Criterion};
use hopsim_sim::run;
use hopsim_studies::sweep::{grid_jobs, sweep, GridAxis, NO_PROGRESS};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

fn robbit_runs(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robbit.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = hopsim_scene::parse(&text, &path, &[]).unwrap();
    let mut group = c.benchmark_group("robbit");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    group.bench_function("run_20s", |b| {
        b.iter(|| black_box(run(&scene, &mut ()).unwrap().hops))
    });
    let axes: Vec<GridAxis> = [
        "controller.torque=0.1:0.3:4",
        "controller.impulse_limit=0.04:0.07:4",
    ]
    .iter()
    .map(|a| a.parse().unwrap())
    .collect();
    let jobs = grid_jobs(&axes);
    group.bench_function("sweep_16_runs_of_20s", |b| {
        b.iter(|| {
            let points = sweep(&path, &text, &[], &jobs, |s| run(s, &mut ()), NO_PROGRESS);
            assert!(points.iter().all(|p| p.result.is_ok()));
            black_box(points.len())
        })
    });
    group.finish();
}

criterion_group!(benches, robbit_runs);
criterion_main!(benches);
