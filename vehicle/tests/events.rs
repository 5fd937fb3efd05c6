//! Guarantees the event engine keeps on synthetic traffic: every trigger fires on level at
//! the step its condition first holds, `after` chains and `delay_s` wait as documented,
//! `repeat` fires again, actions move the speed and the lateral offset along their shapes,
//! the documented TOML parses, and every malformed event is refused naming its field.
//!
//! Run: `CARGO_TARGET_DIR=/work/wt-events/target cargo test -p vehicle --release --test events`

mod common;

use common::events::*;
use vehicle::*;

/// Every trigger kind, each with its default rule and the other one, on traffic whose
/// values cross the thresholds between steps (the time at an exact step, as promised).
#[test]
fn each_trigger_fires_at_the_step_its_condition_first_holds() {
    // Me: from station 100 at 6 m/s (0.05 m a step). Other: standing at 200 (bumpers
    // 199–204). My front at 104 + 6t: gap 95 − 6t, closing at 6 m/s.
    let approach = |t: f64| [car(100.0 + 6.0 * t, 6.0), car(200.0, 0.0)];
    // Me ahead at 150 standing; other coming from 100 at 10 m/s: gap from its front (104
    // + 10t) to my rear (149): 45 − 10t.
    let overtaken = |t: f64| [car(150.0, 0.0), car(100.0 + 10.0 * t, 10.0)];
    // Me behind at 100, 8 m/s; other ahead from 130 at 10 m/s: the gap (25 + 2t) opens.
    let opening = |t: f64| [car(100.0 + 8.0 * t, 8.0), car(130.0 + 10.0 * t, 10.0)];
    type View = fn(f64) -> [VehicleView; 2];
    let cases: [(&str, View, Option<u64>); 23] = [
        ("time_s = 8.0", approach, Some(960)),
        ("time_s = 8.0, rule = \"less\"", approach, Some(0)),
        // Travelled 10 m at 10/6 s = step 200 exactly; the threshold just past it.
        ("distance_m = 10.001", approach, Some(201)),
        ("distance_m = 10.001, rule = \"less\"", approach, Some(0)),
        // 95 − 6t ≤ 12.02 from t = 13.83 s: step 1659.6 → 1660.
        ("gap_m = 12.02, to = \"other\"", approach, Some(1660)),
        // Already holding at step 0: fires on level, at once.
        ("gap_m = 100.0, to = \"other\"", approach, Some(0)),
        (
            "gap_m = 94.99, to = \"other\", rule = \"greater\"",
            approach,
            Some(0),
        ),
        (
            "gap_m = 95.01, to = \"other\", rule = \"greater\"",
            approach,
            None,
        ),
        // The other behind me: 45 − 10t ≤ 5.02 from t = 3.998 s: step 479.76 → 480.
        ("gap_m = 5.02, to = \"other\"", overtaken, Some(480)),
        // Reference point to reference point: 100 − 6t ≤ 40.01 from t = 9.998 s: step
        // 1199.76 → 1200.
        ("spacing_m = 40.01, to = \"other\"", approach, Some(1200)),
        // The other behind me: |50 − 10t| ≤ 5.01 from t = 4.499 s: step 539.88 → 540.
        ("spacing_m = 5.01, to = \"other\"", overtaken, Some(540)),
        // 100 at the start: not more than 100.01.
        (
            "spacing_m = 100.01, to = \"other\", rule = \"greater\"",
            approach,
            None,
        ),
        // Time gap (95 − 6t)/6 ≤ 2.01 from t = 13.823 s: step 1658.8 → 1659.
        ("time_gap_s = 2.01, to = \"other\"", approach, Some(1659)),
        // The one behind is the other: (45 − 10t)/10 ≤ 1.003 from t = 3.497: step 419.6.
        ("time_gap_s = 1.003, to = \"other\"", overtaken, Some(420)),
        // With a side, only while this vehicle is on it: behind the other, as before, and
        // never ahead of it; ahead of the other overtaking, as before, and never behind.
        (
            "time_gap_s = 2.01, to = \"other\", side = \"behind\"",
            approach,
            Some(1659),
        ),
        (
            "time_gap_s = 2.01, to = \"other\", side = \"ahead\"",
            approach,
            None,
        ),
        (
            "time_gap_s = 1.003, to = \"other\", side = \"ahead\"",
            overtaken,
            Some(420),
        ),
        (
            "time_gap_s = 1.003, to = \"other\", side = \"behind\"",
            overtaken,
            None,
        ),
        // Closing at 6 m/s: (95 − 6t)/6 ≤ 3.01 from t = 12.823 s: step 1538.8 → 1539.
        ("ttc_s = 3.01, to = \"other\"", approach, Some(1539)),
        // Between the axles, on the spacing 100 − 6t: (100 − 6t)/6 ≤ 2.01 from
        // t = 14.657 s: step 1758.8 → 1759; and ≤ 3.01 from t = 13.657 s: step 1638.8 → 1639.
        (
            "time_gap_s = 2.01, to = \"other\", between_axles = true",
            approach,
            Some(1759),
        ),
        (
            "ttc_s = 3.01, to = \"other\", between_axles = true",
            approach,
            Some(1639),
        ),
        // Opening: no time to collision, whatever the rule.
        ("ttc_s = 100.0, to = \"other\"", opening, None),
        (
            "ttc_s = 0.0, to = \"other\", rule = \"greater\"",
            opening,
            None,
        ),
    ];
    for (trigger, view, expected) in cases {
        let mut events = engine(&format!(
            "[[events]]\nname = \"e\"\ntrigger = {{ {trigger} }}\n\
             action = {{ speed_mps = 5.0, rate_mps2 = 1.0 }}"
        ));
        let log = run(&mut events, 2400, view);
        assert_eq!(first_start(&log, "e"), expected, "{trigger}");
        // Once only: started at most once.
        let starts = log.iter().filter(|e| e.2 == FiredKind::Started).count();
        assert!(starts <= 1, "{trigger}: {log:?}");
    }
}

