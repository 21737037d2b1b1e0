//! What happens after Lemke's method fails with the configured covering vector
//! (docs/lcp.md, "Recovery and fallbacks"), and the certificate that decides it.

mod problems;

use hopsim_lcp::{Certificate, LcpSolution, LcpStatus, LemkeOptions, LemkeSolver, SolveMethod};
use nalgebra::{dmatrix, dvector, DMatrix, DVector};
use problems::{check_certificate, check_solution};
use proptest::prelude::*;

/// Lemke's method alone with the covering vector `d` (`None`: all ones).
fn alone(m: &DMatrix<f64>, q: &DVector<f64>, d: Option<Vec<f64>>) -> LcpSolution {
    let options = LemkeOptions {
        covering: d,
        fallback: false,
        ..LemkeOptions::default()
    };
    LemkeSolver::new(options)
        .solve(m.as_view(), q.as_view())
        .unwrap()
        .clone()
}

/// The covering vectors of the fallback, in order, as docs/lcp.md lists them: `1 + i`
/// (all ones instead when the configured one was given), `n − i`, `1 + (7i mod n)`,
/// `1 + n |q_i| / ‖q‖_∞`.
fn alternates(q: &DVector<f64>, user: bool) -> Vec<Vec<f64>> {
    let n = q.len();
    let q_norm = q.amax();
    let first = (0..n)
        .map(|i| if user { 1.0 } else { 1.0 + i as f64 })
        .collect();
    vec![
        first,
        (0..n).map(|i| (n - i) as f64).collect(),
        (0..n).map(|i| 1.0 + ((7 * i) % n) as f64).collect(),
        (0..n)
            .map(|i| 1.0 + n as f64 * q[i].abs() / q_norm)
            .collect(),
    ]
}

