//! MuJoCo models (MJCF) as scenes: read by `hopsim-mjcf`, written as the equivalent scene
//! text with its notices (docs/mjcf.md, "From MJCF to a scene").

use crate::error::SceneError;
use crate::scene::NOTICE;
use std::path::Path;

/// Whether `path` names a MuJoCo model: its extension is `xml` (any case).
pub fn is_mjcf(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

/// The scene text of the MuJoCo model at `path`: the TOML of `hopsim_mjcf::scene_toml`
/// after its header, one `# notice: …` line for each thing the model holds that the scene
/// leaves out or that has no effect (the reader's notices, then the import's).
pub fn import_mjcf(path: &Path) -> Result<String, SceneError> {
    let model = hopsim_mjcf::read_file(path, &hopsim_mjcf::ReadOptions::default())
        .map_err(|e| SceneError::Import(e.to_string()))?;
    let scene = hopsim_mjcf::scene_toml(&model, &path.display().to_string())
        .map_err(|e| SceneError::Import(format!("{}: {e}", path.display())))?;
    let (header, body) = scene
        .toml
        .split_once('\n')
        .unwrap_or(("", scene.toml.as_str()));
    let mut text = format!("{header}\n");
    let notices = model.notices.iter().map(|n| n.to_string());
    for notice in notices.chain(scene.notices.iter().cloned()) {
        text.push_str(NOTICE);
        text.push_str(&notice.replace('\n', " "));
        text.push('\n');
    }
    text.push_str(body);
    Ok(text)
}
