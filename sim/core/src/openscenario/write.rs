//! The scenario as carfollow writes it: the road, the chase, the lead, the actors with
//! their events, and the duration, as a scenario file's TOML.

use super::entities::Entity;
use super::error::OscError;
use super::init::{Init, Placed, RoadLanes};
use super::story::{read_stories, Names};
use super::world::ReferenceLine;
use super::xml::{child, children, elements, only_element, Xml};
use super::{ImportOptions, Imported};
use roxmltree::Node;
use std::path::{Component, Path, PathBuf};

/// The lead's target: the NIST board, shipped with carfollow.
const TARGET: &str = "targets/nist-ten-segment.toml";

/// The road of the file's `RoadNetwork/LogicFile`.
pub struct Road {
    /// Its id and lanes.
    pub lanes: RoadLanes,
    /// The OpenDRIVE file.
    pub file: PathBuf,
    /// Its reference line, as carfollow lays it.
    pub segments: Vec<sim_render::RouteSegment>,
}

/// Reads the road of `RoadNetwork/LogicFile` (relative to `dir`, the scenario's folder).
pub fn read_road(xml: &Xml, dir: &Path) -> Result<Road, OscError> {
    let root = xml.doc.root_element();
    let logic = child(root, "RoadNetwork")
        .and_then(|n| child(n, "LogicFile"))
        .ok_or_else(|| xml.at(root, "<OpenSCENARIO> has no <RoadNetwork><LogicFile>: carfollow's route is the road of an OpenDRIVE file"))?;
    let file = dir.join(xml.req(logic, "filepath")?);
    let opendrive = crate::opendrive::load(&file).map_err(|e| match e {
        crate::opendrive::OpenDriveError::Io { source, .. } => xml.at(
            logic,
            format!("<LogicFile>: cannot read {}: {source}", file.display()),
        ),
        other => other.into(),
    })?;
    let road = crate::opendrive::import(&opendrive, None, |_| None)?;
    let origin = opendrive
        .roads
        .iter()
        .find(|r| r.id == road.id)
        .and_then(|r| r.geometries.first())
        .map_or([0.0; 3], |g| [g.x, g.y, g.hdg]);
    Ok(Road {
        lanes: RoadLanes {
            heading_rad: origin[2],
            reference: ReferenceLine::new(origin, road.segments.clone()),
            id: road.id,
            roads: road.roads,
            lanes: road.lanes,
            lane_width_m: road.lane_width_m,
            lane_widths_m: road.lane_widths_m,
            median_m: road.median_m,
            inner_lanes: road.inner_lanes,
            lane_offset: road.lane_offset,
        },
        file,
        segments: road.segments,
    })
}

/// The largest share of the camera's half field of view the target may lie off its axis
/// at the start: room around it for the tracker's window.
const IN_VIEW_SHARE: f64 = 0.6;
/// The default lens and pixel, mm, and half the frame's width, pixels (`[camera]`).
const DEFAULT_FOCAL_MM: f64 = 8.0;
const PIXEL_MM: f64 = 0.025;
const HALF_WIDTH_PX: f64 = 128.0;

/// The lens, mm: one that sees the target at the initial gap `gap_m` as the default 8 mm
/// lens sees it at the target's nominal range, or the default's where that is longer; but
/// no longer than keeps the target (its back at station `target_s_m`) within
/// [`IN_VIEW_SHARE`] of the half field of view from the camera at `camera_s_m` (a tight
/// curve puts it off the axis). `lanes` are the chase's and the lead's.
fn focal_length_mm(
    road: &Road,
    camera_s_m: f64,
    target_s_m: f64,
    lanes: [u32; 2],
    gap_m: f64,
) -> f64 {
    let nominal_m = crate::parse_target(crate::BUILTIN_TARGET_TEXT, Path::new(TARGET))
        .map_or(10.0, |t| t.nominal_range_m());
    let spec = sim_render::RouteSpec {
        segments: road.segments.clone(),
        intersections_m: Vec::new(),
        lane_width_m: road.lanes.lane_width_m,
        lanes: road.lanes.lanes,
        elevation: Vec::new(),
        median_m: road.lanes.median_m,
        lane_widths_m: road.lanes.lane_widths_m.clone(),
        lane_offset: road.lanes.lane_offset.clone(),
    };
    let route = sim_render::Route::new(spec.clone());
    let camera = route.pose_at(camera_s_m, spec.lane_centre_m(lanes[0]));
    let [x, z] = route.point(target_s_m, spec.lane_centre_m(lanes[1]));
    let seen = camera.inverse_transform_point(&nalgebra::Point3::new(x, 0.0, z));
    let off_axis = seen.z.atan2(seen.x).abs();
    let widest = HALF_WIDTH_PX * PIXEL_MM * IN_VIEW_SHARE / off_axis.tan().max(1e-9);
    let f = (DEFAULT_FOCAL_MM * gap_m / nominal_m)
        .min(widest)
        .max(DEFAULT_FOCAL_MM);
    (f * 10.0).round() / 10.0
}

