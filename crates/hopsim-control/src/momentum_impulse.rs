//! Robbit's momentum-stored-impulse control (docs/physics.md §5.3).

use crate::{ControlEvent, ControlInput, Controller, MomentumImpulseConfig, Release};
use hopsim_model::Model;
use hopsim_step::{Actuation, TorqueCommand};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Motor on: `+T` on the flywheel, `-T` on the disc.
    Stance,
    /// Braked in the step that started at `since`; torque zero until the release
    /// ([`Release`]) starts the next cycle. `airborne`: a step without contact load has
    /// followed the brake.
    Released { since: f64, airborne: bool },
}

/// Spins the flywheel up in stance and brakes it when `ζ ≥ ζ0`.
pub struct MomentumImpulse {
    config: MomentumImpulseConfig,
    disc: usize,
    /// `I_S I_R / (I_S + I_R)`, kg m².
    reduced_inertia: f64,
    phase: Phase,
}

impl MomentumImpulse {
    /// A controller for `model`, whose flywheel body is `config.flywheel`.
    pub fn new(config: MomentumImpulseConfig, model: &Model) -> Self {
        let flywheel = &model.bodies()[config.flywheel];
        let disc = flywheel.joint.as_ref().and_then(|j| j.parent).unwrap_or(0);
        let (i_s, i_r) = (model.bodies()[disc].inertia, flywheel.inertia);
        Self {
            config,
            disc,
            reduced_inertia: i_s * i_r / (i_s + i_r),
            phase: Phase::Stance,
        }
    }

    /// The impulse `ζ = I_S I_R/(I_S + I_R) (ψ̇ - φ̇)` a brake would transfer now [5.7-5.9].
    pub fn stored_impulse(&self, input: &ControlInput<'_>) -> f64 {
        let k = input.kinematics;
        self.reduced_inertia
            * (k.angular_velocity(self.config.flywheel) - k.angular_velocity(self.disc))
    }
}

impl Controller for MomentumImpulse {
    fn control(
        &mut self,
        input: &ControlInput<'_>,
        actuation: &mut Actuation,
        events: &mut Vec<ControlEvent>,
    ) {
        let t = input.state.t;
        if let Phase::Released { since, airborne } = self.phase {
            // Steps start on the grid `t_start + k Δt`: with half a step of slack a time
            // `τ` after the brake is reached exactly `max(1, round(τ / Δt))` steps after
            // it, whatever the round-off of the step times.
            let reached = |duration: f64| t - since >= duration - 0.5 * input.dt;
            let released = match self.config.release {
                // The first step after a loaded step that followed a flight; or, when the
                // brake did not lift the disc, `rearm_timeout` after it, in contact.
                Release::Touchdown { rearm_timeout } => {
                    let touchdown = airborne && input.in_contact;
                    touchdown || (input.in_contact && reached(rearm_timeout))
                }
                // The motor is off in the brake's step and the steps that start less than
                // `off_time` after it.
                Release::OffTime { off_time } => reached(off_time),
            };
            self.phase = if released {
                Phase::Stance
            } else {
                Phase::Released {
                    since,
                    airborne: airborne || !input.in_contact,
                }
            };
        }
        if self.phase != Phase::Stance {
            if self.config.hold_brake {
                // The engaged brake keeps the rates locked (a bilateral velocity constraint
                // each step: it transmits the touchdown impact to the flywheel too).
                actuation.locks.push((self.disc, self.config.flywheel));
            }
            return;
        }
        if self.stored_impulse(input) >= self.config.impulse_limit {
            actuation.locks.push((self.disc, self.config.flywheel));
            events.push(ControlEvent::Brake {
                body: self.disc,
                other: self.config.flywheel,
            });
            self.phase = Phase::Released {
                since: t,
                airborne: false,
            };
        } else {
            actuation.torques.push(TorqueCommand {
                body: self.config.flywheel,
                reaction: Some(self.disc),
                torque: self.config.torque,
            });
        }
    }
}
