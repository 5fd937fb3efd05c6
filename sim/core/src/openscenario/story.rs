//! `Storyboard`'s stories: each `Event` of a vehicle's maneuvers as one of carfollow's
//! events on that vehicle (`[[actors.events]]`, `[[lead.events]]`): its `StartTrigger` as
//! the event's trigger, its action as the event's action. What carfollow cannot run as the
//! standard defines it is refused, naming the element; nothing is dropped.

use super::error::OscError;
use super::init::{Init, RoadLanes};
use super::xml::{child, children, elements, only_element, Xml};
use roxmltree::Node;
use std::collections::{BTreeMap, BTreeSet};
use vehicle::{EventSpec, Rule, TriggerSpec};

mod actions;
mod acts;
mod stop;

use acts::{
    act_trigger, conditional_start, group_never_holds, never_fires, parameter_holds, ActStart,
};

/// What the stories give: each vehicle's events (by its name in the file), and what is
/// read and not applied (the ego's actions).
#[derive(Debug, Default)]
pub struct Stories {
    /// Each vehicle's events, in the order written.
    pub events: BTreeMap<String, Vec<EventSpec>>,
    /// How many actions of the ego the stories hold (read, and not applied).
    pub ego_actions: usize,
    /// The maneuvers of other vehicles with several events, of speed and of lateral
    /// actions, one of which at least has the priority `override` (1.0's `overwrite`): the
    /// standard ends the maneuver's other running events when it starts, carfollow ends
    /// only a running action of the kind it starts (said in a warning).
    pub side_by_side: Vec<String>,
    /// The acts and events that never start, each as "act `name`" or "event `name`": a
    /// condition group of each of their start trigger's holds a `ParameterCondition` that
    /// does not (nothing changes a parameter during a run). They are not imported.
    pub never_started: Vec<String>,
}

/// The vehicles as carfollow names them (`chase`, `lead`, the actors' names), by the
/// names the file gives them.
pub type Names = BTreeMap<String, String>;

/// One `Event` found in the stories: whose it is and its name as carfollow gives it.
struct Found {
    owner: String,
    name: String,
}

/// Reads every `Story` of the storyboard, and with `read_stop` the `StopTrigger`'s groups
/// other than one simulation time each, as events that end the run ([`stop`]).
pub fn read_stories(
    xml: &Xml,
    names: &Names,
    init: &Init,
    road: &RoadLanes,
    ego: &str,
    read_stop: bool,
) -> Result<Stories, OscError> {
    let root = xml.doc.root_element();
    let Some(storyboard) = child(root, "Storyboard") else {
        return Ok(Stories::default());
    };
    // First the events' owners and names (an `after` may name a later event), and how
    // many lane changes each vehicle makes.
    let mut found: BTreeMap<u32, Found> = BTreeMap::new();
    let mut lane_changes: BTreeMap<String, usize> = BTreeMap::new();
    let mut taken: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let Storied {
        events: all,
        side_by_side,
        mut never_started,
        mut never,
    } = events(xml, storyboard, ego)?;
    // Events whose own start trigger never fires are not imported either.
    let mut kept = Vec::with_capacity(all.len());
    for (event, owners) in all {
        if child(event, "StartTrigger").map_or(Ok(false), |t| never_fires(xml, t))? {
            never_started.push(format!("event `{}`", xml.req(event, "name")?));
            never.insert(event.id().get());
        } else {
            kept.push((event, owners));
        }
    }
    let all = kept;
    for (event, owners) in &all {
        for owner in owners {
            let base = xml.req(*event, "name")?;
            let name = super::unique(&base, taken.entry(owner.clone()).or_default());
            found.entry(event.id().get()).or_insert(Found {
                owner: owner.clone(),
                name,
            });
            for action in children(*event, "Action") {
                if action
                    .descendants()
                    .any(|d| d.has_tag_name("LaneChangeAction"))
                {
                    *lane_changes.entry(owner.clone()).or_default() += 1;
                }
            }
        }
    }
    let context = Context {
        xml,
        names,
        init,
        road,
        found: &found,
        never: &never,
        lane_changes: &lane_changes,
        act_depth: std::cell::Cell::new(0),
        ego,
    };
    let mut stories = Stories {
        side_by_side,
        never_started,
        ..Stories::default()
    };
    for (event, owners) in all {
        for owner in owners {
            if owner == ego {
                stories.ego_actions += children(event, "Action").count();
                continue;
            }
            let specs = context.event(event, &owner)?;
            stories.events.entry(owner).or_default().extend(specs);
        }
    }
    if read_stop {
        context.stop_events(storyboard, ego, &mut taken, &mut stories)?;
    }
    Ok(stories)
}

/// An event and the vehicles its maneuver group acts on.
type Owned<'a, 'b> = (Node<'a, 'b>, Vec<String>);

