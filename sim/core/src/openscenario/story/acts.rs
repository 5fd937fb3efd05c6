//! What is decided when the file is read: whether an act starts at t = 0, on a condition
//! or never, and whether a `ParameterCondition` holds (nothing changes a parameter during
//! a run).

use super::super::error::OscError;
use super::super::xml::{child, children, Xml};
use super::compare;
use roxmltree::Node;

/// When an act starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ActStart {
    /// At t = 0, with the run.
    AtOnce,
    /// The first step its start trigger holds: its events are judged from then on.
    OnCondition,
    /// Never (each of its trigger's groups holds a `ParameterCondition` that does not).
    Never,
}

/// Checks an act's triggers, and says when it starts: it has no stop trigger that can fire
/// (an empty one, with no condition group, never does: a trigger is true when one of its
/// groups is); it starts at t = 0 with no start trigger, an empty one (no condition group:
/// esmini starts such an act at once), or one with a condition group every condition of
/// which holds from the first step (a simulation time greater than a time at most 0, or
/// equal to 0, or a `ParameterCondition` that holds, with no delay). It never starts when
/// each of its groups holds a `ParameterCondition` that does not hold ([`never_fires`]);
/// else it starts on its trigger's condition.
pub(super) fn act_trigger(xml: &Xml, act: Node) -> Result<ActStart, OscError> {
    if let Some(stop) = child(act, "StopTrigger").filter(|s| child(*s, "ConditionGroup").is_some())
    {
        return Err(xml.unsupported(
            stop,
            "act stop trigger",
            "carfollow's events run to their end",
        ));
    }
    let Some(trigger) = child(act, "StartTrigger") else {
        return Ok(ActStart::AtOnce);
    };
    let mut on_condition = false;
    let (mut groups, mut never) = (0, 0);
    for group in children(trigger, "ConditionGroup") {
        groups += 1;
        let conditions: Vec<_> = children(group, "Condition").collect();
        if conditions.is_empty() {
            return Err(xml.at(group, "<ConditionGroup> has no <Condition>"));
        }
        if group_never_holds(xml, group)? {
            never += 1;
            continue;
        }
        let mut all = true;
        for c in conditions {
            all &= holds_from_the_start(xml, c)?;
        }
        if all {
            return Ok(ActStart::AtOnce);
        }
        on_condition = true;
    }
    Ok(if groups > 0 && never == groups {
        ActStart::Never
    } else if on_condition {
        ActStart::OnCondition
    } else {
        ActStart::AtOnce
    })
}

/// The start trigger of the act `node` is in (or is), when that act starts on a condition.
pub(super) fn conditional_start<'a, 'b>(
    xml: &Xml,
    node: Node<'a, 'b>,
) -> Result<Option<Node<'a, 'b>>, OscError> {
    let Some(act) = node.ancestors().find(|a| a.has_tag_name("Act")) else {
        return Ok(None);
    };
    Ok(match act_trigger(xml, act)? {
        ActStart::OnCondition => child(act, "StartTrigger"),
        _ => None,
    })
}

/// Whether a condition of an act's start trigger holds from the first step: a simulation
/// time greater than a time at most 0, or equal to 0, or a `ParameterCondition` that
/// holds, with no delay.
fn holds_from_the_start(xml: &Xml, condition: Node) -> Result<bool, OscError> {
    let by_value = child(condition, "ByValueCondition");
    let at_start = if let Some(t) = by_value.and_then(|v| child(v, "SimulationTimeCondition")) {
        let rule = xml.req(t, "rule")?;
        let value = xml.num(t, "value")?;
        (value <= 0.0 && matches!(rule.as_str(), "greaterThan" | "greaterOrEqual"))
            || (value == 0.0 && rule == "equalTo")
    } else if let Some(p) = by_value.and_then(|v| child(v, "ParameterCondition")) {
        parameter_holds(xml, p)?
    } else {
        false
    };
    Ok(at_start && !xml.opt_num(condition, "delay")?.is_some_and(|d| d != 0.0))
}

/// Whether a `ParameterCondition` holds: the same throughout a run, since no action here
/// sets a parameter.
pub(super) fn parameter_holds(xml: &Xml, c: Node) -> Result<bool, OscError> {
    let name = xml.req(c, "parameterRef")?;
    let have = xml.param_value(c, &name)?;
    let want = xml.req(c, "value")?;
    let rule = xml.req(c, "rule")?;
    match (have.trim().parse::<f64>(), want.trim().parse::<f64>()) {
        (Ok(a), Ok(b)) => compare(&rule, a.total_cmp(&b)),
        _ => compare(&rule, have.cmp(&want)),
    }
    .ok_or_else(|| {
        xml.at(
            c,
            format!("<ParameterCondition rule=\"{rule}\">: not a rule of the standard"),
        )
    })
}

/// Whether a condition group can never hold: one of its conditions is a
/// `ParameterCondition` that does not hold (a group holds when all its conditions do).
pub(super) fn group_never_holds(xml: &Xml, group: Node) -> Result<bool, OscError> {
    for c in children(group, "Condition") {
        let parameter = child(c, "ByValueCondition").and_then(|v| child(v, "ParameterCondition"));
        if let Some(p) = parameter {
            if !parameter_holds(xml, p)? {
                return Ok(true);
            }
        }
    }
    Ok(false)
}

/// Whether a `StartTrigger` can never fire: it has condition groups, none of which can
/// ever hold ([`group_never_holds`]; a trigger fires when one of its groups holds).
pub(super) fn never_fires(xml: &Xml, trigger: Node) -> Result<bool, OscError> {
    let mut groups = children(trigger, "ConditionGroup").peekable();
    if groups.peek().is_none() {
        return Ok(false);
    }
    for group in groups {
        if !group_never_holds(xml, group)? {
            return Ok(false);
        }
    }
    Ok(true)
}
