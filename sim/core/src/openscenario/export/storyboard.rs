//! The storyboard written: `Init` (each vehicle's lane, station and speed, and the
//! environment), and one story of the lead's and the actors' speed profiles and events.

use super::act_start::act_start;
use super::entity;
use super::xml_out::{a, n, XmlOut};
use crate::Scenario;
use vehicle::{ActionSpec, EventSpec, KeepSide, KeepSpec, ProfileEntry, Rule, Shape, TriggerSpec};

/// One vehicle's maneuver: its entity name and its events as written.
struct Group {
    entity: String,
    /// The name of its maneuver group (its maneuver's is this and `-maneuver`): the
    /// entity's, or, in an act of its own, the event's.
    label: String,
    /// The profile's speed changes, as events of their own.
    profile: Vec<ProfileStep>,
    /// Its events, each with the name written (unique in the file).
    events: Vec<(String, EventSpec)>,
    /// The lanes inside the driving lanes on each side of the road file written (1 with a
    /// median): carfollow's lane k is OpenDRIVE's lane −(k + this).
    inner_lanes: i64,
    /// The `maximumExecutionCount` of an event that repeats with no limit: one run a
    /// physics step of the scenario's duration and one more, more than it can run (an
    /// event starts at most once a step), since the standard's count has no "no limit".
    unlimited_runs: u32,
}

/// A step of a speed profile: from the key `from` (s or m), to `speed_mps` by the next
/// key `to`.
struct ProfileStep {
    name: String,
    from: f64,
    to: f64,
    from_speed_mps: f64,
    speed_mps: f64,
    distance: bool,
}

/// The story: the lead's maneuver group (when there is a lead) and each actor's; and the events that end the
/// run, which the `StopTrigger` holds.
pub struct Story {
    groups: Vec<Group>,
    /// The events judged once a latched condition holds (an `all` whose first member is
    /// latched): each in an act of its own, started by that member, with the rest of the
    /// `all` as its own trigger.
    acts: Vec<(TriggerSpec, Group)>,
    /// Each vehicle's events whose action is `end_run` (a group of them alone).
    stops: Vec<Group>,
}

impl Story {
    /// The story of `s`.
    pub fn new(s: &Scenario) -> Story {
        let file = &s.resolved;
        let mut taken: Vec<String> = Vec::new();
        let mut groups = Vec::new();
        if let Some(lead) = &file.lead {
            groups.push(group(
                "lead",
                &lead.speed_profile,
                &lead.speed_basis,
                s.lead_initial_speed_mps,
                &s.lead_events.0,
                &mut taken,
            ));
        }
        for (actor, written) in s.actors.iter().zip(&file.actors) {
            groups.push(group(
                &actor.name,
                &written.speed_profile,
                &written.speed_basis,
                actor.initial_speed_mps,
                &actor.events.0,
                &mut taken,
            ));
        }
        let inner_lanes = crate::opendrive::inner_lanes(&s.route);
        let steps = (s.duration_s * f64::from(vehicle::PHYSICS_HZ)).ceil();
        let unlimited_runs = (steps + 1.0).min(f64::from(u32::MAX)) as u32;
        let mut stops = Vec::new();
        for g in &mut groups {
            g.inner_lanes = inner_lanes;
            g.unlimited_runs = unlimited_runs;
            let (ends, events) = std::mem::take(&mut g.events)
                .into_iter()
                .partition(|(_, e)| e.action.end_run == Some(true));
            g.events = events;
            stops.push(Group {
                entity: g.entity.clone(),
                label: g.entity.clone(),
                profile: Vec::new(),
                events: ends,
                inner_lanes,
                unlimited_runs,
            });
        }
        let mut acts = Vec::new();
        for g in &mut groups {
            for (name, mut event) in std::mem::take(&mut g.events) {
                let Some((start, own)) = act_start(&event.trigger) else {
                    g.events.push((name, event));
                    continue;
                };
                event.trigger = own;
                acts.push((
                    start,
                    Group {
                        entity: g.entity.clone(),
                        label: name.clone(),
                        profile: Vec::new(),
                        events: vec![(name, event)],
                        inner_lanes,
                        unlimited_runs,
                    },
                ));
            }
        }
        groups.retain(|g| !g.profile.is_empty() || !g.events.is_empty());
        stops.retain(|g| !g.events.is_empty());
        Story {
            groups,
            acts,
            stops,
        }
    }

