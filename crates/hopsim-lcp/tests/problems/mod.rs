//! Generated LCPs for the property tests of every solver path: the classes on which
//! Lemke's method is complete (P-matrices, positive semidefinite, copositive), degenerate
//! ones, and the frictional contact LCP of docs/physics.md §4.3 built from a random
//! Delassus matrix `G = Wᵀ M⁻¹ W` (with joint-stop rows, as the stepper assembles them).
//! Also an independent check of a claimed solution and the bases a warm start can meet.
#![allow(dead_code)]

use hopsim_lcp::{LcpSolution, LcpStatus, LemkeSolver, WarmStart};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// What is known about a generated problem's solutions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// Every principal minor positive: exactly one solution for every `q`.
    PMatrix,
    /// Symmetric positive semidefinite (singular in general), `q` built from a solution:
    /// solvable, and every solution has the same `w`.
    Psd,
    /// `xᵀ M x ≥ 0` (positive semidefinite plus skew-symmetric), `q` built from a solution:
    /// copositive-plus and feasible, so Lemke's method solves it.
    Monotone,
    /// Non-negative with a positive diagonal: strictly copositive, solvable for every `q`.
    Copositive,
    /// Small integers, repeated rows, zeros in `q`: degenerate, solvable or not.
    Degenerate,
    /// The frictional contact LCP of docs/physics.md §4.3: no guarantee.
    Contact,
}

impl Class {
    /// Lemke's method with its fallbacks must solve every problem of the class.
    pub fn solvable(self) -> bool {
        matches!(
            self,
            Class::PMatrix | Class::Psd | Class::Monotone | Class::Copositive
        )
    }

    /// Every solution has the same `z`.
    pub fn unique_z(self) -> bool {
        self == Class::PMatrix
    }

    /// Every solution has the same `w` (symmetric positive semidefinite `M`: two solutions
    /// `z¹`, `z²` have `(z¹ − z²)ᵀ M (z¹ − z²) = −z¹ᵀw² − z²ᵀw¹ ≤ 0`, so `M (z¹ − z²) = 0`).
    pub fn unique_w(self) -> bool {
        matches!(self, Class::PMatrix | Class::Psd)
    }
}

/// A generated LCP `w = M z + q`.
#[derive(Debug, Clone)]
pub struct Problem {
    pub class: Class,
    pub m: DMatrix<f64>,
    pub q: DVector<f64>,
}

impl Problem {
    pub fn n(&self) -> usize {
        self.q.len()
    }

    /// The problem with `pad` decoupled rows appended: `M` block-diagonal with a zero
    /// block, `q_e = ‖q‖_∞`. It has the solutions of `(M, q)` with `z_e = 0`, `w_e = q_e`,
    /// the same norms (so the same internal scaling and certificate tolerance), and
    /// Lemke's method takes the same pivots on it: `w_e = q_e + z0` stays positive while
    /// `z0 ≥ 0`, so an appended row never leaves, and a row's updates read only itself
    /// and the pivot row. A size above the specialised ones sends it down the generic
    /// code.
    pub fn embedded(&self, pad: usize) -> Problem {
        let n = self.n();
        let mut m = DMatrix::zeros(n + pad, n + pad);
        m.view_mut((0, 0), (n, n)).copy_from(&self.m);
        let q_norm = self.q.amax();
        let q = DVector::from_fn(n + pad, |i, _| if i < n { self.q[i] } else { q_norm });
        Problem {
            class: self.class,
            m,
            q,
        }
    }
}

/// Entries in `[−1, 1)`.
fn unit() -> impl Strategy<Value = f64> {
    -1.0..1.0f64
}

/// A power of ten in `[1e-3, 1e3]`, to scale `M` or `q`.
fn scale() -> impl Strategy<Value = f64> {
    prop_oneof![Just(1.0), Just(1e-3), Just(1e3)]
}

fn square(n: usize, v: &[f64]) -> DMatrix<f64> {
    DMatrix::from_row_slice(n, n, &v[..n * n])
}

