//! Plain controller settings, as a scene file states them (SI units).

/// Momentum-stored-impulse control of Robbit (docs/physics.md §5.3).
#[derive(Clone, Debug, PartialEq)]
pub struct MomentumImpulseConfig {
    /// Index of the flywheel body; it receives `+T`, its parent (the disc) `-T`.
    pub flywheel: usize,
    /// Stance torque `T`, N m.
    pub torque: f64,
    /// Impulse limit `ζ0`, N m s: brake when `ζ = I_S I_R/(I_S + I_R) (ψ̇ - φ̇) ≥ ζ0`.
    pub impulse_limit: f64,
    /// When the motor comes back on after a brake.
    pub release: Release,
    /// Keep the brake engaged (the rates locked) from the brake until the next cycle
    /// starts; otherwise the lock acts in the brake's step only and the flywheel then
    /// turns freely with the motor off.
    pub hold_brake: bool,
}

/// When the next cycle starts (the motor back on) after a brake (docs/physics.md §5.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Release {
    /// Motor off until the disc touches the ground again after a flight (the thesis'
    /// simulation). A brake that does not lift the disc is followed by no flight: then the
    /// next cycle starts once `rearm_timeout` seconds have passed since the brake with the
    /// disc in contact.
    Touchdown {
        /// s, > 0.
        rearm_timeout: f64,
    },
    /// Motor off for `off_time` seconds after each brake, whatever the contact (the
    /// thesis' experiment: 100 ms).
    OffTime {
        /// s, ≥ 0; 0 restarts the motor in the step after the brake.
        off_time: f64,
    },
}

impl std::fmt::Display for Release {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Release::Touchdown { rearm_timeout } => write!(
                f,
                "motor off from the brake until touchdown (rearm after {rearm_timeout} s in contact)"
            ),
            Release::OffTime { off_time } => {
                write!(f, "motor off for {off_time} s after each brake")
            }
        }
    }
}

/// When the cane is extended (docs/physics.md §5.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CaneMode {
    /// Never extended.
    Retracted,
    /// Always extended.
    Extended,
    /// Extended from `delay · P` for `duration · P` in each motor period `P` (wrapping).
    Timed {
        /// `CD`, fraction of the period.
        delay: f64,
        /// `CDC`, fraction of the period.
        duration: f64,
    },
    /// The thesis' schedule: a trigger at the start `kP` of every motor period extends the
    /// cane at `kP + delay · P` for `duration · P`, unless the cane is still out at `kP`
    /// (then that period's trigger is lost). With `delay + duration < 1` this is `Timed`;
    /// with `delay + duration ≥ 1` the cane is operated every second period.
    Triggered {
        /// `CD`, fraction of the period.
        delay: f64,
        /// `CDC`, fraction of the period.
        duration: f64,
    },
}

impl CaneMode {
    /// `(CD, CDC)` of a timed or triggered schedule.
    pub fn timing(&self) -> Option<(f64, f64)> {
        match *self {
            CaneMode::Timed { delay, duration } | CaneMode::Triggered { delay, duration } => {
                Some((delay, duration))
            }
            CaneMode::Retracted | CaneMode::Extended => None,
        }
    }
}

impl std::fmt::Display for CaneMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CaneMode::Retracted => write!(f, "always retracted"),
            CaneMode::Extended => write!(f, "always extended"),
            CaneMode::Timed { delay, duration } => {
                write!(f, "extended from CD = {delay} P for CDC = {duration} P")
            }
            CaneMode::Triggered { delay, duration } => write!(
                f,
                "triggered at CD = {delay} P for CDC = {duration} P unless still out (thesis)"
            ),
        }
    }
}

/// Open-loop bi-directional joint torque pulse with a cane schedule (docs/physics.md §5.4).
#[derive(Clone, Debug, PartialEq)]
pub struct PulseConfig {
    /// Index of the body driven by the joint motor (its parent takes the reaction): on a
    /// revolute joint (a pinned base included) or a prismatic one.
    pub joint_body: usize,
    /// Pulse magnitude (`+torque`, then `-torque`): a torque in N m on a revolute joint, a
    /// force in N along the axis of a prismatic one (the scene's `force`).
    pub torque: f64,
    /// Duration of each of the two pulses, s.
    pub pulse_duration: f64,
    /// Motor period `P`, s.
    pub period: f64,
    /// Index of the cane's shape in the model, if the robot has one.
    pub cane_shape: Option<usize>,
    /// Cane schedule.
    pub cane: CaneMode,
}

impl PulseConfig {
    /// Whether the pulse is a force along a prismatic joint (N) rather than a torque (N m).
    pub fn drives_force(&self, model: &hopsim_model::Model) -> bool {
        model.bodies()[self.joint_body]
            .joint
            .as_ref()
            .is_some_and(|j| matches!(j.kind, hopsim_model::JointKind::Prismatic { .. }))
    }
}

/// Which controller a scene runs.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum ControllerConfig {
    /// No actuation: a passive system.
    #[default]
    Passive,
    /// Robbit's momentum-stored impulse.
    MomentumImpulse(MomentumImpulseConfig),
    /// CaneBot's pulsed joint torque with cane schedule.
    Pulse(PulseConfig),
}