    /// The condition groups the events that end the run add to the `StopTrigger`: each
    /// event's trigger as its start trigger would be written, about its vehicle.
    pub fn write_stops(&self, x: &mut XmlOut) {
        for g in &self.stops {
            for (name, e) in &g.events {
                g.trigger(x, name, &e.trigger);
            }
        }
    }

    /// The `Story` element (none when no vehicle has a speed change or an event).
    pub fn write(&self, x: &mut XmlOut) {
        if self.groups.is_empty() && self.acts.is_empty() {
            return;
        }
        x.open("Story", &[a("name", "carfollow")]);
        if !self.groups.is_empty() {
            x.open("Act", &[a("name", "act")]);
            for g in &self.groups {
                g.write(x);
            }
            x.open("StartTrigger", &[]);
            time_condition(x, "act-start", 0.0, "greaterThan");
            x.close();
            x.close();
        }
        for (start, g) in &self.acts {
            let name = format!("{}-act", g.label);
            x.open("Act", &[a("name", &name)]);
            g.write(x);
            x.open("StartTrigger", &[]);
            g.trigger(x, &format!("{name}-start"), start);
            x.close();
            x.close();
        }
        x.close();
    }
}

/// `name`, or `name` made unique among `taken` (`name-2`, ...), taken.
fn unique(name: &str, taken: &mut Vec<String>) -> String {
    let mut out = name.to_string();
    let mut k = 2;
    while taken.contains(&out) {
        out = format!("{name}-{k}");
        k += 1;
    }
    taken.push(out.clone());
    out
}

fn group(
    name: &str,
    profile: &[[f64; 2]],
    basis: &str,
    initial_speed_mps: f64,
    events: &[EventSpec],
    taken: &mut Vec<String>,
) -> Group {
    let entity = entity(name).to_string();
    let distance = basis == "distance";
    let mut steps = Vec::new();
    let mut speed = initial_speed_mps;
    let mut key = 0.0_f64;
    for &[k, v] in profile {
        if v != speed {
            steps.push(ProfileStep {
                name: unique(&format!("{entity}-profile-{}", steps.len() + 1), taken),
                from: key.min(k),
                to: k,
                from_speed_mps: speed,
                speed_mps: v,
                distance,
            });
        }
        speed = v;
        key = k;
    }
    let events = events
        .iter()
        .map(|e| (unique(&e.name, taken), e.clone()))
        .collect();
    Group {
        label: entity.clone(),
        entity,
        profile: steps,
        events,
        inner_lanes: 0,
        unlimited_runs: 1,
    }
}

impl Group {
    fn write(&self, x: &mut XmlOut) {
        x.open(
            "ManeuverGroup",
            &[a("maximumExecutionCount", 1), a("name", &self.label)],
        );
        x.open("Actors", &[a("selectTriggeringEntities", "false")]);
        x.empty("EntityRef", &[a("entityRef", &self.entity)]);
        x.close();
        x.open("Maneuver", &[a("name", format!("{}-maneuver", self.label))]);
        for step in &self.profile {
            self.profile_event(x, step);
        }
        for (name, e) in &self.events {
            let runs = match (e.repeat, e.max_runs) {
                (false, _) => 1,
                (true, Some(n)) => n,
                (true, None) => self.unlimited_runs,
            };
            x.open(
                "Event",
                &[
                    a("name", name),
                    a("priority", "parallel"),
                    a("maximumExecutionCount", runs),
                ],
            );
            x.open("Action", &[a("name", format!("{name}-action"))]);
            self.action(x, &e.action);
            x.close();
            x.open("StartTrigger", &[]);
            self.trigger(x, name, &e.trigger);
            x.close();
            x.close();
        }
        x.close();
        x.close();
    }