/// `after` holds from the step after the other's action ended; `delay_s` starts the action
/// that many steps after the condition first held, whatever it does meanwhile.
#[test]
fn after_chains_and_delays() {
    let mut events = engine(
        r#"
        [[events]]
        name = "slow"
        trigger = { time_s = 1.0 }
        action = { speed_mps = 4.0, duration_s = 2.0 }

        [[events]]
        name = "pull-out"
        trigger = { after = "slow" }
        action = { lane = 2, duration_s = 1.0 }

        [[events]]
        name = "back"
        trigger = { after = "pull-out", delay_s = 0.5 }
        action = { lane = 1, lateral_speed_mps = 3.5 }

        [[events]]
        name = "brief"
        trigger = { gap_m = 90.0, to = "other", delay_s = 6.0 }
        action = { stop = true, decel_mps2 = 4.0 }
        "#,
    );
    let log = run(&mut events, 1200, |t| {
        [car(100.0 + 6.0 * t, 6.0), car(200.0, 0.0)]
    });
    let at = |name: &str, kind: FiredKind| {
        log.iter()
            .find(|e| e.1 == name && e.2 == kind)
            .map(|e| e.0)
            .unwrap_or_else(|| panic!("{name} {kind:?}: {log:?}"))
    };
    use FiredKind::*;
    assert_eq!(at("slow", Started), 120);
    assert_eq!(at("slow", Ended), 360);
    assert_eq!(at("pull-out", Started), 361);
    assert_eq!(at("pull-out", Ended), 481);
    // 60 steps of delay, then 3.5 m at 3.5 m/s: 1 s.
    assert_eq!(at("back", Started), 542);
    assert_eq!(at("back", Ended), 662);
    // Gap 95 − 6t ≤ 90 from t = 0.8333 s (step 100), then 6 s: step 820, though the
    // gap has long been smaller.
    assert_eq!(at("brief", Started), 820);
}

/// A speed action replaces the running one, which ends there (and what waits for its end
/// starts at the next step); a lane change likewise replaces a lane change.
#[test]
fn a_new_action_replaces_the_running_one_of_its_kind() {
    let mut events = engine(
        r#"
        [[events]]
        name = "long"
        trigger = { time_s = 0.0 }
        action = { speed_mps = 20.0, duration_s = 5.0 }

        [[events]]
        name = "sudden"
        trigger = { time_s = 1.0 }
        action = { speed_mps = 2.0, shape = "step" }

        [[events]]
        name = "then"
        trigger = { after = "long" }
        action = { lane = 2, duration_s = 2.0 }

        [[events]]
        name = "swerve"
        trigger = { time_s = 2.0 }
        action = { lane = 3, duration_s = 1.0 }
        "#,
    );
    let log = run(&mut events, 600, |_| [car(0.0, 10.0), car(50.0, 5.0)]);
    use FiredKind::*;
    let expected: Vec<(u64, String, FiredKind)> = [
        (0, "long", Started),
        (120, "long", Ended),
        (120, "sudden", Started),
        (120, "sudden", Ended),
        (121, "then", Started),
        (240, "then", Ended),
        (240, "swerve", Started),
        (360, "swerve", Ended),
    ]
    .into_iter()
    .map(|(n, name, kind)| (n, name.to_string(), kind))
    .collect();
    assert_eq!(log, expected);
    let s = events.speed_override().unwrap();
    assert_eq!((s.speed_mps, s.accel_mps2), (2.0, 0.0));
    assert_eq!(events.lateral_offset_m(), -7.0);
}

