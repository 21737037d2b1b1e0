//! Lemke on contact LCPs of the form in docs/physics.md §4 (μ = 1): the exact 6×6 two-contact
//! Robbit case, and rows of eccentric discs giving sizes 3, 6, 12, 24 and 48.
//! Reference point (issue 2): Siconos' C lexicographic Lemke, ~380 ns on the Robbit case.

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hopsim_lcp::{LcpStatus, LemkeSolver};
use nalgebra::{DMatrix, DVector};
use std::hint::black_box;

fn bench_case(
    c: &mut Criterion,
    group: &str,
    id: Option<usize>,
    m: &DMatrix<f64>,
    q: &DVector<f64>,
) {
    let mut solver = LemkeSolver::default();
    let sol = solver.solve(m.as_view(), q.as_view()).unwrap();
    assert_eq!(
        sol.status,
        LcpStatus::Solved,
        "{group}: benchmark problem must solve"
    );
    eprintln!(
        "{group}{}: n = {}, {} pivots, method {}",
        id.map(|i| format!("/{i}")).unwrap_or_default(),
        q.len(),
        sol.pivots,
        sol.method
    );
    let mut run = |b: &mut criterion::Bencher| {
        b.iter(|| {
            let sol = solver
                .solve(black_box(m.as_view()), black_box(q.as_view()))
                .unwrap();
            black_box(sol.z[0]);
        })
    };
    match id {
        Some(i) => {
            let mut g = c.benchmark_group(group);
            g.bench_function(BenchmarkId::from_parameter(i), &mut run);
            g.finish();
        }
        None => {
            c.bench_function(group, &mut run);
        }
    }
}

fn lemke(c: &mut Criterion) {
    let (m, q) = common::robbit_two_contacts();
    bench_case(c, "lemke_robbit_6x6", None, &m, &q);
    // Contact rows: 1 disc on the ground (3), 1 disc against a wall (6), then 2, 4, 8 discs.
    for (n, discs, ground_only) in [
        (3, 1, true),
        (6, 1, false),
        (12, 2, false),
        (24, 4, false),
        (48, 8, false),
    ] {
        let mut rng = common::Rng(0x5eed_0000 + n as u64);
        let (m, q) = common::disc_row(&mut rng, discs, ground_only, Some(1.0));
        assert_eq!(q.len(), n);
        bench_case(c, "lemke_contact", Some(n), &m, &q);
    }
}

criterion_group!(benches, lemke);
criterion_main!(benches);
