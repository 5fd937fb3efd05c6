//! An event's trigger checked: exactly one condition, with its vehicles, rule, delay and
//! edges, or a group of them (`all`, `any`).

use super::{
    check, invalid, Condition, EventScript, KeepSide, ReachSpec, Rule, Trigger, TriggerSpec,
};
use super::{MAX_GAP_M, MAX_KEY, MAX_LANES, MAX_POSITION_OFFSET_M, MAX_STANDSTILL_S, MAX_TIME_S};
use super::{MAX_TRIGGER_DEPTH, MAX_TRIGGER_GROUPS};
use crate::error::VehicleError;
use crate::speed_profile::MAX_SPEED_MPS;

impl EventScript {
    /// Event `i`'s trigger at `path` (`trigger`, `trigger.all[1]`, ...), `depth` members
    /// deep, checked.
    pub(super) fn trigger(
        &self,
        i: usize,
        path: &str,
        t: &TriggerSpec,
        depth: usize,
    ) -> Result<Trigger, VehicleError> {
        let given: Vec<&str> = [
            ("time_s", t.time_s.is_some()),
            ("distance_m", t.distance_m.is_some()),
            ("gap_m", t.gap_m.is_some()),
            ("spacing_m", t.spacing_m.is_some()),
            ("time_gap_s", t.time_gap_s.is_some()),
            ("ttc_s", t.ttc_s.is_some()),
            ("speed_mps", t.speed_mps.is_some()),
            ("relative_speed_mps", t.relative_speed_mps.is_some()),
            ("standstill_s", t.standstill_s.is_some()),
            ("road_end_s", t.road_end_s.is_some()),
            ("reach", t.reach.is_some()),
            ("after", t.after.is_some()),
            ("started", t.started.is_some()),
            ("contact", t.contact),
            ("all", t.all.is_some()),
            ("any", t.any.is_some()),
        ]
        .into_iter()
        .filter_map(|(name, set)| set.then_some(name))
        .collect();
        if given.len() != 1 {
            return Err(invalid(
                i,
                path,
                format!(
                    "must give exactly one of time_s, distance_m, gap_m, spacing_m, time_gap_s, ttc_s, \
                     speed_mps, relative_speed_mps, standstill_s, road_end_s, reach, after, started, contact, all \
                     and any \
                     (given: {})",
                    if given.is_empty() {
                        "none".to_string()
                    } else {
                        given.join(", ")
                    }
                ),
            ));
        }
        let field = |name: &str| format!("{path}.{name}");
        if t.between_axles && t.time_gap_s.is_none() && t.ttc_s.is_none() {
            return Err(invalid(
                i,
                &field("between_axles"),
                format!(
                    "only for time_gap_s and ttc_s, not {} (spacing_m is the distance between axles)",
                    given[0]
                ),
            ));
        }
        if t.side.is_some() && t.time_gap_s.is_none() {
            return Err(invalid(
                i,
                &field("side"),
                format!("only for time_gap_s, not {}", given[0]),
            ));
        }
        if let Some(members) = t.all.as_ref().or(t.any.as_ref()) {
            return self.group(i, path, t, given[0], members, depth);
        }
        let needs_to = t.gap_m.is_some()
            || t.spacing_m.is_some()
            || t.time_gap_s.is_some()
            || t.ttc_s.is_some()
            || t.relative_speed_mps.is_some()
            || t.contact;
        let to = match (&t.to, needs_to) {
            (Some(to), true) if to.trim().is_empty() => {
                return Err(invalid(i, &field("to"), "must not be empty".into()))
            }
            (Some(to), true) => to.clone(),
            (None, true) => {
                return Err(invalid(
                    i,
                    &field("to"),
                    format!("missing: a {} trigger measures to a vehicle", given[0]),
                ))
            }
            (Some(_), false) => {
                return Err(invalid(
                    i,
                    &field("to"),
                    format!("a {} trigger measures to no vehicle", given[0]),
                ))
            }
            (None, false) => String::new(),
        };
        let of = of(i, path, t, given[0])?;
        let condition = if let Some(v) = t.time_s {
            Condition::Time(check(i, &field("time_s"), v, 0.0, MAX_KEY, false)?)
        } else if let Some(v) = t.distance_m {
            Condition::Distance(check(i, &field("distance_m"), v, 0.0, MAX_KEY, false)?)
        } else if let Some(v) = t.gap_m {
            let v = check(i, &field("gap_m"), v, -MAX_GAP_M, MAX_GAP_M, false)?;
            Condition::Gap(v, to)
        } else if let Some(v) = t.spacing_m {
            Condition::Spacing(check(i, &field("spacing_m"), v, 0.0, MAX_GAP_M, false)?, to)
        } else if let Some(v) = t.time_gap_s {
            let v = check(i, &field("time_gap_s"), v, 0.0, MAX_TIME_S, false)?;
            Condition::TimeGap(v, to, t.between_axles, t.side.unwrap_or(KeepSide::Either))
        } else if let Some(v) = t.ttc_s {
            let v = check(i, &field("ttc_s"), v, 0.0, MAX_TIME_S, false)?;
            Condition::Ttc(v, to, t.between_axles)
        } else if let Some(v) = t.speed_mps {
            let max = f64::from(MAX_SPEED_MPS);
            Condition::Speed(check(i, &field("speed_mps"), v, 0.0, max, false)?, of)
        } else if let Some(v) = t.relative_speed_mps {
            let max = f64::from(MAX_SPEED_MPS);
            let v = check(i, &field("relative_speed_mps"), v, -max, max, false)?;
            Condition::RelativeSpeed(v, to)
        } else if let Some(v) = t.standstill_s {
            let v = check(i, &field("standstill_s"), v, 0.0, MAX_STANDSTILL_S, false)?;
            Condition::Standstill(v, of)
        } else if let Some(v) = t.road_end_s {
            let v = check(i, &field("road_end_s"), v, 0.0, MAX_STANDSTILL_S, false)?;
            Condition::RoadEnd(v, of)
        } else if let Some(r) = &t.reach {
            Condition::Reach(reach(i, path, r)?, of)
        } else if t.contact {
            Condition::Contact(to)
        } else {
            let (kind, name) = match (&t.after, &t.started) {
                (Some(after), _) => ("after", after.as_str()),
                (None, started) => ("started", started.as_deref().unwrap_or_default()),
            };
            let j = self.other_event(i, &field(kind), name)?;
            if kind == "after" {
                Condition::After(j)
            } else {
                Condition::Started(j)
            }
        };
        let rule = match (&condition, t.rule) {
            (Condition::After(_) | Condition::Started(_), Some(_)) => {
                return Err(invalid(
                    i,
                    &field("rule"),
                    format!(
                        "{} trigger has no threshold to compare with",
                        if t.after.is_some() {
                            "an after"
                        } else {
                            "a started"
                        }
                    ),
                ))
            }
            (Condition::Standstill(..), Some(_)) => {
                return Err(invalid(
                    i,
                    &field("rule"),
                    "a standstill trigger takes no rule: it holds once the vehicle has stood \
                     still this long"
                        .into(),
                ))
            }
            (Condition::RoadEnd(..), Some(_)) => {
                return Err(invalid(
                    i,
                    &field("rule"),
                    "a road_end_s trigger takes no rule: it holds once the vehicle has been at \
                     the road's end this long"
                        .into(),
                ))
            }
            (Condition::Contact(_), Some(_)) => {
                return Err(invalid(
                    i,
                    &field("rule"),
                    "a contact trigger takes no rule: it holds while the two vehicles touch".into(),
                ))
            }
            (Condition::Reach(..), Some(_)) => {
                return Err(invalid(
                    i,
                    &field("rule"),
                    "a reach trigger takes no rule: it holds while the vehicle is within \
                     tolerance_m of the point"
                        .into(),
                ))
            }
            (_, Some(rule)) => rule,
            (
                Condition::Time(_)
                | Condition::Distance(_)
                | Condition::After(_)
                | Condition::Started(_),
                None,
            ) => Rule::Greater,
            (_, None) => Rule::Less,
        };
        let delay_s = match t.delay_s {
            Some(v) => check(i, &field("delay_s"), v, 0.0, MAX_KEY, false)?,
            None => 0.0,
        };
        Ok(Trigger {
            condition,
            rule,
            delay_s,
            rising: t.rising,
            falling: t.falling,
            latched: latched(i, path, t, depth)?,
        })
    }

