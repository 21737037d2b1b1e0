//! The explicit Runge–Kutta pair of Dormand and Prince of order 8 with error estimators of
//! orders 5 and 3 ("DOP853", Hairer, Nørsett & Wanner, *Solving Ordinary Differential
//! Equations I*, §II.10): 12 stages per step, the last stage of an accepted step's end
//! state is the next step's first. At the tight tolerances of the reduced models (relative
//! 1e-10) it takes about a third of the right-hand-side evaluations of the 5(4) pair
//! (docs/performance.md, "The fixed-point analysis").
//!
//! The coefficients are those of the authors' published code, to double precision.

/// Nodes `c_i` of the 12 stages.
const C: [f64; 12] = [
    0.0,
    0.05260015195876773,
    0.0789002279381516,
    0.1183503419072274,
    0.2816496580927726,
    0.3333333333333333,
    0.25,
    0.3076923076923077,
    0.6512820512820513,
    0.6,
    0.8571428571428571,
    1.0,
];
/// Coupling coefficients `a_ij` (row `i`, `j < i`) of the 12 stages; row 12 holds the
/// eighth-order weights `b_j`.
const A: [[f64; 12]; 13] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        0.05260015195876773,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.0197250569845379,
        0.0591751709536137,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.02958758547680685,
        0.0,
        0.08876275643042054,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.2413651341592667,
        0.0,
        -0.8845494793282861,
        0.924834003261792,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.037037037037037035,
        0.0,
        0.0,
        0.17082860872947386,
        0.12546768756682242,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.037109375,
        0.0,
        0.0,
        0.17025221101954405,
        0.06021653898045596,
        -0.017578125,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.03709200011850479,
        0.0,
        0.0,
        0.17038392571223998,
        0.10726203044637328,
        -0.015319437748624402,
        0.008273789163814023,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.6241109587160757,
        0.0,
        0.0,
        -3.3608926294469414,
        -0.868219346841726,
        27.59209969944671,
        20.154067550477894,
        -43.48988418106996,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.47766253643826434,
        0.0,
        0.0,
        -2.4881146199716677,
        -0.590290826836843,
        21.230051448181193,
        15.279233632882423,
        -33.28821096898486,
        -0.020331201708508627,
        0.0,
        0.0,
        0.0,
    ],
    [
        -0.9371424300859873,
        0.0,
        0.0,
        5.186372428844064,
        1.0914373489967295,
        -8.149787010746927,
        -18.52006565999696,
        22.739487099350505,
        2.4936055526796523,
        -3.0467644718982196,
        0.0,
        0.0,
    ],
    [
        2.273310147516538,
        0.0,
        0.0,
        -10.53449546673725,
        -2.0008720582248625,
        -17.9589318631188,
        27.94888452941996,
        -2.8589982771350235,
        -8.87285693353063,
        12.360567175794303,
        0.6433927460157636,
        0.0,
    ],
    [
        0.054293734116568765,
        0.0,
        0.0,
        0.0,
        0.0,
        4.450312892752409,
        1.8915178993145003,
        -5.801203960010585,
        0.3111643669578199,
        -0.1521609496625161,
        0.20136540080403034,
        0.04471061572777259,
    ],
];
/// Weights of the fifth-order error estimate (`b − b̂₅`).
const E5: [f64; 12] = [
    0.01312004499419488,
    0.0,
    0.0,
    0.0,
    0.0,
    -1.2251564463762044,
    -0.4957589496572502,
    1.6643771824549864,
    -0.35032884874997366,
    0.3341791187130175,
    0.08192320648511571,
    -0.022355307863886294,
];
/// The third-order estimate's weights are `b − ê₃`; `ê₃` is non-zero at stages 0, 8, 11.
const E3_SHIFT: [(usize, f64); 3] = [
    (0, 0.2440944881889764),
    (8, 0.7338466882816118),
    (11, 0.022058823529411766),
];
/// Nodes of the three extra stages of the dense output.
const C_EXTRA: [f64; 3] = [0.1, 0.2, 0.7777777777777778];
/// Coupling coefficients of the three extra stages (over the 12 stages, the first
/// stage of the next step and the extra stages before them).
const A_EXTRA: [[f64; 15]; 3] = [
    [
        0.056167502283047954,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.25350021021662483,
        -0.2462390374708025,
        -0.12419142326381637,
        0.15329179827876568,
        0.00820105229563469,
        0.007567897660545699,
        -0.008298,
        0.0,
        0.0,
    ],
    [
        0.03183464816350214,
        0.0,
        0.0,
        0.0,
        0.0,
        0.028300909672366776,
        0.053541988307438566,
        -0.05492374857139099,
        0.0,
        0.0,
        -0.00010834732869724932,
        0.0003825710908356584,
        -0.00034046500868740456,
        0.1413124436746325,
        0.0,
    ],
    [
        -0.42889630158379194,
        0.0,
        0.0,
        0.0,
        0.0,
        -4.697621415361164,
        7.683421196062599,
        4.06898981839711,
        0.3567271874552811,
        0.0,
        0.0,
        0.0,
        -0.0013990241651590145,
        2.9475147891527724,
        -9.15095847217987,
    ],
];
/// Coefficients of the dense output's four highest terms over the 16 stages.
const D: [[f64; 16]; 4] = [
    [
        -8.428938276109013,
        0.0,
        0.0,
        0.0,
        0.0,
        0.5667149535193777,
        -3.0689499459498917,
        2.38466765651207,
        2.117034582445028,
        -0.871391583777973,
        2.2404374302607883,
        0.6315787787694688,
        -0.08899033645133331,
        18.148505520854727,
        -9.194632392478356,
        -4.436036387594894,
    ],
    [
        10.427508642579134,
        0.0,
        0.0,
        0.0,
        0.0,
        242.28349177525817,
        165.20045171727028,
        -374.5467547226902,
        -22.113666853125306,
        7.733432668472264,
        -30.674084731089398,
        -9.332130526430229,
        15.697238121770845,
        -31.139403219565178,
        -9.35292435884448,
        35.81684148639408,
    ],
    [
        19.985053242002433,
        0.0,
        0.0,
        0.0,
        0.0,
        -387.0373087493518,
        -189.17813819516758,
        527.8081592054236,
        -11.57390253995963,
        6.8812326946963,
        -1.0006050966910838,
        0.7777137798053443,
        -2.778205752353508,
        -60.19669523126412,
        84.32040550667716,
        11.99229113618279,
    ],
    [
        -25.69393346270375,
        0.0,
        0.0,
        0.0,
        0.0,
        -154.18974869023643,
        -231.5293791760455,
        357.6391179106141,
        93.40532418362432,
        -37.45832313645163,
        104.0996495089623,
        29.8402934266605,
        -43.53345659001114,
        96.32455395918828,
        -39.17726167561544,
        -149.72683625798564,
    ],
];

