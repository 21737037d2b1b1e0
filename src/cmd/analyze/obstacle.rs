//! `hopsim analyze obstacle`: energy to get a wheel over a wall (physics.md §5.2).

use clap::Args;
use hopsim_analysis::numerics::{linspace, logspace};
use hopsim_analysis::obstacle::{
    self, region_map_allometric, region_map_inertia_froude, RegionCell, Strategy, Wheel,
};
use hopsim_io::CsvTable;
use hopsim_studies::plot::{CategoryMap, LinePlot, Series, SeriesStyle, BLACK, PALETTE};
use indicatif::ProgressBar;
use serde_json::json;
use std::time::Instant;

use super::common::{self, invalid, num, nums, OutDir, OutputArgs, Table};

/// Costs of rolling, trivial hopping and rotational hopping over a wall of height h, for a
/// wheel at one speed; with --out also cost curves and the region maps (cheapest strategy)
/// over α × Fr and over body mass × speed (allometric wheel).
#[derive(Args)]
pub struct ObstacleArgs {
    /// Wheel mass m [kg].
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub mass: f64,
    /// Wheel radius R [m].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub radius: f64,
    /// Inertia about the centre of mass I [kg m²] (default: α m R²).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "inertia_factor")]
    pub inertia: Option<f64>,
    /// Inertia factor α = I / (m R²) (default 0.5, a solid disc).
    #[arg(long, allow_negative_numbers = true)]
    pub inertia_factor: Option<f64>,
    /// Wall height h [m] (default: 0.2 R).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "height_ratio")]
    pub height: Option<f64>,
    /// Wall height as a fraction of the radius, h / R (default 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub height_ratio: Option<f64>,
    /// Approach speed u_x [m/s] (default: Fr = 1).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "froude")]
    pub speed: Option<f64>,
    /// Froude number Fr = u_x² / (g R) (default 1).
    #[arg(long, allow_negative_numbers = true)]
    pub froude: Option<f64>,
    /// Gravitational acceleration [m/s²].
    #[arg(long, allow_negative_numbers = true, default_value_t = hopsim_analysis::STANDARD_GRAVITY)]
    pub gravity: f64,
    /// h/R values of the region maps (with --out).
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        default_value = "0.1,0.2,0.3,0.4,0.5"
    )]
    pub map_height_ratios: Vec<f64>,
    /// Region-map cells per axis (with --out).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(2..=400))]
    pub resolution: u32,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Axis ranges of the maps.
const ALPHA_RANGE: (f64, f64) = (0.01, 1.0);
const FROUDE_RANGE: (f64, f64) = (0.01, 10.0);
const MASS_RANGE: (f64, f64) = (0.01, 1000.0);
const SPEED_RANGE: (f64, f64) = (0.1, 10.0);

fn wheel_and_case(args: &ObstacleArgs) -> anyhow::Result<(Wheel, f64, f64)> {
    for (name, value) in [
        ("mass", Some(args.mass)),
        ("radius", Some(args.radius)),
        ("inertia", args.inertia),
        ("inertia-factor", args.inertia_factor),
        ("height", args.height),
        ("height-ratio", args.height_ratio),
        ("speed", args.speed),
        ("froude", args.froude),
        ("gravity", Some(args.gravity)),
    ] {
        common::check_finite(name, value)?;
        if let Some(v) = value {
            if v <= 0.0 {
                return invalid(format!("--{name} must be > 0, got {v}"));
            }
        }
    }
    let inertia = args
        .inertia
        .unwrap_or(args.inertia_factor.unwrap_or(0.5) * args.mass * args.radius * args.radius);
    let wheel = Wheel {
        mass: args.mass,
        radius: args.radius,
        inertia,
        gravity: args.gravity,
    };
    wheel.validate()?;
    let height = args
        .height
        .unwrap_or(args.height_ratio.unwrap_or(0.2) * args.radius);
    let speed = args
        .speed
        .unwrap_or_else(|| wheel.speed_from_froude(args.froude.unwrap_or(1.0)));
    if height >= args.radius {
        return invalid(format!(
            "the wall height {height} m must be below the radius {} m",
            args.radius
        ));
    }
    for &ratio in &args.map_height_ratios {
        if !(ratio.is_finite() && ratio > 0.0 && ratio < 1.0) {
            return invalid(format!(
                "--map-height-ratios values must lie in (0, 1), got {ratio}"
            ));
        }
    }
    Ok((wheel, speed, height))
}

