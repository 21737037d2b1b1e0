//! Small numerical tools shared by the analyses: a bracketing root finder (Brent), the
//! first root of a function on an interval (scan + Brent), a golden-section minimiser,
//! an adaptive Dormand–Prince 5(4) step and an integrator that stops at an event, a
//! Levenberg–Marquardt least-squares solver with a finite-difference Jacobian, and the
//! eigenvalues of a 2 × 2 matrix.

use crate::dop853;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Brent's method on a bracket `[a, b]` with `f(a)` and `f(b)` of opposite sign (or one of
/// them zero). Returns `None` without a sign change. `tolerance` is absolute in `x`.
pub fn brent(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, tolerance: f64) -> Option<f64> {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a), f(b));
    if !(fa.is_finite() && fb.is_finite()) {
        return None;
    }
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa.signum() == fb.signum() {
        return None;
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * tolerance;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Some(b);
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
        if !fb.is_finite() {
            return None;
        }
    }
    Some(b)
}

/// The first point in `(start, end]` where `f` changes sign, found by scanning `steps`
/// equal sub-intervals from `start` and refining the first bracket with [`brent`].
/// `f(start)` itself is not treated as a root (the caller removes a known root there,
/// e.g. by dividing by `t`). Returns `None` when no sign change is found.
pub fn first_sign_change(
    f: impl FnMut(f64) -> f64,
    start: f64,
    end: f64,
    steps: usize,
    tolerance: f64,
) -> Option<f64> {
    first_sign_change_lipschitz(f, start, end, steps, f64::INFINITY, tolerance)
}

/// [`first_sign_change`] for an `f` whose slope is bounded, `|f'| ≤ lipschitz`: from a
/// point with value `f(t)` no root lies within `|f(t)| / lipschitz`, so the scan steps by
/// the larger of that distance and the equal sub-interval. It finds every root the
/// equal-step scan finds, with fewer evaluations where `|f|` is large.
pub fn first_sign_change_lipschitz(
    mut f: impl FnMut(f64) -> f64,
    start: f64,
    end: f64,
    steps: usize,
    lipschitz: f64,
    tolerance: f64,
) -> Option<f64> {
    let h = (end - start) / steps.max(1) as f64;
    let mut t0 = start;
    let mut f0 = f(t0);
    while t0 < end {
        let t1 = (t0 + h.max(f0.abs() / lipschitz)).min(end);
        let f1 = f(t1);
        if f1 == 0.0 {
            return Some(t1);
        }
        if f0 != 0.0 && f1.signum() != f0.signum() {
            return brent(&mut f, t0, t1, tolerance);
        }
        t0 = t1;
        f0 = f1;
    }
    None
}

/// Golden-section search for a minimum of `f` on `[a, b]` (assumed unimodal there).
/// Returns `(x, f(x))`.
pub fn golden_section_minimum(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    iterations: usize,
) -> (f64, f64) {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (a, b);
    let mut x1 = b - ratio * (b - a);
    let mut x2 = a + ratio * (b - a);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    for _ in 0..iterations {
        if f1 <= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - ratio * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + ratio * (b - a);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        (x1, f1)
    } else {
        (x2, f2)
    }
}

/// One Dormand–Prince 5(4) step of `y' = f(t, y)` from `(t, y)` with size `h`.
/// Returns the fifth-order solution and the embedded error estimate (y5 − y4).
pub fn dormand_prince_step<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    y: &[f64; N],
    h: f64,
) -> ([f64; N], [f64; N]) {
    let (y5, err, _) = dormand_prince_stages(f, t, y, &f(t, y), h);
    (y5, err)
}

