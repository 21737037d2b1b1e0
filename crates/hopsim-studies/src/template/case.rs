//! One template case (docs/physics.md §5.1): its gait over the last hops, warnings where the
//! template's assumptions fail, and (as files) the trajectory and the per-hop records.

use super::ParamsWithEccentricity;
use crate::plot::{LinePlot, Series, SeriesStyle, PALETTE};
use crate::report::{num, nums, Report, ReportFile, TextTable};
use crate::Result;
use hopsim_io::{Cell, CsvTable};
use hopsim_theory::template::{
    self, GaitSummary, NoGait, Phase, TemplateCase, TemplateParams, TemplateRun, TrajectorySample,
};
use serde::Serialize;

/// What to run: a named case, possibly with other parameters.
#[derive(Clone, Copy, Debug)]
pub struct CaseParams {
    /// The Table-3.1 case the parameters start from (its name is reported).
    pub case: TemplateCase,
    /// The parameters run.
    pub params: TemplateParams,
    /// Keep the centre-of-mass trajectory (for the files; costs memory).
    pub record_trajectory: bool,
}

/// The gait of a case, every field null without a gait.
#[derive(Clone, Copy, Debug, Default, Serialize)]
struct GaitFields {
    converged: bool,
    mean_speed_mps: Option<f64>,
    stride_m: Option<f64>,
    hop_frequency_hz: Option<f64>,
    cost_of_transport: Option<f64>,
    dimensionless_speed: Option<f64>,
    froude_number: Option<f64>,
    #[serde(rename = "impulse_Ns")]
    impulse_n_s: Option<f64>,
    flight_time_s: Option<f64>,
    touchdown_angle_rad: Option<f64>,
    #[serde(rename = "touchdown_loss_J")]
    touchdown_loss_j: Option<f64>,
    speed_spread: Option<f64>,
}

impl From<Option<&GaitSummary>> for GaitFields {
    fn from(s: Option<&GaitSummary>) -> Self {
        let Some(s) = s else {
            return GaitFields::default();
        };
        GaitFields {
            converged: s.converged,
            mean_speed_mps: Some(s.mean_speed_mps),
            stride_m: Some(s.stride_m),
            hop_frequency_hz: Some(s.hop_frequency_hz),
            cost_of_transport: Some(s.cost_of_transport),
            dimensionless_speed: Some(s.dimensionless_speed),
            froude_number: Some(s.froude_number),
            impulse_n_s: Some(s.impulse_n_s),
            flight_time_s: Some(s.flight_time_s),
            touchdown_angle_rad: Some(s.touchdown_angle_rad),
            touchdown_loss_j: Some(s.touchdown_loss_j),
            speed_spread: Some(s.speed_spread),
        }
    }
}

/// One case's result.
#[derive(Debug, Serialize)]
pub struct CaseReport {
    analysis: &'static str,
    case: &'static str,
    parameters: ParamsWithEccentricity,
    /// True when the run has a gait (converged or not).
    gait: bool,
    #[serde(flatten)]
    gait_fields: GaitFields,
    hops_completed: usize,
    no_gait_reason: Option<String>,
    no_gait: Option<NoGait>,
    #[serde(rename = "min_stance_normal_force_N")]
    min_stance_normal_force_n: f64,
    /// Where the template's assumptions fail ([`warnings`]).
    pub warnings: Vec<String>,
    /// The run.
    #[serde(skip)]
    pub run: TemplateRun,
}

/// Runs one case.
pub fn template_case(p: &CaseParams) -> Result<CaseReport> {
    let run = template::simulate(&p.params, p.record_trajectory)?;
    Ok(CaseReport {
        analysis: "template",
        case: p.case.name(),
        parameters: p.params.into(),
        gait: run.summary.is_some(),
        gait_fields: run.summary.as_ref().into(),
        hops_completed: run.hops.len(),
        no_gait_reason: run.no_gait.as_ref().map(ToString::to_string),
        no_gait: run.no_gait.clone(),
        min_stance_normal_force_n: run.min_stance_normal_force_n,
        warnings: warnings(&run),
        run,
    })
}

