//! Validation: a raw [`ScenarioFile`] (overrides applied) checked field by field against
//! its documented bounds, one function per part of the file (route, lead, chase and
//! camera, tracker and loop, environment, distractors, expectations), into a [`Scenario`].
//! What needs the parts together (the chase's start on the route, the physics ground, the
//! controllers, the scene and the first view) is checked by building it, in
//! [`crate::Plan::new`].

mod actors;
mod chase;
mod distractors;
mod elevation;
mod environment;
mod expect;
mod lane_offset;
mod lead;
mod no_lead;
mod route;
mod tracking;

pub use actors::MAX_ACTORS;
pub(crate) use elevation::elevation_problem;
pub use elevation::{MAX_GRADE, MAX_HEIGHT_M, MAX_STEP_M};
pub(crate) use lane_offset::lane_offset_problem;
pub(crate) use route::length_m as route_length_m;
pub(crate) use route::{segment_problem, RoadSource};

use super::file::tail_lamps_lit;
use super::{Scenario, ScenarioError, ScenarioFile, ScenarioSpec};
use tracker::TargetModel;
use vehicle::WorldConfig;

/// Longest route, metres: 50 km, twice the longest shipped drive; it keeps the physics
/// ground (which reaches 200 m past the route) inside its 100 km limit and the drivers'
/// 1 m polyline to 50,000 points.
pub const MAX_ROUTE_M: f64 = 50_000.0;
/// Largest arc radius, metres: 10 km, already indistinguishable from a straight over the
/// camera's range.
pub const MAX_ARC_RADIUS_M: f64 = 10_000.0;
/// Smallest arc radius, metres: the vehicles' turning circles.
pub const MIN_ARC_RADIUS_M: f64 = 8.0;
/// Largest Gaussian blur of the sensor, pixels: beyond 10 px a 256-pixel frame holds no
/// edge at all.
pub const MAX_BLUR_SIGMA_PX: f64 = 10.0;
/// Focal length bounds, millimetres: fish-eye to long telephoto.
pub const FOCAL_LENGTH_MM: [f64; 2] = [1.0, 200.0];
/// Largest teleoperator placement error, pixels: half the frame.
pub const MAX_INIT_OFFSET_PX: f64 = 128.0;

/// Largest `chase.initial_gap_m` at which the tracker may be placed on the target at the
/// start (`tracker.start = "operator"`), metres: the paper's teleoperator placed a target
/// the camera saw (2.2), and 60 m is the longest start the format has always allowed.
/// Beyond it the chase starts far behind: it cruises and its tracker searches.
pub const MAX_PLACED_GAP_M: f64 = 60.0;

/// Largest `chase.initial_gap_m`, metres: the renderer's far plane (`sim_render::FAR_M`,
/// 250 m). Nothing further from the camera is drawn, so a lead further off would not be in
/// the frames at all; the route's length bounds it too (the chase must start on the route,
/// which planning checks).
pub const MAX_INITIAL_GAP_M: f64 = sim_render::FAR_M;

/// Most breadcrumbs the chase controller may keep: 1,000,000 (250 km of path at the
/// default spacing).
pub const MAX_BREADCRUMBS: usize = 1_000_000;

/// A vehicle crate's error as the dotted field it is about (under `prefix`) and what to
/// say of it.
pub(crate) fn vehicle_error(prefix: &str, e: &vehicle::VehicleError) -> (String, String) {
    match e {
        vehicle::VehicleError::InvalidParameter {
            field,
            value,
            allowed,
            reason,
        } => (
            format!("{prefix}.{field}"),
            match allowed {
                Some([min, max]) => format!(
                    "= {}: must be finite and within {min}–{max}",
                    short(value.to_string())
                ),
                None => format!("= {}: {reason}", short(value.to_string())),
            },
        ),
        // An event's field is dotted below the vehicle's `events` list: `events[2].trigger`.
        vehicle::VehicleError::InvalidEvent { field, reason } => (
            format!("{prefix}{}", field.trim_start_matches("events")),
            reason.clone(),
        ),
        other => (prefix.to_string(), format!(": {other}")),
    }
}

/// Whether the override `assignment` (`key=value`) set `field` or a table holding it, or
/// a field inside it.
pub(super) fn override_names(assignment: &str, field: &str) -> bool {
    // An item of a list is `actors[0].lane` in an error and `actors.0.lane` in a `--set`.
    let field = &field.replace('[', ".").replace(']', "");
    assignment.split_once('=').is_some_and(|(k, _)| {
        let k = k.trim();
        k == field
            || field
                .strip_prefix(k)
                .is_some_and(|rest| rest.starts_with('.'))
            || k.strip_prefix(field)
                .is_some_and(|rest| rest.starts_with('.'))
    })
}

/// A number as written for people: `1e300`, not three hundred digits.
fn short(text: String) -> String {
    match text.parse::<f64>() {
        Ok(v) if text.len() > 12 => format!("{v:e}"),
        _ => text,
    }
}

