//! Offsets within a lane (OpenSCENARIO's `LaneOffsetAction`): the vehicle moves to the
//! offset from its lane's centre along its shape, taking the time that makes its peak
//! lateral acceleration the one asked; an offset is from the lane the last lane change went
//! to, and a lane change ends on the lane's centre. Speed profiles (its
//! `SpeedProfileAction`): each change follows the one before from the speed it reached,
//! over its time or at its rate, and the event ends with the last. Malformed offsets and
//! profiles are refused naming their field.
//!
//! Run: `cargo test -p vehicle --release --test offsets_and_profiles`

mod common;

use common::events::*;
use vehicle::*;

/// The lateral offset asked at each step of `steps`, and every event fired, on a vehicle
/// driving at 10 m/s beside a standing one.
fn lateral(toml_text: &str, steps: u64) -> (Vec<f64>, Vec<(u64, String, FiredKind)>) {
    let mut events = engine(toml_text);
    let (mut offsets, mut log) = (Vec::new(), Vec::new());
    for n in 0..steps {
        let now = Step(n);
        let view = [car(100.0 + 10.0 * now.seconds(), 10.0), car(0.0, 0.0)];
        for f in events.update(now, &view, 0) {
            log.push((n, f.name, f.kind));
        }
        offsets.push(events.lateral_offset_m());
    }
    (offsets, log)
}

/// The largest second difference of `y` per step², as an acceleration, m/s².
fn peak_accel(y: &[f64]) -> f64 {
    let hz = 120.0_f64;
    y.windows(3)
        .map(|w| ((w[2] - 2.0 * w[1] + w[0]) * hz * hz).abs())
        .fold(0.0, f64::max)
}

#[test]
fn an_offset_takes_the_time_its_shape_needs_for_its_peak_lateral_acceleration() {
    for (shape, seconds) in [
        // Cubic: 6 × 0.8 / T² = 0.5.
        ("cubic", (6.0_f64 * 0.8 / 0.5).sqrt()),
        // Sinusoidal: π² × 0.8 / (2 T²) = 0.5.
        (
            "sinusoidal",
            std::f64::consts::PI * (0.8_f64 / (2.0 * 0.5)).sqrt(),
        ),
    ] {
        let (y, log) = lateral(
            &format!(
                "[[events]]\nname = \"drift\"\ntrigger = {{ time_s = 1.0 }}\n\
                 action = {{ offset_m = 0.8, lateral_accel_mps2 = 0.5, shape = \"{shape}\" }}"
            ),
            1200,
        );
        let steps = (seconds * 120.0).round() as u64;
        assert_eq!(
            log,
            [
                (120, "drift".to_string(), FiredKind::Started),
                (120 + steps, "drift".to_string(), FiredKind::Ended),
            ],
            "{shape}"
        );
        assert_eq!(y[119], 0.0);
        assert_eq!(*y.last().unwrap(), 0.8, "{shape}");
        let peak = peak_accel(&y[120..=(120 + steps as usize)]);
        assert!((peak - 0.5).abs() < 0.01, "{shape}: peak {peak}");
    }
}

#[test]
fn an_offset_is_from_the_lane_the_vehicle_changed_to_and_a_lane_change_ends_on_the_centre() {
    let (y, _) = lateral(
        r#"
        [[events]]
        name = "over"
        trigger = { time_s = 0.5 }
        action = { lane = 2, duration_s = 2.0 }

        [[events]]
        name = "hug"
        trigger = { after = "over" }
        action = { offset_m = -0.5, lateral_accel_mps2 = 1.0 }

        [[events]]
        name = "back"
        trigger = { time_s = 8.0 }
        action = { lane = 1, duration_s = 2.0 }
        "#,
        1500,
    );
    // Lane 2 is 3.5 m to the right of lane 1, the route's lane.
    assert_eq!(y[900], -3.5 - 0.5);
    assert_eq!(*y.last().unwrap(), 0.0);
}

