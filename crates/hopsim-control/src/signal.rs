//! Open-loop control signals: an actuator's control as a function of time (constant, sine,
//! pulse train, piecewise-linear table), for runs without a controller of their own
//! (docs/scene-format.md, `[[actuators]]`).

use std::f64::consts::TAU;

/// A control as a function of time `t` (s).
#[derive(Clone, Debug, PartialEq)]
pub enum ControlSignal {
    /// `value` at every time.
    Constant { value: f64 },
    /// `offset + amplitude · sin(2π frequency t + phase)`; `frequency` in Hz, `phase` in rad.
    Sine {
        amplitude: f64,
        frequency: f64,
        phase: f64,
        offset: f64,
    },
    /// `value` during the first `width` seconds of every `period`, starting at `t = 0`;
    /// 0 otherwise.
    Pulse { period: f64, width: f64, value: f64 },
    /// Linear between the points `(times[i], values[i])`, held at the first value before the
    /// first time and at the last after the last (a table read from a CSV file is one).
    Table { times: Vec<f64>, values: Vec<f64> },
}

impl ControlSignal {
    /// The control at time `t`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            ControlSignal::Constant { value } => *value,
            ControlSignal::Sine {
                amplitude,
                frequency,
                phase,
                offset,
            } => offset + amplitude * (TAU * frequency * t + phase).sin(),
            ControlSignal::Pulse {
                period,
                width,
                value,
            } => {
                if t >= 0.0 && t.rem_euclid(*period) < *width {
                    *value
                } else {
                    0.0
                }
            }
            ControlSignal::Table { times, values } => table_value(times, values, t),
        }
    }

    /// What is wrong with the signal's parameters, if anything: every number finite, a
    /// pulse's period positive and width in `[0, period]`, a table's times strictly
    /// increasing with one value each.
    pub fn problem(&self) -> Option<String> {
        let numbers: Vec<f64> = match self {
            ControlSignal::Constant { value } => vec![*value],
            ControlSignal::Sine {
                amplitude,
                frequency,
                phase,
                offset,
            } => vec![*amplitude, *frequency, *phase, *offset],
            ControlSignal::Pulse {
                period,
                width,
                value,
            } => vec![*period, *width, *value],
            ControlSignal::Table { times, values } => {
                times.iter().chain(values.iter()).copied().collect()
            }
        };
        if let Some(v) = numbers.iter().find(|v| !v.is_finite()) {
            return Some(format!("every number must be finite, got {v}"));
        }
        match self {
            ControlSignal::Pulse { period, width, .. } => {
                if *period <= 0.0 {
                    return Some(format!("a pulse's period must be positive, got {period}"));
                }
                if !(0.0..=*period).contains(width) {
                    return Some(format!(
                        "a pulse's width must be in [0, period = {period}], got {width}"
                    ));
                }
            }
            ControlSignal::Table { times, values } => {
                if times.is_empty() || times.len() != values.len() {
                    return Some(format!(
                        "a table needs as many values as times, at least one: {} times, {} values",
                        times.len(),
                        values.len()
                    ));
                }
                if let Some(i) = times.windows(2).position(|w| w[0] >= w[1]) {
                    return Some(format!(
                        "a table's times must increase strictly: {} is followed by {}",
                        times[i],
                        times[i + 1]
                    ));
                }
            }
            ControlSignal::Constant { .. } | ControlSignal::Sine { .. } => {}
        }
        None
    }
}

/// Linear interpolation in the table `(times, values)` (times strictly increasing, not
/// empty), held constant beyond its ends.
fn table_value(times: &[f64], values: &[f64], t: f64) -> f64 {
    // The first point after `t`.
    let i = times.partition_point(|&ti| ti <= t);
    if i == 0 {
        return values[0];
    }
    if i == times.len() {
        return values[i - 1];
    }
    let (t0, t1, v0, v1) = (times[i - 1], times[i], values[i - 1], values[i]);
    v0 + (v1 - v0) * (t - t0) / (t1 - t0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_and_holds_its_ends() {
        let s = ControlSignal::Table {
            times: vec![0.0, 1.0, 3.0],
            values: vec![2.0, 4.0, 0.0],
        };
        assert_eq!(s.problem(), None);
        assert_eq!(s.value(-1.0), 2.0);
        assert_eq!(s.value(0.5), 3.0);
        assert_eq!(s.value(1.0), 4.0);
        assert_eq!(s.value(2.0), 2.0);
        assert_eq!(s.value(7.0), 0.0);
    }

    #[test]
    fn pulse_is_on_for_its_width_in_every_period() {
        let s = ControlSignal::Pulse {
            period: 0.5,
            width: 0.1,
            value: 3.0,
        };
        let on: Vec<bool> = [0.0, 0.05, 0.1, 0.3, 0.55, 1.02, -0.01]
            .iter()
            .map(|&t| s.value(t) == 3.0)
            .collect();
        assert_eq!(on, [true, true, false, false, true, true, false]);
    }

    #[test]
    fn sine_has_its_amplitude_frequency_phase_and_offset() {
        let s = ControlSignal::Sine {
            amplitude: 2.0,
            frequency: 0.25,
            phase: 0.0,
            offset: 1.0,
        };
        // A quarter period (1 s) in: the crest.
        assert!((s.value(1.0) - 3.0).abs() < 1e-15);
        assert!((s.value(3.0) + 1.0).abs() < 1e-15);
    }

    #[test]
    fn bad_parameters_are_named() {
        let bad = [
            ControlSignal::Pulse {
                period: 0.0,
                width: 0.0,
                value: 1.0,
            },
            ControlSignal::Table {
                times: vec![0.0, 0.0],
                values: vec![1.0, 2.0],
            },
            ControlSignal::Table {
                times: vec![0.0],
                values: vec![],
            },
            ControlSignal::Constant { value: f64::NAN },
        ];
        for s in bad {
            assert!(s.problem().is_some(), "{s:?}");
        }
    }
}
