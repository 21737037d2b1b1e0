//! Differential tests of every solver path on generated problems (`problems/mod.rs`):
//!
//! - the warm start against the cold solve, for every remembered basis (none, empty, full,
//!   partial, stale, of another size, of a drifting `q`) and every size the warm path
//!   compiles on its own (1 … 6) or shares (7 and up);
//! - the code compiled for each small size (`n ≤ 12` in the cold hot path, `n ≤ 6` in the
//!   warm path, the pivot row by index, the last pair of rows when `n mod 4` is 1 or 2)
//!   against the generic code, by embedding the problem in a larger one that Lemke's
//!   method pivots on identically (see `Problem::embedded`): bit for bit.

mod problems;

use hopsim_lcp::{LcpSolution, LcpStatus, LemkeOptions, LemkeSolver, SolveMethod, WarmStart};
use nalgebra::DVector;
use problems::{
    any_problem, basis, check_certificate, check_solution, remember, target, Basis, Problem,
};
use proptest::prelude::*;

/// Lemke's method alone: the fallbacks' covering vectors depend on `n`, so an embedded
/// problem would try others.
fn no_fallback() -> LemkeOptions {
    LemkeOptions {
        fallback: false,
        ..LemkeOptions::default()
    }
}

fn cold(p: &Problem, options: LemkeOptions) -> LcpSolution {
    LemkeSolver::new(options)
        .solve(p.m.as_view(), p.q.as_view())
        .expect("valid data")
        .clone()
}