/// A P-matrix: `A Aᵀ + δ I`, or strictly row-diagonally dominant with a positive diagonal
/// (not symmetric); any `q`.
pub fn p_matrix(max_n: usize) -> impl Strategy<Value = Problem> {
    (1..=max_n)
        .prop_flat_map(|n| {
            (
                Just(n),
                prop::collection::vec(unit(), n * n),
                prop::collection::vec(unit(), n),
                any::<bool>(),
                1e-3..1.0f64,
                scale(),
            )
        })
        .prop_map(|(n, a, q, symmetric, delta, s)| {
            let a = square(n, &a);
            let m = if symmetric {
                &a * a.transpose() + DMatrix::identity(n, n) * delta
            } else {
                let mut m = a;
                for i in 0..n {
                    let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[(i, j)].abs()).sum();
                    m[(i, i)] = off + delta;
                }
                m
            };
            Problem {
                class: Class::PMatrix,
                m: m * s,
                q: DVector::from_vec(q),
            }
        })
}

/// A solution `(z, w)` of size `n` to build `q = w − M z` from: `z > 0` on a random
/// support, `w ≥ 0` off it, both with exact zeros (degenerate pairs) now and then.
fn known_solution(n: usize) -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    let value = prop_oneof![1 => Just(0.0), 3 => 0.0..1.0f64];
    (
        prop::collection::vec(any::<bool>(), n),
        prop::collection::vec(value.clone(), n),
        prop::collection::vec(value, n),
    )
        .prop_map(move |(support, z, w)| {
            let z: Vec<f64> = (0..n)
                .map(|i| if support[i] { z[i] } else { 0.0 })
                .collect();
            let w: Vec<f64> = (0..n)
                .map(|i| if support[i] { 0.0 } else { w[i] })
                .collect();
            (z, w)
        })
}

/// `B Bᵀ` (rank `r ≤ n`), plus a skew-symmetric part for [`Class::Monotone`], with `q`
/// built from a known solution; `integer` draws `B` and the solution from small integers
/// (many ties).
pub fn semidefinite(max_n: usize, skew: bool) -> impl Strategy<Value = Problem> {
    (1..=max_n)
        .prop_flat_map(|n| {
            (
                Just(n),
                0..=n,
                prop::collection::vec(unit(), n * n),
                prop::collection::vec(unit(), n * n),
                known_solution(n),
                any::<bool>(),
            )
        })
        .prop_map(move |(n, rank, b, s, (z, w), integer)| {
            let round = |v: f64| if integer { (2.0 * v).round() } else { v };
            let b = DMatrix::from_fn(n, rank, |i, j| round(b[i * n + j]));
            let mut m = &b * b.transpose();
            if skew {
                let s = square(n, &s);
                m += &s - s.transpose();
            }
            let z = DVector::from_iterator(n, z.into_iter().map(round).map(f64::abs));
            let w = DVector::from_iterator(n, w.into_iter().map(round).map(f64::abs));
            let q = w - &m * z;
            let class = if skew { Class::Monotone } else { Class::Psd };
            Problem { class, m, q }
        })
}

/// Non-negative `M` with a positive diagonal and zeros off it now and then; any `q`.
pub fn copositive(max_n: usize) -> impl Strategy<Value = Problem> {
    (1..=max_n)
        .prop_flat_map(|n| {
            (
                Just(n),
                prop::collection::vec(prop_oneof![Just(0.0), 0.0..1.0f64], n * n),
                prop::collection::vec(0.01..1.0f64, n),
                prop::collection::vec(unit(), n),
            )
        })
        .prop_map(|(n, a, d, q)| {
            let mut m = square(n, &a);
            for i in 0..n {
                m[(i, i)] = d[i];
            }
            Problem {
                class: Class::Copositive,
                m,
                q: DVector::from_vec(q),
            }
        })
}