/// The longest lens a cruising chase is given, mm: through it a car's back, 1.8 m wide,
/// fills 80 % of the frame's width 8.8 m off, so that a chase stopping nearer loses it (one
/// lens trades reach against the view up close).
const MAX_CRUISE_FOCAL_MM: f64 = 25.0;
/// The time from a vehicle entering the search's reach to the chase's braking on it, s: a
/// few frames of search and the first measurements, the loop's latency and the gap
/// keeper's reaction time.
const ACQUIRE_TO_BRAKE_S: f64 = 1.0;

/// The lens, mm, of a chase cruising at `speed_mps` with nothing followed (no lead, or one
/// far ahead): one whose whole-image search ([`tracker::robust::acquire_scales`]) reaches
/// a vehicle's back as far as the chase needs to stop behind it, in normal braking, from
/// the moment the search could find it ([`ACQUIRE_TO_BRAKE_S`] at that speed, then the gap
/// keeper's largest deceleration, to its standstill gap); the default 8 mm lens where that
/// reaches far enough, and at most [`MAX_CRUISE_FOCAL_MM`]. The default lens finds a
/// vehicle's back of 10 m nominal range from 25 m only, from which a chase at 72 km/h
/// cannot stop.
fn cruise_focal_length_mm(speed_mps: f64) -> f64 {
    let gap_keeper = vehicle::GapKeeperConfig::default();
    let standstill_m = match gap_keeper.policy {
        vehicle::GapPolicy::TimeHeadway {
            standstill_gap_m, ..
        } => f64::from(standstill_gap_m),
        _ => f64::from(gap_keeper.min_gap_m),
    };
    let decel = f64::from(gap_keeper.max_decel_mps2);
    let needed_m =
        speed_mps * ACQUIRE_TO_BRAKE_S + speed_mps * speed_mps / (2.0 * decel) + standstill_m;
    let nominal_m = crate::parse_target(crate::BUILTIN_TARGET_TEXT, Path::new(TARGET))
        .map_or(10.0, |t| t.nominal_range_m());
    let reach_m = nominal_m / tracker::robust::ACQUIRE_SCALES[0];
    let f = (DEFAULT_FOCAL_MM * needed_m / reach_m).clamp(DEFAULT_FOCAL_MM, MAX_CRUISE_FOCAL_MM);
    (f * 10.0).round() / 10.0
}

/// carfollow's names for the vehicles: `chase`, `lead`, and each other vehicle's name with
/// what an actor's name may not hold (anything but letters, digits, `-` and `_`) made
/// `-`, unique.
fn carfollow_names(vehicles: &[Entity], ego: &str, lead: Option<&str>) -> Names {
    let mut names = Names::new();
    let mut used: Vec<String> = vec!["chase".into(), "lead".into()];
    for v in vehicles {
        let name = if v.name == ego {
            "chase".to_string()
        } else if Some(v.name.as_str()) == lead {
            "lead".to_string()
        } else {
            let base = super::safe_name(&v.name);
            let base = if base.is_empty() {
                "actor".to_string()
            } else {
                base
            };
            super::unique(&base, &mut used)
        };
        names.insert(v.name.clone(), name);
    }
    names
}

/// What `--lead` says for no lead: the chase cruises, following nothing until its tracker
/// finds a vehicle in its path.
pub const NO_LEAD: &str = "none";

