//! A batch of 256 Robbits (`scenes/robbit.toml`, its controller hopping) stepped together
//! on 1 and 2 threads: one batch step (256 simulation steps), and 100 steps in one call
//! (the threads meet once per call).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hopsim_sim::Batch;
use std::path::Path;

const COPIES: usize = 256;

fn batch(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robbit.toml");
    let scene = hopsim_scene::load(&path, &[]).expect("scenes/robbit.toml");
    let mut group = c.benchmark_group("batch");
    for (threads, steps) in [(1, 1), (2, 1), (1, 100), (2, 100)] {
        group.throughput(Throughput::Elements((COPIES * steps) as u64));
        let mut batch = Batch::new(&scene, COPIES, threads).expect("a batch");
        // Starts spread over a hop cycle, so that copies are in flight and in stance.
        for i in 0..COPIES {
            let mut state = scene.initial.clone();
            state.u[3] = 40.0 * i as f64 / COPIES as f64;
            batch.set_state(i, state).expect("a standing start");
        }
        let name = match steps {
            1 => format!("256_robbits_{threads}_threads"),
            _ => format!("256_robbits_{steps}_steps_{threads}_threads"),
        };
        group.bench_function(name, |b| b.iter(|| batch.step(steps)));
    }
    group.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
