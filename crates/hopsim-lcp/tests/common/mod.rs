//! Shared by the integration tests and the benchmarks: contact LCPs of the form in
//! docs/physics.md §4 and an independent brute-force LCP solver.
#![allow(dead_code)]

use hopsim_lcp::{LcpSolution, LemkeOptions, LemkeSolver};
use nalgebra::{DMatrix, DVector};

/// Lemke's method alone: no fallback covering vectors, no enumeration.
pub fn no_fallback() -> LemkeOptions {
    LemkeOptions {
        fallback: false,
        ..LemkeOptions::default()
    }
}

/// Solves `(M, q)` with a fresh solver configured by `options`; panics on invalid input.
pub fn solve_with(options: LemkeOptions, m: &DMatrix<f64>, q: &DVector<f64>) -> LcpSolution {
    LemkeSolver::new(options)
        .solve(m.as_view(), q.as_view())
        .unwrap()
        .clone()
}

/// Planar contact system: diagonal mass matrix, one normal and one tangential generalised
/// force direction per contact (columns of `W_N`, `W_T`), friction coefficients.
pub struct ContactSystem {
    pub mass: Vec<f64>,
    pub w_n: Vec<Vec<f64>>,
    pub w_t: Vec<Vec<f64>>,
    pub mu: Vec<f64>,
}

/// Disc of radius `r` whose centre of mass is `a` from its centre (docs/physics.md §2), with
/// its generalised coordinates `(x, y, φ)` starting at `dof`.
#[derive(Clone, Copy)]
pub struct Disc {
    pub dof: usize,
    pub r: f64,
    pub a: f64,
    pub phi: f64,
    /// Disc centre.
    pub cx: f64,
    pub cy: f64,
}

impl Disc {
    pub fn com(&self) -> [f64; 2] {
        [
            self.cx + self.a * self.phi.sin(),
            self.cy - self.a * self.phi.cos(),
        ]
    }
}

fn cross(r: [f64; 2], v: [f64; 2]) -> f64 {
    r[0] * v[1] - r[1] * v[0]
}

impl ContactSystem {
    pub fn new(mass: Vec<f64>) -> Self {
        ContactSystem {
            mass,
            w_n: vec![],
            w_t: vec![],
            mu: vec![],
        }
    }

    /// Contact at world point `p` with unit normal `n` (pointing into `disc`), optionally
    /// against a second disc `other` (which feels the opposite force).
    pub fn add(&mut self, disc: &Disc, other: Option<&Disc>, p: [f64; 2], n: [f64; 2], mu: f64) {
        let f = self.mass.len();
        let t = [n[1], -n[0]];
        let mut wn = vec![0.0; f];
        let mut wt = vec![0.0; f];
        for (body, sign) in std::iter::once((disc, 1.0)).chain(other.map(|o| (o, -1.0))) {
            let c = body.com();
            let r = [p[0] - c[0], p[1] - c[1]];
            wn[body.dof] += sign * n[0];
            wn[body.dof + 1] += sign * n[1];
            wn[body.dof + 2] += sign * cross(r, n);
            wt[body.dof] += sign * t[0];
            wt[body.dof + 1] += sign * t[1];
            wt[body.dof + 2] += sign * cross(r, t);
        }
        self.w_n.push(wn);
        self.w_t.push(wt);
        self.mu.push(mu);
    }

    /// Disc on flat ground `y = 0` (its centre at height `r`): `w_N = (0, 1, −a sin φ)`,
    /// `w_T = (1, 0, R − a cos φ)` (docs/physics.md §2).
    pub fn ground(&mut self, d: &Disc, mu: f64) {
        self.add(d, None, [d.cx, d.cy - d.r], [0.0, 1.0], mu);
    }

    /// Disc against the corner of a step of height `h` to its right.
    pub fn corner(&mut self, d: &Disc, h: f64, mu: f64) {
        let dx = (2.0 * d.r * h - h * h).sqrt();
        let n = [-dx / d.r, (d.r - h) / d.r];
        self.add(d, None, [d.cx - d.r * n[0], d.cy - d.r * n[1]], n, mu);
    }

    /// Disc against a vertical wall touching it on its right.
    pub fn wall(&mut self, d: &Disc, mu: f64) {
        self.add(d, None, [d.cx + d.r, d.cy], [-1.0, 0.0], mu);
    }

    /// Disc `d` touching disc `left` on its left.
    pub fn pair(&mut self, left: &Disc, d: &Disc, mu: f64) {
        let (ex, ey) = (d.cx - left.cx, d.cy - left.cy);
        let len = (ex * ex + ey * ey).sqrt();
        let n = [ex / len, ey / len];
        let p = [d.cx - d.r * n[0], d.cy - d.r * n[1]];
        self.add(d, Some(left), p, n, mu);
    }

    /// The LCP `w = A z + b` of docs/physics.md §4 (restitution 0) for `ũ = u^A + G h Δt`:
    /// `z = (Λ_N, Λ_R, ξ_L)`, `w = (ξ_N, ξ_R, Λ_L)`.
    pub fn lcp(&self, u_tilde: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
        let k = self.mu.len();
        let g = |x: &[f64], y: &[f64]| -> f64 {
            x.iter()
                .zip(y)
                .zip(&self.mass)
                .map(|((a, b), m)| a * b / m)
                .sum()
        };
        let dot = |x: &[f64]| -> f64 { x.iter().zip(u_tilde).map(|(a, b)| a * b).sum() };
        let mut a = DMatrix::zeros(3 * k, 3 * k);
        let mut b = DVector::zeros(3 * k);
        for r in 0..k {
            for c in 0..k {
                let (g_nn, g_nt) = (g(&self.w_n[r], &self.w_n[c]), g(&self.w_n[r], &self.w_t[c]));
                let (g_tn, g_tt) = (g(&self.w_t[r], &self.w_n[c]), g(&self.w_t[r], &self.w_t[c]));
                a[(r, c)] = g_nn - g_nt * self.mu[c];
                a[(r, k + c)] = g_nt;
                a[(k + r, c)] = g_tn - g_tt * self.mu[c];
                a[(k + r, k + c)] = g_tt;
            }
            a[(k + r, 2 * k + r)] = 1.0;
            a[(2 * k + r, r)] = 2.0 * self.mu[r];
            a[(2 * k + r, k + r)] = -1.0;
            b[r] = dot(&self.w_n[r]);
            b[k + r] = dot(&self.w_t[r]);
        }
        (a, b)
    }
}