/// What [`events`] finds in the stories.
struct Storied<'a, 'b> {
    /// Every event of an act that starts, with the vehicles its maneuver group acts on.
    events: Vec<Owned<'a, 'b>>,
    /// See [`Stories::side_by_side`].
    side_by_side: Vec<String>,
    /// The acts that never start (see [`Stories::never_started`]).
    never_started: Vec<String>,
    /// The node ids of the events of those acts.
    never: BTreeSet<u32>,
}

/// Every `Event` of the stories' acts that start, with the vehicles its maneuver group acts
/// on, and the names of the maneuvers of vehicles other than the `ego` whose several events
/// carfollow runs side by side where the standard's `override` would end some (see
/// [`Stories::side_by_side`]); the acts' and groups' own settings checked on the way.
fn events<'a, 'b>(
    xml: &Xml,
    storyboard: Node<'a, 'b>,
    ego: &str,
) -> Result<Storied<'a, 'b>, OscError> {
    let mut out = Vec::new();
    let mut side_by_side = Vec::new();
    let mut never_started = Vec::new();
    let mut never = BTreeSet::new();
    for story in elements(storyboard) {
        match story.tag_name().name() {
            "Init" | "StopTrigger" => continue,
            "Story" => {}
            _ => return Err(xml.unsupported(story, "element", "")),
        }
        for act in elements(story) {
            match act.tag_name().name() {
                "ParameterDeclarations" => continue,
                "Act" => {}
                _ => return Err(xml.unsupported(act, "element", "")),
            }
            if act_trigger(xml, act)? == ActStart::Never {
                never_started.push(format!("act `{}`", xml.req(act, "name")?));
                never.extend(
                    act.descendants()
                        .filter(|d| d.has_tag_name("Event"))
                        .map(|e| e.id().get()),
                );
                continue;
            }
            for group in children(act, "ManeuverGroup") {
                if xml
                    .opt_num(group, "maximumExecutionCount")?
                    .is_some_and(|n| n != 1.0)
                {
                    return Err(xml.at(group, "<ManeuverGroup maximumExecutionCount>: carfollow runs each maneuver group once"));
                }
                if let Some(c) = child(group, "CatalogReference") {
                    return Err(xml.unsupported(c, "maneuver", "maneuver catalogs are not read"));
                }
                let actors = child(group, "Actors")
                    .ok_or_else(|| xml.at(group, "<ManeuverGroup> has no <Actors>"))?;
                if xml.attr(actors, "selectTriggeringEntities")?.as_deref() == Some("true") {
                    return Err(xml.at(actors, "<Actors selectTriggeringEntities=\"true\">: carfollow's events name their vehicles"));
                }
                let owners = children(actors, "EntityRef")
                    .map(|e| xml.req(e, "entityRef"))
                    .collect::<Result<Vec<_>, _>>()?;
                for maneuver in children(group, "Maneuver") {
                    let events: Vec<_> = children(maneuver, "Event").collect();
                    if owners.iter().any(|o| o != ego) && overridden(xml, &events)? {
                        side_by_side.push(xml.req(maneuver, "name")?);
                    }
                    out.extend(events.into_iter().map(|e| (e, owners.clone())));
                }
            }
        }
    }
    Ok(Storied {
        events: out,
        side_by_side,
        never_started,
        never,
    })
}

/// Whether a maneuver's `events` hold speed and lateral actions, one event at least with
/// the priority `override` (or none given): the standard would have a starting event end
/// the others, where carfollow ends only the running action of the kind it starts (events
/// of one kind alone end each other's actions here as well).
fn overridden(xml: &Xml, events: &[Node]) -> Result<bool, OscError> {
    let mut overrides = false;
    for e in events {
        overrides |= xml.attr(*e, "priority")?.as_deref() != Some("parallel");
    }
    let has = |tags: &[&str]| {
        events
            .iter()
            .any(|e| e.descendants().any(|d| tags.contains(&d.tag_name().name())))
    };
    Ok(events.len() > 1
        && overrides
        && has(&["SpeedAction", "SpeedProfileAction"])
        && has(&["LaneChangeAction", "LaneOffsetAction"]))
}

struct Context<'c, 'a> {
    xml: &'c Xml<'a>,
    names: &'c Names,
    init: &'c Init,
    road: &'c RoadLanes,
    found: &'c BTreeMap<u32, Found>,
    /// The events that never start ([`Stories::never_started`]), by node id.
    never: &'c BTreeSet<u32>,
    lane_changes: &'c BTreeMap<String, usize>,
    /// How many acts' start triggers are being read, one inside another ([`Context::latched`]).
    act_depth: std::cell::Cell<usize>,
    /// The ego's name in the file.
    ego: &'c str,
}

