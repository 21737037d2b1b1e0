//! Small numerical tools shared by the analyses: a bracketing root finder (Brent), the
//! first root of a function on an interval (scan + Brent), a golden-section minimiser and
//! an adaptive Dormand–Prince 5(4) step.

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
    mut f: impl FnMut(f64) -> f64,
    start: f64,
    end: f64,
    steps: usize,
    tolerance: f64,
) -> Option<f64> {
    let steps = steps.max(1);
    let h = (end - start) / steps as f64;
    let mut t0 = start;
    let mut f0 = f(t0);
    for i in 1..=steps {
        let t1 = if i == steps {
            end
        } else {
            start + h * i as f64
        };
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
    const B5: [f64; 7] = [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ];
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
    for stage in 0..7 {
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
    (y5, err)
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
}
