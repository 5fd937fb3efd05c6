//! Scenario files (`scenarios/*.toml`): parsed into a raw [`ScenarioFile`], overridden by
//! `--set key.path=value`, then validated into a [`Scenario`]. This is the only place that
//! reads scenario TOML. Errors name the file, line, column and field, and say what is
//! allowed.

mod expect;
mod file;
mod library;
mod overrides;
mod road_file;
mod schema;
mod traffic;
mod validate;

pub use expect::Expect;
pub use file::*;
pub use library::shipped_scenarios;
pub use overrides::apply_override;
pub use schema::{scenario_schema_json, SCHEMA_FILE_NAME};
pub use traffic::{kind_albedo, kind_params, ActorFile, ActorSpec, StartFile};
pub use validate::{
    FOCAL_LENGTH_MM, MAX_ACTORS, MAX_ARC_RADIUS_M, MAX_BLUR_SIGMA_PX, MAX_BREADCRUMBS, MAX_GRADE,
    MAX_HEIGHT_M, MAX_INITIAL_GAP_M, MAX_INIT_OFFSET_PX, MAX_PLACED_GAP_M, MAX_ROUTE_M, MAX_STEP_M,
    MIN_ARC_RADIUS_M,
};

use sim_render::{Densities, RouteSpec, Sensor, Sun};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use thiserror::Error;
use tracker::{Camera, TargetModel, TrackerConfig};
pub(crate) use validate::{elevation_problem, lane_offset_problem, vehicle_error};
use validate::{override_names, validate, Blame};
use vehicle::{
    ChaseControllerConfig, DelayLineConfig, LeadDriverConfig, SpeedProfile, WorldConfig,
};

/// The built-in default scenario, `nist-grounds`, compiled in so `carfollow run` works from
/// any folder.
pub const BUILTIN_NAME: &str = "nist-grounds";
const BUILTIN_TEXT: &str = include_str!("../../../../scenarios/nist-grounds.toml");
/// The built-in scenario's target file (`scenarios/targets/nist-ten-segment.toml`), as
/// shipped.
pub const BUILTIN_TARGET_TEXT: &str =
    include_str!("../../../../scenarios/targets/nist-ten-segment.toml");

/// A scenario file that cannot be used.
#[derive(Debug, Error)]
pub enum ScenarioError {
    /// Unreadable file.
    #[error("{path}: cannot read scenario: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Bad TOML, unknown field, wrong type.
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong, naming the field.
        message: String,
    },
    /// A value out of its allowed range.
    #[error("{path}:{line}:{column}: `{field}` {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// 1-based line (of the field, or of its table when the field was left out).
        line: usize,
        /// 1-based column.
        column: usize,
        /// Dotted field path.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A `--set` that cannot be applied.
    #[error("--set {assignment}: {message}")]
    Override {
        /// The `key=value` as given.
        assignment: String,
        /// What is wrong.
        message: String,
    },
    /// The road file named by `route.opendrive`.
    #[error("{path}:{line}:{column}: `route.opendrive`: {source}")]
    Road {
        /// The scenario file.
        path: PathBuf,
        /// 1-based line of `route.opendrive`.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The road file's own error, naming its line and element.
        source: Box<crate::opendrive::OpenDriveError>,
    },
    /// The target file named by `tracker.target`.
    #[error("{path}:{line}:{column}: `tracker.target`: {source}")]
    Target {
        /// The scenario file.
        path: PathBuf,
        /// 1-based line of `tracker.target`.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The target file's own error (boxed: it is large and rare).
        source: Box<crate::target::TargetFileError>,
    },
    /// An OpenSCENARIO file refused as it is read.
    #[error(transparent)]
    OpenScenario(#[from] crate::openscenario::OscError),
    /// An OpenSCENARIO file read, and what it became refused by carfollow's checks.
    #[error("{path}: as carfollow reads it: {message}")]
    Imported {
        /// The OpenSCENARIO file.
        path: PathBuf,
        /// What is wrong, naming carfollow's field.
        message: String,
    },
}

