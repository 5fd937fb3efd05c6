//! The shipped scenario library (`scenarios/*.toml`, `scenarios/targets/*.toml`), compiled
//! in by the build script, so a scenario can be named from anywhere.

use super::{Scenario, ScenarioError};
use std::path::{Path, PathBuf};

mod compiled {
    include!(concat!(env!("OUT_DIR"), "/library.rs"));
}

/// The names of the shipped scenarios (`nist-grounds`, `weave`, ...), in order.
pub fn shipped_scenarios() -> impl Iterator<Item = &'static str> {
    compiled::SCENARIOS.iter().map(|(name, _)| *name)
}

/// The shipped target file a scenario names as `tracker.target` (`targets/NAME.toml`).
fn shipped_target(target: &str) -> Option<&'static str> {
    let name = Path::new(target).file_stem()?.to_str()?;
    let under_targets = Path::new(target).parent() == Some(Path::new("targets"));
    compiled::TARGETS
        .iter()
        .find(|(n, _)| under_targets && *n == name)
        .map(|(_, text)| *text)
}

/// The shipped road file a scenario names as `route.opendrive.file` (`roads/NAME.xodr`).
pub(super) fn shipped_road(file: &str) -> Option<&'static str> {
    let name = Path::new(file).file_stem()?.to_str()?;
    let under_roads = Path::new(file).parent() == Some(Path::new("roads"));
    compiled::ROADS
        .iter()
        .find(|(n, _)| under_roads && *n == name)
        .map(|(_, text)| *text)
}

impl Scenario {
    /// A shipped scenario by name (`scenarios/NAME.toml`, as compiled in), with `--set`
    /// overrides; `None` when no shipped scenario has that name. Errors name the file as
    /// `scenarios/NAME.toml`.
    pub fn shipped(name: &str, overrides: &[String]) -> Option<Result<Scenario, ScenarioError>> {
        let (_, text) = compiled::SCENARIOS.iter().find(|(n, _)| *n == name)?;
        let path = Path::new("scenarios").join(format!("{name}.toml"));
        Some(Scenario::parse(text, &path, overrides, |target| {
            let file = Path::new("scenarios").join(target);
            match shipped_target(target) {
                Some(text) => crate::target::parse(text, &file),
                None => crate::target::load(&file),
            }
        }))
    }

    /// Scenario text (TOML, as a scenario file holds) with `--set` overrides; `origin` is the
    /// name errors give it, and `tracker.target` is read relative to `dir`, or, when no such
    /// file is there, from the shipped targets (`targets/NAME.toml`).
    pub fn from_text(
        text: &str,
        origin: &Path,
        dir: &Path,
        overrides: &[String],
    ) -> Result<Scenario, ScenarioError> {
        Scenario::parse(text, origin, overrides, |target| target_in(dir, target))
    }
}

/// The target file `target` relative to `dir`, or, when no such file is there, the shipped
/// target of that name (`targets/NAME.toml`).
pub(super) fn target_in(
    dir: &Path,
    target: &str,
) -> Result<tracker::TargetModel, crate::target::TargetFileError> {
    let file: PathBuf = dir.join(target);
    match (file.is_file(), shipped_target(target)) {
        (false, Some(text)) => crate::target::parse(text, &file),
        _ => crate::target::load(&file),
    }
}