    /// A step of the profile: at its key, linear to its speed by the next key (over the
    /// time between them, or, by distance, at the rate that reaches it over the distance).
    fn profile_event(&self, x: &mut XmlOut, step: &ProfileStep) {
        x.open(
            "Event",
            &[
                a("name", &step.name),
                a("priority", "parallel"),
                a("maximumExecutionCount", 1),
            ],
        );
        x.open("Action", &[a("name", format!("{}-action", step.name))]);
        let span = step.to - step.from;
        let dynamics = if span <= 0.0 {
            ("step", "time", 0.0)
        } else if step.distance {
            let rate = (step.speed_mps.powi(2) - step.from_speed_mps.powi(2)).abs() / (2.0 * span);
            ("linear", "rate", rate)
        } else {
            ("linear", "time", span)
        };
        speed_action(x, dynamics, SpeedTarget::Absolute(step.speed_mps));
        x.close();
        x.open("StartTrigger", &[]);
        if step.distance {
            condition_group(x, |x| {
                self.entity_condition(x, &step.name, Edge::LEVEL, |x| {
                    x.empty("TraveledDistanceCondition", &[n("value", step.from)]);
                });
            });
        } else {
            time_condition(x, &step.name, step.from, "greaterOrEqual");
        }
        x.close();
        x.close();
    }

    fn action(&self, x: &mut XmlOut, action: &ActionSpec) {
        if let Some(k) = &action.keep {
            keep_action(x, k);
            return;
        }
        if let Some(profile) = &action.profile {
            speed_profile(x, profile);
            return;
        }
        if let Some(offset) = action.offset_m {
            let shape = match action.shape {
                Some(Shape::Sinusoidal) => "sinusoidal",
                _ => "cubic",
            };
            x.open("PrivateAction", &[]);
            x.open("LateralAction", &[]);
            x.open("LaneOffsetAction", &[a("continuous", "false")]);
            x.empty(
                "LaneOffsetActionDynamics",
                &[
                    n(
                        "maxLateralAcc",
                        action.lateral_accel_mps2.unwrap_or_default(),
                    ),
                    a("dynamicsShape", shape),
                ],
            );
            x.open("LaneOffsetTarget", &[]);
            x.empty("AbsoluteTargetLaneOffset", &[n("value", offset)]);
            x.close();
            x.close();
            x.close();
            x.close();
            return;
        }
        if let Some(lane) = action.lane {
            let shape = match action.shape {
                Some(Shape::Sinusoidal) => "sinusoidal",
                _ => "cubic",
            };
            let (dimension, value) = match (action.duration_s, action.lateral_speed_mps) {
                (_, Some(v)) => ("rate", v),
                (Some(d), None) => ("time", d),
                (None, None) => ("time", 0.0),
            };
            x.open("PrivateAction", &[]);
            x.open("LateralAction", &[]);
            x.open("LaneChangeAction", &[]);
            x.empty(
                "LaneChangeActionDynamics",
                &[
                    a("dynamicsShape", shape),
                    n("value", value),
                    a("dynamicsDimension", dimension),
                ],
            );
            x.open("LaneChangeTarget", &[]);
            x.empty(
                "AbsoluteTargetLane",
                &[a("value", -(lane as i64) - self.inner_lanes)],
            );
            x.close();
            x.close();
            x.close();
            x.close();
            return;
        }
        let (speed, dynamics) = match (action.speed_mps.or(action.speed_factor), action.stop) {
            (Some(v), _) => {
                let d = match (action.shape, action.duration_s, action.rate_mps2) {
                    (Some(Shape::Step), _, _) => ("step", "time", 0.0),
                    (_, _, Some(r)) => ("linear", "rate", r),
                    (Some(Shape::Cubic), Some(d), None) => ("cubic", "time", d),
                    (_, Some(d), None) => ("linear", "time", d),
                    (_, None, None) => ("step", "time", 0.0),
                };
                (v, d)
            }
            // A stop: to 0 at its deceleration.
            _ => (
                0.0,
                match action.decel_mps2 {
                    Some(r) => ("linear", "rate", r),
                    None => ("step", "time", 0.0),
                },
            ),
        };
        let target = match &action.speed_of {
            Some(of) => SpeedTarget::Relative {
                of: entity(of),
                value: speed,
                factor: action.speed_factor.is_some(),
                continuous: action.continuous,
            },
            None => SpeedTarget::Absolute(speed),
        };
        speed_action(x, dynamics, target);
    }

