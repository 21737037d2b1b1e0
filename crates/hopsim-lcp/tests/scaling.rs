//! Scale invariance of the solver (it scales `M`, `q` internally) and the
//! `numerical_breakdown` status on problems whose solution is not representable.

mod common;

use hopsim_lcp::{LcpSolution, LcpStatus, LemkeSolver};
use nalgebra::{dmatrix, dvector, DMatrix, DVector};

/// The problems of the scaling test: the Robbit two-contact LCP and random contact LCPs
/// of docs/physics.md §4 (one disc on the ground, a disc in a corner, two and four discs in a
/// row against a wall: sizes 3, 6, 12 and 24).
fn contact_problems() -> Vec<(DMatrix<f64>, DVector<f64>)> {
    let mut rng = common::Rng(0x5ca1_ab1e);
    let mut out = vec![common::robbit_two_contacts()];
    for (discs, ground_only) in [(1, true), (1, false), (2, false), (4, false)] {
        for _ in 0..60 {
            out.push(common::disc_row(&mut rng, discs, ground_only, None));
        }
    }
    out
}

/// Independent check (plain nalgebra, relative to the data's size) that `sol` solves
/// `(M, q)`: `z ≥ 0`, `w = M z + q ≥ 0`, `zᵀw = 0`, to `1e-9` of the problem's scale, with
/// `z` measured in the units of `w` (`‖M‖_∞ z`) so that the check is invariant under
/// scaling `M` or `q`.
fn assert_solves(m: &DMatrix<f64>, q: &DVector<f64>, sol: &LcpSolution, what: &str) {
    assert_eq!(sol.status, LcpStatus::Solved, "{what}: {sol:?}");
    assert!(sol.certificate.holds(), "{what}: {:?}", sol.certificate);
    let w = m * &sol.z + q;
    let m_norm = m.row_iter().map(|r| r.abs().sum()).fold(0.0, f64::max);
    let scale = q.amax().max(m_norm * sol.z.amax());
    let tol = 1e-9 * scale;
    for i in 0..q.len() {
        let z = m_norm * sol.z[i];
        assert!(z >= -tol, "{what}: z[{i}] = {}", sol.z[i]);
        assert!(w[i] >= -tol, "{what}: w[{i}] = {}", w[i]);
        assert!(
            z.min(w[i]).abs() <= tol,
            "{what}: z[{i}] = {}, w[{i}] = {}",
            sol.z[i],
            w[i]
        );
        assert!((sol.w[i] - w[i]).abs() <= tol, "{what}: w[{i}]");
    }
}

/// `max_i |a_i − b_i| / max(‖b‖_∞, tiny)`.
fn rel_diff(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    (a - b).amax() / b.amax().max(f64::MIN_POSITIVE)
}

/// `z(s M, s q) = z(M, q)`, `z(M, s q) = s z(M, q)` and `z(s M, q) = z(M, q) / s`: the
/// LCP's solution set scales exactly so. For factors that are not powers of two the
/// internal scaled problems differ by round-off, so the solutions agree to a relative
/// 1e-9 (the solver's reference `z(M, q)` is itself checked against brute-force
/// enumeration of the complementary bases for the problems up to 12×12).
#[test]
fn solutions_scale_with_the_data() {
    let mut solver = LemkeSolver::default();
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for (k, (m, q)) in contact_problems().into_iter().enumerate() {
        let base = solver.solve(m.as_view(), q.as_view()).unwrap().clone();
        assert_solves(&m, &q, &base, &format!("problem {k}"));
        if q.len() <= 12 {
            let all = common::brute_force(&m, &q, 1e-9 * q.amax());
            assert!(
                all.iter()
                    .any(|z| rel_diff(&base.z, z) <= 1e-9 || (&base.z - z).amax() <= 1e-12),
                "problem {k}: z = {} is none of the {} brute-force solutions",
                base.z,
                all.len()
            );
        }
        for s in [1e-6, 1e-3, 1e3, 1e6] {
            // (s M, s q): same z.
            let (ms, qs) = (&m * s, &q * s);
            let sol = solver.solve(ms.as_view(), qs.as_view()).unwrap().clone();
            let what = format!("problem {k}, (M, q)·{s:e}");
            assert_solves(&ms, &qs, &sol, &what);
            let e = rel_diff(&sol.z, &base.z);
            assert!(e <= 1e-9, "{what}: z differs by {e:e} (relative)");
            worst = worst.max(e);
            // (M, s q): z scales by s.
            let sol = solver.solve(m.as_view(), qs.as_view()).unwrap().clone();
            let what = format!("problem {k}, q·{s:e}");
            assert_solves(&m, &qs, &sol, &what);
            let e = rel_diff(&sol.z, &(&base.z * s));
            assert!(e <= 1e-9, "{what}: z differs by {e:e} (relative)");
            worst = worst.max(e);
            // (s M, q): z scales by 1/s.
            let sol = solver.solve(ms.as_view(), q.as_view()).unwrap().clone();
            let what = format!("problem {k}, M·{s:e}");
            assert_solves(&ms, &q, &sol, &what);
            let e = rel_diff(&sol.z, &(&base.z / s));
            assert!(e <= 1e-9, "{what}: z differs by {e:e} (relative)");
            worst = worst.max(e);
            checked += 3;
        }
    }
    println!("{checked} scaled solves, worst relative difference {worst:e}");
}

