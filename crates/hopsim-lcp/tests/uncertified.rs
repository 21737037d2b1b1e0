//! Which contact LCPs end uncertified, and why (docs/lcp.md, "Uncertified solves").
//!
//! `census` (ignored; `CENSUS_CASES=20000 cargo test -p hopsim-lcp --release --test
//! uncertified -- --ignored --nocapture`) draws contact LCPs from the generator of
//! `problems/mod.rs` and sorts the failures by kind; the other tests hold each kind.

mod problems;

use hopsim_lcp::{LcpStatus, LemkeOptions, LemkeSolver, SolveMethod};
use nalgebra::{DMatrix, DVector};
use problems::{contact_params, ContactParams};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::TestRunner;

/// Every complementary basis whose solution satisfies the LCP to `tol` (relative to the
/// problem's scale), found by nalgebra's LU, and the smallest relative pivot among them.
fn brute_force(m: &DMatrix<f64>, q: &DVector<f64>, tol: f64) -> Vec<(DVector<f64>, f64)> {
    let n = q.len();
    let m_norm = problems::norm_inf(m);
    let mut out = Vec::new();
    for mask in 0u32..1 << n {
        let s: Vec<usize> = (0..n).filter(|j| mask & (1 << j) != 0).collect();
        let mut z = DVector::zeros(n);
        let mut conditioning = 1.0;
        if !s.is_empty() {
            let a = DMatrix::from_fn(s.len(), s.len(), |i, j| m[(s[i], s[j])]);
            let svd = a.clone().svd(false, false);
            let sv = &svd.singular_values;
            conditioning = sv.min() / sv.max().max(f64::MIN_POSITIVE);
            let b = DVector::from_fn(s.len(), |i, _| -q[s[i]]);
            let Some(x) = a.lu().solve(&b) else { continue };
            for (k, &j) in s.iter().enumerate() {
                z[j] = x[k];
            }
        }
        let w = m * &z + q;
        let scale = q.amax().max(m_norm * z.amax());
        let t = tol * scale;
        let unit = m_norm.max(f64::MIN_POSITIVE);
        let ok = (0..n).all(|i| {
            let zi = unit * z[i];
            zi >= -t && w[i] >= -t && zi.min(w[i]).abs() <= t
        });
        if ok && z.iter().all(|v| v.is_finite()) {
            out.push((z, conditioning));
        }
    }
    out
}

#[derive(Debug, Default)]
struct Census {
    problems: usize,
    failed: usize,
    by_status: std::collections::BTreeMap<&'static str, usize>,
    /// Failures with a solution to the certificate's tolerance (brute force).
    solvable: usize,
    /// Failures whose only solutions are numerically singular bases.
    singular_only: usize,
    /// Failures with no solution even at a 1e-6 tolerance.
    unsolvable: usize,
    /// Failures by contacts, `μ > 1`, `ε_T ≠ ε_N`, a repeated contact.
    by_contacts: [usize; 8],
    mu_above_one: usize,
    eps_differ: usize,
    repeated: usize,
    rank_deficient: usize,
    /// Failures a retry on `M + δ‖M‖ I` (δ = 1e-12, 1e-10, 1e-8, 1e-6) solves to the
    /// original problem's tolerance.
    rescued: [usize; 4],
    /// Rescued answers by decade of `‖M‖ ‖z‖ / ‖q‖` (index 0: below 1).
    rho: [[usize; 12]; 4],
    /// The smallest such ratio among the brute-force solutions.
    rho_brute: [usize; 12],
    /// (problems, failures) by (G singular, some μ > 1, some ε_T ≠ ε_N).
    by_features: std::collections::BTreeMap<(bool, bool, bool), (usize, usize)>,
    rho_solved: [usize; 12],
}

