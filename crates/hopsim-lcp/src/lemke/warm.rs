//! Warm start from a complementary basis: [`LemkeSolver::solve_warm`].
//!
//! A time-stepper solves one LCP per step, and in a lasting contact (rolling, sticking,
//! sliding the same way) consecutive LCPs share their complementary basis: which `z_i` are
//! positive does not change. Solving that basis directly (`M_BB z_B = −q_B`, `z_N = 0`,
//! `w = M z + q`) and certifying the result on the original data gives the answer without
//! loading a tableau or pivoting. When the remembered basis does not certify (the contact
//! changed mode, a contact opened or closed), the ordinary solve follows, so the answer is
//! always one Lemke's method would accept: the certificate is the same (docs/lcp.md).
//!
//! An LCP with several solutions (e.g. Painlevé's sliding rod with large `μ`, or several
//! touching bodies in a row) may be answered by another of its solutions than the cold
//! solve would pick: the one with the previous step's basis, if it still certifies.

use super::LemkeSolver;
use crate::certificate::{max_abs, vector_stats, MatRef, ProblemRef};
use crate::enumerate;
use crate::tableau::{self, leading_dim};
use crate::{LcpInputError, LcpSolution, LcpStatus, SolveMethod};
use nalgebra::{DMatrixView, DVectorView};

/// The complementary basis of the last certified answer of [`LemkeSolver::solve_warm`]:
/// which `z_i` were basic. Empty at first and after [`WarmStart::forget`].
#[derive(Debug, Clone, Default)]
pub struct WarmStart {
    basic: Vec<bool>,
    /// The indices `i` of the basic `z_i`, increasing.
    index: Vec<usize>,
    /// Size of the remembered basis (0: none).
    n: usize,
}

impl WarmStart {
    /// No basis yet; room for problems of size `capacity` without allocating.
    pub fn with_capacity(capacity: usize) -> Self {
        WarmStart {
            basic: Vec::with_capacity(capacity),
            index: Vec::with_capacity(capacity),
            n: 0,
        }
    }

    /// Drops the remembered basis (the next solve is cold).
    pub fn forget(&mut self) {
        self.n = 0;
    }

    /// The remembered basis: `Some(basic)` with `basic[i]` when `z_i` was basic.
    pub fn basis(&self) -> Option<&[bool]> {
        (self.n > 0).then(|| &self.basic[..self.n])
    }

    /// Remembers the basis of a certified answer (`z_i > w_i`: `z_i` basic; a degenerate
    /// pair `z_i = w_i = 0` counts as non-basic), forgets it otherwise.
    fn remember(&mut self, sol: &LcpSolution) {
        if sol.status != LcpStatus::Solved {
            self.forget();
            return;
        }
        self.basic.clear();
        self.index.clear();
        for (i, (z, w)) in sol.z.iter().zip(sol.w.iter()).enumerate() {
            self.basic.push(z > w);
            if z > w {
                self.index.push(i);
            }
        }
        self.n = sol.z.len();
    }
}

/// A pivot at most `SINGULAR` times the largest entry of `M_BB` makes it singular (as in
/// the enumeration fallback).
const SINGULAR: f64 = 1e-13;

/// Gaussian elimination with partial pivoting of `a x = b` (`K × K`, compiled per `K`:
/// fixed trip counts); `b` becomes the solution. False when a pivot is at most
/// [`SINGULAR`] times the largest entry of `a`, or not finite.
#[inline(always)]
fn solve_small<const K: usize>(a: &mut [[f64; K]; K], b: &mut [f64; K]) -> bool {
    let mut a_max: f64 = 0.0;
    for row in a.iter() {
        for v in row {
            a_max = a_max.max(v.abs());
        }
    }
    let tiny = SINGULAR * a_max;
    for col in 0..K {
        let mut piv = col;
        for r in col + 1..K {
            if a[r][col].abs() > a[piv][col].abs() {
                piv = r;
            }
        }
        let d = a[piv][col];
        if d.abs() <= tiny || !d.is_finite() {
            return false;
        }
        a.swap(piv, col);
        b.swap(piv, col);
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col][col..];
        for (r, row) in lower.iter_mut().enumerate() {
            let f = row[col] / d;
            for (x, p) in row[col..].iter_mut().zip(pivot_row) {
                *x -= f * p;
            }
            b[col + 1 + r] -= f * b[col];
        }
    }
    for r in (0..K).rev() {
        let mut acc = b[r];
        for c in r + 1..K {
            acc -= a[r][c] * b[c];
        }
        b[r] = acc / a[r][r];
    }
    true
}

