//! What a search looks for: parameters within bounds, the direction, the CMA-ES settings.

use serde::{Deserialize, Serialize};

/// One searched parameter: a scene key (or a function's argument) within bounds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// A scene key (`controller.cane_delay`) or any name.
    pub key: String,
    /// Its bounds, `lower < upper`.
    pub lower: f64,
    pub upper: f64,
    /// Rounded to the nearest whole number before it is evaluated.
    pub integer: bool,
}

impl std::str::FromStr for Parameter {
    type Err = String;

    /// `KEY=LO:HI` (continuous) or `KEY=LO:HI:int` (whole numbers).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let expected = || format!("'{s}': expected KEY=LO:HI or KEY=LO:HI:int");
        let (key, spec) = s.split_once('=').ok_or_else(expected)?;
        let parts: Vec<&str> = spec.split(':').map(str::trim).collect();
        let integer = match parts.get(2) {
            None => false,
            Some(&"int") if parts.len() == 3 => true,
            _ => return Err(expected()),
        };
        let number = |t: &str| {
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{s}': '{t}' is not a finite number"))
        };
        let (lower, upper) = match parts[..] {
            [lo, hi, ..] => (number(lo)?, number(hi)?),
            _ => return Err(expected()),
        };
        let key = key.trim();
        if key.is_empty() {
            return Err(expected());
        }
        let p = Parameter {
            key: key.to_string(),
            lower,
            upper,
            integer,
        };
        p.check()?;
        Ok(p)
    }
}

impl Parameter {
    /// Bounds in order (an integer parameter's span holds a whole number).
    pub fn check(&self) -> Result<(), String> {
        // NaN bounds fail too (parsed bounds are finite; a Python caller's may not be).
        if self.lower.partial_cmp(&self.upper) != Some(std::cmp::Ordering::Less) {
            return Err(format!(
                "{}: the lower bound {} must be below the upper bound {}",
                self.key, self.lower, self.upper
            ));
        }
        if self.integer && self.lower.ceil() > self.upper.floor() {
            return Err(format!(
                "{}: no whole number lies in [{}, {}]",
                self.key, self.lower, self.upper
            ));
        }
        Ok(())
    }

    /// The value of the normalised coordinate `y`: folded into `[0, 1]` by mirroring at
    /// the bounds (`y = 1.2` is `0.8`, `y = −0.3` is `0.3`), so that every point CMA-ES
    /// samples is inside them, then scaled to `[lower, upper]`; integers rounded (and
    /// kept inside the bounds).
    pub fn value(&self, y: f64) -> f64 {
        let folded = y.rem_euclid(2.0);
        let u = if folded > 1.0 { 2.0 - folded } else { folded };
        let v = self.lower + u * (self.upper - self.lower);
        if self.integer {
            v.round().clamp(self.lower.ceil(), self.upper.floor())
        } else {
            v.clamp(self.lower, self.upper)
        }
    }

    /// The normalised coordinate of `value` (the inverse of [`Parameter::value`] inside
    /// the bounds).
    pub fn normalised(&self, value: f64) -> f64 {
        (value - self.lower) / (self.upper - self.lower)
    }
}

/// Whether the objective is to be made small or large.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    Minimize,
    Maximize,
}

/// A search: its parameters, its direction and the CMA-ES settings. Two searches with
/// equal problems (and objectives) give the same evaluations, bit for bit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Problem {
    pub parameters: Vec<Parameter>,
    pub direction: Direction,
    /// Where the search starts, in the parameters' units (`None`: the centre of the bounds).
    pub start: Option<Vec<f64>>,
    /// The initial step size `σ0` as a fraction of each parameter's span.
    pub sigma: f64,
    /// Points per generation `λ` (`None`: CMA-ES' default `4 + ⌊3 ln n⌋`).
    pub population: Option<usize>,
    /// The seed of CMA-ES' random numbers.
    pub seed: u64,
    /// The most generations.
    pub max_generations: usize,
    /// What the objective is, for the record (e.g. the summary field and the scene): a
    /// checkpoint resumes only the search it was written by. Its first word names the
    /// quantity (the figure's axis).
    pub objective: String,
}

