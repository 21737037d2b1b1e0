//! The impulsive wheel's return map (docs/physics.md §5.5): closed forms against iteration.

use hopsim_theory::impulsive_wheel::{wrap_half_turn, ImpulsiveWheel};

#[test]
fn defaults_follow_physics_md() {
    let w = ImpulsiveWheel::default();
    // E₀ = ½ (I + m R²) φ̇_S² = 1 with I = m = R = 1 gives φ̇_S = 1 rad/s.
    assert!((w.rolling_speed() - 1.0).abs() < 1e-15);
    assert!(
        (0.5 * (w.inertia + w.mass * w.radius * w.radius) * w.rolling_speed().powi(2)
            - w.rolling_energy)
            .abs()
            < 1e-15
    );
    assert_eq!(w.gravity, 9.81);
}

#[test]
fn closed_form_fixed_point_is_the_limit_of_iteration() {
    let w = ImpulsiveWheel::default();
    for impulse in [3.2, 3.5, 3.7] {
        let fp = w.fixed_point(impulse).unwrap();
        assert!(fp.stable, "{impulse}");
        let phi_star = fp.fixed_point_rad.unwrap();
        // Iterate from a nearby start (the basin of the stable branch).
        let phis = w.iterate(impulse, phi_star + 0.05, 3000);
        let limit = *phis.last().unwrap();
        assert!(
            (limit - phi_star).abs() < 1e-10,
            "ζ {impulse}: {limit} vs {phi_star}"
        );
        // And it is a fixed point of the map itself.
        assert!((w.return_map(impulse, phi_star) - phi_star).abs() < 1e-14);
    }
}

#[test]
fn closed_form_eigenvalue_is_the_map_derivative() {
    let w = ImpulsiveWheel::default();
    for impulse in [3.2, 3.5, 3.7, 4.0, 5.0] {
        let fp = w.fixed_point(impulse).unwrap();
        let phi = fp.fixed_point_rad.unwrap();
        let h = 1e-6;
        let derivative =
            (w.return_map(impulse, phi + h) - w.return_map(impulse, phi - h)) / (2.0 * h);
        let lambda = fp.eigenvalue.unwrap();
        assert!(
            (derivative - lambda).abs() < 1e-8,
            "ζ {impulse}: {derivative} vs {lambda}"
        );
        assert_eq!(fp.stable, lambda.abs() < 1.0);
    }
    // ζ = 4: |λ| > 1, iteration leaves the fixed point.
    let fp = w.fixed_point(4.0).unwrap();
    assert!(!fp.stable);
    let phi_star = fp.fixed_point_rad.unwrap();
    let far = w
        .iterate(4.0, phi_star + 1e-6, 60)
        .into_iter()
        .map(|p| (wrap_half_turn(p) - phi_star).abs())
        .fold(0.0, f64::max);
    assert!(far > 1e-3);
}

#[test]
fn stable_interval_ends_where_the_eigenvalue_leaves_the_unit_circle() {
    let w = ImpulsiveWheel::default();
    let (lo, hi) = w.stable_impulse_interval();
    assert!(lo < 3.5 && 3.5 < hi);
    let eps = 1e-7;
    // Just below lo: no fixed point (c < φ̇_S T_C); just above: λ ≈ +1.
    assert!(w.fixed_point(lo - eps).unwrap().fixed_point_rad.is_none());
    let above = w.fixed_point(lo + eps).unwrap();
    assert!(above.stable && (above.eigenvalue.unwrap() - 1.0).abs() < 1e-2);
    // At hi: λ = −1 (period doubling).
    let inside = w.fixed_point(hi - eps).unwrap();
    let outside = w.fixed_point(hi + eps).unwrap();
    assert!(inside.stable && !outside.stable);
    assert!((inside.eigenvalue.unwrap() + 1.0).abs() < 1e-5);
}

#[test]
fn bifurcation_settles_on_the_fixed_point_inside_the_stable_interval() {
    let w = ImpulsiveWheel::default();
    let diagram = w.bifurcation(&[3.5, 3.9], 0.1, 500, 8);
    let phi_star = w.fixed_point(3.5).unwrap().fixed_point_rad.unwrap();
    assert!(diagram[0].1.iter().all(|p| (p - phi_star).abs() < 1e-9));
    // Past the period doubling the iterates alternate between two values around φ*.
    let (a, b) = (diagram[1].1[6], diagram[1].1[7]);
    assert!((a - b).abs() > 1e-3);
    assert!((diagram[1].1[5] - b).abs() < 1e-6);
}

