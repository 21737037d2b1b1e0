//! Inelastic impacts and applied impulses in generalised coordinates (docs/physics.md §3).
//!
//! All functions take the mass matrix `M` (`n × n`, symmetric positive definite), a contact
//! (or actuation) Jacobian `J` (`k × n`, rows are the constrained relative velocities, e.g.
//! `(w_Tᵀ; w_Nᵀ)` of one contact) and generalised velocities `u` (`n`). They are
//! dimension-agnostic so that any model of hopsim can use them.
//!
//! * [`collision_matrix`]: `M_c = −Jᵀ (J M⁻¹ Jᵀ)⁻¹ J` [2.20].
//! * [`inelastic_impact`]: restitution-0, no-slip impact `u⁺ = (I − M⁻¹Jᵀ(JM⁻¹Jᵀ)⁻¹J) u⁻`,
//!   percussion `Λ = −(JM⁻¹Jᵀ)⁻¹ J u⁻` [2.15–2.19] and the energy change
//!   `ΔE = ½ u⁻ᵀ M_c u⁻ ≤ 0` [2.21].
//! * [`apply_impulse`]: `u⁺ = u⁻ + M⁻¹ J_iᵀ ζ` [2.22].
//! * [`impulse_for_energy_gain`]: the magnitude `‖ζ‖` along a direction `ρ` that raises the
//!   kinetic energy by exactly `ΔE` [3.6].

use crate::error::{AnalysisError, Result};
use nalgebra::allocator::Allocator;
use nalgebra::{
    Cholesky, DMatrix, DVector, DefaultAllocator, Dim, Dyn, OMatrix, OVector, SMatrix, SVector,
};

fn cholesky(matrix: &DMatrix<f64>, what: &'static str) -> Result<Cholesky<f64, Dyn>> {
    if !matrix.is_square() {
        return Err(AnalysisError::Dimension(format!(
            "{what} is {}×{}, not square",
            matrix.nrows(),
            matrix.ncols()
        )));
    }
    factor(matrix.clone(), what)
}

