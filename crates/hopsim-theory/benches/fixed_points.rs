//! Cost of Robbit's fixed-point analysis (docs/physics.md §5.3, docs/analysis.md §9.11): one
//! return-map evaluation, one grid point (multi-start Levenberg–Marquardt and the
//! stability Jacobian), and a 10 × 10 grid on all cores, from which a 150 × 150 grid is
//! extrapolated (× 225).

use criterion::{criterion_group, criterion_main, Criterion};
use hopsim_theory::fixed_points::{
    find_fixed_point, FixedPointGrid, SolverSettings, DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE,
};
use hopsim_theory::grid::NO_PROGRESS;
use hopsim_theory::robbit::{return_map, Control, RobbitParams, SectionState};
use std::hint::black_box;

fn fixed_points(c: &mut Criterion) {
    let p = RobbitParams::default();
    let z = SectionState::from_energy(&p, -0.8, 0.08).unwrap();
    let control = Control {
        torque: 0.25,
        impulse_limit: 0.056,
    };
    c.bench_function("robbit return map (one cycle)", |b| {
        b.iter(|| return_map(black_box(&p), black_box(&z), black_box(&control)).unwrap())
    });
    let settings = SolverSettings::default();
    c.bench_function("robbit fixed point + stability (one grid point)", |b| {
        b.iter(|| {
            find_fixed_point(black_box(&p), black_box(&z), &settings)
                .unwrap()
                .unwrap()
        })
    });
    let mut group = c.benchmark_group("robbit grid");
    group.sample_size(10);
    let grid = FixedPointGrid::new(p, DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE, 10, 10);
    group.bench_function("10 x 10 default grid, all cores", |b| {
        b.iter(|| grid.run(NO_PROGRESS).unwrap())
    });
    group.finish();
}

criterion_group!(benches, fixed_points);
criterion_main!(benches);
