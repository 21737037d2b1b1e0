//! `hopsim analyze template`: the impulsive eccentric-wheel template (physics.md §5.1).

use clap::{Args, ValueEnum};
use hopsim_analysis::template::{
    self, sweep_case, CargoGrid, GridCell, Phase, SweepPoint, TemplateCase, TemplateParams,
    TemplateRun,
};
use hopsim_analysis::AnalysisError;
use hopsim_io::{Cell, CsvTable};
use hopsim_studies::plot::{Heatmap, LinePlot, Series, SeriesStyle, PALETTE};
use serde_json::json;
use std::time::Instant;

use super::common::{self, invalid, num, num_range, nums, OutDir, OutputArgs, Table};

/// Named parameter sets of Table 3.1 (ranges take their midpoints).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum CaseName {
    #[value(name = "cargo-1")]
    Cargo1,
    #[value(name = "cargo-2")]
    Cargo2,
    #[value(name = "wallaby")]
    Wallaby,
    #[value(name = "kangaroo-rat")]
    KangarooRat,
}

impl From<CaseName> for TemplateCase {
    fn from(name: CaseName) -> Self {
        match name {
            CaseName::Cargo1 => TemplateCase::Cargo1,
            CaseName::Cargo2 => TemplateCase::Cargo2,
            CaseName::Wallaby => TemplateCase::Wallaby,
            CaseName::KangarooRat => TemplateCase::KangarooRat,
        }
    }
}

/// Parameter grids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GridName {
    /// Cargo l/R × φ_TO map of cost of transport and speed (heatmaps).
    #[value(name = "cargo")]
    Cargo,
    /// Wallaby stride against u/sqrt(g l) over its φ_TO and ΔE ranges.
    #[value(name = "wallaby")]
    Wallaby,
    /// Kangaroo rat stride against u/sqrt(g l) over its φ_TO and ΔE ranges.
    #[value(name = "kangaroo-rat")]
    KangarooRat,
    /// Both animal sweeps.
    #[value(name = "animals")]
    Animals,
}

/// Run the template for a named case (default cargo-2) or a grid; every parameter can be
/// overridden. Forward is +x; φ is counter-clockwise (docs/analysis.md).
#[derive(Args)]
pub struct TemplateArgs {
    /// Table-3.1 case, default cargo-2 (parameters given as ranges take the midpoint).
    #[arg(long, value_enum, conflicts_with = "grid")]
    pub case: Option<CaseName>,
    /// Run a parameter grid instead of one case.
    #[arg(long, value_enum)]
    pub grid: Option<GridName>,
    /// Grid points per axis (Cargo: N × N cells; animals: N energies × 5 take-off angles).
    #[arg(long, default_value_t = 40, value_parser = clap::value_parser!(u32).range(2..=400))]
    pub resolution: u32,
    /// Foot radius R [m].
    #[arg(long, allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Leg length l (centre of mass to rim) [m]; eccentricity a = R − l.
    #[arg(long, allow_negative_numbers = true)]
    pub leg_length: Option<f64>,
    /// Mass m [kg].
    #[arg(long, allow_negative_numbers = true)]
    pub mass: Option<f64>,
    /// Inertia about the centre of mass I [kg m²].
    #[arg(long, allow_negative_numbers = true)]
    pub inertia: Option<f64>,
    /// Take-off angle φ_TO [rad].
    #[arg(long, allow_negative_numbers = true)]
    pub takeoff_angle: Option<f64>,
    /// Energy added per take-off ΔE [J].
    #[arg(long, allow_negative_numbers = true)]
    pub energy: Option<f64>,
    /// Impulse tilt τ [rad]: ρ = (−sin(φ_TO + τ), cos(φ_TO + τ)).
    #[arg(long, allow_negative_numbers = true)]
    pub tau: Option<f64>,
    /// Number of hops.
    #[arg(long)]
    pub hops: Option<usize>,
    /// Hops averaged at the end of the run (1 … --hops).
    #[arg(long)]
    pub window: Option<usize>,
    /// Gravitational acceleration [m/s²].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f64>,
    /// Convergence tolerance on the relative spread of per-hop speeds in the window.
    #[arg(long, allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    #[command(flatten)]
    pub output: OutputArgs,
}

