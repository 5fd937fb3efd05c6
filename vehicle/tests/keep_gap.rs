//! A kept gap (`action = { keep = ... }`, OpenSCENARIO's `LongitudinalDistanceAction`) on
//! synthetic traffic that moves as the engine asks: this vehicle drives at the speed its
//! events ask for, the other at its own. The gap settles on the one asked, behind or ahead,
//! by distance or time, within the limits; a gap that is not continuous ends once reached;
//! another speed action replaces it.
//!
//! Run: `cargo test -p vehicle --release --test keep_gap`

mod common;

use common::events::*;
use vehicle::*;

/// What a run of `text` did: my station, speed and acceleration asked at each step, and
/// the events fired.
struct Run {
    me: Vec<(f64, f64, f64)>,
    log: Vec<(u64, String, FiredKind)>,
}

/// Runs `text` for `seconds`, me from `me_at` at `speed` m/s, the other from `other_at`
/// at `other_speed(t)`.
fn drive(
    text: &str,
    seconds: f64,
    me_at: f64,
    speed: f64,
    other_at: f64,
    other_speed: fn(f64) -> f64,
) -> Run {
    let mut events = engine(text);
    let dt = 1.0 / f64::from(PHYSICS_HZ);
    let (mut me, mut v, mut other) = (me_at, speed, other_at);
    let mut run = Run {
        me: Vec::new(),
        log: Vec::new(),
    };
    for n in 0..(seconds * f64::from(PHYSICS_HZ)) as u64 {
        let now = Step(n);
        let vo = other_speed(now.seconds());
        for f in events.update(now, &[car(me, v), car(other, vo)], 0) {
            run.log.push((n, f.name, f.kind));
        }
        let (asked, accel) = events.speed_override().map_or((v, 0.0), |s| {
            (f64::from(s.speed_mps), f64::from(s.accel_mps2))
        });
        v = asked;
        me += v * dt;
        other += vo * dt;
        run.me.push((me, v, accel));
    }
    run
}

/// The bumper gap from the one behind to the one ahead (`car`: bumpers 1 m behind and 4 m
/// ahead of the station).
fn gap(behind: f64, ahead: f64) -> f64 {
    (ahead - 1.0) - (behind + 4.0)
}

#[test]
fn a_kept_gap_settles_behind_and_ahead_by_distance_and_time() {
    let steady = |_: f64| 15.0;
    let other_at = |t: f64| 60.0 + 15.0 * t;
    // 55 m behind at first, asked 20 m: it closes and settles.
    let r = drive(
        "[[events]]\nname = \"k\"\ntrigger = { time_s = 0.0 }\naction = { keep = { gap_m = 20.0, to = \"other\" } }\n",
        40.0, 0.0, 15.0, 60.0, steady,
    );
    let (me, v, _) = *r.me.last().unwrap();
    assert!(
        (gap(me, other_at(40.0)) - 20.0).abs() < 0.05,
        "{}",
        gap(me, other_at(40.0))
    );
    assert!((v - 15.0).abs() < 0.01, "{v}");
    // Within its limits all the way (default 4 m/s² up, 8 down), and never past the gap
    // asked by more than a few centimetres (critically damped).
    assert!(r
        .me
        .iter()
        .all(|m| m.2 <= KEEP_MAX_ACCEL_MPS2 + 1e-9 && m.2 >= -KEEP_MAX_DECEL_MPS2 - 1e-9));
    let closest =
        r.me.iter()
            .enumerate()
            .map(|(n, m)| gap(m.0, other_at((n + 1) as f64 / 120.0)))
            .fold(f64::INFINITY, f64::min);
    assert!(closest > 19.9, "{closest}");
    // A time gap of 1.5 s at 15 m/s: 22.5 m.
    let r = drive(
        "[[events]]\nname = \"k\"\ntrigger = { time_s = 0.0 }\naction = { keep = { time_gap_s = 1.5, to = \"other\" } }\n",
        40.0, 0.0, 15.0, 60.0, steady,
    );
    let me = r.me.last().unwrap().0;
    assert!(
        (gap(me, other_at(40.0)) - 22.5).abs() < 0.05,
        "{}",
        gap(me, other_at(40.0))
    );
    // Ahead of the other, 10 m clear of its front: it slows to let it close.
    let r = drive(
        "[[events]]\nname = \"k\"\ntrigger = { time_s = 0.0 }\naction = { keep = { gap_m = 10.0, to = \"other\", side = \"ahead\" } }\n",
        40.0, 100.0, 15.0, 60.0, steady,
    );
    let me = r.me.last().unwrap().0;
    assert!(
        (gap(other_at(40.0), me) - 10.0).abs() < 0.05,
        "{}",
        gap(other_at(40.0), me)
    );
}

/// The step at which the event `k` of run `r` ended.
fn ended_at(r: &Run) -> u64 {
    r.log
        .iter()
        .find(|e| e.1 == "k" && e.2 == FiredKind::Ended)
        .map(|e| e.0)
        .expect("reached and ended")
}

