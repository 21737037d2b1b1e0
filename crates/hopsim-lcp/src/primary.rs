//! The hot path of a solve: validation, the trivial case, one Lemke run with the
//! configured covering vector, extraction and certificate. It is compiled once per small
//! `n` (fixed loop bounds) and, on x86-64, once more with AVX2 enabled (selected at run
//! time). AVX2 only widens the vectors: no fused multiply-add, so every path gives
//! bit-identical results.

use crate::certificate::{vector_stats, MatRef, ProblemRef};
use crate::tableau::{self, inv_pow2_floor, pow2_floor, Ending, Scales, Work, MAX_FIXED};
use crate::{Certificate, LcpInputError};

/// How the hot path ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum End {
    /// `q ≥ 0`: `z = 0`, `w = q`.
    Trivial,
    /// Lemke's method ended on a basis whose solution certifies.
    Solved,
    /// Anything else; `z`, `w` are unspecified.
    Failed(Ending),
}

/// Result of the hot path.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Primary {
    pub end: End,
    pub pivots: usize,
    pub m_norm: f64,
    pub q_norm: f64,
    pub scales: Scales,
    pub certificate: Certificate,
}

impl Default for Primary {
    fn default() -> Self {
        Primary {
            end: End::Trivial,
            pivots: 0,
            m_norm: 0.0,
            q_norm: 0.0,
            scales: Scales::new(1.0, 1.0, 1.0),
            certificate: Certificate::default(),
        }
    }
}

/// Inputs of the hot path besides the problem.
pub(crate) struct Settings {
    pub rel_tol: f64,
    pub max_pivots: usize,
}

/// Runs the hot path for `(M, q)` with covering vector `work.cover`; writes `z`, `w`
/// (length `n`). `M` is read in place (no copy). Errors on a non-finite entry.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn primary(
    work: &mut Work,
    m: MatRef<'_>,
    q: &[f64],
    z: &mut [f64],
    w: &mut [f64],
    settings: &Settings,
    out: &mut Primary,
) -> Result<(), LcpInputError> {
    #[cfg(all(target_arch = "x86_64", not(feature = "portable")))]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, the only requirement of `primary_avx2`.
        return unsafe { primary_avx2(work, m, q, z, w, settings, out) };
    }
    // SAFETY: the portable copies need no CPU feature.
    unsafe { primary_portable(work, m, q, z, w, settings, out) }
}

/// Calls `$f::<N>` for `n = N ≤ MAX_FIXED`, else `$f::<0>` (any `n`).
macro_rules! by_size {
    ($n:expr, $f:ident, ($($arg:expr),*)) => {{
        const _: () = assert!(MAX_FIXED == 12);
        match $n {
            1 => $f::<1>($($arg),*),
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            5 => $f::<5>($($arg),*),
            6 => $f::<6>($($arg),*),
            7 => $f::<7>($($arg),*),
            8 => $f::<8>($($arg),*),
            9 => $f::<9>($($arg),*),
            10 => $f::<10>($($arg),*),
            11 => $f::<11>($($arg),*),
            12 => $f::<12>($($arg),*),
            _ => $f::<0>($($arg),*),
        }
    }};
}