/// The hops of the averaging window: the last `window` of the run.
fn window(run: &TemplateRun) -> &[template::HopRecord] {
    &run.hops[run.hops.len().saturating_sub(run.params.window)..]
}

/// Where the template's assumptions fail in `run`: a pulling ground in stance or at
/// touchdown, a wheel rolling over the top in stance, speeds not converged.
pub fn warnings(run: &TemplateRun) -> Vec<String> {
    let mut out = Vec::new();
    if run.min_stance_normal_force_n < 0.0 {
        out.push(format!(
            "the rolling stance needs a pulling ground (min normal force {:.4} N): the template ignores lift-off in stance",
            run.min_stance_normal_force_n
        ));
    }
    let window = window(run);
    let pulling = window
        .iter()
        .filter(|h| h.touchdown_normal_percussion_n_s < 0.0)
        .count();
    if pulling > 0 {
        out.push(format!(
            "{pulling} of the last {} touchdowns need a negative normal percussion (the no-slip impact pulls the foot down)",
            window.len()
        ));
    }
    let rolled_over = window.iter().filter(|h| h.stance_revolutions != 0).count();
    if rolled_over > 0 {
        out.push(format!(
            "in {rolled_over} of the last {} stances the wheel rolled over the top (full revolutions): a rolling, not a hopping, regime",
            window.len()
        ));
    }
    if let Some(s) = run.summary.as_ref().filter(|s| !s.converged) {
        out.push(format!(
            "not converged: per-hop speeds in the window differ by {:.2} % (tolerance {:.2} %)",
            100.0 * s.speed_spread,
            100.0 * run.params.convergence_tolerance
        ));
    }
    out
}

/// The centre-of-mass path `(x, y)` of the samples of `phase` from hop `first_hop` on,
/// broken by a `NaN` point between hops and where the other phase interrupts it.
pub fn phase_path(
    trajectory: &[TrajectorySample],
    first_hop: usize,
    phase: Phase,
) -> Vec<(f64, f64)> {
    let gap = (f64::NAN, f64::NAN);
    let mut points = Vec::new();
    let mut last_hop = None;
    for s in trajectory.iter().filter(|s| s.hop >= first_hop) {
        if s.phase == phase {
            if last_hop.is_some_and(|h| h != s.hop) {
                points.push(gap);
            }
            points.push((s.state.q[0], s.state.q[1]));
            last_hop = Some(s.hop);
        } else if last_hop.is_some() && points.last().is_some_and(|p| p.0.is_finite()) {
            points.push(gap);
        }
    }
    points
}

impl CaseReport {
    fn trajectory_csv(&self) -> CsvTable {
        let mut csv = CsvTable::new(&[
            "t_s",
            "hop",
            "phase",
            "x_m",
            "y_m",
            "phi_rad",
            "vx_mps",
            "vy_mps",
            "omega_rad_s",
            "energy_J",
        ]);
        for s in &self.run.trajectory {
            let [x, y, phi] = s.state.q;
            let [vx, vy, w] = s.state.u;
            csv.push(vec![
                s.t.into(),
                s.hop.into(),
                s.phase.name().into(),
                x.into(),
                y.into(),
                phi.into(),
                vx.into(),
                vy.into(),
                w.into(),
                template::mechanical_energy(&self.run.params, &s.state).into(),
            ]);
        }
        csv
    }

