//! Complementary bases solved directly: the exhaustive-enumeration fallback for small `n`
//! and the refinement of a Lemke end basis that does not certify.

use crate::certificate::{Certificate, ProblemRef};

/// Scratch for [`solve_basis`] and [`enumerate`]; lengths `n²`, `n`, `n`.
pub(crate) struct BasisScratch<'s> {
    pub a: &'s mut [f64],
    pub b: &'s mut [f64],
    pub z_basic: &'s mut [bool],
}

/// Solves the complementary basis in which `z_j` is basic exactly where `z_basic[j]`:
/// `M_SS z_S = −q_S`, `z_j = 0` elsewhere, `w_S = 0`, `w_j = (M z + q)_j` elsewhere.
/// Writes `z`, `w`; false when `M_SS` is numerically singular.
pub(crate) fn solve_basis(
    p: &ProblemRef<'_>,
    s: &mut BasisScratch<'_>,
    z: &mut [f64],
    w: &mut [f64],
) -> bool {
    let n = z.len();
    let mut k = 0;
    let mut a_max: f64 = 0.0;
    for i in 0..n {
        if !s.z_basic[i] {
            continue;
        }
        let mut c = 0;
        for j in 0..n {
            if s.z_basic[j] {
                let v = p.m(i, j);
                a_max = a_max.max(v.abs());
                s.a[k * n + c] = v;
                c += 1;
            }
        }
        s.b[k] = -p.q[i];
        k += 1;
    }
    if k > 0 && !gauss_solve(s.a, n, s.b, k, 1e-13 * a_max) {
        return false;
    }
    let mut t = 0;
    for (zj, &basic) in z.iter_mut().zip(s.z_basic.iter()) {
        *zj = if basic {
            t += 1;
            s.b[t - 1]
        } else {
            0.0
        };
    }
    for (i, (wi, &basic)) in w.iter_mut().zip(s.z_basic.iter()).enumerate() {
        *wi = if basic {
            0.0
        } else {
            let mut acc = p.q[i];
            for (j, &zj) in z.iter().enumerate() {
                if zj != 0.0 {
                    acc += p.m(i, j) * zj;
                }
            }
            acc
        };
    }
    true
}

/// Tries all `2ⁿ` complementary bases; the first whose solution certifies is left in
/// `z`, `w`. Only for small `n` (the caller enforces the limit, at most 30).
pub(crate) fn enumerate(
    p: &ProblemRef<'_>,
    s: &mut BasisScratch<'_>,
    z: &mut [f64],
    w: &mut [f64],
    mz: &mut [f64],
) -> Option<Certificate> {
    let n = z.len();
    debug_assert!(n <= 30);
    for mask in 0u32..(1u32 << n) {
        for (j, flag) in s.z_basic[..n].iter_mut().enumerate() {
            *flag = mask & (1 << j) != 0;
        }
        if !solve_basis(p, s, z, w) {
            continue;
        }
        let cert = p.certify(z, w, mz);
        if cert.holds() {
            return Some(cert);
        }
    }
    None
}

/// Gaussian elimination with partial pivoting on the leading `k×k` block of the row-major
/// `a` (row stride `stride`); `b` is overwritten with the solution. False when a pivot's
/// magnitude is `≤ tiny` (numerically singular).
pub(crate) fn gauss_solve(
    a: &mut [f64],
    stride: usize,
    b: &mut [f64],
    k: usize,
    tiny: f64,
) -> bool {
    for col in 0..k {
        let mut piv = col;
        let mut best = a[col * stride + col].abs();
        for r in col + 1..k {
            let v = a[r * stride + col].abs();
            if v > best {
                best = v;
                piv = r;
            }
        }
        if best <= tiny || !best.is_finite() {
            return false;
        }
        if piv != col {
            for c in 0..k {
                a.swap(piv * stride + c, col * stride + c);
            }
            b.swap(piv, col);
        }
        let d = a[col * stride + col];
        for r in col + 1..k {
            let f = a[r * stride + col] / d;
            if f != 0.0 {
                for c in col..k {
                    a[r * stride + c] -= f * a[col * stride + c];
                }
                b[r] -= f * b[col];
            }
        }
    }
    for r in (0..k).rev() {
        let mut acc = b[r];
        for c in r + 1..k {
            acc -= a[r * stride + c] * b[c];
        }
        b[r] = acc / a[r * stride + r];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_solves_a_system_needing_a_row_swap() {
        // [[0, 1], [2, 1]] x = [1, 4] → x = (1.5, 1)
        let mut a = [0.0, 1.0, 2.0, 1.0];
        let mut b = [1.0, 4.0];
        assert!(gauss_solve(&mut a, 2, &mut b, 2, 1e-14));
        assert!(
            (b[0] - 1.5).abs() < 1e-15 && (b[1] - 1.0).abs() < 1e-15,
            "{b:?}"
        );
    }

    #[test]
    fn gauss_rejects_a_singular_system() {
        let mut a = [1.0, 2.0, 2.0, 4.0];
        let mut b = [1.0, 2.0];
        assert!(!gauss_solve(&mut a, 2, &mut b, 2, 1e-13 * 4.0));
    }
}
