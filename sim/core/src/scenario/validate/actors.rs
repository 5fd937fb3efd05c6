//! `[[actors]]`, `lead.lane` and the events: the other vehicles, where they start, and what
//! their events name.

use super::{check, lead::speed_profile, Blame};
use crate::scenario::traffic::{kind_albedo, kind_params, ActorSpec};
use crate::scenario::{ScenarioError, ScenarioFile};
use sim_render::VehicleKind;
use vehicle::VehicleParams;

/// Most actors a scenario may have: the renderer's slots for them.
pub const MAX_ACTORS: usize = sim_render::ObjectSlot::MAX_ACTORS as usize;
/// The smallest room between two vehicles that start in the same lane, bumper to bumper,
/// metres.
const MIN_START_GAP_M: f64 = 0.5;

/// A vehicle placed so far: its name, its lane, where its rear axle starts, its speed and
/// its physics (for its bumpers).
struct Placed {
    name: String,
    lane: u32,
    /// Its offset from its lane's centre, m (positive left).
    offset_m: f64,
    /// Its centre line's distance to the left of the road's centre line, m.
    left_m: f64,
    start_m: f64,
    speed_mps: f64,
    params: VehicleParams,
}

impl Placed {
    fn front_m(&self) -> f64 {
        self.start_m + f64::from(self.params.front_bumper_x_m())
    }
    fn rear_m(&self) -> f64 {
        self.start_m + f64::from(self.params.rear_bumper_x_m())
    }
    /// Whether its body and `other`'s lie side by side across the road: in the same lane
    /// when neither is off its lane's centre, else by their widths about their centre lines.
    fn abreast(&self, other: &Placed) -> bool {
        if self.offset_m == 0.0 && other.offset_m == 0.0 {
            return self.lane == other.lane;
        }
        let half = 0.5 * f64::from(self.params.width_m + other.params.width_m);
        (self.left_m - other.left_m).abs() < half
    }
}

/// The lead's lane, and the actors, checked: names, kinds, lanes on the road, starts on the
/// route and apart from each other, offsets within their lanes, profiles, and events that
/// name vehicles and lanes that exist. `lanes` is the road's lanes each way (`route.lanes`,
/// or its road file's), `route` the road (its lanes' widths and centres),
/// `chase_start_m` is where the chase's rear axle starts (in `chase_lane`), `[chase, lead]`
/// the speeds the chase and the lead (when the scenario has one) start at.
pub(super) fn actors(
    raw: &ScenarioFile,
    lanes: u32,
    route: &sim_render::RouteSpec,
    route_length_m: f64,
    (chase_start_m, chase_lane): (f64, u32),
    [chase_initial_speed_mps, lead_initial_speed_mps]: [f64; 2],
    f: &Blame,
) -> Result<Vec<ActorSpec>, ScenarioError> {
    f.at(
        "route.lanes",
        check(
            (1..=4).contains(&lanes),
            "must be 1–4 (lanes each way)",
            lanes,
        ),
    )?;
    let in_road = |lane: u32| (1..=lanes).contains(&lane);
    let lane_field = if raw.lead.is_some() {
        "lead.lane"
    } else {
        "chase.lane"
    };
    f.at(
        lane_field,
        check(
            in_road(chase_lane),
            &format!("must be a lane of the road, 1–{lanes} (route.lanes)"),
            chase_lane,
        ),
    )?;
    if let Some(lead) = &raw.lead {
        offset(
            "lead.offset_m",
            lead.offset_m,
            route.lane_width_of(lead.lane),
            f,
        )?;
    }
    f.at(
        "actors",
        check(
            raw.actors.len() <= MAX_ACTORS,
            &format!("at most {MAX_ACTORS} actors"),
            raw.actors.len(),
        ),
    )?;
    let mut placed = vec![Placed {
        name: "chase".into(),
        lane: chase_lane,
        offset_m: 0.0,
        left_m: -route.lane_centre_m(chase_lane),
        start_m: chase_start_m,
        speed_mps: chase_initial_speed_mps,
        params: VehicleParams::hmmwv_m998(),
    }];
    if let Some(lead) = &raw.lead {
        placed.push(Placed {
            name: "lead".into(),
            lane: lead.lane,
            offset_m: lead.offset_m,
            left_m: lead.offset_m - route.lane_centre_m(lead.lane),
            start_m: lead.start_m,
            speed_mps: lead_initial_speed_mps,
            params: VehicleParams::pickup(),
        });
    }
    let mut out = Vec::with_capacity(raw.actors.len());
    for (i, a) in raw.actors.iter().enumerate() {
        actor_offset(&format!("actors[{i}].offset_m"), a, route, f)?;
        let (spec, me) = actor(i, a, lanes, route, route_length_m, &placed, f)?;
        placed.push(me);
        out.push(spec);
    }
    let names: Vec<&str> = placed.iter().map(|p| p.name.as_str()).collect();
    if let Some(lead) = &raw.lead {
        events("lead.events", &lead.events, &names, lanes, f)?;
    }
    for (i, a) in raw.actors.iter().enumerate() {
        events(&format!("actors[{i}].events"), &a.events, &names, lanes, f)?;
    }
    Ok(out)
}