    fn hops_csv(&self) -> CsvTable {
        let mut csv = CsvTable::new(&[
            "hop",
            "takeoff_time_s",
            "takeoff_x_m",
            "takeoff_angular_velocity_rad_s",
            "impulse_Ns",
            "flight_time_s",
            "touchdown_angle_rad",
            "touchdown_loss_J",
            "touchdown_normal_percussion_Ns",
            "stance_time_s",
            "stance_revolutions",
            "stride_m",
            "period_s",
            "speed_mps",
        ]);
        for h in &self.run.hops {
            csv.push(vec![
                h.index.into(),
                h.takeoff_time_s.into(),
                h.takeoff_x_m.into(),
                h.takeoff_angular_velocity_rad_s.into(),
                h.impulse_n_s.into(),
                h.flight_time_s.into(),
                h.touchdown_angle_rad.into(),
                h.touchdown_loss_j.into(),
                h.touchdown_normal_percussion_n_s.into(),
                h.stance_time_s.into(),
                Cell::Text(h.stance_revolutions.to_string()),
                h.stride_m.into(),
                h.period_s.into(),
                (h.stride_m / h.period_s).into(),
            ]);
        }
        csv
    }

    /// The centre-of-mass path over the averaging window (the converged gait).
    fn trajectory_plot(&self) -> LinePlot {
        let hops = self.run.hops.len();
        let first_hop = hops.saturating_sub(self.run.params.window);
        let mut plot = LinePlot::new(
            format!(
                "centre of mass, hops {}–{}",
                first_hop + 1,
                hops.max(first_hop + 1)
            ),
            "x (m)",
            "y (m)",
        );
        for (phase, color) in [(Phase::Flight, PALETTE[1]), (Phase::Stance, PALETTE[0])] {
            let points = phase_path(&self.run.trajectory, first_hop, phase);
            plot = plot.with_series(Series::line(phase.name(), points).color(color));
        }
        plot
    }

    fn hop_speed_plot(&self) -> LinePlot {
        let speeds = self
            .run
            .hops
            .iter()
            .map(|h| ((h.index + 1) as f64, h.stride_m / h.period_s))
            .collect();
        LinePlot::new(
            "per-hop speed (stride / period)",
            "hop number",
            "speed (m/s)",
        )
        .with_series(Series::line("speed", speeds).style(SeriesStyle::LineAndPoints))
    }
}

impl Report for CaseReport {
    fn text(&self) -> String {
        let p = &self.run.params;
        let mut t = TextTable::new(format!(
            "template {} (docs/physics.md §5.1; forward = +x)",
            self.case
        ));
        t.row(
            "R, l, a",
            nums(&[
                (p.radius, "m"),
                (p.leg_length, "m"),
                (p.eccentricity(), "m"),
            ]),
        )
        .row("m, I", nums(&[(p.mass, "kg"), (p.inertia, "kg m²")]))
        .row(
            "φ_TO, τ",
            nums(&[(p.takeoff_angle, "rad"), (p.impulse_tilt, "rad")]),
        )
        .row("ΔE", num(p.energy_input, "J"))
        .row("hops (window)", format!("{} ({})", p.hops, p.window));
        let mut text = t.to_string();
        match (&self.run.summary, &self.run.no_gait) {
            (Some(s), _) => {
                let mut r = TextTable::new(format!("gait over the last {} hops", p.window));
                r.row("mean speed", num(s.mean_speed_mps, "m/s"))
                    .row("stride", num(s.stride_m, "m"))
                    .row("hop frequency", num(s.hop_frequency_hz, "Hz"))
                    .row("cost of transport", num(s.cost_of_transport, ""))
                    .row("u / sqrt(g l)", num(s.dimensionless_speed, ""))
                    .row("impulse ‖ζ‖", num(s.impulse_n_s, "N s"))
                    .row("flight time", num(s.flight_time_s, "s"))
                    .row("touchdown angle", num(s.touchdown_angle_rad, "rad"))
                    .row("touchdown loss", num(s.touchdown_loss_j, "J"))
                    .row(
                        "converged",
                        format!("{} (speed spread {:.2e})", s.converged, s.speed_spread),
                    );
                text += &r.to_string();
            }
            (None, Some(no_gait)) => text += &format!("{no_gait}\n"),
            (None, None) => text += "no result\n",
        }
        for w in &self.warnings {
            text += &format!("warning: {w}\n");
        }
        text
    }

