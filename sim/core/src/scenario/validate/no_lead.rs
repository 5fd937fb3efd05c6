//! The chase's start: behind the lead (`[lead]`, `chase.initial_gap_m`), or, in a scenario
//! without a lead, where `chase.start_m` and `chase.lane` put it, cruising in its lane
//! until its tracker finds a vehicle in its path.

use super::{check, Blame};
use crate::scenario::{LeadFile, ScenarioError, ScenarioFile};

/// The lead of `raw`, or for a scenario without one, what the chase drives in its place:
/// its own lane from `chase.start_m` at its cruise speed (`[lead]`'s fields then stand
/// for the chase's lane and start; nothing is placed there). Checks that the fields of
/// each kind of start are given only with it, and what a start without a lead needs: a
/// start on the route (`length` metres), a cruise speed, lane keeping (no lead's path to
/// follow), a tracker that searches (`search_start`), and no distractors (they move with the lead).
pub(super) fn lead_or_lane(
    raw: &ScenarioFile,
    length: f64,
    search_start: bool,
    f: &Blame,
) -> Result<LeadFile, ScenarioError> {
    let chase = &raw.chase;
    if let Some(lead) = &raw.lead {
        let only = "is only for a scenario without [lead] (with one, the chase starts \
                    chase.initial_gap_m behind it, in its lane)";
        if let Some(start) = chase.start_m {
            return Err(f.invalid("chase.start_m", format!("= {start}: {only}")));
        }
        if let Some(lane) = chase.lane {
            return Err(f.invalid("chase.lane", format!("= {lane}: {only}")));
        }
        return Ok(lead.clone());
    }
    let without = "a scenario without [lead]";
    if let Some(gap) = chase.initial_gap_m {
        return Err(f.invalid(
            "chase.initial_gap_m",
            format!("= {gap}: is the gap to the lead; {without} starts the chase at chase.start_m"),
        ));
    }
    let start_m = chase.start_m.ok_or_else(|| {
        f.invalid(
            "chase.start_m",
            format!(
                "is needed in {without}: where the chase's rear axle starts, metres along \
                 the route (or give a [lead] for it to follow)"
            ),
        )
    })?;
    f.at(
        "chase.start_m",
        check(
            start_m.is_finite() && (0.0..length).contains(&start_m),
            &format!("must lie on the route, 0–{length:.0} m"),
            start_m,
        ),
    )?;
    let cruise = chase.controller.cruise_speed_mps.ok_or_else(|| {
        f.invalid(
            "chase.controller.cruise_speed_mps",
            format!(
                "is needed in {without}: the chase cruises at it until its tracker finds a \
                 vehicle in its path"
            ),
        )
    })?;
    if !chase.controller.lane_keeping {
        return Err(f.invalid(
            "chase.controller.lane_keeping",
            format!(
                "= false: must be true in {without} (with no lead's path to follow, the \
                 chase keeps its lane)"
            ),
        ));
    }
    if !search_start {
        return Err(f.invalid(
            "tracker.start",
            format!(
                "must be \"search\" in {without}: there is no target to place the tracker \
                 on at the start; it searches the chase's path"
            ),
        ));
    }
    if !raw.environment.distractors.is_empty() {
        return Err(f.invalid(
            "environment.distractors",
            format!("must be empty in {without}: the distractors move with the lead"),
        ));
    }
    let speed = f64::from(cruise);
    Ok(LeadFile {
        start_m,
        initial_speed_mps: Some(speed),
        speed_basis: "time".into(),
        speed_profile: vec![[0.0, speed]],
        driver: vehicle::LeadDriverConfig::default(),
        lane: chase.lane.unwrap_or(1),
        offset_m: 0.0,
        events: vehicle::EventScript::default(),
        lamps: None,
    })
}
