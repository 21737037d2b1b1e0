//! The one renderer of study reports: `--out DIR` writes the report's CSV files and
//! figures, `--json` prints the report as one JSON object (with the `files` written), and
//! otherwise the report's text is printed followed by `wrote FILE` lines; `--quiet` prints
//! nothing but errors.

use crate::cmd::analyze::common::OutputArgs;
use hopsim_studies::Report;

/// Renders `report` as `output` asks.
pub fn render<R: Report>(report: &R, output: &OutputArgs) -> anyhow::Result<()> {
    let files: Vec<String> = match &output.out {
        Some(dir) => hopsim_studies::write_files(dir, &report.files())?
            .iter()
            .map(|p| p.display().to_string())
            .collect(),
        None => Vec::new(),
    };
    if output.json {
        let mut value = hopsim_io::to_json_value(report)?;
        if let Some(map) = value.as_object_mut() {
            map.insert("files".into(), files.into());
        }
        println!("{}", serde_json::to_string_pretty(&value)?);
    } else if !output.quiet {
        print!("{}", report.text());
        for f in &files {
            println!("wrote {f}");
        }
    }
    Ok(())
}
