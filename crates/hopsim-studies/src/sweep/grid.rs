//! Parameter sweeps: a scene run over the Cartesian product of grid axes, in parallel,
//! with results in a deterministic order (docs/physics.md §5.3, the speed-versus-impulse map).

use hopsim_scene::{Override, Scene};
use hopsim_sim::{RunError, Summary};
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// Called once per finished run of a sweep, from any thread.
pub type RunDone<'a> = &'a (dyn Fn() + Sync);

/// A [`RunDone`] that ignores the reports.
pub const NO_PROGRESS: RunDone<'static> = &|| {};

/// One grid axis: a scene key and the values it takes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GridAxis {
    /// Scene key path, e.g. `controller.torque`.
    pub key: String,
    /// The values, in order.
    pub values: Vec<f64>,
}

/// The most values of one grid axis.
pub const MAX_AXIS_POINTS: usize = 100_000;

impl std::str::FromStr for GridAxis {
    type Err = String;

    /// `key=start:stop:count` (inclusive, evenly spaced) or `key=v1,v2,…`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (key, spec) = s.split_once('=').ok_or_else(|| {
            format!("grid axis '{s}': expected KEY=START:STOP:COUNT or KEY=V1,V2,...")
        })?;
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("grid axis '{s}': '{t}' is not a finite number"))
        };
        let values = if let [start, stop, count] = spec.split(':').collect::<Vec<_>>()[..] {
            let (start, stop) = (number(start)?, number(stop)?);
            let count: usize = count
                .trim()
                .parse()
                .ok()
                .filter(|&n| (1..=MAX_AXIS_POINTS).contains(&n))
                .ok_or_else(|| {
                    format!(
                        "grid axis '{s}': count '{count}' must be an integer from 1 to {MAX_AXIS_POINTS}"
                    )
                })?;
            (0..count)
                .map(|i| match count {
                    1 => start,
                    _ => start + (stop - start) * i as f64 / (count - 1) as f64,
                })
                .collect()
        } else {
            spec.split(',').map(number).collect::<Result<Vec<_>, _>>()?
        };
        Ok(Self {
            key: key.trim().to_string(),
            values,
        })
    }
}

/// One run of a sweep: a label, the grid values (empty for a baseline) and the overrides
/// that make it.
#[derive(Clone, Debug)]
pub struct SweepJob {
    /// `"grid"` for grid points, the baseline's name otherwise.
    pub label: String,
    /// The grid values, in axis order.
    pub values: Vec<f64>,
    /// Overrides applied on top of the sweep's base overrides.
    pub overrides: Vec<Override>,
}

/// A job and what its run gave (by default the run loop's [`Summary`]).
#[derive(Clone, Debug)]
pub struct SweepPoint<R = Summary> {
    pub job: SweepJob,
    /// What the run gave, or the error that stopped the run (or rejected its scene).
    pub result: Result<R, String>,
}

/// Every grid point in row-major order (the last axis varies fastest).
pub fn grid_points(axes: &[GridAxis]) -> Vec<Vec<f64>> {
    axes.iter().fold(vec![Vec::new()], |points, axis| {
        points
            .iter()
            .flat_map(|p| {
                axis.values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(*v);
                    q
                })
            })
            .collect()
    })
}

/// The jobs of a grid: one per point, labelled `"grid"`.
pub fn grid_jobs(axes: &[GridAxis]) -> Vec<SweepJob> {
    grid_points(axes)
        .into_iter()
        .map(|values| SweepJob {
            label: "grid".into(),
            overrides: axes
                .iter()
                .zip(&values)
                .map(|(axis, v)| Override::from_flag("--grid", axis.key.clone(), format!("{v:?}")))
                .collect(),
            values,
        })
        .collect()
}

/// Parses the scene `text` (read from `path`) with `base` overrides and then each job's,
/// and runs it with `run` (e.g. `|scene| hopsim_sim::run(scene, &mut ())`), in parallel on
/// all cores; results keep the order of `jobs`. A run that fails, or a job whose scene is
/// invalid, is a point with its error, not a failed sweep. `progress` is called after each
/// run.
pub fn sweep<R: Send>(
    path: &Path,
    text: &str,
    base: &[Override],
    jobs: &[SweepJob],
    run: impl Fn(&Scene) -> Result<R, RunError> + Sync,
    progress: RunDone<'_>,
) -> Vec<SweepPoint<R>> {
    jobs.par_iter()
        .map(|job| {
            let mut overrides = base.to_vec();
            overrides.extend_from_slice(&job.overrides);
            // A panic outside the steps (which `Simulation` catches itself) is a failed
            // run too, never a lost sweep.
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                hopsim_scene::parse(text, path, &overrides)
                    .map_err(|e| e.to_string())
                    .and_then(|scene| run(&scene).map_err(|e| e.to_string()))
            }))
            .unwrap_or_else(|payload| {
                Err(format!(
                    "internal error: {}. This is a bug in hopsim; please report it",
                    hopsim_sim::panic_message(payload.as_ref())
                ))
            });
            progress();
            SweepPoint {
                job: job.clone(),
                result,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_parse_ranges_and_lists() {
        let a: GridAxis = "controller.torque=0.1:0.3:3".parse().unwrap();
        assert_eq!(a.key, "controller.torque");
        assert_eq!(a.values.len(), 3);
        assert!((a.values[1] - 0.2).abs() < 1e-15 && (a.values[2] - 0.3).abs() < 1e-15);
        let b: GridAxis = "x=1,2.5".parse().unwrap();
        assert_eq!(b.values, vec![1.0, 2.5]);
        assert!("x=1:2:0".parse::<GridAxis>().is_err());
        assert!("x=a,b".parse::<GridAxis>().is_err());
        assert!("x".parse::<GridAxis>().is_err());
    }

    #[test]
    fn grid_is_row_major() {
        let axes = [
            GridAxis {
                key: "a".into(),
                values: vec![1.0, 2.0],
            },
            GridAxis {
                key: "b".into(),
                values: vec![10.0, 20.0, 30.0],
            },
        ];
        let points = grid_points(&axes);
        assert_eq!(points.len(), 6);
        assert_eq!(points[0], vec![1.0, 10.0]);
        assert_eq!(points[1], vec![1.0, 20.0]);
        assert_eq!(points[5], vec![2.0, 30.0]);
    }
}
