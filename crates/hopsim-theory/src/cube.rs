//! The impulse-actuated cube, Robbit's baseline (docs/physics.md §5.3 [5.21]).
//!
//! A cube of face diagonal `l` hops by one angular impulse per step: it lands on its face
//! with restitution `ε` and takes off at `α = π/4`. At forward speed `u_x` it needs the
//! angular impulse per distance
//!
//! `ζ/x = g (m l² + I_S)(1 − ε) / (2 l u_x sin α)`   [N m s/m].
//!
//! For Robbit, `m` is the whole robot's mass `m_S + m_R` (the flywheel pivots at the centre
//! of mass: it adds its mass but not its inertia about the landing edge), `I_S` the disc's
//! inertia and `l = 2(R − a)` for a disc of radius `R` whose centre is `a` from the centre
//! of mass (docs/physics.md §5.3, "hopsim: the cube baseline").

use serde::Serialize;

/// The take-off angle of the cube, `α = π/4` [5.21].
pub const TAKEOFF_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// A cube to compare a hopping robot with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cube {
    /// Mass `m` [kg].
    pub mass: f64,
    /// Inertia about the centre of mass `I_S` [kg m²].
    pub inertia: f64,
    /// Face diagonal `l` [m].
    pub diagonal: f64,
    /// Gravitational acceleration `g` [m/s²].
    pub gravity: f64,
}

impl Cube {
    /// The cube equivalent to a disc of radius `R` whose centre is `a` (`eccentricity`)
    /// from the centre of mass: `l = 2(R − a)`.
    pub fn of_disc(mass: f64, inertia: f64, radius: f64, eccentricity: f64, gravity: f64) -> Self {
        Cube {
            mass,
            inertia,
            diagonal: 2.0 * (radius - eccentricity),
            gravity,
        }
    }

    /// The angular impulse per forward distance `ζ/x` [N m s/m] at forward speed `speed`
    /// (`u_x`, m/s) and face restitution `restitution` (`ε`), [5.21].
    pub fn impulse_per_distance(&self, speed: f64, restitution: f64) -> f64 {
        let (m, l, i_s, g) = (self.mass, self.diagonal, self.inertia, self.gravity);
        g * (m * l * l + i_s) * (1.0 - restitution) / (2.0 * l * speed * TAKEOFF_ANGLE.sin())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [5.21] evaluated by hand for `m = 2 kg`, `I_S = 0.01 kg m²`, `R = 0.25 m`,
    /// `a = 0.05 m` (so `l = 0.4 m`), `g = 9.81 m/s²`, `u_x = 0.5 m/s`, `ε = 0.3`:
    /// `m l² + I_S = 0.33`, `g · 0.33 · 0.7 = 2.26611`, `2 l u_x sin α = 0.4 · √2/2 =
    /// 0.2828427…`, so `ζ/x = 2.26611 / 0.2828427… = 8.0119…` N m s/m.
    #[test]
    fn impulse_per_distance_follows_the_formula() {
        let cube = Cube::of_disc(2.0, 0.01, 0.25, 0.05, 9.81);
        assert!((cube.diagonal - 0.4).abs() < 1e-15);
        let expected = 2.26611 / (0.2 * std::f64::consts::SQRT_2);
        assert!((expected - 8.011_909).abs() < 1e-6, "{expected}");
        let value = cube.impulse_per_distance(0.5, 0.3);
        assert!(
            (value - expected).abs() < 1e-12 * expected,
            "{value} vs {expected}"
        );
        // Inversely proportional to the speed, proportional to 1 − ε; none for ε = 1.
        let slower = cube.impulse_per_distance(0.25, 0.3);
        assert!((slower - 2.0 * value).abs() < 1e-12 * value);
        assert_eq!(cube.impulse_per_distance(0.5, 1.0), 0.0);
    }
}
