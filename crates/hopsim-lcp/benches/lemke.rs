//! Lemke on contact LCPs of the form in docs/physics.md §4 (μ = 1): the exact 6×6 two-contact
//! Robbit case, and rows of eccentric discs giving sizes 3, 6, 12, 24 and 48; and the warm
//! start (`solve_warm` from the problem's own basis) at sizes 3 and 6.
//! Reference point (issue 2): Siconos' C lexicographic Lemke, ~380 ns on the Robbit case.

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hopsim_lcp::{LcpStatus, LemkeSolver, SolveMethod, WarmStart};
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

/// `solve_warm` of `(m, q)` with the basis of its own answer remembered: the warm path
/// alone (basis solve and certificate), as in a time step of a lasting contact.
fn bench_warm(c: &mut Criterion, name: &str, m: &DMatrix<f64>, q: &DVector<f64>) {
    let mut solver = LemkeSolver::default();
    let mut warm = WarmStart::with_capacity(q.len());
    solver
        .solve_warm(m.as_view(), q.as_view(), &mut warm)
        .unwrap();
    let sol = solver
        .solve_warm(m.as_view(), q.as_view(), &mut warm)
        .unwrap();
    assert_eq!(
        (sol.status, sol.method),
        (LcpStatus::Solved, SolveMethod::WarmStart),
        "{name}: the second solve must be warm"
    );
    let basic = warm.basis().map_or(0, |b| b.iter().filter(|&&b| b).count());
    eprintln!("{name}: n = {}, {basic} basic z", q.len());
    c.bench_function(name, |b| {
        b.iter(|| {
            let sol = solver
                .solve_warm(black_box(m.as_view()), black_box(q.as_view()), &mut warm)
                .unwrap();
            black_box(sol.z[0]);
        })
    });
}

fn warm(c: &mut Criterion) {
    let mut rng = common::Rng(0x5eed_0000 + 3);
    let (m, q) = common::disc_row(&mut rng, 1, true, Some(1.0));
    bench_warm(c, "warm_contact_3x3", &m, &q);
    let mut rng = common::Rng(0x5eed_0000 + 6);
    let (m, q) = common::disc_row(&mut rng, 1, false, Some(1.0));
    bench_warm(c, "warm_contact_6x6", &m, &q);
}

criterion_group!(benches, lemke, warm);
criterion_main!(benches);
