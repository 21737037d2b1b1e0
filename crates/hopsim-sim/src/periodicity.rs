//! Poincaré-section period detection for gaits (docs/physics.md §5.3, §5.4).
//!
//! The section is stroboscopic for periodically driven gaits: the state at the start of
//! every motor period `t = k P` ([`PoincareSection::new`]). Steps do not in general end on
//! `k P`, so the section state is interpolated linearly between the two step ends that
//! bracket it (within one step; an impact inside that step is smeared over it, which the
//! tolerances below are far above). For a gait that times itself (Robbit's brake) the
//! section is taken at events instead ([`PoincareSection::at_events`]): the caller adds a
//! sample at each event with [`PoincareSection::sample`].
//! The forward position `x` of a floating base is left out (a gait repeats up to a
//! translation; [`PoincareSection::leaving_out`] names other coordinates, e.g.
//! `Model::horizontal_positions`); every other coordinate and every velocity is kept.
//!
//! A gait has period `p` when the section states `p` motor periods apart agree within a
//! tolerance over the last `window` comparisons: with `z_k` the `k`-th section state,
//!
//! ```text
//! r_p = max over the last `window` k, over components i of |z_{k+p,i} − z_{k,i}| / tol_i,
//! tol_i = relative_tolerance · (max − min of component i over the compared stretch of the
//!         run, every step, not only the sections) + absolute_tolerance
//! ```
//!
//! The detected period is the smallest `p ≤ max_period` with `r_p ≤ 1`; none when no `p`
//! qualifies (quasi-periodic, chaotic, still in its transient, or a period above
//! `max_period`).
//!
//! The tolerance is relative to each variable's own excursion in the gait because a
//! time-stepper's section cannot repeat exactly: impacts and lift-offs are resolved on the
//! step grid, so the section state of a periodic gait jitters by `O(Δt)` (for CaneBot at
//! `Δt = P/1800`, up to about 0.5 % of the excursions; halving `Δt` roughly halves it, see
//! docs/canebot.md), while `z` of a period-2 gait compared one period apart differs by a
//! sizeable fraction of the excursion.

use crate::{Observer, RunError, StepView};
use serde::Serialize;

/// How periodicity is decided.
#[derive(Clone, Debug, PartialEq)]
pub struct PeriodicityOptions {
    /// Section samples compared for each candidate period (the last ones of the run).
    pub window: usize,
    /// Largest period tried, in motor periods.
    pub max_period: usize,
    /// Agreement required, as a fraction of each component's excursion (max − min) over
    /// the compared stretch of the run.
    pub relative_tolerance: f64,
    /// Added to every component's tolerance (m, rad, m/s, rad/s), for components that do
    /// not move.
    pub absolute_tolerance: f64,
}

impl Default for PeriodicityOptions {
    /// The last 8 comparisons, periods 1 to 4, 2 % of each excursion plus 1e-6.
    fn default() -> Self {
        Self {
            window: 8,
            max_period: 4,
            relative_tolerance: 0.02,
            absolute_tolerance: 1e-6,
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
    /// `PeriodicityOptions::relative_tolerance`.
    pub relative_tolerance: f64,
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
            " (residuals {} for p = 1..{}, 1 = {} % of the excursions; {} sections, last {} compared)",
            residuals.join(", "),
            self.residuals.len(),
            100.0 * self.relative_tolerance,
            self.sections,
            self.window
        )
    }
}

