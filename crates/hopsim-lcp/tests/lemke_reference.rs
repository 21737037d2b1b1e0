//! Lemke's pivoting against a textbook implementation in exact rational arithmetic
//! (Murty, "Linear Complementarity, Linear and Nonlinear Programming", §2.3–2.4: the full
//! tableau `[I | −M | −d | q]`, the lexicographic minimum-ratio test on the rows of
//! `[q̄ | B⁻¹]`, `z0`'s row leaving whenever it ties for the minimum ratio). On small
//! integer problems, where degenerate ties are exact, the solver must take the same path:
//! the same ending after the same number of pivots, with the same `z`.

use hopsim_lcp::{LcpStatus, LemkeOptions, LemkeSolver};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use std::cmp::Ordering;

/// A rational number `n / d` in lowest terms, `d > 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Q {
    n: i128,
    d: i128,
}

fn gcd(a: i128, b: i128) -> i128 {
    if b == 0 {
        a.abs()
    } else {
        gcd(b, a % b)
    }
}

impl Q {
    fn int(n: i64) -> Q {
        Q {
            n: i128::from(n),
            d: 1,
        }
    }

    fn new(n: i128, d: i128) -> Q {
        assert!(
            d != 0 && n.abs() < 1 << 100 && d.abs() < 1 << 100,
            "too large"
        );
        let g = gcd(n, d).max(1) * d.signum();
        Q { n: n / g, d: d / g }
    }

    fn sub(self, o: Q) -> Q {
        Q::new(self.n * o.d - o.n * self.d, self.d * o.d)
    }

    fn mul(self, o: Q) -> Q {
        Q::new(self.n * o.n, self.d * o.d)
    }

    fn div(self, o: Q) -> Q {
        Q::new(self.n * o.d, self.d * o.n)
    }

    fn cmp(self, o: Q) -> Ordering {
        (self.n * o.d).cmp(&(o.n * self.d))
    }

    fn to_f64(self) -> f64 {
        self.n as f64 / self.d as f64
    }
}

#[derive(Debug, PartialEq, Eq)]
enum Ending {
    Complementary,
    Ray,
    PivotLimit,
}

/// Lemke's method with covering vector `d` on the exact tableau; `(ending, pivots, z)`.
fn lemke_exact(m: &[Vec<i64>], q: &[i64], d: &[i64], max_pivots: usize) -> (Ending, usize, Vec<Q>) {
    let n = q.len();
    let z0 = 2 * n;
    // Columns: w_0..w_{n-1}, z_0..z_{n-1}, z0, then the right-hand side.
    let mut t: Vec<Vec<Q>> = (0..n)
        .map(|i| {
            let mut row = vec![Q::int(0); 2 * n + 2];
            row[i] = Q::int(1);
            for j in 0..n {
                row[n + j] = Q::int(-m[i][j]);
            }
            row[z0] = Q::int(-d[i]);
            row[2 * n + 1] = Q::int(q[i]);
            row
        })
        .collect();
    let mut basis: Vec<usize> = (0..n).collect();
    let rhs = 2 * n + 1;
    let z_of = |t: &Vec<Vec<Q>>, basis: &Vec<usize>| {
        let mut z = vec![Q::int(0); n];
        for (i, &v) in basis.iter().enumerate() {
            if (n..2 * n).contains(&v) {
                z[v - n] = t[i][rhs];
            }
        }
        z
    };
    if q.iter().all(|&v| v >= 0) {
        return (Ending::Complementary, 0, vec![Q::int(0); n]);
    }
    // The row of `[q̄ | B⁻¹]` divided by `div(i)`, compared lexicographically.
    let key = |t: &Vec<Vec<Q>>, i: usize, div: Q| -> Vec<Q> {
        std::iter::once(rhs)
            .chain(0..n)
            .map(|k| t[i][k].div(div))
            .collect()
    };
    let lex_min = |t: &Vec<Vec<Q>>, rows: &[usize], div: &dyn Fn(usize) -> Q| -> usize {
        let mut best = rows[0];
        for &i in &rows[1..] {
            let (a, b) = (key(t, i, div(i)), key(t, best, div(best)));
            let order = a
                .iter()
                .zip(&b)
                .map(|(x, y)| x.cmp(*y))
                .find(|o| *o != Ordering::Equal)
                .unwrap_or(Ordering::Equal);
            if order == Ordering::Less {
                best = i;
            }
        }
        best
    };
    let pivot = |t: &mut Vec<Vec<Q>>, basis: &mut Vec<usize>, r: usize, c: usize| {
        let p = t[r][c];
        for v in t[r].iter_mut() {
            *v = v.div(p);
        }
        let pivot_row = t[r].clone();
        for (i, row) in t.iter_mut().enumerate() {
            if i != r && row[c].n != 0 {
                let f = row[c];
                for (x, &p) in row.iter_mut().zip(&pivot_row) {
                    *x = x.sub(f.mul(p));
                }
            }
        }
        let leaving = basis[r];
        basis[r] = c;
        leaving
    };
    // z0 enters (its column is −d: the most negative q_i/d_i leaves, lexicographically).
    let all: Vec<usize> = (0..n).collect();
    let r = lex_min(&t, &all, &|i| Q::int(d[i]));
    let mut leaving = pivot(&mut t, &mut basis, r, z0);
    let mut pivots = 1;
    loop {
        let entering = if leaving < n {
            leaving + n
        } else {
            leaving - n
        };
        if pivots >= max_pivots {
            return (Ending::PivotLimit, pivots, z_of(&t, &basis));
        }
        let rows: Vec<usize> = (0..n).filter(|&i| t[i][entering].n > 0).collect();
        if rows.is_empty() {
            return (Ending::Ray, pivots, z_of(&t, &basis));
        }
        let min = rows
            .iter()
            .map(|&i| t[i][rhs].div(t[i][entering]))
            .min_by(|a, b| a.cmp(*b))
            .unwrap();
        let tied: Vec<usize> = rows
            .iter()
            .copied()
            .filter(|&i| t[i][rhs].div(t[i][entering]).cmp(min) == Ordering::Equal)
            .collect();
        let z0_row = basis.iter().position(|&v| v == z0).unwrap();
        let r = if tied.contains(&z0_row) {
            z0_row
        } else {
            let column: Vec<Q> = (0..n).map(|i| t[i][entering]).collect();
            lex_min(&t, &tied, &|i| column[i])
        };
        leaving = pivot(&mut t, &mut basis, r, entering);
        pivots += 1;
        if leaving == z0 {
            return (Ending::Complementary, pivots, z_of(&t, &basis));
        }
    }
}

