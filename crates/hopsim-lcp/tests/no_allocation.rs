//! Once its buffers have grown, a `LemkeSolver` solve allocates nothing: not on the hot
//! path, not in the fallbacks, not when the problem size changes.

mod common;

use hopsim_lcp::{LcpStatus, LemkeSolver};
use nalgebra::{dmatrix, dvector};

#[path = "../../../tests/support/counting_allocator.rs"]
mod counting_allocator;
use counting_allocator::allocated;

#[test]
fn repeated_solves_of_varying_size_do_not_allocate() {
    let mut rng = common::Rng(11);
    let mut problems = vec![common::robbit_two_contacts()];
    for discs in [1, 2, 4, 8, 1, 2] {
        problems.push(common::disc_row(&mut rng, discs, false, None));
    }
    problems.push((dmatrix![-1.0], dvector![-1.0])); // ray + all fallbacks
    problems.push((dmatrix![0.0, 1.0; 2.0, 0.0], dvector![0.0, -3.0])); // enumeration
    problems.push((dmatrix![1.0, 2.0; 0.0, 1.0], dvector![1.0, 1.0])); // trivial

    let mut solver = LemkeSolver::default();
    for (m, q) in &problems {
        solver.solve(m.as_view(), q.as_view()).unwrap();
    }
    let before = allocated();
    let mut solved = 0;
    for _ in 0..20 {
        for (m, q) in &problems {
            let sol = solver.solve(m.as_view(), q.as_view()).unwrap();
            solved += usize::from(sol.status == LcpStatus::Solved);
        }
    }
    let after = allocated();
    assert_eq!(
        after - before,
        0,
        "allocations during {} solves",
        20 * problems.len()
    );
    assert_eq!(
        solved,
        20 * (problems.len() - 1),
        "all but the infeasible one solve"
    );
}

/// The warm path neither: warm answers and fallbacks to Lemke's method, on the sizes
/// compiled on their own and the generic one, with the basis changing size.
#[test]
fn repeated_warm_solves_of_varying_size_do_not_allocate() {
    let mut rng = common::Rng(5);
    let mut problems = Vec::new();
    for discs in [1, 2, 4, 1, 8] {
        problems.push(common::disc_row(&mut rng, discs, false, None));
    }
    // An empty basis of 12 rows, then a landing.
    let m = nalgebra::DMatrix::identity(12, 12);
    problems.push((m.clone(), nalgebra::DVector::from_element(12, 1.0)));
    problems.push((m, nalgebra::DVector::from_fn(12, |i, _| i as f64 - 5.5)));
    let largest = problems.iter().map(|(_, q)| q.len()).max().unwrap();
    let mut solver = LemkeSolver::default();
    solver.reserve(largest);
    let mut warm = hopsim_lcp::WarmStart::with_capacity(largest);
    // (warm answers, Lemke answers): counted without allocating.
    let run = |solver: &mut LemkeSolver, warm: &mut hopsim_lcp::WarmStart| {
        let mut counts = (0, 0);
        for (m, q) in &problems {
            for _ in 0..2 {
                let sol = solver.solve_warm(m.as_view(), q.as_view(), warm).unwrap();
                match sol.method {
                    hopsim_lcp::SolveMethod::WarmStart => counts.0 += 1,
                    hopsim_lcp::SolveMethod::Lemke => counts.1 += 1,
                    _ => {}
                }
            }
        }
        counts
    };
    run(&mut solver, &mut warm);
    let before = allocated();
    let counts = run(&mut solver, &mut warm);
    assert_eq!(allocated() - before, 0);
    assert!(counts.0 > 0 && counts.1 > 0, "{counts:?}");
}