/// Defines the hot path's entry `$entry`, which dispatches on `n` (inlined into its caller,
/// so a solve makes one call), and the copies `$fixed::<N>`: one per small `N` with fixed
/// loop bounds, `$fixed::<0>` for any `n`, all compiled with the attributes `$feature`
/// (e.g. a target feature): one body for every instruction set.
macro_rules! hot_path {
    ([$(#[$cfg:meta])*] [$(#[$feature:meta])*] $entry:ident, $fixed:ident) => {
        /// # Safety
        /// The CPU supports the target features of `$fixed`, if any.
        $(#[$cfg])*
        #[allow(clippy::too_many_arguments, unused_unsafe)]
        #[inline(always)]
        unsafe fn $entry(
            work: &mut Work,
            m: MatRef<'_>,
            q: &[f64],
            z: &mut [f64],
            w: &mut [f64],
            s: &Settings,
            out: &mut Primary,
        ) -> Result<(), LcpInputError> {
            // SAFETY: the caller guarantees the target features of `$fixed`.
            unsafe { by_size!(q.len(), $fixed, (work, m, q, z, w, s, out)) }
        }

        $(#[$cfg])*
        $(#[$feature])*
        #[allow(clippy::too_many_arguments)]
        #[inline(never)]
        fn $fixed<const N: usize>(
            work: &mut Work,
            m: MatRef<'_>,
            q: &[f64],
            z: &mut [f64],
            w: &mut [f64],
            s: &Settings,
            out: &mut Primary,
        ) -> Result<(), LcpInputError> {
            let n = if N == 0 { q.len() } else { N };
            core(n, work, m, q, z, w, s, out)
        }
    };
}

hot_path!([] [] primary_portable, fixed_portable);
hot_path!(
    [
        #[cfg(target_arch = "x86_64")]
        #[cfg_attr(feature = "portable", allow(dead_code))]
    ]
    [#[target_feature(enable = "avx2")]]
    primary_avx2,
    fixed_avx2
);

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn core(
    n: usize,
    work: &mut Work,
    m: MatRef<'_>,
    q: &[f64],
    z: &mut [f64],
    w: &mut [f64],
    s: &Settings,
    out: &mut Primary,
) -> Result<(), LcpInputError> {
    let q = &q[..n];
    let (z, w) = (&mut z[..n], &mut w[..n]);
    let (q_norm, q_min, q_sum) = vector_stats(q);
    if !q_sum.is_finite() {
        // A non-finite entry, or a sum that overflowed (`q_norm` is exact either way).
        nonfinite_q(q)?;
    }

    let mut t = work.parts(n);
    let mut m_norm = tableau::matrix_norm(n, m, t.row_sum);
    if !m_norm.is_finite() {
        m_norm = checked_norm(n, m)?;
    }
    *out = Primary {
        m_norm,
        q_norm,
        ..Primary::default()
    };
    if n == 0 || q_min >= 0.0 {
        z.fill(0.0);
        w.copy_from_slice(q);
    } else {
        let q_inv = inv_pow2_floor(q_norm);
        let m_inv = tableau::load(n, &mut t, q, q_inv, m_norm);
        out.scales = Scales::new(q_inv, m_inv, pow2_floor(q_norm));
        let (ending, pivots) = tableau::pivot_loop(n, &mut t, m, m_inv, s.max_pivots);
        out.end = End::Failed(ending);
        out.pivots = pivots;
        if ending != Ending::Complementary || !tableau::extract(n, &t, &out.scales, z, w) {
            return Ok(());
        }
    }
    let p = ProblemRef {
        m,
        q,
        m_norm,
        q_norm,
        rel_tol: s.rel_tol,
    };
    out.certificate = p.certify(z, w, t.mz);
    if out.end != End::Trivial && out.certificate.holds() {
        out.end = End::Solved;
    }
    Ok(())
}

/// The error for the first non-finite entry of `q`, else of `M` (row-major), as the hot
/// path reports it; `Ok` for finite data.
#[cold]
#[inline(never)]
pub(crate) fn check_finite(m: MatRef<'_>, q: &[f64]) -> Result<(), LcpInputError> {
    nonfinite_q(q)?;
    checked_norm(q.len(), m).map(|_| ())
}

/// The first non-finite entry of `q` as an error.
#[cold]
#[inline(never)]
fn nonfinite_q(q: &[f64]) -> Result<(), LcpInputError> {
    match q.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(LcpInputError::NonFinite { what: "q", index }),
        None => Ok(()),
    }
}

/// After a non-finite `‖M‖_∞`: the first non-finite entry of `M` (row-major) as an
/// error; else (the sum of the row sums overflowed) `‖M‖_∞` itself, `f64::MAX` if a row
/// sum overflows.
#[cold]
#[inline(never)]
fn checked_norm(n: usize, m: MatRef<'_>) -> Result<f64, LcpInputError> {
    let mut norm: f64 = 0.0;
    for i in 0..n {
        let mut row = 0.0;
        for j in 0..n {
            let v = m.col(j)[i];
            if !v.is_finite() {
                return Err(LcpInputError::NonFinite {
                    what: "M",
                    index: i * n + j,
                });
            }
            row += v.abs();
        }
        norm = norm.max(row);
    }
    Ok(norm.min(f64::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The hot path answers well-conditioned problems by itself: the tableau's values,
    /// unscaled, certify (no refinement of the basis by the recovery), and equal the
    /// unique solution of the positive definite LCP found independently (the basis of
    /// `z > 0` solved by nalgebra's LU), on every compiled size and the generic one, with
    /// `q` and `M` of magnitudes from `1e-300` to `1e306`.
    #[test]
    fn the_hot_path_certifies_its_own_answer() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let settings = Settings {
            rel_tol: 1e-9,
            max_pivots: 10_000,
        };
        for n in 1..=16 {
            for (s_m, s_q) in [
                (1.0, 1.0),
                (1e-3, 1e3),
                (1.0, 1e-300),
                (1e-150, 1e150),
                (1.0, 1e306),
            ] {
                let a = DMatrix::from_fn(n, n, |_, _| uniform());
                let m = (&a * a.transpose() + DMatrix::identity(n, n)) * s_m;
                let q = DVector::from_fn(n, |_, _| uniform() - 0.3) * s_q;
                let mut work = Work::default();
                work.reserve(n);
                work.parts(n).cover.fill(1.0);
                let (mut z, mut w) = (vec![0.0; n], vec![0.0; n]);
                let mut prim = Primary::default();
                let view = m.as_view();
                primary(
                    &mut work,
                    MatRef::new(&view),
                    q.as_slice(),
                    &mut z,
                    &mut w,
                    &settings,
                    &mut prim,
                )
                .unwrap();
                let case = format!("n = {n}, M·{s_m:e}, q·{s_q:e}");
                assert!(
                    matches!(prim.end, End::Solved | End::Trivial),
                    "{case}: {:?}",
                    prim.end
                );
                assert!(prim.certificate.holds(), "{case}");
                let basic: Vec<usize> = (0..n).filter(|&i| z[i] > 0.0).collect();
                let k = basic.len();
                if k == 0 {
                    assert_eq!(prim.end, End::Trivial, "{case}");
                    continue;
                }
                let mbb = DMatrix::from_fn(k, k, |i, j| m[(basic[i], basic[j])]);
                let qb = DVector::from_fn(k, |i, _| -q[basic[i]]);
                let zb = mbb.lu().solve(&qb).unwrap();
                for (i, &b) in basic.iter().enumerate() {
                    assert!(
                        (z[b] - zb[i]).abs() <= 1e-9 * zb.amax(),
                        "{case}: z = {z:?}"
                    );
                }
            }
        }
    }

    /// The AVX2 build of the hot path must give bit-identical results to the portable one.
    #[test]
    fn avx2_and_portable_paths_agree_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let settings = Settings {
            rel_tol: 1e-9,
            max_pivots: 10_000,
        };
        for n in (1..=16).chain([23, 40]) {
            for _ in 0..20 {
                let a = DMatrix::from_fn(n, n, |_, _| uniform());
                // Half PSD (solvable), half general (rays, pivot limits, breakdowns).
                let m = if uniform() > 0.0 {
                    &a * a.transpose()
                } else {
                    a
                };
                let q = DVector::from_fn(n, |_, _| uniform());
                let mut results = Vec::new();
                for simd in [false, true] {
                    let mut work = Work::default();
                    work.reserve(n);
                    work.parts(n).cover.fill(1.0);
                    let (mut z, mut w) = (vec![0.0; n], vec![0.0; n]);
                    let (mv, qv) = (m.as_view(), q.as_slice());
                    let mut prim = Primary::default();
                    let (zs, ws, out) = (&mut z, &mut w, &mut prim);
                    let (mc, wk, st) = (MatRef::new(&mv), &mut work, &settings);
                    if simd {
                        // SAFETY: AVX2 support was checked above.
                        #[cfg(target_arch = "x86_64")]
                        unsafe {
                            primary_avx2(wk, mc, qv, zs, ws, st, out)
                        }
                        // SAFETY: the portable copies need no CPU feature.
                        #[cfg(not(target_arch = "x86_64"))]
                        unsafe {
                            primary_portable(wk, mc, qv, zs, ws, st, out)
                        }
                    } else {
                        // SAFETY: the portable copies need no CPU feature.
                        unsafe { primary_portable(wk, mc, qv, zs, ws, st, out) }
                    }
                    .unwrap();
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    results.push((
                        prim.end,
                        prim.pivots,
                        bits(&z),
                        bits(&w),
                        prim.certificate.residual.to_bits(),
                    ));
                }
                assert_eq!(results[0], results[1], "n = {n}");
            }
        }
    }
}