/// With `repeat`, an event fires again each time its condition holds after its action
/// ended (the next step at the earliest); without, once.
#[test]
fn repeat_fires_again_once_the_action_has_ended() {
    let mut events = engine(
        r#"
        [[events]]
        name = "again"
        trigger = { time_s = 1.0 }
        action = { lane = 2, duration_s = 1.0 }
        repeat = true

        [[events]]
        name = "once"
        trigger = { time_s = 1.0 }
        action = { speed_mps = 3.0, duration_s = 1.0 }
        "#,
    );
    let log = run(&mut events, 600, |_| [car(0.0, 5.0), car(50.0, 5.0)]);
    let starts = |name: &str| -> Vec<u64> {
        log.iter()
            .filter(|e| e.1 == name && e.2 == FiredKind::Started)
            .map(|e| e.0)
            .collect()
    };
    assert_eq!(starts("again"), [120, 241, 362, 483]);
    assert_eq!(starts("once"), [120]);
}

/// The other shuttling between stations 100 and 140 at 10 m/s (4 s each way) by me,
/// standing at 100: the spacing is 10 t for t in [0, 4) of each 8 s period, then 80 − 10 t.
fn shuttle(t: f64) -> [VehicleView; 2] {
    let u = t % 8.0;
    let x = if u < 4.0 {
        100.0 + 10.0 * u
    } else {
        180.0 - 10.0 * u
    };
    [car(100.0, 0.0), car(x, 0.0)]
}

/// The steps at which a repeating 0.5 s event with `trigger` starts over 24 s by the
/// [`shuttle`].
fn shuttle_starts(trigger: &str) -> Vec<u64> {
    let mut events = engine(&format!(
        "[[events]]\nname = \"e\"\ntrigger = {{ {trigger} }}\n\
         action = {{ speed_mps = 5.0, duration_s = 0.5 }}\nrepeat = true"
    ));
    run(&mut events, 2880, shuttle)
        .iter()
        .filter(|e| e.2 == FiredKind::Started)
        .map(|e| e.0)
        .collect()
}

/// With `rising`, a repeating event fires again only once its condition has stopped holding
/// and holds again: the other shuttles between stations 100 and 140 (40 m each way at
/// 10 m/s, 4 s), so a spacing of 10 m or more holds from 1 s to 7 s of each 8 s, and a
/// 0.5 s action ends long before it stops holding. On level, the event fires again at the
/// step after each end while the condition still holds; on its edge, once a period. At the
/// first step an edge is its level: a condition holding then fires at once. On `all` and
/// `any`, the edge is the group's.
#[test]
fn a_rising_edge_fires_a_repeating_event_once_each_time_its_condition_starts_to_hold() {
    let level = shuttle_starts("spacing_m = 10.0, to = \"other\", rule = \"greater\"");
    // 1 s to 7 s: 0.5 s runs back to back, 61 steps apart, 12 of them a period.
    assert_eq!(level.len(), 3 * 12, "{level:?}");
    let rising =
        shuttle_starts("spacing_m = 10.0, to = \"other\", rule = \"greater\", rising = true");
    assert_eq!(rising, [120, 1080, 2040]);
    // At most 5 m, holding at the first step: fires there, then at each new start of
    // holding (7.5 s into each period).
    let at_once = shuttle_starts("spacing_m = 5.0, to = \"other\", rising = true");
    assert_eq!(at_once, [0, 900, 1860, 2820]);
    let group = shuttle_starts(
        "any = [{ spacing_m = 10.0, to = \"other\", rule = \"greater\" }, { time_s = 100.0 }], rising = true",
    );
    assert_eq!(group, [120, 1080, 2040]);
    let member = shuttle_starts(
        "any = [{ spacing_m = 10.0, to = \"other\", rule = \"greater\", rising = true }, { time_s = 100.0 }]",
    );
    assert_eq!(member, [120, 1080, 2040]);
}

/// With `falling`, an event fires at the step its condition stops holding, having held at
/// the step before, and never at the first step; with `rising` too, at either edge. By the
/// [`shuttle`], a spacing of 10 m or more holds from 1 s to 7 s of
/// each 8 s (7 s itself included), so it stops holding one step after 7 s.
#[test]
fn a_falling_edge_fires_when_the_condition_stops_holding() {
    let far = "spacing_m = 10.0, to = \"other\", rule = \"greater\"";
    assert_eq!(
        shuttle_starts(&format!("{far}, falling = true")),
        [841, 1801, 2761]
    );
    assert_eq!(
        shuttle_starts(&format!("{far}, rising = true, falling = true")),
        [120, 841, 1080, 1801, 2040, 2761]
    );
    // At most 5 m holds at the first step: no edge there; it stops holding past 0.5 s.
    let near = "spacing_m = 5.0, to = \"other\", falling = true";
    assert_eq!(shuttle_starts(near), [61, 1021, 1981]);
}