/// Small integers in `M` and `q` (`−1 … 2`, `−1 … 1`), some rows repeated.
pub fn degenerate(max_n: usize) -> impl Strategy<Value = Problem> {
    (1..=max_n)
        .prop_flat_map(|n| {
            (
                Just(n),
                prop::collection::vec(-1..=2i32, n * n),
                prop::collection::vec(-1..=1i32, n),
                prop::collection::vec(0..n, 0..=n / 2),
            )
        })
        .prop_map(|(n, a, q, repeats)| {
            let mut m = DMatrix::from_fn(n, n, |i, j| f64::from(a[i * n + j]));
            let mut q = DVector::from_fn(n, |i, _| f64::from(q[i]));
            for (i, &src) in repeats.iter().enumerate() {
                let dst = (src + 1 + i) % n;
                let row = m.row(src).clone_owned();
                m.set_row(dst, &row);
                q[dst] = q[src];
            }
            Problem {
                class: Class::Degenerate,
                m,
                q,
            }
        })
}

/// Parameters of a contact LCP: `k` contacts, `l` closed joint stops, `dof` coordinates.
#[derive(Debug, Clone)]
pub struct ContactParams {
    pub k: usize,
    pub l: usize,
    pub dof: usize,
    /// `dof × (2k + l)` directions: the columns `W_N`, `W_T`, `W_J`, row-major.
    pub w: Vec<f64>,
    /// `dof × dof`, row-major: the mass matrix is `L Lᵀ + 0.1 I`.
    pub l_mass: Vec<f64>,
    pub mu: Vec<f64>,
    pub eps_n: Vec<f64>,
    pub eps_t: Vec<f64>,
    /// The velocity without contact percussions `ũ` and the start velocity `u^A`.
    pub u_tilde: Vec<f64>,
    pub u_a: Vec<f64>,
    /// Contact 1 repeats contact 0's directions (two rows of one resting edge).
    pub repeat: bool,
}

/// Random contact LCPs of up to `max_k` contacts (and up to two joint stops): `μ` in
/// `[0, 2]`, `ε_N` in `[0, 1]`, `ε_T` in `[−1, 1]` or equal to `ε_N`.
pub fn contact_params(max_k: usize) -> impl Strategy<Value = ContactParams> {
    (1..=max_k, 0..=2usize, 1..=9usize)
        .prop_flat_map(|(k, l, dof)| {
            let cols = 2 * k + l;
            (
                (Just(k), Just(l), Just(dof)),
                prop::collection::vec(unit(), dof * cols),
                prop::collection::vec(unit(), dof * dof),
                prop::collection::vec(prop_oneof![Just(0.0), Just(1.0), 0.0..2.0f64], k),
                prop::collection::vec(prop_oneof![Just(0.0), 0.0..1.0f64], k + l),
                prop::collection::vec(prop_oneof![Just(None), (-1.0..1.0f64).prop_map(Some)], k),
                prop::collection::vec(unit(), 2 * dof),
                any::<bool>(),
            )
        })
        .prop_map(
            |((k, l, dof), w, l_mass, mu, eps_n, eps_t, u, repeat)| ContactParams {
                k,
                l,
                dof,
                w,
                l_mass,
                mu,
                eps_t: (0..k).map(|i| eps_t[i].unwrap_or(eps_n[i])).collect(),
                eps_n,
                u_tilde: u[..dof].to_vec(),
                u_a: u[dof..].to_vec(),
                repeat: repeat && k >= 2,
            },
        )
}