/// Small general LCPs (integers in `−2 … 2`, `n ≤ 6`): many end on a ray with the
/// default covering vector although they have a solution.
fn small_general() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (1..=6usize).prop_flat_map(|n| {
        (
            prop::collection::vec(-2..=2i32, n * n),
            prop::collection::vec(-2..=2i32, n),
        )
            .prop_map(move |(a, q)| {
                (
                    DMatrix::from_fn(n, n, |i, j| f64::from(a[i * n + j])),
                    DVector::from_fn(n, |i, _| f64::from(q[i])),
                )
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The solver's answer is the first of: Lemke's method with the configured covering
    /// vector, then with each alternate in order, then enumeration; `pivots` counts every
    /// run made, and a failure reports the first run's iterate. Each run is reproduced on
    /// its own with that covering vector and no fallback.
    #[test]
    fn the_fallback_tries_the_documented_covering_vectors_in_order(
        (m, q) in small_general(),
        user in prop::option::of(prop::collection::vec(0.5..3.0f64, 6)),
    ) {
        let n = q.len();
        let user = user.map(|d| d[..n].to_vec());
        let options = LemkeOptions { covering: user.clone(), ..LemkeOptions::default() };
        let sol = LemkeSolver::new(options).solve(m.as_view(), q.as_view()).unwrap().clone();
        check_certificate(&m, &q, &sol, 1e-9)?;
        let first = alone(&m, &q, user.clone());
        if first.status == LcpStatus::Solved {
            prop_assert_eq!(sol, first);
            return Ok(());
        }
        let mut pivots = first.pivots;
        for d in alternates(&q, user.is_some()) {
            let run = alone(&m, &q, Some(d));
            pivots += run.pivots;
            if run.status == LcpStatus::Solved {
                prop_assert_eq!(sol.method, SolveMethod::LemkeAlternateCovering);
                prop_assert_eq!(&sol.z, &run.z);
                prop_assert_eq!(&sol.w, &run.w);
                prop_assert_eq!(sol.certificate, run.certificate);
                prop_assert_eq!(sol.pivots, pivots);
                return Ok(());
            }
        }
        prop_assert_eq!(sol.pivots, pivots);
        if sol.status == LcpStatus::Solved {
            prop_assert_eq!(sol.method, SolveMethod::Enumeration);
            check_solution(&m, &q, &sol)?;
        } else {
            // Nothing solved: the first run's status and iterate, and truly no solution.
            prop_assert_eq!(
                (sol.status, sol.method, &sol.z, &sol.w, sol.certificate),
                (first.status, SolveMethod::Lemke, &first.z, &first.w, first.certificate)
            );
            prop_assert!(brute_force_solutions(&m, &q).is_empty(), "a solution exists");
        }
    }
}

/// Every complementary basis whose solution satisfies the LCP to `1e-9` (small `n`;
/// nalgebra's LU, not the crate's).
fn brute_force_solutions(m: &DMatrix<f64>, q: &DVector<f64>) -> Vec<DVector<f64>> {
    let n = q.len();
    let tol = 1e-9 * q.amax().max(1.0);
    (0u32..1 << n)
        .filter_map(|mask| {
            let s: Vec<usize> = (0..n).filter(|j| mask & (1 << j) != 0).collect();
            let mut z = DVector::zeros(n);
            if !s.is_empty() {
                let a = DMatrix::from_fn(s.len(), s.len(), |i, j| m[(s[i], s[j])]);
                let b = DVector::from_fn(s.len(), |i, _| -q[s[i]]);
                let x = a.lu().solve(&b)?;
                for (k, &j) in s.iter().enumerate() {
                    z[j] = x[k];
                }
            }
            let w = m * &z + q;
            let ok = (0..n).all(|i| z[i] >= -tol && w[i] >= -tol && (z[i] * w[i]).abs() <= tol);
            ok.then_some(z)
        })
        .collect()
}

/// Enumeration is the last resort, for `n ≤ enumeration_limit` only: with a limit below
/// `n` the same problem stays unsolved.
#[test]
fn enumeration_runs_up_to_its_limit() {
    // Lemke's method ends on a ray with every covering vector; z = (1.5, 0) solves it.
    let (m, q) = (dmatrix![0.0, 1.0; 2.0, 0.0], dvector![0.0, -3.0]);
    for (limit, solved) in [(1, false), (2, true), (25, true)] {
        let options = LemkeOptions {
            enumeration_limit: limit,
            ..LemkeOptions::default()
        };
        let sol = LemkeSolver::new(options)
            .solve(m.as_view(), q.as_view())
            .unwrap()
            .clone();
        assert_eq!(sol.status == LcpStatus::Solved, solved, "limit {limit}");
        if solved {
            assert_eq!(
                (sol.method, sol.z[0], sol.z[1]),
                (SolveMethod::Enumeration, 1.5, 0.0)
            );
        }
    }
}

/// `holds()` accepts each measure up to and including the tolerance and nothing beyond,
/// and no NaN.
#[test]
fn a_certificate_holds_exactly_up_to_its_tolerance() {
    let t = 1e-9;
    let at = Certificate {
        complementarity: t,
        most_negative: -t,
        residual: t,
        tolerance: t,
        matrix_norm: 2.0,
    };
    assert!(at.holds());
    assert_eq!(at.z_tolerance(), t / 2.0);
    let above = t * (1.0 + f64::EPSILON);
    for bad in [
        Certificate {
            complementarity: above,
            ..at
        },
        Certificate {
            most_negative: -above,
            ..at
        },
        Certificate {
            residual: above,
            ..at
        },
        Certificate {
            complementarity: f64::NAN,
            ..at
        },
        Certificate {
            most_negative: f64::NAN,
            ..at
        },
        Certificate {
            residual: f64::NAN,
            ..at
        },
        Certificate {
            tolerance: f64::NAN,
            ..at
        },
    ] {
        assert!(!bad.holds(), "{bad:?}");
    }
}

/// `w = −z − 1`: Lemke's method stops on a ray at once with `z = w = 0` (`z0 = 1` is
/// basic), so the certificate is `(0, 0, |0 − q|, 1e-9 · ‖q‖)` = `(0, 0, 1, 1e-9)`.
#[test]
fn a_failed_solve_reports_the_certificate_of_its_iterate() {
    let sol = hopsim_lcp::solve_lcp(&dmatrix![-1.0], &dvector![-1.0]).unwrap();
    assert_eq!(sol.status, LcpStatus::RayTermination);
    assert_eq!((sol.z[0], sol.w[0]), (0.0, 0.0));
    let c = sol.certificate;
    assert_eq!(
        (c.complementarity, c.most_negative, c.residual, c.tolerance),
        (0.0, 0.0, 1.0, 1e-9)
    );
    // Scaled by 4: the same iterate, the residual and tolerance in the units of `w`.
    let sol = hopsim_lcp::solve_lcp(&dmatrix![-4.0], &dvector![-4.0]).unwrap();
    let c = sol.certificate;
    assert_eq!((c.residual, c.tolerance), (4.0, 4e-9));
}

/// A solved answer's certificate, by hand: `M = [[2, 1], [1, 2]]`, `q = (−5, −6)` gives
/// `z = (4/3, 7/3)`, `w = 0`: the scale is `max(‖q‖, ‖M‖ ‖z‖) = 3 · 7/3 = 7`.
#[test]
fn a_solved_answer_reports_its_tolerance_from_the_scale_of_z() {
    let sol = hopsim_lcp::solve_lcp(&dmatrix![2.0, 1.0; 1.0, 2.0], &dvector![-5.0, -6.0]).unwrap();
    assert_eq!(sol.status, LcpStatus::Solved);
    let c = sol.certificate;
    assert!((c.tolerance - 7e-9).abs() <= 1e-23, "{c:?}");
    assert!(c.residual <= 1e-14 && c.complementarity == 0.0 && c.most_negative == 0.0);
    // A looser tolerance is proportional.
    let options = LemkeOptions {
        rel_tol: 1e-6,
        ..LemkeOptions::default()
    };
    let (m, q) = (dmatrix![2.0, 1.0; 1.0, 2.0], dvector![-5.0, -6.0]);
    let sol = LemkeSolver::new(options)
        .solve(m.as_view(), q.as_view())
        .unwrap()
        .clone();
    assert!((sol.certificate.tolerance - 7e-6).abs() <= 1e-20);
}