/// `max_runs` bounds a repeating event's runs; `check` refuses it without `repeat` and
/// below 2.
#[test]
fn max_runs_bounds_the_runs_of_a_repeating_event() {
    let mut events = engine(
        r#"
        [[events]]
        name = "thrice"
        trigger = { time_s = 1.0 }
        action = { lane = 2, duration_s = 1.0 }
        repeat = true
        max_runs = 3
        "#,
    );
    let log = run(&mut events, 600, |_| [car(0.0, 5.0), car(50.0, 5.0)]);
    let starts: Vec<u64> = log
        .iter()
        .filter(|e| e.2 == FiredKind::Started)
        .map(|e| e.0)
        .collect();
    assert_eq!(starts, [120, 241, 362]);
    for (extra, field, says) in [
        (
            "max_runs = 3",
            "events[0].max_runs",
            "needs `repeat = true`",
        ),
        (
            "repeat = true\nmax_runs = 1",
            "events[0].max_runs",
            "= 1: must be at least 2",
        ),
    ] {
        let e = script(&format!(
            "[[events]]\nname = \"e\"\ntrigger = {{ time_s = 1.0 }}\n\
             action = {{ stop = true, decel_mps2 = 4.0 }}\n{extra}\n"
        ))
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains(field) && e.contains(says), "{e}");
    }
}

/// The speed follows the action's shape from the vehicle's speed at its start, with its
/// rate as the acceleration, and is held after; a lane change moves the offset to the
/// lane's centre along its shape, and the next one starts from where it is.
#[test]
fn actions_follow_their_shapes() {
    let mut events = engine(
        r#"
        [[events]]
        name = "speed"
        trigger = { time_s = 0.0 }
        action = { speed_mps = 16.0, duration_s = 2.0, shape = "cubic" }

        [[events]]
        name = "lane"
        trigger = { time_s = 0.0 }
        action = { lane = 3, duration_s = 4.0, shape = "sinusoidal" }

        [[events]]
        name = "back"
        trigger = { time_s = 2.0 }
        action = { lane = 1, duration_s = 1.0 }
        "#,
    );
    let view = [car(0.0, 10.0), car(50.0, 5.0)];
    assert_eq!(events.speed_override(), None);
    events.update(Step(0), &view, 0);
    let s = events.speed_override().unwrap();
    assert_eq!((s.speed_mps, s.accel_mps2), (10.0, 0.0));
    for n in 1..=360 {
        events.update(Step(n), &view, 0);
        let s = events.speed_override().unwrap();
        let offset = events.lateral_offset_m();
        if n == 120 {
            // Half way: the mean speed, the cubic's steepest rate 1.5 × 6 m/s / 2 s.
            assert!((s.speed_mps - 13.0).abs() < 1e-5, "{s:?}");
            assert!((s.accel_mps2 - 4.5).abs() < 1e-5, "{s:?}");
            // A quarter of the sinusoid: (1 − cos π/4)/2 of lane 3's −7 m.
            let expected = -7.0 * 0.5 * (1.0 - std::f64::consts::FRAC_PI_4.cos());
            assert!((offset - expected).abs() < 1e-9, "{offset}");
        }
        if n >= 240 {
            assert_eq!((s.speed_mps, s.accel_mps2), (16.0, 0.0));
        }
        if n >= 360 {
            assert_eq!(offset, 0.0);
        }
    }
}

/// Every example the docs show parses and checks.
#[test]
fn the_documented_toml_parses() {
    let text = r#"
        [[events]]
        name = "cut-in"
        trigger = { time_s = 8.0 }
        action = { lane = 1, duration_s = 2.5, shape = "cubic" }
        [[events]]
        name = "b"
        trigger = { distance_m = 120.0 }
        action = { lane = 2, lateral_speed_mps = 1.0, shape = "sinusoidal" }
        [[events]]
        name = "c"
        trigger = { gap_m = 12.0, to = "other", rule = "less" }
        action = { speed_mps = 8.0, rate_mps2 = 2.0 }
        [[events]]
        name = "d"
        trigger = { time_gap_s = 1.5, to = "other" }
        action = { speed_mps = 8.0, duration_s = 3.0, shape = "cubic" }
        [[events]]
        name = "e"
        trigger = { ttc_s = 3.0, to = "other", rule = "greater" }
        action = { speed_mps = 0.0, shape = "step" }
        [[events]]
        name = "f"
        trigger = { after = "cut-in", delay_s = 0.5 }
        action = { stop = true, decel_mps2 = 4.0 }
        repeat = true
    "#;
    let s = script(text);
    s.validate().unwrap();
    assert_eq!(s.0.len(), 6);
    Events::new(&s, &["me", "other"], LANES).unwrap();
    let vehicles: Vec<(String, &str)> = s.vehicles_named().collect();
    assert_eq!(
        vehicles,
        [
            ("events[2].trigger.to".to_string(), "other"),
            ("events[3].trigger.to".to_string(), "other"),
            ("events[4].trigger.to".to_string(), "other"),
        ]
    );
    let lanes: Vec<(String, u32)> = s.lanes_named().collect();
    assert_eq!(
        lanes,
        [
            ("events[0].action.lane".to_string(), 1),
            ("events[1].action.lane".to_string(), 2)
        ]
    );
    // What serialises reads back the same.
    #[derive(serde::Serialize)]
    struct File<'a> {
        events: &'a EventScript,
    }
    let again = script(&toml::to_string(&File { events: &s }).unwrap());
    assert_eq!(again, s);
}

