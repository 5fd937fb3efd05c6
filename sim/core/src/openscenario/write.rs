//! The scenario as carfollow writes it: the road, the chase, the lead, the actors with
//! their events, and the duration, as a scenario file's TOML.

use super::entities::Entity;
use super::error::OscError;
use super::init::{Init, Placed, RoadLanes};
use super::story::{read_stories, Names};
use super::xml::{child, children, elements, only_element, Xml};
use super::{ImportOptions, Imported};
use std::path::{Component, Path, PathBuf};
use toml::{Table, Value};

/// The road of the file's `RoadNetwork/LogicFile`.
pub struct Road {
    /// Its id and lanes.
    pub lanes: RoadLanes,
    /// The OpenDRIVE file.
    pub file: PathBuf,
}

/// Reads the road of `RoadNetwork/LogicFile` (relative to `dir`, the scenario's folder).
pub fn read_road(xml: &Xml, dir: &Path) -> Result<Road, OscError> {
    let root = xml.doc.root_element();
    let logic = child(root, "RoadNetwork")
        .and_then(|n| child(n, "LogicFile"))
        .ok_or_else(|| xml.at(root, "<OpenSCENARIO> has no <RoadNetwork><LogicFile>: carfollow's route is the road of an OpenDRIVE file"))?;
    let file = dir.join(xml.req(logic, "filepath")?);
    let opendrive = crate::opendrive::load(&file)?;
    let road = crate::opendrive::import(&opendrive, None, |_| None)?;
    Ok(Road {
        lanes: RoadLanes {
            id: road.id,
            lanes: road.lanes,
            lane_width_m: road.lane_width_m,
        },
        file,
    })
}

/// carfollow's names for the vehicles: `chase`, `lead`, and each other vehicle's name with
/// what an actor's name may not hold (anything but letters, digits, `-` and `_`) made
/// `-`, unique.
fn carfollow_names(vehicles: &[Entity], ego: &str, lead: &str) -> Names {
    let mut names = Names::new();
    let mut used: Vec<String> = vec!["chase".into(), "lead".into()];
    for v in vehicles {
        let name = if v.name == ego {
            "chase".to_string()
        } else if v.name == lead {
            "lead".to_string()
        } else {
            let base: String = v.name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' }).collect();
            let base = if base.is_empty() { "actor".to_string() } else { base };
            let mut name = base.clone();
            let mut k = 2;
            while used.contains(&name) {
                name = format!("{base}-{k}");
                k += 1;
            }
            used.push(name.clone());
            name
        };
        names.insert(v.name.clone(), name);
    }
    names
}

/// The lead: `given`, or the nearest vehicle ahead of the ego in its lane at t = 0.
fn choose_lead(xml: &Xml, vehicles: &[Entity], init: &Init, ego: &str, given: Option<&str>) -> Result<String, OscError> {
    let at_ego = init.placed[ego];
    if let Some(name) = given {
        if name == ego || !vehicles.iter().any(|v| v.name == name) {
            return Err(OscError::File { path: xml.path.clone(), message: format!("--lead {name}: no vehicle of that name other than the ego") });
        }
        return Ok(name.to_string());
    }
    vehicles
        .iter()
        .filter(|v| v.name != ego)
        .filter_map(|v| init.placed.get(&v.name).map(|p| (v, p)))
        .filter(|(_, p)| p.lane == at_ego.lane && p.s_m > at_ego.s_m)
        .min_by(|a, b| a.1.s_m.total_cmp(&b.1.s_m))
        .map(|(v, _)| v.name.clone())
        .ok_or_else(|| OscError::File {
            path: xml.path.clone(),
            message: format!("no vehicle is ahead of the ego `{ego}` in its lane at t = 0, and carfollow's chase follows a lead (name one with --lead)"),
        })
}