/// Draws contact LCPs and sorts the uncertified ones (see the module doc).
#[test]
#[ignore]
fn census() {
    let cases: usize = std::env::var("CENSUS_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let mut runner = TestRunner::deterministic();
    let strategy = contact_params(5);
    let mut solver = LemkeSolver::default();
    let mut c = Census::default();
    let mut examples: Vec<ContactParams> = Vec::new();
    let mut solvable: Vec<ContactParams> = Vec::new();
    let mut smallest: Option<ContactParams> = None;
    for _ in 0..cases {
        let params = strategy.new_tree(&mut runner).unwrap().current();
        let p = params.lcp();
        c.problems += 1;
        let sol = solver.solve(p.m.as_view(), p.q.as_view()).unwrap();
        let key = (
            params.dof < 2 * params.k + params.l,
            params.mu.iter().any(|&mu| mu > 1.0),
            (0..params.k).any(|i| params.eps_t[i] != params.eps_n[i]),
        );
        let e = c.by_features.entry(key).or_default();
        e.0 += 1;
        e.1 += usize::from(sol.status != LcpStatus::Solved);
        if sol.status == LcpStatus::Solved {
            let rho = problems::norm_inf(&p.m) * sol.z.amax() / p.q.amax();
            if rho.is_finite() && rho > 0.0 {
                c.rho_solved[(rho.log10().floor().clamp(-1.0, 10.0) + 1.0) as usize] += 1;
            }
            continue;
        }
        if p.n()
            < smallest
                .as_ref()
                .map_or(usize::MAX, |s: &ContactParams| s.lcp().n())
        {
            smallest = Some(params.clone());
        }
        c.failed += 1;
        *c.by_status.entry(sol.status.as_str()).or_default() += 1;
        c.by_contacts[params.k] += 1;
        c.mu_above_one += usize::from(params.mu.iter().any(|&mu| mu > 1.0));
        c.eps_differ += usize::from((0..params.k).any(|i| params.eps_t[i] != params.eps_n[i]));
        c.repeated += usize::from(params.repeat);
        if p.n() <= 17 {
            let found = brute_force(&p.m, &p.q, 1e-9);
            let m_norm = problems::norm_inf(&p.m);
            let best = found
                .iter()
                .map(|(z, _)| m_norm * z.amax() / p.q.amax())
                .fold(f64::INFINITY, f64::min);
            if best.is_finite() {
                let k = (best.log10().floor().clamp(-1.0, 10.0) + 1.0) as usize;
                c.rho_brute[k] += 1;
            }
            if found.iter().any(|(_, cond)| *cond > 1e-12) {
                c.solvable += 1;
                solvable.push(params.clone());
            } else if !found.is_empty() {
                c.singular_only += 1;
            } else if brute_force(&p.m, &p.q, 1e-6).is_empty() {
                c.unsolvable += 1;
            }
        }
        // Experiment: a regularised retry, certified against the original problem.
        let m_norm = problems::norm_inf(&p.m);
        for (slot, delta) in [1e-12, 1e-10, 1e-8, 1e-6].iter().enumerate() {
            let mr = &p.m + DMatrix::identity(p.n(), p.n()) * (delta * m_norm);
            let r = LemkeSolver::default()
                .solve(mr.as_view(), p.q.as_view())
                .unwrap()
                .clone();
            if r.status == LcpStatus::Solved {
                let w = &p.m * &r.z + &p.q;
                let scale = p.q.amax().max(m_norm * r.z.amax());
                let t = 1e-9 * scale;
                let ok = (0..p.n()).all(|i| {
                    let zi = m_norm * r.z[i];
                    zi >= -t && w[i] >= -t && zi.min(w[i]).abs() <= t
                });
                if ok {
                    c.rescued[slot] += 1;
                    let rho = m_norm * r.z.amax() / p.q.amax();
                    let k = (rho.log10().floor().clamp(-1.0, 10.0) + 1.0) as usize;
                    c.rho[slot][k] += 1;
                }
            }
        }
        let rank_deficient = params.dof < 2 * params.k + params.l;
        c.rank_deficient += usize::from(rank_deficient);
        if examples.len() < 3 {
            examples.push(params);
        }
    }
    println!("{c:#?}");
    println!("smallest: {smallest:?}");
    for params in &solvable {
        let p = params.lcp();
        let n = p.n();
        let m_norm = problems::norm_inf(&p.m);
        let rho = |z: &DVector<f64>| m_norm * z.amax() / p.q.amax();
        let found = brute_force(&p.m, &p.q, 1e-9);
        let sizes: Vec<f64> = found.iter().map(|(z, _)| rho(z)).collect();
        println!("{params:?}");
        let mut line = format!(
            "n = {n}, k = {}, dof = {}, solutions ρ {:?}",
            params.k,
            params.dof,
            sizes.iter().map(|r| format!("{r:.1e}")).collect::<Vec<_>>()
        );
        let e = LemkeSolver::new(LemkeOptions {
            enumeration_limit: 20,
            ..Default::default()
        })
        .solve(p.m.as_view(), p.q.as_view())
        .unwrap()
        .clone();
        line += &format!("; enumeration {} ρ {:.2e}", e.status, rho(&e.z));
        let mut rng = problems_rng(n as u64);
        let mut tries = 0;
        for t in 0..200 {
            let d: Vec<f64> = (0..n).map(|_| 0.5 + rng()).collect();
            let r = LemkeSolver::new(LemkeOptions {
                covering: Some(d),
                fallback: false,
                ..Default::default()
            })
            .solve(p.m.as_view(), p.q.as_view())
            .unwrap()
            .clone();
            if r.status == LcpStatus::Solved {
                tries = t + 1;
                line += &format!("; random covering #{tries} ρ {:.2e}", rho(&r.z));
                break;
            }
        }
        if tries == 0 {
            line += "; no random covering";
        }
        for delta in [1e-14, 1e-12, 1e-10] {
            let mr = &p.m + DMatrix::identity(n, n) * (delta * m_norm);
            let r = LemkeSolver::default()
                .solve(mr.as_view(), p.q.as_view())
                .unwrap()
                .clone();
            line += &format!("; δ {delta:e}: {} ρ {:.2e}", r.status, rho(&r.z));
        }
        println!("{line}");
    }
    for e in examples {
        println!("{e:?}");
    }
}

fn problems_rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// One coordinate `u` (mass 1) and one contact whose normal and tangential velocities both
/// follow it, `γ_N = a u`, `γ_T = b u` with `a = −1/2`, `b = 1` (a slider on a rail
/// touching a surface at an angle: `G` has rank 1); `ũ = 1`, `u^A = 1`, `ε_N = 0`.
fn rail(mu: f64, eps_t: f64) -> problems::Problem {
    ContactParams {
        k: 1,
        l: 0,
        dof: 1,
        w: vec![-0.5, 1.0],
        l_mass: vec![0.9f64.sqrt()],
        mu: vec![mu],
        eps_n: vec![0.0],
        eps_t: vec![eps_t],
        u_tilde: vec![1.0],
        u_a: vec![1.0],
        repeat: false,
    }
    .lcp()
}

/// Genuinely unsolvable: Newton's tangential restitution against a coupled normal. On
/// the rail, `Λ_N > 0` needs `ξ_N = a u^E = 0`, so `u^E = 0`; then `ξ_T = ε_T b u^A =
/// ε_T`. With `ε_T = −1/2` the contact slides along `−t`, so `Λ_T = μ Λ_N` and `u^E = 1 +
/// (a + μ b) Λ_N = 1 − (1/2 − μ) Λ_N`: `Λ_N = 1/(1/2 − μ)` for `μ < 1/2`, and no solution
/// for `μ ≥ 1/2` (friction would drive the contact deeper). With `ε_T = ε_N` it sticks:
/// `Λ_T = Λ_N/2 − 1`, and every `Λ_N ≥ 1/(1/2 + μ)` (up to `1/(1/2 − μ)` for `μ < 1/2`)
/// solves: for `μ ≥ 1/2` an unbounded set, the indeterminacy of a jam.
#[test]
fn newton_tangential_restitution_on_a_rail_has_no_solution_above_the_critical_friction() {
    let mut solver = LemkeSolver::default();
    // Below μ* = |a|/b = 1/2: the closed form.
    let p = rail(0.25, -0.5);
    let sol = solver.solve(p.m.as_view(), p.q.as_view()).unwrap();
    assert_eq!(sol.status, LcpStatus::Solved);
    let (lambda_n, lambda_t) = (sol.z[0], sol.z[1] - 0.25 * sol.z[0]);
    assert!(
        (lambda_n - 4.0).abs() <= 1e-12 && (lambda_t - 1.0).abs() <= 1e-12,
        "{}",
        sol.z
    );
    // Above it: no solution, though Lemke's method, the other covering vectors and the
    // enumeration of all 8 bases ran.
    for mu in [0.5, 0.75, 2.0] {
        let p = rail(mu, -0.5);
        let sol = solver.solve(p.m.as_view(), p.q.as_view()).unwrap();
        assert_eq!(sol.status, LcpStatus::RayTermination, "μ = {mu}");
        assert!(!sol.certificate.holds());
    }
    // With ε_T = ε_N the same contact sticks, with any Λ_N from 1/(1/2 + μ) up.
    for mu in [0.25, 0.75, 2.0] {
        let p = rail(mu, 0.0);
        let sol = solver.solve(p.m.as_view(), p.q.as_view()).unwrap();
        assert_eq!(sol.status, LcpStatus::Solved, "μ = {mu}");
        let (lambda_n, lambda_t) = (sol.z[0], sol.z[1] - mu * sol.z[0]);
        let u_end = 1.0 - 0.5 * lambda_n + lambda_t;
        assert!(u_end.abs() <= 1e-12, "μ = {mu}: u^E = {u_end}");
        assert!(
            lambda_n >= 1.0 / (0.5 + mu) - 1e-12,
            "μ = {mu}: Λ_N = {lambda_n}"
        );
        assert!(lambda_t.abs() <= mu * lambda_n + 1e-12);
    }
}

/// A solvable problem above the enumeration limit can end on a ray: three contacts and
/// two joint stops on one coordinate (`n = 11`, drawn by `census`). Lemke's method ends
/// on a ray with every covering vector; the enumeration, allowed up to 11, finds the
/// solution, whose size is that of the data (`‖M‖ ‖z‖ / ‖q‖ = 1.4`).
#[test]
fn a_solvable_problem_above_the_enumeration_limit_may_end_on_a_ray() {
    let p = ContactParams {
        k: 3,
        l: 2,
        dof: 1,
        w: vec![
            -0.31026460409551476,
            0.671760798370388,
            -0.21311263957757387,
            -0.6126388173584498,
            -0.12350898803851092,
            0.7362078861481578,
            0.4051152059599322,
            0.3871378548954246,
        ],
        l_mass: vec![-0.753491903693063],
        mu: vec![1.0, 0.0, 0.3920716485293164],
        eps_n: vec![0.0; 5],
        eps_t: vec![-0.9225365651983336, 0.627208631750387, 0.0],
        u_tilde: vec![0.07891402473839325],
        u_a: vec![0.7676791074961611],
        repeat: false,
    }
    .lcp();
    assert_eq!(p.n(), 11);
    let default = LemkeSolver::default()
        .solve(p.m.as_view(), p.q.as_view())
        .unwrap()
        .clone();
    assert_eq!(default.status, LcpStatus::RayTermination);
    let options = LemkeOptions {
        enumeration_limit: 11,
        ..LemkeOptions::default()
    };
    let sol = LemkeSolver::new(options)
        .solve(p.m.as_view(), p.q.as_view())
        .unwrap()
        .clone();
    assert_eq!(
        (sol.status, sol.method),
        (LcpStatus::Solved, SolveMethod::Enumeration)
    );
    problems::check_solution(&p.m, &p.q, &sol).unwrap();
    let rho = problems::norm_inf(&p.m) * sol.z.amax() / p.q.amax();
    assert!(rho < 10.0, "‖M‖ ‖z‖ / ‖q‖ = {rho}");
}

proptest::proptest! {
    #![proptest_config(proptest::test_runner::Config::with_cases(3000))]

    /// Degenerate problems do not end uncertified: with independent contact directions
    /// (at least as many coordinates as directions, so `G` is positive definite) every
    /// contact LCP is solved, at any `μ ≤ 2` and restitution, whatever ties its data make
    /// (`μ = 0`, `μ = 1`, `ε = 0` drawn often).
    #[test]
    fn contact_lcps_with_independent_directions_are_always_solved(
        params in contact_params(4).prop_filter("independent directions", |p| {
            !p.repeat && p.dof >= 2 * p.k + p.l
        })
    ) {
        let p = params.lcp();
        let sol = LemkeSolver::default().solve(p.m.as_view(), p.q.as_view()).unwrap().clone();
        problems::check_solution(&p.m, &p.q, &sol)?;
    }
}