    /// The index of the event `name` that event `i`'s `after` or `started` at `field`
    /// waits for: another of its vehicle's events.
    fn other_event(&self, i: usize, field: &str, name: &str) -> Result<usize, VehicleError> {
        match self.0.iter().position(|e| e.name == name) {
            Some(j) if j == i => Err(invalid(
                i,
                field,
                format!("\"{name}\" is this event itself"),
            )),
            Some(j) => Ok(j),
            None => Err(invalid(i, field, format!("no event is named \"{name}\""))),
        }
    }

    /// Event `i`'s `all` or `any` (`kind`) at `path`, of `members`, checked.
    fn group(
        &self,
        i: usize,
        path: &str,
        t: &TriggerSpec,
        kind: &str,
        members: &[TriggerSpec],
        depth: usize,
    ) -> Result<Trigger, VehicleError> {
        let field = |name: &str| format!("{path}.{name}");
        for (name, given) in [
            ("to", t.to.is_some()),
            ("of", t.of.is_some()),
            ("rule", t.rule.is_some()),
        ] {
            if given {
                return Err(invalid(
                    i,
                    &field(name),
                    format!("an {kind} trigger takes no {name}: give it to its members"),
                ));
            }
        }
        if t.delay_s.is_some() {
            return Err(invalid(
                i,
                &field("delay_s"),
                format!("an {kind} trigger takes no delay_s: give each member its delay_s"),
            ));
        }
        if members.is_empty() {
            return Err(invalid(
                i,
                &field(kind),
                "must list at least one trigger".into(),
            ));
        }
        if depth + 1 >= MAX_TRIGGER_DEPTH {
            return Err(invalid(
                i,
                &field(kind),
                format!("all and any nest at most {MAX_TRIGGER_DEPTH} deep"),
            ));
        }
        let members = members
            .iter()
            .enumerate()
            .map(|(k, m)| self.trigger(i, &format!("{path}.{kind}[{k}]"), m, depth + 1))
            .collect::<Result<Vec<_>, _>>()?;
        let condition = if kind == "all" {
            Condition::All(members)
        } else {
            Condition::Any(members)
        };
        let groups = condition_groups(&condition);
        if depth == 0 && groups > MAX_TRIGGER_GROUPS {
            return Err(invalid(
                i,
                path,
                format!(
                    "comes to {groups} condition groups as OpenSCENARIO writes it (any of \
                     groups, each all of conditions): at most {MAX_TRIGGER_GROUPS}"
                ),
            ));
        }
        Ok(Trigger {
            condition,
            rule: Rule::Greater,
            delay_s: 0.0,
            rising: t.rising,
            falling: t.falling,
            latched: latched(i, path, t, depth)?,
        })
    }
}

