//! Synthetic traffic for the event engine's tests: a script from TOML, a car at a
//! station, and a run of an engine over a traffic view.

use vehicle::*;

pub const LANES: Lanes = Lanes {
    width_m: 3.5,
    count: 3,
    route_lane: 1,
    widths_m: None,
};

pub fn script(toml_text: &str) -> EventScript {
    #[derive(serde::Deserialize)]
    struct File {
        events: EventScript,
    }
    toml::from_str::<File>(toml_text)
        .unwrap_or_else(|e| panic!("{e}"))
        .events
}

/// A vehicle at `station_m` with its bumpers 1 m behind and 4 m ahead of it.
pub fn car(station_m: f64, speed_mps: f64) -> VehicleView {
    VehicleView {
        station_m,
        left_offset_m: 0.0,
        speed_mps,
        front_m: station_m + 4.0,
        rear_m: station_m - 1.0,
        touching: 0,
    }
}

/// Runs `events` (vehicle 0 is "me", 1 is "other") for `steps`, the traffic at each step
/// from `view`; every event fired.
pub fn run(
    events: &mut Events,
    steps: u64,
    view: impl Fn(f64) -> [VehicleView; 2],
) -> Vec<(u64, String, FiredKind)> {
    let mut log = Vec::new();
    for n in 0..steps {
        let now = Step(n);
        for f in events.update(now, &view(now.seconds()), 0) {
            assert_eq!(f.step, now);
            log.push((n, f.name, f.kind));
        }
    }
    log
}

pub fn engine(toml_text: &str) -> Events {
    Events::new(&script(toml_text), &["me", "other"], LANES).unwrap()
}

/// The step each event first started at, by name.
pub fn first_start(log: &[(u64, String, FiredKind)], name: &str) -> Option<u64> {
    log.iter()
        .find(|(_, n, k)| n == name && *k == FiredKind::Started)
        .map(|e| e.0)
}

pub const OK_TRIGGER: &str = "trigger = { time_s = 1.0 }";
pub const OK_ACTION: &str = "action = { speed_mps = 5.0, rate_mps2 = 1.0 }";

/// A script of a good event "a" and an event "b" with `trigger` and `action`.
pub fn one(trigger: &str, action: &str) -> String {
    format!(
        "[[events]]\nname = \"a\"\n{OK_TRIGGER}\n{OK_ACTION}\n\
         [[events]]\nname = \"b\"\n{trigger}\n{action}\n"
    )
}

/// Each case's text is refused, naming its field; none panics.
pub fn refused_naming(cases: Vec<(String, &str)>) {
    for (text, field) in cases {
        let err = script(&text).validate().unwrap_err();
        match &err {
            VehicleError::InvalidEvent { field: f, .. } => assert_eq!(f, field, "{text}"),
            other => panic!("{text}: {other:?}"),
        }
        println!("{err}");
    }
}