pub fn run(args: ObstacleArgs) -> anyhow::Result<()> {
    let (wheel, speed, height) = wheel_and_case(&args)?;
    let cmp = obstacle::compare(&wheel, speed, height)?;
    let unit = wheel.energy_unit();
    let mut timings = Vec::new();
    let files = args.output.write_files(|out| {
        timings = write_maps(&args, &wheel, height, out)?;
        Ok(())
    })?;
    let rot = cmp.rotational_hop.as_ref();
    if args.output.json {
        return common::print_json(&json!({
            "analysis": "obstacle",
            "wheel": {
                "mass_kg": wheel.mass,
                "radius_m": wheel.radius,
                "inertia_kg_m2": wheel.inertia,
                "gravity_mps2": wheel.gravity,
            },
            "speed_mps": speed,
            "height_m": height,
            "froude": cmp.froude,
            "inertia_factor": cmp.inertia_factor,
            "height_ratio": cmp.height_ratio,
            "energy_unit_J": unit,
            "rolling": cmp.rolling,
            "trivial_hop_J": cmp.trivial_hop_j,
            "rotational_hop": cmp.rotational_hop,
            "costs_per_mgr": {
                "rolling": cmp.rolling.cost_j / unit,
                "trivial_hop": cmp.trivial_hop_j / unit,
                "rotational_hop": rot.map(|h| h.cost_j / unit),
            },
            "cheapest": cmp.cheapest,
            "map_timings_s": timings.iter().map(|(name, s)| json!({"map": name, "elapsed_s": s})).collect::<Vec<_>>(),
            "files": files,
        }));
    }
    if args.output.quiet {
        return Ok(());
    }
    let mut t = Table::new("wheel over a wall (physics.md §5.2)");
    t.row(
        "m, R, I",
        nums(&[
            (wheel.mass, "kg"),
            (wheel.radius, "m"),
            (wheel.inertia, "kg m²"),
        ]),
    )
    .row("α = I/(mR²)", num(cmp.inertia_factor, ""))
    .row(
        "speed (Fr)",
        format!("{} (Fr {})", num(speed, "m/s"), num(cmp.froude, "")),
    )
    .row(
        "wall height (h/R)",
        format!("{} ({})", num(height, "m"), num(cmp.height_ratio, "")),
    );
    print!("{t}");
    let mut c = Table::new("cost [J] (in units of m g R)");
    let r = &cmp.rolling;
    c.row(
        "rolling",
        format!(
            "{} ({}): corner {} + landing {} J, climb assist {} J, {} impacts, path {}",
            num(r.cost_j, "J"),
            num(r.cost_j / unit, ""),
            num(r.corner_loss_j, ""),
            num(r.landing_loss_j, ""),
            num(r.climb_assist_j, ""),
            r.impacts,
            r.path.name()
        ),
    )
    .row(
        "trivial hop",
        format!(
            "{} ({})",
            num(cmp.trivial_hop_j, "J"),
            num(cmp.trivial_hop_j / unit, "")
        ),
    );
    match rot {
        Some(h) => c.row(
            "rotational hop",
            format!(
                "{} ({}): braking {} + spin {} + deficit {} J, φ₀ {}, φ̇⁺ {}",
                num(h.cost_j, "J"),
                num(h.cost_j / unit, ""),
                num(h.braking_j, ""),
                num(h.spin_j, ""),
                num(h.deficit_j, ""),
                num(h.takeoff_angle_rad, "rad"),
                num(h.spin_rad_s, "rad/s")
            ),
        ),
        None => c.row("rotational hop", "cannot clear the wall"),
    };
    c.row("cheapest", cmp.cheapest.name());
    print!("{c}");
    for (name, seconds) in &timings {
        println!("map {name}: {}", num(*seconds, "s"));
    }
    common::print_written(&files);
    Ok(())
}

