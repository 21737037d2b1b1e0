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
use crate::certificate::{MatRef, ProblemRef};
use crate::enumerate;
use crate::tableau;
use crate::{LcpInputError, LcpSolution, LcpStatus, SolveMethod};
use nalgebra::{DMatrixView, DVectorView};

/// The complementary basis of the last certified answer of [`LemkeSolver::solve_warm`]:
/// which `z_i` were basic. Empty at first and after [`WarmStart::forget`].
#[derive(Debug, Clone, Default)]
pub struct WarmStart {
    basic: Vec<bool>,
    /// Size of the remembered basis (0: none).
    n: usize,
}

impl WarmStart {
    /// No basis yet; room for problems of size `capacity` without allocating.
    pub fn with_capacity(capacity: usize) -> Self {
        WarmStart {
            basic: Vec::with_capacity(capacity),
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
        let n = sol.z.len();
        self.basic.clear();
        self.basic
            .extend(sol.z.iter().zip(sol.w.iter()).map(|(z, w)| z > w));
        self.n = n;
    }
}

/// A pivot at most `SINGULAR` times the largest entry of `M_BB` makes it singular (as in
/// the enumeration fallback).
const SINGULAR: f64 = 1e-13;

/// Gaussian elimination with partial pivoting of the leading `k × k` block of `a`
/// (`k = b.len() ≤ W`); `b` becomes the solution. False when a pivot is at most
/// [`SINGULAR`] times the block's largest entry, or not finite.
#[inline(always)]
fn solve_small<const W: usize>(a: &mut [[f64; W]; W], b: &mut [f64]) -> bool {
    let k = b.len();
    let mut a_max: f64 = 0.0;
    for row in a.iter().take(k) {
        for v in row.iter().take(k) {
            a_max = a_max.max(v.abs());
        }
    }
    let tiny = SINGULAR * a_max;
    for col in 0..k {
        let mut piv = col;
        for r in col + 1..k {
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
        let pivot_row = &upper[col][col..k];
        for (r, row) in lower[..k - col - 1].iter_mut().enumerate() {
            let f = row[col] / d;
            for (x, p) in row[col..k].iter_mut().zip(pivot_row) {
                *x -= f * p;
            }
            b[col + 1 + r] -= f * b[col];
        }
    }
    for r in (0..k).rev() {
        let mut acc = b[r];
        for c in r + 1..k {
            acc -= a[r][c] * b[c];
        }
        b[r] = acc / a[r][r];
    }
    true
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
        let fits = n > 0 && warm.n == n && m.ncols() == n && q.len() == n;
        if fits && self.solve_basis_of(&m, q.as_slice(), &warm.basic[..n]) {
            return Ok(&self.sol);
        }
        self.solve(m, q)?;
        warm.remember(&self.sol);
        Ok(&self.sol)
    }

    /// Solves the complementary basis `basic` of `(M, q)` directly and publishes it if it
    /// certifies; `false` (nothing published) otherwise, also for `q ≥ 0` and for
    /// non-finite data, which the ordinary solve handles and reports.
    fn solve_basis_of(&mut self, m: &DMatrixView<'_, f64>, q: &[f64], basic: &[bool]) -> bool {
        match q.len() {
            1 => self.basis_fixed::<1>(m, q, basic),
            2 => self.basis_fixed::<2>(m, q, basic),
            3 => self.basis_fixed::<3>(m, q, basic),
            4 => self.basis_fixed::<4>(m, q, basic),
            5 => self.basis_fixed::<5>(m, q, basic),
            6 => self.basis_fixed::<6>(m, q, basic),
            // Larger sizes share one copy, with the basis solved in the heap scratch.
            n => self.basis_core::<0>(n, m, q, basic),
        }
    }

    /// [`LemkeSolver::solve_basis_of`] compiled for one small size (fixed trip counts).
    #[inline(never)]
    fn basis_fixed<const N: usize>(
        &mut self,
        m: &DMatrixView<'_, f64>,
        q: &[f64],
        basic: &[bool],
    ) -> bool {
        self.basis_core::<N>(N, m, q, basic)
    }

    #[inline(always)]
    /// The warm path for size `n`; with `W = n` the basis is solved on the stack, with
    /// `W = 0` in the heap scratch.
    fn basis_core<const W: usize>(
        &mut self,
        n: usize,
        m: &DMatrixView<'_, f64>,
        q: &[f64],
        basic: &[bool],
    ) -> bool {
        let (q, basic) = (&q[..n], &basic[..n]);
        let (mut q_norm, mut q_min, mut q_sum) = (0.0_f64, f64::INFINITY, 0.0);
        for &v in q {
            q_norm = q_norm.max(v.abs());
            q_min = q_min.min(v);
            q_sum += v;
        }
        // `max` and `min` skip NaN; the sum does not.
        if !q_sum.is_finite() || q_min >= 0.0 {
            return false;
        }
        self.reserve(n);
        let mref = MatRef::new(m);
        let parts = self.work.parts(n);
        let m_norm = tableau::matrix_norm(n, mref, parts.row_sum);
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
        // The basic indices, `M_BB` (row-major) and `−q_B`.
        let idx = parts.ties;
        let mut k = 0;
        for (i, _) in basic.iter().enumerate().filter(|(_, &b)| b) {
            idx[k] = i;
            k += 1;
        }
        let idx = &idx[..k];
        let b = &mut self.lu_rhs[..k];
        let solved = if W > 0 {
            let mut a = [[0.0; W]; W];
            for ((&i, a_row), b_i) in idx.iter().zip(a.iter_mut()).zip(b.iter_mut()) {
                for (&j, a_ij) in idx.iter().zip(a_row.iter_mut()) {
                    *a_ij = p.m(i, j);
                }
                *b_i = -q[i];
            }
            solve_small(&mut a, b)
        } else {
            let a = &mut self.lu[..k * k];
            let mut a_max: f64 = 0.0;
            for ((&i, a_row), b_i) in idx.iter().zip(a.chunks_exact_mut(k)).zip(b.iter_mut()) {
                for (&j, a_ij) in idx.iter().zip(a_row.iter_mut()) {
                    *a_ij = p.m(i, j);
                    a_max = a_max.max(a_ij.abs());
                }
                *b_i = -q[i];
            }
            enumerate::gauss_solve(a, k, b, k, SINGULAR * a_max)
        };
        if !solved {
            return false;
        }
        // z = (z_B, 0); w = M z + q off the basis, 0 on it.
        let (zs, ws, mz) = (&mut self.zs[..n], &mut self.ws[..n], parts.mz);
        zs.fill(0.0);
        tableau::set_padded(mz, 1.0, q);
        for (&j, &z_j) in idx.iter().zip(b.iter()) {
            zs[j] = z_j;
            tableau::sub_scaled_padded(mz, -z_j, &mref.col(j)[..n]);
        }
        for ((w_i, &m_i), &b_i) in ws.iter_mut().zip(mz.iter()).zip(basic) {
            *w_i = if b_i { 0.0 } else { m_i };
        }
        let cert = p.certify(zs, ws, mz);
        if !cert.holds() {
            return false;
        }
        self.commit(n, LcpStatus::Solved, SolveMethod::WarmStart, cert, 0);
        true
    }
}
