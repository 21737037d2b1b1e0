//! Choosing and counting over a fixed-point grid: the most stable and the fastest stable
//! gait, the reasons without a fixed point, and the colour ranges and markers of the maps.

use super::summary::PointSummary;
use std::collections::BTreeMap;

/// `max |λ|` of a point known to have a fixed point.
fn max_abs_eigenvalue(q: &PointSummary) -> f64 {
    q.details
        .as_ref()
        .map_or(f64::NAN, |f| f.max_abs_eigenvalue)
}

/// Speed of a point known to have a fixed point [m/s].
fn speed(q: &PointSummary) -> f64 {
    q.details.as_ref().map_or(f64::NAN, |f| f.speed_mps)
}

/// Indices of the stable points.
fn stable(points: &[PointSummary]) -> impl Iterator<Item = usize> + Clone + '_ {
    (0..points.len()).filter(|&i| points[i].stable && points[i].details.is_some())
}

/// The stable point with the smallest `max |λ|` among those the no-slip, closed-contact
/// model describes consistently (no warnings), else among all stable points.
pub fn most_stable(points: &[PointSummary]) -> Option<usize> {
    let by_radius = |&a: &usize, &b: &usize| {
        max_abs_eigenvalue(&points[a]).total_cmp(&max_abs_eigenvalue(&points[b]))
    };
    let all = stable(points);
    all.clone()
        .filter(|&i| points[i].consistent())
        .min_by(by_radius)
        .or_else(|| all.min_by(by_radius))
}

/// The stable point with the largest speed.
pub fn fastest_stable(points: &[PointSummary]) -> Option<usize> {
    stable(points).max_by(|&a, &b| speed(&points[a]).total_cmp(&speed(&points[b])))
}

/// How many points have no fixed point, per kind of reason (`NoFixedPoint::kind`).
pub fn reason_counts(points: &[PointSummary]) -> BTreeMap<&'static str, usize> {
    let mut counts = BTreeMap::new();
    for kind in points.iter().filter_map(|q| q.reason_kind) {
        *counts.entry(kind).or_default() += 1;
    }
    counts
}

/// How many fixed points carry model warnings.
pub fn with_warnings(points: &[PointSummary]) -> usize {
    points
        .iter()
        .filter(|q| q.details.as_ref().is_some_and(|f| !f.warnings.is_empty()))
        .count()
}

/// Up to `count` of `items`, evenly spaced from the first to the last (all when there
/// are no more than `count`).
pub fn evenly_spaced<T: Copy>(items: &[T], count: usize) -> Vec<T> {
    if items.len() <= count || count < 2 {
        return items.iter().take(count).copied().collect();
    }
    (0..count)
        .map(|i| items[i * (items.len() - 1) / (count - 1)])
        .collect()
}

/// The colour range of a heatmap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColourRange {
    pub min: f64,
    pub max: f64,
    /// Whether a long upper tail was cut ([`colour_range`]).
    pub capped: bool,
}

/// Colour range of a heatmap: minimum to maximum of the finite values, except that with
/// `cap` a long upper tail (the range more than twice the range up to the 95th percentile,
/// e.g. the large torques next to `φ_TO = 0`) is cut at the 95th percentile so that the
/// rest of the map keeps its contrast. `0 … 1` without finite values; a single value `v`
/// gets `v ± 0.5`.
pub fn colour_range(values: &[Option<f64>], cap: bool) -> ColourRange {
    let mut finite: Vec<f64> = values
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    let range = |min, max, capped| ColourRange { min, max, capped };
    if finite.is_empty() {
        return range(0.0, 1.0, false);
    }
    finite.sort_by(f64::total_cmp);
    let (lo, hi) = (finite[0], finite[finite.len() - 1]);
    let p95 = finite[(0.95 * (finite.len() - 1) as f64).round() as usize];
    if cap && hi - lo > 2.0 * (p95 - lo) && p95 > lo {
        range(lo, p95, true)
    } else if hi > lo {
        range(lo, hi, false)
    } else {
        range(lo - 0.5, hi + 0.5, false)
    }
}

/// Where the maps mark the points `marked` picks (`(φ_TO, E_TO)`, e.g. the unstable fixed
/// points) on a grid of `n_angles` take-off angles (row-major, angles inner): on dense grids
/// only every `k`-th row and column (`k = ⌈max(n, m) / 40⌉`), so that the markers hatch the
/// region without hiding it.
pub fn grid_markers(
    points: &[PointSummary],
    n_angles: usize,
    marked: impl Fn(&PointSummary) -> bool,
) -> Vec<(f64, f64)> {
    let n_angles = n_angles.max(1);
    let n_energies = points.len() / n_angles;
    let k = n_angles.max(n_energies).div_ceil(40).max(1);
    points
        .iter()
        .enumerate()
        .filter(|(i, _)| (i % n_angles).is_multiple_of(k) && (i / n_angles).is_multiple_of(k))
        .filter(|(_, q)| marked(q))
        .map(|(_, q)| (q.takeoff_angle_rad, q.takeoff_energy))
        .collect()
}

/// An unstable fixed point (`max |λ| ≥ 1`).
pub fn unstable(q: &PointSummary) -> bool {
    q.fixed_point && !q.stable
}

#[cfg(test)]
mod tests {
    use super::super::summary::FixedPointSummary;
    use super::*;