/// The scenario's duration: its `StopTrigger`'s simulation time (the earliest of its
/// condition groups, each a `SimulationTimeCondition`).
fn duration(xml: &Xml) -> Result<f64, OscError> {
    let root = xml.doc.root_element();
    let stop = child(root, "Storyboard").and_then(|s| child(s, "StopTrigger"));
    let Some(stop) = stop.filter(|s| elements(*s).next().is_some()) else {
        return Err(xml.at(root, "<Storyboard> has no <StopTrigger>: give the run's length with --set duration_s=SECONDS"));
    };
    let mut earliest = f64::INFINITY;
    for group in children(stop, "ConditionGroup") {
        let conditions: Vec<_> = children(group, "Condition").collect();
        let [condition] = conditions.as_slice() else {
            return Err(xml.at(group, format!("<StopTrigger> group of {} conditions: carfollow ends a run at a time (or give it with --set duration_s=SECONDS)", conditions.len())));
        };
        let time = child(*condition, "ByValueCondition").map(|v| only_element(xml, v)).transpose()?.filter(|c| c.has_tag_name("SimulationTimeCondition"));
        let Some(time) = time else {
            let what = elements(*condition).next().and_then(|c| elements(c).next()).unwrap_or(*condition);
            return Err(xml.unsupported(what, "stop condition", "carfollow ends a run at a time; or give it with --set duration_s=SECONDS"));
        };
        let delay = xml.opt_num(*condition, "delay")?.unwrap_or(0.0).max(0.0);
        earliest = earliest.min(xml.num(time, "value")?.max(0.0) + delay);
    }
    if !earliest.is_finite() {
        return Err(xml.at(stop, "<StopTrigger> has no <ConditionGroup>: give the run's length with --set duration_s=SECONDS"));
    }
    Ok(earliest)
}

/// `path` relative to the folder `base` (both made absolute; `..` where they part).
fn relative(path: &Path, base: &Path) -> PathBuf {
    // The parts of an absolute path, with `.` dropped and `..` taken back.
    let parts = |p: &Path| -> Vec<std::ffi::OsString> {
        let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        let mut out: Vec<std::ffi::OsString> = Vec::new();
        for c in abs.components() {
            match c {
                Component::CurDir => {}
                Component::ParentDir => {
                    out.pop();
                }
                c => out.push(c.as_os_str().to_os_string()),
            }
        }
        out
    };
    let (p, b) = (parts(path), parts(base));
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    out
}

fn profile(speed: f64) -> Value {
    Value::Array(vec![Value::Array(vec![Value::Float(0.0), Value::Float(speed)])])
}

fn events_value(xml: &Xml, events: &[vehicle::EventSpec]) -> Result<Value, OscError> {
    Value::try_from(events).map_err(|e| OscError::File { path: xml.path.clone(), message: format!("cannot write the events: {e}") })
}