fn apply_overrides(args: &TemplateArgs, mut p: TemplateParams) -> anyhow::Result<TemplateParams> {
    common::check_all_finite(&[
        ("radius", args.radius),
        ("leg-length", args.leg_length),
        ("mass", args.mass),
        ("inertia", args.inertia),
        ("takeoff-angle", args.takeoff_angle),
        ("energy", args.energy),
        ("tau", args.tau),
        ("gravity", args.gravity),
        ("tolerance", args.tolerance),
    ])?;
    p.radius = args.radius.unwrap_or(p.radius);
    p.leg_length = args.leg_length.unwrap_or(p.leg_length);
    p.mass = args.mass.unwrap_or(p.mass);
    p.inertia = args.inertia.unwrap_or(p.inertia);
    p.takeoff_angle = args.takeoff_angle.unwrap_or(p.takeoff_angle);
    p.energy_input = args.energy.unwrap_or(p.energy_input);
    p.impulse_tilt = args.tau.unwrap_or(p.impulse_tilt);
    p.hops = args.hops.unwrap_or(p.hops);
    p.window = args.window.unwrap_or(p.window);
    p.gravity = args.gravity.unwrap_or(p.gravity);
    p.convergence_tolerance = args.tolerance.unwrap_or(p.convergence_tolerance);
    // `validate` blames `window` when hops < window; when only --hops was given, the
    // number of hops is the value to fix.
    if args.window.is_none() && p.hops < p.window {
        return Err(AnalysisError::invalid(
            "hops",
            p.hops as f64,
            &format!(
                "must be at least the averaging window (`window` = {})",
                p.window
            ),
        )
        .into());
    }
    p.validate()?;
    Ok(p)
}

pub fn run(args: TemplateArgs) -> anyhow::Result<()> {
    match args.grid {
        Some(GridName::Cargo) => run_cargo_grid(&args),
        Some(GridName::Wallaby) => run_animals(&args, &[TemplateCase::Wallaby]),
        Some(GridName::KangarooRat) => run_animals(&args, &[TemplateCase::KangarooRat]),
        Some(GridName::Animals) => {
            run_animals(&args, &[TemplateCase::Wallaby, TemplateCase::KangarooRat])
        }
        None => run_case(&args),
    }
}

fn params_json(p: &TemplateParams) -> serde_json::Value {
    json!({
        "radius_m": p.radius,
        "leg_length_m": p.leg_length,
        "eccentricity_m": p.eccentricity(),
        "mass_kg": p.mass,
        "inertia_kg_m2": p.inertia,
        "takeoff_angle_rad": p.takeoff_angle,
        "energy_input_J": p.energy_input,
        "impulse_tilt_rad": p.impulse_tilt,
        "hops": p.hops,
        "window": p.window,
        "gravity_mps2": p.gravity,
        "convergence_tolerance": p.convergence_tolerance,
    })
}

fn warnings(run: &TemplateRun) -> Vec<String> {
    let mut out = Vec::new();
    if run.min_stance_normal_force_n < 0.0 {
        out.push(format!(
            "the rolling stance needs a pulling ground (min normal force {:.4} N): the template ignores lift-off in stance",
            run.min_stance_normal_force_n
        ));
    }
    let window = &run.hops[run.hops.len().saturating_sub(run.params.window)..];
    let pulling = window
        .iter()
        .filter(|h| h.touchdown_normal_percussion_ns < 0.0)
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
    if let Some(s) = &run.summary {
        if !s.converged {
            out.push(format!(
                "not converged: per-hop speeds in the window differ by {:.2} % (tolerance {:.2} %)",
                100.0 * s.speed_spread,
                100.0 * run.params.convergence_tolerance
            ));
        }
    }
    out
}

