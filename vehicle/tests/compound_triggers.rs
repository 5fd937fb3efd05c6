//! Triggers of several conditions (`all`, `any`): an `all` fires at the first step at which
//! every member holds together, an `any` at the first at which one does; a member's delay
//! is OpenSCENARIO's (the member holds when its condition held that long before, so a
//! condition that stopped holding stops holding later too); a one-member group fires where
//! its member alone does; members watch vehicles and stand still as triggers do; malformed
//! groups are refused naming the member's field.
//!
//! Run: `cargo test -p vehicle --release --test compound_triggers`

mod common;

use common::events::*;
use vehicle::*;

/// Me from station 100 at 6 m/s; the other standing at 200 (the gap 95 − 6t closing).
fn approach(t: f64) -> [VehicleView; 2] {
    [car(100.0 + 6.0 * t, 6.0), car(200.0, 0.0)]
}

/// The step at which an event with `trigger` first starts on `approach` traffic, if it
/// does within 30 s.
fn fires(trigger: &str) -> Option<u64> {
    let mut events = engine(&format!(
        "[[events]]\nname = \"e\"\ntrigger = {trigger}\n\
         action = {{ speed_mps = 5.0, rate_mps2 = 1.0 }}"
    ));
    let log = run(&mut events, 3600, approach);
    let starts = log.iter().filter(|e| e.2 == FiredKind::Started).count();
    assert!(starts <= 1, "{trigger}: {log:?}");
    first_start(&log, "e")
}

#[test]
fn all_waits_for_every_member_and_any_for_the_first() {
    // The gap 95 − 6t ≤ 12.02 from step 1660 (as in `events.rs`).
    let gap = "{ gap_m = 12.02, to = \"other\" }";
    assert_eq!(fires(gap), Some(1660));
    let cases = [
        // Time ≥ 5 s holds first: the gap decides.
        (
            format!("{{ all = [{{ time_s = 5.0 }}, {gap}] }}"),
            Some(1660),
        ),
        // The gap holds first: the time decides.
        (
            format!("{{ all = [{gap}, {{ time_s = 15.0 }}] }}"),
            Some(1800),
        ),
        // Each holds, but never at the same step.
        (
            format!("{{ all = [{{ time_s = 2.0, rule = \"less\" }}, {gap}] }}"),
            None,
        ),
        (
            format!("{{ any = [{{ time_s = 8.0 }}, {gap}] }}"),
            Some(960),
        ),
        (
            format!("{{ any = [{{ time_s = 20.0 }}, {gap}] }}"),
            Some(1660),
        ),
        (
            format!("{{ any = [{{ time_s = 1.0, rule = \"less\" }}, {gap}] }}"),
            Some(0),
        ),
        // OpenSCENARIO's shape: any of groups, each all of conditions.
        (
            format!(
                "{{ any = [{{ all = [{{ time_s = 14.0 }}, {gap}] }}, \
                 {{ all = [{{ speed_mps = 6.5, rule = \"greater\" }}, {{ time_s = 1.0 }}] }}] }}"
            ),
            Some(1680),
        ),
    ];
    for (trigger, expected) in cases {
        assert_eq!(fires(&trigger), expected, "{trigger}");
    }
}

/// A one-member group fires where its member alone does, delay and all: for a whole
/// event's trigger, "delay_s after it first holds" and "held delay_s before" agree.
#[test]
fn a_group_of_one_fires_where_its_member_does() {
    for member in [
        "{ time_s = 8.0 }",
        "{ time_s = 8.0, delay_s = 1.25 }",
        "{ gap_m = 12.02, to = \"other\", delay_s = 0.5 }",
        "{ ttc_s = 3.01, to = \"other\", delay_s = 2.0 }",
        "{ distance_m = 10.001, delay_s = 0.004 }",
        "{ time_s = 1.0, rule = \"less\", delay_s = 2.0 }",
    ] {
        let alone = fires(member);
        assert!(alone.is_some(), "{member}");
        for kind in ["all", "any"] {
            let grouped = format!("{{ {kind} = [{member}] }}");
            assert_eq!(fires(&grouped), alone, "{grouped}");
        }
    }
}