/// The scenario of the file as carfollow's scenario text.
#[allow(clippy::too_many_arguments)]
pub fn scenario(
    xml: &Xml,
    vehicles: &[Entity],
    road: &Road,
    ego: &str,
    init: Init,
    options: &ImportOptions,
    dir: &Path,
) -> Result<Imported, OscError> {
    let mut warnings = init.warnings.clone();
    for v in vehicles {
        if !init.placed.contains_key(&v.name) {
            return Err(OscError::At { path: xml.path.clone(), line: v.line, message: format!("<ScenarioObject name=\"{}\"> is placed by no <TeleportAction> in <Init>", v.name) });
        }
        if v.controlled && v.name != ego {
            return Err(OscError::At { path: xml.path.clone(), line: v.line, message: format!("unsupported <ObjectController> of `{}` (carfollow drives its vehicles by their events)", v.name) });
        }
    }
    let lead = choose_lead(xml, vehicles, &init, ego, options.lead.as_deref())?;
    let names = carfollow_names(vehicles, ego, &lead);
    let stories = read_stories(xml, &names, &init, &road.lanes, ego)?;
    let speed = |name: &str| init.speed_mps.get(name).copied().unwrap_or(0.0);
    let at_ego: Placed = init.placed[ego];
    let at_lead: Placed = init.placed[&lead];
    let ego_controlled = vehicles.iter().any(|v| v.name == ego && v.controlled);
    if stories.ego_actions > 0 || ego_controlled {
        warnings.push(format!(
            "the ego `{ego}`'s {} storyboard action(s){} are not applied: carfollow's loop drives the chase",
            stories.ego_actions,
            if ego_controlled { " and its controller" } else { "" }
        ));
    }
    let lead_kind = vehicles.iter().find(|v| v.name == lead).map_or("", |v| v.kind);
    warnings.push(format!(
        "the lead `{lead}` (a {lead_kind} in the file) is carfollow's lead vehicle, the pickup with the tracker's target board"
    ));
    // The chase starts its camera `initial_gap_m` from the lead's rear bumper.
    let camera_forward_m = f64::from(vehicle::CameraMount::default().forward_m);
    let rear_bumper_m = f64::from(vehicle::VehicleParams::pickup().rear_bumper_x_m());
    let gap_m = at_lead.s_m + rear_bumper_m - camera_forward_m - at_ego.s_m;
    if !(3.0..=60.0).contains(&gap_m) {
        return Err(OscError::At {
            path: xml.path.clone(),
            line: init.line.get(ego).copied().unwrap_or(1),
            message: format!("the ego `{ego}` starts with its camera {gap_m:.1} m behind the lead `{lead}`'s back: carfollow's chase starts 3–60 m behind the target it follows"),
        });
    }
    let duration_s = match options.duration_s {
        Some(d) => d,
        None => duration(xml)?,
    };
    let ego_speed = speed(ego);
    if (ego_speed - speed(&lead)).abs() > 1e-9 {
        warnings.push(format!(
            "the ego `{ego}` starts at the lead's speed, {} m/s, not its own {} m/s (carfollow's chase starts at the lead's speed); {} m/s is its cruising speed",
            speed(&lead), ego_speed, ego_speed
        ));
    }
    let base = options.relative_to.clone().unwrap_or_else(|| dir.to_path_buf());
    let header = child(xml.doc.root_element(), "FileHeader");
    let description = header.and_then(|h| h.attribute("description")).unwrap_or("").to_string();
    let stem = xml.path.file_stem().map_or("imported".into(), |s| s.to_string_lossy().into_owned());

    let mut doc = Table::new();
    doc.insert("name".into(), Value::String(stem));
    doc.insert("description".into(), Value::String(description));
    doc.insert("duration_s".into(), Value::Float(duration_s));
    let mut opendrive = Table::new();
    opendrive.insert("file".into(), Value::String(relative(&road.file, &base).to_string_lossy().replace('\\', "/")));
    opendrive.insert("road".into(), Value::String(road.lanes.id.clone()));
    let mut route = Table::new();
    route.insert("opendrive".into(), Value::Table(opendrive));
    doc.insert("route".into(), Value::Table(route));

    let mut lead_table = Table::new();
    lead_table.insert("start_m".into(), Value::Float(at_lead.s_m));
    lead_table.insert("initial_speed_mps".into(), Value::Float(speed(&lead)));
    lead_table.insert("speed_profile".into(), profile(speed(&lead)));
    lead_table.insert("lane".into(), Value::Integer(i64::from(at_lead.lane)));
    if let Some(events) = stories.events.get(&lead) {
        lead_table.insert("events".into(), events_value(xml, events)?);
    }
    doc.insert("lead".into(), Value::Table(lead_table));

    let mut controller = Table::new();
    controller.insert("lane_keeping".into(), Value::Boolean(true));
    if ego_speed >= 0.5 {
        controller.insert("cruise_speed_mps".into(), Value::Float(ego_speed));
    }
    let mut chase = Table::new();
    chase.insert("initial_gap_m".into(), Value::Float(gap_m));
    chase.insert("controller".into(), Value::Table(controller));
    doc.insert("chase".into(), Value::Table(chase));

    let mut tracker = Table::new();
    tracker.insert("target".into(), Value::String("targets/nist-ten-segment.toml".into()));
    doc.insert("tracker".into(), Value::Table(tracker));

    let mut actors = Vec::new();
    for v in vehicles.iter().filter(|v| v.name != ego && v.name != lead) {
        let at = init.placed[&v.name];
        let mut actor = Table::new();
        actor.insert("name".into(), Value::String(names[&v.name].clone()));
        actor.insert("kind".into(), Value::String(v.kind.into()));
        actor.insert("lane".into(), Value::Integer(i64::from(at.lane)));
        let mut start = Table::new();
        start.insert("station_m".into(), Value::Float(at.s_m));
        actor.insert("start".into(), Value::Table(start));
        actor.insert("initial_speed_mps".into(), Value::Float(speed(&v.name)));
        actor.insert("speed_profile".into(), profile(speed(&v.name)));
        if let Some(events) = stories.events.get(&v.name) {
            actor.insert("events".into(), events_value(xml, events)?);
        }
        actors.push(Value::Table(actor));
    }
    if !actors.is_empty() {
        doc.insert("actors".into(), Value::Array(actors));
    }
    let body = toml::to_string(&doc).map_err(|e| OscError::File { path: xml.path.clone(), message: format!("cannot write the scenario: {e}") })?;
    let source = xml.path.file_name().map_or(String::new(), |f| f.to_string_lossy().into_owned());
    let text = format!("# Imported from the OpenSCENARIO file {source} by `carfollow import`.\n{body}");
    Ok(Imported { text, warnings })
}