/// Largest size whose warm path is compiled on its own, with the basis solved on the
/// stack.
const MAX_WARM_FIXED: usize = 6;

/// Gathers `M_BB` and `−q_B` of the `K` basic indices `index` and solves them on the stack
/// with [`solve_small`] compiled for `K` (fixed trip counts); the solution goes to `b`.
#[inline(always)]
fn solve_basis_of_size<const K: usize>(p: &ProblemRef<'_>, index: &[usize], b: &mut [f64]) -> bool {
    let index = &index[..K];
    let b: &mut [f64; K] = (&mut b[..K]).try_into().expect("K entries");
    let mut a = [[0.0; K]; K];
    for ((&i, a_row), b_i) in index.iter().zip(a.iter_mut()).zip(b.iter_mut()) {
        for (&j, a_ij) in index.iter().zip(a_row.iter_mut()) {
            *a_ij = p.m(i, j);
        }
        *b_i = -p.q[i];
    }
    solve_small(&mut a, b)
}

/// [`solve_basis_of_size`] for the size of `index`, which is at most `W ≤
/// MAX_WARM_FIXED`.
#[inline(always)]
fn solve_basis_sized<const W: usize>(p: &ProblemRef<'_>, index: &[usize], b: &mut [f64]) -> bool {
    const _: () = assert!(MAX_WARM_FIXED == 6);
    match index.len() {
        0 => true,
        1 => solve_basis_of_size::<1>(p, index, b),
        2 if W >= 2 => solve_basis_of_size::<2>(p, index, b),
        3 if W >= 3 => solve_basis_of_size::<3>(p, index, b),
        4 if W >= 4 => solve_basis_of_size::<4>(p, index, b),
        5 if W >= 5 => solve_basis_of_size::<5>(p, index, b),
        6 if W >= 6 => solve_basis_of_size::<6>(p, index, b),
        // More basic indices than the size: not a basis of this problem.
        _ => false,
    }
}

/// [`solve_basis_of_size`] for any number `k` of basic indices, in the heap scratch `a`
/// (`k²` entries) by [`enumerate::gauss_solve`]; `b` (`k` entries) receives `z_B`. An
/// empty basis (`z = 0`) has nothing to solve.
fn solve_basis_heap(p: &ProblemRef<'_>, index: &[usize], a: &mut [f64], b: &mut [f64]) -> bool {
    let k = index.len();
    if k == 0 {
        return true;
    }
    let mut a_max: f64 = 0.0;
    for ((&i, a_row), b_i) in index.iter().zip(a.chunks_exact_mut(k)).zip(b.iter_mut()) {
        for (&j, a_ij) in index.iter().zip(a_row.iter_mut()) {
            *a_ij = p.m(i, j);
            a_max = a_max.max(a_ij.abs());
        }
        *b_i = -p.q[i];
    }
    enumerate::gauss_solve(a, k, b, k, SINGULAR * a_max)
}

impl LemkeSolver {
    /// Solves `(M, q)` like [`LemkeSolver::solve`], trying first the basis remembered in
    /// `warm` (when it has the problem's size); remembers the basis of the answer. A warm
    /// answer has [`SolveMethod::WarmStart`] and no pivots. No heap allocation once the
    /// buffers (and `warm`, see [`WarmStart::with_capacity`]) have grown to size `n`.
    pub fn solve_warm(
        &mut self,
        m: DMatrixView<'_, f64>,
        q: DVectorView<'_, f64>,
        warm: &mut WarmStart,
    ) -> Result<&LcpSolution, LcpInputError> {
        let n = m.nrows();
        // (The options are checked for size `n` once, by the ordinary solve, which
        // refuses what it cannot accept: until then no warm answer.)
        if n == 0 || warm.n != n || m.ncols() != n || q.len() != n || self.cover_n != n {
            return self.solve_and_remember(m, q, warm);
        }
        const _: () = assert!(MAX_WARM_FIXED == 6);
        match n {
            1 => self.warm_sized::<1>(m, q, warm),
            2 => self.warm_sized::<2>(m, q, warm),
            3 => self.warm_sized::<3>(m, q, warm),
            4 => self.warm_sized::<4>(m, q, warm),
            5 => self.warm_sized::<5>(m, q, warm),
            6 => self.warm_sized::<6>(m, q, warm),
            _ => self.warm_sized::<0>(m, q, warm),
        }
    }

    /// The ordinary solve after the remembered basis did not answer; remembers the basis
    /// of its answer.
    #[inline(never)]
    fn solve_and_remember(
        &mut self,
        m: DMatrixView<'_, f64>,
        q: DVectorView<'_, f64>,
        warm: &mut WarmStart,
    ) -> Result<&LcpSolution, LcpInputError> {
        self.solve(m, q)?;
        warm.remember(&self.sol);
        Ok(&self.sol)
    }