/// A validated scenario: everything the closed loop needs, with defaults filled in. Only
/// validation makes one ([`Scenario::load`], [`Scenario::parse`], [`Scenario::builtin`]),
/// and nothing changes it after: its contents ([`ScenarioSpec`]) are read through it,
/// never written. A clone shares them.
///
/// ```compile_fail
/// let mut s = sim_core::Scenario::builtin(&[]).unwrap();
/// s.duration_s = 1.0; // refused: a validated scenario is read-only
/// ```
///
/// ```
/// let s = sim_core::Scenario::builtin(&["duration_s=2".into()]).unwrap();
/// assert_eq!(s.duration_s, 2.0);
/// ```
#[derive(Clone, Debug)]
pub struct Scenario(Arc<ScenarioSpec>);

impl std::ops::Deref for Scenario {
    type Target = ScenarioSpec;

    fn deref(&self) -> &ScenarioSpec {
        &self.0
    }
}

impl Scenario {
    /// The scenario `spec` says, once validated.
    pub(crate) fn validated(spec: ScenarioSpec) -> Scenario {
        Scenario(Arc::new(spec))
    }
}

/// What a validated [`Scenario`] holds, read through it.
#[derive(Clone, Debug)]
pub struct ScenarioSpec {
    /// Name (the output folder).
    pub name: String,
    /// What it is for.
    pub description: String,
    /// Where it was read from (`None` for the built-in one).
    pub path: Option<PathBuf>,
    /// What reading an OpenSCENARIO file or an OpenDRIVE road left unapplied, a line each
    /// (`check` and `run` say them among the warnings).
    pub import_warnings: Vec<String>,
    /// Simulated time, seconds.
    pub duration_s: f64,
    /// The seed.
    pub seed: u64,
    /// The route.
    pub route: RouteSpec,
    /// Whether the scenario has a lead. Without one, the `lead_` fields stand for what the
    /// chase drives in its place, its own lane from its start at its cruise speed (no lead
    /// is placed, drawn or tracked), and `initial_gap_m` means nothing.
    pub has_lead: bool,
    /// Chase: rear-axle station at t = 0, metres (`initial_gap_m` behind the lead, or
    /// `chase.start_m`).
    pub chase_start_m: f64,
    /// Lead: rear-axle station at t = 0, metres.
    pub lead_start_m: f64,
    /// Lead: speed at t = 0, m/s.
    pub lead_initial_speed_mps: f64,
    /// Lead: the scripted speed.
    pub lead_profile: SpeedProfile,
    /// Lead: the driver's tuning.
    pub lead_driver: LeadDriverConfig,
    /// Lead: its lane at the start (1 is next to the centre line); the chase's too.
    pub lead_lane: u32,
    /// Lead: its offset from its lane's centre, metres, positive to the left.
    pub lead_offset_m: f64,
    /// Lead: its events.
    pub lead_events: vehicle::EventScript,
    /// The other vehicles, in the file's order.
    pub actors: Vec<ActorSpec>,
    /// Chase: camera-to-target distance at t = 0, metres.
    pub initial_gap_m: f64,
    /// Chase: speed at t = 0, m/s (the lead's initial speed unless the file sets it).
    pub chase_initial_speed_mps: f64,
    /// Chase: the controller (its camera mount is the camera's).
    pub chase: ChaseControllerConfig,
    /// Camera intrinsics, shared with the tracker's stage 8.
    pub camera: Camera,
    /// Tracker settings.
    pub tracker: TrackerConfig,
    /// The target model.
    pub target: TargetModel,
    /// The teleoperator's placement error `[dx_px, dy_px, dscale]`.
    pub init_offset: [f64; 3],
    /// Whether the tracker starts with nothing placed, searching (`tracker.start`).
    pub search_start: bool,
    /// The delay line.
    pub delay: DelayLineConfig,
    /// Physics world (ground, bumps).
    pub world: WorldConfig,
    /// Light.
    pub sun: Sun,
    /// Clutter.
    pub densities: Densities,
    /// Hand-placed scenery (overpasses).
    pub placements: Vec<sim_render::Placement>,
    /// Controlled distractors moving with the lead.
    pub distractors: Vec<sim_render::Distractor>,
    /// Sensor.
    pub sensor: Sensor,
    /// What the road is paved with.
    pub road_surface: sim_render::RoadSurface,
    /// Textures on the ground.
    pub textures: sim_render::Textures,
    /// Fog (`None`: clear air).
    pub fog: Option<sim_render::Fog>,
    /// Rain (`None`: dry).
    pub rain: Option<sim_render::Rain>,
    /// The chase's headlamps' beam (`None`: off).
    pub headlamps: Option<sim_render::Beam>,
    /// Whether the lead's tail lamps are lit.
    pub lead_tail_lamps: bool,
    /// Pass/fail criteria.
    pub expect: Expect,
    /// The scenario as resolved: the file with the `--set` overrides applied and every
    /// default filled in (written to `summary.json`).
    pub resolved: ScenarioFile,
    /// The `--set` overrides applied, in order.
    pub overrides: Vec<String>,
    /// Where it came from, to place the errors found in planning it.
    pub(crate) source: Source,
}