/// Each malformed trigger is refused, naming the field; none panics.
#[test]
fn bad_triggers_name_their_field() {
    let (ok_trigger, ok_action) = (OK_TRIGGER, OK_ACTION);
    refused_naming(vec![
        (one("trigger = { }", ok_action), "events[1].trigger"),
        (
            one(
                "trigger = { time_s = 1.0, gap_m = 3.0, to = \"other\" }",
                ok_action,
            ),
            "events[1].trigger",
        ),
        (
            one("trigger = { gap_m = 3.0 }", ok_action),
            "events[1].trigger.to",
        ),
        (
            one("trigger = { time_s = 3.0, to = \"other\" }", ok_action),
            "events[1].trigger.to",
        ),
        (
            one("trigger = { after = \"c\" }", ok_action),
            "events[1].trigger.after",
        ),
        (
            one("trigger = { after = \"b\" }", ok_action),
            "events[1].trigger.after",
        ),
        (
            one("trigger = { after = \"a\", rule = \"less\" }", ok_action),
            "events[1].trigger.rule",
        ),
        (
            one("trigger = { time_s = -1.0 }", ok_action),
            "events[1].trigger.time_s",
        ),
        (
            one("trigger = { time_s = nan }", ok_action),
            "events[1].trigger.time_s",
        ),
        (
            one("trigger = { time_s = 1.0, delay_s = inf }", ok_action),
            "events[1].trigger.delay_s",
        ),
        (
            one("trigger = { ttc_s = -2.0, to = \"other\" }", ok_action),
            "events[1].trigger.ttc_s",
        ),
        (
            one(
                "trigger = { gap_m = 5.0, to = \"other\", between_axles = true }",
                ok_action,
            ),
            "events[1].trigger.between_axles",
        ),
        (
            one(
                "trigger = { gap_m = 5.0, to = \"other\", side = \"ahead\" }",
                ok_action,
            ),
            "events[1].trigger.side",
        ),
        (
            one(ok_trigger, "action = { speed_factor = 0.5, shape = \"step\" }"),
            "events[1].action.speed_factor",
        ),
        (
            one(ok_trigger, "action = { speed_of = \"other\", lane = 2, duration_s = 1.0 }"),
            "events[1].action.speed_of",
        ),
        (
            one(
                ok_trigger,
                "action = { speed_of = \"other\", speed_mps = 1.0, speed_factor = 2.0, shape = \"step\" }",
            ),
            "events[1].action",
        ),
        (
            one(ok_trigger, "action = { speed_mps = 5.0, shape = \"step\", continuous = true }"),
            "events[1].action.continuous",
        ),
        (one(ok_trigger, "action = { }"), "events[1].action"),
    ]);
}

/// Each malformed action or name is refused, naming the field; none panics.
#[test]
fn bad_actions_and_names_name_their_field() {
    let (ok_trigger, ok_action) = (OK_TRIGGER, OK_ACTION);
    refused_naming(vec![
        (
            one(
                ok_trigger,
                "action = { lane = 2, speed_mps = 3.0, duration_s = 1.0 }",
            ),
            "events[1].action",
        ),
        (one(ok_trigger, "action = { lane = 2 }"), "events[1].action"),
        (
            one(ok_trigger, "action = { lane = 0, duration_s = 1.0 }"),
            "events[1].action.lane",
        ),
        (
            one(ok_trigger, "action = { lane = 2, duration_s = 0.0 }"),
            "events[1].action.duration_s",
        ),
        (
            one(
                ok_trigger,
                "action = { lane = 2, lateral_speed_mps = -1.0 }",
            ),
            "events[1].action.lateral_speed_mps",
        ),
        (
            one(
                ok_trigger,
                "action = { lane = 2, duration_s = 1.0, shape = \"step\" }",
            ),
            "events[1].action.shape",
        ),
        (
            one(
                ok_trigger,
                "action = { lane = 2, duration_s = 1.0, rate_mps2 = 1.0 }",
            ),
            "events[1].action.rate_mps2",
        ),
        (
            one(ok_trigger, "action = { speed_mps = 50.0, rate_mps2 = 1.0 }"),
            "events[1].action.speed_mps",
        ),
        (
            one(ok_trigger, "action = { speed_mps = 5.0, rate_mps2 = 0.0 }"),
            "events[1].action.rate_mps2",
        ),
        (
            one(ok_trigger, "action = { speed_mps = 5.0 }"),
            "events[1].action",
        ),
        (
            one(
                ok_trigger,
                "action = { speed_mps = 5.0, duration_s = 1.0, rate_mps2 = 1.0 }",
            ),
            "events[1].action",
        ),
        (
            one(
                ok_trigger,
                "action = { speed_mps = 5.0, duration_s = 2.0, shape = \"sinusoidal\" }",
            ),
            "events[1].action.shape",
        ),
        (
            one(
                ok_trigger,
                "action = { speed_mps = 5.0, duration_s = 2.0, shape = \"step\" }",
            ),
            "events[1].action.shape",
        ),
        (
            one(
                ok_trigger,
                "action = { speed_mps = 5.0, rate_mps2 = 2.0, shape = \"cubic\" }",
            ),
            "events[1].action.shape",
        ),
        (
            one(ok_trigger, "action = { stop = true }"),
            "events[1].action.decel_mps2",
        ),
        (
            one(ok_trigger, "action = { stop = false, decel_mps2 = 3.0 }"),
            "events[1].action.stop",
        ),
        (
            one(
                ok_trigger,
                "action = { stop = true, decel_mps2 = 3.0, duration_s = 1.0 }",
            ),
            "events[1].action.duration_s",
        ),
        (
            one(ok_trigger, "action = { stop = true, decel_mps2 = 30.0 }"),
            "events[1].action.decel_mps2",
        ),
        (
            "[[events]]\nname = \"a\"\ntrigger = { time_s = 1.0 }\n\
             action = { stop = true, decel_mps2 = 3.0 }\n\
             [[events]]\nname = \"a\"\ntrigger = { time_s = 1.0 }\n\
             action = { stop = true, decel_mps2 = 3.0 }\n"
                .to_string(),
            "events[1].name",
        ),
        (
            one(ok_trigger, ok_action).replace("\"b\"", "\" \""),
            "events[1].name",
        ),
    ]);
}