/// How far the chase's camera starts behind the lead's back, metres, for an ego placed at
/// station `ego_s_m` and a lead at `lead_s_m` (the chase starts its camera `initial_gap_m`
/// from the lead's rear bumper).
fn camera_gap_m(ego_s_m: f64, lead_s_m: f64) -> f64 {
    let camera_forward_m = f64::from(vehicle::CameraMount::default().forward_m);
    let rear_bumper_m = f64::from(vehicle::VehicleParams::pickup().rear_bumper_x_m());
    lead_s_m + rear_bumper_m - camera_forward_m - ego_s_m
}

/// The lead chosen, and, when the nearest vehicle ahead is not it because it starts beyond
/// the renderer's reach, that vehicle's name and camera gap.
struct LeadChoice {
    lead: Option<String>,
    beyond_reach: Option<(String, f64)>,
}

/// The lead: `given` ([`NO_LEAD`] for none), or the nearest vehicle ahead of the ego in
/// its lane at t = 0 (its reference point in the lane's strip, `lanes`), or none when no vehicle is, or when that vehicle starts further ahead
/// than the renderer draws ([`crate::MAX_INITIAL_GAP_M`]): it is then an actor in the
/// chase's path, which the chase cruises towards until its tracker finds it, as esmini's
/// ego approaches a far target.
fn choose_lead(
    xml: &Xml,
    vehicles: &[Entity],
    init: &Init,
    lanes: &RoadLanes,
    ego: &str,
    given: Option<&str>,
) -> Result<LeadChoice, OscError> {
    let at_ego = init.placed[ego];
    match given {
        Some(NO_LEAD) => {
            return Ok(LeadChoice {
                lead: None,
                beyond_reach: None,
            })
        }
        Some(name) => {
            if name == ego || !vehicles.iter().any(|v| v.name == name) {
                return Err(OscError::File {
                    path: xml.path.clone(),
                    message: format!(
                        "--lead {name}: no vehicle of that name other than the ego (--lead {NO_LEAD} for no lead)"
                    ),
                });
            }
            if init.placed.get(name).is_some_and(|p| p.oncoming) {
                return Err(OscError::File {
                    path: xml.path.clone(),
                    message: format!(
                        "--lead {name}: it starts on the oncoming side; carfollow's lead starts in a lane of the ego's side"
                    ),
                });
            }
            return Ok(LeadChoice {
                lead: Some(name.to_string()),
                beyond_reach: None,
            });
        }
        None => {}
    }
    let nearest = vehicles
        .iter()
        .filter(|v| v.name != ego)
        .filter_map(|v| init.placed.get(&v.name).map(|p| (v, p)))
        .filter(|(_, p)| lanes.lane_of_placed(p) == Some(at_ego.lane) && p.s_m > at_ego.s_m)
        .min_by(|a, b| a.1.s_m.total_cmp(&b.1.s_m));
    Ok(match nearest {
        Some((v, p)) if camera_gap_m(at_ego.s_m, p.s_m) > crate::MAX_INITIAL_GAP_M => LeadChoice {
            lead: None,
            beyond_reach: Some((v.name.clone(), camera_gap_m(at_ego.s_m, p.s_m))),
        },
        nearest => LeadChoice {
            lead: nearest.map(|(v, _)| v.name.clone()),
            beyond_reach: None,
        },
    })
}

/// What of the ego is read and not applied, for its one warning: its storyboard actions
/// (`actions` of them), its controller (`controlled`), its controller actions in `Init` (at
/// `init_lines`); `None` when nothing is.
fn ego_ignored(actions: usize, controlled: bool, init_lines: &[u32]) -> Option<String> {
    let mut parts = Vec::new();
    if actions > 0 {
        parts.push(format!("{actions} storyboard action(s)"));
    }
    if controlled {
        parts.push("controller".to_string());
    }
    if !init_lines.is_empty() {
        let lines: Vec<String> = init_lines.iter().map(u32::to_string).collect();
        parts.push(format!(
            "controller action(s) in <Init> (line {})",
            lines.join(", ")
        ));
    }
    let verb = if parts == ["controller"] { "is" } else { "are" };
    match parts.len() {
        0 => None,
        1 => Some(format!("{} {verb}", parts[0])),
        n => Some(format!(
            "{} and {} {verb}",
            parts[..n - 1].join(", "),
            parts[n - 1]
        )),
    }
}

/// How long a run whose `StopTrigger` gives no simulation time may last at the most, s:
/// it ends when one of its conditions holds, or then.
pub const STOP_LIMIT_S: f64 = 120.0;