    /// The condition groups of trigger `t` of the event `name`: one for each group of
    /// [`groups`], its conditions named after the event (the event's own name when there
    /// is one condition).
    fn trigger(&self, x: &mut XmlOut, name: &str, t: &TriggerSpec) {
        let groups = groups(t);
        let one = groups.len() == 1 && groups[0].len() == 1;
        for (g, group) in groups.iter().enumerate() {
            condition_group(x, |x| {
                for (k, leaf) in group.iter().enumerate() {
                    let named = if one {
                        name.to_string()
                    } else {
                        format!("{name}-{}-{}", g + 1, k + 1)
                    };
                    self.condition(x, &named, leaf);
                }
            });
        }
    }

    /// The `Condition` `name` of the one-condition trigger `t`.
    fn condition(&self, x: &mut XmlOut, name: &str, t: &TriggerSpec) {
        let rule = |default: Rule| match t.rule.unwrap_or(default) {
            Rule::Less => "lessThan",
            Rule::Greater => "greaterThan",
            Rule::Equal => "equalTo",
            Rule::NotEqual => "notEqualTo",
        };
        let edge = Edge {
            delay: t.delay_s.unwrap_or(0.0),
            rising: t.rising,
            falling: t.falling,
        };
        let to = t.to.as_deref().map(entity).unwrap_or(super::EGO);
        if let Some(v) = t.time_s {
            condition(x, name, edge, |x| {
                x.open("ByValueCondition", &[]);
                x.empty(
                    "SimulationTimeCondition",
                    &[n("value", v), a("rule", rule(Rule::Greater))],
                );
                x.close();
            });
        } else if let Some(v) = t.distance_m {
            self.entity_condition(x, name, edge, |x| {
                x.empty("TraveledDistanceCondition", &[n("value", v)]);
            });
        } else if let Some((other, state)) = t
            .after
            .as_ref()
            .map(|e| (e, "endTransition"))
            .or(t.started.as_ref().map(|e| (e, "startTransition")))
        {
            let target = self
                .events
                .iter()
                .find(|(_, e)| &e.name == other)
                .map_or(other.as_str(), |(written, _)| written.as_str());
            condition(x, name, edge, |x| {
                x.open("ByValueCondition", &[]);
                x.empty(
                    "StoryboardElementStateCondition",
                    &[
                        a("storyboardElementType", "event"),
                        a("storyboardElementRef", target),
                        a("state", state),
                    ],
                );
                x.close();
            });
        } else if let Some((v, freespace)) = t
            .gap_m
            .map(|v| (v, "true"))
            .or(t.spacing_m.map(|v| (v, "false")))
        {
            self.entity_condition(x, name, edge, |x| {
                x.empty(
                    "RelativeDistanceCondition",
                    &[
                        a("entityRef", to),
                        a("freespace", freespace),
                        a("relativeDistanceType", "longitudinal"),
                        a("coordinateSystem", "road"),
                        n("value", v),
                        a("rule", rule(Rule::Less)),
                    ],
                );
            });
        } else if let Some(v) = t.time_gap_s {
            let freespace = if t.between_axles { "false" } else { "true" };
            // A headway is measured by the vehicle behind towards the one ahead: ahead of
            // `to`, this vehicle is the one measured to.
            let (subject, reference) = match t.side {
                Some(vehicle::KeepSide::Ahead) => (to, self.entity.as_str()),
                _ => (self.entity.as_str(), to),
            };
            self.watching_condition(x, name, edge, subject, |x| {
                x.empty(
                    "TimeHeadwayCondition",
                    &[
                        a("entityRef", reference),
                        n("value", v),
                        a("freespace", freespace),
                        a("coordinateSystem", "road"),
                        a("relativeDistanceType", "longitudinal"),
                        a("rule", rule(Rule::Less)),
                    ],
                );
            });
        } else if let Some(v) = t.ttc_s {
            let freespace = if t.between_axles { "false" } else { "true" };
            self.entity_condition(x, name, edge, |x| {
                x.open(
                    "TimeToCollisionCondition",
                    &[
                        n("value", v),
                        a("freespace", freespace),
                        a("coordinateSystem", "road"),
                        a("relativeDistanceType", "longitudinal"),
                        a("rule", rule(Rule::Less)),
                    ],
                );
                x.open("TimeToCollisionConditionTarget", &[]);
                x.empty("EntityRef", &[a("entityRef", to)]);
                x.close();
                x.close();
            });
        } else if let Some(v) = t.speed_mps {
            let of = t.of.as_deref().map_or(self.entity.as_str(), entity);
            self.watching_condition(x, name, edge, of, |x| {
                x.empty(
                    "SpeedCondition",
                    &[n("value", v), a("rule", rule(Rule::Less))],
                );
            });
        } else if let Some(v) = t.standstill_s {
            let of = t.of.as_deref().map_or(self.entity.as_str(), entity);
            self.watching_condition(x, name, edge, of, |x| {
                x.empty("StandStillCondition", &[n("duration", v)]);
            });
        } else if t.contact {
            self.entity_condition(x, name, edge, |x| {
                x.open("CollisionCondition", &[]);
                x.empty("EntityRef", &[a("entityRef", to)]);
                x.close();
            });
        } else if let Some(v) = t.road_end_s {
            let of = t.of.as_deref().map_or(self.entity.as_str(), entity);
            self.watching_condition(x, name, edge, of, |x| {
                x.empty("EndOfRoadCondition", &[n("duration", v)]);
            });
        } else if let Some(v) = t.relative_speed_mps {
            self.entity_condition(x, name, edge, |x| {
                x.empty(
                    "RelativeSpeedCondition",
                    &[
                        a("entityRef", to),
                        n("value", v),
                        a("rule", rule(Rule::Less)),
                    ],
                );
            });
        } else if let Some(r) = &t.reach {
            let of = t.of.as_deref().map_or(self.entity.as_str(), entity);
            self.watching_condition(x, name, edge, of, |x| {
                x.open("ReachPositionCondition", &[n("tolerance", r.tolerance_m)]);
                x.open("Position", &[]);
                x.empty(
                    "LanePosition",
                    &[
                        a("roadId", crate::opendrive::ROAD_ID),
                        a("laneId", -(r.lane as i64) - self.inner_lanes),
                        n("offset", r.offset_m),
                        n("s", r.station_m),
                    ],
                );
                x.close();
                x.close();
            });
        }
    }

