//! The validated sweep: its grid of points, their stable ids, and shards of the grid.
//!
//! **Grid order.** Scenarios in the file's order; within a scenario, the axis product with the
//! first axis (in sorted path order) outermost; the seed innermost, so a point's seeds are
//! neighbours. The order is a pure function of the file.
//!
//! **Ids.** A point's id is the 64-bit FNV-1a hash, in hex, of its canonical description
//! (`weave seed=1 tracker.lambda=0.5`) and the sweep's common overrides: it does not depend on
//! the machine, the run, the shard or the Rust version, and it changes when the experiment does.

use super::file::{flatten_axes, Roles, SweepFile, SweepScenario};
use super::SweepError;
use sim_core::line_column;
use sim_core::openscenario::is_openscenario;
use sim_core::{from_toml_naming_field, locate_field, planning_key, Plan, Scenario, ScenarioError};
use std::path::{Path, PathBuf};

/// The most points a sweep may have.
const MAX_POINTS: usize = 1_000_000;

/// One parameter axis: a dotted scenario path and its values, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// Dotted path, as `--set` takes it (`tracker.lambda`).
    pub path: String,
    /// The values, in the file's order (a range ascending).
    pub values: Vec<toml::Value>,
}

/// One point of the grid: a scenario, a seed and one value per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Position in the grid order (0-based).
    pub index: usize,
    /// Stable id (16 hex digits).
    pub id: String,
    /// Index into [`Sweep::scenarios`].
    pub scenario: usize,
    /// The scenario's name.
    pub scenario_name: String,
    /// The seed.
    pub seed: u64,
    /// `(axis path, value)` for each axis, in axis order.
    pub params: Vec<(String, toml::Value)>,
}

impl Point {
    /// `weave seed=1 tracker.lambda=0.5`.
    pub fn describe(&self) -> String {
        let mut s = format!("{} seed={}", self.scenario_name, self.seed);
        for (path, value) in &self.params {
            s.push_str(&format!(" {path}={value}"));
        }
        s
    }

    /// Every override of this point, in the order applied: the common ones, the seed, then
    /// the axis values (but the OpenSCENARIO parameters, see [`Point::osc_params`]).
    pub fn overrides(&self, common: &[String]) -> Vec<String> {
        let mut all = common.to_vec();
        all.push(format!("seed={}", self.seed));
        all.extend(
            self.params
                .iter()
                .filter(|(p, _)| !p.starts_with(OSC_PARAM))
                .map(|(p, v)| format!("{p}={v}")),
        );
        all
    }

    /// The values of the OpenSCENARIO file's own parameters at this point (a parameter
    /// distribution's run), as `--param NAME=VALUE` takes them: its params named
    /// `$NAME`.
    pub fn osc_params(&self) -> Vec<String> {
        self.params
            .iter()
            .filter_map(|(p, v)| {
                let name = p.strip_prefix(OSC_PARAM)?;
                let value = match v {
                    toml::Value::String(s) => s.clone(),
                    other => other.to_string(),
                };
                Some(format!("{name}={value}"))
            })
            .collect()
    }
}

/// How a point names an OpenSCENARIO parameter among its params (`$EgoSpeed`), as the
/// standard refers to one: a parameter distribution's points set these, not fields.
pub const OSC_PARAM: &str = "$";

/// A sweep's scenario loaded with a point's `overrides` and, for an OpenSCENARIO file,
/// its own parameters' values `osc_params` (`NAME=VALUE`).
pub(super) fn load_scenario(
    scenario: &SweepScenario,
    overrides: &[String],
    osc_params: Vec<String>,
) -> Result<Scenario, ScenarioError> {
    if is_openscenario(&scenario.path) {
        let options = sim_core::openscenario::ImportOptions {
            params: osc_params,
            ego: scenario.roles.ego.clone(),
            lead: scenario.roles.lead.clone(),
            ..Default::default()
        };
        Scenario::load_openscenario(&scenario.path, overrides, &options)
    } else {
        Scenario::from_file_text(&scenario.text, &scenario.path, overrides)
    }
}