/// [`dormand_prince_step`] given its first stage `k0 = f(t, y)`, which does not depend on
/// `h` (so a step retried with another `h`, or the trial steps of an event search, share
/// it). Also returns the last stage `f(t + h, y5)`: the method is "first same as last", so
/// that stage is the next step's `k0`, bit for bit (its state is `y5`, summed in the same
/// order).
pub fn dormand_prince_stages<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    y: &[f64; N],
    k0: &[f64; N],
    h: f64,
) -> ([f64; N], [f64; N], [f64; N]) {
    const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
    const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    // First same as last: the fifth-order weights are the last stage's row of `A`.
    const B5: [f64; 7] = {
        let a = A[6];
        [a[0], a[1], a[2], a[3], a[4], a[5], 0.0]
    };
    const B4: [f64; 7] = [
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ];
    let mut k = [[0.0; N]; 7];
    k[0] = *k0;
    for stage in 1..7 {
        let mut ys = *y;
        for (j, a) in A[stage].iter().enumerate().take(stage) {
            for i in 0..N {
                ys[i] += h * a * k[j][i];
            }
        }
        k[stage] = f(t + C[stage] * h, &ys);
    }
    let mut y5 = *y;
    let mut err = [0.0; N];
    for stage in 0..7 {
        for i in 0..N {
            y5[i] += h * B5[stage] * k[stage][i];
            err[i] += h * (B5[stage] - B4[stage]) * k[stage][i];
        }
    }
    (y5, err, k[6])
}

/// The scaled error norm of a Dormand–Prince step (≤ 1 means accept).
pub fn error_norm<const N: usize>(
    y: &[f64; N],
    y_new: &[f64; N],
    err: &[f64; N],
    rtol: f64,
    atol: f64,
) -> f64 {
    (0..N)
        .map(|i| err[i].abs() / (atol + rtol * y[i].abs().max(y_new[i].abs())))
        .fold(0.0, f64::max)
}

/// `sin(x)/x`, accurate near zero.
pub fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// `n` values evenly spaced from `start` to `end` inclusive (`n == 1` gives `start`).
pub fn linspace(start: f64, end: f64, n: usize) -> Vec<f64> {
    match n {
        0 => Vec::new(),
        1 => vec![start],
        _ => (0..n)
            .map(|i| start + (end - start) * i as f64 / (n - 1) as f64)
            .collect(),
    }
}

/// `n` values evenly spaced in `log10` from `start` to `end` inclusive (both > 0).
pub fn logspace(start: f64, end: f64, n: usize) -> Vec<f64> {
    linspace(start.log10(), end.log10(), n)
        .into_iter()
        .map(|e| 10f64.powf(e))
        .collect()
}

/// Tolerances and step limits of [`integrate_to_event`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdeSettings {
    /// Relative tolerance of the Dormand–Prince error estimate.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// First trial step.
    pub initial_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Largest number of step attempts before giving up.
    pub max_steps: usize,
}

/// How [`integrate_to_event`] ended.
#[derive(Debug, Clone, PartialEq)]
pub enum OdeEnd<const N: usize, B> {
    /// The event function reached zero from below at `t` (or was already ≥ 0 at the start).
    Event {
        /// Event time.
        t: f64,
        /// State at the event.
        y: [f64; N],
    },
    /// The `accepted` callback asked to stop after an accepted step at `t`.
    Stopped {
        /// Time of the accepted step.
        t: f64,
        /// What the callback returned.
        reason: B,
    },
    /// `max_steps` step attempts without the event.
    StepLimit {
        /// Time reached.
        t: f64,
    },
    /// The state or the error estimate became non-finite at `t`.
    NonFinite {
        /// Time reached.
        t: f64,
    },
}