fn region_cells_csv(cells: &[RegionCell], x_name: &str, y_name: &str) -> CsvTable {
    let mut csv = CsvTable::new(&[
        x_name,
        y_name,
        "rolling_per_mgr",
        "trivial_hop_per_mgr",
        "rotational_hop_per_mgr",
        "cheapest",
    ]);
    for c in cells {
        csv.push(vec![
            c.x.into(),
            c.y.into(),
            c.rolling.into(),
            c.trivial_hop.into(),
            c.rotational_hop.into(),
            c.cheapest.name().into(),
        ]);
    }
    csv
}

fn category_map(
    title: String,
    x_label: &str,
    y_label: &str,
    x: Vec<f64>,
    y: Vec<f64>,
    cells: &[RegionCell],
) -> CategoryMap {
    let mut map = CategoryMap::new(
        title,
        x_label,
        y_label,
        Strategy::ALL.iter().map(|s| s.name().to_string()).collect(),
        x,
        y,
        cells.iter().map(|c| Some(c.cheapest.index())).collect(),
    );
    map.colors = Some(vec![PALETTE[0], PALETTE[1], PALETTE[2]]);
    map
}

/// Runs one region map with the progress bar `bar`; records how long it took as `name`.
fn timed_map(
    timings: &mut Vec<(String, f64)>,
    name: String,
    bar: ProgressBar,
    map: impl FnOnce(&ProgressBar) -> hopsim_analysis::Result<Vec<RegionCell>>,
) -> anyhow::Result<Vec<RegionCell>> {
    let started = Instant::now();
    let cells = map(&bar)?;
    bar.finish_and_clear();
    timings.push((name, started.elapsed().as_secs_f64()));
    Ok(cells)
}