/// The `StopTrigger`'s condition groups that are one `SimulationTimeCondition` each: the
/// time of the earliest (its value and delay), the scenario's duration. The other groups
/// end the run as events do ([`super::story::read_stories`]); `None` when every group is
/// one of those.
fn duration(xml: &Xml) -> Result<Option<f64>, OscError> {
    let root = xml.doc.root_element();
    let stop = child(root, "Storyboard").and_then(|s| child(s, "StopTrigger"));
    let Some(stop) = stop.filter(|s| elements(*s).next().is_some()) else {
        return Err(xml.at(root, "<Storyboard> has no <StopTrigger>: give the run's length with --set duration_s=SECONDS"));
    };
    let groups: Vec<_> = children(stop, "ConditionGroup").collect();
    if groups.is_empty() {
        return Err(xml.at(stop, "<StopTrigger> has no <ConditionGroup>: give the run's length with --set duration_s=SECONDS"));
    }
    let mut earliest: Option<f64> = None;
    for group in groups {
        if let Some((condition, time)) = time_only(xml, group)? {
            let delay = xml.opt_num(condition, "delay")?.unwrap_or(0.0).max(0.0);
            let at = xml.num(time, "value")?.max(0.0) + delay;
            earliest = Some(earliest.map_or(at, |e| e.min(at)));
        }
    }
    Ok(earliest)
}

/// When `group` (a `ConditionGroup`) is one `SimulationTimeCondition` and nothing else: its
/// `Condition` and that element.
pub(super) fn time_only<'a, 'b>(
    xml: &Xml,
    group: Node<'a, 'b>,
) -> Result<Option<(Node<'a, 'b>, Node<'a, 'b>)>, OscError> {
    let conditions: Vec<_> = children(group, "Condition").collect();
    let [condition] = conditions.as_slice() else {
        return Ok(None);
    };
    let time = child(*condition, "ByValueCondition")
        .map(|v| only_element(xml, v))
        .transpose()?
        .filter(|c| c.has_tag_name("SimulationTimeCondition"));
    Ok(time.map(|t| (*condition, t)))
}

