//! Roads with a median and lanes of their own widths (`route.median_m`,
//! `route.lane_widths_m`): esmini's e6mini.xodr (MPL-2.0, `tests/data/opendrive/`) is read
//! as its file says; vehicles start, follow and change lanes on each lane's own centre, and
//! the vehicle in the chase's path is found in its own lane; `check` refuses what is wrong
//! in one line naming the file, the line and the field.
//!
//! Run: `cargo test --release -p sim-core --test road_lanes`

use sim_core::opendrive;
use sim_core::{ClosedLoop, Plan, Scenario};
use sim_render::Backend;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/opendrive")
        .join(name)
}

fn target() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/targets/nist-ten-segment.toml")
        .display()
        .to_string()
}

fn parse(text: &str) -> Result<Scenario, sim_core::ScenarioError> {
    Scenario::from_file_text(text, Path::new("/tmp/lanes.toml"), &[])
}

/// The `a` of the `<width>` of lane `id` in e6mini's text, read with no help from the
/// importer.
fn width_in_file(text: &str, id: i32) -> f64 {
    let at = text
        .find(&format!("<lane id=\"{id}\" "))
        .unwrap_or_else(|| panic!("lane {id}"));
    let width = &text[at..][text[at..].find("<width ").unwrap()..];
    let a = &width[width.find(" a=\"").unwrap() + 4..];
    a[..a.find('"').unwrap()].parse().unwrap()
}

#[test]
fn e6minis_lanes_are_read_as_the_file_gives_them() {
    let text = std::fs::read_to_string(data("e6mini.xodr")).unwrap();
    let file = opendrive::load(&data("e6mini.xodr")).unwrap();
    let road = opendrive::import(&file, None, |_| None).unwrap_or_else(|e| panic!("{e}"));
    // Right side: −1 border (the median), −2..−4 driving, then stop and border lanes.
    assert_eq!(road.lanes, 3);
    assert_eq!(road.median_m, width_in_file(&text, -1));
    assert_eq!(road.median_m, 2.6);
    assert_eq!(road.inner_lanes, 1);
    let widths: Vec<f64> = (2..=4).map(|k| width_in_file(&text, -k)).collect();
    assert_eq!(road.lane_widths_m, widths);
    assert_eq!(road.lane_widths_m, vec![3.65, 3.5, 3.9]);
    assert_eq!(road.lane_width_m, 3.65);
    // The left mirrors the right, lane for lane.
    for k in 1..=4 {
        assert_eq!(width_in_file(&text, k), width_in_file(&text, -k));
    }
    // A scenario on it plans, with the route carrying the lanes.
    let s = parse(&format!(
        "name = \"e6\"\nduration_s = 1.0\n[route]\nopendrive = {{ file = {:?} }}\n\
         [lead]\nstart_m = 30.0\nlane = 3\ninitial_speed_mps = 5.0\n\
         speed_profile = [[0.0, 5.0]]\n[tracker]\ntarget = {:?}\n",
        data("e6mini.xodr").display().to_string(),
        target()
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.route.median_m, 2.6);
    assert_eq!(s.route.lane_widths_m, vec![3.65, 3.5, 3.9]);
    Plan::new(&s).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_median_that_differs_left_and_right_is_refused_naming_the_section() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(data("e6mini.xodr")).unwrap();
    // Lane 1 (the left's median) narrower than lane −1.
    let at = text.find("<lane id=\"1\" ").unwrap();
    let w = at + text[at..].find("a=\"2.6000000000000001e+00\"").unwrap();
    let bad = format!(
        "{}a=\"2.0\"{}",
        &text[..w],
        &text[w + "a=\"2.6000000000000001e+00\"".len()..]
    );
    let path = dir.path().join("e6-median.xodr");
    std::fs::write(&path, &bad).unwrap();
    let file = opendrive::load(&path).unwrap();
    let err = opendrive::import(&file, None, |_| None)
        .unwrap_err()
        .to_string();
    let line = bad
        .lines()
        .position(|l| l.contains("<laneSection"))
        .unwrap()
        + 1;
    assert!(err.contains(&format!("e6-median.xodr:{line}: ")), "{err}");
    assert!(err.contains("<laneSection"), "{err}");
    assert!(
        err.contains("differ from the right's") && err.contains("beyond 2 m"),
        "{err}"
    );
    assert!(!err.contains('\n'), "{err}");
}

/// A straight road of three lanes (3.65, 3.5, 3.9 m) beyond a 2.6 m median, the lead in
/// lane 1 60 m ahead of the start, a van in lane 2 and a sedan in lane 3 beside it, the
/// sedan moving to lane 2 after 1 s (over 2 s), `extra` appended.
fn divided(extra: &str) -> String {
    format!(
        r#"name = "divided"
duration_s = 7.0
[route]
lanes = 3
lane_widths_m = [3.65, 3.5, 3.9]
median_m = 2.6
segments = [{{ straight_m = 600.0 }}]
[lead]
start_m = 60.0
initial_speed_mps = 10.0
speed_profile = [[0.0, 10.0]]
[chase]
initial_gap_m = 20.0
controller = {{ lane_keeping = true }}
[tracker]
target = {target:?}
[[actors]]
name = "van"
kind = "van"
lane = 2
start = {{ station_m = 40.0 }}
initial_speed_mps = 10.0
speed_profile = [[0.0, 10.0]]
[[actors]]
name = "sedan"
kind = "sedan"
lane = 3
start = {{ station_m = 120.0 }}
initial_speed_mps = 10.0
speed_profile = [[0.0, 10.0]]
[[actors.events]]
name = "over"
trigger = {{ time_s = 1.0 }}
action = {{ lane = 2, duration_s = 2.0 }}
{extra}"#,
        target = target()
    )
}

/// Lane k's centre on the road of [`divided`]: the median, the lanes inside, half its own.
fn centre(lane: usize) -> f64 {
    let widths = [3.65, 3.5, 3.9];
    2.6 + widths[..lane - 1].iter().sum::<f64>() + 0.5 * widths[lane - 1]
}

#[test]
fn vehicles_start_follow_and_change_lanes_on_each_lanes_centre() {
    let s = parse(&divided("")).unwrap_or_else(|e| panic!("{e}"));
    for k in 1..=3u32 {
        assert!((s.route.lane_centre_m(k) - centre(k as usize)).abs() < 1e-12);
    }
    let plan = Plan::new(&s).unwrap_or_else(|e| panic!("{e}"));
    // The route heads +x from the origin: a vehicle's z is its offset right of the centre
    // line.
    let (chase, lead) = plan.start_poses();
    for pose in std::iter::once(chase).chain(lead) {
        let z = pose.translation.z as f64;
        assert!((z - centre(1)).abs() < 0.01, "{z} vs {}", centre(1));
    }
    let backend = Backend::choose(None).unwrap();
    let mut looped = ClosedLoop::new(plan, backend, false).unwrap();
    let mut frames = Vec::new();
    while let Some(out) = looped.step().unwrap() {
        frames.push(out.record.traffic.clone().expect("traffic"));
    }
    let offset = |frame: &sim_core::TrafficFrame, name: &str| {
        frame
            .vehicles
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("{name}"))
            .xz[1]
    };
    let first = &frames[0];
    for (name, lane) in [("chase", 1), ("lead", 1), ("van", 2), ("sedan", 3)] {
        let z = offset(first, name);
        assert!(
            (z - centre(lane)).abs() < 0.02,
            "{name}: {z} vs {}",
            centre(lane)
        );
    }
    // The chase's path holds the lead (lane 1), not the van beside it in lane 2.
    assert_eq!(first.path_vehicle.as_deref(), Some("lead"));
    // Pure pursuit holds each lane's centre; the sedan has moved to lane 2's.
    let last = frames.last().unwrap();
    for (name, lane) in [("chase", 1), ("lead", 1), ("van", 2), ("sedan", 2)] {
        let z = offset(last, name);
        assert!(
            (z - centre(lane)).abs() < 0.1,
            "{name}: {z} vs {}",
            centre(lane)
        );
    }
}

