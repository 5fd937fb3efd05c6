//! Traffic in scenario files: `[[actors]]`, `route.lanes`, `lead.lane` and the events are
//! checked like every other field. A bad one is refused in one line naming the file, line
//! and field; a good one plans, with its vehicles where it says.
//! Run with `cargo test --release -p sim-core --test traffic_files`.

use sim_core::{Plan, Scenario};
use std::path::{Path, PathBuf};

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

/// `nist-grounds` on a road of two lanes each way, with a van ahead in the next lane
/// that cuts in, and a car standing further on in the lead's lane.
fn traffic_text() -> String {
    let base = std::fs::read_to_string(scenarios_dir().join("nist-grounds.toml")).unwrap();
    let base = base.replace("[route]\n", "[route]\nlanes = 2\n");
    format!(
        "{base}
[[actors]]
name = \"van\"
kind = \"van\"
lane = 2
start = {{ gap_m = 3.0, ahead_of = \"chase\" }}
speed_profile = [[0.0, 5.0]]

[[actors.events]]
name = \"cut-in\"
trigger = {{ time_s = 4.0 }}
action = {{ lane = 1, duration_s = 2.5, shape = \"sinusoidal\" }}

[[actors]]
name = \"parked\"
kind = \"sedan\"
lane = 1
start = {{ station_m = 300.0 }}
speed_profile = [[0.0, 0.0]]
"
    )
}

/// Loads and plans `text` as `scenarios/bad.toml`, as `carfollow check` does.
fn load(text: &str) -> Result<Plan, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    std::fs::create_dir(dir.path().join("targets")).unwrap();
    std::fs::copy(
        scenarios_dir().join("targets/nist-ten-segment.toml"),
        dir.path().join("targets/nist-ten-segment.toml"),
    )
    .unwrap();
    Plan::load(&path, &[]).map_err(|e| {
        let e = e.to_string().replace(&dir.path().display().to_string(), "");
        assert!(!e.contains('\n'), "one line: {e}");
        e
    })
}

/// 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle")
        + 1
}

/// The error of the text with `from` replaced by `to`; it must name the line with `to`
/// (or `at` when given) and `field`.
fn refused(from: &str, to: &str, field: &str, at: Option<&str>) -> String {
    let text = traffic_text().replacen(from, to, 1);
    assert_ne!(text, traffic_text(), "{from:?} is in the text");
    let Err(e) = load(&text) else {
        panic!("accepted: {to}");
    };
    let line = line_of(&text, at.unwrap_or(to));
    assert!(
        e.starts_with(&format!("/bad.toml:{line}:")),
        "line {line} expected: {e}"
    );
    assert!(e.contains(&format!("`{field}`")), "{field} expected: {e}");
    e
}

#[test]
fn a_traffic_scenario_plans_with_every_vehicle_listed() {
    let plan = load(&traffic_text()).unwrap();
    let s: &Scenario = plan.scenario();
    assert!(s.has_traffic());
    assert_eq!(s.route.lanes, 2);
    assert_eq!(s.actors.len(), 2);
    let names: Vec<&str> = plan
        .vehicles()
        .unwrap()
        .members()
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    assert_eq!(names, ["chase", "lead", "van", "parked"]);
    // The van starts 3 m ahead of the chase's front bumper, beside it in lane 2.
    let van = &s.actors[0];
    let chase = vehicle::VehicleParams::hmmwv_m998();
    let params = sim_core::kind_params(van.kind);
    let gap = van.start_m + f64::from(params.rear_bumper_x_m())
        - (plan.chase_start_m() + f64::from(chase.front_bumper_x_m()));
    assert!((gap - 3.0).abs() < 1e-9, "{gap}");
}

#[test]
fn a_trigger_naming_no_vehicle_is_refused() {
    let e = refused(
        "trigger = { time_s = 4.0 }",
        "trigger = { gap_m = 4.0, to = \"bus\" }",
        "actors[0].events[0].trigger.to",
        None,
    );
    assert!(
        e.contains("\"bus\"") && e.contains("chase, lead, van, parked"),
        "{e}"
    );
}

#[test]
fn a_lane_off_the_road_is_refused() {
    let e = refused(
        "lane = 2\nstart",
        "lane = 3\nstart",
        "actors[0].lane",
        Some("lane = 3"),
    );
    assert!(e.contains("1–2"), "{e}");
    refused(
        "lanes = 2\n",
        "lanes = 5\n",
        "route.lanes",
        Some("lanes = 5"),
    );
}

#[test]
fn a_lane_change_to_a_lane_that_does_not_exist_is_refused() {
    let e = refused(
        "action = { lane = 1,",
        "action = { lane = 4,",
        "actors[0].events[0].action.lane",
        None,
    );
    assert!(e.contains("lanes 1–2"), "{e}");
}

#[test]
fn overlapping_starts_are_refused() {
    // The parked car moved onto the lead, which starts at 30 m in lane 1.
    let e = refused(
        "start = { station_m = 300.0 }",
        "start = { station_m = 31.0 }",
        "actors[1].start",
        None,
    );
    assert!(e.contains("`lead`"), "{e}");
}

#[test]
fn bad_kinds_names_starts_and_events_are_refused() {
    let e = refused("kind = \"van\"", "kind = \"bus\"", "actors[0].kind", None);
    assert!(
        e.contains("\"sedan\", \"hatchback\", \"van\", \"truck\""),
        "{e}"
    );
    refused(
        "name = \"parked\"",
        "name = \"lead\"",
        "actors[1].name",
        None,
    );
    refused(
        "start = { gap_m = 3.0, ahead_of = \"chase\" }",
        "start = { gap_m = 3.0 }",
        "actors[0].start",
        None,
    );
    refused(
        "ahead_of = \"chase\"",
        "ahead_of = \"parked\"",
        "actors[0].start.ahead_of",
        None,
    );
    refused(
        "duration_s = 2.5, shape",
        "duration_s = -2.5, shape",
        "actors[0].events[0].action.duration_s",
        Some("duration_s = -2.5"),
    );
    refused(
        "start = { station_m = 300.0 }",
        "start = { station_m = 1e6 }",
        "actors[1].start",
        None,
    );
}

#[test]
fn a_scenario_without_traffic_resolves_as_before() {
    // No lanes, actors or events written: the resolved file has none of them, so that
    // `summary.json` of a scenario without traffic is unchanged.
    let s = Scenario::load(&scenarios_dir().join("nist-grounds.toml"), &[]).unwrap();
    assert!(!s.has_traffic());
    let resolved = s.resolved_json().to_string();
    for key in ["\"lanes\"", "\"actors\"", "\"events\"", "\"lane\""] {
        assert!(!resolved.contains(key), "{key} in {resolved}");
    }
}

#[test]
fn a_cruise_speed_without_lane_keeping_is_refused_saying_why() {
    let e = refused(
        "initial_gap_m = 10.0\n",
        "initial_gap_m = 10.0\ncontroller = { cruise_speed_mps = 12.0 }\n",
        "chase.controller.cruise_speed_mps",
        Some("cruise_speed_mps"),
    );
    assert!(e.contains("needs lane_keeping"), "{e}");
    // With lane keeping on, the same speed is taken.
    let text = traffic_text().replacen(
        "initial_gap_m = 10.0\n",
        "initial_gap_m = 10.0\ncontroller = { lane_keeping = true, cruise_speed_mps = 12.0 }\n",
        1,
    );
    load(&text).unwrap();
}