/// Where a scenario came from, to place an error in it: its text, the path errors name,
/// and the `--set` overrides applied to it.
#[derive(Clone, Debug)]
pub(crate) struct Source {
    text: Arc<str>,
    path: PathBuf,
    overrides: Vec<String>,
    /// The text is what an OpenSCENARIO file (`path`) became: its lines are not the
    /// file's, so an error names the field, not a line.
    imported: bool,
}

impl Source {
    /// The error of `field`, saying `message`: at the field's line in the file (or its
    /// table's, when the file leaves it out), or as the `--set` that gave its value.
    pub(crate) fn invalid(&self, field: &str, message: String) -> ScenarioError {
        // `field` then the message: "`x` = 3: ..." or, for a nested error, "`x` is refused: ...".
        let message = match message.strip_prefix(": ") {
            Some(rest) => format!("is refused: {rest}"),
            None => message,
        };
        // A value that came from `--set` is reported as such, not at the file's line.
        if let Some(assignment) = self
            .overrides
            .iter()
            .rev()
            .find(|a| override_names(a, field))
        {
            return ScenarioError::Override {
                assignment: assignment.clone(),
                message: format!("`{field}` {message}"),
            };
        }
        if self.imported {
            return ScenarioError::Imported {
                path: self.path.clone(),
                message: format!("`{field}` {message}"),
            };
        }
        let (line, column) = line_column(&self.text, locate(&self.text, field));
        ScenarioError::Invalid {
            path: self.path.clone(),
            line,
            column,
            field: field.to_string(),
            message,
        }
    }

    /// Whether the scenario gives `field` (dotted) itself: the file writes it, or a
    /// `--set` does.
    pub(crate) fn gives(&self, field: &str) -> bool {
        let parent = field.rsplit_once('.').map_or("", |(p, _)| p);
        self.overrides.iter().any(|a| override_names(a, field))
            || locate(&self.text, field) != locate(&self.text, parent)
    }

    /// The first of `fields` (which together decide something found wrong) that an
    /// override set, else `otherwise`: an error is blamed on what the user changed.
    pub(crate) fn blame<'a>(&self, fields: &[&'a str], otherwise: &'a str) -> &'a str {
        fields
            .iter()
            .copied()
            .find(|f| self.overrides.iter().any(|a| override_names(a, f)))
            .unwrap_or(otherwise)
    }
}

/// The error of the file a scenario's `field` names (`tracker.target`, `route.opendrive`),
/// which says `source`: the override's, when a `--set` gave the field, else `placed` at the
/// field's line and column in the scenario's `text`.
pub(super) fn file_error<E: std::fmt::Display>(
    overrides: &[String],
    text: &str,
    field: &str,
    source: E,
    placed: impl FnOnce(usize, usize, E) -> ScenarioError,
) -> ScenarioError {
    if let Some(assignment) = overrides.iter().rev().find(|a| override_names(a, field)) {
        return ScenarioError::Override {
            assignment: assignment.clone(),
            message: format!("`{field}`: {source}"),
        };
    }
    let (line, column) = line_column(text, locate(text, field));
    placed(line, column, source)
}

