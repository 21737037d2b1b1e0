//! Small dense linear algebra on row-major slices, in place, so the stepper allocates
//! nothing per step. The sizes are tiny (`n` = generalised coordinates, a handful), so
//! plain loops over slices beat any general-purpose routine.

/// Calls `$fixed::<N>` for `n = N ≤ 8` (loops the compiler unrolls), else `$dynamic`.
macro_rules! by_size {
    ($n:expr, $fixed:ident, $dynamic:ident, ($($arg:expr),*)) => {
        match $n {
            1 => $fixed::<1>($($arg),*),
            2 => $fixed::<2>($($arg),*),
            3 => $fixed::<3>($($arg),*),
            4 => $fixed::<4>($($arg),*),
            5 => $fixed::<5>($($arg),*),
            6 => $fixed::<6>($($arg),*),
            7 => $fixed::<7>($($arg),*),
            8 => $fixed::<8>($($arg),*),
            n => $dynamic(n, $($arg),*),
        }
    };
}

/// Overwrites the leading `n × n` block of the row-major `a` (stride `n`) with its
/// factorisation `a = L D Lᵀ` (`L` unit lower triangular below the diagonal, `1 / D_ii` on
/// the diagonal: no square roots, and the solves multiply instead of divide). Returns
/// `false` unless the block is positive definite (every pivot `D_ii > 0`).
fn factor_in_place(a: &mut [f64], n: usize) -> bool {
    by_size!(n, factor_fixed, factor_dynamic, (a))
}

/// Row `j` of the factor, rows `0..j` done: `w_k = L_jk D_k`, then `L_jk` and `1 / D_j`.
#[inline(always)]
fn factor_row(row_j: &mut [f64], done: &[f64], n: usize, j: usize) -> bool {
    for k in 0..j {
        let row_k = &done[k * n..k * n + k];
        row_j[k] -= dot(&row_j[..k], row_k);
    }
    let mut d = row_j[j];
    for k in 0..j {
        let w = row_j[k];
        let l = w * done[k * n + k];
        d -= w * l;
        row_j[k] = l;
    }
    if d <= 0.0 || !d.is_finite() {
        return false;
    }
    row_j[j] = 1.0 / d;
    true
}

/// [`factor_dynamic`] with the size known at compile time (the loops unroll).
fn factor_fixed<const N: usize>(a: &mut [f64]) -> bool {
    factor_dynamic(N, a)
}

#[inline(always)]
fn factor_dynamic(n: usize, a: &mut [f64]) -> bool {
    let a = &mut a[..n * n];
    for j in 0..n {
        let (done, rest) = a.split_at_mut(j * n);
        if !factor_row(&mut rest[..n], done, n, j) {
            return false;
        }
    }
    true
}