/// One step of size `h` from `(t, y)`, given the first stage `k0 = f(t, y)` (which does not
/// depend on `h`, so a retried step or the trial steps of an event search share it).
/// Holds the eighth-order solution `y`, the unscaled fifth- and third-order error
/// estimates, to be combined by [`error_norm`], and the stages for [`Step::dense`]. The
/// first stage of the next step, `f(t + h, y)`, is left to the caller (only an accepted
/// step needs it).
pub struct Step<const N: usize> {
    /// The eighth-order solution at `t + h`.
    pub y: [f64; N],
    /// Fifth-order error estimate (unscaled).
    pub err5: [f64; N],
    /// Third-order error estimate (unscaled).
    pub err3: [f64; N],
    k: [[f64; N]; 12],
}

/// See [`Step`].
pub fn stages<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    y: &[f64; N],
    k0: &[f64; N],
    h: f64,
) -> Step<N> {
    let mut k = [[0.0; N]; 12];
    k[0] = *k0;
    for stage in 1..12 {
        let mut ys = *y;
        for (j, a) in A[stage].iter().enumerate().take(stage) {
            if *a != 0.0 {
                for i in 0..N {
                    ys[i] += h * a * k[j][i];
                }
            }
        }
        k[stage] = f(t + C[stage] * h, &ys);
    }
    let mut y8 = *y;
    let mut err5 = [0.0; N];
    let mut err3 = [0.0; N];
    for (stage, k) in k.iter().enumerate() {
        let (b, e5) = (A[12][stage], E5[stage]);
        for i in 0..N {
            y8[i] += h * b * k[i];
            err5[i] += e5 * k[i];
            err3[i] += b * k[i];
        }
    }
    for (stage, shift) in E3_SHIFT {
        for i in 0..N {
            err3[i] -= shift * k[stage][i];
        }
    }
    Step {
        y: y8,
        err5,
        err3,
        k,
    }
}

