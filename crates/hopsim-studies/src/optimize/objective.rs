//! Objectives: a function of the parameters' values, or a run-summary field of a scene
//! whose keys the parameters override, with constraints on other fields. Each evaluates a
//! generation in parallel on all cores.

use super::search::Outcome;
use crate::run_summary::run_scene;
use crate::sweep::{sweep, RunDone, SweepJob};
use hopsim_scene::{Override, Scene};
use hopsim_sim::StopFlag;
use rayon::prelude::*;
use serde_json::Value;
use std::sync::atomic::AtomicBool;

/// What a search minimises or maximises.
pub trait Objective: Sync {
    /// The outcomes of `points` (each the parameters' values, in parameter order), in
    /// order; `done` is called after each point, from any thread.
    fn evaluate(&self, points: &[Vec<f64>], done: RunDone<'_>) -> Vec<Outcome>;
}

/// A function of the parameters' values, evaluated in parallel (rayon).
pub struct FunctionObjective<F>(pub F);

impl<F: Fn(&[f64]) -> Outcome + Sync> Objective for FunctionObjective<F> {
    fn evaluate(&self, points: &[Vec<f64>], done: RunDone<'_>) -> Vec<Outcome> {
        points
            .par_iter()
            .map(|p| {
                let outcome = (self.0)(p);
                done();
                outcome
            })
            .collect()
    }
}

/// A bound on a run-summary field: a run whose field lies outside `[lower, upper]` is
/// rejected.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Constraint {
    /// A dotted path into the run summary (`hopsim run --summary`), e.g. `hops`.
    pub field: String,
    pub lower: Option<f64>,
    pub upper: Option<f64>,
}

impl std::str::FromStr for Constraint {
    type Err = String;

    /// `FIELD=LO:HI`, either bound may be left out (`hops=10:`, `max_penetration_m=:1e-3`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let expected = || format!("'{s}': expected FIELD=LO:HI (either bound may be empty)");
        let (field, spec) = s.split_once('=').ok_or_else(expected)?;
        let (lo, hi) = spec.split_once(':').ok_or_else(expected)?;
        let bound = |t: &str| -> Result<Option<f64>, String> {
            let t = t.trim();
            if t.is_empty() {
                return Ok(None);
            }
            t.parse::<f64>()
                .ok()
                .filter(|v| !v.is_nan())
                .map(Some)
                .ok_or_else(|| format!("'{s}': '{t}' is not a number"))
        };
        let c = Constraint {
            field: field.trim().to_string(),
            lower: bound(lo)?,
            upper: bound(hi)?,
        };
        if c.field.is_empty() || (c.lower.is_none() && c.upper.is_none()) {
            return Err(expected());
        }
        Ok(c)
    }
}

impl std::fmt::Display for Constraint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let b = |v: Option<f64>| v.map_or(String::new(), hopsim_io::number);
        write!(f, "{}={}:{}", self.field, b(self.lower), b(self.upper))
    }
}

/// The number at the dotted `path` of a JSON value (object keys; array indices as numbers).
pub fn json_number(value: &Value, path: &str) -> Result<f64, String> {
    let mut v = value;
    for segment in path.split('.') {
        v = match v {
            Value::Object(map) => map.get(segment),
            Value::Array(items) => segment.parse::<usize>().ok().and_then(|i| items.get(i)),
            _ => None,
        }
        .ok_or_else(|| format!("the run summary has no field '{path}'"))?;
    }
    match v {
        Value::Number(n) => n
            .as_f64()
            .ok_or_else(|| format!("'{path}' is not a number")),
        Value::Bool(b) => Ok(f64::from(u8::from(*b))),
        Value::Null => Err(format!("'{path}' is null in this run")),
        _ => Err(format!("'{path}' is not a number")),
    }
}

/// A scene's run-summary field (the JSON of `hopsim run --summary`) as the objective, the
/// parameters scene keys set as overrides on top of `base`; a run that fails, or whose
/// summary breaks a constraint, is rejected with the reason.
pub struct SceneObjective<'a> {
    pub scene: &'a Scene,
    pub base: Vec<Override>,
    pub keys: Vec<String>,
    pub field: String,
    pub constraints: Vec<Constraint>,
    /// Once set, every run stops at its next step (and is rejected).
    pub stop: Option<&'a AtomicBool>,
}

impl SceneObjective<'_> {
    /// The objective of one run's summary (serialised to JSON).
    fn outcome(&self, summary: &Value) -> Outcome {
        for c in &self.constraints {
            let v = json_number(summary, &c.field)?;
            if c.lower.is_some_and(|lo| v < lo) || c.upper.is_some_and(|hi| v > hi) {
                return Err(format!(
                    "constraint {c} broken: {} = {}",
                    c.field,
                    hopsim_io::number(v)
                ));
            }
        }
        json_number(summary, &self.field)
    }

    /// The overrides of the point `values`.
    pub fn job(&self, values: &[f64]) -> SweepJob {
        SweepJob {
            label: "search".into(),
            values: values.to_vec(),
            overrides: (self.keys.iter().zip(values))
                .map(|(k, v)| Override::from_flag("--param", k.clone(), format!("{v:?}")))
                .collect(),
        }
    }
}

impl Objective for SceneObjective<'_> {
    /// The runs go through the sweep's parallel runner (`sweep::sweep`).
    fn evaluate(&self, points: &[Vec<f64>], done: RunDone<'_>) -> Vec<Outcome> {
        let jobs: Vec<SweepJob> = points.iter().map(|p| self.job(p)).collect();
        let scene = self.scene;
        let runs = sweep(
            &scene.path,
            &scene.text,
            &self.base,
            &jobs,
            |s| run_scene(s, &mut self.stop.map(StopFlag)),
            done,
        );
        runs.into_iter()
            .map(|p| {
                let report = p.result?;
                let json = hopsim_io::to_json_value(&report).map_err(|e| e.to_string())?;
                self.outcome(&json)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constraints_parse_with_open_ends() {
        let c: Constraint = "hops=10:".parse().unwrap();
        assert_eq!((c.lower, c.upper), (Some(10.0), None));
        let c: Constraint = "gait.period=:1".parse().unwrap();
        assert_eq!(
            (c.field.as_str(), c.lower, c.upper),
            ("gait.period", None, Some(1.0))
        );
        assert_eq!(c.to_string(), "gait.period=:1");
        assert!("hops=:".parse::<Constraint>().is_err());
        assert!("hops".parse::<Constraint>().is_err());
    }

    #[test]
    fn json_paths_reach_nested_numbers() {
        let v: Value =
            serde_json::from_str(r#"{"a": {"b": [1.5, {"c": 2}]}, "n": null, "t": true}"#).unwrap();
        assert_eq!(json_number(&v, "a.b.0"), Ok(1.5));
        assert_eq!(json_number(&v, "a.b.1.c"), Ok(2.0));
        assert_eq!(json_number(&v, "t"), Ok(1.0));
        assert!(json_number(&v, "n").unwrap_err().contains("null"));
        assert!(json_number(&v, "a.x")
            .unwrap_err()
            .contains("no field 'a.x'"));
        assert!(json_number(&v, "a").unwrap_err().contains("not a number"));
    }
}
