//! Lemke solver: small exact cases, statuses, fallbacks, degenerate and unsolvable
//! problems, Murty's exponential example, input validation, workspace reuse.

mod common;

use hopsim_lcp::{
    solve_lcp, LcpInputError, LcpSolution, LcpStatus, LemkeOptions, LemkeSolver, SolveMethod,
};
use nalgebra::{dmatrix, dvector, DMatrix, DVector};

/// Independent check of a claimed solution (plain nalgebra, not the crate's certificate).
fn assert_solves(m: &DMatrix<f64>, q: &DVector<f64>, sol: &LcpSolution, tol: f64) {
    assert_eq!(sol.status, LcpStatus::Solved, "{sol:?}");
    assert!(sol.certificate.holds(), "{:?}", sol.certificate);
    let w = m * &sol.z + q;
    for i in 0..q.len() {
        assert!(sol.z[i] >= -tol, "z[{i}] = {}", sol.z[i]);
        assert!(w[i] >= -tol, "w[{i}] = {}", w[i]);
        assert!(
            (sol.z[i] * w[i]).abs() <= tol,
            "z[{i}]·w[{i}] = {}",
            sol.z[i] * w[i]
        );
        assert!(
            (sol.w[i] - w[i]).abs() <= tol,
            "reported w[{i}] = {}, M z + q = {}",
            sol.w[i],
            w[i]
        );
    }
}

#[test]
fn one_by_one_solvable() {
    let (m, q) = (dmatrix![2.0], dvector![-1.0]);
    let sol = solve_lcp(&m, &q).unwrap();
    assert_solves(&m, &q, &sol, 1e-12);
    assert_eq!(sol.z[0], 0.5);
    assert_eq!(sol.w[0], 0.0);
    assert_eq!(sol.method, SolveMethod::Lemke);
    assert_eq!(sol.pivots, 2, "z0 in, then z1 replaces z0");
}

#[test]
fn one_by_one_unsolvable_is_a_ray_not_a_solution() {
    // w = −z − 1 < 0 for every z ≥ 0: no solution exists, so no fallback can find one.
    let (m, q) = (dmatrix![-1.0], dvector![-1.0]);
    for options in [LemkeOptions::default(), common::no_fallback()] {
        let sol = common::solve_with(options, &m, &q);
        assert_eq!(sol.status, LcpStatus::RayTermination);
        assert!(!sol.certificate.holds());
        assert_eq!(sol.method, SolveMethod::Lemke);
    }
}

#[test]
fn nonnegative_q_is_trivial() {
    let m = dmatrix![-5.0, 1.0; 2.0, -7.0];
    let q = dvector![0.0, 3.0];
    let sol = solve_lcp(&m, &q).unwrap();
    assert_eq!(sol.status, LcpStatus::Solved);
    assert_eq!(sol.method, SolveMethod::Trivial);
    assert_eq!(sol.pivots, 0);
    assert_eq!(sol.z, DVector::zeros(2));
    assert_eq!(sol.w, q);
}

#[test]
fn empty_problem_is_trivial() {
    let sol = solve_lcp(&DMatrix::zeros(0, 0), &DVector::zeros(0)).unwrap();
    assert_eq!(
        (sol.status, sol.method, sol.z.len()),
        (LcpStatus::Solved, SolveMethod::Trivial, 0)
    );
}

#[test]
fn small_spd_problem_matches_the_closed_form() {
    // lcp_deudeu: both constraints active, z = M⁻¹(−q) = (4/3, 7/3).
    let (m, q) = (dmatrix![2.0, 1.0; 1.0, 2.0], dvector![-5.0, -6.0]);
    let sol = solve_lcp(&m, &q).unwrap();
    assert_solves(&m, &q, &sol, 1e-12);
    assert!((sol.z[0] - 4.0 / 3.0).abs() < 1e-14 && (sol.z[1] - 7.0 / 3.0).abs() < 1e-14);
}

