//! The capsule's closed forms: the closest point of a segment, and the signed distance of
//! a point from a capsule (docs/physics.md §2, §7).

use crate::Vec2;

/// The point of the segment `from`–`to` closest to `p` (the end `from` when the segment
/// has no length).
#[inline]
pub(crate) fn closest_on_segment(from: Vec2, to: Vec2, p: Vec2) -> Vec2 {
    let e = to - from;
    let length_sq = e.norm_squared();
    if length_sq == 0.0 {
        return from;
    }
    let t = ((p - from).dot(&e) / length_sq).clamp(0.0, 1.0);
    from + t * e
}

/// Signed distance of `p` from the capsule of `radius` about `from`–`to` (`< 0` inside),
/// its closest boundary point and the unit outward normal there; `None` when `p` lies on
/// the segment itself, where every direction is as near.
#[inline]
pub(crate) fn capsule_signed_distance(
    from: Vec2,
    to: Vec2,
    radius: f64,
    p: Vec2,
) -> Option<(f64, Vec2, Vec2)> {
    let axis = closest_on_segment(from, to, p);
    let d = p - axis;
    let length = d.norm();
    let outward = d.try_normalize(1e-12 * (1.0 + axis.norm()))?;
    Some((length - radius, axis + radius * outward, outward))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point on the segment has no outward direction, wherever the segment lies; one
    /// just off it, beyond round-off of its coordinates, has one.
    #[test]
    fn a_point_on_the_segment_has_no_normal() {
        for (from, to) in [
            (Vec2::new(-1.0, 0.0), Vec2::new(1.0, 0.0)),
            (Vec2::new(3.0, 4.0), Vec2::new(7.0, 4.0)),
        ] {
            let middle = 0.5 * (from + to);
            assert_eq!(capsule_signed_distance(from, to, 0.1, middle), None);
            // Within the round-off of the middle's coordinates (1e-12 of 1 + |middle|).
            let scale = 1.0 + middle.norm();
            let near = middle + Vec2::new(0.0, 0.4e-12 * scale);
            assert_eq!(capsule_signed_distance(from, to, 0.1, near), None);
            let off = middle + Vec2::new(0.0, 1e-9);
            let (gap, point, normal) = capsule_signed_distance(from, to, 0.1, off).unwrap();
            assert!((gap - (1e-9 - 0.1)).abs() < 1e-15);
            assert_eq!(normal, Vec2::new(0.0, 1.0));
            assert!((point - (middle + Vec2::new(0.0, 0.1))).norm() < 1e-15);
        }
    }
}