/// Actor `i` (`a`) checked against the vehicles `placed` before it, on a road of `lanes`
/// lanes each way and `route_length_m` metres: what the plan places, and its place.
fn actor(
    i: usize,
    a: &crate::scenario::ActorFile,
    lanes: u32,
    route: &sim_render::RouteSpec,
    route_length_m: f64,
    placed: &[Placed],
    f: &Blame,
) -> Result<(ActorSpec, Placed), ScenarioError> {
    let in_road = |lane: u32| (1..=lanes).contains(&lane);
    let at = |field: &str| format!("actors[{i}].{field}");
    f.at(
        &at("name"),
        check(
            !a.name.is_empty()
                && a.name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_'),
            "must be non-empty: letters, digits, '-' or '_'",
            format!("{:?}", a.name),
        ),
    )?;
    f.at(
        &at("name"),
        check(
            !placed.iter().any(|p| p.name == a.name),
            "is taken: `chase`, `lead` and every actor need a name of their own",
            format!("{:?}", a.name),
        ),
    )?;
    let kind = VehicleKind::ALL
        .into_iter()
        .find(|k| k.as_str() == a.kind)
        .ok_or_else(|| {
            f.invalid(
                &at("kind"),
                format!(
                    "= {:?}: must be one of {}",
                    a.kind,
                    VehicleKind::ALL
                        .map(|k| format!("\"{}\"", k.as_str()))
                        .join(", ")
                ),
            )
        })?;
    f.at(
        &at("lane"),
        check(
            in_road(a.lane),
            &format!("must be a lane of the road, 1–{lanes} (route.lanes)"),
            a.lane,
        ),
    )?;
    let section = format!("actors[{i}]");
    let profile = speed_profile(&section, &a.speed_basis, &a.speed_profile)
        .map_err(|(field, message)| f.invalid(&field, message))?;
    let speed = a
        .initial_speed_mps
        .unwrap_or_else(|| a.speed_profile.first().map_or(0.0, |k| k[1]));
    f.at(
        &at("initial_speed_mps"),
        check(
            speed.is_finite() && (0.0..=40.0).contains(&speed),
            "must be 0–40 m/s",
            speed,
        ),
    )?;
    let albedo = a.albedo.unwrap_or_else(|| kind_albedo(kind));
    f.at(
        &at("albedo"),
        check(
            albedo.is_finite() && (0.02..=0.95).contains(&albedo),
            "must be 0.02–0.95",
            albedo,
        ),
    )?;
    let params = kind_params(kind);
    let start_m = start(i, a, placed, &params, speed, f)?;
    f.at(
        &at("start"),
        check(
            start_m.is_finite()
                && start_m + f64::from(params.rear_bumper_x_m()) >= 0.0
                && start_m + f64::from(params.front_bumper_x_m()) <= route_length_m,
            &format!("puts it off the route (0–{route_length_m:.0} m, bumper to bumper)"),
            format!("{start_m:.1} m"),
        ),
    )?;
    let me = Placed {
        name: a.name.clone(),
        lane: a.lane,
        offset_m: a.offset_m,
        left_m: a.offset_m - route.lane_centre_m(a.lane),
        start_m,
        speed_mps: speed,
        params,
    };
    if let Some(other) = placed.iter().find(|p| {
        p.abreast(&me)
            && me.rear_m() < p.front_m() + MIN_START_GAP_M
            && p.rear_m() < me.front_m() + MIN_START_GAP_M
    }) {
        // Off their lanes' centres, by their bodies (on them, `abreast` is the same lane).
        if me.offset_m != 0.0 || other.offset_m != 0.0 {
            return Err(f.invalid(
                &at("start"),
                format!(
                    "puts its body against `{}`'s (its {:.1}–{:.1} m along the route and \
                     {:.2} m left of the centre line, `{}`'s {:.1}–{:.1} m and {:.2} m, \
                     each as wide as it is): leave at least {MIN_START_GAP_M} m between them",
                    other.name,
                    me.rear_m(),
                    me.front_m(),
                    me.left_m,
                    other.name,
                    other.rear_m(),
                    other.front_m(),
                    other.left_m
                ),
            ));
        }
        return Err(f.invalid(
            &at("start"),
            format!(
                "puts it on `{}` in lane {} (its body {:.1}–{:.1} m along the route, \
                 `{}`'s {:.1}–{:.1} m): leave at least {MIN_START_GAP_M} m between them",
                other.name,
                me.lane,
                me.rear_m(),
                me.front_m(),
                other.name,
                other.rear_m(),
                other.front_m()
            ),
        ));
    }
    let spec = ActorSpec {
        name: a.name.clone(),
        kind,
        lane: a.lane,
        offset_m: a.offset_m,
        start_m,
        initial_speed_mps: speed,
        profile,
        albedo,
        events: a.events.clone(),
        // Set with the sun's elevation (`validate`).
        tail_lamps: false,
    };
    Ok((spec, me))
}

