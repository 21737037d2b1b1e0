//! No input of the public API panics. Sequences of calls of one solver and one warm start
//! on problems of varying size (non-square, `q` of another length, views into larger
//! matrices), with arbitrary data (NaN, ±∞, ±0, subnormal, huge, tiny) mixed into
//! generated problems, and arbitrary options (covering vectors, pivot limits, tolerances,
//! enumeration limits): every call returns `Ok` or the typed error its input deserves,
//! a `Solved` answer carries a certificate that holds (and that an independent check
//! confirms), an error leaves the last answer and the remembered basis as they were.

mod problems;

use hopsim_lcp::{
    LcpInputError, LcpSolution, LcpStatus, LemkeOptions, LemkeSolver, SolveMethod, WarmStart,
};
use nalgebra::{DMatrix, DVector};
use problems::{any_problem, check_solution, Problem};
use proptest::prelude::*;

/// Any `f64`, with the troublesome ones often.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -1.0..1.0f64,
        1 => prop::sample::select(vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            -f64::MAX,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
            1e300,
            -1e300,
            1e-300,
            -1e-300,
            1e150,
            -1e150,
        ]),
        1 => any::<f64>(),
    ]
}

/// The data of one call: a generated problem with some entries replaced by [`wild`]
/// values, or all-wild data; shapes that may not fit.
#[derive(Debug, Clone)]
struct Data {
    rows: usize,
    cols: usize,
    /// `rows + extra` rows are stored; the call sees a view of the first `rows`.
    extra: usize,
    m: Vec<f64>,
    q: Vec<f64>,
}

fn data() -> impl Strategy<Value = Data> {
    let generated = (
        any_problem(14),
        prop::collection::vec((any::<prop::sample::Index>(), wild()), 0..4),
        0..3usize,
    )
        .prop_map(|(p, wilds, extra)| {
            let n = p.n();
            let mut m: Vec<f64> = Vec::new();
            for j in 0..n {
                m.extend(p.m.column(j).iter());
                m.extend(std::iter::repeat_n(7.0, extra));
            }
            let mut q = p.q.as_slice().to_vec();
            for (index, v) in wilds {
                let i = index.index(m.len() + n);
                if i < m.len() {
                    m[i] = v;
                } else {
                    q[i - m.len()] = v;
                }
            }
            Data {
                rows: n,
                cols: n,
                extra,
                m,
                q,
            }
        });
    let wild_data = (
        0..=12usize,
        prop_oneof![3 => Just(0i32), 1 => -1..=1i32],
        prop_oneof![3 => Just(0i32), 1 => -1..=1i32],
        0..2usize,
    )
        .prop_flat_map(|(n, dc, dq, extra)| {
            let cols = (n as i32 + dc).max(0) as usize;
            let q_len = (n as i32 + dq).max(0) as usize;
            (
                Just((n, cols, extra)),
                prop::collection::vec(wild(), (n + extra) * cols),
                prop::collection::vec(wild(), q_len),
            )
        })
        .prop_map(|((rows, cols, extra), m, q)| Data {
            rows,
            cols,
            extra,
            m,
            q,
        });
    prop_oneof![3 => generated, 1 => wild_data]
}

/// Options: the defaults, or anything (valid or not).
fn options() -> impl Strategy<Value = LemkeOptions> {
    let covering = prop_oneof![
        3 => Just(None),
        1 => prop::collection::vec(prop_oneof![3 => 0.1..10.0f64, 1 => wild()], 0..15).prop_map(Some),
    ];
    let rel_tol = prop_oneof![
        3 => Just(1e-9),
        1 => prop::sample::select(vec![1e-12, 1e-6, 0.5, 0.0, -1e-9, 1.0, 2.0, f64::NAN, f64::INFINITY]),
    ];
    (
        prop_oneof![3 => Just(None), 1 => (0..40usize).prop_map(Some)],
        covering,
        rel_tol,
        0..=12usize,
        any::<bool>(),
    )
        .prop_map(
            |(max_pivots, covering, rel_tol, enumeration_limit, fallback)| LemkeOptions {
                max_pivots,
                covering,
                rel_tol,
                enumeration_limit,
                fallback,
            },
        )
}

#[derive(Debug, Clone)]
enum Call {
    Solve(Data),
    Warm(Data),
    Forget,
    Options(LemkeOptions),
}

fn call() -> impl Strategy<Value = Call> {
    prop_oneof![
        3 => data().prop_map(Call::Solve),
        6 => data().prop_map(Call::Warm),
        1 => Just(Call::Forget),
        1 => options().prop_map(Call::Options),
    ]
}

