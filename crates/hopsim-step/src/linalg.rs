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

/// A rank-revealing `L D Lᵀ` factorisation with diagonal (complete) pivoting of a small
/// symmetric positive semi-definite matrix, in reused buffers (docs/physics.md §8.3): the
/// pivot is the largest remaining diagonal entry, and the factorisation stops where it
/// falls to `rel_tol` times the largest diagonal entry of the matrix. The rows past the
/// rank are dependent on the others (to that tolerance); [`PivotedFactor::solve`] gives
/// them zero, which solves every consistent system `A x = b` (`b` in the range of `A`)
/// exactly, as a pseudo-inverse would.
#[derive(Clone, Debug)]
pub struct PivotedFactor {
    n: usize,
    rank: usize,
    /// `perm[k]`: the original index of pivot `k`.
    perm: Vec<usize>,
    /// The `n × n` working matrix: `L` below the diagonal, `D` on it (first `rank` columns).
    data: Vec<f64>,
    work: Vec<f64>,
}

impl PivotedFactor {
    /// Room for matrices up to `capacity × capacity`.
    pub fn new(capacity: usize) -> Self {
        Self {
            n: 0,
            rank: 0,
            perm: vec![0; capacity],
            data: vec![0.0; capacity * capacity],
            work: vec![0.0; capacity],
        }
    }

    /// Factors the row-major `n × n` `a` (stride `n`); returns its numerical rank (0 for
    /// a zero or non-finite matrix).
    pub fn factor(&mut self, a: &[f64], n: usize, rel_tol: f64) -> usize {
        self.n = n;
        let d = &mut self.data[..n * n];
        d.copy_from_slice(&a[..n * n]);
        for (k, p) in self.perm[..n].iter_mut().enumerate() {
            *p = k;
        }
        let largest = (0..n).fold(0.0_f64, |m, i| m.max(d[i * n + i]));
        self.rank = 0;
        if !(largest.is_finite() && largest > 0.0) {
            return 0;
        }
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| d[i * n + i].total_cmp(&d[j * n + j]))
                .unwrap_or(k);
            let pivot = d[p * n + p];
            // Also stops at a NaN pivot.
            if pivot.partial_cmp(&(rel_tol * largest)) != Some(std::cmp::Ordering::Greater) {
                break;
            }
            if p != k {
                self.perm.swap(k, p);
                for c in 0..n {
                    d.swap(k * n + c, p * n + c);
                }
                for r in 0..n {
                    d.swap(r * n + k, r * n + p);
                }
            }
            // The trailing block's Schur complement; the column becomes `L`.
            for i in k + 1..n {
                let l = d[i * n + k] / pivot;
                for j in k + 1..n {
                    d[i * n + j] -= l * d[k * n + j];
                }
            }
            for i in k + 1..n {
                d[i * n + k] /= pivot;
            }
            self.rank = k + 1;
        }
        self.rank
    }

    /// The original indices of the rows left out as dependent (past the rank).
    pub fn dependent(&self) -> &[usize] {
        &self.perm[self.rank..self.n]
    }

    /// Solves `A x = b` in place (`x`: `b` in, length `n`): the independent unknowns from
    /// the factor, the dependent ones zero.
    pub fn solve(&mut self, x: &mut [f64]) {
        let (n, r) = (self.n, self.rank);
        let (d, y) = (&self.data, &mut self.work[..r]);
        for (k, y) in y.iter_mut().enumerate() {
            *y = x[self.perm[k]];
        }
        for i in 0..r {
            let s: f64 = (0..i).map(|k| d[i * n + k] * y[k]).sum();
            y[i] -= s;
        }
        for i in (0..r).rev() {
            let mut s = y[i] / d[i * n + i];
            for k in i + 1..r {
                s -= d[k * n + i] * y[k];
            }
            y[i] = s;
        }
        x[..n].fill(0.0);
        for (k, y) in y.iter().enumerate() {
            x[self.perm[k]] = *y;
        }
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

    #[test]
    fn the_pivoted_factor_solves_a_consistent_singular_system() {
        // A = B Bᵀ with a third row of B the sum of the first two: rank 2.
        let b = [[1.0, 2.0, 0.5], [0.0, -1.0, 3.0]];
        let rows = [b[0], b[1], [1.0, 1.0, 3.5]];
        let a: Vec<f64> = (0..9).map(|k| dot(&rows[k / 3], &rows[k % 3])).collect();
        let mut factor = PivotedFactor::new(3);
        assert_eq!(factor.factor(&a, 3, 1e-12), 2);
        assert_eq!(factor.dependent().len(), 1);
        // b in the range of A: A x_true.
        let x_true = [0.3, -1.0, 2.0];
        let mut x = times(&a, 3, &x_true);
        let rhs = x.clone();
        factor.solve(&mut x);
        for (r, b) in times(&a, 3, &x).iter().zip(&rhs) {
            assert!((r - b).abs() < 1e-12 * b.abs().max(1.0), "{r} vs {b}");
        }
        // A regular matrix has full rank and the exact solution.
        let spd = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        assert_eq!(factor.factor(&spd, 3, 1e-12), 3);
        let mut x = times(&spd, 3, &x_true);
        factor.solve(&mut x);
        for (x, t) in x.iter().zip(x_true) {
            assert!((x - t).abs() < 1e-12, "{x} vs {t}");
        }
        assert_eq!(factor.factor(&[f64::NAN; 9], 3, 1e-12), 0);
    }
}
