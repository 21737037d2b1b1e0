//! The a-posteriori certificate of an LCP answer, computed from the original `M`, `q`.

use crate::tableau::{active_len, leading_dim, set_padded, sub_scaled_padded, MAX_FIXED};
use nalgebra::DMatrixView;
use std::marker::PhantomData;

/// How well `(z, w)` satisfies `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0`.
///
/// All three measures are in the units of `w`, with `z` entering as `‖M‖_∞ z` (the change
/// of `w` it can cause), and `tolerance = rel_tol · max(‖q‖_∞, ‖M‖_∞ ‖z‖_∞)`: a
/// backward-error style scale, so the test means the same for a contact LCP with
/// `q ~ 1e-3` as for one with `q ~ 1e3`, and for `(sM, q)` as for `(M, q)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Certificate {
    /// `max_i |min(‖M‖ z_i, w_i)|`.
    pub complementarity: f64,
    /// `min(0, ‖M‖ min_i z_i, min_i w_i)` (so always `≤ 0`).
    pub most_negative: f64,
    /// `‖w − M z − q‖_∞`.
    pub residual: f64,
    /// The scaled tolerance the three numbers are held to.
    pub tolerance: f64,
    /// `‖M‖_∞`, the scale `z` enters with: `z` is resolved to `tolerance / matrix_norm`.
    pub matrix_norm: f64,
}

impl Certificate {
    /// The resolution of `z`: `tolerance / ‖M‖_∞` (the tolerance itself for `M = 0`).
    pub fn z_tolerance(&self) -> f64 {
        if self.matrix_norm > 0.0 {
            self.tolerance / self.matrix_norm
        } else {
            self.tolerance
        }
    }
}

impl Certificate {
    /// All three measures within `tolerance` (false if any is NaN).
    pub fn holds(&self) -> bool {
        self.complementarity <= self.tolerance
            && self.most_negative >= -self.tolerance
            && self.residual <= self.tolerance
    }
}

/// `M` read in place from the caller's matrix: column `j` is the `n` entries from
/// `ptr + j·stride` (the matrix is a view with row stride 1).
#[derive(Debug, Clone, Copy)]
pub(crate) struct MatRef<'a> {
    ptr: *const f64,
    stride: usize,
    n: usize,
    data: PhantomData<&'a f64>,
}

impl<'a> MatRef<'a> {
    /// The square view `m`, without copying.
    pub fn new(m: &DMatrixView<'a, f64>) -> Self {
        assert_eq!(m.nrows(), m.ncols());
        MatRef {
            ptr: m.as_ptr(),
            stride: m.strides().1,
            n: m.nrows(),
            data: PhantomData,
        }
    }

    /// The size `n`.
    #[inline(always)]
    pub fn n(&self) -> usize {
        self.n
    }

    /// Column `j` (`n` entries).
    #[inline(always)]
    pub fn col(&self, j: usize) -> &'a [f64] {
        assert!(j < self.n);
        // SAFETY: `m` is an `n × n` view with row stride 1 and column stride `stride` of data
        // borrowed (shared) for `'a`, so its column `j < n` is `n` contiguous entries from
        // `ptr + j·stride`. Only the view's own entries are covered (not the rows of a
        // parent matrix between its columns, which another view may borrow mutably).
        unsafe { std::slice::from_raw_parts(self.ptr.add(j * self.stride), self.n) }
    }
}

/// The original problem with the norms its certificates are scaled by.
pub(crate) struct ProblemRef<'a> {
    /// `M`, the caller's data.
    pub m: MatRef<'a>,
    pub q: &'a [f64],
    /// `‖M‖_∞` (maximum absolute row sum).
    pub m_norm: f64,
    /// `‖q‖_∞`.
    pub q_norm: f64,
    pub rel_tol: f64,
}