/// 1-based (line, column) of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    crate::target::line_column(text, offset)
}

/// The byte offset of a dotted path in the TOML text: the key when present, else the
/// nearest enclosing table that is, else the start.
pub fn locate(text: &str, dotted: &str) -> usize {
    use toml::de::{DeTable, DeValue};
    let Ok(root) = DeTable::parse(text) else {
        return 0;
    };
    let mut table: &DeTable = root.get_ref();
    let mut best = 0;
    for part in dotted.split('.') {
        // `name[i]...`: the key, then an item of a list (of tables) for each index.
        let (name, indices) = part.split_once('[').unwrap_or((part, ""));
        let Some((key, value)) = table.iter().find(|(k, _)| k.get_ref().as_ref() == name) else {
            break;
        };
        best = key.span().start;
        let mut value = value;
        for index in indices.split('[').filter(|i| !i.is_empty()) {
            let item = match (
                value.get_ref(),
                index.trim_end_matches(']').parse::<usize>(),
            ) {
                (DeValue::Array(items), Ok(i)) => items.get(i),
                _ => None,
            };
            let Some(item) = item else {
                return best;
            };
            best = item.span().start;
            value = item;
        }
        match value.get_ref() {
            DeValue::Table(t) => table = t,
            _ => break,
        }
    }
    best
}

/// Sets `value[pointer]` to `fill` where it is absent or `null` (the parents exist: every
/// table of the file has a default).
fn fill_null(value: &mut serde_json::Value, pointer: &str, fill: serde_json::Value) {
    let (parent, key) = pointer.rsplit_once('/').expect("a pointer below the root");
    if let Some(serde_json::Value::Object(table)) = value.pointer_mut(parent) {
        let slot = table.entry(key).or_insert(serde_json::Value::Null);
        if slot.is_null() {
            *slot = fill;
        }
    }
}

/// Numbers that came from `f32` fields as their `f32`'s shortest decimal (2.2, not
/// 2.200000047683716); a number that is not exactly an `f32` stays as it is.
fn shortest_f32(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Number(n) => {
            if let Some(x) = n
                .as_f64()
                .filter(|x| !n.is_i64() && !n.is_u64() && x.is_finite())
            {
                let f = x as f32;
                if f64::from(f) == x {
                    if let Some(short) = format!("{f}")
                        .parse::<f64>()
                        .ok()
                        .and_then(serde_json::Number::from_f64)
                    {
                        *n = short;
                    }
                }
            }
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(shortest_f32),
        serde_json::Value::Object(table) => table.values_mut().for_each(shortest_f32),
        _ => {}
    }
}

/// Deserializes TOML `text` into a `T`. A mistake comes back as its error (for its place)
/// and its message, which names the field it is about when it is about one
/// (`` `a.b[2].c`: invalid type… ``), as scenario and sweep files report them.
pub fn from_toml_naming_field<T: serde::de::DeserializeOwned>(
    text: &str,
) -> Result<T, (toml::de::Error, String)> {
    let de = toml::Deserializer::parse(text).map_err(|e| {
        let mut message = e.message().trim().to_string();
        // toml says "duplicate key" and points at it: name it.
        if message == "duplicate key" {
            if let Some(key) = e.span().and_then(|span| text.get(span)) {
                let key = key.trim();
                if !key.is_empty() && !key.contains('\n') {
                    message = format!("duplicate key `{key}`");
                }
            }
        }
        (e, message)
    })?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let mut segments: Vec<String> = e.path().iter().map(|s| s.to_string()).collect();
        let e = e.into_inner();
        let message = e.message().trim().to_string();
        // An unknown field's message names it: the path is the table it stands in.
        if message.starts_with("unknown field") {
            segments.pop();
        }
        let message = if segments.is_empty() {
            message
        } else {
            format!("`{}`: {message}", field_path(&segments))
        };
        (e, message)
    })
}

/// A field's dotted path from serde_path_to_error's segments: `a.b[2].c`.
fn field_path(segments: &[String]) -> String {
    let mut path = String::new();
    for s in segments {
        if s.starts_with('[') || path.is_empty() {
            path.push_str(s);
        } else {
            path.push('.');
            path.push_str(s);
        }
    }
    path
}

