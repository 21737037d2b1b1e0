//! `hopsim analyze template`: the impulsive eccentric-wheel template (docs/physics.md §5.1),
//! computed by [`hopsim_studies::template`].

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use hopsim_studies::template::{self as study, AnimalSweepsParams, CargoGridParams, CaseParams};
use hopsim_theory::template::{CargoGrid, TemplateCase, TemplateParams};
use hopsim_theory::AnalysisError;

use super::common::{invalid, OutputArgs};
use crate::cmd::render::render;

/// Parses a Table-3.1 case name (`cargo-1`, `cargo-2`, `wallaby`, `kangaroo-rat`).
fn case_parser() -> impl TypedValueParser<Value = TemplateCase> {
    PossibleValuesParser::new(TemplateCase::ALL.map(TemplateCase::name))
        .map(|name| TemplateCase::from_name(&name).expect("a listed case name"))
}

/// Parameter grids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GridName {
    /// Cargo l/R × φ_TO map of cost of transport and speed (heatmaps).
    Cargo,
    /// Wallaby stride against u/sqrt(g l) over its φ_TO and ΔE ranges.
    Wallaby,
    /// Kangaroo rat stride against u/sqrt(g l) over its φ_TO and ΔE ranges.
    KangarooRat,
    /// Both animal sweeps.
    Animals,
}

impl GridName {
    /// The animals an animal grid sweeps.
    fn animals(self) -> &'static [TemplateCase] {
        match self {
            GridName::Wallaby => &[TemplateCase::Wallaby],
            GridName::KangarooRat => &[TemplateCase::KangarooRat],
            _ => &[TemplateCase::Wallaby, TemplateCase::KangarooRat],
        }
    }
}

/// Run the template for a named case (default cargo-2) or a grid; every parameter can be
/// overridden. Forward is +x; φ is counter-clockwise (docs/analysis.md).
#[derive(Args)]
pub struct TemplateArgs {
    /// Table-3.1 case, default cargo-2 (parameters given as ranges take the midpoint).
    #[arg(long, value_parser = case_parser(), conflicts_with = "grid")]
    pub case: Option<TemplateCase>,
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

fn reject_axis_overrides(axes: &[(&str, bool)]) -> anyhow::Result<()> {
    match axes.iter().find(|(_, given)| *given) {
        Some((name, _)) => invalid(format!(
            "--{name} is a grid axis and cannot be overridden with --grid"
        )),
        None => Ok(()),
    }
}

pub fn run(args: TemplateArgs) -> anyhow::Result<()> {
    let n = args.resolution as usize;
    match args.grid {
        None => {
            let case = args.case.unwrap_or(TemplateCase::Cargo2);
            let params = CaseParams {
                case,
                params: apply_overrides(&args, case.params())?,
                record_trajectory: args.output.out.is_some(),
            };
            render(&study::template_case(&params)?, &args.output)
        }
        Some(GridName::Cargo) => {
            reject_axis_overrides(&[
                ("radius", args.radius.is_some()),
                ("takeoff-angle", args.takeoff_angle.is_some()),
            ])?;
            let params = CargoGridParams {
                base: apply_overrides(&args, CargoGrid::table_3_1_base())?,
                resolution: n,
            };
            let report = study::cargo_grid(&params, &args.output.cell_bars())?;
            render(&report, &args.output)
        }
        Some(grid) => {
            reject_axis_overrides(&[
                ("takeoff-angle", args.takeoff_angle.is_some()),
                ("energy", args.energy.is_some()),
            ])?;
            let animals = grid
                .animals()
                .iter()
                .map(|&case| Ok((case, apply_overrides(&args, case.params())?)))
                .collect::<anyhow::Result<_>>()?;
            let params = AnimalSweepsParams {
                animals,
                energies: n,
            };
            let report = study::animal_sweeps(&params, &args.output.cell_bars())?;
            render(&report, &args.output)
        }
    }
}