impl Problem {
    /// Whether `other` is this search, perhaps planned for another number of generations
    /// (a checkpoint of it can be resumed, and extended, with
    /// [`Search::with_max_generations`](super::search::Search::with_max_generations)).
    pub fn same_search(&self, other: &Problem) -> bool {
        let planned = Problem {
            max_generations: self.max_generations,
            ..other.clone()
        };
        *self == planned
    }
}

/// Default of [`Problem::sigma`]: 0.3 of each span.
pub const DEFAULT_SIGMA: f64 = 0.3;

impl Problem {
    /// The number of points per generation.
    pub fn population(&self) -> usize {
        let n = self.parameters.len() as f64;
        self.population
            .unwrap_or(4 + (3.0 * n.ln()).floor() as usize)
    }

    /// Checks parameters, start, step size and population.
    pub fn check(&self) -> Result<(), String> {
        if self.parameters.is_empty() {
            return Err("no parameter to search".into());
        }
        for (i, p) in self.parameters.iter().enumerate() {
            p.check()?;
            if self.parameters[..i].iter().any(|q| q.key == p.key) {
                return Err(format!(
                    "{} is given twice; give each parameter once",
                    p.key
                ));
            }
        }
        if let Some(start) = &self.start {
            if start.len() != self.parameters.len() {
                return Err(format!(
                    "the start has {} values for {} parameters",
                    start.len(),
                    self.parameters.len()
                ));
            }
            for (p, v) in self.parameters.iter().zip(start) {
                if !(p.lower..=p.upper).contains(v) {
                    return Err(format!(
                        "{}: the start {v} is outside [{}, {}]",
                        p.key, p.lower, p.upper
                    ));
                }
            }
        }
        if self.sigma.is_nan() || self.sigma <= 0.0 || self.sigma.is_infinite() {
            return Err(format!("sigma {} must be a positive number", self.sigma));
        }
        if self.population.is_some_and(|l| l < 2) {
            return Err("the population must have at least 2 points".into());
        }
        if self.max_generations == 0 {
            return Err("the search needs at least one generation".into());
        }
        Ok(())
    }

    /// The start in normalised coordinates.
    pub(crate) fn normalised_start(&self) -> Vec<f64> {
        match &self.start {
            Some(s) => (self.parameters.iter().zip(s))
                .map(|(p, v)| p.normalised(*v))
                .collect(),
            None => vec![0.5; self.parameters.len()],
        }
    }

    /// The objective's first word: the quantity (`distance_per_hop_m`).
    pub fn quantity(&self) -> &str {
        self.objective
            .split_whitespace()
            .next()
            .unwrap_or("objective")
    }

    /// The parameters' values at the normalised point `y`.
    pub fn values(&self, y: &[f64]) -> Vec<f64> {
        self.parameters
            .iter()
            .zip(y)
            .map(|(p, y)| p.value(*y))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_parse_with_bounds_and_kind() {
        let p: Parameter = "controller.cane_delay=0:0.5".parse().unwrap();
        assert_eq!((p.lower, p.upper, p.integer), (0.0, 0.5, false));
        let q: Parameter = "n=1:9:int".parse().unwrap();
        assert!(q.integer);
        assert!("x=1:0".parse::<Parameter>().is_err());
        assert!("x=0.2:0.4:int".parse::<Parameter>().is_err());
        assert!("x=0:1:float".parse::<Parameter>().is_err());
        assert!("x=a:1".parse::<Parameter>().is_err());
    }

    /// The fold is the identity inside `[0, 1]`, a mirror at each bound, and periodic.
    #[test]
    fn values_fold_into_the_bounds() {
        let p: Parameter = "x=-1:3".parse().unwrap();
        for (y, v) in [
            (0.0, -1.0),
            (0.25, 0.0),
            (1.0, 3.0),
            (1.25, 2.0),
            (-0.25, 0.0),
            (2.25, 0.0),
        ] {
            assert!((p.value(y) - v).abs() < 1e-12, "y = {y}: {}", p.value(y));
        }
        let n: Parameter = "n=0.5:3.5:int".parse().unwrap();
        assert_eq!(n.value(0.0), 1.0);
        assert_eq!(n.value(1.0), 3.0);
        assert_eq!(n.value(0.5), 2.0);
    }
}
