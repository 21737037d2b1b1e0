//! `sin θ` and `cos θ` together, in plain Rust, for the bodies' rotations.
//!
//! Every step evaluates each rotating body's `(sin θ, cos θ)` twice (docs/physics.md §4.1:
//! at the midpoint and at the end of the step), and a rolling body's angle grows without
//! bound (a disc rolling 37 m turns by 185 rad). The platform's `sin_cos` then takes its slow
//! argument reduction; this one reduces by `π/2` in the classic three-part Cody–Waite way
//! and evaluates the fdlibm minimax kernels on `[−π/4, π/4]` (error below 1 ulp there),
//! with about two thirds of the instructions (70 against 110 per call in a Robbit run). It is also the same on every platform, where the
//! system's `libm` may differ in the last bit.
//!
//! Valid for `|θ| < 2²⁰ · π/2` (about 1.6e6 rad); larger or non-finite angles fall back
//! to [`f64::sin_cos`]. The reduction keeps 85 bits of `π/2`, and 118 or 151 where the
//! leading bits of `θ − k π/2` cancel (next to a multiple of `π/2`), so each result stays
//! within about one ulp of itself.

/// `π/2` in three pieces of 33 bits each (so `k · PIO2_i` is exact for `|k| < 2²⁰`) and the
/// tails after the first, second and third.
const PIO2_1: f64 = 1.5707963267341256;
const PIO2_1T: f64 = 6.077100506506192e-11;
const PIO2_2: f64 = 6.077100506303966e-11;
const PIO2_2T: f64 = 2.0222662487959506e-21;
const PIO2_3: f64 = 2.0222662487111665e-21;
const PIO2_3T: f64 = 8.4784276603689e-32;
/// Largest `|θ|` the reduction handles exactly enough.
const REDUCE_LIMIT: f64 = 1647099.3303760714; // 2²⁰ · π/2
/// `2⁻²⁷`: below it `θ − θ³/6` rounds to `θ` and `1 − θ²/2` to 1.
const TINY: f64 = 7.450580596923828e-09;
/// `1.5 · 2⁵²`: adding and subtracting it rounds to the nearest integer (ties to even).
const ROUND: f64 = 6755399441055744.0;

