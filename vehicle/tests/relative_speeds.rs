//! Guarantees that a speed change relative to another vehicle goes to that vehicle's speed
//! (times a factor, or plus a difference) as it is when the change starts, and with
//! `continuous` keeps to it as that speed changes until another speed action replaces it.
//!
//! Run: `cargo test -p vehicle --release --test relative_speeds`

mod common;

use common::events::*;
use vehicle::*;

/// A speed relative to another vehicle's: to its speed times a factor or plus a difference
/// as it is when the change starts; kept to it as the other's speed changes with
/// `continuous`, which runs until another speed action replaces it; held where it was
/// reached without.
#[test]
fn a_relative_speed_goes_to_the_others_speed_and_keeps_to_it_when_continuous() {
    // The other speeds up from 10 m/s by 1 m/s every second; I drive at 8 m/s.
    let view = |t: f64| [car(100.0, 8.0), car(150.0, 10.0 + t)];
    let speed_at = |action: &str, t: f64| {
        let mut events = engine(&format!(
            "[[events]]\nname = \"rel\"\ntrigger = {{ time_s = 2.0 }}\naction = {{ {action} }}\n\
             [[events]]\nname = \"then\"\ntrigger = {{ time_s = 9.0 }}\n\
             action = {{ speed_mps = 3.0, shape = \"step\" }}"
        ));
        let steps = Step::from_seconds(t).0 + 1;
        let log = run(&mut events, steps, view);
        let ended = log
            .iter()
            .find(|e| e.1 == "rel" && e.2 == FiredKind::Ended)
            .map(|e| e.0);
        (events.speed_override().unwrap().speed_mps, ended)
    };
    let close = |a: f32, b: f64| (f64::from(a) - b).abs() < 1e-4;
    // A factor, at once, continuous: 0.5 × (10 + t), to the step that replaces it.
    let factor = "speed_of = \"other\", speed_factor = 0.5, shape = \"step\", continuous = true";
    for t in [2.0, 5.0, 8.5] {
        let (v, ended) = speed_at(factor, t);
        assert!(close(v, 0.5 * (10.0 + t)), "at {t} s: {v}");
        assert_eq!(ended, None, "a continuous speed ended before {t} s");
    }
    let (v, ended) = speed_at(factor, 9.5);
    assert!(close(v, 3.0), "{v}");
    assert_eq!(ended, Some(Step::from_seconds(9.0).0), "replaced at 9 s");
    // A difference over 1 s, not continuous: to 12 − 2 = 10 m/s, held after 3 s.
    let delta = "speed_of = \"other\", speed_mps = -2.0, duration_s = 1.0";
    let (v, ended) = speed_at(delta, 6.0);
    assert!(close(v, 10.0), "{v}");
    assert_eq!(ended, Some(Step::from_seconds(3.0).0));
    // The same, continuous: the difference kept, 2 m/s below the other.
    let (v, _) = speed_at(&format!("{delta}, continuous = true"), 6.0);
    assert!(close(v, 14.0), "{v}");
}
