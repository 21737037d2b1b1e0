//! The fixed-point study as text: the point's or the grid's table, a sample of the grid's
//! fixed points, and the time-stepper cross-check.

use super::selection::evenly_spaced;
use super::summary::{Eigenvalue, FixedPointSummary, GaitCheck, PointSummary};
use super::{GridReport, PointReport};
use crate::report::{num, num_range, nums, opt_num, TextTable};
use std::fmt::Write;

/// Grid points listed under the grid's table besides the most stable and the fastest.
const SAMPLE: usize = 8;

/// `β* = (T*, ζ0*)`.
fn control(torque: f64, impulse_limit: f64) -> String {
    nums(&[(torque, "N m"), (impulse_limit, "N m s")])
}

/// `predicted P, <label> S` in `unit` (`—` for a missing `S`).
fn versus(predicted: f64, label: &str, simulated: Option<f64>, unit: &str) -> String {
    format!(
        "predicted {}, {label} {}",
        num(predicted, unit),
        opt_num(simulated, unit, "—")
    )
}

fn complex(l: &Eigenvalue) -> String {
    if l.im == 0.0 {
        num(l.re, "")
    } else {
        format!(
            "{} {} {}i",
            num(l.re, ""),
            if l.im < 0.0 { "−" } else { "+" },
            num(l.im.abs(), "")
        )
    }
}

/// What `--simulate` adds: the check's table, or why there is none.
fn gait_check_text(check: Option<&GaitCheck>, requested: bool, missing: &str) -> String {
    match check {
        Some(check) => gait_check_table(check).to_string(),
        None if requested => format!("--simulate: {missing}\n"),
        None => String::new(),
    }
}

fn gait_check_table(check: &GaitCheck) -> TextTable {
    let mut t = TextTable::new(format!(
        "time-stepper from rest (Δt = {} s, {} s, {} brakes) vs predicted gait",
        check.dt_s, check.duration_s, check.brakes
    ));
    t.row(
        "β* = (T*, ζ0*)",
        control(check.point.torque, check.point.impulse_limit),
    );
    let (predicted, simulated) = (&check.predicted, &check.simulated);
    let compared = (
        check.window,
        check.max_angle_error_rad,
        check.angle_tolerance_rad,
        check.max_rate_error_rad_s,
        check.rate_tolerance_rad_s,
    );
    match compared {
        (Some(window), Some(angle), Some(angle_tol), Some(rate), Some(rate_tol)) => {
            t.row(
                "take-off angle φ_TO",
                versus(
                    predicted.takeoff_angle_rad,
                    "last simulated",
                    simulated.last_takeoff_angle_rad,
                    "rad",
                ),
            )
            .row(
                "take-off rate φ̇_TO",
                versus(
                    predicted.takeoff_rate_rad_s,
                    "last simulated",
                    simulated.last_takeoff_rate_rad_s,
                    "rad/s",
                ),
            )
            .row(
                format!("max error, last {window} brakes"),
                format!(
                    "{} (tolerance {}), {} (tolerance {})",
                    num(angle, "rad"),
                    num(angle_tol, "rad"),
                    num(rate, "rad/s"),
                    num(rate_tol, "rad/s")
                ),
            )
            .row(
                "speed",
                versus(predicted.speed_mps, "simulated", simulated.speed_mps, "m/s"),
            )
            .row(
                "period",
                versus(predicted.period_s, "simulated", simulated.period_s, "s"),
            )
            .row(
                "converges to the predicted gait",
                if check.converged { "yes" } else { "no" },
            );
        }
        _ => {
            t.row(
                "converges to the predicted gait",
                "no: fewer than two brakes in the run",
            );
        }
    }
    t.row("elapsed", num(check.elapsed_s, "s"));
    t
}

/// The fixed point's rows of the point's table.
fn fixed_point_rows(t: &mut TextTable, f: &FixedPointSummary, stable: bool) {
    t.row("β* = (T*, ζ0*)", control(f.torque, f.impulse_limit))
        .row(
            "eigenvalues of ∂P/∂z",
            format!(
                "{}, {}",
                complex(&f.eigenvalues[0]),
                complex(&f.eigenvalues[1])
            ),
        )
        .row(
            "max |λ|",
            format!(
                "{} ({})",
                num(f.max_abs_eigenvalue, ""),
                if stable { "stable" } else { "unstable" }
            ),
        )
        .row(
            "speed, stride, period",
            nums(&[(f.speed_mps, "m/s"), (f.stride_m, "m"), (f.period_s, "s")]),
        )
        .row(
            "flight, stance",
            format!(
                "{} ({} reversals of φ̇)",
                nums(&[(f.flight_time_s, "s"), (f.stance_time_s, "s")]),
                f.stance_reversals
            ),
        )
        .row("touchdown angle", num(f.touchdown_angle_rad, "rad"))
        .row(
            "energy per cycle",
            format!(
                "motor {} = brake loss {} + touchdown loss {}",
                num(f.motor_work, "J"),
                num(f.brake_loss, "J"),
                num(f.touchdown_loss, "J")
            ),
        )
        .row(
            "impulse per distance ζ0/stride",
            num(f.impulse_per_distance, "N m s/m"),
        )
        .row("residual", num(f.residual_rad, "rad"));
}