/// `|a − b|_∞` relative to `max(1, |b|_∞)`.
fn rel_diff(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

/// The warm answer `sol` to `p` against the cold answer `cold`, the warm start having
/// remembered `before`.
fn agree(
    p: &Problem,
    cold: &LcpSolution,
    sol: &LcpSolution,
    before: Option<&[bool]>,
) -> Result<(), TestCaseError> {
    if p.class.solvable() {
        // Lemke's method alone processes these classes (Murty, §2.3): no fallback needed.
        prop_assert_eq!(cold.status, LcpStatus::Solved, "{:?} must solve", p.class);
        prop_assert!(
            matches!(cold.method, SolveMethod::Trivial | SolveMethod::Lemke),
            "{:?} solved by {}",
            p.class,
            cold.method
        );
    }
    check_certificate(&p.m, &p.q, cold, 1e-9)?;
    if cold.status == LcpStatus::Solved {
        check_solution(&p.m, &p.q, cold)?;
    }
    if sol.method != SolveMethod::WarmStart {
        // The remembered basis did not answer: the ordinary solve did, as on its own.
        prop_assert_eq!(sol, cold);
        return Ok(());
    }
    // A warm answer solves the remembered basis: z = 0 off it, w = 0 on it.
    prop_assert_eq!(sol.pivots, 0);
    check_solution(&p.m, &p.q, sol)?;
    let before = before.expect("a warm answer needs a remembered basis");
    prop_assert_eq!(before.len(), p.n());
    for (i, &basic) in before.iter().enumerate() {
        let off = if basic { sol.w[i] } else { sol.z[i] };
        prop_assert!(
            off == 0.0,
            "entry {} off the basis {:?}: {}",
            i,
            before,
            off
        );
    }
    if cold.status == LcpStatus::Solved {
        if p.class.unique_z() {
            let dz = rel_diff(&sol.z, &cold.z);
            prop_assert!(dz <= 1e-9, "z differs by {:e}: {} vs {}", dz, sol.z, cold.z);
        }
        if p.class.unique_w() {
            let dw = rel_diff(&sol.w, &cold.w);
            prop_assert!(dw <= 1e-9, "w differs by {:e}: {} vs {}", dw, sol.w, cold.w);
        }
    } else {
        // Lemke's method is complete on the solvable classes; elsewhere a warm start may
        // keep a solution it did not find (checked above).
        prop_assert!(!p.class.solvable());
    }
    Ok(())
}

/// After a solve, the warm start remembers the basis that answered: the remembered one
/// (`before`) for a warm answer, else the answer's `z_i > w_i`, or nothing after a
/// failure.
fn remembers(
    warm: &WarmStart,
    sol: &LcpSolution,
    before: Option<&[bool]>,
) -> Result<(), TestCaseError> {
    let expected: Option<Vec<bool>> = if sol.method == SolveMethod::WarmStart {
        before.map(<[bool]>::to_vec)
    } else {
        (sol.status == LcpStatus::Solved && !sol.z.is_empty())
            .then(|| sol.z.iter().zip(sol.w.iter()).map(|(z, w)| z > w).collect())
    };
    prop_assert_eq!(warm.basis().map(<[bool]>::to_vec), expected);
    Ok(())
}

/// What one case of [`a_warm_start_agrees_with_the_cold_solve`] exercised.
#[derive(Default, Debug)]
struct Tally {
    /// Warm answers, per size.
    warm: [usize; 24],
    /// Warm attempts that fell back to the ordinary solve, per size.
    fell_back: [usize; 24],
    /// Empty remembered bases met by a `q` with a negative entry, above the sizes the warm
    /// path compiles on its own.
    empty_generic: usize,
    /// Both failed; the warm start alone solved.
    failed_both: usize,
    warm_only: usize,
}

/// Every class, size 1 … 16 (contact LCPs up to 20), every kind of remembered basis: the
/// warm answer is the cold one (or, where the solution is not unique, another certified
/// solution with the remembered basis), and both fail together on the classes Lemke's
/// method is complete on. The tally shows every size took both ways.
#[test]
fn a_warm_start_agrees_with_the_cold_solve() {
    let tally = std::cell::RefCell::new(Tally::default());
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig::with_cases(4000));
    let strategy = (any_problem(16), basis(any_problem(16)));
    let result = runner.run(&strategy, |(p, start)| {
        let mut solver = LemkeSolver::default();
        let mut warm = WarmStart::default();
        remember(&mut solver, &mut warm, &start, &p);
        let before = warm.basis().map(<[bool]>::to_vec);
        let t = target(&start, &p);
        let cold = cold(&t, LemkeOptions::default());
        let sol = solver
            .solve_warm(t.m.as_view(), t.q.as_view(), &mut warm)
            .expect("valid data")
            .clone();
        agree(&t, &cold, &sol, before.as_deref())?;
        remembers(&warm, &sol, before.as_deref())?;
        let mut tally = tally.borrow_mut();
        let n = t.n();
        match (sol.method, before.as_deref()) {
            (SolveMethod::WarmStart, _) => tally.warm[n] += 1,
            (_, Some(b)) if b.len() == n && t.q.min() < 0.0 => {
                tally.fell_back[n] += 1;
                tally.empty_generic += usize::from(n > 6 && !b.contains(&true));
            }
            _ => {}
        }
        match (sol.status, cold.status) {
            (LcpStatus::Solved, LcpStatus::Solved) => {}
            (LcpStatus::Solved, _) => tally.warm_only += 1,
            _ => tally.failed_both += 1,
        }
        // The same problem again: a P-matrix answer's own basis answers it warm.
        if sol.status == LcpStatus::Solved && t.class.unique_z() && t.q.min() < 0.0 {
            let again = solver
                .solve_warm(t.m.as_view(), t.q.as_view(), &mut warm)
                .expect("valid data")
                .clone();
            prop_assert_eq!(again.method, SolveMethod::WarmStart);
            prop_assert!(rel_diff(&again.z, &sol.z) <= 1e-12);
        }
        Ok(())
    });
    let tally = tally.into_inner();
    println!("{tally:?}");
    if let Err(e) = result {
        panic!("{e}");
    }
    for n in 1..=16 {
        assert!(
            tally.warm[n] > 0 && tally.fell_back[n] > 0,
            "size {n} not covered: {tally:?}"
        );
    }
    assert!(tally.empty_generic > 0, "{tally:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The copies of the cold hot path compiled for `n ≤ 12` (and the generic one for
    /// larger `n`) give bit for bit what the generic code gives on the problem embedded
    /// in a larger one: status, method, pivots, certificate, `z`, `w`.
    #[test]
    fn the_sized_cold_paths_agree_with_the_generic_one_bit_for_bit(
        p in any_problem(16),
        pad in 1..=16usize,
    ) {
        let big = p.embedded(pad);
        let small = cold(&p, no_fallback());
        let large = cold(&big, no_fallback());
        same_on_embedding(&p, &small, &large)?;
    }

    /// The warm path's copies for `n ≤ 6` (basis solved on the stack, one elimination per
    /// basis size) against the generic warm path (heap scratch), from the same basis.
    #[test]
    fn the_sized_warm_paths_agree_with_the_generic_one_bit_for_bit(
        p in any_problem(8),
        pad in 1..=8usize,
        flags in prop::collection::vec(any::<bool>(), 24),
    ) {
        let n = p.n();
        let big = p.embedded(pad);
        let mut answers = Vec::new();
        for (q, size) in [(&p, n), (&big, n + pad)] {
            let mut solver = LemkeSolver::new(no_fallback());
            let mut warm = WarmStart::default();
            let basic: Vec<bool> = (0..size).map(|i| i < n && flags[i]).collect();
            let start = Basis::Subset(basic);
            remember(&mut solver, &mut warm, &start, q);
            let sol = solver
                .solve_warm(q.m.as_view(), q.q.as_view(), &mut warm)
                .expect("valid data")
                .clone();
            answers.push(sol);
        }
        same_on_embedding(&p, &answers[0], &answers[1])?;
    }
}

/// `large` (the answer to `p` embedded with decoupled rows) equals `small` (the answer to
/// `p`) on `p`'s rows bit for bit, with the same status, method, pivots and certificate;
/// the appended rows of a solution are `z_e = 0`, `w_e = q_e` (to the round-off of the
/// pivots, which compute `w_e` by row operations).
fn same_on_embedding(
    p: &Problem,
    small: &LcpSolution,
    large: &LcpSolution,
) -> Result<(), TestCaseError> {
    let n = p.n();
    prop_assert_eq!(
        (small.status, small.method, small.pivots),
        (large.status, large.method, large.pivots)
    );
    prop_assert_eq!(small.z.as_slice(), &large.z.as_slice()[..n]);
    prop_assert_eq!(small.w.as_slice(), &large.w.as_slice()[..n]);
    // The appended rows' residual is `|w_e − q_e|` (`z_e = 0`, `M_e· = 0`).
    let q_norm = p.q.amax();
    let off = large
        .w
        .rows(n, large.w.len() - n)
        .add_scalar(-q_norm)
        .amax();
    let (s, l) = (small.certificate, large.certificate);
    prop_assert_eq!(
        (
            s.complementarity,
            s.most_negative,
            s.residual.max(off),
            s.tolerance
        ),
        (l.complementarity, l.most_negative, l.residual, l.tolerance)
    );
    if large.status == LcpStatus::Solved {
        prop_assert!(large.z.rows(n, large.z.len() - n).iter().all(|&z| z == 0.0));
        prop_assert!(off <= 1e-14 * q_norm, "w_e − q_e = {:e}", off);
    }
    Ok(())
}