/// Integrates `y' = f(t, y)` from `(t0, y0)` with adaptive Dormand–Prince 8(5,3) steps
/// ([`crate::dop853`]) until `event(t, y)` first reaches zero from below; the crossing
/// inside the step is located by Brent's method on the step's seventh-order continuous
/// extension, to `1e-15 · max_step`, and the state there is the eighth-order solution of a
/// step of that length from the step's start. An event value ≥ 0
/// at the start is an event at `t0`. A crossing and re-crossing within one step is not
/// seen (steps are bounded by `max_step`). After every accepted step `accepted(t, y)` may
/// return `Some(reason)` to stop.
pub fn integrate_to_event<const N: usize, B>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t0: f64,
    y0: [f64; N],
    settings: &OdeSettings,
    event: impl Fn(f64, &[f64; N]) -> f64,
    mut accepted: impl FnMut(f64, &[f64; N]) -> Option<B>,
) -> OdeEnd<N, B> {
    let (mut t, mut y) = (t0, y0);
    if event(t, &y) >= 0.0 {
        return OdeEnd::Event { t, y };
    }
    let mut h = settings.initial_step.min(settings.max_step);
    // The first stage of the step: `f` at its start state.
    let mut k0 = f(t, &y);
    for _ in 0..settings.max_steps {
        let step = dop853::stages(f, t, &y, &k0, h);
        let y_new = step.y;
        let errors = (&step.err5, &step.err3);
        let norm = dop853::error_norm(&y, &y_new, errors, h, settings.rtol, settings.atol);
        if !norm.is_finite() || !y_new.iter().all(|v| v.is_finite()) {
            return OdeEnd::NonFinite { t };
        }
        if norm > 1.0 {
            h *= (0.9 * dop853::step_factor(norm)).max(0.2);
            continue;
        }
        if event(t + h, &y_new) >= 0.0 {
            let dense = step.dense(f, t, &y, h);
            let value = |s: f64| {
                if s == 0.0 {
                    event(t, &y)
                } else {
                    event(t + s, &dense.at(s))
                }
            };
            let s = brent(value, 0.0, h, 1e-15 * settings.max_step).unwrap_or(h);
            return OdeEnd::Event {
                t: t + s,
                y: dop853::stages(f, t, &y, &k0, s).y,
            };
        }
        t += h;
        y = y_new;
        k0 = f(t, &y);
        if let Some(reason) = accepted(t, &y) {
            return OdeEnd::Stopped { t, reason };
        }
        h = (h * (0.9 * dop853::step_factor(norm.max(1e-16))).min(5.0)).min(settings.max_step);
    }
    OdeEnd::StepLimit { t }
}

/// Settings of [`levenberg_marquardt`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LmSettings {
    /// Converged when the residual's Euclidean norm is at most this.
    pub tolerance: f64,
    /// Largest number of accepted or rejected steps.
    pub max_iterations: usize,
    /// Forward-difference step of the Jacobian, relative to `max(|x_j|, 1)`.
    pub jacobian_step: f64,
    /// Initial damping `λ` (relative to the diagonal of `JᵀJ`).
    pub initial_damping: f64,
}

impl Default for LmSettings {
    fn default() -> Self {
        LmSettings {
            tolerance: 1e-10,
            max_iterations: 60,
            jacobian_step: 1e-6,
            initial_damping: 1e-3,
        }
    }
}

/// Result of [`levenberg_marquardt`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LmResult<const N: usize> {
    /// Best point found.
    #[serde(with = "serde_array")]
    pub x: [f64; N],
    /// Residual norm there.
    pub residual_norm: f64,
    /// Iterations used.
    pub iterations: usize,
    /// Residual evaluations used (including the Jacobian's).
    pub evaluations: usize,
    /// `residual_norm ≤ tolerance`.
    pub converged: bool,
}

mod serde_array {
    use serde::Serializer;
    pub fn serialize<S: Serializer, const N: usize>(x: &[f64; N], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(x.iter())
    }
}

/// Levenberg–Marquardt for `min ‖r(x)‖²`, `r: ℝᴺ → ℝᴹ` (a square system `M = N` is solved
/// for `r = 0`, i.e. damped Newton). The Jacobian comes from forward differences (backward
/// where the forward point is undefined), recomputed after every accepted step; steps solve `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr` (Marquardt scaling).
/// `r` may fail (`None`) at points where it is undefined: such a trial step is rejected
/// and the damping raised. Returns `None` when `r(x0)` itself fails.
pub fn levenberg_marquardt<const N: usize, const M: usize>(
    mut residual: impl FnMut(&[f64; N]) -> Option<[f64; M]>,
    x0: [f64; N],
    settings: &LmSettings,
) -> Option<LmResult<N>> {
    let r0 = residual(&x0);
    levenberg_marquardt_from(residual, x0, r0, settings)
}

