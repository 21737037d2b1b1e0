//! Axes and their ticks. An [`Axis`] is a plotters coordinate that chooses its own ticks:
//! steps of 1, 2 or 5 × 10^k on a linear axis; whole numbers only on an integer axis
//! (cycle numbers, lags); decades, and 2 and 5 times them while they fit, on a
//! logarithmic axis (never 0.316 or 31.6). Tick values are exact multiples of their step,
//! so round-off never shows as a tick (`-1.26e-29`), and labels carry as many decimals as
//! the step needs.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, KeyPointWeight, Ranged};
use std::ops::Range;

/// How an axis maps values and where it ticks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scale {
    /// Values as they are; ticks every 1, 2 or 5 × 10^k.
    #[default]
    Linear,
    /// Whole numbers (counts, cycle numbers, lags): ticks every 1, 2, 5, 10, … only.
    Integer,
    /// The chart's coordinate is `log10` of the value (values ≤ 0 are left out).
    Log,
}

impl Scale {
    /// The chart coordinate of `value` (NaN for a value ≤ 0 on a logarithmic axis).
    pub fn to_chart(self, value: f64) -> f64 {
        match self {
            Scale::Log if value > 0.0 => value.log10(),
            Scale::Log => f64::NAN,
            Scale::Linear | Scale::Integer => value,
        }
    }

    /// The value at chart coordinate `c`.
    pub fn to_value(self, c: f64) -> f64 {
        match self {
            Scale::Log => 10f64.powf(c),
            Scale::Linear | Scale::Integer => c,
        }
    }
}

/// Most labelled ticks on an axis.
pub const MAX_TICKS: usize = 10;

/// An axis: its range in chart coordinates and its scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    lo: f64,
    hi: f64,
    scale: Scale,
}

impl Axis {
    /// The axis over `range` (chart coordinates; a reversed range is put in order, a
    /// non-finite one becomes `0 … 1`, an empty one is widened around its value).
    pub fn new((a, b): (f64, f64), scale: Scale) -> Self {
        let (lo, hi) = match (a.is_finite() && b.is_finite(), a.min(b), a.max(b)) {
            (false, _, _) => (0.0, 1.0),
            (true, lo, hi) if hi > lo => (lo, hi),
            (true, v, _) => (v - 0.5 * v.abs().max(1.0), v + 0.5 * v.abs().max(1.0)),
        };
        Axis { lo, hi, scale }
    }

    /// The range in chart coordinates.
    pub fn bounds(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }

    /// The scale.
    pub fn scale(&self) -> Scale {
        self.scale
    }

    /// The labelled ticks (chart coordinates), at most `max`.
    pub fn ticks(&self, max: usize) -> Vec<f64> {
        match self.scale {
            Scale::Linear => linear_ticks(self.lo, self.hi, max, None),
            Scale::Integer => linear_ticks(self.lo, self.hi, max, Some(1.0)),
            Scale::Log => log_ticks(self.lo, self.hi, max),
        }
    }

    /// The lines of the light grid (chart coordinates), at most `max`: finer steps on a
    /// linear axis, never between whole numbers on an integer axis, 1 … 9 × 10^k on a
    /// logarithmic axis.
    fn light_ticks(&self, max: usize) -> Vec<f64> {
        match self.scale {
            Scale::Log => {
                let all = multiples_of_decades(self.lo, self.hi, &[1, 2, 3, 4, 5, 6, 7, 8, 9]);
                match all.len() <= max {
                    true => all,
                    false => multiples_of_decades(self.lo, self.hi, &[1]),
                }
            }
            _ => {
                let step = nice_step(self.lo, self.hi, max, self.min_step());
                every(self.lo, self.hi, step)
            }
        }
    }

    fn min_step(&self) -> Option<f64> {
        (self.scale == Scale::Integer).then_some(1.0)
    }