    /// A `ByEntityCondition` on this group's vehicle.
    fn entity_condition(
        &self,
        x: &mut XmlOut,
        name: &str,
        edge: Edge,
        inner: impl FnOnce(&mut XmlOut),
    ) {
        self.watching_condition(x, name, edge, &self.entity, inner);
    }

    /// A `ByEntityCondition` on the vehicle the file calls `subject`.
    fn watching_condition(
        &self,
        x: &mut XmlOut,
        name: &str,
        edge: Edge,
        subject: &str,
        inner: impl FnOnce(&mut XmlOut),
    ) {
        condition(x, name, edge, |x| {
            x.open("ByEntityCondition", &[]);
            x.open("TriggeringEntities", &[a("triggeringEntitiesRule", "any")]);
            x.empty("EntityRef", &[a("entityRef", subject)]);
            x.close();
            x.open("EntityCondition", &[]);
            inner(x);
            x.close();
            x.close();
        });
    }
}

/// A trigger as OpenSCENARIO writes one: any of groups, each all of one-condition
/// triggers (an `all` of `any`s multiplied out; `check` bounds how many groups that makes,
/// `vehicle::MAX_TRIGGER_GROUPS`).
fn groups(t: &TriggerSpec) -> Vec<Vec<&TriggerSpec>> {
    if let Some(members) = &t.any {
        members.iter().flat_map(groups).collect()
    } else if let Some(members) = &t.all {
        members.iter().fold(vec![Vec::new()], |sofar, m| {
            let ways = groups(m);
            sofar
                .iter()
                .flat_map(|g| ways.iter().map(move |w| [g.as_slice(), w].concat()))
                .collect()
        })
    } else {
        vec![vec![t]]
    }
}