/// [`levenberg_marquardt`] from `x0` with its residual `r0 = r(x0)` already evaluated (a
/// multi-start search ranks its starts by it); counted as the first evaluation.
pub fn levenberg_marquardt_from<const N: usize, const M: usize>(
    mut residual: impl FnMut(&[f64; N]) -> Option<[f64; M]>,
    x0: [f64; N],
    r0: Option<[f64; M]>,
    settings: &LmSettings,
) -> Option<LmResult<N>> {
    let norm = |r: &[f64; M]| r.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut x = x0;
    let mut r = r0.filter(|r| r.iter().all(|v| v.is_finite()))?;
    let mut evaluations = 1;
    let mut cost = norm(&r);
    let mut lambda = settings.initial_damping;
    let mut iterations = 0;
    let mut jacobian: Option<DMatrix<f64>> = None;
    while iterations < settings.max_iterations && cost > settings.tolerance {
        iterations += 1;
        let jac = match jacobian.take() {
            Some(j) => j,
            None => {
                let mut j = DMatrix::<f64>::zeros(M, N);
                for col in 0..N {
                    let h = settings.jacobian_step * x[col].abs().max(1.0);
                    let mut shifted = |d: f64| {
                        let mut xs = x;
                        xs[col] += d;
                        evaluations += 1;
                        residual(&xs).filter(|r| r.iter().all(|v| v.is_finite()))
                    };
                    // Forward difference; backward where the forward point is undefined.
                    let derivative: [f64; M] = if let Some(f) = shifted(h) {
                        std::array::from_fn(|i| (f[i] - r[i]) / h)
                    } else if let Some(b) = shifted(-h) {
                        std::array::from_fn(|i| (r[i] - b[i]) / h)
                    } else {
                        return Some(LmResult {
                            x,
                            residual_norm: cost,
                            iterations,
                            evaluations,
                            converged: false,
                        });
                    };
                    for (i, d) in derivative.iter().enumerate() {
                        j[(i, col)] = *d;
                    }
                }
                j
            }
        };
        let jtj = jac.transpose() * &jac;
        let jtr = jac.transpose() * DVector::from_column_slice(&r);
        jacobian = Some(jac);
        let mut a = jtj.clone();
        for i in 0..N {
            a[(i, i)] += lambda * jtj[(i, i)].max(1e-12);
        }
        let Some(step) = a.lu().solve(&(-jtr)) else {
            lambda *= 10.0;
            continue;
        };
        let trial: [f64; N] = std::array::from_fn(|i| x[i] + step[i]);
        evaluations += 1;
        match residual(&trial).filter(|r| r.iter().all(|v| v.is_finite())) {
            Some(r_trial) if norm(&r_trial) < cost => {
                let small = (0..N).all(|i| step[i].abs() <= 1e-15 * x[i].abs().max(1.0));
                x = trial;
                r = r_trial;
                cost = norm(&r);
                lambda = (lambda / 3.0).max(1e-12);
                jacobian = None;
                if small {
                    break;
                }
            }
            _ => {
                lambda *= 4.0;
                if lambda > 1e12 {
                    break;
                }
            }
        }
    }
    Some(LmResult {
        x,
        residual_norm: cost,
        iterations,
        evaluations,
        converged: cost <= settings.tolerance,
    })
}

/// A complex number `re + i im` (an eigenvalue).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Complex {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Complex {
    /// Modulus `|z|`.
    pub fn modulus(&self) -> f64 {
        self.re.hypot(self.im)
    }

    /// Argument `arg z ∈ (−π, π]`.
    pub fn argument(&self) -> f64 {
        self.im.atan2(self.re)
    }
}