impl ContactParams {
    /// The LCP `w = A z + b` of docs/physics.md §4.3 with the joint stops after it (§7.2):
    /// `z = (Λ_N, Λ_R, ξ_L, Λ_J)`, `w = (ξ_N, ξ_R, Λ_L, ξ_J)`.
    pub fn lcp(&self) -> Problem {
        let (k, l, d) = (self.k, self.l, self.dof);
        let cols = 2 * k + l;
        let mut w = DMatrix::from_row_slice(d, cols, &self.w);
        if self.repeat {
            let (n0, t0) = (w.column(0).clone_owned(), w.column(k).clone_owned());
            w.set_column(1, &n0);
            w.set_column(k + 1, &t0);
        }
        let lm = DMatrix::from_fn(
            d,
            d,
            |i, j| if j <= i { self.l_mass[i * d + j] } else { 0.0 },
        );
        let mass = &lm * lm.transpose() + DMatrix::identity(d, d) * 0.1;
        let g = w.transpose() * mass.cholesky().expect("positive definite").solve(&w);
        let (u_tilde, u_a) = (
            DVector::from_column_slice(&self.u_tilde),
            DVector::from_column_slice(&self.u_a),
        );
        let (gamma_tilde, gamma_a) = (w.transpose() * u_tilde, w.transpose() * u_a);
        let n = 3 * k + l;
        // Indices into G: normal `c`, tangential `k + c`, stop `2k + c`; into A: Λ_N `c`,
        // Λ_R `k + c`, ξ_L `2k + c`, Λ_J `3k + c`.
        let (gn, gt, gj) = (|c: usize| c, |c: usize| k + c, |c: usize| 2 * k + c);
        let mut a = DMatrix::zeros(n, n);
        let mut b = DVector::zeros(n);
        for r in 0..k {
            for c in 0..k {
                let mu = self.mu[c];
                a[(r, c)] = g[(gn(r), gn(c))] - g[(gn(r), gt(c))] * mu;
                a[(r, k + c)] = g[(gn(r), gt(c))];
                a[(k + r, c)] = g[(gt(r), gn(c))] - g[(gt(r), gt(c))] * mu;
                a[(k + r, k + c)] = g[(gt(r), gt(c))];
            }
            for c in 0..l {
                a[(r, 3 * k + c)] = g[(gn(r), gj(c))];
                a[(k + r, 3 * k + c)] = g[(gt(r), gj(c))];
            }
            a[(k + r, 2 * k + r)] = 1.0;
            a[(2 * k + r, r)] = 2.0 * self.mu[r];
            a[(2 * k + r, k + r)] = -1.0;
            b[r] = gamma_tilde[gn(r)] + self.eps_n[r] * gamma_a[gn(r)];
            b[k + r] = gamma_tilde[gt(r)] + self.eps_t[r] * gamma_a[gt(r)];
        }
        for r in 0..l {
            for c in 0..k {
                a[(3 * k + r, c)] = g[(gj(r), gn(c))] - g[(gj(r), gt(c))] * self.mu[c];
                a[(3 * k + r, k + c)] = g[(gj(r), gt(c))];
            }
            for c in 0..l {
                a[(3 * k + r, 3 * k + c)] = g[(gj(r), gj(c))];
            }
            b[3 * k + r] = gamma_tilde[gj(r)] + self.eps_n[k + r] * gamma_a[gj(r)];
        }
        Problem {
            class: Class::Contact,
            m: a,
            q: b,
        }
    }
}

/// Contact LCPs of up to `max_k` contacts (see [`contact_params`]).
pub fn contact(max_k: usize) -> impl Strategy<Value = Problem> {
    contact_params(max_k).prop_map(|p| p.lcp())
}

/// Any of the classes, of size up to `max_n` (contact LCPs up to `3⌈max_n/3⌉ + 2`).
pub fn any_problem(max_n: usize) -> impl Strategy<Value = Problem> {
    prop_oneof![
        p_matrix(max_n),
        semidefinite(max_n, false),
        semidefinite(max_n, true),
        copositive(max_n),
        degenerate(max_n),
        contact(max_n.div_ceil(3)),
    ]
}