impl Context<'_, '_> {
    /// carfollow's name of the vehicle the file calls `name`.
    fn name(&self, node: Node, name: &str) -> Result<String, OscError> {
        self.names.get(name).cloned().ok_or_else(|| {
            self.xml.at(
                node,
                format!("<{}>: no entity is named `{name}`", node.tag_name().name()),
            )
        })
    }

    /// The events of `event` on `owner` (one per action), named from `taken`'s names.
    fn event(&self, event: Node, owner: &str) -> Result<Vec<EventSpec>, OscError> {
        let xml = self.xml;
        let base = xml.req(event, "name")?;
        // A new action replaces the running action of its kind (speed; lane or offset),
        // and the vehicle's other events run on: the standard's `parallel`. An `override`
        // would also end its maneuver's other running events (a warning says so).
        match xml.attr(event, "priority")?.as_deref() {
            None | Some("overwrite") | Some("override") | Some("parallel") => {}
            Some(p) => return Err(xml.at(event, format!("<Event priority=\"{p}\">: carfollow's events run side by side (\"parallel\"; \"override\" and 1.0's \"overwrite\" are read so, with a warning)"))),
        }
        // Runs at most: once, or `repeat` up to `max_runs`.
        let max_runs = match xml.opt_num(event, "maximumExecutionCount")? {
            None => 1,
            Some(n) if n >= 1.0 && n.fract() == 0.0 && n <= f64::from(u32::MAX) => n as u32,
            Some(n) => {
                return Err(xml.at(
                    event,
                    format!("<Event maximumExecutionCount=\"{n}\">: a count of runs, 1 or more"),
                ))
            }
        };
        // No start trigger, or an empty one (no condition group): at once, as esmini reads
        // both (a trigger with no group takes its default, true for a start).
        let own =
            match child(event, "StartTrigger").filter(|t| child(*t, "ConditionGroup").is_some()) {
                Some(t) => self.trigger(t, owner)?,
                None => TriggerSpec {
                    time_s: Some(0.0),
                    ..TriggerSpec::default()
                },
            };
        let trigger = self.once_started(event, own, owner)?;
        let name = self
            .found
            .get(&event.id().get())
            .filter(|f| f.owner == owner)
            .map_or(base.clone(), |f| f.name.clone());
        let actions: Vec<_> = children(event, "Action").collect();
        if actions.is_empty() {
            return Err(xml.at(event, "<Event> has no <Action>"));
        }
        actions
            .iter()
            .enumerate()
            .map(|(i, &a)| {
                Ok(EventSpec {
                    name: if i == 0 {
                        name.clone()
                    } else {
                        format!("{name}/{}", i + 1)
                    },
                    trigger: trigger.clone(),
                    action: self.action(a, owner)?,
                    repeat: max_runs > 1,
                    max_runs: (max_runs > 1).then_some(max_runs),
                })
            })
            .collect()
    }

    /// `own`, the trigger of `event` on `owner`, judged only once the event's act has
    /// started: with the act's start trigger latched before it when the act starts on a
    /// condition (`all = [act's, own...]`, an `all` of its own spliced in), else as it is.
    /// An own trigger latched itself (a wait for a start of an act that starts on a
    /// condition) goes in an `all` of its own: only members latch.
    fn once_started(
        &self,
        event: Node,
        own: TriggerSpec,
        owner: &str,
    ) -> Result<TriggerSpec, OscError> {
        let mut members = match conditional_start(self.xml, event)? {
            Some(act) => vec![self.latched(act, owner)?],
            None if own.latched => Vec::new(),
            None => return Ok(own),
        };
        let splice = !(own.rising || own.falling || own.latched);
        match own.all {
            Some(all) if splice => members.extend(all),
            _ => members.push(own),
        }
        Ok(TriggerSpec {
            all: Some(members),
            ..TriggerSpec::default()
        })
    }

    /// The start trigger `act` (of an act that starts on a condition) as a latched trigger
    /// of an event on `owner`: once it holds, the act has started. Acts waiting for each
    /// other's starts nest at most [`vehicle::MAX_TRIGGER_DEPTH`] deep.
    fn latched(&self, act: Node, owner: &str) -> Result<TriggerSpec, OscError> {
        let depth = self.act_depth.get();
        if depth >= vehicle::MAX_TRIGGER_DEPTH {
            return Err(self.xml.at(
                act,
                "<StartTrigger>: acts wait for each other's starts in a loop, or too deep",
            ));
        }
        self.act_depth.set(depth + 1);
        let trigger = self.trigger(act, owner);
        self.act_depth.set(depth);
        Ok(TriggerSpec {
            latched: true,
            ..trigger?
        })
    }