/// Eigenvalues of the real 2 × 2 matrix `[[a, b], [c, d]]` (rows), largest modulus first:
/// roots of `λ² − tr λ + det = 0`, with the smaller real root taken as `det / λ₁` to avoid
/// cancellation; a complex pair when `((a − d)/2)² + bc < 0`.
pub fn eigenvalues_2x2(m: [[f64; 2]; 2]) -> [Complex; 2] {
    let [[a, b], [c, d]] = m;
    let half_trace = 0.5 * (a + d);
    let det = a * d - b * c;
    let half_diff = 0.5 * (a - d);
    let disc = half_diff * half_diff + b * c;
    if disc >= 0.0 {
        let s = disc.sqrt();
        let first = half_trace + s.copysign(half_trace);
        let second = if first == 0.0 {
            half_trace - s
        } else {
            det / first
        };
        let (l1, l2) = if first.abs() >= second.abs() {
            (first, second)
        } else {
            (second, first)
        };
        [Complex { re: l1, im: 0.0 }, Complex { re: l2, im: 0.0 }]
    } else {
        let im = (-disc).sqrt();
        [
            Complex { re: half_trace, im },
            Complex {
                re: half_trace,
                im: -im,
            },
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_cubic_root() {
        let root = brent(|x| x * x * x - 2.0, 0.0, 2.0, 1e-14).unwrap();
        assert!((root - 2f64.cbrt()).abs() < 1e-12);
        assert!(brent(|x| x * x + 1.0, -1.0, 1.0, 1e-12).is_none());
    }

    #[test]
    fn first_sign_change_skips_later_roots() {
        // sin has roots at π, 2π, 3π; the first one after 0.5 is π.
        let root = first_sign_change(f64::sin, 0.5, 10.0, 100, 1e-13).unwrap();
        assert!((root - std::f64::consts::PI).abs() < 1e-10);
    }

    #[test]
    fn golden_section_finds_parabola_minimum() {
        let (x, fx) = golden_section_minimum(|x| (x - 0.3).powi(2) + 1.0, -1.0, 2.0, 80);
        assert!((x - 0.3).abs() < 1e-7 && (fx - 1.0).abs() < 1e-12);
    }

    #[test]
    fn dormand_prince_integrates_harmonic_oscillator() {
        let f = |_t: f64, y: &[f64; 2]| [y[1], -y[0]];
        let (mut t, mut y, h) = (0.0, [1.0, 0.0], 0.01);
        while t < 1.0 - 1e-12 {
            let (y_new, err) = dormand_prince_step(&f, t, &y, h);
            assert!(error_norm(&y, &y_new, &err, 1e-8, 1e-10) < 1.0);
            y = y_new;
            t += h;
        }
        assert!((y[0] - 1f64.cos()).abs() < 1e-11 && (y[1] + 1f64.sin()).abs() < 1e-11);
    }

    #[test]
    fn event_integration_stops_at_the_event() {
        // Harmonic oscillator y = cos t: y' = −sin t reaches −0.5 at t = asin(0.5) = π/6.
        let f = |_t: f64, y: &[f64; 2]| [y[1], -y[0]];
        let settings = OdeSettings {
            rtol: 1e-12,
            atol: 1e-14,
            initial_step: 1e-3,
            max_step: 0.1,
            max_steps: 10_000,
        };
        let mut steps = 0;
        let end = integrate_to_event(
            &f,
            0.0,
            [1.0, 0.0],
            &settings,
            |_, y| -0.5 - y[1],
            |_, _| {
                steps += 1;
                None::<()>
            },
        );
        let OdeEnd::Event { t, y } = end else {
            panic!("no event: {end:?}")
        };
        assert!((t - std::f64::consts::FRAC_PI_6).abs() < 1e-11, "t = {t}");
        assert!((y[0] - t.cos()).abs() < 1e-11 && (y[1] + 0.5).abs() < 1e-11);
        assert!(steps >= 2);
        // Already at the event: stops at t0; a stop request is reported.
        assert!(matches!(
            integrate_to_event(&f, 0.0, [1.0, 0.0], &settings, |_, y| y[0] - 1.0, |_, _| None::<()>),
            OdeEnd::Event { t, .. } if t == 0.0
        ));
        let stopped = integrate_to_event(
            &f,
            0.0,
            [1.0, 0.0],
            &settings,
            |_, _| -1.0,
            |t, _| (t > 0.5).then_some("late"),
        );
        assert!(matches!(stopped, OdeEnd::Stopped { reason: "late", t } if t > 0.5));
    }

    #[test]
    fn levenberg_marquardt_solves_rosenbrock_and_square_systems() {
        // Rosenbrock as residuals: r = (10 (y − x²), 1 − x), zero at (1, 1).
        let settings = LmSettings::default();
        let res = levenberg_marquardt(
            |x: &[f64; 2]| Some([10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]]),
            [-1.2, 1.0],
            &settings,
        )
        .unwrap();
        assert!(res.converged, "{res:?}");
        assert!((res.x[0] - 1.0).abs() < 1e-9 && (res.x[1] - 1.0).abs() < 1e-9);
        // A square nonlinear system with a region where the residual is undefined (x < 0):
        // x² + y² = 4, e^x + y = 1 has a root near (1.004, −1.729).
        let res = levenberg_marquardt(
            |x: &[f64; 2]| {
                (x[0] >= 0.0).then(|| [x[0] * x[0] + x[1] * x[1] - 4.0, x[0].exp() + x[1] - 1.0])
            },
            [2.0, 0.0],
            &settings,
        )
        .unwrap();
        assert!(res.converged, "{res:?}");
        let [x, y] = res.x;
        assert!((x * x + y * y - 4.0).abs() < 1e-10 && (x.exp() + y - 1.0).abs() < 1e-10);
        // An inconsistent least-squares problem ends at the minimum, not converged.
        let res = levenberg_marquardt(
            |x: &[f64; 1]| Some([x[0] - 1.0, x[0] + 1.0]),
            [3.0],
            &settings,
        )
        .unwrap();
        assert!(!res.converged && res.x[0].abs() < 1e-8);
        assert!(levenberg_marquardt(|_: &[f64; 1]| None::<[f64; 1]>, [0.0], &settings).is_none());
    }

    #[test]
    fn eigenvalues_of_2x2_matrices() {
        // Real: [[2, 1], [1, 2]] has 3 and 1.
        let [a, b] = eigenvalues_2x2([[2.0, 1.0], [1.0, 2.0]]);
        assert!((a.re - 3.0).abs() < 1e-15 && (b.re - 1.0).abs() < 1e-15 && a.im == 0.0);
        // Rotation-scaling: 0.5 (cos θ, −sin θ; sin θ, cos θ) has 0.5 e^{±iθ}.
        let (r, th) = (0.5, 0.7f64);
        let [a, b] = eigenvalues_2x2([[r * th.cos(), -r * th.sin()], [r * th.sin(), r * th.cos()]]);
        assert!((a.modulus() - r).abs() < 1e-15 && (a.argument().abs() - th).abs() < 1e-14);
        assert!((a.im + b.im).abs() < 1e-15);
        // Tiny eigenvalue next to a large one keeps its relative accuracy.
        let [a, b] = eigenvalues_2x2([[1e8, 1.0], [0.0, 1e-8]]);
        assert!((a.re - 1e8).abs() < 1e-6 && (b.re - 1e-8).abs() < 1e-22);
        // Characteristic polynomial check on a non-symmetric matrix.
        let m = [[0.3, -1.7], [0.4, -0.9]];
        for l in eigenvalues_2x2(m) {
            // (a − λ)(d − λ) − bc = 0 for complex λ.
            let (ar, ai) = (m[0][0] - l.re, -l.im);
            let (dr, di) = (m[1][1] - l.re, -l.im);
            let (pr, pi) = (ar * dr - ai * di - m[0][1] * m[1][0], ar * di + ai * dr);
            assert!(pr.abs() < 1e-14 && pi.abs() < 1e-14);
        }
    }
}
