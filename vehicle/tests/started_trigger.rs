//! `started` triggers: an event that waits for another's start fires at the step after that
//! action started, or `delay_s` later, whether the other's action is still running or has
//! ended; in a group, with a rising edge, and in a repeating event; malformed ones are
//! refused naming their field.
//!
//! Run: `cargo test -p vehicle --release --test started_trigger`

mod common;

use common::events::*;
use vehicle::*;

/// The step at which `name` first did `kind` in `log`.
fn at(log: &[(u64, String, FiredKind)], name: &str, kind: FiredKind) -> u64 {
    log.iter()
        .find(|e| e.1 == name && e.2 == kind)
        .map(|e| e.0)
        .unwrap_or_else(|| panic!("{name} {kind:?}: {log:?}"))
}

/// A brake 1 s after a lane change starts, while the change still runs (esmini's
/// `alks_r157_cut_in_quick_brake`); a wait for the start with no delay starts at the next
/// step; a start waited for in a group, on its rising edge.
#[test]
fn a_started_trigger_fires_after_the_other_action_starts() {
    let mut events = engine(
        r#"
        [[events]]
        name = "cut-in"
        trigger = { time_s = 2.0 }
        action = { lane = 2, duration_s = 3.0 }

        [[events]]
        name = "brake"
        trigger = { started = "cut-in", delay_s = 1.0, rising = true }
        action = { speed_mps = 0.0, rate_mps2 = 4.0 }

        [[events]]
        name = "note"
        trigger = { started = "cut-in" }
        action = { speed_mps = 5.0, rate_mps2 = 1.0 }

        [[events]]
        name = "both"
        trigger = { all = [{ started = "brake" }, { time_s = 1.0 }] }
        action = { end_run = true }
        "#,
    );
    let log = run(&mut events, 1200, |t| {
        [car(100.0 + 6.0 * t, 6.0), car(400.0, 0.0)]
    });
    use FiredKind::*;
    assert_eq!(at(&log, "cut-in", Started), 240);
    // The lane change runs 3 s (to step 600): the brake starts while it runs.
    assert_eq!(at(&log, "cut-in", Ended), 600);
    assert_eq!(at(&log, "brake", Started), 241 + 120);
    // "note" at the step after; the brake replaces its speed change.
    assert_eq!(at(&log, "note", Started), 241);
    assert_eq!(at(&log, "note", Ended), 361);
    assert_eq!(at(&log, "both", Started), 362);
}

/// An event that never starts leaves what waits for its start waiting; a repeating event
/// whose trigger is another's start fires again once its own action has ended, as an
/// `after` trigger's does.
#[test]
fn a_start_that_never_comes_is_never_seen_and_a_start_stays_seen() {
    let mut events = engine(
        r#"
        [[events]]
        name = "never"
        trigger = { time_s = 1000.0 }
        action = { lane = 2, duration_s = 3.0 }

        [[events]]
        name = "waits"
        trigger = { started = "never" }
        action = { speed_mps = 0.0, rate_mps2 = 4.0 }

        [[events]]
        name = "go"
        trigger = { time_s = 0.5 }
        action = { speed_mps = 8.0, rate_mps2 = 1.0 }

        [[events]]
        name = "again"
        trigger = { started = "go" }
        action = { speed_mps = 7.0, duration_s = 1.0 }
        repeat = true
        max_runs = 3
        "#,
    );
    let log = run(&mut events, 1200, |t| {
        [car(100.0 + 6.0 * t, 6.0), car(400.0, 0.0)]
    });
    assert!(log.iter().all(|e| e.1 != "waits"), "{log:?}");
    let starts: Vec<u64> = log
        .iter()
        .filter(|e| e.1 == "again" && e.2 == FiredKind::Started)
        .map(|e| e.0)
        .collect();
    // From the step after "go" started, then each step after its own 1 s action ended.
    assert_eq!(starts, [61, 61 + 121, 61 + 2 * 121]);
}

/// Each malformed `started` trigger is refused, naming the field.
#[test]
fn bad_started_triggers_name_their_field() {
    refused_naming(vec![
        (
            one("trigger = { started = \"c\" }", OK_ACTION),
            "events[1].trigger.started",
        ),
        (
            one("trigger = { started = \"b\" }", OK_ACTION),
            "events[1].trigger.started",
        ),
        (
            one("trigger = { started = \"a\", rule = \"less\" }", OK_ACTION),
            "events[1].trigger.rule",
        ),
        (
            one("trigger = { started = \"a\", after = \"a\" }", OK_ACTION),
            "events[1].trigger",
        ),
        (
            one("trigger = { started = \"a\", to = \"other\" }", OK_ACTION),
            "events[1].trigger.to",
        ),
    ]);
}