/// A `ConditionGroup` of the conditions `inner` writes.
fn condition_group(x: &mut XmlOut, inner: impl FnOnce(&mut XmlOut)) {
    x.open("ConditionGroup", &[]);
    inner(x);
    x.close();
}

/// A condition's `delay` (s) and its `conditionEdge`: `rising`, `falling`, both
/// (`risingOrFalling`) or neither (`none`).
#[derive(Clone, Copy)]
struct Edge {
    delay: f64,
    rising: bool,
    falling: bool,
}

impl Edge {
    /// No delay, no edge.
    const LEVEL: Edge = Edge {
        delay: 0.0,
        rising: false,
        falling: false,
    };

    /// The `conditionEdge` attribute.
    fn name(self) -> &'static str {
        match (self.rising, self.falling) {
            (true, true) => "risingOrFalling",
            (true, false) => "rising",
            (false, true) => "falling",
            (false, false) => "none",
        }
    }
}

/// A `Condition`, with its delay and edge.
fn condition(x: &mut XmlOut, name: &str, edge: Edge, inner: impl FnOnce(&mut XmlOut)) {
    x.open(
        "Condition",
        &[
            a("name", name),
            n("delay", edge.delay),
            a("conditionEdge", edge.name()),
        ],
    );
    inner(x);
    x.close();
}

/// A condition group of one `SimulationTimeCondition`.
pub fn time_condition(x: &mut XmlOut, name: &str, value: f64, rule: &str) {
    condition_group(x, |x| {
        condition(x, name, Edge::LEVEL, |x| {
            x.open("ByValueCondition", &[]);
            x.empty(
                "SimulationTimeCondition",
                &[n("value", value), a("rule", rule)],
            );
            x.close();
        });
    });
}

/// A `SpeedProfileAction` of `profile`'s changes (`followingMode="position"`): each with
/// its time, a change at a rate after the first over the time that rate takes from the
/// speed before, the first at a rate as the `DynamicConstraints`' acceleration and
/// deceleration.
fn speed_profile(x: &mut XmlOut, profile: &[ProfileEntry]) {
    x.open("PrivateAction", &[]);
    x.open("LongitudinalAction", &[]);
    x.open("SpeedProfileAction", &[a("followingMode", "position")]);
    if let Some(rate) = profile.first().and_then(|e| e.rate_mps2) {
        x.empty(
            "DynamicConstraints",
            &[
                n("maxAcceleration", rate),
                n("maxDeceleration", rate),
                n("maxSpeed", crate::openscenario::init::MAX_SPEED_MPS),
            ],
        );
    }
    let mut before: Option<f64> = None;
    for e in profile {
        let time = match (e.duration_s, e.rate_mps2, before) {
            (Some(t), _, _) => Some(t),
            (None, Some(r), Some(v)) => Some((e.speed_mps - v).abs() / r),
            _ => None,
        };
        let mut attrs = vec![n("speed", e.speed_mps)];
        if let Some(t) = time {
            attrs.push(n("time", t));
        }
        x.empty("SpeedProfileEntry", &attrs);
        before = Some(e.speed_mps);
    }
    x.close();
    x.close();
    x.close();
}