/// The Cholesky factor of a symmetric positive definite `matrix` (any storage).
fn factor<D: Dim>(matrix: OMatrix<f64, D, D>, what: &'static str) -> Result<Cholesky<f64, D>>
where
    DefaultAllocator: Allocator<D, D>,
{
    if matrix.iter().any(|x| !x.is_finite()) {
        return Err(AnalysisError::NotPositiveDefinite { what });
    }
    Cholesky::new(matrix).ok_or(AnalysisError::NotPositiveDefinite { what })
}

fn check_dimensions(
    mass: &DMatrix<f64>,
    jacobian: &DMatrix<f64>,
    velocity: Option<&DVector<f64>>,
) -> Result<()> {
    let n = mass.nrows();
    if jacobian.ncols() != n {
        return Err(AnalysisError::Dimension(format!(
            "Jacobian has {} columns but the mass matrix is {n}×{n}",
            jacobian.ncols()
        )));
    }
    if let Some(u) = velocity {
        if u.len() != n {
            return Err(AnalysisError::Dimension(format!(
                "velocity has {} entries but the mass matrix is {n}×{n}",
                u.len()
            )));
        }
    }
    Ok(())
}

/// Checks that the vector `what` has one entry per row of the Jacobian.
fn check_rows(what: &str, vector: &DVector<f64>, jacobian: &DMatrix<f64>) -> Result<()> {
    if vector.len() != jacobian.nrows() {
        return Err(AnalysisError::Dimension(format!(
            "{what} has {} entries but the Jacobian has {} rows",
            vector.len(),
            jacobian.nrows()
        )));
    }
    Ok(())
}

/// `M⁻¹ Jᵀ` (`n × k`).
pub fn inverse_mass_times_transpose(
    mass: &DMatrix<f64>,
    jacobian: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    check_dimensions(mass, jacobian, None)?;
    let chol = cholesky(mass, "the mass matrix")?;
    Ok(chol.solve(&jacobian.transpose()))
}

/// The Delassus matrix `G = J M⁻¹ Jᵀ` (`k × k`): the inverse effective mass seen by the
/// constrained velocities.
pub fn delassus(mass: &DMatrix<f64>, jacobian: &DMatrix<f64>) -> Result<DMatrix<f64>> {
    Ok(jacobian * inverse_mass_times_transpose(mass, jacobian)?)
}

/// The collision matrix `M_c = −Jᵀ (J M⁻¹ Jᵀ)⁻¹ J` [2.20]; symmetric negative semidefinite.
pub fn collision_matrix(mass: &DMatrix<f64>, jacobian: &DMatrix<f64>) -> Result<DMatrix<f64>> {
    let g = delassus(mass, jacobian)?;
    let chol = cholesky(&g, "the Delassus matrix J M⁻¹ Jᵀ")?;
    let g_inv_j = chol.solve(jacobian);
    Ok(-(jacobian.transpose() * g_inv_j))
}

/// Kinetic energy `½ uᵀ M u`.
pub fn kinetic_energy(mass: &DMatrix<f64>, velocity: &DVector<f64>) -> f64 {
    0.5 * velocity.dot(&(mass * velocity))
}

/// The outcome of a restitution-0, no-slip impact.
#[derive(Debug, Clone, PartialEq)]
pub struct InelasticImpact {
    /// Post-impact velocities `u⁺` (they satisfy `J u⁺ = 0`).
    pub velocity_after: DVector<f64>,
    /// Percussion `Λ = −(J M⁻¹ Jᵀ)⁻¹ J u⁻`, one entry per row of `J` (force × time).
    pub percussion: DVector<f64>,
    /// Kinetic energy change `ΔE = ½ u⁻ᵀ M_c u⁻` (≤ 0: energy is lost).
    pub energy_change: f64,
}

/// Restitution-0, no-slip impact [2.15–2.21]: the constrained relative velocities `J u`
/// vanish after the impact.
pub fn inelastic_impact(
    mass: &DMatrix<f64>,
    jacobian: &DMatrix<f64>,
    velocity_before: &DVector<f64>,
) -> Result<InelasticImpact> {
    check_dimensions(mass, jacobian, Some(velocity_before))?;
    if !mass.is_square() {
        cholesky(mass, "the mass matrix")?;
    }
    let (velocity_after, percussion, energy_change) =
        impact_of(mass.clone(), jacobian, velocity_before)?;
    Ok(InelasticImpact {
        velocity_after,
        percussion,
        energy_change,
    })
}

/// [`inelastic_impact`] with sizes known at compile time (`n` coordinates, `k` rows), on
/// the stack: `(u⁺, Λ, ΔE)`.
pub fn inelastic_impact_fixed<const N: usize, const K: usize>(
    mass: &SMatrix<f64, N, N>,
    jacobian: &SMatrix<f64, K, N>,
    velocity_before: &SVector<f64, N>,
) -> Result<(SVector<f64, N>, SVector<f64, K>, f64)> {
    impact_of(*mass, jacobian, velocity_before)
}

/// `(u⁺, Λ, ΔE)` of an impact with `N` coordinates and `K` rows.
type ImpactOf<N, K> = (OVector<f64, N>, OVector<f64, K>, f64);

/// The impact of [`inelastic_impact`] for any storage: `u⁺`, `Λ` and `ΔE`.
fn impact_of<N: Dim, K: Dim>(
    mass: OMatrix<f64, N, N>,
    jacobian: &OMatrix<f64, K, N>,
    velocity_before: &OVector<f64, N>,
) -> Result<ImpactOf<N, K>>
where
    DefaultAllocator: Allocator<N, N>
        + Allocator<K, N>
        + Allocator<N, K>
        + Allocator<K, K>
        + Allocator<N>
        + Allocator<K>,
{
    let m_inv_jt = factor(mass, "the mass matrix")?.solve(&jacobian.transpose());
    let g = jacobian * &m_inv_jt;
    let approach = jacobian * velocity_before;
    let percussion = -factor(g, "the Delassus matrix J M⁻¹ Jᵀ")?.solve(&approach);
    let velocity_after = velocity_before + &m_inv_jt * &percussion;
    // ½ u⁻ᵀ M_c u⁻ = −½ (J u⁻)ᵀ G⁻¹ (J u⁻) = ½ (J u⁻)ᵀ Λ.
    let energy_change = 0.5 * approach.dot(&percussion);
    Ok((velocity_after, percussion, energy_change))
}

/// Energy change `ΔE = ½ u⁻ᵀ M_c u⁻` of a restitution-0 impact [2.21].
pub fn impact_energy_change(
    mass: &DMatrix<f64>,
    jacobian: &DMatrix<f64>,
    velocity_before: &DVector<f64>,
) -> Result<f64> {
    Ok(inelastic_impact(mass, jacobian, velocity_before)?.energy_change)
}

/// Applied impulse `ζ` acting through the Jacobian `J_i` of its point (or rotational
/// Jacobian of its body): `u⁺ = u⁻ + M⁻¹ J_iᵀ ζ` [2.22].
pub fn apply_impulse(
    mass: &DMatrix<f64>,
    jacobian: &DMatrix<f64>,
    velocity_before: &DVector<f64>,
    impulse: &DVector<f64>,
) -> Result<DVector<f64>> {
    check_dimensions(mass, jacobian, Some(velocity_before))?;
    check_rows("impulse", impulse, jacobian)?;
    Ok(velocity_before + inverse_mass_times_transpose(mass, jacobian)? * impulse)
}

/// The magnitude `‖ζ‖ ≥ 0` of an impulse `ζ = ‖ζ‖ ρ` applied through `J` that raises the
/// kinetic energy by exactly `ΔE ≥ 0` [3.6]:
/// `‖ζ‖ = (−ρᵀJu⁻ + sqrt((ρᵀJu⁻)² + 2KΔE)) / K`, `K = ρᵀ J M⁻¹ Jᵀ ρ`.
/// `direction` need not be normalised; the returned magnitude multiplies it as given.
pub fn impulse_for_energy_gain(
    mass: &DMatrix<f64>,
    jacobian: &DMatrix<f64>,
    direction: &DVector<f64>,
    velocity_before: &DVector<f64>,
    energy_gain: f64,
) -> Result<f64> {
    check_dimensions(mass, jacobian, Some(velocity_before))?;
    check_rows("direction", direction, jacobian)?;
    if !(energy_gain.is_finite() && energy_gain >= 0.0) {
        return Err(AnalysisError::invalid(
            "energy gain",
            energy_gain,
            "must be finite and ≥ 0",
        ));
    }
    let g = delassus(mass, jacobian)?;
    let k = direction.dot(&(&g * direction));
    if k.is_nan() || k <= 0.0 {
        return Err(AnalysisError::NotPositiveDefinite {
            what: "ρᵀ J M⁻¹ Jᵀ ρ (the impulse direction has no effect)",
        });
    }
    let b = direction.dot(&(jacobian * velocity_before));
    // Numerically stable root of ½K s² + b s − ΔE = 0 with s ≥ 0.
    let disc = (b * b + 2.0 * k * energy_gain).sqrt();
    Ok(if b <= 0.0 {
        (disc - b) / k
    } else {
        2.0 * energy_gain / (b + disc)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{dmatrix, dvector};

    #[test]
    fn point_mass_loses_normal_kinetic_energy() {
        // A point mass m hitting the ground with (vx, vy): a no-slip impact stops it
        // completely; a frictionless one (normal row only) removes ½ m vy².
        let m = 2.5;
        let mass = dmatrix![m, 0.0; 0.0, m];
        let u = dvector![1.2, -3.0];
        let normal_only = dmatrix![0.0, 1.0];
        let energy_change = impact_energy_change(&mass, &normal_only, &u).unwrap();
        assert!((energy_change + 0.5 * m * 9.0).abs() < 1e-12);
        let both = dmatrix![1.0, 0.0; 0.0, 1.0];
        let hit = inelastic_impact(&mass, &both, &u).unwrap();
        assert!(hit.velocity_after.norm() < 1e-12);
        assert!((hit.energy_change + kinetic_energy(&mass, &u)).abs() < 1e-12);
    }

    #[test]
    fn dimension_errors_are_reported() {
        let mass = dmatrix![1.0, 0.0; 0.0, 1.0];
        let j = dmatrix![1.0, 0.0, 0.0];
        assert!(matches!(
            collision_matrix(&mass, &j),
            Err(AnalysisError::Dimension(_))
        ));
        let singular = dmatrix![1.0, 0.0; 2.0, 0.0];
        assert!(matches!(
            collision_matrix(&mass, &singular),
            Err(AnalysisError::NotPositiveDefinite { .. })
        ));
        let bad_mass = dmatrix![-1.0, 0.0; 0.0, 1.0];
        assert!(collision_matrix(&bad_mass, &dmatrix![1.0, 0.0]).is_err());
    }
}