#[test]
fn infeasible_problems_report_ray_termination() {
    let cases = [
        // w = −z + q < 0 with q < 0.
        (-DMatrix::<f64>::identity(3, 3), dvector![-1.0, -2.0, -0.5]),
        // w1 = −z2 − 1 < 0 always.
        (dmatrix![0.0, -1.0; 1.0, 0.0], dvector![-1.0, -1.0]),
        // w1 = −z1 − z2 − 1 < 0 always.
        (dmatrix![-1.0, -1.0; 1.0, 1.0], dvector![-1.0, 2.0]),
    ];
    for (m, q) in cases {
        assert!(
            common::brute_force(&m, &q, 1e-12).is_empty(),
            "test problem must be infeasible"
        );
        let sol = solve_lcp(&m, &q).unwrap();
        assert_eq!(sol.status, LcpStatus::RayTermination, "M = {m}, q = {q}");
        assert!(
            !sol.certificate.holds(),
            "a failure's certificate must not hold"
        );
    }
}

#[test]
fn alternate_covering_rescues_a_ray_from_the_default_covering() {
    // A solvable LCP (z = (2, 3)) on which Lemke with d = 1 ends on a ray.
    let (m, q) = (dmatrix![-1.0, 1.0; -1.0, 0.0], dvector![-1.0, 2.0]);
    let plain = common::solve_with(common::no_fallback(), &m, &q);
    assert_eq!(plain.status, LcpStatus::RayTermination);
    let sol = solve_lcp(&m, &q).unwrap();
    assert_solves(&m, &q, &sol, 1e-12);
    assert_eq!(sol.method, SolveMethod::LemkeAlternateCovering);
    assert!((sol.z[0] - 2.0).abs() < 1e-12 && (sol.z[1] - 3.0).abs() < 1e-12);
    assert!(sol.pivots > plain.pivots, "pivots count all Lemke runs");
}

#[test]
fn enumeration_finds_what_lemke_cannot() {
    // z = (1.5, 0) solves it; Lemke ends on a ray with every covering vector tried.
    let (m, q) = (dmatrix![0.0, 1.0; 2.0, 0.0], dvector![0.0, -3.0]);
    let sol = solve_lcp(&m, &q).unwrap();
    assert_solves(&m, &q, &sol, 1e-12);
    assert_eq!(sol.method, SolveMethod::Enumeration);
    let limited = LemkeOptions {
        enumeration_limit: 1,
        ..LemkeOptions::default()
    };
    let sol = common::solve_with(limited, &m, &q);
    assert_eq!(
        sol.status,
        LcpStatus::RayTermination,
        "n above the enumeration limit"
    );
}

/// Murty's example: lower triangular, 1 on the diagonal, 2 below; q = −1; z = e_1.
fn murty(n: usize) -> (DMatrix<f64>, DVector<f64>) {
    let m = DMatrix::from_fn(n, n, |i, j| match i.cmp(&j) {
        std::cmp::Ordering::Equal => 1.0,
        std::cmp::Ordering::Greater => 2.0,
        std::cmp::Ordering::Less => 0.0,
    });
    (m, DVector::from_element(n, -1.0))
}

#[test]
fn murty_exponential_example_takes_two_to_the_n_pivots_and_solves() {
    for n in 8..=12 {
        let (m, q) = murty(n);
        let options = LemkeOptions {
            max_pivots: Some(1 << (n + 1)),
            ..common::no_fallback()
        };
        let sol = common::solve_with(options, &m, &q);
        assert_solves(&m, &q, &sol, 1e-9);
        assert_eq!(sol.pivots, 1 << n, "n = {n}");
        let mut e1 = DVector::zeros(n);
        e1[0] = 1.0;
        assert!((&sol.z - e1).amax() < 1e-9, "n = {n}: z = {}", sol.z);
    }
}

#[test]
fn murty_example_beyond_the_default_pivot_limit_still_solves_by_fallback() {
    let (m, q) = murty(12);
    let plain = common::solve_with(common::no_fallback(), &m, &q);
    assert_eq!(plain.status, LcpStatus::PivotLimit);
    assert_eq!(plain.pivots, 50 * 12 + 100);
    let sol = solve_lcp(&m, &q).unwrap();
    assert_solves(&m, &q, &sol, 1e-9);
    assert_ne!(sol.method, SolveMethod::Lemke);
}

#[test]
fn zero_pivot_limit_reports_pivot_limit() {
    let options = LemkeOptions {
        max_pivots: Some(0),
        ..common::no_fallback()
    };
    let sol = common::solve_with(options, &dmatrix![1.0], &dvector![-1.0]);
    assert_eq!((sol.status, sol.pivots), (LcpStatus::PivotLimit, 0));
}

