//! ASAM OpenSCENARIO 1.0–1.3 (`.xosc`) read as carfollow scenarios: the vehicles, their
//! start and their storyboard's events on the road of the file's OpenDRIVE `LogicFile`,
//! written as carfollow's own scenario text, which then runs as any scenario file does
//! (`carfollow import` writes it out; `check` and `run` read it in memory).
//!
//! The mapping (the book's "OpenSCENARIO" page has the table):
//! - the **ego** (`--ego NAME`, else the entity named `Ego`, `ego`, `hero` or
//!   `ego_vehicle`) is the chase: its `Init` gives its start and its speed (the chase's
//!   cruising speed); its storyboard actions and controllers are read and not applied,
//!   since carfollow's loop drives it, which `check` says in one warning line;
//! - the **lead** (`--lead NAME`, else the nearest vehicle ahead of the ego in its lane at
//!   t = 0) is carfollow's lead, the pickup with the target board; every other vehicle is
//!   an actor of the kind its bounding box is nearest;
//! - each `Event` is an event of the vehicles its maneuver group names, its `StartTrigger`
//!   the event's trigger (see `story.rs` for each condition and action);
//! - the `StopTrigger`'s `SimulationTimeCondition` is the scenario's duration.
//!
//! What carfollow cannot run as the standard defines it is refused in one line naming the
//! file, the line and the element; nothing is dropped silently.

mod distribution;
mod draw;
mod entities;
mod environment;
mod error;
pub mod export;
mod expr;
mod init;
mod story;
mod world;
mod write;
mod xml;

pub use distribution::{
    is_distribution, read_distribution, DistributedParameter, Distribution, Runs, MAX_RUNS,
    STREAM_PREFIX,
};
pub use error::OscError;
pub use expr::evaluate as evaluate_expression;

use std::path::{Path, PathBuf};
use xml::{child, Xml};

/// The names a file's ego goes by when `--ego` does not name it, in the order tried.
pub const EGO_NAMES: [&str; 4] = ["Ego", "ego", "hero", "ego_vehicle"];

/// How an OpenSCENARIO file is read.
#[derive(Clone, Debug, Default)]
pub struct ImportOptions {
    /// The entity that is the chase (default: one of [`EGO_NAMES`]).
    pub ego: Option<String>,
    /// The entity that is the lead (default: the nearest ahead of the ego in its lane).
    pub lead: Option<String>,
    /// `NAME=VALUE` for the file's own `ParameterDeclarations`, in order.
    pub params: Vec<String>,
    /// The run's length, s, given from outside (`import --duration`, or `--set
    /// duration_s=...`): the `StopTrigger` is then not read.
    pub duration_s: Option<f64>,
    /// The folder the written scenario's paths are relative to (default: the file's own).
    pub relative_to: Option<PathBuf>,
}

/// A file read as carfollow scenario text.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The scenario, as a scenario file holds it (TOML).
    pub text: String,
    /// What is read and not applied, one line each.
    pub warnings: Vec<String>,
}

/// Whether `path` names an OpenSCENARIO file (`.xosc`).
pub fn is_openscenario(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xosc"))
}

/// Reads the OpenSCENARIO file at `path`.
pub fn import(path: &Path, options: &ImportOptions) -> Result<Imported, OscError> {
    let text = xml::read_text(path)?;
    let mut xml = Xml::parse(&text, path)?;
    give_params(&mut xml, &options.params)?;
    let root = xml.doc.root_element();
    if root.tag_name().name() != "OpenSCENARIO" {
        return Err(xml.at(
            root,
            format!(
                "<{}>: not an OpenSCENARIO file (its root is <OpenSCENARIO>)",
                root.tag_name().name()
            ),
        ));
    }
    version(&xml, 0.0, "carfollow reads OpenSCENARIO")?;
    if child(root, "ParameterValueDistribution").is_some() {
        return Err(xml.at(
            root,
            "<OpenSCENARIO>: a parameter distribution, not a scenario: run its points with \
             `carfollow sweep`",
        ));
    }
    if child(root, "CatalogDefinition").is_some() || child(root, "Catalog").is_some() {
        return Err(xml.at(
            root,
            "<OpenSCENARIO>: a catalog or a parameter distribution, not a scenario",
        ));
    }
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let catalogs = entities::Catalogs::read(&xml, &dir)?;
    let vehicles = entities::read_entities(&xml, &catalogs)?;
    let road = write::read_road(&xml, &dir)?;
    let ego = choose_ego(&xml, &vehicles, options.ego.as_deref())?;
    let init = init::read_init(&xml, &road.lanes, &ego, &catalogs)?;
    let mut imported = write::scenario(&xml, &vehicles, &road, &ego, init, options, &dir)?;
    // carfollow's own settings, carried by an exported file (`export::carried`).
    let base = options.relative_to.clone().unwrap_or_else(|| dir.clone());
    imported.text = export::carried::apply(&xml, &imported.text, &dir, &base)?;
    Ok(imported)
}