/// Small integer problems: `M` in `−2 … 3`, `q` in `−3 … 2`, a covering vector in `1 … 3`
/// (all ones half the time), rows repeated now and then: degenerate ties abound.
fn integer_problem() -> impl Strategy<Value = (Vec<Vec<i64>>, Vec<i64>, Vec<i64>)> {
    (1..=6usize).prop_flat_map(|n| {
        (
            prop::collection::vec(prop::collection::vec(-2..=3i64, n), n),
            prop::collection::vec(-3..=2i64, n),
            prop_oneof![Just(vec![1i64; n]), prop::collection::vec(1..=3i64, n)],
            prop::collection::vec(0..n, 0..=n / 2),
        )
            .prop_map(move |(mut m, mut q, d, repeats)| {
                for (k, &src) in repeats.iter().enumerate() {
                    let dst = (src + 1 + k) % n;
                    m[dst] = m[src].clone();
                    q[dst] = q[src];
                }
                (m, q, d)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn lemke_takes_the_path_of_the_exact_lexicographic_method((m, q, d) in integer_problem()) {
        let n = q.len();
        let max_pivots = 50 * n + 100;
        let (ending, pivots, z) = lemke_exact(&m, &q, &d, max_pivots);
        let options = LemkeOptions {
            covering: Some(d.iter().map(|&v| v as f64).collect()),
            fallback: false,
            ..LemkeOptions::default()
        };
        let mm = DMatrix::from_fn(n, n, |i, j| m[i][j] as f64);
        let qq = DVector::from_fn(n, |i, _| q[i] as f64);
        let sol = LemkeSolver::new(options).solve(mm.as_view(), qq.as_view()).unwrap().clone();
        let status = match ending {
            Ending::Complementary => LcpStatus::Solved,
            Ending::Ray => LcpStatus::RayTermination,
            Ending::PivotLimit => LcpStatus::PivotLimit,
        };
        prop_assert_eq!((sol.status, sol.pivots), (status, pivots), "M = {:?}, q = {:?}, d = {:?}", m, q, d);
        if ending == Ending::Complementary {
            for (zi, exact) in sol.z.iter().zip(&z) {
                let e = exact.to_f64();
                prop_assert!((zi - e).abs() <= 1e-12 * e.abs().max(1.0), "z = {}, exact {:?}", sol.z, z);
            }
        }
    }
}