/// A member's delay looks back: `time_s ≤ 1` delayed 2 s holds from 2 s to 3 s only
/// (steps 240–360), so a group needing it with `time_s ≥ 2.5` fires at 2.5 s and one needing
/// it with `time_s ≥ 3.5` never does (the trigger alone, latched, would fire at 2 s).
#[test]
fn a_members_delay_is_its_condition_that_long_ago() {
    let pulse = "{ time_s = 1.0, rule = \"less\", delay_s = 2.0 }";
    assert_eq!(fires(pulse), Some(240));
    assert_eq!(
        fires(&format!("{{ all = [{pulse}, {{ time_s = 2.5 }}] }}")),
        Some(300)
    );
    assert_eq!(
        fires(&format!("{{ all = [{pulse}, {{ time_s = 3.0 }}] }}")),
        Some(360)
    );
    assert_eq!(
        fires(&format!("{{ all = [{pulse}, {{ time_s = 3.01 }}] }}")),
        None
    );
    // The gap ≤ 94.01 holds from step 20 (t = 0.165 s → 19.8); delayed 1 s, from step 140.
    assert_eq!(
        fires("{ all = [{ gap_m = 94.01, to = \"other\", delay_s = 1.0 }, { time_s = 0.5 }] }"),
        Some(140)
    );
}

/// A latched member holds from the first step it holds on (an OpenSCENARIO act's start):
/// `time_s ≤ 1` latched lets a group needing `time_s ≥ 3` fire at 3 s, where unlatched it
/// never does; latched after a delay, from when the delayed condition first holds; a latch
/// on an edge keeps the edge's one step. An event's own trigger takes no latch.
#[test]
fn a_latched_member_holds_from_its_first_step_on() {
    let early = "{ time_s = 1.0, rule = \"less\"";
    assert_eq!(
        fires(&format!("{{ all = [{early} }}, {{ time_s = 3.0 }}] }}")),
        None
    );
    assert_eq!(
        fires(&format!(
            "{{ all = [{early}, latched = true }}, {{ time_s = 3.0 }}] }}"
        )),
        Some(360)
    );
    // The gap ≤ 12.02 from step 1660, delayed 1 s: from step 1780, latched after it.
    let gap = "gap_m = 12.02, to = \"other\", delay_s = 1.0, latched = true";
    assert_eq!(
        fires(&format!("{{ all = [{{ {gap} }}, {{ time_s = 2.0 }}] }}")),
        Some(1780)
    );
    // A rising edge at the first step it holds, latched: the group waits for the time.
    let rising = "{ time_s = 4.0, rising = true, latched = true }";
    assert_eq!(
        fires(&format!("{{ all = [{rising}, {{ time_s = 6.0 }}] }}")),
        Some(720)
    );
    assert_eq!(
        fires("{ all = [{ time_s = 4.0, rising = true }, { time_s = 6.0 }] }"),
        None
    );
    refused_naming(vec![(
        one("trigger = { time_s = 1.0, latched = true }", OK_ACTION),
        "events[1].trigger.latched",
    )]);
}

/// Members watch other vehicles and stand still as whole triggers do, and an `after`
/// member waits for another event's end.
#[test]
fn members_watch_vehicles_standstills_and_other_events() {
    let mut events = engine(
        r#"
        [[events]]
        name = "slow"
        trigger = { time_s = 1.0 }
        action = { speed_mps = 4.0, duration_s = 2.0 }

        [[events]]
        name = "both"
        trigger = { all = [{ after = "slow" }, { standstill_s = 4.0, of = "other" }] }
        action = { lane = 2, duration_s = 1.0 }
        "#,
    );
    let log = run(&mut events, 1200, approach);
    // `slow` ends at step 360; the other has stood still since step 0, 4 s at step 480.
    assert_eq!(first_start(&log, "both"), Some(480));
}

