//! Small dense linear algebra in place, so the stepper allocates nothing per step.

use nalgebra::{DMatrix, DVector};

/// Overwrites the leading `n × n` block of `a` with its lower Cholesky factor `L`
/// (`a = L Lᵀ`). Returns `false` when the block is not positive definite.
pub fn cholesky_in_place(a: &mut DMatrix<f64>, n: usize) -> bool {
    for j in 0..n {
        let mut d = a[(j, j)];
        for k in 0..j {
            d -= a[(j, k)] * a[(j, k)];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[(j, j)] = d;
        for i in j + 1..n {
            let mut s = a[(i, j)];
            for k in 0..j {
                s -= a[(i, k)] * a[(j, k)];
            }
            a[(i, j)] = s / d;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place for the leading `n` entries of `x` (holding `b`).
pub fn cholesky_solve(l: &DMatrix<f64>, n: usize, x: &mut [f64]) {
    for i in 0..n {
        let mut s = x[i];
        for k in 0..i {
            s -= l[(i, k)] * x[k];
        }
        x[i] = s / l[(i, i)];
    }
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in i + 1..n {
            s -= l[(k, i)] * x[k];
        }
        x[i] = s / l[(i, i)];
    }
}

/// Writes `a · x` (leading `rows × cols` block of `a`) into `out[..rows]`.
pub fn mat_vec(a: &DMatrix<f64>, rows: usize, cols: usize, x: &[f64], out: &mut [f64]) {
    out[..rows].fill(0.0);
    for (j, xj) in x.iter().enumerate().take(cols) {
        if *xj != 0.0 {
            for (i, o) in out.iter_mut().enumerate().take(rows) {
                *o += a[(i, j)] * xj;
            }
        }
    }
}

/// `aᵀ b` for columns `ca` of `a` and `cb` of `b`, over the first `n` rows.
pub fn col_dot(a: &DMatrix<f64>, ca: usize, b: &DMatrix<f64>, cb: usize, n: usize) -> f64 {
    (0..n).map(|i| a[(i, ca)] * b[(i, cb)]).sum()
}

/// `aᵀ v` for column `ca` of `a`.
pub fn col_dot_vec(a: &DMatrix<f64>, ca: usize, v: &DVector<f64>) -> f64 {
    (0..v.len()).map(|i| a[(i, ca)] * v[i]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_a_spd_system() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0]);
        let x_true = [1.0, -2.0, 0.5];
        let mut b = [0.0; 3];
        mat_vec(&a, 3, 3, &x_true, &mut b);
        let mut l = a.clone();
        assert!(cholesky_in_place(&mut l, 3));
        cholesky_solve(&l, 3, &mut b);
        for (x, t) in b.iter().zip(x_true) {
            assert!((x - t).abs() < 1e-12, "{x} vs {t}");
        }
    }

    #[test]
    fn cholesky_rejects_an_indefinite_matrix() {
        let mut a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert!(!cholesky_in_place(&mut a, 2));
    }
}
