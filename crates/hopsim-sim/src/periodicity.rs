//! Poincaré-section period detection for periodically driven gaits (physics.md §5.4).
//!
//! The section is stroboscopic: the state at the start of every motor period `t = k P`.
//! The forward position `x` is left out (a gait repeats up to a translation); every other
//! coordinate and every velocity is kept. Steps do not in general end on `k P`, so the
//! section state is interpolated linearly between the two step ends that bracket it
//! (within one step; an impact inside that step is smeared over it, which the tolerances
//! below are far above).
//!
//! A gait has period `p` when the section states `p` motor periods apart agree within the
//! tolerances over the last `window` comparisons: with `z_k` the `k`-th section state,
//!
//! ```text
//! r_p = max over the last `window` k, over components i of |z_{k+p,i} − z_{k,i}| / tol_i
//! ```
//!
//! (`tol_i` = [`PeriodicityOptions::position_tolerance`] for coordinates,
//! [`PeriodicityOptions::velocity_tolerance`] for velocities). The detected period is the
//! smallest `p ≤ max_period` with `r_p ≤ 1`; none when no `p` qualifies (quasi-periodic,
//! chaotic, still in its transient, or a period above `max_period`).

use serde::Serialize;

/// How periodicity is decided.
#[derive(Clone, Debug, PartialEq)]
pub struct PeriodicityOptions {
    /// Section samples compared for each candidate period (the last ones of the run).
    pub window: usize,
    /// Largest period tried, in motor periods.
    pub max_period: usize,
    /// Agreement required of the coordinates (m for `y`, rad for angles).
    pub position_tolerance: f64,
    /// Agreement required of the velocities (m/s, rad/s).
    pub velocity_tolerance: f64,
}

impl Default for PeriodicityOptions {
    /// The last 8 comparisons, periods 1 to 4, 1 mm or 1 mrad and 1 cm/s or 0.01 rad/s
    /// (docs/canebot.md shows how these compare with the section spread of the gaits).
    fn default() -> Self {
        Self {
            window: 8,
            max_period: 4,
            position_tolerance: 1e-3,
            velocity_tolerance: 1e-2,
        }
    }
}

/// The outcome of period detection, as the run summary reports it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Periodicity {
    /// The smallest period (in motor periods) whose residual is at most 1; `null` if none.
    pub period: Option<usize>,
    /// `r_p` for `p = 1, 2, …` (dimensionless: 1 is the tolerance); `NaN` when the run has
    /// too few section samples for that `p`.
    pub residuals: Vec<f64>,
    /// Section samples collected (motor periods started, including `t = 0`).
    pub sections: usize,
    /// Comparisons per period (`PeriodicityOptions::window`).
    pub window: usize,
}

impl Periodicity {
    /// `r_p` of the detected period, or the smallest residual when none was detected.
    pub fn residual(&self) -> f64 {
        match self.period {
            Some(p) => self.residuals[p - 1],
            None => self
                .residuals
                .iter()
                .copied()
                .filter(|r| r.is_finite())
                .fold(f64::NAN, f64::min),
        }
    }
}

impl std::fmt::Display for Periodicity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.period {
            Some(p) => write!(f, "period {p}")?,
            None => write!(f, "no period ≤ {}", self.residuals.len())?,
        }
        let residuals: Vec<String> = self.residuals.iter().map(|r| format!("{r:.3}")).collect();
        write!(
            f,
            " (residuals {} for p = 1..{}; {} sections, last {} compared)",
            residuals.join(", "),
            self.residuals.len(),
            self.sections,
            self.window
        )
    }
}

/// Collects the stroboscopic section `t = t0 + k P` of a run.
#[derive(Clone, Debug)]
pub struct PoincareSection {
    period: f64,
    t0: f64,
    /// Number of coordinates in a section state (`q` without `x`); velocities follow.
    coordinates: usize,
    /// Index `k` of the next section time `t0 + k P`.
    next: u64,
    previous: Option<(f64, Vec<f64>)>,
    samples: Vec<Vec<f64>>,
    /// Times of the samples, s.
    times: Vec<f64>,
}

impl PoincareSection {
    /// A section every `period` seconds starting at `t0` (the first sample is the state
    /// pushed at `t0`).
    pub fn new(period: f64, t0: f64) -> Self {
        assert!(
            period > 0.0 && period.is_finite(),
            "the period must be positive"
        );
        Self {
            period,
            t0,
            coordinates: 0,
            next: 0,
            previous: None,
            samples: Vec::new(),
            times: Vec::new(),
        }
    }

    /// The section state of `(q, u)`: `q` without `x` (`q[0]`), then `u`.
    pub fn section_state(q: &[f64], u: &[f64]) -> Vec<f64> {
        q[1..].iter().chain(u).copied().collect()
    }