    /// A `StartTrigger` as a trigger of an event on `owner`: its one condition as it is,
    /// several as `any` of its condition groups, each `all` of its conditions.
    fn trigger(&self, trigger: Node, owner: &str) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        let mut groups = Vec::new();
        for group in children(trigger, "ConditionGroup") {
            // A group that never holds never fires the trigger: the others decide.
            if group_never_holds(xml, group)? {
                continue;
            }
            let mut all = children(group, "Condition")
                .map(|c| self.condition(c, owner))
                .collect::<Result<Vec<_>, _>>()?;
            groups.push(match all.len() {
                0 => return Err(xml.at(group, "<ConditionGroup> has no <Condition>")),
                1 => all.remove(0),
                _ => TriggerSpec {
                    all: Some(all),
                    ..TriggerSpec::default()
                },
            });
        }
        Ok(match groups.len() {
            0 => {
                return Err(xml.at(
                    trigger,
                    format!(
                        "<{}> has no <ConditionGroup>, so its event would never start",
                        trigger.tag_name().name()
                    ),
                ))
            }
            1 => groups.remove(0),
            _ => TriggerSpec {
                any: Some(groups),
                ..TriggerSpec::default()
            },
        })
    }

    /// One `Condition` of a trigger on an event of `owner`, with its delay.
    fn condition(&self, condition: Node, owner: &str) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        let (rising, falling) = match xml.attr(condition, "conditionEdge")?.as_deref() {
            Some("none") | None => (false, false),
            Some("rising") => (true, false),
            Some("falling") => (false, true),
            Some("risingOrFalling") => (true, true),
            Some(edge) => return Err(xml.at(condition, format!("<Condition conditionEdge=\"{edge}\">: not an edge (\"none\", \"rising\", \"falling\", \"risingOrFalling\")"))),
        };
        let delay = xml.opt_num(condition, "delay")?.filter(|&d| d != 0.0);
        if delay.is_some_and(|d| d < 0.0) {
            return Err(xml.at(condition, "<Condition delay>: must not be negative"));
        }
        let inner = only_element(xml, condition)?;
        let mut spec = match inner.tag_name().name() {
            "ByValueCondition" => self.by_value(only_element(xml, inner)?, owner)?,
            "ByEntityCondition" => self.by_entity(inner, owner)?,
            _ => return Err(xml.unsupported(inner, "condition", "")),
        };
        // A condition of several entities is a group: each of its members waits the delay
        // (any or all of them, each as it was the delay before, is the group as it was).
        match spec.all.as_mut().or(spec.any.as_mut()) {
            Some(members) => members.iter_mut().for_each(|m| m.delay_s = delay),
            None => spec.delay_s = delay,
        }
        spec.rising = rising;
        spec.falling = falling;
        Ok(spec)
    }

    fn rule(&self, node: Node) -> Result<Rule, OscError> {
        match self.xml.req(node, "rule")?.as_str() {
            "lessThan" | "lessOrEqual" => Ok(Rule::Less),
            "greaterThan" | "greaterOrEqual" => Ok(Rule::Greater),
            "equalTo" => Ok(Rule::Equal),
            "notEqualTo" => Ok(Rule::NotEqual),
            r => Err(self.xml.at(
                node,
                format!(
                    "<{} rule=\"{r}\">: not a rule of the standard",
                    node.tag_name().name()
                ),
            )),
        }
    }

    fn by_value(&self, c: Node, owner: &str) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        match c.tag_name().name() {
            "SimulationTimeCondition" => Ok(TriggerSpec {
                time_s: Some(xml.num(c, "value")?.max(0.0)),
                rule: Some(self.rule(c)?),
                ..TriggerSpec::default()
            }),
            "StoryboardElementStateCondition" => {
                let kind = xml.req(c, "storyboardElementType")?;
                let state = xml.req(c, "state")?;
                let reference = xml.req(c, "storyboardElementRef")?;
                if matches!(
                    kind.as_str(),
                    "story" | "act" | "maneuverGroup" | "maneuver"
                ) && matches!(state.as_str(), "startTransition" | "runningState")
                {
                    // A story starts at t = 0; an act, and the maneuver groups and
                    // maneuvers in it, at t = 0 or once its start trigger holds
                    // (`act_trigger`).
                    return self.started_at(c, &kind, &reference, owner);
                }
                // An event's start: the step its action starts (a wait for it, with the
                // condition's delay, as esmini starts `alks_r157_cut_in_quick_brake`'s
                // brake after its lane change starts).
                let start = kind == "event" && state == "startTransition";
                if !start && !matches!(state.as_str(), "endTransition" | "completeState") {
                    return Err(xml.at(c, format!("<StoryboardElementStateCondition storyboardElementType=\"{kind}\" state=\"{state}\">: carfollow waits for an element's end (endTransition or completeState) or a start (a story, act, maneuver group or maneuver, startTransition or runningState; an event, startTransition)")));
                }
                // An element's end is its last event's: every event under it ended (each
                // runs once, and an act's own stop trigger is refused).
                let events = events_of(xml, c, &kind, &reference)?;
                let mut each = Vec::with_capacity(events.len());
                for event in events {
                    if self.never.contains(&event.id().get()) {
                        return Err(xml.at(c, format!("<StoryboardElementStateCondition storyboardElementRef=\"{reference}\">: waits for an event that never starts (a `ParameterCondition` of its start trigger does not hold)")));
                    }
                    if !start {
                        self.not_continuous(c, event, &reference)?;
                    }
                    let found = self.found.get(&event.id().get());
                    if let Some(f) = found.filter(|f| f.owner == self.ego && owner != self.ego) {
                        return Err(xml.at(c, format!("<StoryboardElementStateCondition storyboardElementRef=\"{reference}\">: waits for an event of the ego `{}`, whose actions carfollow does not apply (its loop drives the chase)", f.owner)));
                    }
                    let found = found.filter(|f| f.owner == owner).ok_or_else(|| {
                        xml.at(c, format!("<StoryboardElementStateCondition storyboardElementRef=\"{reference}\">: not an event of `{owner}` (carfollow's events wait for their own vehicle's)"))
                    })?;
                    let name = Some(found.name.clone());
                    let (after, started) = if start { (None, name) } else { (name, None) };
                    each.push(TriggerSpec {
                        after,
                        started,
                        ..TriggerSpec::default()
                    });
                }
                Ok(match each.len() {
                    1 => each.remove(0),
                    _ => TriggerSpec {
                        all: Some(each),
                        ..TriggerSpec::default()
                    },
                })
            }
            "ParameterCondition" => {
                // No action here sets a parameter, so the condition is the same throughout:
                // true, the event starts at once; false, it never would, and its group is
                // left out of the trigger (`group_never_holds`) before it comes here.
                if !parameter_holds(xml, c)? {
                    let name = xml.req(c, "parameterRef")?;
                    return Err(xml.at(c, format!("<ParameterCondition parameterRef=\"{name}\">: never holds, so its event would never start")));
                }
                Ok(TriggerSpec {
                    time_s: Some(0.0),
                    ..TriggerSpec::default()
                })
            }
            _ => Err(xml.unsupported(c, "condition", "")),
        }
    }

    /// The trigger, for an event on `owner`, of a condition `c` on the start of the story,
    /// act, maneuver group or maneuver named `reference` (`kind` its element): the first
    /// step, or, within an act that starts on a condition, that act's start trigger
    /// latched.
    fn started_at(
        &self,
        c: Node,
        kind: &str,
        reference: &str,
        owner: &str,
    ) -> Result<TriggerSpec, OscError> {
        let tag = match kind {
            "story" => "Story",
            "act" => "Act",
            "maneuverGroup" => "ManeuverGroup",
            _ => "Maneuver",
        };
        let element = resolve(self.xml, c, tag, reference)?;
        match conditional_start(self.xml, element)? {
            Some(act) => self.latched(act, owner),
            None => Ok(TriggerSpec {
                time_s: Some(0.0),
                ..TriggerSpec::default()
            }),
        }
    }

    /// Refuses a wait for the end of `event` (referred to as `reference`) when it holds a
    /// continuous `LaneOffsetAction`, which never ends.
    fn not_continuous(&self, c: Node, event: Node, reference: &str) -> Result<(), OscError> {
        let xml = self.xml;
        for offset in event
            .descendants()
            .filter(|d| d.has_tag_name("LaneOffsetAction"))
        {
            if xml.attr(offset, "continuous")?.as_deref() == Some("true") {
                return Err(xml.at(c, format!("<StoryboardElementStateCondition storyboardElementRef=\"{reference}\">: its <LaneOffsetAction continuous=\"true\"> never ends")));
            }
        }
        Ok(())
    }

    fn by_entity(&self, c: Node, owner: &str) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        let triggering = child(c, "TriggeringEntities")
            .ok_or_else(|| xml.at(c, "<ByEntityCondition> has no <TriggeringEntities>"))?;
        let condition = child(c, "EntityCondition")
            .ok_or_else(|| xml.at(c, "<ByEntityCondition> has no <EntityCondition>"))?;
        let e = only_element(xml, condition)?;
        let mut each = children(triggering, "EntityRef")
            .map(|r| self.entity_condition(e, &xml.req(r, "entityRef")?, owner))
            .collect::<Result<Vec<_>, _>>()?;
        if each.len() == 1 {
            return Ok(each.remove(0));
        }
        if each.is_empty() {
            return Err(xml.at(triggering, "<TriggeringEntities> names no entity"));
        }
        // Several entities: the condition of any one of them, or of all at once.
        Ok(match xml.req(triggering, "triggeringEntitiesRule")?.as_str() {
            "any" => TriggerSpec {
                any: Some(each),
                ..TriggerSpec::default()
            },
            "all" => TriggerSpec {
                all: Some(each),
                ..TriggerSpec::default()
            },
            rule => {
                return Err(xml.at(
                    triggering,
                    format!("<TriggeringEntities triggeringEntitiesRule=\"{rule}\">: not a rule of the standard (any, all)"),
                ))
            }
        })
    }

    /// The entity condition `e` of the entity `subject`, on an event of `owner`.
    fn entity_condition(
        &self,
        e: Node,
        subject: &str,
        owner: &str,
    ) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        let subject = subject.to_string();
        let name = e.tag_name().name();
        if name == "TraveledDistanceCondition" {
            if subject != owner {
                return Err(xml.at(e, format!("<TraveledDistanceCondition> of `{subject}` on an event of `{owner}`: carfollow's distance triggers are the moving vehicle's own")));
            }
            return Ok(TriggerSpec {
                distance_m: Some(xml.num(e, "value")?),
                rule: Some(Rule::Greater),
                ..TriggerSpec::default()
            });
        }
        if matches!(
            name,
            "SpeedCondition" | "StandStillCondition" | "EndOfRoadCondition"
        ) {
            return self.watching(e, &subject, owner);
        }
        if name == "ReachPositionCondition"
            || (name == "DistanceCondition" && child(e, "Position").is_some())
        {
            return self.reach(e, &subject, owner);
        }
        let other = match name {
            "TimeToCollisionCondition" => {
                let target = child(e, "TimeToCollisionConditionTarget")
                    .map(|t| only_element(xml, t))
                    .transpose()?
                    .ok_or_else(|| xml.at(e, "<TimeToCollisionCondition> has no target"))?;
                entity_ref(
                    xml,
                    target,
                    "time-to-collision target",
                    "carfollow's are vehicles",
                )?
            }
            "TimeHeadwayCondition" | "RelativeDistanceCondition" | "RelativeSpeedCondition" => {
                xml.req(e, "entityRef")?
            }
            "CollisionCondition" => entity_ref(
                xml,
                only_element(xml, e)?,
                "collision target",
                "carfollow's are vehicles, each named",
            )?,
            _ => return Err(xml.unsupported(e, "condition", "")),
        };
        if name == "RelativeSpeedCondition" {
            return self.relative_speed(e, &subject, &other, owner);
        }
        if name == "CollisionCondition" {
            // A contact is the same seen from either vehicle.
            let to = if subject == owner { other } else { subject };
            if to == owner {
                return Err(xml.at(e, format!("<CollisionCondition> of `{owner}` with itself")));
            }
            return Ok(TriggerSpec {
                contact: true,
                to: Some(self.name(e, &to)?),
                ..TriggerSpec::default()
            });
        }
        // Reference point to reference point: a relative distance's spacing, a headway's or
        // time to collision's `between_axles` (below).
        let spacing = !xml.boolean(e, "freespace")?;
        if name == "RelativeDistanceCondition" {
            let kind = xml.req(e, "relativeDistanceType")?;
            if kind != "longitudinal" {
                return Err(xml.at(e, format!("<RelativeDistanceCondition relativeDistanceType=\"{kind}\">: carfollow's gaps are longitudinal")));
            }
        }
        // Which of the two measures: the triggering entity, `subject`.
        let measures = subject == owner;
        let to = if measures {
            other
        } else if other == owner {
            subject
        } else {
            return Err(xml.at(e, format!("<{name}> between `{subject}` and `{other}` on an event of `{owner}`: carfollow's triggers are about the vehicle the event moves")));
        };
        let to = Some(self.name(e, &to)?);
        let value = Some(xml.num(e, "value")?);
        let rule = Some(self.rule(e)?);
        Ok(match name {
            "TimeToCollisionCondition" => TriggerSpec {
                ttc_s: value,
                to,
                rule,
                between_axles: spacing,
                ..TriggerSpec::default()
            },
            // A headway is measured only towards a vehicle ahead of the one measuring it
            // (the triggering entity, `subject`).
            "TimeHeadwayCondition" => TriggerSpec {
                time_gap_s: value,
                to,
                rule,
                between_axles: spacing,
                side: Some(if measures {
                    vehicle::KeepSide::Behind
                } else {
                    vehicle::KeepSide::Ahead
                }),
                ..TriggerSpec::default()
            },
            _ if spacing => TriggerSpec {
                spacing_m: value,
                to,
                rule,
                ..TriggerSpec::default()
            },
            _ => TriggerSpec {
                gap_m: value,
                to,
                rule,
                ..TriggerSpec::default()
            },
        })
    }

    /// A `SpeedCondition`, `StandStillCondition` or `EndOfRoadCondition` `e` of `subject`
    /// on an event of `owner`: a speed, standstill or road end trigger watching `subject`
    /// (`of`, left out when it is the event's own vehicle).
    fn watching(&self, e: Node, subject: &str, owner: &str) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        let of = if subject == owner {
            None
        } else {
            Some(self.name(e, subject)?)
        };
        let tag = e.tag_name().name();
        if matches!(tag, "StandStillCondition" | "EndOfRoadCondition") {
            let duration = xml.num(e, "duration")?;
            if duration < 0.0 {
                return Err(xml.at(
                    e,
                    format!("<{tag} duration=\"{duration}\">: a time, 0 or more"),
                ));
            }
            let standstill = tag == "StandStillCondition";
            return Ok(TriggerSpec {
                standstill_s: standstill.then_some(duration),
                road_end_s: (!standstill).then_some(duration),
                of,
                ..TriggerSpec::default()
            });
        }
        if let Some(direction) = xml.attr(e, "direction")? {
            return Err(xml.at(e, format!("<SpeedCondition direction=\"{direction}\">: carfollow's speed triggers watch the speed along the road")));
        }
        Ok(TriggerSpec {
            speed_mps: Some(xml.num(e, "value")?),
            of,
            rule: Some(self.rule(e)?),
            ..TriggerSpec::default()
        })
    }

    /// A `RelativeSpeedCondition` `e`: the speed of `subject` less that of `other`, on an
    /// event of `owner`, one of the two (seen from `other`, the difference and its side
    /// turn over).
    fn relative_speed(
        &self,
        e: Node,
        subject: &str,
        other: &str,
        owner: &str,
    ) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        if let Some(direction) = xml.attr(e, "direction")? {
            return Err(xml.at(e, format!("<RelativeSpeedCondition direction=\"{direction}\">: carfollow's speed triggers watch the speed along the road")));
        }
        let value = xml.num(e, "value")?;
        let rule = self.rule(e)?;
        let (to, value, rule) = if subject == owner {
            (other, value, rule)
        } else if other == owner {
            let turned = match rule {
                Rule::Less => Rule::Greater,
                Rule::Greater => Rule::Less,
                same => same,
            };
            // `0.0 - v`, not `-v`: a value of 0 stays 0, not −0.
            (subject, 0.0 - value, turned)
        } else {
            return Err(xml.at(e, format!("<RelativeSpeedCondition> between `{subject}` and `{other}` on an event of `{owner}`: carfollow's triggers are about the vehicle the event moves")));
        };
        Ok(TriggerSpec {
            relative_speed_mps: Some(value),
            to: Some(self.name(e, to)?),
            rule: Some(rule),
            ..TriggerSpec::default()
        })
    }

    /// A `ReachPositionCondition` (or 1.2's `DistanceCondition` to a position, at most its
    /// value) `e` of `subject` on an event of `owner`: a reach trigger.
    fn reach(&self, e: Node, subject: &str, owner: &str) -> Result<TriggerSpec, OscError> {
        let xml = self.xml;
        let tolerance_m = if e.has_tag_name("ReachPositionCondition") {
            xml.num(e, "tolerance")?
        } else {
            if !matches!(self.rule(e)?, Rule::Less) {
                return Err(xml.at(e, "<DistanceCondition> to a position: carfollow's reach triggers hold within a distance (rule lessThan or lessOrEqual)"));
            }
            if xml.attr(e, "freespace")?.as_deref() == Some("true") {
                return Err(xml.at(e, "<DistanceCondition freespace=\"true\"> to a position: carfollow measures to the vehicle's reference point (freespace=\"false\")"));
            }
            match xml.attr(e, "relativeDistanceType")?.as_deref() {
                None | Some("euclidianDistance") | Some("euclideanDistance") => {}
                Some(kind) => return Err(xml.at(e, format!("<DistanceCondition relativeDistanceType=\"{kind}\"> to a position: carfollow's reach triggers measure the distance (euclidianDistance)"))),
            }
            xml.num(e, "value")?
        };
        if tolerance_m.is_nan() || tolerance_m <= 0.0 {
            return Err(xml.at(
                e,
                format!(
                    "<{}>: the distance {tolerance_m} m must be above 0",
                    e.tag_name().name()
                ),
            ));
        }
        let position = child(e, "Position")
            .map(|p| only_element(xml, p))
            .transpose()?
            .ok_or_else(|| xml.at(e, format!("<{}> has no <Position>", e.tag_name().name())))?;
        let (station_m, lane, offset_m) = super::init::point_on_road(xml, self.road, position)?;
        let of = if subject == owner {
            None
        } else {
            Some(self.name(e, subject)?)
        };
        Ok(TriggerSpec {
            reach: Some(vehicle::ReachSpec {
                station_m,
                lane,
                offset_m,
                tolerance_m,
            }),
            of,
            ..TriggerSpec::default()
        })
    }
}