/// Says what is wrong with a field: at its line in the file, or as the `--set` that gave
/// it (see [`super::Source::invalid`]).
pub(crate) struct Blame<'a>(pub(crate) &'a dyn Fn(&str, String) -> ScenarioError);

impl Blame<'_> {
    /// `r`'s message, if any, as the error of `field`.
    fn at(&self, field: &str, r: Result<(), String>) -> Result<(), ScenarioError> {
        r.map_err(|m| (self.0)(field, m))
    }

    /// The error of `field`, saying `message`.
    fn invalid(&self, field: &str, message: String) -> ScenarioError {
        (self.0)(field, message)
    }
}

/// Range check helper: `Err(message)` saying what is allowed.
fn check(ok: bool, allowed: &str, value: impl std::fmt::Display) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(format!("= {}: {allowed}", short(value.to_string())))
    }
}

/// Checks every field of `raw` (given with `overrides` applied) and builds the scenario;
/// `f` places an error, `load_target` reads `tracker.target`, `roads` `route.opendrive`.
pub(super) fn validate(
    raw: ScenarioFile,
    overrides: &[String],
    source: super::Source,
    f: &Blame,
    load_target: impl Fn(&str) -> Result<TargetModel, ScenarioError>,
    roads: &RoadSource,
) -> Result<Scenario, ScenarioError> {
    f.at(
        "name",
        check(
            !raw.name.trim().is_empty()
                && raw
                    .name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_'),
            "must be non-empty, letters, digits, '-' or '_' (it names the output folder)",
            format!("{:?}", raw.name),
        ),
    )?;
    f.at(
        "duration_s",
        check(
            // At least one camera frame: the run records round(duration × 15 Hz) frames.
            raw.duration_s.is_finite()
                && raw.duration_s >= 1.0 / f64::from(vehicle::CAMERA_HZ)
                && raw.duration_s <= 86_400.0,
            "must be at least one camera frame (1/15 s) and at most 86400 seconds",
            raw.duration_s,
        ),
    )?;

    let (route, length, road_warnings) = route::route(&raw.route, f, roads)?;
    let (tracker, init_offset, target, search_start) = tracking::tracker(&raw, f, load_target)?;
    let has_lead = raw.lead.is_some();
    let lead = no_lead::lead_or_lane(&raw, length, search_start, f)?;
    let (lead_profile, lead_initial_speed_mps) = lead::lead(&lead, length, f)?;
    let (chase, camera, initial_gap_m) = chase::chase_and_camera(&raw, f)?;
    let chase_initial_speed_mps = chase::initial_speed(&raw.chase, lead_initial_speed_mps, f)?;
    if has_lead {
        chase::far_start(&raw, initial_gap_m, search_start, f)?;
    }
    let delay = tracking::delay(&raw, f)?;
    let e = environment::environment(&raw.environment, f)?;
    let headlamps = chase::headlamps(&raw.chase, f)?;
    let distractors = distractors::distractors(
        &raw.environment.distractors,
        &target,
        &camera,
        &route,
        lead.start_m,
        &e.sun,
        f,
    )?;
    let placements = environment::overpasses(&raw.environment, length, f)?;
    expect::expect(&raw.expect, f)?;
    chase::tuning(&chase, &lead.driver, f)?;
    let chase_start_m = if has_lead {
        crate::plan::chase_start_m(lead.start_m, initial_gap_m, chase.camera_mount.forward_m)
    } else {
        lead.start_m
    };
    let mut actors = actors::actors(
        &raw,
        route.lanes,
        &route,
        length,
        (chase_start_m, lead.lane),
        [chase_initial_speed_mps, lead_initial_speed_mps],
        f,
    )?;
    let night = e.sun.elevation_deg;
    for (spec, file) in actors.iter_mut().zip(&raw.actors) {
        spec.tail_lamps = tail_lamps_lit(file.lamps.as_ref(), night);
    }
    let lead_tail_lamps = has_lead && tail_lamps_lit(lead.lamps.as_ref(), night);
    let mut world = WorldConfig::default();
    world.ground.bumps = raw.environment.bumps.clone();
    Ok(Scenario::validated(ScenarioSpec {
        resolved: raw.clone(),
        overrides: overrides.to_vec(),
        name: raw.name,
        description: raw.description,
        path: None,
        import_warnings: road_warnings,
        duration_s: raw.duration_s,
        seed: raw.seed,
        route,
        has_lead,
        chase_start_m,
        lead_start_m: lead.start_m,
        lead_initial_speed_mps,
        lead_profile,
        lead_driver: lead.driver,
        lead_lane: lead.lane,
        lead_offset_m: lead.offset_m,
        lead_events: lead.events,
        actors,
        initial_gap_m,
        chase_initial_speed_mps,
        chase,
        camera,
        tracker,
        target,
        init_offset,
        search_start,
        delay,
        world,
        sun: e.sun,
        densities: e.densities,
        placements,
        distractors,
        sensor: e.sensor,
        road_surface: e.road_surface,
        textures: e.textures,
        fog: e.fog,
        rain: e.rain,
        headlamps,
        lead_tail_lamps,
        expect: raw.expect,
        source,
    }))
}
