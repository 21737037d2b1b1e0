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