/// A shard: the `index`-th (0-based) of `count` round-robin slices of the grid order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 0-based slice number, `< count`.
    pub index: usize,
    /// Number of slices, at least 1.
    pub count: usize,
}

impl Shard {
    /// Whether the point at grid position `index` is in this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.count == self.index
    }

    /// `results-shard-I-of-N.jsonl`.
    pub fn file_name(&self) -> String {
        format!("results-shard-{}-of-{}.jsonl", self.index, self.count)
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("`{s}`: expected I/N with 0 <= I < N (I is 0-based)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// A validated sweep: its scenarios, seeds, common overrides, axes and the grid.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The sweep file.
    pub path: PathBuf,
    /// The scenarios, in the file's order.
    pub scenarios: Vec<SweepScenario>,
    /// The seeds, in the file's order.
    pub seeds: Vec<u64>,
    /// Common overrides: the file's `set`, then the command line's.
    pub set: Vec<String>,
    /// The axes, in sorted path order.
    pub axes: Vec<Axis>,
    /// Every point, in grid order.
    pub points: Vec<Point>,
    /// The OpenSCENARIO parameter distribution the points are the runs of, when the sweep
    /// file is one (`carfollow sweep FILE.xosc`).
    pub distribution: Option<sim_core::openscenario::Distribution>,
    /// How many plans its check built: one per [`planning_key`] (0 for a sweep loaded
    /// without planning).
    pub plans: usize,
    /// What the results are results of: the 64-bit FNV-1a hash, in hex, of the sweep file's
    /// text, the command line's overrides, and the text of every scenario and target file
    /// its points read. `--resume` refuses a folder whose results have another.
    pub hash: String,
}

impl Sweep {
    /// Reads and validates a sweep file; `extra_set` are command-line overrides applied after
    /// the file's `set`. Each scenario file is read once, and every point's scenario is
    /// loaded with its overrides and planned (one point of each [`planning_key`]: the others
    /// plan alike), so nothing runs unless every point can.
    pub fn load(path: &Path, extra_set: &[String]) -> Result<Sweep, SweepError> {
        Sweep::read(path, extra_set, &Roles::default(), true)
    }

    /// [`Sweep::load`] with the chase and the lead of its OpenSCENARIO scenarios named
    /// (`sweep --ego --lead`); refused for a sweep of none.
    pub fn load_as(path: &Path, extra_set: &[String], roles: &Roles) -> Result<Sweep, SweepError> {
        Sweep::read(path, extra_set, roles, true)
    }

    /// [`Sweep::load`] for a sweep already checked (a sweep worker, started by the sweep
    /// that checked it): every point's scenario is loaded, for the hash, but not planned.
    pub fn load_checked(
        path: &Path,
        extra_set: &[String],
        roles: &Roles,
    ) -> Result<Sweep, SweepError> {
        Sweep::read(path, extra_set, roles, false)
    }

    fn read(
        path: &Path,
        extra_set: &[String],
        roles: &Roles,
        plan: bool,
    ) -> Result<Sweep, SweepError> {
        if sim_core::openscenario::is_openscenario(path) {
            return Sweep::read_distribution(path, extra_set, roles, plan);
        }
        Sweep::read_file(path, extra_set, roles, plan)
    }

    /// [`Sweep::read`] of a sweep file.
    fn read_file(
        path: &Path,
        extra_set: &[String],
        roles: &Roles,
        plan: bool,
    ) -> Result<Sweep, SweepError> {
        let text = std::fs::read_to_string(path).map_err(|error| SweepError::Io {
            path: path.to_owned(),
            action: "cannot read the sweep",
            error,
        })?;
        let at = |field: &str| line_column(&text, locate_field(&text, field));
        let invalid = |field: &str, message: String| {
            let (line, column) = at(field);
            SweepError::Invalid {
                path: path.to_owned(),
                line,
                column,
                field: field.to_string(),
                message,
            }
        };
        // The field a mistake is about is named, as a scenario's errors name it.
        let raw: SweepFile = from_toml_naming_field(&text).map_err(|(e, message)| {
            let (line, column) = line_column(&text, e.span().map_or(0, |s| s.start));
            SweepError::Parse {
                path: path.to_owned(),
                line,
                column,
                message,
            }
        })?;

        if raw.scenarios.is_empty() {
            return Err(invalid(
                "scenarios",
                "needs at least one scenario file".into(),
            ));
        }
        if raw.seeds.is_empty() {
            return Err(invalid("seeds", "needs at least one seed".into()));
        }
        if let Some(s) = raw
            .seeds
            .iter()
            .enumerate()
            .find_map(|(i, s)| raw.seeds[..i].contains(s).then_some(s))
        {
            return Err(invalid("seeds", format!("lists seed {s} twice")));
        }
        let axes: Vec<Axis> = flatten_axes(&raw.axes)
            .map_err(|(p, m)| invalid(&format!("axes.{p}"), m))?
            .into_iter()
            .map(|(path, values)| Axis { path, values })
            .collect();
        if let Some(a) = axes.iter().find(|a| a.path == "seed") {
            return Err(invalid(
                &format!("axes.{}", a.path),
                "is not an axis: list the seeds in `seeds`".into(),
            ));
        }
        // Each value once: a repeated value would be two points of one id.
        for a in &axes {
            if let Some(v) = a
                .values
                .iter()
                .enumerate()
                .find_map(|(i, v)| a.values[..i].contains(v).then_some(v))
            {
                return Err(invalid(
                    &format!("axes.{}", a.path),
                    format!("lists {v} twice"),
                ));
            }
        }
        let mut set = raw.set.clone();
        set.extend_from_slice(extra_set);
        if let Some(s) = set
            .iter()
            .find(|s| s.split_once('=').is_some_and(|(k, _)| k.trim() == "seed"))
        {
            let field = if raw.set.contains(s) { "set" } else { "seeds" };
            return Err(invalid(
                field,
                format!("`{s}` would be overridden by each point's seed: list seeds in `seeds`"),
            ));
        }
        // An axis sets its field at every point, after `set` and `--set`: the same field, or
        // one inside it, set there would be overridden without a word. (A table set there
        // with the axis's field inside it is fine: the axis changes that field.)
        for a in &axes {
            if let Some(s) = set.iter().find(|s| {
                s.split_once('=').is_some_and(|(k, _)| {
                    let k = k.trim();
                    k == a.path
                        || k.strip_prefix(a.path.as_str())
                            .is_some_and(|rest| rest.starts_with('.'))
                })
            }) {
                let field = if raw.set.contains(s) { "set" } else { "axes" };
                return Err(invalid(
                    field,
                    format!(
                        "`{s}` sets what the axis `{}` sweeps; drop one of them",
                        a.path
                    ),
                ));
            }
        }

        // The planning keys of the scenarios planned already: one of the same key plans alike
        // (see `planning_key`).
        let mut planned_keys = std::collections::BTreeSet::new();
        // The scenarios, each with the common overrides.
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut scenarios: Vec<SweepScenario> = Vec::new();
        for file in &raw.scenarios {
            let scenario_path = dir.join(file);
            let point_error = |e: ScenarioError| {
                let field = if matches!(e, sim_core::ScenarioError::Override { .. }) {
                    "set"
                } else {
                    "scenarios"
                };
                let (line, column) = at(field);
                SweepError::Point {
                    path: path.to_owned(),
                    line,
                    column,
                    field: field.into(),
                    point: file.clone(),
                    error: Box::new(e),
                }
            };
            let text: std::sync::Arc<str> = std::fs::read_to_string(&scenario_path)
                .map_err(|source| {
                    point_error(ScenarioError::Io {
                        path: scenario_path.clone(),
                        source,
                    })
                })?
                .into();
            let base = load_scenario(
                &SweepScenario {
                    path: scenario_path.clone(),
                    name: String::new(),
                    text: text.clone(),
                    roles: roles.clone(),
                },
                &set,
                Vec::new(),
            )
            .map_err(point_error)?;
            if plan && planned_keys.insert(planning_key(&base)) {
                // Its own mistakes are the scenario's (or `set`'s), not an axis's.
                Plan::new(&base).map_err(point_error)?;
            }
            let name = &base.name;
            if scenarios.iter().any(|s| &s.name == name) {
                return Err(invalid(
                    "scenarios",
                    format!("names scenario `{name}` twice"),
                ));
            }
            scenarios.push(SweepScenario {
                path: scenario_path,
                name: name.clone(),
                text,
                roles: roles.clone(),
            });
        }

        if roles.given() && !scenarios.iter().any(|s| is_openscenario(&s.path)) {
            return Err(invalid(
                "scenarios",
                "lists no OpenSCENARIO scenario (.xosc), whose entities --ego and --lead name"
                    .into(),
            ));
        }

        let count = scenarios.len()
            * raw.seeds.len()
            * axes.iter().map(|a| a.values.len()).product::<usize>();
        if count > MAX_POINTS {
            return Err(invalid(
                "axes",
                format!("make {count} points; at most {MAX_POINTS} are allowed"),
            ));
        }
        let points = grid(&scenarios, &raw.seeds, &axes, &set);

        // Every point's overrides, before anything runs; and every file the points read (the
        // scenarios and their targets), which the hash covers.
        let mut inputs = Inputs::of(scenarios.iter().map(|s| s.path.clone()));
        for point in &points {
            let overrides = point.overrides(&set);
            let scenario = &scenarios[point.scenario];
            let loaded = load_scenario(scenario, &overrides, point.osc_params());
            if let Ok(s) = &loaded {
                inputs.note(s, &scenario.path);
            }
            let planned = match loaded {
                Ok(s) if plan && planned_keys.insert(planning_key(&s)) => Plan::new(&s).map(|_| ()),
                Ok(_) => Ok(()),
                Err(e) => Err(e),
            };
            if let Err(e) = planned {
                let field = match &e {
                    sim_core::ScenarioError::Override { assignment, .. } => axes
                        .iter()
                        .find(|a| {
                            assignment
                                .split_once('=')
                                .is_some_and(|(k, _)| k.trim() == a.path)
                        })
                        .map_or("seeds".to_string(), |a| format!("axes.{}", a.path)),
                    _ => "axes".to_string(),
                };
                let (line, column) = at(&field);
                return Err(SweepError::Point {
                    path: path.to_owned(),
                    line,
                    column,
                    field,
                    point: point.describe(),
                    error: Box::new(e),
                });
            }
        }
        Ok(Sweep {
            plans: planned_keys.len(),
            hash: sweep_hash(&text, extra_set, &inputs),
            path: path.to_owned(),
            scenarios,
            seeds: raw.seeds,
            set,
            axes,
            points,
            distribution: None,
        })
    }

    /// The plan of a point's scenario, with all its overrides applied.
    pub fn plan(&self, point: &Point) -> Result<Plan, SweepError> {
        let scenario = &self.scenarios[point.scenario];
        load_scenario(scenario, &point.overrides(&self.set), point.osc_params())
            .and_then(|s| Plan::new(&s))
            .map_err(|e| SweepError::Run {
                point: point.describe(),
                message: e.to_string(),
            })
    }

    /// The points of a shard (all of them without one), in grid order.
    pub fn shard(&self, shard: Option<Shard>) -> Vec<&Point> {
        self.points
            .iter()
            .filter(|p| shard.is_none_or(|s| s.contains(p.index)))
            .collect()
    }
}

/// The grid in its fixed order (see the module notes).
fn grid(scenarios: &[SweepScenario], seeds: &[u64], axes: &[Axis], set: &[String]) -> Vec<Point> {
    let combos: usize = axes.iter().map(|a| a.values.len()).product();
    let mut points = Vec::new();
    for (si, scenario) in scenarios.iter().enumerate() {
        for combo in 0..combos {
            // Mixed-radix digits of `combo`, the last axis fastest.
            let mut rest = combo;
            let mut params = vec![(String::new(), toml::Value::Boolean(false)); axes.len()];
            for (ai, axis) in axes.iter().enumerate().rev() {
                let n = axis.values.len();
                params[ai] = (axis.path.clone(), axis.values[rest % n].clone());
                rest /= n;
            }
            for &seed in seeds {
                let mut point = Point {
                    index: points.len(),
                    id: String::new(),
                    scenario: si,
                    scenario_name: scenario.name.clone(),
                    seed,
                    params: params.clone(),
                };
                point.id = id_of(&point, set);
                points.push(point);
            }
        }
    }
    points
}

/// A point's id (see the module notes): of its description and the common overrides.
pub(super) fn id_of(point: &Point, set: &[String]) -> String {
    let mut canonical = point.describe();
    for s in set {
        canonical.push_str(&format!("\nset {s}"));
    }
    format!("{:016x}", vehicle::fnv1a64(canonical.as_bytes()))
}

/// What a sweep's points read besides the sweep file, for [`sweep_hash`].
#[derive(Debug, Default)]
pub(super) struct Inputs {
    /// Files: the scenarios, their targets and their road files.
    files: std::collections::BTreeSet<std::path::PathBuf>,
    /// The OpenSCENARIO points' scenarios as imported, which hold what their catalogs gave.
    imported: std::collections::BTreeSet<String>,
}

impl Inputs {
    /// The inputs of a sweep of the scenario files `paths`.
    pub(super) fn of(paths: impl IntoIterator<Item = std::path::PathBuf>) -> Inputs {
        Inputs {
            files: paths.into_iter().collect(),
            imported: Default::default(),
        }
    }

    /// Notes what the point `s`, loaded from the scenario file at `path`, reads: its target
    /// and road file (relative to the file's folder), and, from an OpenSCENARIO file, the
    /// scenario imported from it.
    pub(super) fn note(&mut self, s: &Scenario, path: &Path) {
        let dir = path.parent().unwrap_or(Path::new("."));
        self.files.insert(dir.join(&s.resolved.tracker.target));
        if let Some(road) = &s.resolved.route.opendrive {
            self.files.insert(dir.join(&road.file));
        }
        if sim_core::openscenario::is_openscenario(path) {
            self.imported
                .insert(toml::to_string(&s.resolved).unwrap_or_default());
        }
    }
}

/// [`Sweep::hash`]: of the sweep file's `text`, the command line's overrides, the text of
/// every file in `inputs`, and the scenarios imported from OpenSCENARIO files. A shipped
/// target that is not on disk is compiled in, and changes only with the program, like
/// everything else the hash leaves to the version.
pub(super) fn sweep_hash(text: &str, extra_set: &[String], inputs: &Inputs) -> String {
    let mut hashed = text.to_string();
    for s in extra_set {
        hashed.push_str(&format!("\n--set {s}"));
    }
    for file in &inputs.files {
        if let Ok(content) = std::fs::read_to_string(file) {
            hashed.push_str(&format!("\n--file {}\n{content}", file.display()));
        }
    }
    for imported in &inputs.imported {
        hashed.push_str(&format!("\n--imported\n{imported}"));
    }
    format!("{:016x}", vehicle::fnv1a64(hashed.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_0_based() {
        assert_eq!("0/4".parse(), Ok(Shard { index: 0, count: 4 }));
        assert!("4/4".parse::<Shard>().is_err());
        assert!("1/0".parse::<Shard>().is_err());
        assert!("x".parse::<Shard>().is_err());
    }
}