/// Where actor `i` (`a`, with physics `params` and initial speed `speed`) starts, its rear
/// axle's station: by station, or by gap or time gap to a vehicle placed before it.
fn start(
    i: usize,
    a: &crate::scenario::ActorFile,
    placed: &[Placed],
    params: &VehicleParams,
    speed: f64,
    f: &Blame,
) -> Result<f64, ScenarioError> {
    let field = format!("actors[{i}].start");
    let s = &a.start;
    let say = |m: &str| f.invalid(&field, m.to_string());
    match (s.station_m, s.gap_m, s.time_gap_s) {
        (Some(station), None, None) => {
            if s.ahead_of.is_some() || s.behind.is_some() {
                return Err(say(
                    "gives station_m with ahead_of or behind: a station is along the route, \
                     a gap is to a vehicle",
                ));
            }
            Ok(station)
        }
        (None, gap, time_gap) if gap.is_some() != time_gap.is_some() => {
            let (to, ahead) = match (&s.ahead_of, &s.behind) {
                (Some(to), None) => (to, true),
                (None, Some(to)) => (to, false),
                _ => {
                    return Err(say(
                        "gives a gap: name the vehicle with exactly one of ahead_of or behind",
                    ))
                }
            };
            let Some(other) = placed.iter().find(|p| &p.name == to) else {
                let known: Vec<&str> = placed.iter().map(|p| p.name.as_str()).collect();
                return Err(f.invalid(
                    &format!("{field}.{}", if ahead { "ahead_of" } else { "behind" }),
                    format!(
                        "= {to:?}: no such vehicle before this actor (it may name {})",
                        known.join(", ")
                    ),
                ));
            };
            let gap_m = match (gap, time_gap) {
                (Some(g), None) => {
                    f.at(
                        &format!("{field}.gap_m"),
                        check(
                            g.is_finite() && (0.0..=1000.0).contains(&g),
                            "must be 0–1000 m",
                            g,
                        ),
                    )?;
                    g
                }
                (None, Some(t)) => {
                    f.at(
                        &format!("{field}.time_gap_s"),
                        check(
                            t.is_finite() && (0.0..=60.0).contains(&t),
                            "must be 0–60 s",
                            t,
                        ),
                    )?;
                    // The vehicle behind covers the gap.
                    let behind_speed = if ahead { other.speed_mps } else { speed };
                    if behind_speed <= 0.0 && t > 0.0 {
                        return Err(f.invalid(
                            &format!("{field}.time_gap_s"),
                            format!(
                                "= {t}: the vehicle behind starts standing, so a time gap has \
                                 no length: give gap_m"
                            ),
                        ));
                    }
                    t * behind_speed
                }
                _ => unreachable!("exactly one of the two, by the match"),
            };
            Ok(if ahead {
                other.front_m() + gap_m - f64::from(params.rear_bumper_x_m())
            } else {
                other.rear_m() - gap_m - f64::from(params.front_bumper_x_m())
            })
        }
        _ => Err(say(
            "must give exactly one of station_m, gap_m or time_gap_s (with ahead_of or \
             behind for a gap)",
        )),
    }
}