/// Applies `--param NAME=VALUE` to the root's declarations.
fn give_params(xml: &mut Xml, params: &[String]) -> Result<(), OscError> {
    let root = xml.doc.root_element();
    let declared: Vec<String> = child(root, "ParameterDeclarations")
        .map(|d| {
            xml::children(d, "ParameterDeclaration")
                .filter_map(|p| p.attribute("name").map(str::to_string))
                .collect()
        })
        .unwrap_or_default();
    for assignment in params {
        let param = |message: String| OscError::Param {
            assignment: assignment.clone(),
            message,
        };
        let Some((name, value)) = assignment.split_once('=') else {
            return Err(param("expected NAME=VALUE".into()));
        };
        let name = name.trim();
        if !declared.iter().any(|d| d == name) {
            let known = if declared.is_empty() {
                "none".to_string()
            } else {
                declared.join(", ")
            };
            return Err(param(format!(
                "the file declares no parameter `{name}` (it declares: {known})"
            )));
        }
        xml.given.insert(name.to_string(), value.to_string());
    }
    Ok(())
}

/// Refuses a version other than 1.`lowest` to 1.3; the message says `what` reads them
/// (parameter distributions came with 1.1).
fn version(xml: &Xml, lowest: f64, what: &str) -> Result<(), OscError> {
    let root = xml.doc.root_element();
    let header = child(root, "FileHeader")
        .ok_or_else(|| xml.at(root, "<OpenSCENARIO> has no <FileHeader>"))?;
    let major = xml.num(header, "revMajor")?;
    let minor = xml.num(header, "revMinor")?;
    if major != 1.0 || !(lowest..=3.0).contains(&minor) || minor.fract() != 0.0 {
        return Err(xml.at(
            header,
            format!(
                "<FileHeader revMajor=\"{major}\" revMinor=\"{minor}\">: {what} 1.{lowest} to 1.3"
            ),
        ));
    }
    Ok(())
}

/// The entity that is the chase.
fn choose_ego(
    xml: &Xml,
    vehicles: &[entities::Entity],
    given: Option<&str>,
) -> Result<String, OscError> {
    let named = |n: &str| vehicles.iter().any(|v| v.name == n);
    match given {
        Some(name) if named(name) => Ok(name.to_string()),
        Some(name) => Err(OscError::File {
            path: xml.path.clone(),
            message: format!(
                "--ego {name}: no vehicle of that name (the file's: {})",
                names(vehicles)
            ),
        }),
        None => EGO_NAMES
            .iter()
            .find(|n| named(n))
            .map(|n| n.to_string())
            .ok_or_else(|| OscError::File {
                path: xml.path.clone(),
                message: format!(
                    "no ego: no vehicle is named {} (name one with --ego; the file's: {})",
                    EGO_NAMES.join(", "),
                    names(vehicles)
                ),
            }),
    }
}

/// `name` as a file name or a scenario's vehicle name may carry it: ASCII letters, digits,
/// `-` and `_` kept, anything else `-`.
pub fn safe_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// `base`, or `base-2`, `base-3`, ... if `used` has it, added to `used`: names made
/// unique among the vehicles or among one vehicle's events.
fn unique(base: &str, used: &mut Vec<String>) -> String {
    let mut name = base.to_string();
    let mut k = 2;
    while used.contains(&name) {
        name = format!("{base}-{k}");
        k += 1;
    }
    used.push(name.clone());
    name
}

fn names(vehicles: &[entities::Entity]) -> String {
    vehicles
        .iter()
        .map(|v| v.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}