#[test]
fn degenerate_problems_terminate_with_a_valid_certificate() {
    let cases: Vec<(DMatrix<f64>, DVector<f64>)> = vec![
        // Repeated rows and equal q: every row ties in every ratio test.
        (dmatrix![1.0, 1.0; 1.0, 1.0], dvector![-1.0, -1.0]),
        (
            dmatrix![1.0, 1.0, 1.0; 1.0, 1.0, 1.0; 1.0, 1.0, 1.0],
            dvector![-1.0, -1.0, -1.0],
        ),
        // Zeros in q next to negative entries.
        (
            dmatrix![1.0, 0.0, 1.0; 0.0, 1.0, 1.0; 1.0, 1.0, 2.0],
            dvector![0.0, -1.0, 0.0],
        ),
        (
            dmatrix![2.0, 1.0, 0.0; 1.0, 2.0, 1.0; 0.0, 1.0, 2.0],
            dvector![0.0, 0.0, -1.0],
        ),
        // Identical constraints stacked, PSD but singular.
        (
            dmatrix![1.0, -1.0, 0.0; -1.0, 1.0, 0.0; 1.0, -1.0, 0.0],
            dvector![-1.0, 1.0, -1.0],
        ),
        // All ratios tie at the first pivot (equal q/d), repeated rows in a 5×5.
        (
            DMatrix::from_fn(5, 5, |i, j| {
                if i == j {
                    2.0
                } else if i / 2 == j / 2 {
                    1.0
                } else {
                    0.5
                }
            }),
            DVector::from_element(5, -1.0),
        ),
    ];
    for (i, (m, q)) in cases.iter().enumerate() {
        let sol = solve_lcp(m, q).unwrap();
        assert_solves(m, q, &sol, 1e-9);
        // Without fallbacks: Lemke alone solves all but case 4, whose zero column makes it
        // end on a ray at once (z3 enters with an all-zero column); it must say so.
        let plain = common::solve_with(common::no_fallback(), m, q);
        if i == 4 {
            assert_eq!(plain.status, LcpStatus::RayTermination);
            assert_eq!(sol.method, SolveMethod::LemkeAlternateCovering);
        } else {
            assert_eq!(plain, sol, "case {i}");
            assert_eq!(sol.method, SolveMethod::Lemke);
        }
    }
}

#[test]
fn covering_vector_is_configurable_and_validated() {
    let (m, q) = (dmatrix![2.0, 1.0; 1.0, 2.0], dvector![-5.0, -6.0]);
    let options = LemkeOptions {
        covering: Some(vec![3.0, 0.5]),
        ..LemkeOptions::default()
    };
    let sol = common::solve_with(options, &m, &q);
    assert_solves(&m, &q, &sol, 1e-12);
    for (covering, expected) in [
        (vec![1.0], LcpInputError::CoveringLength { n: 2, len: 1 }),
        (
            vec![1.0, 0.0],
            LcpInputError::CoveringNotPositive {
                index: 1,
                value: 0.0,
            },
        ),
    ] {
        let options = LemkeOptions {
            covering: Some(covering),
            ..LemkeOptions::default()
        };
        let err = LemkeSolver::new(options)
            .solve(m.as_view(), q.as_view())
            .unwrap_err();
        assert_eq!(err, expected);
    }
}

#[test]
fn invalid_input_is_an_error_not_a_panic() {
    let mut solver = LemkeSolver::default();
    let m23 = DMatrix::<f64>::zeros(2, 3);
    let err = solver
        .solve(m23.as_view(), dvector![1.0, 1.0].as_view())
        .unwrap_err();
    assert_eq!(err, LcpInputError::NotSquare { rows: 2, cols: 3 });
    let err = solver
        .solve(
            dmatrix![1.0, 0.0; 0.0, 1.0].as_view(),
            dvector![1.0].as_view(),
        )
        .unwrap_err();
    assert_eq!(err, LcpInputError::SizeMismatch { n: 2, q_len: 1 });
    let err = solver
        .solve(
            dmatrix![1.0, 0.0; f64::NAN, 1.0].as_view(),
            dvector![-1.0, -1.0].as_view(),
        )
        .unwrap_err();
    assert_eq!(
        err,
        LcpInputError::NonFinite {
            what: "M",
            index: 2
        }
    );
    // Checked even when q ≥ 0 would make the problem trivial.
    let err = solver
        .solve(
            dmatrix![1.0, f64::INFINITY; 0.0, 1.0].as_view(),
            dvector![1.0, 1.0].as_view(),
        )
        .unwrap_err();
    assert_eq!(
        err,
        LcpInputError::NonFinite {
            what: "M",
            index: 1
        }
    );
    let err = solver
        .solve(
            dmatrix![1.0, 0.0; 0.0, 1.0].as_view(),
            dvector![-1.0, f64::NEG_INFINITY].as_view(),
        )
        .unwrap_err();
    assert_eq!(
        err,
        LcpInputError::NonFinite {
            what: "q",
            index: 1
        }
    );
    assert!(err.to_string().contains("q entry 1"), "{err}");
    // The solver still works after errors.
    let sol = solver
        .solve(dmatrix![2.0].as_view(), dvector![-1.0].as_view())
        .unwrap();
    assert_eq!(sol.z[0], 0.5);
}

