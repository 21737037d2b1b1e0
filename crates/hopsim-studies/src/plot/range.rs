//! Data ranges: the finite range, padding, and a y range that a few far outliers do not
//! stretch (Tukey's fences).

use super::series::Series;

pub(super) fn finite_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    (lo <= hi).then_some((lo, hi))
}

pub(super) fn padded(range: Option<(f64, f64)>, fraction: f64) -> (f64, f64) {
    match range {
        None => (0.0, 1.0),
        Some((lo, hi)) if hi - lo <= f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) => {
            let d = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
            (lo - d, hi + d)
        }
        Some((lo, hi)) => {
            let d = fraction * (hi - lo);
            (lo - d, hi + d)
        }
    }
}

/// Tukey's fences are this many interquartile ranges beyond the quartiles.
const FENCE_IQRS: f64 = 3.0;

/// At most this fraction of the points may lie outside the fences to be drawn as outliers
/// (more are data, and the range covers them).
const MAX_OUTLIER_FRACTION: f64 = 0.05;

/// Tukey's outer fences of the finite `values`: the quartiles ∓ [`FENCE_IQRS`]
/// interquartile ranges (None without finite values; the full range if the quartiles
/// coincide).
fn tukey_fences(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut v: Vec<f64> = values.filter(|v| v.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let full = (*v.first()?, *v.last()?);
    let quantile = |q: f64| {
        let pos = q * (v.len() - 1) as f64;
        let (i, f) = (pos.floor() as usize, pos.fract());
        v[i] + f * (v[(i + 1).min(v.len() - 1)] - v[i])
    };
    let (q1, q3) = (quantile(0.25), quantile(0.75));
    let iqr = q3 - q1;
    Some(match iqr > 0.0 {
        true => (q1 - FENCE_IQRS * iqr, q3 + FENCE_IQRS * iqr),
        false => full,
    })
}

/// The range of the finite `values` that a few far outliers do not stretch. Outliers lie
/// outside Tukey's outer fences ([`FENCE_IQRS`] interquartile ranges beyond the quartiles)
/// and farther from the values inside them than those values span; if more than
/// [`MAX_OUTLIER_FRACTION`] of the values lie outside the fences, none is an outlier.
/// `None` without finite values.
pub fn robust_range(values: impl Iterator<Item = f64> + Clone) -> Option<(f64, f64)> {
    let fence = tukey_fences(values.clone())?;
    let finite = || values.clone().filter(|v| v.is_finite());
    let inside = || finite().filter(|x| *x >= fence.0 && *x <= fence.1);
    let (n, outside) = (finite().count(), finite().count() - inside().count());
    if outside as f64 > MAX_OUTLIER_FRACTION * n as f64 {
        return finite_range(finite());
    }
    // Only values at least the inner values' span away from them are outliers: a peak
    // just above the rest is data.
    let (lo, hi) = finite_range(inside())?;
    let span = hi - lo;
    finite_range(finite().filter(|x| *x >= lo - span && *x <= hi + span))
}

/// The automatic y range of `series`: the [`robust_range`] of the series that set the
/// range, widened to the points of the others that lie within their Tukey fences (the
/// robust range of all points if no series sets it).
pub(super) fn auto_y_range(series: &[Series]) -> Option<(f64, f64)> {
    let ys = |sets: bool| {
        (series.iter().filter(move |s| s.sets_range == sets))
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0.is_finite())
            .map(|p| p.1)
    };
    let Some(base) = robust_range(ys(true)) else {
        return robust_range(ys(false));
    };
    let fence = tukey_fences(ys(true)).unwrap_or(base);
    let extra = finite_range(ys(false).filter(|y| *y >= fence.0 && *y <= fence.1));
    Some(match extra {
        Some((lo, hi)) => (base.0.min(lo), base.1.max(hi)),
        None => base,
    })
}
