//! Plain controller settings, as a scene file states them (SI units).

/// Momentum-stored-impulse control of Robbit (physics.md §5.3).
#[derive(Clone, Debug, PartialEq)]
pub struct MomentumImpulseConfig {
    /// Index of the flywheel body; it receives `+T`, its parent (the disc) `-T`.
    pub flywheel: usize,
    /// Stance torque `T`, N m.
    pub torque: f64,
    /// Impulse limit `ζ0`, N m s: brake when `ζ = I_S I_R/(I_S + I_R) (ψ̇ - φ̇) ≥ ζ0`.
    pub impulse_limit: f64,
    /// If no touchdown follows a brake within this time (the brake did not lift the
    /// disc), the next cycle starts anyway, s.
    pub rearm_timeout: f64,
    /// Keep the brake engaged (the rates locked) from the brake until the next cycle
    /// starts at touchdown; otherwise the lock acts in the brake's step only and the
    /// flywheel then turns freely with the motor off.
    pub hold_brake: bool,
}

/// When the cane is extended (physics.md §5.4).
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
}

impl std::fmt::Display for CaneMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CaneMode::Retracted => write!(f, "always retracted"),
            CaneMode::Extended => write!(f, "always extended"),
            CaneMode::Timed { delay, duration } => {
                write!(f, "extended from CD = {delay} P for CDC = {duration} P")
            }
        }
    }
}

/// Open-loop bi-directional joint torque pulse with a cane schedule (physics.md §5.4).
#[derive(Clone, Debug, PartialEq)]
pub struct PulseConfig {
    /// Index of the body driven by the joint motor (its parent takes the reaction).
    pub joint_body: usize,
    /// Pulse torque magnitude, N m (`+torque`, then `-torque`).
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
