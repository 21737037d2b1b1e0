//! Energy to get a wheel over a wall (docs/physics.md §5.2): the cost of rolling, of a trivial
//! hop and of a rotational hop at one operating point; optionally the costs against speed
//! and the maps of the cheapest strategy over `α × Fr` and over body mass × speed.

use crate::plot::{CategoryMap, LinePlot, Series, SeriesStyle, BLACK, PALETTE};
use crate::progress::Progress;
use crate::report::{num, nums, Report, ReportFile, TextTable};
use crate::Result;
use hopsim_io::CsvTable;
use hopsim_theory::grid::CellDone;
use hopsim_theory::numerics::{linspace, logspace};
use hopsim_theory::obstacle::{
    allometric_radius, compare_strategies, region_map_allometric, region_map_inertia_froude,
    RegionCell, Strategy, StrategyComparison, Wheel,
};
use hopsim_theory::AnalysisError;
use serde::Serialize;
use std::time::Instant;

/// Axis ranges of the maps: inertia factor `α`, Froude number, body mass [kg], speed [m/s].
const ALPHA_RANGE: (f64, f64) = (0.01, 1.0);
const FROUDE_RANGE: (f64, f64) = (0.01, 10.0);
const MASS_RANGE: (f64, f64) = (0.01, 1000.0);
const SPEED_RANGE: (f64, f64) = (0.1, 10.0);
/// Points of the costs-against-speed curves.
const CURVE_POINTS: usize = 120;

/// The operating point, and the maps to draw.
#[derive(Clone, Debug)]
pub struct ObstacleParams {
    /// The wheel.
    pub wheel: Wheel,
    /// Approach speed `u_x` [m/s].
    pub speed_mps: f64,
    /// Wall height `h` [m].
    pub height_m: f64,
    /// The maps (None: only the operating point).
    pub maps: Option<MapParams>,
}

/// The region maps: one pair per wall height.
#[derive(Clone, Debug)]
pub struct MapParams {
    /// Wall heights `h/R`, each in (0, 1).
    pub height_ratios: Vec<f64>,
    /// Cells per axis.
    pub resolution: usize,
}

/// The three costs in units of `m g R`.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CostsPerMgr {
    pub rolling: f64,
    pub trivial_hop: f64,
    /// None when the rotational hop cannot clear the wall.
    pub rotational_hop: Option<f64>,
}

impl From<&StrategyComparison> for CostsPerMgr {
    fn from(c: &StrategyComparison) -> Self {
        let unit = c.energy_unit_j;
        CostsPerMgr {
            rolling: c.rolling.cost_j / unit,
            trivial_hop: c.trivial_hop_j / unit,
            rotational_hop: c.rotational_hop.map(|h| h.cost_j / unit),
        }
    }
}

/// How long one region map took.
#[derive(Clone, Debug, Serialize)]
pub struct MapTiming {
    /// `alpha_froude h/R=…` or `allometric h/R=…`.
    pub map: String,
    pub elapsed_s: f64,
}

/// The two region maps of one wall height.
#[derive(Clone, Debug)]
pub struct RegionMaps {
    /// `h/R`.
    pub height_ratio: f64,
    /// Cells over `α × Fr`, `Fr` outer.
    pub inertia_froude: Vec<RegionCell>,
    /// Cells over body mass × speed, speed outer.
    pub mass_speed: Vec<RegionCell>,
}

/// The costs against speed and the region maps.
#[derive(Clone, Debug)]
pub struct Maps {
    /// `(Fr, the strategies)` at `CURVE_POINTS` Froude numbers `0.01 … 10`.
    pub costs_vs_speed: Vec<(f64, StrategyComparison)>,
    /// Axes of the region maps.
    pub inertia_factors: Vec<f64>,
    pub froudes: Vec<f64>,
    pub masses_kg: Vec<f64>,
    pub speeds_mps: Vec<f64>,
    /// One pair of maps per wall height.
    pub regions: Vec<RegionMaps>,
}