/// The point's table, its model warnings and the cross-check.
pub fn point_text(r: &PointReport) -> String {
    let q = &r.point;
    let mut t = TextTable::new(
        "Robbit fixed point (docs/physics.md §5.3; forward = +x, φ counter-clockwise)",
    );
    t.row(
        "flywheel at touchdown",
        r.about.parameters.flywheel_at_touchdown,
    )
    .row(
        "section state z = (φ_TO, φ̇_TO)",
        format!(
            "{} (E_TO {})",
            nums(&[
                (q.takeoff_angle_rad, "rad"),
                (q.takeoff_rate_rad_s, "rad/s")
            ]),
            num(q.takeoff_energy, "J")
        ),
    );
    let mut warnings = String::new();
    match (&q.details, &q.reason) {
        (Some(f), _) => {
            fixed_point_rows(&mut t, f, q.stable);
            for w in &f.warnings {
                let _ = writeln!(warnings, "warning: {w}");
            }
        }
        (None, Some(reason)) => {
            t.row("fixed point", format!("none: {reason}"));
        }
        (None, None) => {}
    }
    format!(
        "{t}{warnings}{}",
        gait_check_text(
            r.simulation.as_ref(),
            r.simulate_requested,
            "no fixed point to simulate"
        )
    )
}

/// The grid's table, the sample of its fixed points and the cross-check.
pub fn grid_text(r: &GridReport) -> String {
    let (n, m) = (r.angles_rad.len(), r.energies.len());
    let mut t = TextTable::new(format!(
        "Robbit fixed points (docs/physics.md §5.3), {n} × {m} grid (φ_TO × E_TO)"
    ));
    let reasons = if r.no_fixed_point_reasons.is_empty() {
        "0".to_string()
    } else {
        r.no_fixed_point_reasons
            .iter()
            // The kinds in words, e.g. "2 solver failed", the words that start the CSV's
            // and the JSON's reason text for that kind.
            .map(|(k, v)| format!("{v} {}", k.replace('-', " ")))
            .collect::<Vec<_>>()
            .join(", ")
    };
    t.row(
        "φ_TO range",
        num_range(r.angles_rad[0], r.angles_rad[n - 1], "rad"),
    )
    .row(
        "E_TO range",
        format!(
            "{} (rolling kinetic energy before the brake)",
            num_range(r.energies[0], r.energies[m - 1], "J")
        ),
    )
    .row(
        "flywheel at touchdown",
        r.about.parameters.flywheel_at_touchdown,
    )
    .row(
        "fixed points",
        format!(
            "{} of {} (stable {}, unstable {})",
            r.fixed_points, r.points_total, r.stable_points, r.unstable_points
        ),
    )
    .row("no fixed point", reasons)
    .row(
        "model warnings",
        format!(
            "{} fixed points leave the friction cone or need a pulling ground",
            r.fixed_points_with_warnings
        ),
    )
    .row("elapsed", num(r.elapsed_s, "s"));
    let mut out = t.to_string();
    out.push_str(&sample_table(r));
    out.push_str(&gait_check_text(
        r.simulation.as_ref(),
        r.simulate_requested,
        "no stable fixed point in the grid to simulate",
    ));
    if let Some(gaits) = &r.gaits {
        out.push_str(&gaits.text());
    }
    out
}

/// The most stable and the fastest stable fixed point, then up to [`SAMPLE`] fixed points
/// evenly spaced over the grid.
fn sample_table(r: &GridReport) -> String {
    let found: Vec<&PointSummary> = r.points.iter().filter(|q| q.details.is_some()).collect();
    let labelled: Vec<(&str, &PointSummary)> = r
        .most_stable
        .iter()
        .map(|q| ("most stable¹", q))
        .chain(r.fastest_stable.iter().map(|q| ("fastest stable", q)))
        .chain(evenly_spaced(&found, SAMPLE).into_iter().map(|q| ("", q)))
        .collect();
    if labelled.is_empty() {
        return String::new();
    }
    let mut out = format!(
        "  {:<15} {:>8} {:>8} {:>9} {:>10} {:>8} {:>8} {:>8}\n",
        "", "φ_TO", "E_TO", "T*", "ζ0*", "max|λ|", "stable", "speed"
    );
    for (label, q) in labelled {
        let Some(f) = &q.details else { continue };
        let _ = writeln!(
            out,
            "  {:<15} {:>8.4} {:>8.4} {:>9.4} {:>10.5} {:>8.4} {:>8} {:>8.4}",
            label,
            q.takeoff_angle_rad,
            q.takeoff_energy,
            f.torque,
            f.impulse_limit,
            f.max_abs_eigenvalue,
            if q.stable { "yes" } else { "no" },
            f.speed_mps
        );
    }
    out.push_str(
        "  (angles rad, energies J, T* N m, ζ0* N m s, speed m/s; ¹ without model warnings)\n",
    );
    out
}