/// `‖M‖_∞`, the largest absolute row sum.
pub fn norm_inf(m: &DMatrix<f64>) -> f64 {
    (0..m.nrows())
        .map(|i| m.row(i).iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// The certificate of any answer (solved or not) is what docs/lcp.md defines, recomputed
/// here from `M`, `q` and the reported `z`, `w`: `complementarity = max_i |min(‖M‖ z_i,
/// w_i)|`, `most_negative = min(0, ‖M‖ min z, min w)`, `residual = ‖w − M z − q‖_∞`,
/// `tolerance = rel_tol · max(‖q‖_∞, ‖M‖_∞ ‖z‖_∞)`, to round-off.
pub fn check_certificate(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    sol: &LcpSolution,
    rel_tol: f64,
) -> Result<(), TestCaseError> {
    let c = &sol.certificate;
    if q.is_empty() {
        // Nothing to measure.
        prop_assert_eq!(*c, hopsim_lcp::Certificate::default());
        return Ok(());
    }
    let m_norm = norm_inf(m);
    let unit = if m_norm > 0.0 { m_norm } else { 1.0 };
    let (z, w) = (&sol.z, &sol.w);
    let r = m * z + q;
    let size = q.amax().max(m_norm * z.amax()).max(w.amax());
    if !size.is_finite() {
        return Ok(());
    }
    let round_off = 1e-13 * size;
    let mut expected = [0.0f64; 3];
    for i in 0..q.len() {
        let low = (unit * z[i]).min(w[i]);
        expected[0] = expected[0].max(low.abs());
        expected[1] = expected[1].min(low);
        expected[2] = expected[2].max((w[i] - r[i]).abs());
    }
    prop_assert!(
        (c.matrix_norm - m_norm).abs() <= 1e-14 * m_norm,
        "matrix_norm: {} reported, {} expected",
        c.matrix_norm,
        m_norm
    );
    let reported = [c.complementarity, c.most_negative, c.residual];
    for (name, (e, r)) in ["complementarity", "most_negative", "residual"]
        .iter()
        .zip(expected.iter().zip(reported))
    {
        prop_assert!(
            (e - r).abs() <= round_off,
            "{}: {} reported, {} expected",
            name,
            r,
            e
        );
    }
    let scale = q.amax().max(m_norm * z.amax()).max(f64::MIN_POSITIVE);
    let tolerance = rel_tol * scale;
    prop_assert!(
        (c.tolerance - tolerance).abs() <= 1e-12 * tolerance,
        "tolerance {} reported, {} expected",
        c.tolerance,
        tolerance
    );
    Ok(())
}

/// Independent check (plain nalgebra, not the crate's certificate) that `sol` is a
/// solution to the tolerance of its certificate, which is the one docs/lcp.md defines with
/// the default `rel_tol = 1e-9` (see [`check_certificate`]): `z ≥ 0`, `w = M z + q ≥ 0`
/// and `min(‖M‖_∞ z_i, w_i) = 0`, each within `tol` (in the units of `w`).
pub fn check_solution(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    sol: &LcpSolution,
) -> Result<(), TestCaseError> {
    prop_assert_eq!(sol.status, LcpStatus::Solved);
    prop_assert!(sol.certificate.holds(), "{:?}", sol.certificate);
    check_certificate(m, q, sol, 1e-9)?;
    let m_norm = norm_inf(m);
    let unit = if m_norm > 0.0 { m_norm } else { 1.0 };
    let w = m * &sol.z + q;
    let scale = q.amax().max(m_norm * sol.z.amax());
    // The certificate's own tolerance, plus round-off of this different summation order.
    let tol = sol.certificate.tolerance + 1e-13 * scale;
    for i in 0..q.len() {
        let (zi, wi) = (unit * sol.z[i], w[i]);
        prop_assert!(zi >= -tol, "z[{}] = {}", i, sol.z[i]);
        prop_assert!(wi >= -tol, "w[{}] = {}", i, wi);
        prop_assert!(
            zi.min(wi).abs() <= tol,
            "complementarity at {}: {} {}",
            i,
            zi,
            wi
        );
        prop_assert!(
            (sol.w[i] - wi).abs() <= tol,
            "reported w[{}] = {}, M z + q = {}",
            i,
            sol.w[i],
            wi
        );
    }
    Ok(())
}

/// A remembered basis to start a warm solve of size `n` from.
#[derive(Debug, Clone)]
pub enum Basis {
    /// Nothing remembered.
    None,
    /// `z = 0` certified (every contact open): the empty basis.
    Empty,
    /// Every `z_i` basic.
    Full,
    /// `z_i` basic where the flag is set (flags beyond `n` ignored).
    Subset(Vec<bool>),
    /// The basis of the answer to another problem of the same size.
    Stale(Problem),
    /// A basis of another size.
    OtherSize(usize),
    /// The basis of the problem's own answer for `q` moved by `δ` times this vector.
    Drift(Vec<f64>),
}

/// Remembered bases for problems of size `n`; `Stale` draws another problem of the same
/// class only through `stale`.
pub fn basis(stale: impl Strategy<Value = Problem> + 'static) -> impl Strategy<Value = Basis> {
    prop_oneof![
        Just(Basis::None),
        Just(Basis::Empty),
        Just(Basis::Full),
        prop::collection::vec(any::<bool>(), 20).prop_map(Basis::Subset),
        stale.prop_map(Basis::Stale),
        (1..20usize).prop_map(Basis::OtherSize),
        prop::collection::vec(unit(), 20).prop_map(Basis::Drift),
    ]
}

/// `(I, q)` with `q_i = −1` where `basic[i]`, else `1`: its answer `z_i = 1` on the basis
/// leaves exactly that basis in a warm start.
pub fn identity_with_basis(basic: &[bool]) -> (DMatrix<f64>, DVector<f64>) {
    let n = basic.len();
    let q = DVector::from_fn(n, |i, _| if basic[i] { -1.0 } else { 1.0 });
    (DMatrix::identity(n, n), q)
}

/// Leaves `basis` (for the problem `p`) in `warm`, by solving with `solver`.
pub fn remember(solver: &mut LemkeSolver, warm: &mut WarmStart, basis: &Basis, p: &Problem) {
    let n = p.n();
    let mut solve = |m: &DMatrix<f64>, q: &DVector<f64>| {
        solver
            .solve_warm(m.as_view(), q.as_view(), warm)
            .expect("valid data");
    };
    match basis {
        Basis::None => warm.forget(),
        Basis::Empty => {
            let (m, q) = identity_with_basis(&vec![false; n]);
            solve(&m, &q);
        }
        Basis::Full => {
            let (m, q) = identity_with_basis(&vec![true; n]);
            solve(&m, &q);
        }
        Basis::Subset(flags) => {
            let flags: Vec<bool> = (0..n).map(|i| flags[i % flags.len()]).collect();
            let (m, q) = identity_with_basis(&flags);
            solve(&m, &q);
        }
        Basis::Stale(other) => {
            let other = resized(other, n);
            solve(&other.m, &other.q);
        }
        Basis::OtherSize(size) => {
            let size = if *size == n { n + 1 } else { *size };
            let (m, q) = identity_with_basis(&vec![true; size]);
            solve(&m, &q);
        }
        Basis::Drift(_) => solve(&p.m, &p.q),
    }
}

/// The problem a warm solve after [`remember`] answers: `p`, or for [`Basis::Drift`] `p`
/// with `q` moved by `1e-3 ‖q‖_∞` times the drift. (For the classes whose `q` was built
/// from a solution, upwards only: the solution stays feasible, which is all a
/// copositive-plus LCP needs to be solvable.)
pub fn target(basis: &Basis, p: &Problem) -> Problem {
    let mut p = p.clone();
    if let Basis::Drift(d) = basis {
        let s = 1e-3 * p.q.amax();
        let up = matches!(p.class, Class::Psd | Class::Monotone);
        for i in 0..p.n() {
            let di = d[i % d.len()];
            p.q[i] += s * if up { di.abs() } else { di };
        }
    }
    p
}

/// `p` cut or padded (decoupled rows, see [`Problem::embedded`]) to size `n`.
fn resized(p: &Problem, n: usize) -> Problem {
    if p.n() >= n {
        Problem {
            class: p.class,
            m: p.m.view((0, 0), (n, n)).clone_owned(),
            q: p.q.rows(0, n).clone_owned(),
        }
    } else {
        p.embedded(n - p.n())
    }
}
