//! Force elements: linear springs between points on two bodies (docs/physics.md §5.4).

use crate::Vec2;

/// A linear spring-damper between a point on body `a` and a point on body `b`.
///
/// Force along the line between the points: `-(k (L - L0) + c L̇)`, tension positive
/// when stretched. Energy `½ k (L - L0)²`.
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    /// Name used in records and viewers.
    pub name: String,
    /// Body carrying the first end.
    pub body_a: usize,
    /// First end in body `a`'s frame, relative to its centre of mass, m.
    pub point_a: Vec2,
    /// Body carrying the second end.
    pub body_b: usize,
    /// Second end in body `b`'s frame, m.
    pub point_b: Vec2,
    /// Stiffness `k`, N/m (≥ 0).
    pub stiffness: f64,
    /// Rest length `L0`, m (≥ 0).
    pub rest_length: f64,
    /// Viscous damping `c`, N s/m (≥ 0).
    pub damping: f64,
    /// An extension spring (cable) pulls only when longer than its rest length.
    pub tension_only: bool,
}

impl Spring {
    /// Stored energy at length `length`.
    pub fn energy(&self, length: f64) -> f64 {
        let stretch = length - self.rest_length;
        if self.tension_only && stretch < 0.0 {
            0.0
        } else {
            0.5 * self.stiffness * stretch * stretch
        }
    }

    /// Elastic and damping tension at `length`, `rate = L̇` (N, positive pulls the ends together).
    pub fn tension(&self, length: f64, rate: f64) -> (f64, f64) {
        let stretch = length - self.rest_length;
        if self.tension_only && stretch < 0.0 {
            (0.0, 0.0)
        } else {
            (self.stiffness * stretch, self.damping * rate)
        }
    }
}

/// Direction from `b` to `a` and the distance, guarding the zero-length case.
pub(crate) fn separation(a: Vec2, b: Vec2) -> (Vec2, f64) {
    let d = a - b;
    let length = d.norm();
    if length > 0.0 {
        (d / length, length)
    } else {
        (Vec2::zeros(), 0.0)
    }
}
