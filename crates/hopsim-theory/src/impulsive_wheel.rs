//! The impulsive wheel with centred mass (docs/physics.md §5.5, thesis appendix C).
//!
//! A wheel `m, I, R` rolls at `φ̇_S` and is kicked every `T_C` seconds at its contact point
//! by an impulse of fixed magnitude `‖ζ‖` in the body-fixed direction `(−sin φ, cos φ)`.
//! The take-off angle obeys the return map
//!
//! `φ_{i+1} = φ_i − c sin 2φ_i + φ̇_S T_C`,   `c = R ‖ζ‖² / (m I g)`,
//!
//! with fixed point `φ* = ½ asin(φ̇_S T_C / c)` (exists for `c ≥ φ̇_S T_C`) and eigenvalue
//! `λ = 1 − 2 c cos 2φ* = 1 − 2 sqrt(c² − φ̇_S² T_C²)`. The fixed point is stable for
//! `|λ| < 1`, i.e. `φ̇_S T_C < c < sqrt(1 + φ̇_S² T_C²)`, which gives the stable impulse
//! interval `‖ζ‖ ∈ (sqrt(φ̇_S T_C m I g / R), sqrt(sqrt(1 + φ̇_S² T_C²) m I g / R))`.
//! The second branch `π/2 − φ*` has `λ = 1 + 2 sqrt(c² − φ̇_S² T_C²) > 1` (unstable).
//!
//! The rolling speed comes from the rolling energy: `E₀ = ½ (I + m R²) φ̇_S²`, taken
//! positive as in the map. Defaults: `m = R = I = 1`, `T_C = 1`, `E₀ = 1`, `g = 9.81`.

use crate::error::{require_finite, require_positive, Result};
use crate::STANDARD_GRAVITY;
use serde::Serialize;
use std::f64::consts::PI;

/// Parameters of the impulsive wheel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ImpulsiveWheel {
    /// Mass `m` [kg].
    pub mass: f64,
    /// Radius `R` [m].
    pub radius: f64,
    /// Inertia about the centre `I` [kg m²].
    pub inertia: f64,
    /// Time between impulses `T_C` [s].
    pub cycle_time: f64,
    /// Rolling energy `E₀ = ½ (I + m R²) φ̇_S²` [J].
    pub rolling_energy: f64,
    /// Gravitational acceleration [m/s²].
    pub gravity: f64,
}

impl Default for ImpulsiveWheel {
    /// `m = R = I = 1`, `T_C = 1`, `E₀ = 1`, `g = 9.81` (docs/physics.md §5.5).
    fn default() -> Self {
        ImpulsiveWheel {
            mass: 1.0,
            radius: 1.0,
            inertia: 1.0,
            cycle_time: 1.0,
            rolling_energy: 1.0,
            gravity: STANDARD_GRAVITY,
        }
    }
}

/// Fixed point of the take-off-angle return map for one impulse, and its stability (not
/// Robbit's [`crate::fixed_points::FixedPoint`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TakeoffAngleFixedPoint {
    /// `‖ζ‖` [N s].
    #[serde(rename = "impulse_Ns")]
    pub impulse_n_s: f64,
    /// `c = R ‖ζ‖² / (m I g)` [rad].
    pub coupling: f64,
    /// `φ* = ½ asin(φ̇_S T_C / c)` [rad], None when `c < φ̇_S T_C` (no fixed point).
    pub fixed_point_rad: Option<f64>,
    /// `λ = 1 − 2 sqrt(c² − φ̇_S² T_C²)`, None without a fixed point.
    pub eigenvalue: Option<f64>,
    /// `|λ| < 1`.
    pub stable: bool,
}

impl ImpulsiveWheel {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<()> {
        require_positive("mass", self.mass)?;
        require_positive("radius", self.radius)?;
        require_positive("inertia", self.inertia)?;
        require_positive("cycle-time", self.cycle_time)?;
        require_positive("rolling-energy", self.rolling_energy)?;
        require_positive("gravity", self.gravity)
    }