fn run_case(args: &TemplateArgs) -> anyhow::Result<()> {
    let case: TemplateCase = args.case.unwrap_or(CaseName::Cargo2).into();
    let params = apply_overrides(args, case.params())?;
    let record = args.output.out.is_some();
    let run = template::simulate(&params, record)?;
    let files = args
        .output
        .write_files(|out| write_case_outputs(out, &run))?;
    let warnings = warnings(&run);
    let s = run.summary.as_ref();
    if args.output.json {
        let value = json!({
            "analysis": "template",
            "case": case.name(),
            "parameters": params_json(&params),
            "gait": s.is_some(),
            "converged": s.is_some_and(|s| s.converged),
            "mean_speed_mps": s.map(|s| s.mean_speed_mps),
            "stride_m": s.map(|s| s.stride_m),
            "hop_frequency_hz": s.map(|s| s.hop_frequency_hz),
            "cost_of_transport": s.map(|s| s.cost_of_transport),
            "dimensionless_speed": s.map(|s| s.dimensionless_speed),
            "froude_number": s.map(|s| s.froude_number),
            "impulse_Ns": s.map(|s| s.impulse_ns),
            "flight_time_s": s.map(|s| s.flight_time_s),
            "touchdown_angle_rad": s.map(|s| s.touchdown_angle_rad),
            "touchdown_loss_J": s.map(|s| s.touchdown_loss_j),
            "speed_spread": s.map(|s| s.speed_spread),
            "hops_completed": run.hops.len(),
            "no_gait_reason": run.no_gait.as_ref().map(|n| n.to_string()),
            "no_gait": run.no_gait,
            "min_stance_normal_force_N": run.min_stance_normal_force_n,
            "warnings": warnings,
            "files": files,
        });
        return common::print_json(&value);
    }
    if args.output.quiet {
        return Ok(());
    }
    let mut t = Table::new(format!(
        "template {} (physics.md §5.1; forward = +x)",
        case.name()
    ));
    t.row(
        "R, l, a",
        nums(&[
            (params.radius, "m"),
            (params.leg_length, "m"),
            (params.eccentricity(), "m"),
        ]),
    )
    .row(
        "m, I",
        nums(&[(params.mass, "kg"), (params.inertia, "kg m²")]),
    )
    .row(
        "φ_TO, τ",
        nums(&[(params.takeoff_angle, "rad"), (params.impulse_tilt, "rad")]),
    )
    .row("ΔE", num(params.energy_input, "J"))
    .row(
        "hops (window)",
        format!("{} ({})", params.hops, params.window),
    );
    print!("{t}");
    match (&run.summary, &run.no_gait) {
        (Some(s), _) => {
            let mut r = Table::new(format!("gait over the last {} hops", params.window));
            r.row("mean speed", num(s.mean_speed_mps, "m/s"))
                .row("stride", num(s.stride_m, "m"))
                .row("hop frequency", num(s.hop_frequency_hz, "Hz"))
                .row("cost of transport", num(s.cost_of_transport, ""))
                .row("u / sqrt(g l)", num(s.dimensionless_speed, ""))
                .row("impulse ‖ζ‖", num(s.impulse_ns, "N s"))
                .row("flight time", num(s.flight_time_s, "s"))
                .row("touchdown angle", num(s.touchdown_angle_rad, "rad"))
                .row("touchdown loss", num(s.touchdown_loss_j, "J"))
                .row(
                    "converged",
                    format!("{} (speed spread {:.2e})", s.converged, s.speed_spread),
                );
            print!("{r}");
        }
        (None, Some(no_gait)) => println!("{no_gait}"),
        (None, None) => println!("no result"),
    }
    for w in &warnings {
        println!("warning: {w}");
    }
    common::print_written(&files);
    Ok(())
}