/// A `SpeedAction` to `speed_mps` with `(shape, dimension, value)` dynamics.
/// Where a `SpeedAction` goes.
enum SpeedTarget<'a> {
    /// To this speed, m/s.
    Absolute(f64),
    /// To the vehicle `of`'s speed plus `value`, or times it (`factor`).
    Relative {
        of: &'a str,
        value: f64,
        factor: bool,
        continuous: bool,
    },
}

/// A `LongitudinalDistanceAction` of the kept gap `k`: its limits as `DynamicConstraints`,
/// those given only (an omitted one reads back as carfollow's default), the jerk limit as
/// both rates.
fn keep_action(x: &mut XmlOut, k: &KeepSpec) {
    let mut attrs = vec![a("entityRef", entity(&k.to))];
    match (k.gap_m, k.time_gap_s) {
        (Some(d), _) => attrs.push(n("distance", d)),
        (None, t) => attrs.push(n("timeGap", t.unwrap_or_default())),
    }
    let side = match k.side.unwrap_or(KeepSide::Behind) {
        KeepSide::Behind => "trailingReferencedEntity",
        KeepSide::Ahead => "leadingReferencedEntity",
        KeepSide::Either => "any",
    };
    attrs.extend([
        a("freespace", !k.between_axles),
        a("continuous", k.continuous.unwrap_or(true)),
        a("displacement", side),
        a("coordinateSystem", "road"),
    ]);
    x.open("PrivateAction", &[]);
    x.open("LongitudinalAction", &[]);
    x.open("LongitudinalDistanceAction", &attrs);
    let limits: Vec<_> = [
        ("maxAcceleration", k.max_accel_mps2),
        ("maxDeceleration", k.max_decel_mps2),
        ("maxSpeed", k.max_speed_mps),
        ("maxAccelerationRate", k.max_jerk_mps3),
        ("maxDecelerationRate", k.max_jerk_mps3),
    ]
    .into_iter()
    .filter_map(|(name, v)| v.map(|v| n(name, v)))
    .collect();
    if !limits.is_empty() {
        x.empty("DynamicConstraints", &limits);
    }
    x.close();
    x.close();
    x.close();
}

fn speed_action(x: &mut XmlOut, (shape, dimension, value): (&str, &str, f64), target: SpeedTarget) {
    x.open("PrivateAction", &[]);
    x.open("LongitudinalAction", &[]);
    x.open("SpeedAction", &[]);
    x.empty(
        "SpeedActionDynamics",
        &[
            a("dynamicsShape", shape),
            n("value", value),
            a("dynamicsDimension", dimension),
        ],
    );
    x.open("SpeedActionTarget", &[]);
    match target {
        SpeedTarget::Absolute(v) => x.empty("AbsoluteTargetSpeed", &[n("value", v)]),
        SpeedTarget::Relative {
            of,
            value,
            factor,
            continuous,
        } => x.empty(
            "RelativeTargetSpeed",
            &[
                a("entityRef", of),
                n("value", value),
                a(
                    "speedTargetValueType",
                    if factor { "factor" } else { "delta" },
                ),
                a("continuous", continuous),
            ],
        ),
    }
    x.close();
    x.close();
    x.close();
    x.close();
}