impl ProblemRef<'_> {
    /// `M_ij`.
    #[inline(always)]
    pub fn m(&self, i: usize, j: usize) -> f64 {
        self.m.col(j)[i]
    }

    /// Certificate of `(z, w)`; `mz` is scratch of length at least `active_len(n)`, used
    /// for `n > MAX_FIXED`. Allocates nothing.
    #[inline(always)]
    pub fn certify(&self, z: &[f64], w: &[f64], mz: &mut [f64]) -> Certificate {
        let n = self.q.len();
        let (z, w) = (&z[..n], &w[..n]);
        // Small n: `M z + q` accumulates on the stack (registers), not through memory.
        let mut local = [0.0; leading_dim(MAX_FIXED)];
        let mz = if n <= MAX_FIXED {
            &mut local[..active_len(n)]
        } else {
            &mut mz[..active_len(n)]
        };
        set_padded(mz, 1.0, self.q);
        let mut z_norm: f64 = 0.0;
        for (j, &zj) in z.iter().enumerate() {
            z_norm = max_abs(z_norm, zj);
            if zj != 0.0 {
                sub_scaled_padded(mz, -zj, &self.m.col(j)[..n]);
            }
        }
        self.measure(z, w, mz, z_norm)
    }

    /// Certificate of `(z, w)` given `mz = M z + q` (the columns of zero `z_j` may be
    /// left out: that changes at most the sign of a zero) and `z_norm = ‖z‖_∞` (see
    /// [`max_abs`]).
    #[inline(always)]
    pub fn measure(&self, z: &[f64], w: &[f64], mz: &[f64], z_norm: f64) -> Certificate {
        let n = self.q.len();
        let (z, w, mz) = (&z[..n], &w[..n], &mz[..n]);
        let mut complementarity: f64 = 0.0;
        let mut most_negative: f64 = 0.0;
        let mut residual: f64 = 0.0;
        // 0, or NaN once a value is not finite (see [`finite_or_nan`]).
        let mut nonfinite = 0.0;
        // `z` in the units of `w` (a zero `M` leaves `z` as it is).
        let z_unit = if self.m_norm > 0.0 { self.m_norm } else { 1.0 };
        for ((&zi, &wi), &ri) in z.iter().zip(w).zip(mz.iter()) {
            let zi = z_unit * zi;
            let low = if zi < wi { zi } else { wi };
            let c = low.abs();
            complementarity = if c > complementarity {
                c
            } else {
                complementarity
            };
            most_negative = if low < most_negative {
                low
            } else {
                most_negative
            };
            let r = (wi - ri).abs();
            residual = if r > residual { r } else { residual };
            // `r` is not finite when `w_i` or `(M z + q)_i` is not, nor so when `z_i` is.
            nonfinite += finite_or_nan(r);
        }
        let scale = self.q_norm.max(self.m_norm * z_norm).max(f64::MIN_POSITIVE);
        // (An overflow of `‖M‖ z_i` makes the scale infinite.)
        if !(nonfinite + scale).is_finite() {
            // The comparisons above skip NaN: make a non-finite iterate fail loudly.
            complementarity = f64::NAN;
            most_negative = f64::NAN;
            residual = f64::NAN;
        }
        Certificate {
            complementarity,
            most_negative,
            residual,
            tolerance: self.rel_tol * scale,
            matrix_norm: self.m_norm,
        }
    }
}

/// 0 for a finite `x`, NaN otherwise: summed, it flags a non-finite value without the
/// overflow a sum of huge finite values would cause.
#[inline(always)]
pub(crate) fn finite_or_nan(x: f64) -> f64 {
    x * 0.0
}

/// `max(acc, |v|)` as the certificate accumulates `‖z‖_∞` (a NaN `v` is skipped; the
/// certificate's sum exposes it).
#[inline(always)]
pub(crate) fn max_abs(acc: f64, v: f64) -> f64 {
    let a = v.abs();
    if a > acc {
        a
    } else {
        acc
    }
}

/// `(‖q‖_∞, min_i q_i, Σ q_i)` in one pass. The maximum and minimum skip NaN and are exact
/// whatever the sum does; a non-finite sum flags a non-finite entry, or an overflow.
#[inline(always)]
pub(crate) fn vector_stats(q: &[f64]) -> (f64, f64, f64) {
    let (mut norm, mut min, mut sum) = (0.0_f64, f64::INFINITY, 0.0);
    for &v in q {
        sum += v;
        norm = max_abs(norm, v);
        min = if v < min { v } else { min };
    }
    (norm, min, sum)
}