fn write_case_outputs(out: &mut OutDir, run: &TemplateRun) -> anyhow::Result<()> {
    let p = &run.params;
    let mut traj = CsvTable::new(&[
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
    for s in &run.trajectory {
        let [x, y, phi] = s.state.q;
        let [vx, vy, w] = s.state.u;
        traj.push(vec![
            s.t.into(),
            s.hop.into(),
            s.phase.name().into(),
            x.into(),
            y.into(),
            phi.into(),
            vx.into(),
            vy.into(),
            w.into(),
            template::mechanical_energy(p, &s.state).into(),
        ]);
    }
    out.csv("trajectory.csv", &traj)?;
    let mut hops = CsvTable::new(&[
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
    for h in &run.hops {
        hops.push(vec![
            h.index.into(),
            h.takeoff_time_s.into(),
            h.takeoff_x_m.into(),
            h.takeoff_angular_velocity_rad_s.into(),
            h.impulse_ns.into(),
            h.flight_time_s.into(),
            h.touchdown_angle_rad.into(),
            h.touchdown_loss_j.into(),
            h.touchdown_normal_percussion_ns.into(),
            h.stance_time_s.into(),
            Cell::Text(h.stance_revolutions.to_string()),
            h.stride_m.into(),
            h.period_s.into(),
            (h.stride_m / h.period_s).into(),
        ]);
    }
    out.csv("hops.csv", &hops)?;
    // Centre-of-mass path over the last `window` hops (the converged gait).
    let first_hop = run.hops.len().saturating_sub(p.window);
    let mut plot = LinePlot::new(
        format!(
            "centre of mass, hops {}–{}",
            first_hop + 1,
            run.hops.len().max(first_hop + 1)
        ),
        "x [m]",
        "y [m]",
    );
    for (phase, color, label) in [
        (Phase::Flight, PALETTE[1], "flight"),
        (Phase::Stance, PALETTE[0], "stance"),
    ] {
        let mut points = Vec::new();
        let mut last_hop = None;
        for s in run.trajectory.iter().filter(|s| s.hop >= first_hop) {
            if s.phase == phase {
                if last_hop.is_some_and(|h| h != s.hop) {
                    points.push((f64::NAN, f64::NAN));
                }
                points.push((s.state.q[0], s.state.q[1]));
                last_hop = Some(s.hop);
            } else if last_hop.is_some()
                && points.last().is_some_and(|p: &(f64, f64)| p.0.is_finite())
            {
                points.push((f64::NAN, f64::NAN));
            }
        }
        plot = plot.with_series(Series::line(label, points).color(color));
    }
    out.figure("trajectory", &plot)?;
    let speeds: Vec<(f64, f64)> = run
        .hops
        .iter()
        .map(|h| ((h.index + 1) as f64, h.stride_m / h.period_s))
        .collect();
    let speed_plot = LinePlot::new("per-hop speed (stride / period)", "hop", "speed [m/s]")
        .with_series(Series::line("speed", speeds).style(SeriesStyle::LineAndPoints));
    out.figure("hop_speed", &speed_plot)?;
    Ok(())
}

fn reject_axis_overrides(axes: &[(&str, bool)]) -> anyhow::Result<()> {
    for (name, given) in axes {
        if *given {
            return invalid(format!(
                "--{name} is a grid axis and cannot be overridden with --grid"
            ));
        }
    }
    Ok(())
}

fn run_cargo_grid(args: &TemplateArgs) -> anyhow::Result<()> {
    reject_axis_overrides(&[
        ("radius", args.radius.is_some()),
        ("takeoff-angle", args.takeoff_angle.is_some()),
    ])?;
    let n = args.resolution as usize;
    let mut grid = CargoGrid::table_3_1(n, n);
    let leg = grid.base.leg_length;
    grid.base = apply_overrides(args, grid.base)?;
    if grid.base.leg_length != leg {
        let l = grid.base.leg_length;
        grid.leg_over_radius = hopsim_analysis::numerics::linspace(l / 5.8, l / 0.3, n);
    }
    let started = Instant::now();
    let bar = common::bar(n * n, "Cargo grid", args.output.hide_progress());
    let cells = grid.run(&|| bar.inc(1))?;
    bar.finish_and_clear();
    let elapsed = started.elapsed().as_secs_f64();
    let converged: Vec<&GridCell> = cells.iter().filter(|c| c.converged().is_some()).collect();
    let best_cot = converged.iter().min_by(|a, b| {
        a.converged()
            .unwrap()
            .cost_of_transport
            .total_cmp(&b.converged().unwrap().cost_of_transport)
    });
    let fastest = converged.iter().max_by(|a, b| {
        a.converged()
            .unwrap()
            .mean_speed_mps
            .total_cmp(&b.converged().unwrap().mean_speed_mps)
    });
    let files = args.output.write_files(|out| {
        let mut csv = CsvTable::new(&[
            "leg_over_radius",
            "radius_m",
            "takeoff_angle_rad",
            "gait",
            "converged",
            "mean_speed_mps",
            "stride_m",
            "hop_frequency_hz",
            "cost_of_transport",
            "dimensionless_speed",
            "speed_spread",
            "no_gait_reason",
        ]);
        for c in &cells {
            let s = c.summary.as_ref();
            csv.push(vec![
                c.leg_over_radius.into(),
                c.radius.into(),
                c.takeoff_angle.into(),
                s.is_some().into(),
                s.is_some_and(|s| s.converged).into(),
                s.map(|s| s.mean_speed_mps).into(),
                s.map(|s| s.stride_m).into(),
                s.map(|s| s.hop_frequency_hz).into(),
                s.map(|s| s.cost_of_transport).into(),
                s.map(|s| s.dimensionless_speed).into(),
                s.map(|s| s.speed_spread).into(),
                c.no_gait.clone().map_or(Cell::Empty, Cell::Text),
            ]);
        }
        out.csv("cargo_grid.csv", &csv)?;
        let map = |title: &str, label: &str, f: fn(&template::GaitSummary) -> f64| {
            Heatmap::new(
                title,
                "l / R",
                "φ_TO [rad]",
                label,
                grid.leg_over_radius.clone(),
                grid.takeoff_angles.clone(),
                cells.iter().map(|c| c.converged().map(f)).collect(),
            )
        };
        out.figure(
            "cargo_grid_cost_of_transport",
            &map(
                "Cargo template: cost of transport (blank: no converged gait)",
                "cost of transport",
                |s| s.cost_of_transport,
            ),
        )?;
        out.figure(
            "cargo_grid_speed",
            &map(
                "Cargo template: mean speed (blank: no converged gait)",
                "mean speed [m/s]",
                |s| s.mean_speed_mps,
            ),
        )
    })?;
    let cell_json = |c: &GridCell| {
        let s = c.summary.as_ref();
        json!({
            "leg_over_radius": c.leg_over_radius,
            "radius_m": c.radius,
            "takeoff_angle_rad": c.takeoff_angle,
            "converged": s.is_some_and(|s| s.converged),
            "mean_speed_mps": s.map(|s| s.mean_speed_mps),
            "stride_m": s.map(|s| s.stride_m),
            "hop_frequency_hz": s.map(|s| s.hop_frequency_hz),
            "cost_of_transport": s.map(|s| s.cost_of_transport),
            "no_gait_reason": c.no_gait,
        })
    };
    if args.output.json {
        return common::print_json(&json!({
            "analysis": "template-grid",
            "grid": "cargo",
            "base_parameters": params_json(&grid.base),
            "leg_over_radius": grid.leg_over_radius,
            "takeoff_angles_rad": grid.takeoff_angles,
            "cells_total": cells.len(),
            "cells_with_gait": cells.iter().filter(|c| c.summary.is_some()).count(),
            "cells_converged": converged.len(),
            "elapsed_s": elapsed,
            "min_cost_of_transport": best_cot.map(|c| cell_json(c)),
            "max_speed": fastest.map(|c| cell_json(c)),
            "cells": cells.iter().map(cell_json).collect::<Vec<_>>(),
            "files": files,
        }));
    }
    if args.output.quiet {
        return Ok(());
    }
    let mut t = Table::new(format!("Cargo template grid, {n} × {n} cells (l/R × φ_TO)"));
    t.row(
        "l/R range",
        num_range(grid.leg_over_radius[0], grid.leg_over_radius[n - 1], ""),
    )
    .row(
        "φ_TO range",
        num_range(grid.takeoff_angles[0], grid.takeoff_angles[n - 1], "rad"),
    )
    .row(
        "cells with a gait",
        cells.iter().filter(|c| c.summary.is_some()).count(),
    )
    .row("cells converged", converged.len())
    .row("elapsed", num(elapsed, "s"));
    let describe = |c: &GridCell| {
        let s = c.converged().expect("converged cell");
        format!(
            "CoT {} at {} m/s (l/R {}, R {}, φ_TO {})",
            num(s.cost_of_transport, ""),
            num(s.mean_speed_mps, ""),
            num(c.leg_over_radius, ""),
            num(c.radius, "m"),
            num(c.takeoff_angle, "rad")
        )
    };
    if let Some(c) = best_cot {
        t.row("lowest CoT", describe(c));
    }
    if let Some(c) = fastest {
        t.row("fastest", describe(c));
    }
    print!("{t}");
    common::print_written(&files);
    Ok(())
}

fn run_animals(args: &TemplateArgs, cases: &[TemplateCase]) -> anyhow::Result<()> {
    reject_axis_overrides(&[
        ("takeoff-angle", args.takeoff_angle.is_some()),
        ("energy", args.energy.is_some()),
    ])?;
    const ANGLES: usize = 5;
    let n_energy = args.resolution as usize;
    let started = Instant::now();
    let mut results: Vec<(TemplateCase, TemplateParams, Vec<SweepPoint>)> = Vec::new();
    for &case in cases {
        let base = apply_overrides(args, case.params())?;
        let bar = common::bar(ANGLES * n_energy, case.name(), args.output.hide_progress());
        let points = sweep_case(case, &base, ANGLES, n_energy, &|| bar.inc(1))?;
        bar.finish_and_clear();
        results.push((case, base, points));
    }
    let elapsed = started.elapsed().as_secs_f64();
    let files = args.output.write_files(|out| {
        for (case, _, points) in &results {
            let mut csv = CsvTable::new(&[
                "takeoff_angle_rad",
                "energy_input_J",
                "gait",
                "converged",
                "mean_speed_mps",
                "dimensionless_speed",
                "stride_m",
                "hop_frequency_hz",
                "cost_of_transport",
                "no_gait_reason",
            ]);
            for pt in points {
                let s = pt.summary.as_ref();
                csv.push(vec![
                    pt.takeoff_angle.into(),
                    pt.energy_input.into(),
                    s.is_some().into(),
                    s.is_some_and(|s| s.converged).into(),
                    s.map(|s| s.mean_speed_mps).into(),
                    s.map(|s| s.dimensionless_speed).into(),
                    s.map(|s| s.stride_m).into(),
                    s.map(|s| s.hop_frequency_hz).into(),
                    s.map(|s| s.cost_of_transport).into(),
                    pt.no_gait.clone().map_or(Cell::Empty, Cell::Text),
                ]);
            }
            out.csv(&format!("{}_sweep.csv", case.name()), &csv)?;
            let mut plot = LinePlot::new(
                format!(
                    "{}: stride against dimensionless speed (ΔE {}…{} J; open: not converged)",
                    case.name(),
                    num(case.ranges().energy_input.0, ""),
                    num(case.ranges().energy_input.1, "")
                ),
                "u / sqrt(g l)",
                "stride [m]",
            );
            let mut angles: Vec<f64> = points.iter().map(|p| p.takeoff_angle).collect();
            angles.dedup();
            for (i, phi) in angles.iter().enumerate() {
                let color = PALETTE[i % PALETTE.len()];
                let of = |converged: bool| -> Vec<(f64, f64)> {
                    points
                        .iter()
                        .filter(|p| p.takeoff_angle == *phi)
                        .filter_map(|p| p.summary.as_ref())
                        .filter(|s| s.converged == converged)
                        .map(|s| (s.dimensionless_speed, s.stride_m))
                        .collect()
                };
                plot = plot.with_series(
                    Series::line(format!("φ_TO = {phi:.3}"), of(true))
                        .style(SeriesStyle::LineAndPoints)
                        .color(color),
                );
                let open = of(false);
                if !open.is_empty() {
                    plot = plot.with_series(
                        Series::points("", open)
                            .style(SeriesStyle::Crosses)
                            .color(color)
                            .unlabelled(),
                    );
                }
            }
            out.figure(&format!("{}_stride_vs_speed", case.name()), &plot)?;
        }
        Ok(())
    })?;
    if args.output.json {
        let sweeps: Vec<serde_json::Value> = results
            .iter()
            .map(|(case, base, points)| {
                json!({
                    "case": case.name(),
                    "base_parameters": params_json(base),
                    "points": points.iter().map(|p| {
                        let s = p.summary.as_ref();
                        json!({
                            "takeoff_angle_rad": p.takeoff_angle,
                            "energy_input_J": p.energy_input,
                            "converged": s.is_some_and(|s| s.converged),
                            "mean_speed_mps": s.map(|s| s.mean_speed_mps),
                            "dimensionless_speed": s.map(|s| s.dimensionless_speed),
                            "stride_m": s.map(|s| s.stride_m),
                            "no_gait_reason": p.no_gait,
                        })
                    }).collect::<Vec<_>>(),
                })
            })
            .collect();
        return common::print_json(&json!({
            "analysis": "template-animals",
            "elapsed_s": elapsed,
            "sweeps": sweeps,
            "files": files,
        }));
    }
    if args.output.quiet {
        return Ok(());
    }
    for (case, _, points) in &results {
        let gaits: Vec<_> = points.iter().filter_map(|p| p.summary.as_ref()).collect();
        let converged = gaits.iter().filter(|s| s.converged).count();
        let mut t = Table::new(format!(
            "{} sweep: {} take-off angles × {} energies",
            case.name(),
            ANGLES,
            n_energy
        ));
        t.row("points with a gait", gaits.len())
            .row("converged", converged);
        let range = |f: fn(&template::GaitSummary) -> f64| {
            let lo = gaits.iter().map(|s| f(s)).fold(f64::INFINITY, f64::min);
            let hi = gaits.iter().map(|s| f(s)).fold(f64::NEG_INFINITY, f64::max);
            (!gaits.is_empty()).then_some((lo, hi))
        };
        if let Some((lo, hi)) = range(|s| s.dimensionless_speed) {
            t.row("u / sqrt(g l)", num_range(lo, hi, ""));
        }
        if let Some((lo, hi)) = range(|s| s.stride_m) {
            t.row("stride", num_range(lo, hi, "m"));
        }
        t.row("elapsed (all sweeps)", num(elapsed, "s"));
        print!("{t}");
    }
    common::print_written(&files);
    Ok(())
}