/// Event `i`'s `latched` at `path`, `depth` members deep, checked: only on a member (an
/// event's own trigger fires the first step it holds, so a latch would change nothing).
fn latched(i: usize, path: &str, t: &TriggerSpec, depth: usize) -> Result<bool, VehicleError> {
    if t.latched && depth == 0 {
        return Err(invalid(
            i,
            &format!("{path}.latched"),
            "only for a member of all or any: an event's own trigger fires at the first step \
             it holds"
                .into(),
        ));
    }
    Ok(t.latched)
}

/// How many condition groups a checked condition comes to written as OpenSCENARIO
/// writes a trigger, any of groups each all of conditions (saturating).
fn condition_groups(c: &Condition) -> usize {
    match c {
        Condition::Any(members) => members.iter().fold(0usize, |n, m| {
            n.saturating_add(condition_groups(&m.condition))
        }),
        Condition::All(members) => members.iter().fold(1usize, |n, m| {
            n.saturating_mul(condition_groups(&m.condition))
        }),
        _ => 1,
    }
}

/// Event `i`'s reach point at `path`, checked (its lane against the road by the caller).
fn reach(i: usize, path: &str, r: &ReachSpec) -> Result<ReachSpec, VehicleError> {
    let f = |name: &str| format!("{path}.reach.{name}");
    if !(1..=MAX_LANES).contains(&r.lane) {
        return Err(invalid(
            i,
            &f("lane"),
            format!(
                "= {}: lanes are numbered 1 to {MAX_LANES} from the centre line",
                r.lane
            ),
        ));
    }
    Ok(ReachSpec {
        station_m: check(i, &f("station_m"), r.station_m, 0.0, MAX_KEY, false)?,
        lane: r.lane,
        offset_m: check(
            i,
            &f("offset_m"),
            r.offset_m,
            -MAX_POSITION_OFFSET_M,
            MAX_POSITION_OFFSET_M,
            false,
        )?,
        tolerance_m: check(i, &f("tolerance_m"), r.tolerance_m, 0.0, MAX_GAP_M, true)?,
    })
}

/// Event `i`'s `of` at `path` (empty for this vehicle), checked for the trigger `kind` it
/// is on: only a speed, standstill, road end or reach trigger watches another vehicle.
fn of(i: usize, path: &str, t: &TriggerSpec, kind: &str) -> Result<String, VehicleError> {
    let watches = t.speed_mps.is_some()
        || t.standstill_s.is_some()
        || t.road_end_s.is_some()
        || t.reach.is_some();
    match (&t.of, watches) {
        (Some(of), true) if of.trim().is_empty() => Err(invalid(
            i,
            &format!("{path}.of"),
            "must not be empty".into(),
        )),
        (Some(of), true) => Ok(of.clone()),
        (Some(_), false) => Err(invalid(
            i,
            &format!("{path}.of"),
            format!(
                "a {kind} trigger watches no vehicle (of is for speed_mps, standstill_s, road_end_s \
                 and reach)"
            ),
        )),
        (None, _) => Ok(String::new()),
    }
}