impl Scenario {
    /// The scenario as it ran, for `summary.json`: the file with its overrides applied
    /// ([`Scenario::resolved`]), the defaults it left out filled in with the values the run
    /// used, and the chase controller's settings as they ran (its camera mount and field of
    /// view come from `[camera]`).
    pub fn resolved_json(&self) -> serde_json::Value {
        use serde_json::json;
        let mut v = serde_json::to_value(&self.resolved).expect("a scenario file serialises");
        let c = &self.camera;
        fill_null(&mut v, "/camera/focal_length_mm", json!(c.focal_length_mm));
        fill_null(&mut v, "/camera/pixel_size_mm", json!(c.pixel_size_mm));
        fill_null(&mut v, "/camera/image_center_px", json!(c.image_center_px));
        if self.has_lead {
            fill_null(&mut v, "/chase/initial_gap_m", json!(self.initial_gap_m));
        }
        fill_null(
            &mut v,
            "/lead/initial_speed_mps",
            json!(self.lead_initial_speed_mps),
        );
        if let Some(chase) = v.pointer_mut("/chase/controller") {
            *chase = serde_json::to_value(&self.chase).expect("a controller serialises");
        }
        let d = &self.densities;
        for (name, value) in [
            ("trees_per_km", d.trees_per_km),
            ("poles_per_km", d.poles_per_km),
            ("houses_per_km", d.houses_per_km),
            ("buildings_per_km", d.buildings_per_km),
            ("parked_vehicles_per_km", d.parked_vehicles_per_km),
            ("oncoming_vehicles_per_km", d.oncoming_vehicles_per_km),
            ("cracks_per_km", d.cracks_per_km),
            ("patches_per_km", d.patches_per_km),
            ("potholes_per_km", d.potholes_per_km),
        ] {
            fill_null(
                &mut v,
                &format!("/environment/clutter/{name}"),
                json!(value),
            );
        }
        let sun = &self.sun;
        for (name, value) in [
            ("azimuth_deg", json!(sun.azimuth_deg)),
            ("elevation_deg", json!(sun.elevation_deg)),
            ("strength", json!(sun.strength)),
            ("ambient", json!(sun.ambient)),
            ("soft_shadows", json!(sun.soft_shadows)),
        ] {
            fill_null(&mut v, &format!("/environment/sun/{name}"), value);
        }
        fill_null(
            &mut v,
            "/environment/textures/enabled",
            json!(self.textures.enabled),
        );
        fill_null(
            &mut v,
            "/environment/textures/contrast",
            json!(self.textures.contrast),
        );
        fill_null(
            &mut v,
            "/environment/road/surface",
            json!(self.road_surface.as_str()),
        );
        self.fill_tracker_loop_and_sensor(&mut v);
        shortest_f32(&mut v);
        v
    }

    /// [`Scenario::resolved_json`]'s defaults of `[tracker]`, `[loop]` and
    /// `[environment.sensor]` (the sensor's optional effects stay `null` when off).
    fn fill_tracker_loop_and_sensor(&self, v: &mut serde_json::Value) {
        use serde_json::json;
        let t = &self.tracker;
        for (name, value) in [
            ("lambda", json!(t.lambda)),
            ("delta_deg", json!(t.delta_deg)),
            ("zeta_px", json!(t.zeta_px)),
            ("edge_threshold", json!(t.edge_threshold)),
            ("lost_after_s", json!(t.lost_after_s)),
            ("subpixel_edges", json!(t.subpixel_edges)),
            ("mode", json!(t.mode.as_str())),
            ("init_offset", json!(self.init_offset)),
        ] {
            fill_null(v, &format!("/tracker/{name}"), value);
        }
        let d = &self.delay;
        for (name, value) in [
            ("rate_hz", json!(t.rate_hz)),
            ("latency_ms", json!(d.latency_ms)),
            ("jitter_ms", json!(d.jitter_ms)),
            ("drop_probability", json!(d.drop_probability)),
        ] {
            fill_null(v, &format!("/loop/{name}"), value);
        }
        let s = &self.sensor;
        for (name, value) in [
            ("gain", json!(s.gain)),
            ("noise_sigma_grey", json!(s.noise_sigma_grey)),
            ("vignetting", json!(s.vignetting)),
            ("interlaced", json!(s.interlaced)),
        ] {
            fill_null(v, &format!("/environment/sensor/{name}"), value);
        }
    }