    /// The label of the tick at chart coordinate `c`: decimals as the labelled ticks'
    /// step needs, no trailing zeros, never `-0`; on a logarithmic axis the value itself
    /// with three significant digits (`0.2`, `10`, `5000`).
    pub fn label(&self, c: f64) -> String {
        match self.scale {
            Scale::Log => three_significant_digits(Scale::Log.to_value(c)),
            _ => tick_label(c, nice_step(self.lo, self.hi, MAX_TICKS, self.min_step())),
        }
    }
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, (start, end): (i32, i32)) -> i32 {
        let t = (value - self.lo) / (self.hi - self.lo);
        (f64::from(start) + t * f64::from(end - start)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        match hint.weight() {
            KeyPointWeight::Bold => self.ticks(hint.max_num_points()),
            KeyPointWeight::Any => self.light_ticks(hint.max_num_points()),
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// The smallest step of 1, 2 or 5 × 10^k (at least `min_step`) with at most `max` of its
/// multiples in `[lo, hi]`.
fn nice_step(lo: f64, hi: f64, max: usize, min_step: Option<f64>) -> f64 {
    let max = max.max(2) as f64;
    let raw = ((hi - lo) / max).max(min_step.unwrap_or(0.0));
    let mut k = 10f64.powf(raw.log10().floor() - 1.0);
    loop {
        for m in [1.0, 2.0, 5.0] {
            let step = m * k;
            let count = (hi / step + 1e-9).floor() - (lo / step - 1e-9).ceil() + 1.0;
            if count <= max && step >= min_step.unwrap_or(0.0) {
                return step;
            }
        }
        k *= 10.0;
    }
}

/// The multiples of `step` in `[lo, hi]` (a relative tolerance of 1e-9 at the ends).
fn every(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// At most `max` ticks of a linear axis (whole numbers with `min_step = 1`).
fn linear_ticks(lo: f64, hi: f64, max: usize, min_step: Option<f64>) -> Vec<f64> {
    every(lo, hi, nice_step(lo, hi, max, min_step))
}

/// `log10(m · 10^k)` for every `m` of `multipliers` and every decade `k`, within the
/// chart range `[a, b]`.
fn multiples_of_decades(a: f64, b: f64, multipliers: &[u32]) -> Vec<f64> {
    let decades = (a.floor() as i64 - 1)..=(b.ceil() as i64);
    decades
        .flat_map(|k| {
            multipliers
                .iter()
                .map(move |&m| k as f64 + f64::from(m).log10())
        })
        .filter(|&c| c >= a - 1e-9 && c <= b + 1e-9)
        .collect()
}

/// At most `max` ticks of a logarithmic axis over the chart range `[a, b]`: 1, 2 and 5
/// times the decades; else the decades; else every second, fifth, tenth … decade. A range
/// within less than a decade that holds fewer than two of them is ticked linearly in value.
fn log_ticks(a: f64, b: f64, max: usize) -> Vec<f64> {
    let one_two_five = multiples_of_decades(a, b, &[1, 2, 5]);
    if one_two_five.len() < 2 {
        let (lo, hi) = (Scale::Log.to_value(a), Scale::Log.to_value(b));
        let ticks = linear_ticks(lo, hi, max.min(5), None);
        return ticks.into_iter().map(|v| Scale::Log.to_chart(v)).collect();
    }
    if one_two_five.len() <= max {
        return one_two_five;
    }
    let decades = multiples_of_decades(a, b, &[1]);
    let mut every_nth = 1;
    loop {
        let kept: Vec<f64> = (decades.iter().copied())
            .filter(|c| (c.round() as i64).rem_euclid(every_nth) == 0)
            .collect();
        if kept.len() <= max.max(1) {
            return kept;
        }
        every_nth = match every_nth {
            1 => 2,
            2 => 5,
            n => 2 * n,
        };
    }
}

/// A tick label for `value` on an axis whose ticks are about `step` apart: as many
/// decimals as the step needs, without trailing zeros (`10`, `0.25`), never `-0`; a value
/// within a millionth of a step of zero is `0`.
pub fn tick_label(value: f64, step: f64) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    let step = if step.is_finite() && step > 0.0 {
        step
    } else {
        value.abs().max(1.0)
    };
    if value.abs() < 1e-6 * step {
        return "0".into();
    }
    // Two more decimals than the step's leading digit, so that steps of 0.25 or 0.025
    // print exactly; trailing zeros are dropped below.
    let decimals = (2 - step.log10().floor() as i32).clamp(0, 15) as usize;
    let magnitude = value.abs();
    let text = if magnitude >= 1e6 || (magnitude > 0.0 && magnitude < 1e-4 && step < 1e-4) {
        // Scientific notation, three significant digits.
        let text = format!("{value:.2e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = trim_zeros(mantissa);
        format!("{mantissa}e{exponent}")
    } else {
        trim_zeros(&format!("{value:.decimals$}"))
    };
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
    }
}

/// `text` (a decimal number) without trailing zeros after the point, nor a bare point.
fn trim_zeros(text: &str) -> String {
    match text.contains('.') {
        true => text.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => text.to_string(),
    }
}

/// `x` with three significant digits, without trailing zeros (axis labels, notes).
pub fn three_significant_digits(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return tick_label(x, 1.0);
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    if x.abs() >= 1e6 || x.abs() < 1e-4 {
        return tick_label(x, x.abs() * 1e-3);
    }
    tick_label(
        format!("{x:.decimals$}").parse().unwrap_or(x),
        10f64.powi(-(decimals as i32)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(axis: &Axis) -> Vec<String> {
        let ticks = axis.ticks(MAX_TICKS);
        ticks.iter().map(|&c| axis.label(c)).collect()
    }

    /// A logarithmic axis ticks at 1, 2 and 5 times the decades while they fit, then at
    /// the decades, then at every few decades; never at 10^(k/2) (0.316, 31.6).
    #[test]
    fn log_axes_tick_at_decades_and_two_and_five() {
        let axis = |lo: f64, hi: f64| Axis::new((lo.log10(), hi.log10()), Scale::Log);
        assert_eq!(
            labels(&axis(0.15, 120.0)),
            ["0.2", "0.5", "1", "2", "5", "10", "20", "50", "100"]
        );
        assert_eq!(
            labels(&axis(0.15, 1200.0)),
            ["1", "10", "100", "1000"],
            "four decades: 1-2-5 would be 12 ticks"
        );
        assert_eq!(
            labels(&axis(1e-3, 1e9)),
            ["0.01", "1", "100", "10000", "1e6", "1e8"]
        );
        // Within a decade: linear values, still plain numbers.
        assert_eq!(labels(&axis(3.0, 8.0)), ["4", "6", "8"]);
        for (lo, hi) in [(0.2, 120.0), (0.01, 5e4), (0.3, 0.9), (2e-3, 0.8)] {
            for label in labels(&axis(lo, hi)) {
                let v: f64 = label.parse().unwrap();
                let mantissa = v / 10f64.powf(v.log10().floor());
                assert!(
                    [1.0, 2.0, 4.0, 5.0, 6.0, 8.0]
                        .iter()
                        .any(|m| (mantissa - m).abs() < 1e-9),
                    "{lo}…{hi}: {label}"
                );
            }
        }
    }

    /// Integer axes tick at whole numbers only, however short; linear axes at exact
    /// multiples of 1, 2 or 5 × 10^k, with zero exactly zero.
    #[test]
    fn integer_and_linear_ticks() {
        let integer = |lo, hi| labels(&Axis::new((lo, hi), Scale::Integer));
        assert_eq!(integer(0.5, 4.5), ["1", "2", "3", "4"]);
        assert_eq!(integer(0.7, 1.3), ["1"]);
        assert_eq!(
            integer(-0.5, 76.5),
            ["0", "10", "20", "30", "40", "50", "60", "70"]
        );
        let linear = |lo, hi| labels(&Axis::new((lo, hi), Scale::Linear));
        assert_eq!(
            linear(0.5, 4.5),
            ["0.5", "1", "1.5", "2", "2.5", "3", "3.5", "4", "4.5"]
        );
        assert_eq!(
            linear(-1.3e-13, 1.1e-13),
            ["-1e-13", "-5e-14", "0", "5e-14", "1e-13"]
        );
        let ticks = Axis::new((-1.0, 1.0), Scale::Linear).ticks(MAX_TICKS);
        assert!(ticks.contains(&0.0), "{ticks:?}");
        assert_eq!(
            linear(0.1, 0.1),
            ["-0.4", "-0.2", "0", "0.2", "0.4", "0.6"],
            "an empty range is widened"
        );
        assert_eq!(
            linear(f64::NAN, 1.0),
            labels(&Axis::new((0.0, 1.0), Scale::Linear))
        );
    }

    #[test]
    fn tick_labels_are_clean() {
        assert_eq!(tick_label(10.0, 1.0), "10");
        assert_eq!(tick_label(-0.0, 0.1), "0");
        assert_eq!(tick_label(-1.26e-29, 0.2), "0");
        assert_eq!(tick_label(0.30000000000000004, 0.1), "0.3");
        assert_eq!(tick_label(0.025, 0.025), "0.025");
        assert_eq!(tick_label(-2.5, 0.5), "-2.5");
        assert_eq!(tick_label(1500.0, 500.0), "1500");
        assert_eq!(three_significant_digits(8.7123), "8.71");
        assert_eq!(three_significant_digits(-0.0), "0");
    }
}