#[test]
fn malformed_groups_are_refused_naming_the_member() {
    let a = OK_ACTION;
    let deep = "{ all = [{ any = [{ all = [{ any = [{ time_s = 1.0 }] }] }] }] }";
    let wide = "{ any = [{ time_s = 1.0 }, { time_s = 2.0 }, { time_s = 3.0 }, \
                { time_s = 4.0 }, { time_s = 5.0 }] }";
    refused_naming(vec![
        (one("trigger = { all = [] }", a), "events[1].trigger.all"),
        (
            one("trigger = { all = [{ time_s = 1.0 }], time_s = 1.0 }", a),
            "events[1].trigger",
        ),
        (
            one("trigger = { all = [{ gap_m = 3.0 }] }", a),
            "events[1].trigger.all[0].to",
        ),
        (
            one(
                "trigger = { any = [{ time_s = 1.0 }, { time_s = -1.0 }] }",
                a,
            ),
            "events[1].trigger.any[1].time_s",
        ),
        (
            one("trigger = { any = [{ after = \"b\" }] }", a),
            "events[1].trigger.any[0].after",
        ),
        (
            one("trigger = { any = [{ time_s = 1.0 }], to = \"other\" }", a),
            "events[1].trigger.to",
        ),
        (
            one("trigger = { any = [{ time_s = 1.0 }], rule = \"less\" }", a),
            "events[1].trigger.rule",
        ),
        (
            one("trigger = { all = [{ time_s = 1.0 }], delay_s = 1.0 }", a),
            "events[1].trigger.delay_s",
        ),
        (
            one(&format!("trigger = {deep}"), a),
            "events[1].trigger.all[0].any[0].all[0].any",
        ),
        // 5 × 5 × 5 = 125 groups written as OpenSCENARIO writes a trigger.
        (
            one(
                &format!("trigger = {{ all = [{wide}, {wide}, {wide}] }}"),
                a,
            ),
            "events[1].trigger",
        ),
    ]);
}

/// The engine finds each member's vehicles and lanes, naming the member; the scenario's
/// checks see them through `vehicles_named` and `lanes_named`.
#[test]
fn members_vehicles_and_lanes_are_named_to_the_caller() {
    let s = script(
        r#"
        [[events]]
        name = "e"
        trigger = { any = [{ time_s = 1.0 }, { all = [{ speed_mps = 3.0, of = "other" }, { gap_m = 5.0, to = "bus" }] }, { reach = { station_m = 10.0, lane = 4, tolerance_m = 1.0 } }] }
        action = { lane = 2, duration_s = 1.0 }
        "#,
    );
    s.validate().unwrap();
    let named: Vec<_> = s.vehicles_named().collect();
    assert_eq!(
        named,
        [
            ("events[0].trigger.any[1].all[0].of".to_string(), "other"),
            ("events[0].trigger.any[1].all[1].to".to_string(), "bus"),
        ]
    );
    let lanes: Vec<_> = s.lanes_named().collect();
    assert_eq!(
        lanes,
        [
            ("events[0].trigger.any[2].reach.lane".to_string(), 4),
            ("events[0].action.lane".to_string(), 2),
        ]
    );
    let field = |e: VehicleError| match e {
        VehicleError::InvalidEvent { field, .. } => field,
        other => panic!("{other:?}"),
    };
    let err = Events::new(&s, &["me", "other"], LANES).unwrap_err();
    assert_eq!(field(err), "events[0].trigger.any[1].all[1].to");
    let err = Events::new(&s, &["me", "other", "bus"], LANES).unwrap_err();
    assert_eq!(field(err), "events[0].trigger.any[2].reach.lane");
}

/// A script with groups writes back to the same TOML it was read from.
#[test]
fn groups_round_trip_through_toml() {
    let s = script(
        r#"
        [[events]]
        name = "e"
        trigger = { any = [{ all = [{ time_s = 1.0, delay_s = 0.5 }, { ttc_s = 2.0, to = "other" }] }, { distance_m = 30.0 }] }
        action = { speed_mps = 0.0, shape = "step" }
        "#,
    );
    #[derive(serde::Serialize)]
    struct File<'a> {
        events: &'a EventScript,
    }
    let again = script(&toml::to_string(&File { events: &s }).unwrap());
    assert_eq!(again, s);
}