/// The study's result.
#[derive(Debug, Serialize)]
pub struct ObstacleReport {
    analysis: &'static str,
    /// The wheel.
    pub wheel: Wheel,
    /// The strategies at the operating point.
    #[serde(flatten)]
    pub comparison: StrategyComparison,
    /// Their costs in units of `m g R`.
    pub costs_per_mgr: CostsPerMgr,
    /// How long each region map took.
    #[serde(rename = "map_timings_s")]
    pub map_timings: Vec<MapTiming>,
    /// The maps, when asked for.
    #[serde(skip)]
    pub maps: Option<Maps>,
}

/// Compares the strategies at the operating point and computes the maps asked for.
pub fn obstacle(p: &ObstacleParams, progress: &dyn Progress) -> Result<ObstacleReport> {
    let ratios = p.maps.iter().flat_map(|m| &m.height_ratios);
    if let Some(&bad) = ratios.into_iter().find(|r| !(**r > 0.0 && **r < 1.0)) {
        Err(AnalysisError::invalid(
            "map-height-ratios",
            bad,
            "each must lie in (0, 1)",
        ))?;
    }
    let comparison = compare_strategies(&p.wheel, p.speed_mps, p.height_m)?;
    let mut timed = TimedMaps {
        progress,
        timings: Vec::new(),
    };
    let maps = match &p.maps {
        Some(m) => Some(maps(&p.wheel, p.height_m, m, &mut timed)?),
        None => None,
    };
    Ok(ObstacleReport {
        analysis: "obstacle",
        wheel: p.wheel,
        costs_per_mgr: (&comparison).into(),
        comparison,
        map_timings: timed.timings,
        maps,
    })
}

/// Runs region maps one after the other, each a progress task, and times them.
struct TimedMaps<'a> {
    progress: &'a dyn Progress,
    timings: Vec<MapTiming>,
}

impl TimedMaps<'_> {
    /// Runs `map` as a task of `cells` cells called `label`; records its time as `name`.
    fn run(
        &mut self,
        name: String,
        label: &str,
        cells: usize,
        map: impl FnOnce(CellDone<'_>) -> hopsim_theory::Result<Vec<RegionCell>>,
    ) -> Result<Vec<RegionCell>> {
        let started = Instant::now();
        let cells = {
            let tick = self.progress.task(cells, label);
            map(&*tick)?
        };
        self.timings.push(MapTiming {
            map: name,
            elapsed_s: started.elapsed().as_secs_f64(),
        });
        Ok(cells)
    }
}

fn maps(wheel: &Wheel, height: f64, p: &MapParams, timed: &mut TimedMaps<'_>) -> Result<Maps> {
    let costs_vs_speed = logspace(FROUDE_RANGE.0, FROUDE_RANGE.1, CURVE_POINTS)
        .into_iter()
        .map(|fr| {
            let speed = wheel.speed_from_froude(fr);
            Ok((fr, compare_strategies(wheel, speed, height)?))
        })
        .collect::<Result<Vec<_>>>()?;
    let n = p.resolution;
    let mut maps = Maps {
        costs_vs_speed,
        inertia_factors: linspace(ALPHA_RANGE.0, ALPHA_RANGE.1, n),
        froudes: logspace(FROUDE_RANGE.0, FROUDE_RANGE.1, n),
        masses_kg: logspace(MASS_RANGE.0, MASS_RANGE.1, n),
        speeds_mps: logspace(SPEED_RANGE.0, SPEED_RANGE.1, n),
        regions: Vec::with_capacity(p.height_ratios.len()),
    };
    for &ratio in &p.height_ratios {
        let inertia_froude = timed.run(
            format!("alpha_froude h/R={ratio}"),
            &format!("α × Fr, h/R = {ratio}"),
            n * n,
            |tick| region_map_inertia_froude(ratio, &maps.inertia_factors, &maps.froudes, tick),
        )?;
        let mass_speed = timed.run(
            format!("allometric h/R={ratio}"),
            &format!("mass × speed, h/R = {ratio}"),
            n * n,
            |tick| region_map_allometric(ratio, &maps.masses_kg, &maps.speeds_mps, tick),
        )?;
        maps.regions.push(RegionMaps {
            height_ratio: ratio,
            inertia_froude,
            mass_speed,
        });
    }
    Ok(maps)
}