/// `y + h Σ_j a_j k_j` over the stages with a coefficient.
fn combine<const N: usize>(y: &[f64; N], h: f64, a: &[f64], k: &[[f64; N]]) -> [f64; N] {
    let mut out = *y;
    for (a, k) in a.iter().zip(k) {
        if *a != 0.0 {
            for i in 0..N {
                out[i] += h * a * k[i];
            }
        }
    }
    out
}

impl<const N: usize> Step<N> {
    /// The seventh-order continuous extension of this step (taken from `(t, y)` with size
    /// `h`): four more evaluations of `f`, `f(t + h, y_{n+1})` among them.
    pub fn dense(
        &self,
        f: &impl Fn(f64, &[f64; N]) -> [f64; N],
        t: f64,
        y: &[f64; N],
        h: f64,
    ) -> Dense<N> {
        let mut k = [[0.0; N]; 16];
        k[..12].copy_from_slice(&self.k);
        k[12] = f(t + h, &self.y);
        for (extra, (a, c)) in A_EXTRA.iter().zip(C_EXTRA).enumerate() {
            let stage = 13 + extra;
            k[stage] = f(t + c * h, &combine(y, h, &a[..stage], &k));
        }
        let mut terms = [[0.0; N]; 7];
        for i in 0..N {
            let delta = self.y[i] - y[i];
            terms[0][i] = delta;
            terms[1][i] = h * k[0][i] - delta;
            terms[2][i] = 2.0 * delta - h * (k[12][i] + k[0][i]);
        }
        for (term, d) in terms[3..].iter_mut().zip(&D) {
            *term = combine(&[0.0; N], h, d, &k);
        }
        Dense { y0: *y, h, terms }
    }
}

/// The continuous extension of a [`Step`]: `y(t + s)` for `0 ≤ s ≤ h`.
pub struct Dense<const N: usize> {
    y0: [f64; N],
    h: f64,
    terms: [[f64; N]; 7],
}

impl<const N: usize> Dense<N> {
    /// `y(t + s)`: with `x = s/h`,
    /// `y0 + x(F0 + (1−x)(F1 + x(F2 + (1−x)(F3 + x(F4 + (1−x)(F5 + x F6))))))`.
    pub fn at(&self, s: f64) -> [f64; N] {
        let x = s / self.h;
        let mut y = [0.0; N];
        for (j, term) in self.terms.iter().rev().enumerate() {
            let factor = if j % 2 == 0 { x } else { 1.0 - x };
            for (y, term) in y.iter_mut().zip(term) {
                *y = (*y + term) * factor;
            }
        }
        for (y, y0) in y.iter_mut().zip(&self.y0) {
            *y += y0;
        }
        y
    }
}