fn solve_dynamic(n: usize, l: &[f64], x: &mut [f64]) {
    let x = &mut x[..n];
    for i in 0..n {
        x[i] -= dot(&l[i * n..i * n + i], &x[..i]);
    }
    for i in (0..n).rev() {
        let mut s = x[i] * l[i * n + i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s;
    }
}

/// The `L D Lᵀ` factorisation of a small symmetric positive definite matrix in a reused
/// buffer, solving several right-hand sides at once (independent dependency chains the
/// processor overlaps). A structurally diagonal matrix (a body tree whose Jacobian rows
/// each touch one coordinate, like Robbit's) takes the shortcut `x_i = b_i / a_ii`.
#[derive(Clone, Debug)]
pub struct Factor {
    diagonal: bool,
    n: usize,
    data: Vec<f64>,
}

impl Factor {
    /// Room for matrices up to `capacity × capacity`; `diagonal` when every matrix it
    /// will factor is diagonal by structure.
    pub fn new(capacity: usize, diagonal: bool) -> Self {
        Self {
            diagonal,
            n: 0,
            data: vec![0.0; capacity * capacity],
        }
    }

    /// Factors the leading `n × n` block of the row-major `a` (stride `n`); `false` unless
    /// it is positive definite.
    pub fn factor(&mut self, a: &[f64], n: usize) -> bool {
        self.n = n;
        if self.diagonal {
            for (i, inv) in self.data[..n].iter_mut().enumerate() {
                let d = a[i * n + i];
                if d <= 0.0 || !d.is_finite() {
                    return false;
                }
                *inv = 1.0 / d;
            }
            return true;
        }
        let data = &mut self.data[..n * n];
        data.copy_from_slice(&a[..n * n]);
        factor_in_place(data, n)
    }

    /// [`Factor::solve`] for a caller compiled for `n = N` (`N = 0`: any `n`), inlined into
    /// it without the dispatch on `n`.
    #[inline(always)]
    pub fn solve_sized<const N: usize>(&self, xs: &mut [f64]) {
        if N == 0 || N > 8 {
            self.solve(xs);
        } else if self.diagonal {
            scale_many_fixed::<N>(&self.data, xs);
        } else {
            solve_many_fixed::<N>(&self.data, xs);
        }
    }

    /// Solves `A x = b` in place for each row of `xs` (`count × n`, row-major).
    pub fn solve(&self, xs: &mut [f64]) {
        let n = self.n;
        if self.diagonal {
            by_size!(n, scale_many_fixed, scale_many_dynamic, (&self.data, xs))
        } else {
            by_size!(n, solve_many_fixed, solve_many_dynamic, (&self.data, xs))
        }
    }
}

/// The diagonal solve: each row of `xs` times the inverse diagonal `inv` (`N` entries).
#[inline(always)]
fn scale_many_fixed<const N: usize>(inv: &[f64], xs: &mut [f64]) {
    let inv: &[f64; N] = inv[..N].try_into().expect("N entries");
    let (xs, _) = xs.as_chunks_mut::<N>();
    for x in xs {
        for (x, inv) in x.iter_mut().zip(inv) {
            *x *= inv;
        }
    }
}

fn scale_many_dynamic(n: usize, inv: &[f64], xs: &mut [f64]) {
    for row in xs.chunks_exact_mut(n) {
        for (x, inv) in row.iter_mut().zip(&inv[..n]) {
            *x *= inv;
        }
    }
}

fn solve_many_fixed<const N: usize>(l: &[f64], xs: &mut [f64]) {
    let (rows, _) = l.as_chunks::<N>();
    let l = &rows[..N];
    let (xs, _) = xs.as_chunks_mut::<N>();
    for i in 0..N {
        for k in 0..i {
            let lik = l[i][k];
            for x in xs.iter_mut() {
                x[i] -= lik * x[k];
            }
        }
    }
    for i in (0..N).rev() {
        let d = l[i][i];
        for x in xs.iter_mut() {
            x[i] *= d;
        }
        for k in i + 1..N {
            let lki = l[k][i];
            for x in xs.iter_mut() {
                x[i] -= lki * x[k];
            }
        }
    }
}

fn solve_many_dynamic(n: usize, l: &[f64], xs: &mut [f64]) {
    for x in xs.chunks_exact_mut(n) {
        solve_dynamic(n, l, x);
    }
}

/// `aᵀ b` over the shorter of the two slices.
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `y += alpha x`.
#[inline]
pub fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += alpha * x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `A x` for the row-major `n × n` matrix `a`.
    fn times(a: &[f64], n: usize, x: &[f64]) -> Vec<f64> {
        (0..n).map(|i| dot(&a[i * n..(i + 1) * n], x)).collect()
    }

    #[test]
    fn the_factor_solves_a_spd_system() {
        let a = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let x_true = [1.0, -2.0, 0.5];
        let mut b = times(&a, 3, &x_true);
        let mut factor = Factor::new(3, false);
        assert!(factor.factor(&a, 3));
        factor.solve(&mut b);
        for (x, t) in b.iter().zip(x_true) {
            assert!((x - t).abs() < 1e-12, "{x} vs {t}");
        }
    }

    #[test]
    fn fixed_and_dynamic_sizes_agree_for_many_right_hand_sides() {
        // A 10 × 10 SPD matrix: its leading blocks exercise sizes 1..=10 (fixed up to 8).
        let n: usize = 10;
        let a: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                1.0 / (1.0 + i.abs_diff(j) as f64) + if i == j { n as f64 } else { 0.0 }
            })
            .collect();
        for size in 1..=n {
            let block: Vec<f64> = (0..size * size)
                .map(|k| a[(k / size) * n + k % size])
                .collect();
            let mut factor = Factor::new(n, false);
            assert!(factor.factor(&block, size));
            let rhs: Vec<f64> = (0..3 * size).map(|i| (i as f64).sin()).collect();
            let mut x = rhs.clone();
            factor.solve(&mut x);
            for (x, b) in x.chunks_exact(size).zip(rhs.chunks_exact(size)) {
                let residual = times(&block, size, x);
                for (r, b) in residual.iter().zip(b) {
                    assert!((r - b).abs() < 1e-12, "size {size}: {r} vs {b}");
                }
            }
        }
    }

    #[test]
    fn the_diagonal_shortcut_divides() {
        let d = [2.0, 0.0, 0.0, 4.0];
        let mut diagonal = Factor::new(2, true);
        assert!(diagonal.factor(&d, 2));
        let mut x = [1.0, 1.0, 2.0, 2.0];
        diagonal.solve(&mut x);
        assert_eq!(x, [0.5, 0.25, 1.0, 0.5]);
        assert!(!diagonal.factor(&[1.0, 0.0, 0.0, -1.0], 2));
    }

    #[test]
    fn the_factor_rejects_an_indefinite_or_non_finite_matrix() {
        let mut factor = Factor::new(2, false);
        assert!(!factor.factor(&[1.0, 2.0, 2.0, 1.0], 2));
        assert!(!factor.factor(&[1.0, 0.0, 0.0, f64::NAN], 2));
    }
}