/// The error the input deserves, checked in this order: shape, options, data.
fn expected_error(d: &Data, options: &LemkeOptions) -> Option<LcpInputError> {
    let n = d.rows;
    if d.cols != n {
        return Some(LcpInputError::NotSquare {
            rows: n,
            cols: d.cols,
        });
    }
    if d.q.len() != n {
        return Some(LcpInputError::SizeMismatch {
            n,
            q_len: d.q.len(),
        });
    }
    let rel_tol = options.rel_tol;
    if !(rel_tol > 0.0 && rel_tol < 1.0) {
        return Some(LcpInputError::Tolerance { value: rel_tol });
    }
    if let Some(c) = &options.covering {
        if c.len() != n {
            return Some(LcpInputError::CoveringLength { n, len: c.len() });
        }
        if let Some(index) = c.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            let value = c[index];
            return Some(LcpInputError::CoveringNotPositive { index, value });
        }
    }
    if let Some(index) = d.q.iter().position(|v| !v.is_finite()) {
        return Some(LcpInputError::NonFinite { what: "q", index });
    }
    let stored = n + d.extra;
    for i in 0..n {
        for j in 0..n {
            if !d.m[j * stored + i].is_finite() {
                let index = i * n + j;
                return Some(LcpInputError::NonFinite { what: "M", index });
            }
        }
    }
    None
}

/// Two errors are the same (a NaN in an error compares unequal to itself).
fn same_error(a: &LcpInputError, b: &LcpInputError) -> bool {
    a.to_string() == b.to_string()
}

/// Two answers are the same, NaN for NaN (a failed iterate that overflowed has NaN
/// measures).
fn same(a: &LcpSolution, b: &LcpSolution) -> bool {
    format!("{a:?}") == format!("{b:?}")
}

/// What an `Ok` answer must satisfy, whatever the data.
fn check_answer(d: &Data, sol: &LcpSolution, options: &LemkeOptions) -> Result<(), TestCaseError> {
    let n = d.rows;
    prop_assert_eq!((sol.z.len(), sol.w.len()), (n, n));
    let holds = sol.certificate.holds();
    prop_assert_eq!(holds, sol.status == LcpStatus::Solved, "{:?}", sol);
    if sol.status != LcpStatus::Solved {
        return Ok(());
    }
    prop_assert!(sol.z.iter().chain(sol.w.iter()).all(|v| v.is_finite()));
    // The independent check (default tolerance, data that cannot overflow it).
    let tame = d.m.iter().chain(&d.q).all(|v| v.abs() < 1e100)
        && sol.z.amax() < 1e100
        && options.rel_tol == 1e-9;
    if tame {
        let stored = n + d.extra;
        let m = DMatrix::from_fn(n, n, |i, j| d.m[j * stored + i]);
        let q = DVector::from_column_slice(&d.q);
        check_solution(&m, &q, sol)?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1500))]

    #[test]
    fn no_call_panics_and_every_answer_is_what_it_claims(
        calls in prop::collection::vec(call(), 1..12),
        first in options(),
    ) {
        let mut options = first.clone();
        let mut solver = LemkeSolver::new(first);
        let mut warm = WarmStart::default();
        for call in calls {
            let (d, use_warm) = match call {
                Call::Solve(d) => (d, false),
                Call::Warm(d) => (d, true),
                Call::Forget => {
                    warm.forget();
                    prop_assert!(warm.basis().is_none());
                    continue;
                }
                Call::Options(o) => {
                    solver.set_options(o.clone());
                    options = o;
                    continue;
                }
            };
            let stored = d.rows + d.extra;
            let full = DMatrix::from_column_slice(stored, d.cols, &d.m);
            let m = full.view((0, 0), (d.rows, d.cols));
            let q = DVector::from_column_slice(&d.q);
            let last = solver.solution().clone();
            let remembered = warm.basis().map(<[bool]>::to_vec);
            let result = if use_warm {
                solver.solve_warm(m, q.as_view(), &mut warm)
            } else {
                solver.solve(m, q.as_view())
            };
            let expected = expected_error(&d, &options);
            match (result, expected) {
                (Ok(sol), None) => {
                    let sol = sol.clone();
                    check_answer(&d, &sol, &options)?;
                    prop_assert!(same(solver.solution(), &sol));
                    if use_warm && sol.method == SolveMethod::WarmStart {
                        prop_assert_eq!(warm.basis().map(<[bool]>::to_vec), remembered);
                    } else if use_warm {
                        let basis: Option<Vec<bool>> = (sol.status == LcpStatus::Solved && d.rows > 0)
                            .then(|| sol.z.iter().zip(sol.w.iter()).map(|(z, w)| z > w).collect());
                        prop_assert_eq!(warm.basis().map(<[bool]>::to_vec), basis);
                    } else {
                        prop_assert_eq!(warm.basis().map(<[bool]>::to_vec), remembered);
                    }
                }
                (Err(e), Some(x)) => {
                    prop_assert!(same_error(&e, &x), "error {} where {} was due", e, x);
                    prop_assert!(same(solver.solution(), &last), "{:?}", solver.solution());
                    prop_assert_eq!(warm.basis().map(<[bool]>::to_vec), remembered);
                }
                (Ok(sol), Some(x)) => prop_assert!(false, "{:?} where the error {} was due", sol, x),
                (Err(e), None) => prop_assert!(false, "error {} on valid input", e),
            }
        }
    }
}