/// The engine refuses a `to` or a `speed_of` that names no vehicle, a lane the road does not have and bad
/// lanes, naming the field; the parser refuses unknown fields, naming them.
#[test]
fn the_engine_and_the_parser_name_bad_fields() {
    let (ok_trigger, ok_action) = (OK_TRIGGER, OK_ACTION);
    let s = script(&one(
        "trigger = { gap_m = 3.0, to = \"nobody\" }",
        ok_action,
    ));
    s.validate().unwrap();
    let err = Events::new(&s, &["me", "other"], LANES).unwrap_err();
    assert!(
        matches!(&err, VehicleError::InvalidEvent { field, .. } if field == "events[1].trigger.to"),
        "{err:?}"
    );
    let s = script(&one(
        ok_trigger,
        "action = { speed_of = \"nobody\", speed_mps = 1.0, shape = \"step\" }",
    ));
    s.validate().unwrap();
    let err = Events::new(&s, &["me", "other"], LANES).unwrap_err();
    assert!(
        matches!(&err, VehicleError::InvalidEvent { field, .. } if field == "events[1].action.speed_of"),
        "{err:?}"
    );
    let s = script(&one(ok_trigger, "action = { lane = 4, duration_s = 1.0 }"));
    let err = Events::new(&s, &["me"], LANES).unwrap_err();
    assert!(
        matches!(&err, VehicleError::InvalidEvent { field, .. } if field == "events[1].action.lane"),
        "{err:?}"
    );
    let bad_lanes = Lanes {
        route_lane: 4,
        ..LANES
    };
    assert!(matches!(
        Events::new(&EventScript::default(), &[], bad_lanes),
        Err(VehicleError::InvalidParameter {
            field: "route_lane",
            ..
        })
    ));
    // Unknown fields are refused by the parser, naming them.
    #[derive(Debug, serde::Deserialize)]
    #[allow(dead_code)]
    struct File {
        events: EventScript,
    }
    let err = toml::from_str::<File>(&one("trigger = { time = 1.0 }", ok_action)).unwrap_err();
    assert!(err.to_string().contains("unknown field `time`"), "{err}");
}