/// Collects the Poincaré section of a run: stroboscopic (`t = t0 + k P`) or at events.
#[derive(Clone, Debug)]
pub struct PoincareSection {
    /// `(P, t0)` of a stroboscopic section; `None` for a section at events.
    strobe: Option<(f64, f64)>,
    /// Number of coordinates in a section state (`q` without `x`); velocities follow.
    coordinates: usize,
    /// Index `k` of the next section time `t0 + k P`.
    next: u64,
    previous: Option<(f64, Vec<f64>)>,
    samples: Vec<Vec<f64>>,
    /// Times of the samples, s.
    times: Vec<f64>,
    /// Indices of the coordinates of `q` left out of the section state.
    left_out: Vec<usize>,
    /// Componentwise minimum and maximum of the states pushed since the last sample.
    low: Vec<f64>,
    high: Vec<f64>,
    /// For each sample after the first: the componentwise (min, max) over the period that
    /// ended with it (`spans[k - 1]` ends with sample `k`).
    spans: Vec<(Vec<f64>, Vec<f64>)>,
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
            strobe: Some((period, t0)),
            ..Self::at_events()
        }
    }

    /// A section whose samples the caller takes ([`PoincareSection::sample`]), e.g. at
    /// every brake of Robbit; [`PoincareSection::push`] then only follows the excursions.
    pub fn at_events() -> Self {
        Self {
            strobe: None,
            coordinates: 0,
            next: 0,
            previous: None,
            samples: Vec::new(),
            times: Vec::new(),
            left_out: vec![0],
            low: Vec::new(),
            high: Vec::new(),
            spans: Vec::new(),
        }
    }

    /// Leaves the coordinates `left_out` of `q` out of the section state instead of `q[0]`
    /// (the `x` of a floating base first in the tree): e.g. every floating base's `x`
    /// (`Model::horizontal_positions`), or none for a robot fixed to the world.
    pub fn leaving_out(mut self, left_out: Vec<usize>) -> Self {
        self.left_out = left_out;
        self
    }

    /// The section state of `(q, u)`: `q` without the coordinates left out, then `u`.
    pub fn section_state(&self, q: &[f64], u: &[f64]) -> Vec<f64> {
        let kept = q
            .iter()
            .enumerate()
            .filter(|(i, _)| !self.left_out.contains(i));
        kept.map(|(_, v)| *v).chain(u.iter().copied()).collect()
    }

    /// The number of coordinates of `q` that the section keeps.
    fn kept(&self, q: &[f64]) -> usize {
        (0..q.len()).filter(|i| !self.left_out.contains(i)).count()
    }

    /// Feeds the state `(q, u)` at time `t` (call it for the start state and after every
    /// step, in time order); records every section time passed since the last call.
    pub fn push(&mut self, t: f64, q: &[f64], u: &[f64]) {
        self.coordinates = self.kept(q);
        let z = self.section_state(q, u);
        while let Some((period, t0)) = self.strobe {
            let ts = t0 + self.next as f64 * period;
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
            self.add(ts, sample);
            self.next += 1;
        }
        for ((l, h), v) in self.low.iter_mut().zip(self.high.iter_mut()).zip(&z) {
            *l = l.min(*v);
            *h = h.max(*v);
        }
        self.previous = Some((t, z));
    }

    /// Takes the state `(q, u)` at time `t` as the next sample (a section at events; push
    /// the same state too, so that the excursions include it).
    pub fn sample(&mut self, t: f64, q: &[f64], u: &[f64]) {
        self.coordinates = self.kept(q);
        self.add(t, self.section_state(q, u));
    }

    /// Appends a sample; the excursions since the previous sample become its span.
    fn add(&mut self, t: f64, sample: Vec<f64>) {
        if !self.samples.is_empty() {
            let (mut low, mut high) = (self.low.clone(), self.high.clone());
            for ((l, h), v) in low.iter_mut().zip(high.iter_mut()).zip(&sample) {
                *l = l.min(*v);
                *h = h.max(*v);
            }
            self.spans.push((low, high));
        }
        self.low.clone_from(&sample);
        self.high.clone_from(&sample);
        self.samples.push(sample);
        self.times.push(t);
    }

    /// The section states so far, one per motor period (or event).
    pub fn samples(&self) -> &[Vec<f64>] {
        &self.samples
    }

    /// The section times so far, s.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Number of coordinates (`q` without those left out) at the front of each section state.
    pub fn coordinates(&self) -> usize {
        self.coordinates
    }

    /// The tolerance of each component for comparisons from sample `first` on: the
    /// excursion over the periods from sample `first` to the last sample.
    pub fn tolerances(&self, first: usize, options: &PeriodicityOptions) -> Vec<f64> {
        let dim = self.samples.first().map_or(0, Vec::len);
        let (mut low, mut high) = (vec![f64::INFINITY; dim], vec![f64::NEG_INFINITY; dim]);
        for (l, h) in &self.spans[first.min(self.spans.len())..] {
            for i in 0..dim {
                low[i] = low[i].min(l[i]);
                high[i] = high[i].max(h[i]);
            }
        }
        (0..dim)
            .map(|i| {
                let span = if high[i] >= low[i] {
                    high[i] - low[i]
                } else {
                    0.0
                };
                options.relative_tolerance * span + options.absolute_tolerance
            })
            .collect()
    }

    /// `r_p` (see the module documentation), `NaN` with too few samples.
    pub fn residual(&self, p: usize, options: &PeriodicityOptions) -> f64 {
        let n = self.samples.len();
        if p == 0 || options.window == 0 || n < options.window + p {
            return f64::NAN;
        }
        let first = n - options.window - p;
        let tol = self.tolerances(first, options);
        let mut worst = 0.0_f64;
        for k in first..n - p {
            let (a, b) = (&self.samples[k], &self.samples[k + p]);
            for ((x, y), tol) in a.iter().zip(b).zip(&tol) {
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
            relative_tolerance: options.relative_tolerance,
        }
    }
}