/// Powers of two scale exactly, and the solver's internal scaling is by powers of two:
/// the scaled problem must then be solved bit for bit like the original (same pivots,
/// same method, `z` exactly scaled). Only down to `M · 2^-20`: below that the
/// certificate's scale bug (see `certificate_is_invariant_under_scaling_m_and_q`) sends
/// some problems through the refinement, which gives a different (still correct) `z`.
#[test]
fn power_of_two_scaling_is_bit_exact() {
    let mut solver = LemkeSolver::default();
    for (k, (m, q)) in contact_problems().into_iter().enumerate() {
        let base = solver.solve(m.as_view(), q.as_view()).unwrap().clone();
        assert_eq!(base.status, LcpStatus::Solved);
        for e in [-20, -1, 1, 20, 60] {
            let s = 2f64.powi(e);
            for (sm, sq, factor) in [(s, s, 1.0), (1.0, s, s), (s, 1.0, 1.0 / s)] {
                let (ms, qs) = (&m * sm, &q * sq);
                let sol = solver.solve(ms.as_view(), qs.as_view()).unwrap();
                let what = format!("problem {k}: M·2^{}, q·2^{}", sm.log2(), sq.log2());
                assert_eq!(sol.status, LcpStatus::Solved, "{what}");
                assert_eq!(sol.pivots, base.pivots, "{what}");
                assert_eq!(sol.method, base.method, "{what}");
                assert_eq!(sol.z, &base.z * factor, "{what}");
                assert_eq!(sol.w, &base.w * sq, "{what}");
            }
        }
    }
}

/// `M = [1e-300]`, `q = [−1e300]`: every entry is finite, but the only solution,
/// `z = 1e600`, overflows. No finite `z` certifies: `w = M z + q ≤ 1.8e8 − 1e300 < 0`
/// while the tolerance is `1e-9 · max(1e300, 1e-300 z) = 1e291`. The solver must report
/// `numerical_breakdown` (its tableau solution overflows when unscaled), never `solved`,
/// and a certificate that does not hold, with the fallbacks and without them. As one
/// block of a larger problem whose other block is the Robbit contact LCP the problem has
/// no representable solution either: any failure status will do there (the scaled pivot
/// `1e-300 / ‖M‖` is below the pivot tolerance, so Lemke's method ends on a ray).
#[test]
fn overflowing_solution_is_a_numerical_breakdown() {
    let fails = |sol: &LcpSolution, what: &str| {
        assert!(!sol.certificate.holds(), "{what}");
        // The certificate names the failure: a NaN measure or one above the tolerance.
        let c = sol.certificate;
        let measures = [c.complementarity, -c.most_negative, c.residual];
        assert!(
            measures.iter().any(|v| v.is_nan() || *v > c.tolerance),
            "{what}"
        );
    };
    let (m1, q1) = (dmatrix![1e-300], dvector![-1e300]);
    let (mc, qc) = common::robbit_two_contacts();
    let n = qc.len() + 1;
    let mut m2 = DMatrix::zeros(n, n);
    m2.view_mut((0, 0), (n - 1, n - 1)).copy_from(&mc);
    m2[(n - 1, n - 1)] = 1e-300;
    let mut q2 = DVector::zeros(n);
    q2.rows_mut(0, n - 1).copy_from(&qc);
    q2[n - 1] = -1e300;
    for options in [common::no_fallback(), Default::default()] {
        let fallback = options.fallback;
        let sol = common::solve_with(options.clone(), &m1, &q1);
        let what = format!("1×1, fallback {fallback}: {sol:?}");
        assert_eq!(sol.status, LcpStatus::NumericalBreakdown, "{what}");
        assert_eq!(sol.status.as_str(), "numerical_breakdown");
        fails(&sol, &what);
        let sol = common::solve_with(options, &m2, &q2);
        let what = format!("{n}×{n}, fallback {fallback}: {sol:?}");
        assert_ne!(sol.status, LcpStatus::Solved, "{what}");
        fails(&sol, &what);
    }
}