    fn files(&self) -> Vec<ReportFile> {
        vec![
            ReportFile::csv("trajectory.csv", self.trajectory_csv()),
            ReportFile::csv("hops.csv", self.hops_csv()),
            ReportFile::figure("trajectory", self.trajectory_plot()),
            ReportFile::figure("hop_speed", self.hop_speed_plot()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopsim_theory::template::{BodyState, HopRecord};

    fn sample(hop: usize, phase: Phase, x: f64) -> TrajectorySample {
        TrajectorySample {
            hop,
            phase,
            t: x,
            state: BodyState {
                q: [x, 1.0, 0.0],
                u: [0.0; 3],
            },
        }
    }

    fn hop(index: usize, percussion: f64, revolutions: i64) -> HopRecord {
        HopRecord {
            index,
            takeoff_time_s: 0.0,
            takeoff_x_m: 0.0,
            takeoff_angular_velocity_rad_s: 0.0,
            impulse_n_s: 1.0,
            flight_time_s: 0.1,
            touchdown_angle_rad: 0.0,
            touchdown_loss_j: 0.0,
            touchdown_normal_percussion_n_s: percussion,
            stance_time_s: 0.1,
            stance_revolutions: revolutions,
            stride_m: 1.0,
            period_s: 0.2,
        }
    }

    fn run(hops: Vec<HopRecord>, window: usize, min_force: f64) -> TemplateRun {
        TemplateRun {
            params: TemplateParams {
                window,
                ..TemplateCase::Cargo2.params()
            },
            hops,
            summary: None,
            no_gait: None,
            min_stance_normal_force_n: min_force,
            trajectory: Vec::new(),
        }
    }

    #[test]
    fn phase_path_breaks_between_hops_and_phases() {
        let trajectory = [
            sample(0, Phase::Flight, 0.0),
            sample(1, Phase::Flight, 1.0),
            sample(1, Phase::Flight, 2.0),
            sample(1, Phase::Stance, 3.0),
            sample(2, Phase::Flight, 4.0),
            sample(2, Phase::Stance, 5.0),
        ];
        let xs = |phase| -> Vec<f64> {
            phase_path(&trajectory, 1, phase)
                .iter()
                .map(|p| p.0)
                .collect()
        };
        // Hop 0 is left out; each break is one NaN point per interruption.
        let shape = |xs: Vec<f64>| -> Vec<Option<f64>> {
            xs.into_iter().map(|x| x.is_finite().then_some(x)).collect()
        };
        assert_eq!(
            shape(xs(Phase::Flight)),
            [Some(1.0), Some(2.0), None, None, Some(4.0), None]
        );
        assert_eq!(shape(xs(Phase::Stance)), [Some(3.0), None, None, Some(5.0)]);
    }

    #[test]
    fn warnings_look_only_at_the_window() {
        // A pulling touchdown and a roll-over before the window are not reported.
        let hops = vec![
            hop(0, -1.0, 1),
            hop(1, 1.0, 0),
            hop(2, -0.5, 0),
            hop(3, 1.0, 2),
        ];
        let w = warnings(&run(hops, 2, 1.0));
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].starts_with("1 of the last 2 touchdowns"), "{}", w[0]);
        assert!(w[1].starts_with("in 1 of the last 2 stances"), "{}", w[1]);
        let quiet = warnings(&run(vec![hop(0, 1.0, 0)], 1, 0.0));
        assert!(quiet.is_empty(), "{quiet:?}");
        let pulling = warnings(&run(vec![hop(0, 1.0, 0)], 1, -2.0));
        assert!(pulling[0].contains("pulling ground"), "{pulling:?}");
    }

    #[test]
    fn no_gait_serialises_every_gait_field_as_null() {
        let fields = serde_json::to_value(GaitFields::from(None)).unwrap();
        let map = fields.as_object().unwrap();
        assert_eq!(map.len(), 12);
        assert_eq!(map["converged"], false);
        assert!(map
            .iter()
            .filter(|(k, _)| *k != "converged")
            .all(|(_, v)| v.is_null()));
    }
}