#[test]
fn check_refuses_lane_widths_and_medians_it_cannot_draw() {
    let base = divided("");
    let cases = [
        (
            "lane_width_m too",
            base.replace("median_m = 2.6", "median_m = 2.6\nlane_width_m = 3.5"),
            "route.lane_widths_m",
            "cannot be given with `route.lane_width_m`",
        ),
        (
            "count",
            base.replace("[3.65, 3.5, 3.9]", "[3.65, 3.5]"),
            "route.lane_widths_m",
            "one width per lane",
        ),
        (
            "narrow",
            base.replace("[3.65, 3.5, 3.9]", "[3.65, 1.5, 3.9]"),
            "route.lane_widths_m",
            "lane 2's width must be 2–6 metres",
        ),
        (
            "wide median",
            base.replace("median_m = 2.6", "median_m = 12.0"),
            "route.median_m",
            "must be 0–10 metres",
        ),
        (
            "negative median",
            base.replace("median_m = 2.6", "median_m = -1.0"),
            "route.median_m",
            "must be 0–10 metres",
        ),
    ];
    for (what, text, field, reason) in cases {
        let err = parse(&text)
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"))
            .to_string();
        assert!(!err.contains('\n'), "{what}: {err}");
        assert!(err.contains("/tmp/lanes.toml:"), "{what}: {err}");
        assert!(err.contains(field) && err.contains(reason), "{what}: {err}");
    }
    // With a road file, its lanes give the median and the widths.
    let od = format!(
        "name = \"e6\"\nduration_s = 1.0\n[route]\nopendrive = {{ file = {:?} }}\nmedian_m = 1.0\n\
         [lead]\nstart_m = 30.0\nspeed_profile = [[0.0, 5.0]]\n[tracker]\ntarget = {:?}\n",
        data("e6mini.xodr").display().to_string(),
        target()
    );
    let err = parse(&od).err().unwrap().to_string();
    assert!(
        err.contains("route.median_m") && err.contains("road file's lanes"),
        "{err}"
    );
}
