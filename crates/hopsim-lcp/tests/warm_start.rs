//! Warm starts ([`LemkeSolver::solve_warm`]): on LCPs with a unique solution they give the
//! cold solve's answer; a remembered basis that no longer fits falls back to Lemke's
//! method; bad data is still an error.

use hopsim_lcp::{LcpInputError, LcpStatus, LemkeSolver, SolveMethod, WarmStart};
use nalgebra::{dmatrix, dvector, DMatrix, DVector};

/// Uniform numbers in [−1, 1) (xorshift, fixed seed).
fn uniform(seed: &mut u64) -> f64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    (*seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// A positive definite `M = A Aᵀ + I/2` has the P-property: every `q` gives exactly one
/// solution, so a warm answer must equal the cold one. `q` drifts slowly along a
/// sequence, as a time-stepper's does, so most solves keep their basis and some cross a
/// change of basis. Sizes 1–9 cover the copies compiled per size (≤ 6) and the general
/// one.
#[test]
fn a_warm_start_finds_the_unique_solution_of_a_p_matrix_lcp() {
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    for n in 1..=9 {
        let a = DMatrix::from_fn(n, n, |_, _| uniform(&mut seed));
        let m = &a * a.transpose() + DMatrix::identity(n, n) * 0.5;
        let q0 = DVector::from_fn(n, |_, _| uniform(&mut seed));
        let drift = DVector::from_fn(n, |_, _| uniform(&mut seed));
        let (mut warm_solver, mut cold_solver) = (LemkeSolver::default(), LemkeSolver::default());
        let mut warm = WarmStart::with_capacity(n);
        let (mut hits, mut lemke) = (0, 0);
        for step in 0..400 {
            let q = &q0 + &drift * (0.01 * step as f64);
            let cold = cold_solver.solve(m.as_view(), q.as_view()).unwrap().clone();
            let sol = warm_solver
                .solve_warm(m.as_view(), q.as_view(), &mut warm)
                .unwrap();
            assert_eq!(sol.status, LcpStatus::Solved, "n = {n}, step {step}");
            assert!(sol.certificate.holds());
            let scale = 1.0 + cold.z.amax();
            let dz = (&sol.z - &cold.z).amax();
            assert!(dz <= 1e-12 * scale, "n = {n}, step {step}: |Δz| = {dz:e}");
            match sol.method {
                SolveMethod::WarmStart => {
                    assert_eq!(sol.pivots, 0);
                    hits += 1;
                }
                SolveMethod::Lemke => lemke += 1,
                _ => {}
            }
        }
        // The drift moves q by 4 |drift| over the run: the basis changes a few times (the
        // first solve is always cold) and holds in between.
        assert!(
            hits > 10 * lemke,
            "n = {n}: {hits} warm answers, {lemke} by Lemke"
        );
        assert!(lemke >= 1, "n = {n}: no cold solve");
    }
}

/// `M = [[2, 1], [1, 2]]`: `q = (−1, 1)` has `z = (1/2, 0)`; `q = (1, −1)` needs the other
/// basis, `z = (0, 1/2)`, found by Lemke's method; `q = (2, −2)` then keeps that basis,
/// `z = (0, 1)`, without pivots.
#[test]
fn a_basis_that_no_longer_fits_falls_back_to_lemke() {
    let m = dmatrix![2.0, 1.0; 1.0, 2.0];
    let mut solver = LemkeSolver::default();
    let mut warm = WarmStart::default();
    let cases = [
        (dvector![-1.0, 1.0], [0.5, 0.0], SolveMethod::Lemke),
        (dvector![1.0, -1.0], [0.0, 0.5], SolveMethod::Lemke),
        (dvector![2.0, -2.0], [0.0, 1.0], SolveMethod::WarmStart),
    ];
    for (q, z, method) in cases {
        let sol = solver
            .solve_warm(m.as_view(), q.as_view(), &mut warm)
            .unwrap();
        assert_eq!((sol.status, sol.method), (LcpStatus::Solved, method), "{q}");
        assert!((sol.z[0] - z[0]).abs() < 1e-15 && (sol.z[1] - z[1]).abs() < 1e-15);
        assert_eq!(warm.basis(), Some(&[z[0] > 0.0, z[1] > 0.0][..]));
    }
    // `q ≥ 0` is the trivial answer, not the remembered basis.
    let q = dvector![1.0, 1.0];
    let sol = solver
        .solve_warm(m.as_view(), q.as_view(), &mut warm)
        .unwrap();
    assert_eq!(sol.method, SolveMethod::Trivial);
    assert_eq!(sol.z.as_slice(), &[0.0, 0.0]);
    // A problem of another size ignores the basis.
    let (m3, q3) = (DMatrix::identity(3, 3), dvector![-1.0, -2.0, 0.5]);
    let sol = solver
        .solve_warm(m3.as_view(), q3.as_view(), &mut warm)
        .unwrap();
    assert_eq!(
        (sol.method, sol.z.as_slice()),
        (SolveMethod::Lemke, &[1.0, 2.0, 0.0][..])
    );
}

/// Non-finite data is the same error warm as cold, and an unsolvable problem is reported
/// as such (and forgets the basis).
#[test]
fn bad_data_is_an_error_and_failures_are_not_remembered() {
    let m = dmatrix![2.0, 1.0; 1.0, 2.0];
    let mut solver = LemkeSolver::default();
    let mut warm = WarmStart::default();
    let q = dvector![-1.0, -1.0];
    solver
        .solve_warm(m.as_view(), q.as_view(), &mut warm)
        .unwrap();
    assert!(warm.basis().is_some());
    let bad = dvector![-1.0, f64::NAN];
    assert!(matches!(
        solver.solve_warm(m.as_view(), bad.as_view(), &mut warm),
        Err(LcpInputError::NonFinite { what: "q", .. })
    ));
    // `w = −z − 1` can never be non-negative: no solution.
    let (m1, q1) = (dmatrix![-1.0], dvector![-1.0]);
    let sol = solver
        .solve_warm(m1.as_view(), q1.as_view(), &mut warm)
        .unwrap();
    assert_ne!(sol.status, LcpStatus::Solved);
    assert!(warm.basis().is_none());
}

/// A warm attempt publishes nothing unless its basis certifies: when the remembered basis
/// fails and the ordinary solve then reports an error (here a covering vector of the wrong
/// length, set after the basis was remembered), the last answer stays as it was.
#[test]
fn a_failed_warm_attempt_leaves_the_last_answer() {
    let m = dmatrix![2.0, 1.0; 1.0, 2.0];
    let mut solver = LemkeSolver::default();
    let mut warm = WarmStart::default();
    // z = (1/2, 0), w = (0, 3/2): the basis {z_1}.
    let q = dvector![-1.0, 1.0];
    let before = solver
        .solve_warm(m.as_view(), q.as_view(), &mut warm)
        .unwrap()
        .clone();
    assert_eq!(warm.basis(), Some(&[true, false][..]));
    let mut options = solver.options().clone();
    options.covering = Some(vec![1.0]);
    solver.set_options(options);
    // The basis {z_1} gives z_1 = 1 and w_2 = z_1 − 2 = −1: it does not certify.
    let q = dvector![-2.0, -2.0];
    assert!(matches!(
        solver.solve_warm(m.as_view(), q.as_view(), &mut warm),
        Err(LcpInputError::CoveringLength { n: 2, len: 1 })
    ));
    assert_eq!(solver.solution(), &before);
}

/// `(M, q)` of size `n` whose answer has the basis `basic` with `M_BB` the reversed
/// identity (every column of its elimination needs a row exchange; an odd size's middle
/// row does not) and `z_B = 1, 2, 3, …` (exact), decoupled rows off the basis with
/// `w = 1`; and that basis remembered from `(I, ±1)`.
fn reversed_basis(basic: &[bool]) -> (DMatrix<f64>, DVector<f64>, LemkeSolver, WarmStart) {
    let n = basic.len();
    let index: Vec<usize> = (0..n).filter(|&i| basic[i]).collect();
    let k = index.len();
    let mut m = DMatrix::identity(n, n);
    let mut q = DVector::from_element(n, 1.0);
    for (a, &i) in index.iter().enumerate() {
        m[(i, i)] = 0.0;
        m[(i, index[k - 1 - a])] = 1.0;
        // Row i reads z at index[k − 1 − a], whose value is k − a.
        q[i] = -((k - a) as f64);
    }
    let (mut solver, mut warm) = (LemkeSolver::default(), WarmStart::default());
    let flags = DVector::from_fn(n, |i, _| if basic[i] { -1.0 } else { 1.0 });
    let id = DMatrix::<f64>::identity(n, n);
    solver
        .solve_warm(id.as_view(), flags.as_view(), &mut warm)
        .unwrap();
    assert_eq!(warm.basis(), Some(basic));
    (m, q, solver, warm)
}

/// The warm path's Gaussian elimination exchanges rows: a remembered basis whose `M_BB`
/// has zeros on its diagonal is solved warm, exactly, on every size the warm path compiles
/// on its own (1 … 6) and on the generic one, with every basis size.
#[test]
fn a_basis_needing_row_exchanges_is_solved_warm() {
    for n in 1..=10 {
        for mask in [u32::MAX, 0b1011_0110, 0b0110_1101, 0b11, 0b1_1100] {
            let basic: Vec<bool> = (0..n).map(|i| mask & (1 << i) != 0).collect();
            if !basic.contains(&true) {
                continue;
            }
            let (m, q, mut solver, mut warm) = reversed_basis(&basic);
            let sol = solver
                .solve_warm(m.as_view(), q.as_view(), &mut warm)
                .unwrap();
            assert_eq!(sol.method, SolveMethod::WarmStart, "n = {n}, {basic:?}");
            let mut value = 0.0;
            for i in 0..n {
                if basic[i] {
                    value += 1.0;
                    assert_eq!((sol.z[i], sol.w[i]), (value, 0.0), "n = {n}, {basic:?}");
                } else {
                    assert_eq!((sol.z[i], sol.w[i]), (0.0, 1.0), "n = {n}, {basic:?}");
                }
            }
        }
    }
}

/// `M_BB = s [[1, 1], [1, 1 + δ]]` with `s = 1024` and `q_B = −s (1, 1)`: the basis solves
/// to `z_B = (1, 0)`, which certifies. The elimination's second pivot is `s δ`; a pivot at
/// most `1e-13` times the largest entry of `M_BB` counts as singular, so `δ = 1e-14` (or
/// 0) hands over to Lemke's method and `δ = 1e-12` is answered warm; on the sizes compiled
/// on their own and the generic one (the basis padded by decoupled rows).
#[test]
fn the_warm_path_refuses_a_numerically_singular_basis() {
    let s = 1024.0;
    for n in 2..=9 {
        for (delta, warm_answer) in [(0.0, false), (1e-14, false), (1e-12, true), (1e-3, true)] {
            let mut m = DMatrix::identity(n, n);
            m[(0, 0)] = s;
            m[(0, 1)] = s;
            m[(1, 0)] = s;
            m[(1, 1)] = s * (1.0 + delta);
            let mut q = DVector::from_element(n, 1.0);
            q[0] = -s;
            q[1] = -s;
            let mut basic = vec![false; n];
            basic[..2].fill(true);
            let mut solver = LemkeSolver::default();
            let mut warm = WarmStart::default();
            let flags = DVector::from_fn(n, |i, _| if basic[i] { -1.0 } else { 1.0 });
            let id = DMatrix::<f64>::identity(n, n);
            solver
                .solve_warm(id.as_view(), flags.as_view(), &mut warm)
                .unwrap();
            let sol = solver
                .solve_warm(m.as_view(), q.as_view(), &mut warm)
                .unwrap();
            assert_eq!(sol.status, LcpStatus::Solved);
            assert_eq!(
                sol.method == SolveMethod::WarmStart,
                warm_answer,
                "n = {n}, δ = {delta:e}: {:?}",
                sol.method
            );
            // (With δ ≤ 1e-14 any split of z_1 + z_2 = 1 certifies.)
            assert!((sol.z[0] + sol.z[1] - 1.0).abs() <= 1e-9, "{}", sol.z);
            if warm_answer {
                assert_eq!((sol.z[0], sol.z[1]), (1.0, 0.0));
            }
        }
    }
}