    /// A grid point with a fixed point of `max |λ|` `radius` and `speed`, with or without a
    /// model warning.
    fn found(radius: f64, speed: f64, warned: bool) -> PointSummary {
        PointSummary {
            fixed_point: true,
            stable: radius < 1.0,
            details: Some(FixedPointSummary {
                max_abs_eigenvalue: radius,
                speed_mps: speed,
                warnings: if warned {
                    vec!["leaves the friction cone".into()]
                } else {
                    Vec::new()
                },
                ..FixedPointSummary::default()
            }),
            ..PointSummary::default()
        }
    }

    fn missing(kind: &'static str) -> PointSummary {
        PointSummary {
            reason: Some(format!("{kind}: …")),
            reason_kind: Some(kind),
            ..PointSummary::default()
        }
    }

    #[test]
    fn most_stable_prefers_warning_free_points() {
        let points = [
            found(0.2, 0.3, true), // smallest |λ| but warned
            found(0.5, 0.1, false),
            found(0.4, 0.2, false), // the answer
            found(1.5, 0.9, false), // unstable
            missing("solver-failed"),
        ];
        assert_eq!(most_stable(&points), Some(2));
        // Without warning-free stable points, the smallest |λ| of all stable ones.
        let warned = [
            found(0.6, 0.3, true),
            found(0.3, 0.1, true),
            found(0.1, 0.1, false),
        ];
        assert_eq!(most_stable(&warned[..2]), Some(1));
        assert_eq!(most_stable(&warned), Some(2));
        assert_eq!(
            most_stable(&[found(1.2, 0.3, false), missing("numerical")]),
            None
        );
    }

    #[test]
    fn fastest_stable_ignores_unstable_points() {
        let points = [
            found(0.5, 0.3, true),
            found(1.01, 0.9, false),
            found(0.9, 0.4, false),
            missing("no-lift-off"),
        ];
        assert_eq!(fastest_stable(&points), Some(2));
        assert_eq!(fastest_stable(&points[..2]), Some(0));
        assert_eq!(fastest_stable(&points[1..2]), None);
    }

    #[test]
    fn reasons_and_warnings_are_counted_per_kind() {
        let points = [
            missing("solver-failed"),
            found(0.5, 0.3, true),
            missing("no-lift-off"),
            missing("solver-failed"),
            found(1.5, 0.3, true),
            found(0.5, 0.3, false),
        ];
        let counts = reason_counts(&points);
        assert_eq!(
            counts.into_iter().collect::<Vec<_>>(),
            [("no-lift-off", 1), ("solver-failed", 2)]
        );
        assert_eq!(with_warnings(&points), 2);
        assert!(reason_counts(&points[1..2]).is_empty());
    }

    #[test]
    fn colour_range_caps_only_a_long_upper_tail() {
        // 1 … 20 and one outlier: the 95th percentile (20) is the top of the scale.
        let mut tail: Vec<Option<f64>> = (1..=20).map(|v| Some(v as f64)).collect();
        tail.push(Some(1000.0));
        tail.push(None);
        tail.push(Some(f64::NAN));
        let capped = colour_range(&tail, true);
        assert_eq!(
            capped,
            ColourRange {
                min: 1.0,
                max: 20.0,
                capped: true
            }
        );
        assert_eq!(
            colour_range(&tail, false),
            ColourRange {
                min: 1.0,
                max: 1000.0,
                capped: false
            }
        );
        // An even spread keeps its full range.
        let even: Vec<Option<f64>> = (0..=20).map(|v| Some(v as f64)).collect();
        assert_eq!(
            colour_range(&even, true),
            ColourRange {
                min: 0.0,
                max: 20.0,
                capped: false
            }
        );
        // Degenerate inputs.
        assert_eq!(
            colour_range(&[Some(2.0)], true),
            ColourRange {
                min: 1.5,
                max: 2.5,
                capped: false
            }
        );
        assert_eq!(
            colour_range(&[None], true),
            ColourRange {
                min: 0.0,
                max: 1.0,
                capped: false
            }
        );
    }

    #[test]
    fn markers_thin_out_on_dense_grids() {
        let grid = |n: usize, m: usize| -> Vec<PointSummary> {
            (0..n * m)
                .map(|i| PointSummary {
                    takeoff_angle_rad: (i % n) as f64,
                    takeoff_energy: (i / n) as f64,
                    ..found(2.0, 0.1, false)
                })
                .collect()
        };
        // Up to 40 × 40 every unstable point is marked.
        assert_eq!(grid_markers(&grid(40, 3), 40, unstable).len(), 120);
        // 81 × 2: k = 3, every third angle of the first energy row.
        let marks = grid_markers(&grid(81, 2), 81, unstable);
        assert_eq!(marks.len(), 27);
        assert!(marks
            .iter()
            .all(|&(a, e)| (a as usize).is_multiple_of(3) && e == 0.0));
        // Stable points and points without a fixed point are never marked.
        let mixed = [
            found(0.5, 0.1, false),
            missing("numerical"),
            found(1.5, 0.1, false),
        ];
        assert_eq!(grid_markers(&mixed, 3, unstable).len(), 1);
    }

    #[test]
    fn evenly_spaced_keeps_both_ends() {
        let items: Vec<usize> = (0..20).collect();
        assert_eq!(evenly_spaced(&items, 8), [0, 2, 5, 8, 10, 13, 16, 19]);
        assert_eq!(evenly_spaced(&items[..5], 8), [0, 1, 2, 3, 4]);
    }
}
