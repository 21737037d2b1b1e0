//! Cost of the thesis' Figure 5.7 study (docs/analysis.md §9.12): one fixed point run from
//! rest for 20 s (the unit of work, 898 of them on the default 30 × 30 grid), and a 6 × 6
//! grid solved and every fixed point run on all cores, from which the 30 × 30 grid is
//! extrapolated (× 25).

use criterion::{criterion_group, criterion_main, Criterion};
use hopsim_studies::fixed_points::{fixed_points, FixedPointsParams, Sections};
use hopsim_studies::progress::Silent;
use hopsim_studies::robbit_gait::{rest_state, robbit_scene, StepperSettings};
use hopsim_studies::run_summary::run_scene;
use hopsim_theory::fixed_points::{DEFAULT_ANGLE_RANGE, DEFAULT_ENERGY_RANGE};
use hopsim_theory::robbit::{Control, RobbitParams};
use std::hint::black_box;

fn fixed_point_gaits(c: &mut Criterion) {
    let p = RobbitParams::default();
    let settings = StepperSettings::default();
    let mut group = c.benchmark_group("figure 5.7");
    group.sample_size(10);
    // β* of (−0.8 rad, 0.08 J), locked flywheel at touchdown (docs/analysis.md §10.3).
    let control = Control {
        torque: 0.2508,
        impulse_limit: 0.05630,
    };
    group.bench_function("one fixed point from rest, 20 s", |b| {
        b.iter(|| {
            let scene = robbit_scene(&p, &control, &settings, &rest_state(&p)).unwrap();
            run_scene(black_box(&scene), &mut ()).unwrap()
        })
    });
    let params = FixedPointsParams {
        robot: p,
        sections: Sections::Grid {
            angle_range_rad: DEFAULT_ANGLE_RANGE,
            energy_range_j: DEFAULT_ENERGY_RANGE,
            angle_points: 6,
            energy_points: 6,
        },
        simulation: None,
        gaits: Some(settings),
    };
    group.bench_function("6 x 6 grid, every fixed point from rest, all cores", |b| {
        b.iter(|| fixed_points(black_box(&params), &Silent).unwrap())
    });
    group.finish();
}

criterion_group!(benches, fixed_point_gaits);
criterion_main!(benches);
