//! Flight phases: take-off and touchdown with a clearance threshold, so a contact that
//! opens for a step while rolling is not counted as a hop.

/// A robot is airborne (a hop) once every enabled shape clears the terrain by this much, m.
pub const HOP_CLEARANCE: f64 = 1e-3;

/// A confirmed change of the robot's ground contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlightEvent {
    /// Left the ground at `t` (the last loaded step ended then).
    TakeOff { t: f64, step: u64 },
    /// Touched down again at `t`.
    Touchdown { t: f64, step: u64 },
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    Ground,
    /// No load since `(t, step)`, not yet clear of the terrain by the threshold.
    Lifting {
        t: f64,
        step: u64,
    },
    Airborne,
}

/// Tracks ground contact and reports confirmed take-offs and touchdowns.
#[derive(Clone, Debug)]
pub struct FlightTracker {
    phase: Phase,
    hops: u64,
}

impl Default for FlightTracker {
    fn default() -> Self {
        Self {
            phase: Phase::Ground,
            hops: 0,
        }
    }
}

impl FlightTracker {
    /// A tracker for a run whose start has the smallest gap `min_gap` to the world: in the
    /// air (a dropped robot) when it clears the terrain by [`HOP_CLEARANCE`], so that the
    /// drop is not counted as a hop; on the ground otherwise.
    pub fn starting(min_gap: f64) -> Self {
        Self {
            phase: if min_gap > HOP_CLEARANCE {
                Phase::Airborne
            } else {
                Phase::Ground
            },
            hops: 0,
        }
    }

    /// Flight phases so far.
    pub fn hops(&self) -> u64 {
        self.hops
    }

    /// Whether the robot is in a confirmed flight phase.
    pub fn airborne(&self) -> bool {
        self.phase == Phase::Airborne
    }

    /// Feeds one step: whether any contact carried load, the smallest gap at the end of
    /// the step, and the step's end time.
    pub fn update(&mut self, t: f64, step: u64, loaded: bool, min_gap: f64) -> Option<FlightEvent> {
        match (self.phase, loaded) {
            (Phase::Ground, false) => {
                self.phase = Phase::Lifting { t, step };
                self.confirm(min_gap)
            }
            (Phase::Lifting { .. }, false) => self.confirm(min_gap),
            (Phase::Lifting { .. }, true) => {
                self.phase = Phase::Ground;
                None
            }
            (Phase::Airborne, true) => {
                self.phase = Phase::Ground;
                Some(FlightEvent::Touchdown { t, step })
            }
            _ => None,
        }
    }

    fn confirm(&mut self, min_gap: f64) -> Option<FlightEvent> {
        let Phase::Lifting { t, step } = self.phase else {
            return None;
        };
        (min_gap > HOP_CLEARANCE).then(|| {
            self.phase = Phase::Airborne;
            self.hops += 1;
            FlightEvent::TakeOff { t, step }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_brief_opening_is_not_a_hop_but_a_clear_flight_is() {
        let mut f = FlightTracker::default();
        assert_eq!(f.update(0.1, 1, false, 1e-5), None);
        assert_eq!(f.update(0.2, 2, true, 0.0), None);
        assert_eq!(f.hops(), 0);
        assert_eq!(f.update(0.3, 3, false, 1e-4), None);
        assert_eq!(
            f.update(0.4, 4, false, 2e-3),
            Some(FlightEvent::TakeOff { t: 0.3, step: 3 })
        );
        assert!(f.airborne());
        assert_eq!(
            f.update(0.5, 5, true, 0.0),
            Some(FlightEvent::Touchdown { t: 0.5, step: 5 })
        );
        assert_eq!(f.hops(), 1);
    }
}
