//! The one renderer of study reports: `--out DIR` writes the report's CSV files and
//! figures, tables first; `--json` prints the report as one JSON object (with the `files`
//! written and any `missing_figures`), and otherwise the report's text is printed followed
//! by `wrote FILE` lines; `--quiet` prints nothing but errors and warnings. A figure that
//! cannot be drawn is a warning on stderr naming its missing files, not a failure: the
//! tables are written and the exit code stays that of the study.

use crate::cmd::analyze::common::OutputArgs;
use hopsim_studies::{Report, WrittenFiles};

/// Renders `report` as `output` asks.
pub fn render<R: Report>(report: &R, output: &OutputArgs) -> anyhow::Result<()> {
    let written = match &output.out {
        Some(dir) => hopsim_studies::write_files(dir, &report.files())?,
        None => WrittenFiles::default(),
    };
    for missing in &written.missing_figures {
        eprintln!("warning: {missing}; the tables are written");
    }
    let files: Vec<String> = (written.files.iter())
        .map(|p| p.display().to_string())
        .collect();
    if output.json {
        let mut value = hopsim_io::to_json_value(report)?;
        if let Some(map) = value.as_object_mut() {
            map.insert("files".into(), files.into());
            if !written.missing_figures.is_empty() {
                let missing = hopsim_io::to_json_value(&written.missing_figures)?;
                map.insert("missing_figures".into(), missing);
            }
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