/// Speed triggers compare the speed of the vehicle `of` (or this one) with the threshold
/// at every step; standstill triggers count the steps it has stood still without a break.
#[test]
fn speed_and_standstill_triggers_watch_the_vehicle_named() {
    // Other slows at 2 m/s² from 10 m/s: at most 4 m/s from t = 3 s (step 360).
    let slowing = |t: f64| [car(100.0, 6.0), car(200.0, 10.0 - 2.0 * t)];
    let cases: [(&str, Option<u64>); 5] = [
        ("speed_mps = 4.0, of = \"other\"", Some(360)),
        (
            "speed_mps = 4.0, of = \"other\", rule = \"greater\"",
            Some(0),
        ),
        ("speed_mps = 5.0", None),
        ("speed_mps = 5.0, rule = \"greater\"", Some(0)),
        ("speed_mps = 6.0", Some(0)),
    ];
    for (trigger, expected) in cases {
        let mut e = engine(&format!(
            "[[events]]\nname = \"e\"\ntrigger = {{ {trigger} }}\naction = {{ speed_mps = 1.0, shape = \"step\" }}\n"
        ));
        assert_eq!(
            first_start(&run(&mut e, 600, slowing), "e"),
            expected,
            "{trigger}"
        );
    }
    // Other: 3 m/s, standing from 5 s, moving 6–6.5 s, standing again from 6.5 s (step 780).
    let stop_go = |t: f64| {
        let v = if t < 5.0 || (6.0..6.5).contains(&t) {
            3.0
        } else {
            0.0
        };
        [car(100.0, 0.0), car(200.0, v)]
    };
    let cases: [(&str, Option<u64>); 4] = [
        ("standstill_s = 0.5, of = \"other\"", Some(660)),
        ("standstill_s = 2.0, of = \"other\"", Some(1020)),
        (
            "standstill_s = 2.0, of = \"other\", delay_s = 0.5",
            Some(1080),
        ),
        // This vehicle stands from the start.
        ("standstill_s = 1.0", Some(120)),
    ];
    for (trigger, expected) in cases {
        let mut e = engine(&format!(
            "[[events]]\nname = \"e\"\ntrigger = {{ {trigger} }}\naction = {{ speed_mps = 1.0, shape = \"step\" }}\n"
        ));
        assert_eq!(
            first_start(&run(&mut e, 1200, stop_go), "e"),
            expected,
            "{trigger}"
        );
    }
    // `of` naming no vehicle, or on a trigger that watches none, is refused by its field.
    for (trigger, field) in [
        ("speed_mps = 4.0, of = \"bus\"", "events[0].trigger.of"),
        ("time_s = 1.0, of = \"other\"", "events[0].trigger.of"),
        (
            "standstill_s = 1.0, rule = \"less\"",
            "events[0].trigger.rule",
        ),
        ("standstill_s = -1.0", "events[0].trigger.standstill_s"),
        ("speed_mps = 4.0, to = \"other\"", "events[0].trigger.to"),
    ] {
        let s = script(&format!(
            "[[events]]\nname = \"e\"\ntrigger = {{ {trigger} }}\naction = {{ speed_mps = 1.0, shape = \"step\" }}\n"
        ));
        match Events::new(&s, &["me", "other"], LANES) {
            Err(VehicleError::InvalidEvent { field: f, .. }) => assert_eq!(f, field, "{trigger}"),
            other => panic!("{trigger}: {other:?}"),
        }
    }
}

