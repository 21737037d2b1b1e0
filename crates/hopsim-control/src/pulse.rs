//! CaneBot's open-loop bi-directional torque pulse and cane schedule (docs/physics.md §5.4).

use crate::{shape_gap, CaneMode, ControlEvent, ControlInput, Controller, PulseConfig};
use hopsim_model::JointKind;
use hopsim_step::{Actuation, JointForceCommand, TorqueCommand};

/// The schedule is read at each step's midpoint time `t^M = t^A + Δt/2`, where the midpoint
/// scheme evaluates its forces (docs/physics.md §4). A step never straddles a switching time
/// ambiguously: when `Δt` divides the switching times (scenes/canebot.toml: `Δt = P/1800`)
/// every midpoint lies half a step away from them, and each pulse lasts the same number of
/// steps in every period.
/// `+T` for `pulse_duration`, `-T` for `pulse_duration`, then idle, every period `P` (a
/// torque on a revolute joint, a force along the axis of a prismatic one);
/// the cane follows its schedule but cannot extend while its tip is in the ground.
pub struct Pulse {
    config: PulseConfig,
}

impl Pulse {
    pub fn new(config: PulseConfig) -> Self {
        Self { config }
    }

    /// Motor torque (N m) at time `t`, or force (N) on a prismatic joint.
    pub fn torque_at(&self, t: f64) -> f64 {
        let c = &self.config;
        let phase = t.rem_euclid(c.period);
        if phase < c.pulse_duration {
            c.torque
        } else if phase < 2.0 * c.pulse_duration {
            -c.torque
        } else {
            0.0
        }
    }

    /// Whether the schedule wants the cane extended at time `t`.
    pub fn cane_wanted(&self, t: f64) -> bool {
        match self.config.cane {
            CaneMode::Retracted => false,
            CaneMode::Extended => true,
            CaneMode::Timed { delay, duration } => {
                let fraction = (t / self.config.period).rem_euclid(1.0);
                (fraction - delay).rem_euclid(1.0) < duration
            }
            CaneMode::Triggered { delay, duration } => {
                let n = triggered_cycle(delay, duration);
                let periods = (t / self.config.period).rem_euclid(n);
                (periods - delay).rem_euclid(n) < duration
            }
        }
    }
}

/// The number of motor periods between two operations of the thesis' triggered cane
/// (`CaneMode::Triggered`): the operation of period `j` lasts until `(j + CD + CDC) P`, so
/// the triggers at `kP` with `k − j ≤ CD + CDC` find the cane still out and are lost, and
/// the next operation is in period `j + ⌊CD + CDC⌋ + 1` (docs/physics.md §5.4). A sum within
/// `1e-12` of an integer counts as reaching it, so that `0.7 + 0.3` is 1 whatever its
/// rounding. The periods start at `t = 0`, the first operation in period 0.
fn triggered_cycle(delay: f64, duration: f64) -> f64 {
    (delay + duration + 1e-12).floor() + 1.0
}

