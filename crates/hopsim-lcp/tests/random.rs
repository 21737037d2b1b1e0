//! Property tests: random P-matrix LCPs against brute-force enumeration, frictional contact
//! LCPs of docs/physics.md §4, and random (often degenerate or unsolvable) small LCPs whose
//! reported status must be the truth.

mod common;

use hopsim_lcp::{LcpSolution, LcpStatus, LemkeSolver};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// Independent check (plain nalgebra) that `sol` solves the LCP within `tol`.
fn check_solution(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    sol: &LcpSolution,
    tol: f64,
) -> Result<(), TestCaseError> {
    prop_assert_eq!(sol.status, LcpStatus::Solved);
    prop_assert!(sol.certificate.holds(), "{:?}", sol.certificate);
    let w = m * &sol.z + q;
    for i in 0..q.len() {
        prop_assert!(sol.z[i] >= -tol, "z[{}] = {}", i, sol.z[i]);
        prop_assert!(w[i] >= -tol, "w[{}] = {}", i, w[i]);
        prop_assert!(
            (sol.z[i] * w[i]).abs() <= tol,
            "z·w at {} = {}",
            i,
            sol.z[i] * w[i]
        );
    }
    Ok(())
}

fn matrix(n: usize, values: &[f64]) -> DMatrix<f64> {
    DMatrix::from_row_slice(n, n, &values[..n * n])
}

/// `(n, A entries, q entries)` with entries in [-1, 1].
fn raw(max_n: usize) -> impl Strategy<Value = (usize, Vec<f64>, Vec<f64>)> {
    (1..=max_n).prop_flat_map(move |n| {
        (
            Just(n),
            prop::collection::vec(-1.0..1.0f64, n * n),
            prop::collection::vec(-1.0..1.0f64, n),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// SPD `M = A Aᵀ + δ I` is a P-matrix: exactly one solution, which Lemke must find.
    #[test]
    fn spd_p_matrix_matches_brute_force((n, a, q) in raw(8), delta in 1e-3..1.0f64) {
        let a = matrix(n, &a);
        let m = &a * a.transpose() + DMatrix::identity(n, n) * delta;
        let q = DVector::from_vec(q);
        let sols = common::brute_force(&m, &q, 1e-9);
        prop_assert_eq!(sols.len(), 1, "a P-matrix LCP has a unique solution");
        let sol = common::solve_with(common::no_fallback(), &m, &q);
        check_solution(&m, &q, &sol, 1e-9)?;
        prop_assert!((&sol.z - &sols[0]).amax() <= 1e-7 * (1.0 + sols[0].amax()), "z = {}, brute force {}", sol.z, sols[0]);
    }

    /// Non-symmetric, strictly row-diagonally-dominant with positive diagonal: a P-matrix.
    #[test]
    fn diagonally_dominant_p_matrix_matches_brute_force((n, a, q) in raw(8), margin in 0.05..2.0f64) {
        let mut m = matrix(n, &a);
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[(i, j)].abs()).sum();
            m[(i, i)] = off + margin;
        }
        let q = DVector::from_vec(q);
        let sols = common::brute_force(&m, &q, 1e-9);
        prop_assert_eq!(sols.len(), 1);
        let sol = common::solve_with(common::no_fallback(), &m, &q);
        check_solution(&m, &q, &sol, 1e-9)?;
        prop_assert!((&sol.z - &sols[0]).amax() <= 1e-7 * (1.0 + sols[0].amax()));
    }

    /// Small integer LCPs, often degenerate (ties, zero rows, repeated rows) or unsolvable:
    /// a reported solution must check out, and when brute force finds a solution the
    /// solver (with its fallbacks) must not report failure.
    #[test]
    fn status_tells_the_truth_on_small_integer_lcps(
        (n, a, q) in (1..=5usize).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-2i32..=2, n * n),
            prop::collection::vec(-2i32..=2, n),
        ))
    ) {
        let m = DMatrix::from_row_iterator(n, n, a.iter().map(|&v| f64::from(v)));
        let q = DVector::from_iterator(n, q.iter().map(|&v| f64::from(v)));
        let sol = LemkeSolver::default().solve(m.as_view(), q.as_view()).unwrap().clone();
        let exists = !common::brute_force(&m, &q, 1e-9).is_empty();
        if sol.status == LcpStatus::Solved {
            check_solution(&m, &q, &sol, 1e-9)?;
        } else {
            prop_assert!(!exists, "solver reported {:?} but a solution exists", sol.status);
            prop_assert!(!sol.certificate.holds());
        }
        if exists {
            prop_assert_eq!(sol.status, LcpStatus::Solved);
        }
    }

    /// Frictional contact LCPs (docs/physics.md §4) with one to four contacts between eccentric
    /// discs, the ground, each other and a wall; random masses, shapes, states and μ.
    #[test]
    fn frictional_contact_lcps_solve_with_a_valid_certificate(seed in any::<u64>(), contacts in 1usize..=4) {
        let mut rng = common::Rng(seed | 1);
        // 1: disc on the ground; 2: disc in a corner; 3: two discs on the ground touching;
        // 4: the same against a wall.
        let (discs, ground_only) = [(1, true), (1, false), (2, true), (2, false)][contacts - 1];
        let (m, q) = common::disc_row(&mut rng, discs, ground_only, None);
        prop_assert_eq!(q.len(), 3 * contacts);
        let sol = LemkeSolver::default().solve(m.as_view(), q.as_view()).unwrap().clone();
        check_solution(&m, &q, &sol, 1e-9)?;
    }
}

#[test]
fn robbit_two_contact_lcp_solves_with_lemke_alone() {
    let (m, q) = common::robbit_two_contacts();
    let sol = common::solve_with(common::no_fallback(), &m, &q);
    assert_eq!(sol.status, LcpStatus::Solved);
    assert!(sol.certificate.holds());
    // The step corner takes the impact; the ground contact opens (Λ_N1 = 0, ξ_N1 > 0).
    assert_eq!(sol.z[0], 0.0);
    assert!(sol.z[1] > 0.0 && sol.w[0] > 0.0);
    let w = &m * &sol.z + &q;
    assert!((&w - &sol.w).amax() < 1e-12);
}

/// Larger contact problems (up to 24 contacts, 72×72) from many random states: Lemke
/// with the fallback covering vectors must certify every one.
#[test]
fn many_contact_rows_solve() {
    let mut rng = common::Rng(2024);
    let mut solver = LemkeSolver::default();
    for discs in [1, 2, 3, 4, 6, 8, 12] {
        for _ in 0..150 {
            let (m, q) = common::disc_row(&mut rng, discs, false, None);
            let sol = solver.solve(m.as_view(), q.as_view()).unwrap();
            assert_eq!(sol.status, LcpStatus::Solved, "{discs} discs");
            let w = &m * &sol.z + &q;
            assert!(w.min() >= -1e-9 && sol.z.min() >= -1e-9);
            assert!(sol.z.dot(&w).abs() <= 1e-9 * (1.0 + q.amax()));
        }
    }
}