/// Non-unit parameters against docs/physics.md §5.5 written out here, independently of the
/// module's `coupling`/`return_map`: `E₀ = ½ (I + m R²) φ̇_S²` (rolling wheel, centred
/// mass), `c = R ‖ζ‖² / (m I g)`, `φ* = ½ asin(φ̇_S T_C / c)`,
/// `λ = 1 − 2 sqrt(c² − φ̇_S² T_C²)`, stable for `φ̇_S T_C < c < sqrt(1 + φ̇_S² T_C²)`.
#[test]
fn fixed_point_and_eigenvalue_match_the_closed_forms_for_non_unit_parameters() {
    let (m, r, i, t_c, e0, g) = (2.5, 0.4, 0.3, 0.7, 3.0, 9.5);
    let w = ImpulsiveWheel {
        mass: m,
        radius: r,
        inertia: i,
        cycle_time: t_c,
        rolling_energy: e0,
        gravity: g,
    };
    let rate = (2.0 * e0 / (i + m * r * r)).sqrt();
    let drift = rate * t_c;
    // Impulses with c = R ζ²/(m I g) between the drift and sqrt(1 + drift²) (stable),
    // and above it (unstable).
    let zeta_for = |c: f64| (c * m * i * g / r).sqrt();
    let (lo, hi) = (drift, (1.0 + drift * drift).sqrt());
    let mut checked = 0;
    for (c_target, stable) in [
        (lo + 0.1 * (hi - lo), true),
        (lo + 0.5 * (hi - lo), true),
        (lo + 0.9 * (hi - lo), true),
        (1.2 * hi, false),
        (3.0 * hi, false),
    ] {
        let zeta = zeta_for(c_target);
        let c = r * zeta * zeta / (m * i * g);
        let phi_star = 0.5 * (drift / c).asin();
        let lambda = 1.0 - 2.0 * (c * c - drift * drift).sqrt();
        let fp = w.fixed_point(zeta).unwrap();
        let got_phi = fp.fixed_point_rad.expect("a fixed point");
        let got_lambda = fp.eigenvalue.unwrap();
        eprintln!(
            "ζ {zeta:.4}: φ* {phi_star:.6} (Δ {:.1e}), λ {lambda:.6} (Δ {:.1e})",
            got_phi - phi_star,
            got_lambda - lambda
        );
        assert!(
            (fp.coupling - c).abs() < 1e-12 * c,
            "ζ {zeta}: c {} vs {c}",
            fp.coupling
        );
        assert!(
            (got_phi - phi_star).abs() < 1e-9,
            "ζ {zeta}: φ* {got_phi} vs {phi_star}"
        );
        assert!(
            (got_lambda - lambda).abs() < 1e-9,
            "ζ {zeta}: λ {got_lambda} vs {lambda}"
        );
        assert_eq!(fp.stable, stable, "ζ {zeta}: λ {lambda}");
        // φ* is a fixed point of the map written out here: φ − c sin 2φ + φ̇_S T_C.
        let map = |phi: f64| phi - c * (2.0 * phi).sin() + drift;
        assert!((map(phi_star) - phi_star).abs() < 1e-12);
        // And λ is that map's slope there (central difference).
        let h = 1e-6;
        let slope = (map(phi_star + h) - map(phi_star - h)) / (2.0 * h);
        assert!((slope - lambda).abs() < 1e-8, "slope {slope} vs λ {lambda}");
        checked += 1;
    }
    assert_eq!(checked, 5);
    // Below c = φ̇_S T_C there is no fixed point.
    assert!(w
        .fixed_point(zeta_for(0.9 * drift))
        .unwrap()
        .fixed_point_rad
        .is_none());
    // The stable interval from the same closed forms.
    let (got_lo, got_hi) = w.stable_impulse_interval();
    assert!(
        (got_lo - zeta_for(lo)).abs() < 1e-9,
        "{got_lo} vs {}",
        zeta_for(lo)
    );
    assert!(
        (got_hi - zeta_for(hi)).abs() < 1e-9,
        "{got_hi} vs {}",
        zeta_for(hi)
    );
}