#[test]
fn views_into_larger_matrices_are_solved_like_owned_matrices() {
    // The time-stepper passes the leading block of a larger buffer.
    let mut big = DMatrix::from_element(5, 5, 99.0);
    big.view_mut((0, 0), (2, 2))
        .copy_from(&dmatrix![2.0, 1.0; 1.0, 2.0]);
    let qbig = dvector![-5.0, -6.0, 42.0];
    let mut solver = LemkeSolver::default();
    let sol = solver
        .solve(big.view((0, 0), (2, 2)), qbig.rows(0, 2))
        .unwrap()
        .clone();
    let own = solve_lcp(&dmatrix![2.0, 1.0; 1.0, 2.0], &dvector![-5.0, -6.0]).unwrap();
    assert_eq!(sol, own);
}

#[test]
fn one_solver_reused_across_sizes_matches_fresh_solvers() {
    let mut rng = common::Rng(7);
    let mut problems = Vec::new();
    problems.push(common::robbit_two_contacts());
    for discs in [1, 2, 4, 1, 8, 2] {
        problems.push(common::disc_row(&mut rng, discs, false, None));
    }
    problems.push(murty(6));
    problems.push((dmatrix![-1.0], dvector![-1.0]));
    problems.push((dmatrix![0.0, 1.0; 2.0, 0.0], dvector![0.0, -3.0]));
    problems.push(common::robbit_two_contacts());
    let mut reused = LemkeSolver::default();
    for (m, q) in &problems {
        let again = reused.solve(m.as_view(), q.as_view()).unwrap().clone();
        let fresh = LemkeSolver::default()
            .solve(m.as_view(), q.as_view())
            .unwrap()
            .clone();
        // Bit-identical, including the failure iterates.
        assert_eq!(again, fresh, "n = {}", q.len());
        assert_eq!(reused.solution(), &fresh);
    }
}

#[test]
fn covering_vector_survives_fallbacks_and_follows_option_changes() {
    // The configured covering vector is written once per size and options change: a
    // fallback's alternate coverings must not leak into the next solve of the same size,
    // and `set_options` must take effect at the same size.
    let ray = (dmatrix![-1.0, 1.0; -1.0, 0.0], dvector![-1.0, 2.0]); // alternate covering
    let spd = (dmatrix![2.0, 1.0; 1.0, 3.0], dvector![-1.0, -1.0]);
    let mut reused = LemkeSolver::default();
    for (m, q) in [&ray, &spd, &ray, &spd] {
        let again = reused.solve(m.as_view(), q.as_view()).unwrap().clone();
        let fresh = common::solve_with(LemkeOptions::default(), m, q);
        assert_eq!(again, fresh);
    }
    for covering in [vec![3.0, 0.5], vec![0.5, 3.0]] {
        let options = LemkeOptions {
            covering: Some(covering),
            ..LemkeOptions::default()
        };
        reused.set_options(options.clone());
        let (m, q) = &spd;
        let again = reused.solve(m.as_view(), q.as_view()).unwrap().clone();
        assert_eq!(again, common::solve_with(options, m, q));
    }
    let options = LemkeOptions {
        covering: Some(vec![1.0, -1.0]),
        ..LemkeOptions::default()
    };
    reused.set_options(options);
    let (m, q) = &spd;
    let err = reused.solve(m.as_view(), q.as_view()).unwrap_err();
    assert_eq!(
        err,
        LcpInputError::CoveringNotPositive {
            index: 1,
            value: -1.0
        }
    );
}