    /// Feeds the state `(q, u)` at time `t` (call it for the start state and after every
    /// step, in time order); records every section time passed since the last call.
    pub fn push(&mut self, t: f64, q: &[f64], u: &[f64]) {
        self.coordinates = q.len() - 1;
        let z = Self::section_state(q, u);
        loop {
            let ts = self.t0 + self.next as f64 * self.period;
            if t < ts {
                break;
            }
            let sample = match &self.previous {
                Some((tp, zp)) if *tp < ts && t > *tp => {
                    let s = (ts - tp) / (t - tp);
                    zp.iter().zip(&z).map(|(a, b)| a + s * (b - a)).collect()
                }
                _ => z.clone(),
            };
            self.samples.push(sample);
            self.times.push(ts);
            self.next += 1;
        }
        self.previous = Some((t, z));
    }

    /// The section states so far, one per motor period.
    pub fn samples(&self) -> &[Vec<f64>] {
        &self.samples
    }

    /// The section times so far, s.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Number of coordinates (`q` without `x`) at the front of each section state.
    pub fn coordinates(&self) -> usize {
        self.coordinates
    }

    /// `r_p` (see the module documentation), `NaN` with too few samples.
    pub fn residual(&self, p: usize, options: &PeriodicityOptions) -> f64 {
        let n = self.samples.len();
        if p == 0 || options.window == 0 || n < options.window + p {
            return f64::NAN;
        }
        let mut worst = 0.0_f64;
        for k in n - options.window - p..n - p {
            let (a, b) = (&self.samples[k], &self.samples[k + p]);
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                let tol = if i < self.coordinates {
                    options.position_tolerance
                } else {
                    options.velocity_tolerance
                };
                worst = worst.max((x - y).abs() / tol);
            }
        }
        worst
    }

    /// Detects the period of the end of the run.
    pub fn detect(&self, options: &PeriodicityOptions) -> Periodicity {
        let residuals: Vec<f64> = (1..=options.max_period)
            .map(|p| self.residual(p, options))
            .collect();
        let period = residuals.iter().position(|&r| r <= 1.0).map(|i| i + 1);
        Periodicity {
            period,
            residuals,
            sections: self.samples.len(),
            window: options.window,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds `f(t)` as a one-coordinate state `q = (x, y)`, `u = (ẋ, ẏ)` at steps of `dt`.
    fn section_of(f: impl Fn(f64) -> f64, period: f64, dt: f64, duration: f64) -> PoincareSection {
        let mut s = PoincareSection::new(period, 0.0);
        let steps = (duration / dt).round() as usize;
        for k in 0..=steps {
            let t = k as f64 * dt;
            s.push(t, &[t, f(t)], &[1.0, 0.0]);
        }
        s
    }

    #[test]
    fn samples_interpolate_to_the_section_times() {
        let s = section_of(|t| 3.0 * t, 0.3, 0.07, 1.0);
        assert_eq!(s.samples().len(), 4);
        for (k, z) in s.samples().iter().enumerate() {
            assert!((z[0] - 0.9 * k as f64).abs() < 1e-12, "{k}: {z:?}");
            assert_eq!(z.len(), 3);
        }
    }

    #[test]
    fn periods_one_and_two_and_none_are_told_apart() {
        let opts = PeriodicityOptions::default();
        let period = 0.25;
        // Period 1: a signal with the drive's period.
        let one = section_of(
            |t| (std::f64::consts::TAU * t / period).sin(),
            period,
            1e-3,
            10.0,
        );
        assert_eq!(one.detect(&opts).period, Some(1));
        // Period 2: half the drive frequency (a period-doubled response).
        let two = section_of(
            |t| 0.1 * (std::f64::consts::PI * t / period + 0.3).sin(),
            period,
            1e-3,
            10.0,
        );
        let d = two.detect(&opts);
        assert_eq!(d.period, Some(2), "{d}");
        assert!(d.residuals[0] > 10.0);
        // None: an incommensurate frequency.
        let none = section_of(
            |t| 0.1 * (t * 2.0_f64.sqrt() * 7.0).sin(),
            period,
            1e-3,
            10.0,
        );
        let d = none.detect(&opts);
        assert_eq!(d.period, None, "{d}");
        assert!(d.residual() > 1.0);
    }

    #[test]
    fn too_short_a_run_has_no_period() {
        let s = section_of(|_| 0.0, 1.0, 0.01, 3.0);
        let d = s.detect(&PeriodicityOptions::default());
        assert_eq!(d.period, None);
        assert!(d.residuals.iter().all(|r| r.is_nan()));
    }
}