/// The entity a condition's `target` names: an `EntityRef`, else refused as an unsupported
/// `what` (`why` says what carfollow reads).
fn entity_ref(xml: &Xml, target: Node, what: &str, why: &str) -> Result<String, OscError> {
    if target.tag_name().name() != "EntityRef" {
        return Err(xml.unsupported(target, what, why));
    }
    xml.req(target, "entityRef")
}

/// Whether `ordering` (the value's against the condition's) meets the standard's `rule`;
/// `None` for a rule that is not the standard's.
fn compare(rule: &str, ordering: std::cmp::Ordering) -> Option<bool> {
    use std::cmp::Ordering::{Equal, Greater, Less};
    Some(match rule {
        "lessThan" => ordering == Less,
        "lessOrEqual" => ordering != Greater,
        "equalTo" => ordering == Equal,
        "notEqualTo" => ordering != Equal,
        "greaterThan" => ordering == Greater,
        "greaterOrEqual" => ordering != Less,
        _ => return None,
    })
}

/// The storyboard elements whose names qualify a reference, innermost first.
const QUALIFIERS: [&str; 5] = ["Event", "Maneuver", "ManeuverGroup", "Act", "Story"];

/// The `<tag>` a state condition `c` refers to as `reference`: a name, or a name qualified
/// by the names of the storyboard elements around it, outermost first and innermost last,
/// separated by `::` (OpenSCENARIO 1.1's `Story::Act::ManeuverGroup::Maneuver::Event::Action`,
/// or any inner part of it, such as `Event::Action`). Refused when nothing or more than
/// one element answers it.
fn resolve<'d, 'i>(
    xml: &'d Xml<'i>,
    c: Node,
    tag: &str,
    reference: &str,
) -> Result<Node<'d, 'i>, OscError> {
    let mut parts: Vec<&str> = reference.split("::").collect();
    let name = parts.pop().unwrap_or_default();
    let answers = |n: &Node| {
        let around = n
            .ancestors()
            .skip(1)
            .filter(|a| QUALIFIERS.iter().any(|q| a.has_tag_name(*q)))
            .map(|a| a.attribute("name").unwrap_or_default());
        n.has_tag_name(tag)
            && n.attribute("name") == Some(name)
            && parts
                .iter()
                .rev()
                .zip(around.chain(std::iter::repeat("")))
                .all(|(p, a)| *p == a)
    };
    let mut found = xml.doc.descendants().filter(answers);
    let say = |what: String| {
        xml.at(
            c,
            format!(
                "<StoryboardElementStateCondition storyboardElementRef=\"{reference}\">: {what}"
            ),
        )
    };
    let first = found
        .next()
        .ok_or_else(|| say(format!("no <{tag}> is named `{reference}`")))?;
    if found.next().is_some() {
        return Err(say(format!(
            "more than one <{tag}> is named `{reference}` (qualify it with the names of the elements around it, as `Event::Action`)"
        )));
    }
    Ok(first)
}

