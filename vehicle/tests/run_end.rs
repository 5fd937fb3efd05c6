//! The road end trigger and the action that ends the run, on synthetic traffic: a road end
//! trigger holds once its vehicle has been within `ROAD_END_M` of the road's end for its
//! duration, and never on a road with no end given; an `end_run` action starts and ends at
//! the step its trigger holds, and the engine says so (`Events::run_ended`); both are
//! refused naming their fields when malformed.
//!
//! Run: `cargo test -p vehicle --release --test run_end`

mod common;

use common::events::*;
use vehicle::*;

/// Me driving at 10 m/s from station 0 towards a road's end at 500 m, then standing 2 m
/// short of it as a driver does (from 49.8 s); the other standing far behind.
fn to_the_end(t: f64) -> [VehicleView; 2] {
    let station = (10.0 * t).min(498.0);
    let speed = if station < 498.0 { 10.0 } else { 0.0 };
    [car(station, speed), car(-100.0, 0.0)]
}

#[test]
fn a_road_end_trigger_holds_after_its_duration_at_the_end() {
    let text = "[[events]]\nname = \"done\"\ntrigger = { road_end_s = 2.5 }\naction = { end_run = true }\n\
                [[events]]\nname = \"other-done\"\ntrigger = { road_end_s = 0.0, of = \"other\" }\naction = { end_run = true }\n";
    let mut events = engine(text).with_road_end_m(500.0);
    let log = run(&mut events, 120 * 60, to_the_end);
    // Within 5 m of the end from station 495: t = 49.5 s, step 5940; 2.5 s later, 6240.
    assert_eq!(first_start(&log, "done"), Some(5940 + 300), "{log:?}");
    // It ends at once, and the engine names it as the one that ended the run.
    assert!(
        log.contains(&(6240, "done".into(), FiredKind::Ended)),
        "{log:?}"
    );
    assert_eq!(events.run_ended(), Some((Step(6240), 0)));
    // The other, standing 600 m from the end, never gets there.
    assert_eq!(first_start(&log, "other-done"), None);
    // A road with no end given: never.
    let mut endless = engine(text);
    let log = run(&mut endless, 120 * 60, to_the_end);
    assert_eq!(first_start(&log, "done"), None, "{log:?}");
    assert_eq!(endless.run_ended(), None);
}

#[test]
fn an_end_run_action_fires_once_its_trigger_holds_and_ends_at_once() {
    let text = "[[events]]\nname = \"brake\"\ntrigger = { time_s = 1.0 }\naction = { speed_mps = 0.0, rate_mps2 = 2.0 }\n\
                [[events]]\nname = \"end\"\ntrigger = { after = \"brake\", delay_s = 0.5 }\naction = { end_run = true }\n";
    let mut events = engine(text);
    let log = run(&mut events, 15 * 120, to_the_end);
    // The brake from 10 m/s at 2 m/s² ends 5 s after 1 s, at step 720; `after` holds from
    // the next step (the end is known once that step's triggers are judged), and the end
    // starts 0.5 s on, ending at once.
    assert_eq!(first_start(&log, "end"), Some(721 + 60), "{log:?}");
    assert!(
        log.contains(&(781, "end".into(), FiredKind::Ended)),
        "{log:?}"
    );
    assert_eq!(events.run_ended(), Some((Step(781), 1)));
    // An end does not move the vehicle: no speed or offset is asked for by it.
    assert_eq!(events.lateral_offset_m(), 0.0);
}

#[test]
fn malformed_road_end_and_end_run_events_are_refused_naming_their_field() {
    refused_naming(vec![
        (
            one("trigger = { road_end_s = -1.0 }", OK_ACTION),
            "events[1].trigger.road_end_s",
        ),
        (
            one("trigger = { road_end_s = 1.0, rule = \"less\" }", OK_ACTION),
            "events[1].trigger.rule",
        ),
        (
            one("trigger = { road_end_s = 1.0, to = \"other\" }", OK_ACTION),
            "events[1].trigger.to",
        ),
        (
            one("trigger = { time_s = 2.0, of = \"other\" }", OK_ACTION),
            "events[1].trigger.of",
        ),
        (
            one(OK_TRIGGER, "action = { end_run = false }"),
            "events[1].action.end_run",
        ),
        (
            one(OK_TRIGGER, "action = { end_run = true, shape = \"cubic\" }"),
            "events[1].action.shape",
        ),
        (
            one(OK_TRIGGER, "action = { end_run = true, stop = true }"),
            "events[1].action",
        ),
    ]);
}