/// The scaled error of a step (≤ 1 means accept): with `sc_i = atol + rtol max(|y_i|,
/// |y8_i|)` and the root-mean-square norms `e5`, `e3` of `err5/sc`, `err3/sc`,
/// `|h| e5² / sqrt(e5² + 0.01 e3²)`, the authors' combination of the two estimators.
pub fn error_norm<const N: usize>(
    y: &[f64; N],
    y_new: &[f64; N],
    (err5, err3): (&[f64; N], &[f64; N]),
    h: f64,
    rtol: f64,
    atol: f64,
) -> f64 {
    let (mut e5, mut e3) = (0.0, 0.0);
    for i in 0..N {
        let scale = atol + rtol * y[i].abs().max(y_new[i].abs());
        e5 += (err5[i] / scale).powi(2);
        e3 += (err3[i] / scale).powi(2);
    }
    let denominator = e5 + 0.01 * e3;
    if denominator <= 0.0 {
        return 0.0;
    }
    h.abs() * e5 / (denominator * N as f64).sqrt()
}

/// `norm^(-1/8)`, the step-size factor of an eighth-order pair, by three square roots
/// (cheaper than `powf`, and exact to rounding).
pub fn step_factor(norm: f64) -> f64 {
    1.0 / norm.sqrt().sqrt().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The harmonic oscillator `x'' = −x` over one period in steps of `2π/20`: the
    /// eighth-order solution's global error is below 1e-9, and halving the step divides it
    /// by about `2^8`.
    #[test]
    fn integrates_the_harmonic_oscillator_to_eighth_order() {
        let f = |_t: f64, y: &[f64; 2]| [y[1], -y[0]];
        let error = |steps: usize| {
            let h = 2.0 * std::f64::consts::PI / steps as f64;
            let mut y = [1.0, 0.0];
            for i in 0..steps {
                let t = i as f64 * h;
                y = stages(&f, t, &y, &f(t, &y), h).y;
            }
            ((y[0] - 1.0).powi(2) + y[1].powi(2)).sqrt()
        };
        let (coarse, fine) = (error(20), error(40));
        assert!(coarse < 1e-8, "error {coarse:e}");
        let order = (coarse / fine).log2();
        assert!((7.5..9.0).contains(&order), "observed order {order}");
    }

    /// The continuous extension of one step of `x'' = −x` is exact at both ends and, inside
    /// the step, its largest error falls by at least `2^7` when the step is halved (local
    /// error `O(h^8)` of the seventh-order extension; measured: 2.02e-7 at `h = 0.8`,
    /// 7.85e-10 at `h = 0.4`, ratio 258).
    #[test]
    fn dense_output_interpolates_the_step_to_seventh_order() {
        let f = |_t: f64, y: &[f64; 2]| [y[1], -y[0]];
        let y0 = [1.0, 0.0];
        let largest_error = |h: f64| {
            let step = stages(&f, 0.0, &y0, &f(0.0, &y0), h);
            let dense = step.dense(&f, 0.0, &y0, h);
            assert_eq!(dense.at(0.0), y0);
            assert!((dense.at(h)[0] - step.y[0]).abs() < 1e-15);
            (1..10)
                .map(|i| {
                    let s = h * i as f64 / 10.0;
                    let y = dense.at(s);
                    (y[0] - s.cos()).abs().max((y[1] + s.sin()).abs())
                })
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (largest_error(0.8), largest_error(0.4));
        assert!(coarse < 1e-6, "error {coarse:e} at h = 0.8");
        assert!(coarse / fine > 128.0, "errors {coarse:e}, {fine:e}");
    }

    /// The rows of `A` sum to the nodes `c` (the stages are consistent), the weights to 1,
    /// and the fifth-order estimate vanishes on `y' = 1` (exact for every stage).
    #[test]
    fn coefficients_are_consistent() {
        for (stage, row) in A.iter().enumerate().take(12) {
            let sum: f64 = row.iter().sum();
            assert!(
                (sum - C[stage]).abs() < 1e-14,
                "row {stage}: {sum} vs {}",
                C[stage]
            );
        }
        assert!((A[12].iter().sum::<f64>() - 1.0).abs() < 1e-14);
        assert!(E5.iter().sum::<f64>().abs() < 1e-14);
        let e3: f64 = A[12].iter().sum::<f64>() - E3_SHIFT.iter().map(|s| s.1).sum::<f64>();
        assert!(e3.abs() < 1e-14, "third-order estimate on y' = 1: {e3}");
    }
}