#[test]
fn malformed_offsets_are_refused_naming_their_field() {
    let t = OK_TRIGGER;
    refused_naming(vec![
        (
            one(t, "action = { offset_m = 0.5, duration_s = 2.0 }"),
            "events[1].action.duration_s",
        ),
        (
            one(t, "action = { offset_m = 0.5, lateral_speed_mps = 1.0 }"),
            "events[1].action.lateral_speed_mps",
        ),
        (
            one(t, "action = { offset_m = 0.5 }"),
            "events[1].action.lateral_accel_mps2",
        ),
        (
            one(t, "action = { offset_m = 0.5, lateral_accel_mps2 = 0.0 }"),
            "events[1].action.lateral_accel_mps2",
        ),
        (
            one(t, "action = { offset_m = 25.0, lateral_accel_mps2 = 1.0 }"),
            "events[1].action.offset_m",
        ),
        (
            one(
                t,
                "action = { offset_m = 0.5, lateral_accel_mps2 = 1.0, shape = \"linear\" }",
            ),
            "events[1].action.shape",
        ),
        (
            one(
                t,
                "action = { offset_m = 0.5, lane = 2, lateral_accel_mps2 = 1.0 }",
            ),
            "events[1].action",
        ),
        (
            one(
                t,
                "action = { speed_mps = 5.0, rate_mps2 = 1.0, lateral_accel_mps2 = 1.0 }",
            ),
            "events[1].action.lateral_accel_mps2",
        ),
        (
            one(
                t,
                "action = { offset_m = 0.5, lateral_accel_mps2 = 1.0, rate_mps2 = 1.0 }",
            ),
            "events[1].action.rate_mps2",
        ),
    ]);
}

#[test]
fn a_profile_makes_its_changes_one_after_another() {
    let mut events = engine(
        r#"
        [[events]]
        name = "p"
        trigger = { time_s = 1.0 }
        action = { profile = [
            { speed_mps = 15.0, duration_s = 2.0 },
            { speed_mps = 15.0, duration_s = 1.0 },
            { speed_mps = 5.0, rate_mps2 = 2.0 },
            { speed_mps = 8.0, duration_s = 0.0 },
        ] }
        "#,
    );
    let mut asked = Vec::new();
    let mut log = Vec::new();
    for n in 0..1300 {
        let now = Step(n);
        // The vehicle's own speed, read when the profile starts: 10 m/s.
        let view = [car(100.0 + 10.0 * now.seconds(), 10.0), car(0.0, 0.0)];
        for f in events.update(now, &view, 0) {
            log.push((n, f.kind));
        }
        asked.push(events.speed_override());
    }
    assert_eq!(log, [(120, FiredKind::Started), (1080, FiredKind::Ended)]);
    let at = |n: usize| asked[n].map(|o| (o.speed_mps, o.accel_mps2)).unwrap();
    assert!(asked[119].is_none());
    assert_eq!(at(240), (12.5, 2.5));
    assert_eq!(at(420), (15.0, 0.0));
    assert_eq!(at(780), (10.0, -2.0));
    assert!((at(1079).0 - (5.0 + 10.0 / 600.0)).abs() < 1e-5);
    assert_eq!(at(1080), (8.0, 0.0));
    assert_eq!(at(1299), (8.0, 0.0));
}

#[test]
fn malformed_profiles_are_refused_naming_their_field() {
    let t = OK_TRIGGER;
    refused_naming(vec![
        (
            one(t, "action = { profile = [] }"),
            "events[1].action.profile",
        ),
        (
            one(t, "action = { profile = [{ speed_mps = 5.0 }] }"),
            "events[1].action.profile[0]",
        ),
        (
            one(
                t,
                "action = { profile = [{ speed_mps = 5.0, duration_s = 1.0, rate_mps2 = 1.0 }] }",
            ),
            "events[1].action.profile[0]",
        ),
        (
            one(
                t,
                "action = { profile = [{ speed_mps = 5.0, duration_s = 1.0 }, \
                 { speed_mps = 50.0, duration_s = 1.0 }] }",
            ),
            "events[1].action.profile[1].speed_mps",
        ),
        (
            one(
                t,
                "action = { profile = [{ speed_mps = 5.0, duration_s = -1.0 }] }",
            ),
            "events[1].action.profile[0].duration_s",
        ),
        (
            one(
                t,
                "action = { profile = [{ speed_mps = 5.0, duration_s = 1.0 }], duration_s = 1.0 }",
            ),
            "events[1].action.duration_s",
        ),
        (
            one(
                t,
                "action = { profile = [{ speed_mps = 5.0, duration_s = 1.0 }], speed_mps = 1.0 }",
            ),
            "events[1].action",
        ),
    ]);
}