/// The events of one vehicle (at `section`) checked: their own rules, then that every
/// vehicle they name is in `names` and every lane they name is on the road.
fn events(
    section: &str,
    script: &vehicle::EventScript,
    names: &[&str],
    lanes: u32,
    f: &Blame,
) -> Result<(), ScenarioError> {
    script.validate().map_err(|e| {
        let (field, message) = crate::scenario::vehicle_error(section, &e);
        f.invalid(&field, message)
    })?;
    for (field, to) in script.vehicles_named() {
        if !names.contains(&to) {
            return Err(f.invalid(
                &format!("{section}{}", field.trim_start_matches("events")),
                format!(
                    "= {to:?}: no such vehicle (the scenario has {})",
                    names.join(", ")
                ),
            ));
        }
    }
    for (field, lane) in script.lanes_named() {
        if !(1..=lanes).contains(&lane) {
            return Err(f.invalid(
                &format!("{section}{}", field.trim_start_matches("events")),
                format!("= {lane}: no such lane: the road has lanes 1–{lanes} (route.lanes)"),
            ));
        }
    }
    Ok(())
}

/// Whether an offset `offset_m` from lane `lane`'s centre puts a vehicle's reference point
/// on a lane of the oncoming side, within half that lane's width of its centre.
pub(crate) fn on_oncoming_lane(route: &sim_render::RouteSpec, lane: u32, offset_m: f64) -> bool {
    let right_m = route.lane_centre_m(lane) - offset_m;
    offset_m.is_finite()
        && (1..=route.lanes)
            .any(|k| (right_m + route.lane_centre_m(k)).abs() <= 0.5 * route.lane_width_of(k))
}

/// An actor's offset from its lane's centre (`field`), checked: as [`offset`], or onto a
/// lane of the oncoming side ([`on_oncoming_lane`]), where it drives with the road.
fn actor_offset(
    field: &str,
    a: &super::super::traffic::ActorFile,
    route: &sim_render::RouteSpec,
    f: &Blame,
) -> Result<(), ScenarioError> {
    if on_oncoming_lane(route, a.lane, a.offset_m) {
        return Ok(());
    }
    let half = 0.5 * route.lane_width_of(a.lane);
    let centre = |k: u32| route.lane_centre_m(a.lane) + route.lane_centre_m(k);
    let (near, far) = (1, route.lanes);
    f.at(
        field,
        check(
            a.offset_m.is_finite() && a.offset_m.abs() <= half,
            &format!(
                "must be within half its lane's width, ±{half} m, or {:.2}–{:.2} m (on a lane \
                 of the oncoming side, driven with the road)",
                centre(near) - 0.5 * route.lane_width_of(near),
                centre(far) + 0.5 * route.lane_width_of(far)
            ),
            a.offset_m,
        ),
    )
}

/// A vehicle's offset from its lane's centre (`field`), checked: finite, and within half the
/// lane's width `lane_width_m`, so that its reference point stays in its lane.
pub(super) fn offset(
    field: &str,
    offset_m: f64,
    lane_width_m: f64,
    f: &Blame,
) -> Result<(), ScenarioError> {
    let half = 0.5 * lane_width_m;
    f.at(
        field,
        check(
            offset_m.is_finite() && offset_m.abs() <= half,
            &format!("must be within half its lane's width, ±{half} m"),
            offset_m,
        ),
    )
}