/// As an observer of a run, the section sees the start state and the state after every
/// step.
impl Observer for PoincareSection {
    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.on_step(view)
    }

    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        let state = view.state;
        self.push(state.t, state.q.as_slice(), state.u.as_slice());
        Ok(())
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
    fn jitter_well_inside_the_tolerance_is_still_period_one() {
        let period = 0.25;
        // ±0.5 % of the excursion (2) of a period-1 signal, changing every period.
        let jittery = section_of(
            |t| {
                let k = (t / period).floor();
                (std::f64::consts::TAU * t / period).cos() + 0.01 * (k * 1.7).sin()
            },
            period,
            1e-3,
            10.0,
        );
        let d = jittery.detect(&PeriodicityOptions::default());
        assert_eq!(d.period, Some(1), "{d}");
        assert!(d.residuals[0] > 0.1, "{d}");
    }

    /// A section at events: samples where the caller takes them, excursions from every
    /// pushed state between them.
    #[test]
    fn a_section_at_events_finds_period_two() {
        let mut s = PoincareSection::at_events();
        for k in 0..20 {
            let t = k as f64;
            let z = if k % 2 == 0 { 1.0 } else { -1.0 };
            s.sample(t, &[0.0, z], &[0.0, 0.0]);
            // Between two events the state swings through ±2.
            s.push(t, &[0.0, z], &[0.0, 0.0]);
            s.push(t + 0.5, &[0.0, 2.0 * z], &[0.0, 0.0]);
        }
        assert_eq!(s.times()[3], 3.0);
        let d = s.detect(&PeriodicityOptions::default());
        assert_eq!(d.period, Some(2), "{d}");
        // Samples 2 apart in z by 2 against an excursion of 4 (tolerance 2 % of it + 1e-6).
        assert!(
            (d.residuals[0] - 2.0 / (0.02 * 4.0 + 1e-6)).abs() < 1e-9,
            "{d}"
        );
    }

    #[test]
    fn too_short_a_run_has_no_period() {
        let s = section_of(|_| 0.0, 1.0, 0.01, 3.0);
        let d = s.detect(&PeriodicityOptions::default());
        assert_eq!(d.period, None);
        assert!(d.residuals.iter().all(|r| r.is_nan()));
    }
}