    /// Reads a scenario file and applies `--set` overrides. An OpenSCENARIO file
    /// (`.xosc`) is read as [`Scenario::load_openscenario`] reads it, with its defaults.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        if crate::openscenario::is_openscenario(path) {
            let options = crate::openscenario::ImportOptions::default();
            return Self::load_openscenario(path, overrides, &options);
        }
        let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_file_text(&text, path, overrides)
    }

    /// Reads an OpenSCENARIO file as the scenario `carfollow import` writes of it, with
    /// `--set` overrides applied to that (a `duration_s` among them stands in for the
    /// file's `StopTrigger`). What carfollow's checks refuse in it is said as the field
    /// of the scenario it became.
    pub fn load_openscenario(
        path: &Path,
        overrides: &[String],
        options: &crate::openscenario::ImportOptions,
    ) -> Result<Scenario, ScenarioError> {
        let mut options = options.clone();
        if overrides.iter().any(|a| override_names(a, "duration_s")) {
            // Any length: the override replaces it.
            options.duration_s.get_or_insert(1.0);
        }
        let imported = crate::openscenario::import(path, &options)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let as_read = |e: ScenarioError| match e {
            ScenarioError::Invalid { field, message, .. } => ScenarioError::Imported {
                path: path.to_owned(),
                message: format!("`{field}` {message}"),
            },
            ScenarioError::Parse { message, .. } => ScenarioError::Imported {
                path: path.to_owned(),
                message,
            },
            other => other,
        };
        let s = Self::from_text(&imported.text, path, dir, overrides).map_err(as_read)?;
        let mut spec = Arc::unwrap_or_clone(s.0);
        spec.path = Some(path.to_owned());
        // What planning refuses is said of the file's own scenario, by field.
        spec.source.imported = true;
        spec.import_warnings.splice(0..0, imported.warnings);
        Ok(Scenario::validated(spec))
    }

    /// [`Scenario::load`] with the file's text already read (`text`, of the file at
    /// `path`): for whoever loads one file many times over, as a sweep's points do.
    pub fn from_file_text(
        text: &str,
        path: &Path,
        overrides: &[String],
    ) -> Result<Scenario, ScenarioError> {
        let dir = path.parent().unwrap_or(Path::new("."));
        Self::parse(text, path, overrides, |target| {
            library::target_in(dir, target)
        })
        .map(|s| {
            let mut spec = Arc::unwrap_or_clone(s.0);
            spec.path = Some(path.to_owned());
            Scenario::validated(spec)
        })
    }

    /// Whether the scenario has traffic: other vehicles, events on the lead, or no lead
    /// (the chase then looks for the vehicle in its path). Only then
    /// do the outputs carry the traffic's truth and columns, so that a scenario without
    /// any writes what it wrote before traffic existed.
    pub fn has_traffic(&self) -> bool {
        !self.actors.is_empty() || !self.lead_events.is_empty() || !self.has_lead
    }

    /// The targets of the actors' kinds, each kind once in the order the actors first
    /// name it: the backs the follower's tracker may acquire besides the lead's target
    /// ([`crate::FrameTracker::set_other_targets`]).
    pub fn other_targets(&self) -> Vec<tracker::TargetModel> {
        let mut kinds: Vec<sim_render::VehicleKind> = Vec::new();
        for a in &self.actors {
            if !kinds.contains(&a.kind) {
                kinds.push(a.kind);
            }
        }
        kinds
            .into_iter()
            .map(sim_render::vehicle_back_model)
            .collect()
    }

    /// The camera frames of its run: its duration at the camera's rate, frame k at k / 15 s.
    pub fn frames(&self) -> u64 {
        (self.duration_s * f64::from(vehicle::CAMERA_HZ)).round() as u64
    }

    /// What is valid but doubtful in the scenario, a line each naming the fields: `check`
    /// and `run` say these as warnings. Today: a lead faster than the chase's gap keeper
    /// will drive (`chase.controller.gap_keeper.max_speed_mps`), so that the gap can only
    /// open.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = self.import_warnings.clone();
        let lead_max = self
            .lead_profile
            .knots
            .iter()
            .map(|k| f64::from(k.speed_mps))
            .fold(self.lead_initial_speed_mps, f64::max);
        let keeper_max = f64::from(self.chase.gap_keeper.max_speed_mps);
        if self.has_lead
            && matches!(self.chase.speed_mode, vehicle::SpeedMode::GapKeeping)
            && lead_max > keeper_max
        {
            out.push(format!(
                "`lead.speed_profile` reaches {lead_max} m/s, faster than \
                 `chase.controller.gap_keeper.max_speed_mps` ({keeper_max} m/s, the fastest \
                 the chase will drive): the gap can only open while the lead is faster"
            ));
        }
        if let Some(warning) = self.lead_beyond_the_road() {
            out.push(warning);
        }
        out
    }

    /// A warning when the lead's speed profile, driven from `lead.start_m` for the whole
    /// of `duration_s`, would take it past the route's end, where it stops: the distance it
    /// drives (the profile integrated in steps of 1/20 s) against the route's length.
    /// Without a lead, the same of the chase cruising from its start, which stops short of
    /// the road's end as the lead does.
    fn lead_beyond_the_road(&self) -> Option<String> {
        const DT_S: f64 = 0.05;
        let length = validate::route_length_m(&self.route);
        let room = length - self.lead_start_m;
        let profile = &self.lead_profile;
        let (mut t, mut d) = (0.0_f64, 0.0_f64);
        let mut end_t = None;
        while t < self.duration_s {
            let key = match profile.basis {
                vehicle::ProfileBasis::Time => t,
                vehicle::ProfileBasis::Distance => d,
            };
            d += f64::from(profile.speed_at(key as f32)) * DT_S;
            t += DT_S;
            if d > room && end_t.is_none() {
                end_t = Some(t);
            }
        }
        let end_t = end_t?;
        if !self.has_lead {
            // What stands for the lead is the chase's own cruise in its lane.
            return Some(format!(
                "the chase, cruising at {} m/s from `chase.start_m` = {} m with no lead, \
                 would reach the route's end ({length:.0} m) at about {end_t:.0} s: it will \
                 stop short of the road's end",
                // The cruise speed is an `f32`: said as it was written.
                self.lead_initial_speed_mps as f32,
                self.lead_start_m
            ));
        }
        Some(format!(
            "`lead.speed_profile` drives about {d:.0} m in the {} s of `duration_s` from \
             `lead.start_m` = {} m, beyond the route's {length:.0} m: the lead will stop at \
             the road's end, at about {end_t:.0} s",
            self.duration_s, self.lead_start_m
        ))
    }

    /// The built-in `nist-grounds`, with `--set` overrides.
    pub fn builtin(overrides: &[String]) -> Result<Scenario, ScenarioError> {
        Self::parse(
            BUILTIN_TEXT,
            Path::new("scenarios/nist-grounds.toml"),
            overrides,
            |target| {
                crate::target::parse(BUILTIN_TARGET_TEXT, &Path::new("scenarios").join(target))
            },
        )
    }

    /// Parses and validates scenario text; `path` is only used in errors, `load_target`
    /// reads `tracker.target`.
    pub fn parse(
        text: &str,
        path: &Path,
        overrides: &[String],
        load_target: impl Fn(&str) -> Result<TargetModel, crate::target::TargetFileError>,
    ) -> Result<Scenario, ScenarioError> {
        let parse_err = |e: toml::de::Error| {
            let (line, column) = line_column(text, e.span().map_or(0, |s| s.start));
            ScenarioError::Parse {
                path: path.to_owned(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        };
        // The file alone first, so its own mistakes are reported at their line, with the
        // field they are about.
        let mut raw: ScenarioFile = from_toml_naming_field(text).map_err(|(e, message)| {
            let (line, column) = line_column(text, e.span().map_or(0, |s| s.start));
            ScenarioError::Parse {
                path: path.to_owned(),
                line,
                column,
                message,
            }
        })?;
        // The file alone again, as the overrides below will read it: whatever that refuses
        // is the file's fault, not an override's.
        let table: toml::Table = toml::from_str(text).map_err(parse_err)?;
        if let Err(e) = toml::Value::Table(table).try_into::<ScenarioFile>() {
            return Err(ScenarioError::Parse {
                path: path.to_owned(),
                line: 1,
                column: 1,
                message: e.message().trim().to_string(),
            });
        }
        if !overrides.is_empty() {
            let mut value: toml::Table = toml::from_str(text).map_err(parse_err)?;
            // One at a time, so an error names the override that caused it.
            for assignment in overrides {
                let created = created_table(&value, assignment);
                apply_override(&mut value, assignment)?;
                raw = toml::Value::Table(value.clone()).try_into().map_err(
                    |e: toml::de::Error| {
                        let message = e.message().trim().to_string();
                        ScenarioError::Override {
                            assignment: assignment.clone(),
                            message: match &created {
                                Some(table) if message.starts_with("missing field") => {
                                    whole_table_hint(table, assignment, &message)
                                }
                                _ => message,
                            },
                        }
                    },
                )?;
            }
        }
        let source = Source {
            text: text.into(),
            path: path.to_owned(),
            overrides: overrides.to_vec(),
            imported: false,
        };
        let invalid = |field: &str, message: String| source.invalid(field, message);
        let load_road = |od: &OpenDriveFile| road_file::load(od, path, text, overrides);
        let gives = |field: &str| source.gives(field);
        let roads = validate::RoadSource {
            load: &load_road,
            gives: &gives,
        };
        validate(
            raw,
            overrides,
            source.clone(),
            &Blame(&invalid),
            |target| {
                load_target(target).map_err(|source| {
                    file_error(
                        overrides,
                        text,
                        "tracker.target",
                        source,
                        |line, column, source| ScenarioError::Target {
                            path: path.to_owned(),
                            line,
                            column,
                            source: Box::new(source),
                        },
                    )
                })
            },
            &roads,
        )
    }
}

/// The table `assignment` sets a field of, as a dotted path, when `root` does not have it
/// (the override creates it): `chase.controller.lookahead` for
/// `chase.controller.lookahead.min_m=3` in a file without `[chase.controller.lookahead]`.
fn created_table(root: &toml::Table, assignment: &str) -> Option<String> {
    let path = assignment.split_once('=')?.0.trim();
    let keys: Vec<&str> = path.split('.').collect();
    let (_, parents) = keys.split_last()?;
    let mut table = root;
    for key in parents {
        match table.get(*key) {
            Some(toml::Value::Table(t)) => table = t,
            Some(_) => return None,
            None => return Some(parents.join(".")),
        }
    }
    None
}

/// The error of an override that created `table` without the fields it cannot do without:
/// what to write instead, the whole table with the defaults of the built-in scenario and
/// the override's own value.
fn whole_table_hint(table: &str, assignment: &str, message: &str) -> String {
    let mut hint = format!(
        "`{table}` is not in the file, and a table given by --set needs all its fields \
         ({message})"
    );
    let pointer = format!("/{}", table.replace('.', "/"));
    let defaults = Scenario::builtin(&[])
        .ok()
        .and_then(|s| s.resolved_json().pointer(&pointer).cloned())
        .and_then(|v| toml::Value::try_from(v).ok());
    if let Some(toml::Value::Table(mut whole)) = defaults {
        let (path, value) = assignment.split_once('=').unwrap_or((assignment, ""));
        let field = path.trim()[table.len()..].trim_start_matches('.');
        if !field.contains('.') {
            whole.insert(field.to_string(), overrides::parse_value(value.trim()));
        }
        hint.push_str(&format!(
            ": give it whole, e.g. --set '{table}={}'",
            toml::Value::Table(whole)
        ));
    }
    hint
}