impl Controller for Pulse {
    fn control(
        &mut self,
        input: &ControlInput<'_>,
        actuation: &mut Actuation,
        events: &mut Vec<ControlEvent>,
    ) {
        let t = input.state.t + 0.5 * input.dt;
        let (body, value) = (self.config.joint_body, self.torque_at(t));
        let joint = input.model.bodies()[body].joint.as_ref();
        match joint.map(|j| j.kind) {
            // A force along the axis, its reaction on the parent (docs/physics.md §7).
            Some(JointKind::Prismatic { .. }) => actuation
                .joint_forces
                .push(JointForceCommand { body, force: value }),
            _ => actuation.torques.push(TorqueCommand {
                body,
                reaction: joint.and_then(|j| j.parent),
                torque: value,
            }),
        }
        if let Some(cane) = self.config.cane_shape {
            let wanted = self.cane_wanted(t);
            let active = input.shapes_active[cane];
            let free = || shape_gap(input.model, input.kinematics, cane) > 0.0;
            if wanted != active && (!wanted || free()) {
                events.push(ControlEvent::ShapeSwitch {
                    shape: cane,
                    active: wanted,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pulse(cane: CaneMode) -> Pulse {
        Pulse::new(PulseConfig {
            joint_body: 1,
            torque: 0.4,
            pulse_duration: 0.1,
            period: 1.0 / 2.8,
            cane_shape: Some(0),
            cane,
        })
    }

    #[test]
    fn torque_is_a_bidirectional_pulse_each_period() {
        let p = pulse(CaneMode::Retracted);
        let period = 1.0 / 2.8;
        for k in 0..3 {
            let t0 = k as f64 * period;
            assert_eq!(p.torque_at(t0 + 0.05), 0.4);
            assert_eq!(p.torque_at(t0 + 0.15), -0.4);
            assert_eq!(p.torque_at(t0 + 0.3), 0.0);
        }
    }

    /// With `Δt = P/1800` (pulse = 504 steps, CD = 0.1: 180 steps) and the schedule read at
    /// the midpoints `t_start + (k + ½) Δt` the stepper's times give, every period has exactly
    /// 504 steps of `+T`, 504 of `−T` and the cane extended for exactly 900 steps from step
    /// 180: no switch moves by a step with round-off.
    #[test]
    fn schedule_switches_on_the_step_grid() {
        let period = 1.0 / 2.8;
        let dt = period / 1800.0;
        let p = pulse(CaneMode::Timed {
            delay: 0.1,
            duration: 0.5,
        });
        for k in 0..40 {
            let (mut plus, mut minus, mut cane, mut first_cane) = (0, 0, 0, None);
            for step in 0..1800 {
                let t = (k * 1800 + step) as f64 * dt + 0.5 * dt;
                match p.torque_at(t) {
                    x if x > 0.0 => plus += 1,
                    x if x < 0.0 => minus += 1,
                    _ => {}
                }
                if p.cane_wanted(t) {
                    cane += 1;
                    first_cane.get_or_insert(step);
                }
            }
            assert_eq!((plus, minus), (504, 504), "period {k}");
            assert_eq!((cane, first_cane), (900, Some(180)), "period {k}");
        }
    }

    #[test]
    fn timed_cane_wraps_across_periods() {
        let period = 1.0 / 2.8;
        let p = pulse(CaneMode::Timed {
            delay: 0.8,
            duration: 0.5,
        });
        // Extended from 0.8 P to 1.3 P, i.e. [0.8, 1) and [0, 0.3) of every period.
        for (fraction, wanted) in [
            (0.1, true),
            (0.29, true),
            (0.31, false),
            (0.79, false),
            (0.85, true),
        ] {
            assert_eq!(
                p.cane_wanted((2.0 + fraction) * period),
                wanted,
                "at {fraction}"
            );
        }
    }

    /// The steps (`Δt = P/1800`, read at midpoints) at which the schedule extends (`true`)
    /// or retracts (`false`) the cane in the first `periods` periods.
    fn switches(p: &Pulse, periods: usize) -> Vec<(usize, bool)> {
        let period = 1.0 / 2.8;
        let dt = period / 1800.0;
        let mut out = Vec::new();
        let mut last = false;
        for step in 0..periods * 1800 {
            let wanted = p.cane_wanted(step as f64 * dt + 0.5 * dt);
            if wanted != last {
                out.push((step, wanted));
                last = wanted;
            }
        }
        out
    }

    fn triggered(delay: f64, duration: f64) -> Pulse {
        pulse(CaneMode::Triggered { delay, duration })
    }

    /// `CD + CDC < 1`: every period's trigger finds the cane in, so the cane is out from
    /// `(k + CD) P` to `(k + CD + CDC) P` in every period, as the windowed schedule.
    #[test]
    fn triggered_cane_short_operates_every_period() {
        let p = triggered(0.1, 0.5);
        let expected: Vec<_> = (0..4)
            .flat_map(|k| [(k * 1800 + 180, true), (k * 1800 + 1080, false)])
            .collect();
        assert_eq!(switches(&p, 4), expected);
        let windowed = pulse(CaneMode::Timed {
            delay: 0.1,
            duration: 0.5,
        });
        assert_eq!(switches(&windowed, 4), expected);
    }

    /// `CD + CDC ≥ 1`: the operation of period `k` is still out at `(k + 1) P`, so that
    /// period's trigger is lost and the cane operates in periods 0, 2, 4, …; at `CD + CDC = 1`
    /// the cane retracts at the very instant of the next trigger, which is lost too. The
    /// windowed schedule (wrapping) differs: it is out in every period, from `t = 0` on.
    #[test]
    fn triggered_cane_long_operates_every_second_period() {
        let every_second = |start: usize, end: usize| -> Vec<(usize, bool)> {
            (0..3)
                .flat_map(|k| [(k * 3600 + start, true), (k * 3600 + end, false)])
                .collect()
        };
        // CD = 0.6, CDC = 0.5: out over [0.6 P, 1.1 P), [2.6 P, 3.1 P), [4.6 P, 5.1 P).
        assert_eq!(switches(&triggered(0.6, 0.5), 6), every_second(1080, 1980));
        // CD = 0.5, CDC = 0.5: out over [0.5 P, P), [2.5 P, 3 P), …
        assert_eq!(switches(&triggered(0.5, 0.5), 6), every_second(900, 1800));
        // CD = 0, CDC = 1: out over [0, P), [2 P, 3 P), … (the windowed one: always out).
        assert_eq!(switches(&triggered(0.0, 1.0), 6), every_second(0, 1800));
        let windowed = pulse(CaneMode::Timed {
            delay: 0.6,
            duration: 0.5,
        });
        // The windows wrap: out from the start to 0.1 P, then over [0.6 P, 1.1 P) and from
        // 1.6 P on, in every period.
        assert_eq!(
            switches(&windowed, 2),
            [
                (0, true),
                (180, false),
                (1080, true),
                (1980, false),
                (2880, true)
            ]
        );
    }

    /// The triggered schedule against its definition played as events, period by period:
    /// a trigger at `kP` is lost while the last operation's end is `≥ kP`, else the cane
    /// is out over `[(k + CD) P, (k + CD + CDC) P)`; compared at every step midpoint.
    #[test]
    fn triggered_cane_matches_its_definition_as_events() {
        let period = 1.0 / 2.8;
        let dt = period / 1800.0;
        for (delay, duration) in [
            (0.05, 0.3),
            (0.2, 0.8),
            (0.35, 0.9),
            (0.9, 0.25),
            (0.0, 0.5),
        ] {
            let p = triggered(delay, duration);
            let mut windows = Vec::new();
            let mut end = f64::NEG_INFINITY;
            for k in 0..8 {
                let start = (k as f64 + delay) * period;
                if end < k as f64 * period {
                    end = start + duration * period;
                    windows.push((start, end));
                }
            }
            for step in 0..6 * 1800 {
                let t = step as f64 * dt + 0.5 * dt;
                let out = windows.iter().any(|&(a, b)| a <= t && t < b);
                assert_eq!(
                    p.cane_wanted(t),
                    out,
                    "CD {delay}, CDC {duration}, step {step}"
                );
            }
        }
    }
}
