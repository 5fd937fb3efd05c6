//! An event judged once a latched condition holds, written as OpenSCENARIO writes it: in an
//! act of its own that the condition starts (the inverse of the importer's reading of an act
//! that starts on a condition).

use vehicle::TriggerSpec;

/// An event trigger that is an act's start and the event's own trigger: an `all` whose
/// first member alone is latched, and no edge of its own. The act's start is that member
/// unlatched; the event's own the rest (one member as it is, several as an `all`, none as
/// the first step).
pub(super) fn act_start(t: &TriggerSpec) -> Option<(TriggerSpec, TriggerSpec)> {
    let members = t.all.as_ref().filter(|_| !(t.rising || t.falling))?;
    let (first, rest) = members.split_first()?;
    let mut latched = 0;
    t.walk("", &mut |_, m| latched += usize::from(m.latched));
    if !first.latched || latched != 1 {
        return None;
    }
    let start = TriggerSpec {
        latched: false,
        ..first.clone()
    };
    let own = match rest {
        [] => TriggerSpec {
            time_s: Some(0.0),
            ..TriggerSpec::default()
        },
        [one] => one.clone(),
        _ => TriggerSpec {
            all: Some(rest.to_vec()),
            ..TriggerSpec::default()
        },
    };
    Some((start, own))
}