/// The case that crashed a time-stepper: every contact opened (`z = 0`, an empty basis of
/// nine rows), then the next landing (a `q` with negative entries) of the same size.
#[test]
fn an_empty_basis_of_any_size_then_a_landing() {
    for n in 1..=20 {
        let mut solver = LemkeSolver::default();
        let mut warm = WarmStart::default();
        let m = DMatrix::identity(n, n) * 2.0;
        let open = DVector::from_element(n, 1.0);
        let sol = solver
            .solve_warm(m.as_view(), open.as_view(), &mut warm)
            .unwrap();
        assert_eq!(sol.status, LcpStatus::Solved);
        assert_eq!(warm.basis(), Some(&vec![false; n][..]));
        let landing = DVector::from_fn(n, |i, _| if i % 3 == 0 { -1.0 } else { 0.5 });
        let sol = solver
            .solve_warm(m.as_view(), landing.as_view(), &mut warm)
            .unwrap();
        assert_eq!(sol.status, LcpStatus::Solved, "n = {n}");
        for i in 0..n {
            let z = if i % 3 == 0 { 0.5 } else { 0.0 };
            assert_eq!(sol.z[i], z, "n = {n}");
        }
        // A landing within the certificate's tolerance of `z = 0` keeps the empty basis,
        // on the sizes compiled on their own and on the others alike.
        if n == 1 {
            continue;
        }
        let touch = DVector::from_fn(n, |i, _| if i == 0 { -1e-12 } else { 1.0 });
        let open = DVector::from_element(n, 1.0);
        solver
            .solve_warm(m.as_view(), open.as_view(), &mut warm)
            .unwrap();
        let sol = solver
            .solve_warm(m.as_view(), touch.as_view(), &mut warm)
            .unwrap();
        assert_eq!(
            (sol.status, sol.method, sol.z.amax()),
            (LcpStatus::Solved, SolveMethod::WarmStart, 0.0),
            "n = {n}"
        );
    }
}

/// Problems of the classes Lemke's method is complete on stay solved when their data
/// are scaled to the ends of the floating-point range.
#[test]
fn extreme_scales_are_answered_or_reported() {
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig::with_cases(300));
    runner
        .run(
            &(
                any_problem(10),
                prop::sample::select(vec![1e-300, 1e-150, 1e150, 1e300]),
                any::<bool>(),
            ),
            |(p, s, scale_m): (Problem, f64, bool)| {
                let (m, q) = if scale_m {
                    (&p.m * s, p.q.clone())
                } else {
                    (p.m.clone(), &p.q * s)
                };
                let mut solver = LemkeSolver::default();
                let mut warm = WarmStart::default();
                for _ in 0..2 {
                    let sol = solver
                        .solve_warm(m.as_view(), q.as_view(), &mut warm)
                        .unwrap();
                    prop_assert_eq!(sol.certificate.holds(), sol.status == LcpStatus::Solved);
                    if sol.status == LcpStatus::Solved {
                        prop_assert!(sol.z.iter().chain(sol.w.iter()).all(|v| v.is_finite()));
                    }
                }
                Ok(())
            },
        )
        .unwrap();
}

/// Non-finite data is an error at every size, also right after an answer of that size
/// (no check on a change of size can stand in for the hot path's), warm and cold; and
/// `‖M‖_∞` is the largest row sum even where the sum of the row sums overflows.
#[test]
fn non_finite_data_is_an_error_at_every_size() {
    for n in 1..=14 {
        let m = DMatrix::<f64>::identity(n, n) * 2.0;
        let q = DVector::from_element(n, -1.0);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for (what, i) in [("M", n * n - 1), ("M", 0), ("q", n - 1)] {
                let (mut mb, mut qb) = (m.clone(), q.clone());
                if what == "M" {
                    mb[(i / n, i % n)] = bad;
                } else {
                    qb[i] = bad;
                }
                for use_warm in [false, true] {
                    let mut solver = LemkeSolver::default();
                    let mut warm = WarmStart::default();
                    let good = solver
                        .solve_warm(m.as_view(), q.as_view(), &mut warm)
                        .unwrap();
                    assert_eq!(good.status, LcpStatus::Solved);
                    let result = if use_warm {
                        solver.solve_warm(mb.as_view(), qb.as_view(), &mut warm)
                    } else {
                        solver.solve(mb.as_view(), qb.as_view())
                    };
                    let expected = LcpInputError::NonFinite { what, index: i };
                    assert!(
                        matches!(&result, Err(e) if same_error(e, &expected)),
                        "n = {n}, {what}[{i}] = {bad}: {result:?}"
                    );
                }
            }
        }
    }
    let m = DMatrix::from_diagonal_element(4, 4, 1e308);
    let q = DVector::from_element(4, -1e308);
    let sol = LemkeSolver::default()
        .solve(m.as_view(), q.as_view())
        .unwrap()
        .clone();
    assert_eq!(sol.status, LcpStatus::Solved);
    assert_eq!(sol.z.as_slice(), &[1.0; 4]);
    assert_eq!(sol.certificate.tolerance, 1e-9 * 1e308);
}
