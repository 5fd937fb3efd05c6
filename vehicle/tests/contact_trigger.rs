//! Contact triggers: an event with `contact = true, to = NAME` fires at the first step the
//! view says the two vehicles touch, on level and on edges; `Events::contacts_watched`
//! names the vehicles the caller must check; malformed ones are refused naming their field.
//!
//! Run: `cargo test -p vehicle --release --test contact_trigger`

mod common;

use common::events::*;
use vehicle::*;

/// Me at 100 m; the other (index 1) touching me from 2 s to 3 s (steps 240 to 359 at
/// 120 Hz).
fn bump(t: f64) -> [VehicleView; 2] {
    let touch = (2.0..3.0).contains(&t);
    let mut me = car(100.0, 0.0);
    let mut other = car(95.0, 0.0);
    me.touching = u64::from(touch) << 1;
    other.touching = u64::from(touch);
    [me, other]
}

#[test]
fn a_contact_trigger_fires_while_the_vehicles_touch() {
    let mut events = engine(
        r#"
        [[events]]
        name = "hit"
        trigger = { contact = true, to = "other" }
        action = { end_run = true }

        [[events]]
        name = "parted"
        trigger = { contact = true, to = "other", falling = true }
        action = { speed_mps = 1.0, rate_mps2 = 1.0 }

        [[events]]
        name = "unrelated"
        trigger = { time_s = 1.0 }
        action = { speed_mps = 2.0, rate_mps2 = 1.0 }
        "#,
    );
    assert_eq!(events.contacts_watched(), [1]);
    let log = run(&mut events, 1200, bump);
    assert_eq!(first_start(&log, "hit"), Some(240), "{log:?}");
    assert_eq!(first_start(&log, "parted"), Some(360), "{log:?}");
    // The other's contact with someone else is not this one's.
    let mut quiet = engine(
        r#"
        [[events]]
        name = "hit"
        trigger = { contact = true, to = "other" }
        action = { end_run = true }
        "#,
    );
    let log = run(&mut quiet, 1200, |t| {
        let [mut me, other] = bump(t);
        me.touching = 0;
        [me, other]
    });
    assert_eq!(first_start(&log, "hit"), None, "{log:?}");
    let none = engine(OK_TRIGGER_SCRIPT);
    assert!(none.contacts_watched().is_empty());
}

const OK_TRIGGER_SCRIPT: &str = r#"
[[events]]
name = "a"
trigger = { time_s = 1.0 }
action = { speed_mps = 5.0, rate_mps2 = 1.0 }
"#;

#[test]
fn bad_contact_triggers_name_their_field() {
    refused_naming(vec![
        (
            one("trigger = { contact = true }", OK_ACTION),
            "events[1].trigger.to",
        ),
        (
            one(
                "trigger = { contact = true, to = \"other\", rule = \"less\" }",
                OK_ACTION,
            ),
            "events[1].trigger.rule",
        ),
        (
            one(
                "trigger = { contact = true, to = \"other\", time_s = 1.0 }",
                OK_ACTION,
            ),
            "events[1].trigger",
        ),
    ]);
}