fn write_maps(
    args: &ObstacleArgs,
    wheel: &Wheel,
    height: f64,
    out: &mut OutDir,
) -> anyhow::Result<Vec<(String, f64)>> {
    let mut timings = Vec::new();
    // Costs against speed for this wheel and wall.
    let froudes = logspace(FROUDE_RANGE.0, FROUDE_RANGE.1, 120);
    let mut csv = CsvTable::new(&[
        "speed_mps",
        "froude",
        "rolling_J",
        "trivial_hop_J",
        "rotational_hop_J",
        "corner_loss_J",
        "landing_loss_J",
        "climb_assist_J",
        "cheapest",
    ]);
    let mut curves: [Vec<(f64, f64)>; 3] = Default::default();
    for &fr in &froudes {
        let speed = wheel.speed_from_froude(fr);
        let cmp = obstacle::compare(wheel, speed, height)?;
        let rot = cmp.rotational_hop.map(|h| h.cost_j);
        csv.push(vec![
            speed.into(),
            fr.into(),
            cmp.rolling.cost_j.into(),
            cmp.trivial_hop_j.into(),
            rot.into(),
            cmp.rolling.corner_loss_j.into(),
            cmp.rolling.landing_loss_j.into(),
            cmp.rolling.climb_assist_j.into(),
            cmp.cheapest.name().into(),
        ]);
        curves[0].push((speed, cmp.rolling.cost_j));
        curves[1].push((speed, cmp.trivial_hop_j));
        curves[2].push((speed, rot.unwrap_or(f64::NAN)));
    }
    out.csv("costs_vs_speed.csv", &csv)?;
    let [rolling, trivial, mut rotational] = curves;
    // Keep the plot readable: the rotational hop's cost diverges at low speed; cut its curve
    // at twice the largest rolling / trivial-hop cost (the CSV has every value).
    let cap = 2.0
        * rolling
            .iter()
            .chain(&trivial)
            .map(|p| p.1)
            .fold(0.0, f64::max);
    for point in &mut rotational {
        if point.1 > cap {
            point.1 = f64::NAN;
        }
    }
    let plot = LinePlot::new(
        format!(
            "cost to get over a wall: α = {:.3}, h/R = {:.3}, R = {} m",
            wheel.inertia_factor(),
            height / wheel.radius,
            wheel.radius
        ),
        "approach speed u_x [m/s]",
        "cost [J]",
    )
    .with_series(Series::line("rolling", rolling).color(PALETTE[0]))
    .with_series(Series::line("trivial hop", trivial).color(PALETTE[1]))
    .with_series(
        Series::line("rotational hop (cut above 2× the others)", rotational)
            .color(PALETTE[2])
            .style(SeriesStyle::Line),
    );
    out.figure("costs_vs_speed", &plot)?;

    let n = args.resolution as usize;
    let alphas = linspace(ALPHA_RANGE.0, ALPHA_RANGE.1, n);
    let map_froudes = logspace(FROUDE_RANGE.0, FROUDE_RANGE.1, n);
    let masses = logspace(MASS_RANGE.0, MASS_RANGE.1, n);
    let speeds = logspace(SPEED_RANGE.0, SPEED_RANGE.1, n);
    let log10 = |v: &[f64]| v.iter().map(|x| x.log10()).collect::<Vec<_>>();
    let hidden = args.output.hide_progress();
    for &ratio in &args.map_height_ratios {
        let tag = format!("{ratio:.2}").replace('.', "p");
        let cells = timed_map(
            &mut timings,
            format!("alpha_froude h/R={ratio}"),
            common::bar(n * n, &format!("α × Fr, h/R = {ratio}"), hidden),
            |bar| region_map_inertia_froude(ratio, &alphas, &map_froudes, &|| bar.inc(1)),
        )?;
        out.csv(
            &format!("region_alpha_froude_h{tag}.csv"),
            &region_cells_csv(&cells, "inertia_factor", "froude"),
        )?;
        let map = category_map(
            format!("cheapest way over a wall, h/R = {ratio}"),
            "α = I / (m R²)",
            "log10 Fr",
            alphas.clone(),
            log10(&map_froudes),
            &cells,
        );
        out.figure(&format!("region_alpha_froude_h{tag}"), &map)?;

        let cells = timed_map(
            &mut timings,
            format!("allometric h/R={ratio}"),
            common::bar(n * n, &format!("mass × speed, h/R = {ratio}"), hidden),
            |bar| region_map_allometric(ratio, &masses, &speeds, &|| bar.inc(1)),
        )?;
        out.csv(
            &format!("region_mass_speed_h{tag}.csv"),
            &region_cells_csv(&cells, "mass_kg", "speed_mps"),
        )?;
        // Fr = 1 line of the allometric wheel: u = sqrt(g R(m)).
        let fr_one: Vec<(f64, f64)> = masses
            .iter()
            .map(|&m| {
                (
                    m.log10(),
                    (wheel.gravity * obstacle::allometric_radius(m))
                        .sqrt()
                        .log10(),
                )
            })
            .collect();
        let map = category_map(
            format!("cheapest way over a wall of h = {ratio} R(m), allometric wheel"),
            "log10 body mass [kg]",
            "log10 speed [m/s]",
            log10(&masses),
            log10(&speeds),
            &cells,
        )
        .with_overlay(Series::line("Fr = 1", fr_one).color(BLACK));
        out.figure(&format!("region_mass_speed_h{tag}"), &map)?;
    }
    Ok(timings)
}