/// The curve of the rotational hop's cost cut (set to NaN) above twice the largest cost of
/// rolling and of the trivial hop, which keeps the plot readable where the rotational hop's
/// cost diverges at low speed (the CSV has every value).
pub fn cut_rotational_curve(
    rolling: &[(f64, f64)],
    trivial: &[(f64, f64)],
    rotational: &mut [(f64, f64)],
) {
    let cap = 2.0
        * rolling
            .iter()
            .chain(trivial)
            .map(|p| p.1)
            .fold(0.0, f64::max);
    for point in rotational.iter_mut().filter(|p| p.1 > cap) {
        point.1 = f64::NAN;
    }
}

/// `0.20` → `0p20`: the wall height in file names.
fn height_tag(ratio: f64) -> String {
    format!("{ratio:.2}").replace('.', "p")
}

fn log10(values: &[f64]) -> Vec<f64> {
    values.iter().map(|x| x.log10()).collect()
}

fn region_csv(cells: &[RegionCell], x_name: &str, y_name: &str) -> CsvTable {
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
    (x_label, x): (&str, Vec<f64>),
    (y_label, y): (&str, Vec<f64>),
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

impl ObstacleReport {
    fn costs_csv(maps: &Maps) -> CsvTable {
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
        for (froude, c) in &maps.costs_vs_speed {
            csv.push(vec![
                c.speed_mps.into(),
                (*froude).into(),
                c.rolling.cost_j.into(),
                c.trivial_hop_j.into(),
                c.rotational_hop.map(|h| h.cost_j).into(),
                c.rolling.corner_loss_j.into(),
                c.rolling.landing_loss_j.into(),
                c.rolling.climb_assist_j.into(),
                c.cheapest.name().into(),
            ]);
        }
        csv
    }

    fn costs_plot(&self, maps: &Maps) -> LinePlot {
        let curve = |cost: fn(&StrategyComparison) -> f64| -> Vec<(f64, f64)> {
            maps.costs_vs_speed
                .iter()
                .map(|(_, c)| (c.speed_mps, cost(c)))
                .collect()
        };
        let rolling = curve(|c| c.rolling.cost_j);
        let trivial = curve(|c| c.trivial_hop_j);
        let mut rotational = curve(|c| c.rotational_hop.map_or(f64::NAN, |h| h.cost_j));
        cut_rotational_curve(&rolling, &trivial, &mut rotational);
        LinePlot::new(
            format!(
                "cost to get over a wall: α = {:.3}, h/R = {:.3}, R = {} m",
                self.wheel.inertia_factor(),
                self.comparison.height_m / self.wheel.radius,
                self.wheel.radius
            ),
            "approach speed u_x (m/s)",
            "cost (J)",
        )
        .with_series(Series::line("rolling", rolling).color(PALETTE[0]))
        .with_series(Series::line("trivial hop", trivial).color(PALETTE[1]))
        .with_series(
            Series::line("rotational hop (cut above 2× the others)", rotational)
                .color(PALETTE[2])
                .style(SeriesStyle::Line),
        )
    }

    fn region_files(&self, maps: &Maps, r: &RegionMaps) -> [ReportFile; 4] {
        let (ratio, tag) = (r.height_ratio, height_tag(r.height_ratio));
        let alpha_froude = category_map(
            format!("cheapest way over a wall, h/R = {ratio}"),
            (
                "inertia factor α = I / (m R²)",
                maps.inertia_factors.clone(),
            ),
            (
                "log10 of Froude number Fr = u² / (g R)",
                log10(&maps.froudes),
            ),
            &r.inertia_froude,
        );
        // Fr = 1 line of the allometric wheel: u = sqrt(g R(m)).
        let fr_one = maps
            .masses_kg
            .iter()
            .map(|&m| {
                let speed = (self.wheel.gravity * allometric_radius(m)).sqrt();
                (m.log10(), speed.log10())
            })
            .collect();
        let mass_speed = category_map(
            format!("cheapest way over a wall of h = {ratio} R(m), allometric wheel"),
            ("log10 of body mass (kg)", log10(&maps.masses_kg)),
            ("log10 of approach speed (m/s)", log10(&maps.speeds_mps)),
            &r.mass_speed,
        )
        .with_overlay(Series::line("Fr = 1", fr_one).color(BLACK));
        [
            ReportFile::csv(
                format!("region_alpha_froude_h{tag}.csv"),
                region_csv(&r.inertia_froude, "inertia_factor", "froude"),
            ),
            ReportFile::figure(format!("region_alpha_froude_h{tag}"), alpha_froude),
            ReportFile::csv(
                format!("region_mass_speed_h{tag}.csv"),
                region_csv(&r.mass_speed, "mass_kg", "speed_mps"),
            ),
            ReportFile::figure(format!("region_mass_speed_h{tag}"), mass_speed),
        ]
    }
}

impl Report for ObstacleReport {
    fn text(&self) -> String {
        let (w, cmp) = (&self.wheel, &self.comparison);
        let unit = cmp.energy_unit_j;
        let mut t = TextTable::new("wheel over a wall (docs/physics.md §5.2)");
        t.row(
            "m, R, I",
            nums(&[(w.mass, "kg"), (w.radius, "m"), (w.inertia, "kg m²")]),
        )
        .row("α = I/(mR²)", num(cmp.inertia_factor, ""))
        .row(
            "speed (Fr)",
            format!("{} (Fr {})", num(cmp.speed_mps, "m/s"), num(cmp.froude, "")),
        )
        .row(
            "wall height (h/R)",
            format!("{} ({})", num(cmp.height_m, "m"), num(cmp.height_ratio, "")),
        );
        let mut c = TextTable::new("cost [J] (in units of m g R)");
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
        match &cmp.rotational_hop {
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
        let mut text = format!("{t}{c}");
        for m in &self.map_timings {
            text += &format!("map {}: {}\n", m.map, num(m.elapsed_s, "s"));
        }
        text
    }

    fn files(&self) -> Vec<ReportFile> {
        let Some(maps) = &self.maps else {
            return Vec::new();
        };
        let mut files = vec![
            ReportFile::csv("costs_vs_speed.csv", Self::costs_csv(maps)),
            ReportFile::figure("costs_vs_speed", self.costs_plot(maps)),
        ];
        for r in &maps.regions {
            files.extend(self.region_files(maps, r));
        }
        files
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rotational_curve_is_cut_above_twice_the_others() {
        let rolling = [(0.0, 1.0), (1.0, 3.0)];
        let trivial = [(0.0, 2.0), (1.0, 2.0)];
        let mut rotational = [(0.0, 6.5), (1.0, 6.0), (2.0, f64::NAN)];
        cut_rotational_curve(&rolling, &trivial, &mut rotational);
        assert!(rotational[0].1.is_nan());
        assert_eq!(rotational[1], (1.0, 6.0));
        assert!(rotational[2].1.is_nan());
    }

    #[test]
    fn height_tags_name_files_with_two_decimals() {
        assert_eq!(height_tag(0.2), "0p20");
        assert_eq!(height_tag(0.125), "0p12");
    }

    #[test]
    fn costs_are_reported_per_mgr_and_the_maps_only_when_asked() {
        let wheel = Wheel {
            mass: 2.0,
            radius: 0.5,
            inertia: 0.25,
            gravity: 9.81,
        };
        let mut p = ObstacleParams {
            wheel,
            speed_mps: wheel.speed_from_froude(1.0),
            height_m: 0.1,
            maps: None,
        };
        let plain = obstacle(&p, &crate::progress::Silent).unwrap();
        assert!((plain.costs_per_mgr.trivial_hop - 0.2).abs() < 1e-12);
        assert!(plain.map_timings.is_empty() && plain.files().is_empty());
        p.maps = Some(MapParams {
            height_ratios: vec![0.2, 0.3],
            resolution: 2,
        });
        let report = obstacle(&p, &crate::progress::Silent).unwrap();
        let names: Vec<&str> = report.map_timings.iter().map(|m| m.map.as_str()).collect();
        assert_eq!(
            names,
            [
                "alpha_froude h/R=0.2",
                "allometric h/R=0.2",
                "alpha_froude h/R=0.3",
                "allometric h/R=0.3"
            ]
        );
        assert_eq!(report.files().len(), 2 + 2 * 4);
        let maps = report.maps.as_ref().unwrap();
        assert_eq!(maps.costs_vs_speed.len(), CURVE_POINTS);
        assert_eq!(maps.regions[1].mass_speed.len(), 4);
    }
}