/// `path` relative to the folder `base` (both made absolute; `..` where they part).
pub(super) fn relative(path: &Path, base: &Path) -> PathBuf {
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

/// The actor `v` is, as written.
fn actor_out(v: &Entity, init: &Init, names: &Names, stories: &super::story::Stories) -> ActorOut {
    let at = init.placed[&v.name];
    let speed = init.speed_mps.get(&v.name).copied().unwrap_or(0.0);
    let events = stories.events.get(&v.name).cloned().unwrap_or_default();
    ActorOut {
        name: names[&v.name].clone(),
        kind: v.kind.into(),
        lane: at.lane,
        offset_m: at.offset_m,
        start: StartOut { station_m: at.s_m },
        initial_speed_mps: starting_speed(speed, &events, init, names),
        speed_profile: vec![[0.0, speed]],
        events,
    }
}

/// The speed a vehicle whose `Init` gives it `init_speed` starts at: that, or the target of
/// a step speed change one of its `events` makes at t = 0, the first such. OpenSCENARIO's
/// step is at once, and carfollow's physics reaches no speed at once but the one a vehicle
/// starts at (so esmini's `cut-in.xosc` sets its overtaker's speed at the act's start).
/// A change relative to another vehicle takes that vehicle's `Init` speed (carfollow's
/// `names` for the file's). A target beyond carfollow's top speed starts the vehicle at
/// that speed, the fastest its driver drives.
fn starting_speed(
    init_speed: f64,
    events: &[vehicle::EventSpec],
    init: &Init,
    names: &Names,
) -> f64 {
    use vehicle::{ActionSpec, Rule, Shape, TriggerSpec};
    let at_start = |t: &TriggerSpec| {
        let plain = TriggerSpec {
            time_s: Some(0.0),
            rule: t.rule,
            rising: t.rising,
            ..TriggerSpec::default()
        };
        *t == plain && matches!(t.rule, None | Some(Rule::Greater))
    };
    let speed_of = |name: &str| {
        names
            .iter()
            .find(|(_, n)| n.as_str() == name)
            .map(|(file, _)| init.speed_mps.get(file).copied().unwrap_or(0.0))
    };
    let target = |a: &ActionSpec| {
        let step = ActionSpec {
            speed_mps: a.speed_mps,
            speed_of: a.speed_of.clone(),
            speed_factor: a.speed_factor,
            continuous: a.continuous,
            shape: Some(Shape::Step),
            ..ActionSpec::default()
        };
        if *a != step {
            return None;
        }
        match (&a.speed_of, a.speed_mps, a.speed_factor) {
            (None, speed, _) => speed,
            (Some(of), delta, factor) => {
                let base = speed_of(of)?;
                Some(factor.map_or(base + delta.unwrap_or(0.0), |f| base * f))
            }
        }
    };
    events
        .iter()
        .filter(|e| at_start(&e.trigger))
        .find_map(|e| target(&e.action))
        .map_or(init_speed, |v| {
            v.clamp(0.0, f64::from(vehicle::MAX_SPEED_MPS))
        })
}

/// The scenario file written, its tables in the order a person writes them.
#[derive(serde::Serialize)]
struct Doc {
    name: String,
    description: String,
    duration_s: f64,
    route: RouteOut,
    #[serde(skip_serializing_if = "Option::is_none")]
    lead: Option<LeadOut>,
    chase: ChaseOut,
    camera: CameraOut,
    tracker: TrackerOut,
    #[serde(skip_serializing_if = "Option::is_none")]
    environment: Option<super::environment::EnvironmentOut>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    actors: Vec<ActorOut>,
}

#[derive(serde::Serialize)]
struct RouteOut {
    opendrive: OpenDriveOut,
}

#[derive(serde::Serialize)]
struct OpenDriveOut {
    file: String,
    road: String,
}

#[derive(serde::Serialize)]
struct LeadOut {
    start_m: f64,
    lane: u32,
    #[serde(skip_serializing_if = "is_centre")]
    offset_m: f64,
    initial_speed_mps: f64,
    speed_profile: Vec<[f64; 2]>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    events: Vec<vehicle::EventSpec>,
}

#[derive(serde::Serialize)]
struct ChaseOut {
    #[serde(skip_serializing_if = "Option::is_none")]
    start_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lane: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    initial_gap_m: Option<f64>,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    start_at_cruise_speed: bool,
    controller: ControllerOut,
}

#[derive(serde::Serialize)]
struct ControllerOut {
    lane_keeping: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    cruise_speed_mps: Option<f64>,
}

#[derive(serde::Serialize)]
struct CameraOut {
    focal_length_mm: f64,
}

#[derive(serde::Serialize)]
struct TrackerOut {
    target: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    start: Option<&'static str>,
}

#[derive(serde::Serialize)]
struct ActorOut {
    name: String,
    kind: String,
    lane: u32,
    #[serde(skip_serializing_if = "is_centre")]
    offset_m: f64,
    start: StartOut,
    initial_speed_mps: f64,
    speed_profile: Vec<[f64; 2]>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    events: Vec<vehicle::EventSpec>,
}

/// For `skip_serializing_if`: a start on its lane's centre.
fn is_centre(offset_m: &f64) -> bool {
    *offset_m == 0.0
}

#[derive(serde::Serialize)]
struct StartOut {
    station_m: f64,
}

/// Checks the ego's start `gap_m` behind the lead (`names`: the ego's and the lead's; the
/// ego placed at `line`), at `ego_speed`: 3 m to the renderer's far plane, and over
/// [`crate::MAX_PLACED_GAP_M`] (a far start: the chase cruises at the ego's speed until its
/// tracker finds the lead, said in a warning) at a speed carfollow's chase cruises at.
/// Returns whether the start is far.
fn start_gap(
    xml: &Xml,
    line: u32,
    [ego, lead]: [&str; 2],
    gap_m: f64,
    ego_speed: f64,
    warnings: &mut Vec<String>,
) -> Result<bool, OscError> {
    let max_gap_m = crate::MAX_INITIAL_GAP_M;
    let refuse = |message: String| OscError::At {
        path: xml.path.clone(),
        line,
        message,
    };
    if !(3.0..=max_gap_m).contains(&gap_m) {
        return Err(refuse(format!("the ego `{ego}` starts with its camera {gap_m:.1} m behind the lead `{lead}`'s back: carfollow's chase starts 3–{max_gap_m} m behind the target it follows (the renderer draws nothing further)")));
    }
    let far = gap_m > crate::MAX_PLACED_GAP_M;
    if far && ego_speed < 0.5 {
        return Err(refuse(format!("the ego `{ego}` starts {gap_m:.1} m behind the lead `{lead}` at {ego_speed} m/s: a chase that starts over {} m behind cruises at its own speed until it finds the lead, and carfollow's chase cruises at 0.5 m/s or more", crate::MAX_PLACED_GAP_M)));
    }
    if far {
        warnings.push(format!(
            "the ego `{ego}` starts {gap_m:.1} m behind the lead `{lead}`: the chase cruises at {ego_speed} m/s and its tracker searches until it finds the lead"
        ));
    }
    Ok(far)
}

/// How the chase starts: behind its lead, or with none, and what that decides of the lens
/// and the tracker's start.
struct Start {
    lead: Option<LeadOut>,
    chase: ChaseOut,
    /// Whether the tracker starts by searching.
    search: bool,
    focal_length_mm: f64,
}

/// The chase's start behind the lead (`[ego, lead]` their names in the file), at the gap
/// their places at t = 0 give, with the lead's events from `stories`.
#[allow(clippy::too_many_arguments)]
fn behind_lead(
    xml: &Xml,
    vehicles: &[Entity],
    road: &Road,
    init: &Init,
    names: &Names,
    stories: &super::story::Stories,
    [ego, lead]: [&str; 2],
    warnings: &mut Vec<String>,
) -> Result<Start, OscError> {
    let speed = |name: &str| init.speed_mps.get(name).copied().unwrap_or(0.0);
    let (at_ego, at_lead) = (init.placed[ego], init.placed[lead]);
    let lead_kind = vehicles
        .iter()
        .find(|v| v.name == lead)
        .map_or("", |v| v.kind);
    warnings.push(format!(
        "the lead `{lead}` (a {lead_kind} in the file) is carfollow's lead vehicle, the pickup with the tracker's target board"
    ));
    let camera_forward_m = f64::from(vehicle::CameraMount::default().forward_m);
    let rear_bumper_m = f64::from(vehicle::VehicleParams::pickup().rear_bumper_x_m());
    let gap_m = camera_gap_m(at_ego.s_m, at_lead.s_m);
    let ego_speed = speed(ego);
    let line = init.line.get(ego).copied().unwrap_or(1);
    let far = start_gap(xml, line, [ego, lead], gap_m, ego_speed, warnings)?;
    // Far behind, the chase cruises at the ego's speed with nothing followed, as with no
    // lead, and needs the lens that finds the lead as far as it needs to stop behind it,
    // should the lead be standing.
    let focal_length_mm = if far {
        cruise_focal_length_mm(ego_speed)
    } else {
        focal_length_mm(
            road,
            at_ego.s_m + camera_forward_m,
            at_lead.s_m + rear_bumper_m,
            [at_ego.lane, at_lead.lane],
            gap_m,
        )
    };
    let gap_m = (gap_m * 1e6).round() / 1e6;
    let lead_events = stories.events.get(lead).cloned().unwrap_or_default();
    Ok(Start {
        lead: Some(LeadOut {
            start_m: at_lead.s_m,
            lane: at_lead.lane,
            offset_m: at_lead.offset_m,
            initial_speed_mps: starting_speed(speed(lead), &lead_events, init, names),
            speed_profile: vec![[0.0, speed(lead)]],
            events: lead_events,
        }),
        chase: ChaseOut {
            start_m: None,
            lane: None,
            initial_gap_m: Some(gap_m),
            // The ego starts at its own speed where it has one carfollow's chase can cruise
            // at, else at the lead's.
            start_at_cruise_speed: ego_speed >= 0.5 && (ego_speed - speed(lead)).abs() > 1e-9,
            controller: ControllerOut {
                lane_keeping: true,
                cruise_speed_mps: (ego_speed >= 0.5).then_some(ego_speed),
            },
        },
        search: far,
        focal_length_mm,
    })
}

/// The chase's start with no lead: where the ego is placed (at `line`), cruising at its
/// speed, `ego_speed`, with its tracker searching its path (said in a warning, with why
/// when the nearest vehicle ahead, `beyond_reach`, starts beyond the renderer's reach).
fn without_lead(
    xml: &Xml,
    line: u32,
    ego: &str,
    at_ego: &Placed,
    ego_speed: f64,
    beyond_reach: Option<(String, f64)>,
    warnings: &mut Vec<String>,
) -> Result<Start, OscError> {
    let no_lead = match beyond_reach {
        Some((name, gap_m)) => format!(
            "no lead (the nearest vehicle ahead in its lane, `{name}`, starts {gap_m:.1} m \
             ahead of the ego's camera, beyond the {} m carfollow's renderer draws, so it is \
             a vehicle in the chase's path)",
            crate::MAX_INITIAL_GAP_M
        ),
        None => "no lead".to_string(),
    };
    if ego_speed < 0.5 {
        return Err(OscError::At {
            path: xml.path.clone(),
            line,
            message: format!(
                "the ego `{ego}` starts at {ego_speed} m/s with {no_lead}: carfollow's chase \
                 then cruises at its own speed, 0.5 m/s or more, until its tracker finds a \
                 vehicle in its path (--lead NAME names one to follow)"
            ),
        });
    }
    warnings.push(format!(
        "{no_lead}: the ego `{ego}` cruises at {ego_speed} m/s in its lane and its tracker \
         searches its path (--lead NAME names a vehicle to follow)"
    ));
    Ok(Start {
        lead: None,
        chase: ChaseOut {
            start_m: Some(at_ego.s_m),
            lane: Some(at_ego.lane),
            initial_gap_m: None,
            start_at_cruise_speed: false,
            controller: ControllerOut {
                lane_keeping: true,
                cruise_speed_mps: Some(ego_speed),
            },
        },
        search: true,
        focal_length_mm: cruise_focal_length_mm(ego_speed),
    })
}

/// The warnings a file's storyboard gives: the ego's actions and controller, which are
/// not applied; a maneuver's events that run side by side; the acts and events that never
/// start.
fn story_warnings(
    vehicles: &[Entity],
    ego: &str,
    init: &Init,
    stories: &super::story::Stories,
    warnings: &mut Vec<String>,
) {
    let ego_controlled = vehicles.iter().any(|v| v.name == ego && v.controlled);
    if let Some(ignored) = ego_ignored(
        stories.ego_actions,
        ego_controlled,
        &init.ego_controller_lines,
    ) {
        warnings.push(format!(
            "the ego `{ego}`'s {ignored} not applied: carfollow's loop drives the chase"
        ));
    }
    if !stories.side_by_side.is_empty() {
        warnings.push(format!(
            "the events of maneuver{} `{}` run side by side: carfollow ends a running action \
             only when another of its kind starts (speed; lane or offset), where the priority \
             `override` would also end the maneuver's other running events",
            if stories.side_by_side.len() == 1 {
                ""
            } else {
                "s"
            },
            stories.side_by_side.join("`, `")
        ));
    }
    if !stories.never_started.is_empty() {
        warnings.push(format!(
            "{} never start{}, and {} not imported: each condition group of {} start \
             trigger{} holds a `ParameterCondition` that does not hold, and nothing changes \
             a parameter during a run",
            stories.never_started.join(", "),
            if stories.never_started.len() == 1 {
                "s"
            } else {
                ""
            },
            if stories.never_started.len() == 1 {
                "is"
            } else {
                "are"
            },
            if stories.never_started.len() == 1 {
                "its"
            } else {
                "their"
            },
            if stories.never_started.len() == 1 {
                ""
            } else {
                "s"
            },
        ));
    }
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
            return Err(OscError::At {
                path: xml.path.clone(),
                line: v.line,
                message: format!(
                    "<ScenarioObject name=\"{}\"> is placed by no <TeleportAction> in <Init>",
                    v.name
                ),
            });
        }
        if v.controlled && v.name != ego {
            return Err(OscError::At { path: xml.path.clone(), line: v.line, message: format!("unsupported <ObjectController> of `{}` (carfollow drives its vehicles by their events)", v.name) });
        }
    }
    // Said on the command line, else as carfollow's export writes a chase without a lead.
    let given = options.lead.as_deref().or_else(|| {
        vehicles
            .iter()
            .any(|v| v.name == ego && v.follows_no_lead)
            .then_some(NO_LEAD)
    });
    let LeadChoice { lead, beyond_reach } =
        choose_lead(xml, vehicles, &init, &road.lanes, ego, given)?;
    let names = carfollow_names(vehicles, ego, lead.as_deref());
    let read_stop = options.duration_s.is_none();
    let stories = read_stories(xml, &names, &init, &road.lanes, ego, read_stop)?;
    let speed = |name: &str| init.speed_mps.get(name).copied().unwrap_or(0.0);
    let at_ego: Placed = init.placed[ego];
    if at_ego.oncoming {
        let line = init.line.get(ego).copied().unwrap_or(1);
        return Err(OscError::At {
            path: xml.path.clone(),
            line,
            message: format!("the ego `{ego}` starts on the oncoming side: carfollow's chase starts in a lane of its own side"),
        });
    }
    if at_ego.offset_m != 0.0 {
        let line = init.line.get(ego).copied().unwrap_or(1);
        return Err(OscError::At {
            path: xml.path.clone(),
            line,
            message: format!(
                "the ego `{ego}` starts {:.2} m {} its lane's centre: carfollow's chase starts on it",
                at_ego.offset_m.abs(),
                if at_ego.offset_m > 0.0 { "left of" } else { "right of" }
            ),
        });
    }
    story_warnings(vehicles, ego, &init, &stories, &mut warnings);
    let ego_speed = speed(ego);
    let line = init.line.get(ego).copied().unwrap_or(1);
    let start = match &lead {
        Some(lead) => behind_lead(
            xml,
            vehicles,
            road,
            &init,
            &names,
            &stories,
            [ego, lead],
            &mut warnings,
        )?,
        None => without_lead(
            xml,
            line,
            ego,
            &at_ego,
            ego_speed,
            beyond_reach,
            &mut warnings,
        )?,
    };
    let duration_s = match options.duration_s {
        Some(d) => d,
        None => match duration(xml)? {
            Some(d) => d,
            None => {
                warnings.push(format!(
                    "<StopTrigger> gives no simulation time: the run ends when one of its \
                     conditions holds, or at {STOP_LIMIT_S} s (--set duration_s=SECONDS runs \
                     that long instead, the StopTrigger unread)"
                ));
                STOP_LIMIT_S
            }
        },
    };
    if let Some(lead) = lead
        .as_deref()
        .filter(|l| (ego_speed - speed(l)).abs() > 1e-9)
    {
        if ego_speed < 0.5 {
            warnings.push(format!(
                "the ego `{ego}` starts at the lead's speed, {} m/s, not its own {ego_speed} m/s: carfollow's chase cruises at 0.5 m/s or more",
                speed(lead)
            ));
        }
    }
    let base = options
        .relative_to
        .clone()
        .unwrap_or_else(|| dir.to_path_buf());
    let header = child(xml.doc.root_element(), "FileHeader");
    let description = header
        .and_then(|h| h.attribute("description"))
        .unwrap_or("")
        .to_string();
    let stem = xml
        .path
        .file_stem()
        .map_or("imported".into(), |s| s.to_string_lossy().into_owned());

    let doc = Doc {
        name: stem,
        description,
        duration_s,
        route: RouteOut {
            opendrive: OpenDriveOut {
                file: relative(&road.file, &base)
                    .to_string_lossy()
                    .replace('\\', "/"),
                road: road.lanes.id.clone(),
            },
        },
        lead: start.lead,
        chase: start.chase,
        camera: CameraOut {
            focal_length_mm: start.focal_length_mm,
        },
        tracker: TrackerOut {
            target: TARGET.into(),
            start: start.search.then_some("search"),
        },
        environment: init.environment.clone(),
        actors: vehicles
            .iter()
            .filter(|v| v.name != ego && Some(&v.name) != lead.as_ref())
            .map(|v| actor_out(v, &init, &names, &stories))
            .collect(),
    };
    let body = toml::to_string(&doc).map_err(|e| OscError::File {
        path: xml.path.clone(),
        message: format!("cannot write the scenario: {e}"),
    })?;
    let source = xml
        .path
        .file_name()
        .map_or(String::new(), |f| f.to_string_lossy().into_owned());
    let text =
        format!("# Imported from the OpenSCENARIO file {source} by `carfollow import`.\n{body}");
    Ok(Imported { text, warnings })
}