/// The documented failure contract (`LcpSolution`: "on a failure status `z`, `w` hold the
/// last Lemke iterate (zeros if it was not finite)"): after the breakdown above the
/// reported iterate must be finite. (An iterate can overflow only when unscaled;
/// `tableau::extract` checks the unscaled values.)
#[test]
fn breakdown_iterate_is_finite() {
    for options in [common::no_fallback(), Default::default()] {
        let sol = common::solve_with(options, &dmatrix![1e-300], &dvector![-1e300]);
        assert_eq!(sol.status, LcpStatus::NumericalBreakdown);
        assert!(
            sol.z.iter().chain(sol.w.iter()).all(|v| v.is_finite()),
            "z = {}, w = {}",
            sol.z,
            sol.w
        );
    }
}

/// `(s M, s q)` has exactly the solutions of `(M, q)` and `(s M, q)` those scaled by
/// `1/s`, so whether a solution certifies must not depend on `s`. This contact LCP (from
/// `common::disc_row`, one disc in a corner) solves at `s = 1` with `‖z‖ ≈ 1.1`; at
/// `(1e-9 M, q)` Lemke's `z` (≈ 1e9 times it) has the round-off entry `z_6 = −2.0e-7`
/// (relative 2e-16). A certificate that held `z` to a tolerance in the units of `w`
/// rejected it (and, over 2000 random contact LCPs, 84 others at `(1e-9 M, q)`); it now
/// measures `z` as `‖M‖ z`.
#[test]
fn certificate_is_invariant_under_scaling_m_and_q() {
    let m = DMatrix::from_row_slice(
        6,
        6,
        &[
            1.4749234080429672e0,
            -1.154953473065223e0,
            -2.6671518062384264e-1,
            7.008912738643426e-1,
            0.0,
            0.0,
            5.955296004577696e-1,
            2.87068644714189e-1,
            -4.8709026436987457e-1,
            6.596316401184803e-1,
            0.0,
            0.0,
            -3.5676217533619865e0,
            -2.711773319540917e0,
            2.2561990504412854e0,
            1.5023936054475684e0,
            1.0,
            0.0,
            -1.4971687448612498e0,
            -3.5796581478919505e0,
            1.5023936054475684e0,
            2.862916519430391e0,
            0.0,
            1.0,
            2.9260774416978204e0,
            0.0,
            -1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            2.9615182693862723e0,
            0.0,
            -1.0,
            0.0,
            0.0,
        ],
    );
    let q = dvector![
        -9.086519467664224e-1,
        2.0727471343363654e-2,
        3.08188643384972e-1,
        -5.797358320380868e-1,
        0.0,
        0.0
    ];
    let base = LemkeSolver::default()
        .solve(m.as_view(), q.as_view())
        .unwrap()
        .clone();
    assert_solves(&m, &q, &base, "s = 1");
    for s in [1e-6, 1e-9, 1e-12] {
        let ms = &m * s;
        for (qs, factor) in [(&q * s, 1.0), (q.clone(), 1.0 / s)] {
            let what = format!("M·{s:e}, z·{factor:e}");
            let sol = LemkeSolver::default()
                .solve(ms.as_view(), qs.as_view())
                .unwrap()
                .clone();
            assert_solves(&ms, &qs, &sol, &what);
            assert!(rel_diff(&sol.z, &(&base.z * factor)) <= 1e-9, "{what}");
        }
    }
}