/// Robbit (docs/physics.md §5.3): `q = (x, y, φ, ψ)`, `M = diag(1.405, 1.405, 3.004e-3,
/// 1.543e-3)`, eccentric disc `R = 0.2`, `a = 0.1`, `μ = 1`, rolling at `φ̇ = −3 rad/s`
/// on the ground into the corner of a 5 cm step (two closed contacts, a 6×6 LCP), flywheel
/// spinning at 20 rad/s, motor torque 0.2 N m, `Δt = 2e-4 s`.
pub fn robbit_two_contacts() -> (DMatrix<f64>, DVector<f64>) {
    let (m, i_s, i_r) = (0.974 + 0.431, 3.004e-3, 1.543e-3);
    let (r, a, phi) = (0.2, 0.1, 0.3);
    let disc = Disc {
        dof: 0,
        r,
        a,
        phi,
        cx: 0.0,
        cy: r,
    };
    let mut sys = ContactSystem::new(vec![m, m, i_s, i_r]);
    sys.ground(&disc, 1.0);
    sys.corner(&disc, 0.05, 1.0);
    let phi_dot = -3.0;
    let u = [
        phi_dot * (a * phi.cos() - r),
        phi_dot * a * phi.sin(),
        phi_dot,
        20.0,
    ];
    let (torque, dt, g) = (0.2, 2e-4, 9.81);
    let h = [0.0, -m * g, -torque, torque];
    let u_tilde: Vec<f64> = (0..4).map(|i| u[i] + h[i] / sys.mass[i] * dt).collect();
    sys.lcp(&u_tilde)
}

/// Small deterministic generator (xorshift), so tests and benches need no extra crates.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// A row of `discs` eccentric discs on the ground, each touching the next, the last one
/// against a wall: `2·discs` contacts (a `6·discs` LCP), or one disc on the ground alone
/// when `ground_only`. Masses, radii, angles, velocities and `μ` come from `rng`.
pub fn disc_row(
    rng: &mut Rng,
    discs: usize,
    ground_only: bool,
    mu: Option<f64>,
) -> (DMatrix<f64>, DVector<f64>) {
    let mut mass = Vec::new();
    let mut row: Vec<Disc> = Vec::new();
    let mut x = 0.0;
    for i in 0..discs {
        let r = rng.uniform(0.1, 0.3);
        let m = rng.uniform(0.5, 2.0);
        if let Some(prev) = row.last() {
            x += 2.0 * (prev.r * r).sqrt();
        }
        mass.extend([m, m, m * r * r * rng.uniform(0.2, 0.5)]);
        let a = r * rng.uniform(0.0, 0.6);
        row.push(Disc {
            dof: 3 * i,
            r,
            a,
            phi: rng.uniform(-1.0, 1.0),
            cx: x,
            cy: r,
        });
    }
    let mut sys = ContactSystem::new(mass);
    let mu_of = |rng: &mut Rng| mu.unwrap_or_else(|| rng.uniform(0.1, 1.5));
    for (i, d) in row.iter().enumerate() {
        let m = mu_of(rng);
        sys.ground(d, m);
        if i > 0 {
            let m = mu_of(rng);
            sys.pair(&row[i - 1], d, m);
        }
    }
    if !ground_only {
        let m = mu_of(rng);
        sys.wall(row.last().unwrap(), m);
    }
    let u: Vec<f64> = (0..sys.mass.len())
        .map(|i| match i % 3 {
            0 => rng.uniform(-0.5, 1.0),
            1 => rng.uniform(-1.0, 0.1),
            _ => rng.uniform(-5.0, 5.0),
        })
        .collect();
    sys.lcp(&u)
}

/// Every solution of the LCP found by brute force over all `2ⁿ` complementary bases
/// (independent of the crate: nalgebra's LU, its own feasibility test).
pub fn brute_force(m: &DMatrix<f64>, q: &DVector<f64>, tol: f64) -> Vec<DVector<f64>> {
    let n = q.len();
    let mut out = Vec::new();
    for mask in 0u32..(1 << n) {
        let s: Vec<usize> = (0..n).filter(|j| mask & (1 << j) != 0).collect();
        let mut z = DVector::zeros(n);
        if !s.is_empty() {
            let mss = DMatrix::from_fn(s.len(), s.len(), |i, j| m[(s[i], s[j])]);
            let rhs = DVector::from_fn(s.len(), |i, _| -q[s[i]]);
            let Some(x) = mss.lu().solve(&rhs) else {
                continue;
            };
            for (k, &j) in s.iter().enumerate() {
                z[j] = x[k];
            }
        }
        let w = m * &z + q;
        // Reject near-singular bases (huge, inaccurate z) and keep feasible ones.
        let accurate = z.amax() < 1e8 && s.iter().all(|&i| w[i].abs() <= tol);
        if accurate && z.iter().chain(w.iter()).all(|&v| v >= -tol) {
            out.push(z);
        }
    }
    out
}
