//! `route.opendrive`: the road file read relative to the scenario file (or, for a shipped
//! scenario, from the shipped roads), imported, and its error placed at the field.

use super::validate::segment_problem;
use super::{file_error, OpenDriveFile, ScenarioError};
use crate::opendrive::{self, ImportedRoad};
use std::path::Path;

/// The road `od` names, the scenario being the file at `scenario` with `text` and
/// `overrides`.
pub(super) fn load(
    od: &OpenDriveFile,
    scenario: &Path,
    text: &str,
    overrides: &[String],
) -> Result<ImportedRoad, ScenarioError> {
    let dir = scenario.parent().unwrap_or(Path::new("."));
    let file = dir.join(&od.file);
    let read = match (file.is_file(), super::library::shipped_road(&od.file)) {
        (false, Some(text)) => opendrive::parse(text, &file),
        _ => opendrive::load(&file),
    };
    read.and_then(|doc| opendrive::import(&doc, od.road.as_deref(), segment_problem))
        .map_err(|source| {
            file_error(
                overrides,
                text,
                "route.opendrive",
                source,
                |line, column, source| ScenarioError::Road {
                    path: scenario.to_owned(),
                    line,
                    column,
                    source: Box::new(source),
                },
            )
        })
}