#[test]
fn a_gap_not_continuous_ends_once_reached_and_the_speed_is_kept() {
    let r = drive(
        "[[events]]\nname = \"k\"\ntrigger = { time_s = 0.0 }\naction = { keep = { gap_m = 20.0, to = \"other\", continuous = false } }\n",
        40.0, 0.0, 15.0, 60.0, |_| 15.0,
    );
    let ended = ended_at(&r);
    let at = |n: u64| r.me[n as usize];
    let other = |n: u64| 60.0 + 15.0 * (n + 1) as f64 / 120.0;
    assert!((gap(at(ended).0, other(ended)) - 20.0).abs() < KEEP_REACHED_M + 0.01);
    // After it, the speed it had is held.
    let v = at(ended).1;
    assert!(r.me[ended as usize..].iter().all(|m| m.1 == v), "{v}");

    // A time gap of 1.5 s at 15 m/s (22.5 m) ends within the same 0.25 m, not within 0.25 s
    // (3.75 m at this speed).
    let r = drive(
        "[[events]]\nname = \"k\"\ntrigger = { time_s = 0.0 }\naction = { keep = { time_gap_s = 1.5, to = \"other\", continuous = false } }\n",
        40.0, 0.0, 15.0, 60.0, |_| 15.0,
    );
    let ended = ended_at(&r);
    let at = |n: u64| r.me[n as usize];
    let (me, v, _) = at(ended);
    let g = gap(me, other(ended));
    assert!(
        (g - 1.5 * v).abs() < KEEP_REACHED_M + 0.05,
        "ended at {g} m, {v} m/s"
    );
}

#[test]
fn a_jerk_limit_bounds_the_change_of_acceleration_and_a_speed_action_replaces_the_gap() {
    let r = drive(
        "[[events]]\nname = \"k\"\ntrigger = { time_s = 0.0 }\naction = { keep = { gap_m = 20.0, to = \"other\", max_jerk_mps3 = 1.0, max_accel_mps2 = 3.0 } }\n\
         [[events]]\nname = \"s\"\ntrigger = { time_s = 30.0 }\naction = { speed_mps = 5.0, rate_mps2 = 2.0 }\n",
        60.0, 0.0, 15.0, 60.0, |_| 15.0,
    );
    // The acceleration asked passes through f32 (`SpeedOverride`).
    let step = 1.0 / 120.0 + 1e-6;
    for w in r.me[..30 * 120].windows(2) {
        assert!((w[1].2 - w[0].2).abs() <= step, "{:?}", w);
        assert!(w[1].2 <= 3.0 + 1e-6);
    }
    // Slower under the jerk limit (its lag the 3 s the acceleration takes to build), nearly
    // settled by 30 s, never closer than asked by more than a few centimetres.
    let gaps: Vec<f64> = (0..30 * 120)
        .map(|n| gap(r.me[n].0, 60.0 + 15.0 * (n + 1) as f64 / 120.0))
        .collect();
    let last = gaps[gaps.len() - 1];
    let least = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((last - 20.0).abs() < 2.0, "{last}");
    assert!(least > 19.9, "{least}");
    // At 30 s the speed action ends the gap and slows the vehicle to 5 m/s at 2 m/s².
    assert!(
        r.log.contains(&(3600, "k".into(), FiredKind::Ended)),
        "{:?}",
        r.log
    );
    assert!(
        (r.me.last().unwrap().1 - 5.0).abs() < 1e-6,
        "{:?} {:?}",
        r.me.last(),
        r.log
    );
}

#[test]
fn malformed_kept_gaps_are_refused_naming_their_field() {
    refused_naming(vec![
        (
            one(OK_TRIGGER, "action = { keep = { to = \"other\" } }"),
            "events[1].action.keep",
        ),
        (
            one(
                OK_TRIGGER,
                "action = { keep = { to = \"other\", gap_m = 5.0, time_gap_s = 1.0 } }",
            ),
            "events[1].action.keep",
        ),
        (
            one(
                OK_TRIGGER,
                "action = { keep = { to = \" \", gap_m = 5.0 } }",
            ),
            "events[1].action.keep.to",
        ),
        (
            one(
                OK_TRIGGER,
                "action = { keep = { to = \"other\", gap_m = -5.0 } }",
            ),
            "events[1].action.keep.gap_m",
        ),
        (
            one(
                OK_TRIGGER,
                "action = { keep = { to = \"other\", gap_m = 5.0, max_jerk_mps3 = 0.0 } }",
            ),
            "events[1].action.keep.max_jerk_mps3",
        ),
        (
            one(
                OK_TRIGGER,
                "action = { keep = { to = \"other\", gap_m = 5.0 }, shape = \"linear\" }",
            ),
            "events[1].action.shape",
        ),
        (
            one(
                OK_TRIGGER,
                "action = { keep = { to = \"other\", gap_m = 5.0 }, stop = true }",
            ),
            "events[1].action",
        ),
    ]);
    // A vehicle the scenario does not have is refused when the engine is built.
    let text = one(
        OK_TRIGGER,
        "action = { keep = { to = \"nobody\", gap_m = 5.0 } }",
    );
    let err = Events::new(&script(&text), &["me", "other"], LANES).unwrap_err();
    assert!(
        err.to_string().contains("events[1].action.keep.to"),
        "{err}"
    );
}