    /// [`LemkeSolver::solve_warm`] compiled for each size `n = W ≤
    /// MAX_WARM_FIXED` (fixed trip counts, the basis solved on the stack) and once with
    /// `W = 0` for larger sizes (the basis solved in the heap scratch).
    #[inline(never)]
    fn warm_sized<const W: usize>(
        &mut self,
        m: DMatrixView<'_, f64>,
        q: DVectorView<'_, f64>,
        warm: &mut WarmStart,
    ) -> Result<&LcpSolution, LcpInputError> {
        let n = if W > 0 { W } else { q.len() };
        if self.solve_basis::<W>(n, &m, q.as_slice(), warm) {
            return Ok(&self.sol);
        }
        self.solve_and_remember(m, q, warm)
    }

    /// Solves the complementary basis of `warm` (of size `n`) for `(M, q)` directly and
    /// publishes it if it certifies; `false` (nothing published) otherwise, also for
    /// `q ≥ 0` and for non-finite data, which the ordinary solve handles and reports.
    /// With `W = n` everything but the published answer lives on the stack; with `W = 0`
    /// the basis is solved in the heap scratch.
    #[inline(always)]
    fn solve_basis<const W: usize>(
        &mut self,
        n: usize,
        m: &DMatrixView<'_, f64>,
        q: &[f64],
        warm: &WarmStart,
    ) -> bool {
        let (basic, index) = (&warm.basic[..n], &warm.index[..]);
        let (q, basic) = (&q[..n], &basic[..n]);
        let (q_norm, q_min, q_sum) = vector_stats(q);
        if !q_sum.is_finite() || q_min >= 0.0 {
            return false;
        }
        let ld = leading_dim(n);
        if W == 0 {
            self.reserve(n);
        }
        let mref = MatRef::new(m);
        // (`n = W` for the sizes compiled on their own: column indices below `W` need no
        // check.)
        assert!(mref.n() == n);
        let m_norm = if W > 0 {
            let mut row_sum = [0.0; leading_dim(MAX_WARM_FIXED)];
            let row_sum = &mut row_sum[..ld];
            for j in 0..n {
                tableau::add_abs_column(row_sum, &mref.col(j)[..n]);
            }
            tableau::norm_of_row_sums(row_sum)
        } else {
            tableau::matrix_norm(n, mref, self.work.parts(n).row_sum)
        };
        if !m_norm.is_finite() {
            return false;
        }
        let p = ProblemRef {
            m: mref,
            q,
            m_norm,
            q_norm,
            rel_tol: self.options.rel_tol,
        };
        // `M_BB` (row-major) and `−q_B`, solved for `z_B` in `b`.
        let k = index.len();
        let mut b_local = [0.0; W];
        let b = if W > 0 {
            &mut b_local[..k]
        } else {
            &mut self.lu_rhs[..k]
        };
        let solved = if W > 0 {
            solve_basis_sized::<W>(&p, index, b)
        } else {
            solve_basis_heap(&p, index, &mut self.lu[..k * k], b)
        };
        if !solved {
            return false;
        }
        // z = (z_B, 0); `M z + q` once, for w (0 on the basis) and the certificate.
        let (mut z_local, mut w_local) = ([0.0; W], [0.0; W]);
        let mut mz_local = [0.0; leading_dim(MAX_WARM_FIXED)];
        let (z, w, mz) = if W > 0 {
            (&mut z_local[..], &mut w_local[..], &mut mz_local[..ld])
        } else {
            let mz = &mut self.work.parts(n).mz[..ld];
            (&mut self.zs[..n], &mut self.ws[..n], mz)
        };
        z.fill(0.0);
        tableau::set_padded(mz, 1.0, q);
        let mut z_norm: f64 = 0.0;
        for (&j, &z_j) in index.iter().zip(b.iter()) {
            z[j] = z_j;
            z_norm = max_abs(z_norm, z_j);
            tableau::sub_scaled_padded(mz, -z_j, &mref.col(j)[..n]);
        }
        for ((w_i, &m_i), &b_i) in w.iter_mut().zip(mz.iter()).zip(basic) {
            *w_i = if b_i { 0.0 } else { m_i };
        }
        let cert = p.measure(z, w, mz, z_norm);
        if !cert.holds() {
            return false;
        }
        let method = SolveMethod::WarmStart;
        self.sol.publish(z, w, LcpStatus::Solved, method, cert, 0);
        true
    }
}
