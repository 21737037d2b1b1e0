//! `hopsim import MODEL.xml -o SCENE.toml`: a MuJoCo model (MJCF) as the equivalent scene
//! file (docs/mjcf.md), checked before it is written, atomically.

use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

use super::exit;

/// A MuJoCo model and where its scene goes.
#[derive(Args)]
pub struct ImportArgs {
    /// The MuJoCo model (MJCF, .xml) of a planar mechanism.
    pub model: PathBuf,
    /// The scene file to write (TOML); without it the scene is printed.
    #[arg(short, long, value_name = "SCENE.toml")]
    pub output: Option<PathBuf>,
}

pub fn run(args: ImportArgs) -> anyhow::Result<ExitCode> {
    let invalid = |err: &dyn std::fmt::Display| {
        eprintln!("error: {err}");
        Ok(ExitCode::from(exit::INVALID_INPUT))
    };
    if let Some(output) = &args.output {
        let same = match (
            std::path::absolute(output),
            std::path::absolute(&args.model),
        ) {
            (Ok(a), Ok(b)) => a == b,
            _ => *output == args.model,
        };
        if same {
            return invalid(&format!(
                "--output {}: that is the model file; choose another path",
                output.display()
            ));
        }
    }
    let text = match hopsim_scene::import_mjcf(&args.model) {
        Ok(text) => text,
        Err(err) => return invalid(&err),
    };
    // The scene the file will hold must load as it is.
    let named = args.output.clone().unwrap_or_else(|| args.model.clone());
    let scene = match hopsim_scene::parse(&text, &named, &[]) {
        Ok(scene) => scene,
        Err(err) => return invalid(&err),
    };
    match &args.output {
        None => print!("{text}"),
        Some(path) => {
            hopsim_io::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
            eprintln!(
                "{}: {} bodies, {} coordinates ({}), written to {}",
                args.model.display(),
                scene.model.bodies().len(),
                scene.coordinates.len(),
                scene.coordinates.join(", "),
                path.display()
            );
        }
    }
    for notice in &scene.notices {
        eprintln!("notice: {notice}");
    }
    Ok(ExitCode::SUCCESS)
}