/// `(sin θ, cos θ)`.
#[inline]
pub fn sin_cos(theta: f64) -> (f64, f64) {
    let a = theta.abs();
    if a < TINY {
        // sin θ = θ and cos θ = 1 to the last bit (keeps the sign of −0).
        return (theta, 1.0);
    }
    if a <= std::f64::consts::FRAC_PI_4 {
        return (kernel_sin(theta, 0.0), kernel_cos(theta, 0.0));
    }
    // NaN (unordered) goes to the platform's function too.
    if a.partial_cmp(&REDUCE_LIMIT) != Some(std::cmp::Ordering::Less) {
        return theta.sin_cos();
    }
    let (k, y0, y1) = reduce(theta);
    let (s, c) = (kernel_sin(y0, y1), kernel_cos(y0, y1));
    match k & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `θ = k π/2 + (y0 + y1)` with `|y0 + y1| ≤ π/4` (to round-off), `y0 + y1` a
/// double-double (fdlibm's medium-size reduction).
#[inline]
fn reduce(theta: f64) -> (i64, f64, f64) {
    let kf = (theta * std::f64::consts::FRAC_2_PI + ROUND) - ROUND;
    let k = kf as i64;
    let exponent = |v: f64| ((v.to_bits() >> 52) & 0x7ff) as i64;
    let e = exponent(theta);
    let mut r = theta - kf * PIO2_1;
    let mut w = kf * PIO2_1T;
    let mut y0 = r - w;
    if e - exponent(y0) > 16 {
        // The leading bits cancelled: take the next 33 bits of π/2.
        (r, w, y0) = next_bits(kf, r, PIO2_2, PIO2_2T);
        if e - exponent(y0) > 49 {
            // And the next (a θ within 2⁻⁴⁹ relative of a multiple of π/2).
            (r, w, y0) = next_bits(kf, r, PIO2_3, PIO2_3T);
        }
    }
    let y1 = (r - y0) - w;
    (k, y0, y1)
}

/// One more round of the reduction: `r − k·(piece + tail)` from the remainder `r` of the
/// rounds before, as `(r, w, y0 = r − w)`.
#[inline]
fn next_bits(kf: f64, t: f64, piece: f64, tail: f64) -> (f64, f64, f64) {
    let w = kf * piece;
    let r = t - w;
    let w = kf * tail - ((t - r) - w);
    (r, w, r - w)
}

/// `sin(x + y)` for `|x + y| ≤ π/4`, `y` the tail of `x` (fdlibm `__kernel_sin`).
#[inline(always)]
fn kernel_sin(x: f64, y: f64) -> f64 {
    const S1: f64 = -0.16666666666666632;
    const S2: f64 = 0.00833333333332249;
    const S3: f64 = -0.0001984126982985795;
    const S4: f64 = 2.7557313707070068e-06;
    const S5: f64 = -2.5050760253406863e-08;
    const S6: f64 = 1.58969099521155e-10;
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    if y == 0.0 {
        x + v * (S1 + z * r)
    } else {
        x - ((z * (0.5 * y - v * r) - y) - v * S1)
    }
}

/// `cos(x + y)` for `|x + y| ≤ π/4`, `y` the tail of `x` (fdlibm `__kernel_cos`).
#[inline(always)]
fn kernel_cos(x: f64, y: f64) -> f64 {
    const C1: f64 = 0.0416666666666666;
    const C2: f64 = -0.001388888888887411;
    const C3: f64 = 2.480158728947673e-05;
    const C4: f64 = -2.7557314351390663e-07;
    const C5: f64 = 2.087572321298175e-09;
    const C6: f64 = -1.1359647557788195e-11;
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    one_minus + (((1.0 - one_minus) - hz) + (z * r - x * y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place of `v` (of the smallest normal number for `v = 0`).
    fn ulp(v: f64) -> f64 {
        let a = v.abs().max(f64::MIN_POSITIVE);
        f64::from_bits(a.to_bits() + 1) - a
    }

    /// The largest difference from the platform's `sin_cos`, in ulps of the larger of
    /// `|sin θ|`, `|cos θ|` (both results are bounded by 1, so this is the absolute error
    /// in units of the result's scale).
    fn worst(thetas: impl Iterator<Item = f64>) -> (f64, f64) {
        let mut worst = (0.0_f64, 0.0);
        for theta in thetas {
            let (s, c) = sin_cos(theta);
            let (s0, c0) = theta.sin_cos();
            let scale = ulp(s0.abs().max(c0.abs()));
            let e = ((s - s0).abs().max((c - c0).abs())) / scale;
            if e > worst.0 {
                worst = (e, theta);
            }
        }
        worst
    }

    /// A deterministic spread of angles: `x_{k+1} = frac(x_k · φ)` scaled to `[−range, range]`.
    fn angles(count: usize, range: f64) -> impl Iterator<Item = f64> {
        let golden = 0.618_033_988_749_894_9;
        (0..count).scan(0.5_f64, move |x, _| {
            *x = (*x + golden).fract();
            Some((2.0 * *x - 1.0) * range)
        })
    }

    #[test]
    fn agrees_with_the_platform_to_one_ulp_of_the_result_scale() {
        // Measured: at most 1 ulp (both the kernels and the platform are within 1 ulp of
        // the exact value, so 2 is the bound that cannot fail for a correct pair).
        for range in [1.0, 10.0, 1e3, 1e6] {
            let (e, theta) = worst(angles(200_000, range));
            assert!(e <= 2.0, "|θ| ≤ {range}: {e} ulp at θ = {theta:e}");
        }
    }

    #[test]
    fn next_to_multiples_of_a_right_angle_each_result_keeps_its_own_precision() {
        // Angles next to k·π/2 (to 3.1e4 rad), where the leading bits of the reduction cancel and one of
        // the results is tiny: each within 2 ulp of itself, not just of the scale 1.
        let mut worst = (0.0_f64, 0.0);
        for k in 1..20_000_i32 {
            let x = f64::from(k) * std::f64::consts::FRAC_PI_2;
            for theta in [
                x,
                f64::from_bits(x.to_bits() + 1),
                f64::from_bits(x.to_bits() - 1),
                -x,
            ] {
                let ((s, c), (s0, c0)) = (sin_cos(theta), theta.sin_cos());
                let e = ((s - s0).abs() / ulp(s0)).max((c - c0).abs() / ulp(c0));
                if e > worst.0 {
                    worst = (e, theta);
                }
            }
        }
        let (e, theta) = worst;
        assert!(e <= 2.0, "{e} ulp at θ = {theta:e}");
    }

    #[test]
    fn exact_values_signs_and_the_fallback() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert!(sin_cos(-0.0).0.is_sign_negative());
        let (s, c) = sin_cos(std::f64::consts::PI);
        assert!(s.abs() < 2e-16 && (c + 1.0).abs() < 1e-16, "{s} {c}");
        // Pythagoras at a large angle a rolling body reaches.
        let (s, c) = sin_cos(185.3);
        assert!((s * s + c * c - 1.0).abs() < 4e-16);
        // Beyond the reduction's range and non-finite angles: the platform's function.
        assert_eq!(sin_cos(1e7), 1e7_f64.sin_cos());
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
        let (s, c) = sin_cos(f64::INFINITY);
        assert!(s.is_nan() && c.is_nan());
    }
}
