//! The impulsive eccentric-wheel template (docs/physics.md §5.1) as studies: one case with its
//! trajectory and hops ([`case`]), the Cargo `l/R × φ_TO` grid ([`cargo_grid`]), and the
//! animals' stride against speed ([`animals`]).

pub mod animals;
pub mod cargo_grid;
pub mod case;

pub use animals::{animal_sweeps, AnimalSweep, AnimalSweepsParams, AnimalSweepsReport};
pub use cargo_grid::{cargo_grid, CargoGridParams, CargoGridReport};
pub use case::{template_case, CaseParams, CaseReport};

use hopsim_theory::template::TemplateParams;
use serde::Serialize;

/// Template parameters as the reports show them: with the eccentricity `a = R − l`.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ParamsWithEccentricity {
    #[serde(flatten)]
    pub params: TemplateParams,
    /// `a = R − l` [m].
    pub eccentricity_m: f64,
}

impl From<TemplateParams> for ParamsWithEccentricity {
    fn from(params: TemplateParams) -> Self {
        ParamsWithEccentricity {
            params,
            eccentricity_m: params.eccentricity(),
        }
    }
}

/// The smallest and largest of `values`, or `None` when there are none.
pub fn span(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values.into_iter().fold(None, |range, v| match range {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopsim_theory::template::TemplateCase;

    #[test]
    fn span_covers_every_value() {
        assert_eq!(span([]), None);
        assert_eq!(span([2.0]), Some((2.0, 2.0)));
        assert_eq!(span([3.0, -1.0, 2.0]), Some((-1.0, 3.0)));
    }

    #[test]
    fn parameters_serialise_with_units_and_eccentricity() {
        let p = TemplateCase::Cargo2.params();
        let v = serde_json::to_value(ParamsWithEccentricity::from(p)).unwrap();
        let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(
            keys,
            [
                "convergence_tolerance",
                "eccentricity_m",
                "energy_input_J",
                "gravity_mps2",
                "hops",
                "impulse_tilt_rad",
                "inertia_kg_m2",
                "leg_length_m",
                "mass_kg",
                "radius_m",
                "takeoff_angle_rad",
                "window",
            ]
        );
        assert_eq!(v["eccentricity_m"], p.radius - p.leg_length);
    }
}
