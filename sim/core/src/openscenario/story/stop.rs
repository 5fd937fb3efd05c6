//! The `StopTrigger`'s condition groups other than one simulation time each (that one is
//! the run's duration): each group an event whose action ends the run (`end_run`), on a
//! vehicle its conditions are about, its trigger the group's conditions, all of them.

use super::{Context, Stories};
use crate::openscenario::error::OscError;
use crate::openscenario::write::time_only;
use crate::openscenario::xml::{child, children};
use roxmltree::Node;
use std::collections::BTreeMap;
use vehicle::{ActionSpec, EventSpec, TriggerSpec};

/// The name an end event takes (made unique among its vehicle's events).
const STOP_EVENT: &str = "stop";

impl Context<'_, '_> {
    /// Adds to `stories` an end event for each condition group of the storyboard's
    /// `StopTrigger` that is not one simulation time, named apart from the names `taken`.
    pub(super) fn stop_events(
        &self,
        storyboard: Node,
        ego: &str,
        taken: &mut BTreeMap<String, Vec<String>>,
        stories: &mut Stories,
    ) -> Result<(), OscError> {
        let Some(stop) = child(storyboard, "StopTrigger") else {
            return Ok(());
        };
        for group in children(stop, "ConditionGroup") {
            // One simulation time is the duration; a group that never holds never ends it.
            if time_only(self.xml, group)?.is_some() || super::group_never_holds(self.xml, group)? {
                continue;
            }
            let owner = self.stop_owner(group, ego)?;
            let mut all = children(group, "Condition")
                .map(|c| self.condition(c, &owner))
                .collect::<Result<Vec<_>, _>>()?;
            // One condition is the trigger, unless latched (a wait for the start of an act
            // that starts on a condition): only a member latches.
            let trigger = match all.len() {
                0 => return Err(self.xml.at(group, "<ConditionGroup> has no <Condition>")),
                1 if !all[0].latched => all.remove(0),
                _ => TriggerSpec {
                    all: Some(all),
                    ..TriggerSpec::default()
                },
            };
            let name =
                crate::openscenario::unique(STOP_EVENT, taken.entry(owner.clone()).or_default());
            stories.events.entry(owner).or_default().push(EventSpec {
                name,
                trigger,
                action: ActionSpec {
                    end_run: Some(true),
                    ..ActionSpec::default()
                },
                repeat: false,
                max_runs: None,
            });
        }
        Ok(())
    }

    /// The vehicle (its name in the file) a stop group's event goes on: the first vehicle
    /// other than the `ego` that its conditions name (an entity, or the owner of an event
    /// they wait for), else the lead. Its triggers are about that vehicle, as an event's
    /// are about the vehicle it moves.
    fn stop_owner(&self, group: Node, ego: &str) -> Result<String, OscError> {
        for d in group.descendants().filter(Node::is_element) {
            let named = match d.tag_name().name() {
                "StoryboardElementStateCondition" => {
                    let kind = self.xml.attr(d, "storyboardElementType")?;
                    let reference = self.xml.attr(d, "storyboardElementRef")?;
                    kind.zip(reference)
                        .and_then(|(k, r)| super::events_of(self.xml, d, &k, &r).ok())
                        .and_then(|e| self.found.get(&e.first()?.id().get()))
                        .map(|f| f.owner.clone())
                }
                _ => self.xml.attr(d, "entityRef")?,
            };
            if let Some(n) = named.filter(|n| n != ego && self.names.contains_key(n)) {
                return Ok(n);
            }
        }
        let lead = self.names.iter().find(|(_, v)| v.as_str() == "lead");
        Ok(lead.map_or_else(String::new, |(k, _)| k.clone()))
    }
}