    /// Rolling speed `φ̇_S = sqrt(2 E₀ / (I + m R²))` [rad/s].
    pub fn rolling_speed(&self) -> f64 {
        (2.0 * self.rolling_energy / (self.inertia + self.mass * self.radius * self.radius)).sqrt()
    }

    /// Phase advance per cycle `φ̇_S T_C` [rad].
    pub fn drift(&self) -> f64 {
        self.rolling_speed() * self.cycle_time
    }

    /// `c = R ‖ζ‖² / (m I g)`.
    pub fn coupling(&self, impulse: f64) -> f64 {
        self.radius * impulse * impulse / (self.mass * self.inertia * self.gravity)
    }

    /// The return map `φ ↦ φ − c sin 2φ + φ̇_S T_C`.
    pub fn return_map(&self, impulse: f64, phi: f64) -> f64 {
        phi - self.coupling(impulse) * (2.0 * phi).sin() + self.drift()
    }

    /// Fixed point and eigenvalue from the closed forms.
    pub fn fixed_point(&self, impulse: f64) -> Result<TakeoffAngleFixedPoint> {
        self.validate()?;
        require_finite("impulse", impulse)?;
        let c = self.coupling(impulse);
        let w = self.drift();
        if c < w || c == 0.0 {
            return Ok(TakeoffAngleFixedPoint {
                impulse_n_s: impulse,
                coupling: c,
                fixed_point_rad: None,
                eigenvalue: None,
                stable: false,
            });
        }
        let phi = 0.5 * (w / c).asin();
        let eigenvalue = 1.0 - 2.0 * (c * c - w * w).sqrt();
        Ok(TakeoffAngleFixedPoint {
            impulse_n_s: impulse,
            coupling: c,
            fixed_point_rad: Some(phi),
            eigenvalue: Some(eigenvalue),
            stable: eigenvalue.abs() < 1.0,
        })
    }

    /// The open interval of impulses `‖ζ‖` with a stable fixed point:
    /// `(sqrt(φ̇_S T_C m I g / R), sqrt(sqrt(1 + (φ̇_S T_C)²) m I g / R))`.
    pub fn stable_impulse_interval(&self) -> (f64, f64) {
        let w = self.drift();
        let scale = self.mass * self.inertia * self.gravity / self.radius;
        ((w * scale).sqrt(), ((1.0 + w * w).sqrt() * scale).sqrt())
    }

    /// `φ_0, φ_1, …, φ_n` (n + 1 values) from `phi0`.
    pub fn iterate(&self, impulse: f64, phi0: f64, n: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(n + 1);
        let mut phi = phi0;
        out.push(phi);
        for _ in 0..n {
            phi = self.return_map(impulse, phi);
            out.push(phi);
        }
        out
    }

    /// Bifurcation diagram: for each impulse, iterate `transient` times from `phi0`, then
    /// keep `keep` iterates wrapped to `[−π/2, π/2)` (the map commutes with `φ ↦ φ + π`).
    pub fn bifurcation(
        &self,
        impulses: &[f64],
        phi0: f64,
        transient: usize,
        keep: usize,
    ) -> Vec<(f64, Vec<f64>)> {
        impulses
            .iter()
            .map(|&impulse| {
                let mut phi = phi0;
                for _ in 0..transient {
                    phi = wrap_half_turn(self.return_map(impulse, phi));
                }
                let kept = (0..keep)
                    .map(|_| {
                        phi = wrap_half_turn(self.return_map(impulse, phi));
                        phi
                    })
                    .collect();
                (impulse, kept)
            })
            .collect()
    }
}

/// Wraps an angle to `[−π/2, π/2)`.
pub fn wrap_half_turn(phi: f64) -> f64 {
    (phi + 0.5 * PI).rem_euclid(PI) - 0.5 * PI
}