/// The `Event`s under the element a state condition `c` of `kind` (`storyboardElementType`)
/// refers to as `reference`: the event itself, the one holding an action, or every event
/// of a story, act, maneuver group or maneuver (at least one).
fn events_of<'d, 'i>(
    xml: &'d Xml<'i>,
    c: Node,
    kind: &str,
    reference: &str,
) -> Result<Vec<Node<'d, 'i>>, OscError> {
    let say = |what: &str| {
        xml.at(
            c,
            format!(
                "<StoryboardElementStateCondition storyboardElementRef=\"{reference}\">: {what}"
            ),
        )
    };
    let tag = match kind {
        "event" => return Ok(vec![resolve(xml, c, "Event", reference)?]),
        "action" => {
            let event = resolve(xml, c, "Action", reference)?
                .parent()
                .filter(|e| e.has_tag_name("Event"))
                .ok_or_else(|| say("not an action of an <Event>"))?;
            return Ok(vec![event]);
        }
        "story" => "Story",
        "act" => "Act",
        "maneuverGroup" => "ManeuverGroup",
        "maneuver" => "Maneuver",
        _ => {
            return Err(xml.at(c, format!("<StoryboardElementStateCondition storyboardElementType=\"{kind}\">: not an element of the standard (story, act, maneuverGroup, maneuver, event, action)")))
        }
    };
    let events: Vec<_> = resolve(xml, c, tag, reference)?
        .descendants()
        .filter(|d| d.has_tag_name("Event"))
        .collect();
    if events.is_empty() {
        return Err(say(&format!(
            "its <{tag}> has no <Event>, so it never ends"
        )));
    }
    Ok(events)
}
