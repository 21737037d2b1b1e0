//! Robbit's momentum-stored-impulse control (physics.md §5.3).

use crate::{ControlEvent, ControlInput, Controller, MomentumImpulseConfig};
use hopsim_model::Model;
use hopsim_step::{Actuation, TorqueCommand};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Motor on: `+T` on the flywheel, `-T` on the disc.
    Stance,
    /// Braked at `since`; torque zero until the disc touches the ground again.
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
        let flywheel = &model.bodies[config.flywheel];
        let disc = flywheel.joint.as_ref().and_then(|j| j.parent).unwrap_or(0);
        let (i_s, i_r) = (model.bodies[disc].inertia, flywheel.inertia);
        Self {
            config,
            disc,
            reduced_inertia: i_s * i_r / (i_s + i_r),
            phase: Phase::Stance,
        }
    }

    /// The impulse `ζ = I_S I_R/(I_S + I_R) (ψ̇ - φ̇)` a brake would transfer now [5.7-5.9].
    pub fn stored_impulse(&self, input: &ControlInput<'_>) -> f64 {
        let w = &input.kinematics.angular_velocity;
        self.reduced_inertia * (w[self.config.flywheel] - w[self.disc])
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
            let touchdown = airborne && input.in_contact;
            let stalled = input.in_contact && t - since >= self.config.rearm_timeout;
            self.phase = if touchdown || stalled {
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