/// Relative speeds, reach points and the equal / not-equal rules fire at the step their
/// condition first holds, on level; a reach's lane and offset are across the road from
/// lane 1's centre; each malformed one is refused naming its field.
#[test]
fn relative_speed_reach_and_equality_fire_as_documented() {
    // Me from 100 at 6 m/s; the other ahead at 200, slowing from 10 m/s at 1 m/s²:
    // me − other = 6 − (10 − t) ≥ 0.5 from t = 4.5 s: step 540 exactly.
    let slowing = |t: f64| [car(100.0 + 6.0 * t, 6.0), car(200.0, (10.0 - t).max(0.0))];
    // In lane 2 (3.5 m right of lane 1's centre): me from 100 at 6 m/s.
    let in_lane_2 = |t: f64| {
        let mut v = car(100.0 + 6.0 * t, 6.0);
        v.left_offset_m = -3.5;
        [v, car(300.0, 0.0)]
    };
    type View = fn(f64) -> [VehicleView; 2];
    let cases: [(&str, View, Option<u64>); 10] = [
        (
            "relative_speed_mps = 0.5, to = \"other\", rule = \"greater\"",
            slowing,
            Some(540),
        ),
        // Less is the default: −4 ≤ −3.999 at once.
        (
            "relative_speed_mps = -3.999, to = \"other\"",
            slowing,
            Some(0),
        ),
        // Equal within a millionth: the difference is −4 + t, 0 at step 480 exactly.
        (
            "relative_speed_mps = 0.0, to = \"other\", rule = \"equal\"",
            slowing,
            Some(480),
        ),
        (
            "relative_speed_mps = -4.0, to = \"other\", rule = \"not_equal\"",
            slowing,
            Some(1),
        ),
        // Time equal to a whole step holds at it; a time between steps never.
        ("time_s = 5.0, rule = \"equal\"", slowing, Some(600)),
        ("time_s = 5.001, rule = \"equal\"", slowing, None),
        ("time_s = 0.0, rule = \"not_equal\"", slowing, Some(1)),
        // Within 2.01 m of station 160 on lane 2's centre: 100 + 6t ≥ 157.99 from t =
        // 9.665 s: step 1159.8 → 1160.
        (
            "reach = { station_m = 160.0, lane = 2, tolerance_m = 2.01 }",
            in_lane_2,
            Some(1160),
        ),
        // On lane 1's centre the point is 3.5 m across: never within 2.01 m.
        (
            "reach = { station_m = 160.0, lane = 1, tolerance_m = 2.01 }",
            in_lane_2,
            None,
        ),
        // 1.5 m left of lane 2's centre, tolerance 2.51: along ≤ √(2.51² − 1.5²) = 2.0125 m
        // from t = 9.6646 s: step 1159.75 → 1160.
        (
            "reach = { station_m = 160.0, lane = 2, offset_m = 1.5, tolerance_m = 2.51 }",
            in_lane_2,
            Some(1160),
        ),
    ];
    for (trigger, view, expected) in cases {
        let mut events = engine(&format!(
            "[[events]]\nname = \"e\"\ntrigger = {{ {trigger} }}\n\
             action = {{ speed_mps = 5.0, rate_mps2 = 1.0 }}"
        ));
        let log = run(&mut events, 2400, view);
        assert_eq!(first_start(&log, "e"), expected, "{trigger}");
    }
    // A reach watching the other vehicle: it stands at 300 (lane 1's centre).
    let mut events = engine(
        "[[events]]\nname = \"e\"\n\
         trigger = { reach = { station_m = 299.5, lane = 1, tolerance_m = 1.0 }, of = \"other\" }\n\
         action = { speed_mps = 5.0, rate_mps2 = 1.0 }",
    );
    assert_eq!(first_start(&run(&mut events, 10, in_lane_2), "e"), Some(0));
    let ok_action = OK_ACTION;
    refused_naming(vec![
        (
            one("trigger = { relative_speed_mps = 1.0 }", ok_action),
            "events[1].trigger.to",
        ),
        (
            one(
                "trigger = { relative_speed_mps = 41.0, to = \"other\" }",
                ok_action,
            ),
            "events[1].trigger.relative_speed_mps",
        ),
        (
            one(
                "trigger = { relative_speed_mps = 1.0, of = \"other\", to = \"other\" }",
                ok_action,
            ),
            "events[1].trigger.of",
        ),
        (
            one(
                "trigger = { reach = { station_m = 1.0, lane = 1, tolerance_m = 0.0 } }",
                ok_action,
            ),
            "events[1].trigger.reach.tolerance_m",
        ),
        (
            one(
                "trigger = { reach = { station_m = 1.0, lane = 0, tolerance_m = 1.0 } }",
                ok_action,
            ),
            "events[1].trigger.reach.lane",
        ),
        (
            one(
                "trigger = { reach = { station_m = 1.0, lane = 1, offset_m = 30.0, tolerance_m = 1.0 } }",
                ok_action,
            ),
            "events[1].trigger.reach.offset_m",
        ),
        (
            one(
                "trigger = { reach = { station_m = 1.0, lane = 1, tolerance_m = 1.0 }, rule = \"equal\" }",
                ok_action,
            ),
            "events[1].trigger.rule",
        ),
        (
            one(
                "trigger = { reach = { station_m = 1.0, lane = 1, tolerance_m = 1.0 }, to = \"other\" }",
                ok_action,
            ),
            "events[1].trigger.to",
        ),
    ]);
    // A reach's lane past the road's lanes is the engine's to refuse.
    let s = script(
        "[[events]]\nname = \"e\"\n\
         trigger = { reach = { station_m = 1.0, lane = 4, tolerance_m = 1.0 } }\n\
         action = { speed_mps = 5.0, rate_mps2 = 1.0 }",
    );
    match Events::new(&s, &["me", "other"], LANES) {
        Err(VehicleError::InvalidEvent { field, .. }) => {
            assert_eq!(field, "events[0].trigger.reach.lane")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        s.lanes_named().collect::<Vec<_>>(),
        [("events[0].trigger.reach.lane".to_string(), 4)]
    );
}

#[test]
fn lanes_of_their_own_widths_put_each_centre_half_its_width_beyond_the_lanes_inside() {
    // e6mini's driving lanes: 3.65, 3.5 and 3.9 m; the route runs along lane 3's centre.
    let lanes = Lanes {
        width_m: 3.65,
        count: 3,
        route_lane: 3,
        widths_m: Some([3.65, 3.5, 3.9, 0.0]),
    };
    let close = |a: f64, b: f64| assert!((a - b).abs() < 1e-12, "{a} vs {b}");
    close(lanes.offset_m(3), 0.0);
    close(lanes.offset_m(2), 0.5 * 3.9 + 0.5 * 3.5);
    close(lanes.offset_m(1), 0.5 * 3.9 + 3.5 + 0.5 * 3.65);
    // One width: the rule of whole lane widths.
    let even = Lanes {
        widths_m: None,
        ..lanes
    };
    close(even.offset_m(1), 2.0 * 3.65);
    // A width out of bounds is refused.
    let bad = Lanes {
        widths_m: Some([3.65, 0.1, 3.9, 0.0]),
        ..lanes
    };
    assert!(matches!(
        Events::new(&EventScript::default(), &[], bad),
        Err(VehicleError::InvalidParameter {
            field: "lane_widths_m",
            ..
        })
    ));
}