/// `Init`: the environment, then each vehicle's place and speed.
pub fn init(x: &mut XmlOut, s: &Scenario) {
    x.open("Init", &[]);
    x.open("Actions", &[]);
    environment(x, s);
    // The chase's camera `initial_gap_m` behind the lead's back (as the importer reads an
    // ego's start, with the default camera mount).
    let camera_forward_m = f64::from(vehicle::CameraMount::default().forward_m);
    let rear_bumper_m = f64::from(vehicle::VehicleParams::pickup().rear_bumper_x_m());
    let chase_s = if s.has_lead {
        s.lead_start_m + rear_bumper_m - camera_forward_m - s.initial_gap_m
    } else {
        s.chase_start_m
    };
    let id = |lane: u32| -(lane as i64) - crate::opendrive::inner_lanes(&s.route);
    private(
        x,
        super::EGO,
        (id(s.lead_lane), 0.0),
        chase_s,
        s.chase_initial_speed_mps,
    );
    if s.has_lead {
        private(
            x,
            super::LEAD,
            (id(s.lead_lane), s.lead_offset_m),
            s.lead_start_m,
            s.lead_initial_speed_mps,
        );
    }
    for actor in &s.actors {
        private(
            x,
            &actor.name,
            (id(actor.lane), actor.offset_m),
            actor.start_m,
            actor.initial_speed_mps,
        );
    }
    x.close();
    x.close();
}

/// One vehicle's start: on OpenDRIVE lane `lane_id`, `offset_m` to the left of its centre,
/// at station `s_m`, at `speed_mps`.
fn private(
    x: &mut XmlOut,
    entity: &str,
    (lane_id, offset_m): (i64, f64),
    s_m: f64,
    speed_mps: f64,
) {
    x.open("Private", &[a("entityRef", entity)]);
    x.open("PrivateAction", &[]);
    x.open("TeleportAction", &[]);
    x.open("Position", &[]);
    x.empty(
        "LanePosition",
        &[
            a("roadId", crate::opendrive::ROAD_ID),
            a("laneId", lane_id),
            n("offset", offset_m),
            n("s", s_m),
        ],
    );
    x.close();
    x.close();
    x.close();
    x.open("PrivateAction", &[]);
    x.open("LongitudinalAction", &[]);
    x.open("SpeedAction", &[]);
    x.empty(
        "SpeedActionDynamics",
        &[
            a("dynamicsShape", "step"),
            n("value", 0.0),
            a("dynamicsDimension", "time"),
        ],
    );
    x.open("SpeedActionTarget", &[]);
    x.empty("AbsoluteTargetSpeed", &[n("value", speed_mps)]);
    x.close();
    x.close();
    x.close();
    x.close();
    x.close();
}

/// The sun, the fog and the rain as an `EnvironmentAction`: the sun's azimuth clockwise
/// from north with the road's start heading east (the importer's `azimuth_deg` inverted),
/// its strength as illuminance (full sun 100 000 lx).
fn environment(x: &mut XmlOut, s: &Scenario) {
    let sun = &s.sun;
    let azimuth = (sun.azimuth_deg + 90.0)
        .to_radians()
        .rem_euclid(std::f64::consts::TAU);
    x.open("GlobalAction", &[]);
    x.open("EnvironmentAction", &[]);
    x.open("Environment", &[a("name", "carfollow")]);
    x.open("Weather", &[]);
    x.empty(
        "Sun",
        &[
            n("azimuth", azimuth),
            n("elevation", sun.elevation_deg.to_radians()),
            n("illuminance", sun.strength * 100_000.0),
        ],
    );
    if let Some(fog) = &s.fog {
        x.empty("Fog", &[n("visualRange", fog.visual_range_m)]);
    }
    match &s.rain {
        Some(rain) => x.empty(
            "Precipitation",
            &[
                a("precipitationType", "rain"),
                n("precipitationIntensity", rain.rate_mm_h),
            ],
        ),
        None => x.empty(
            "Precipitation",
            &[
                a("precipitationType", "dry"),
                n("precipitationIntensity", 0.0),
            ],
        ),
    }
    x.close();
    x.close();
    x.close();
    x.close();
}
