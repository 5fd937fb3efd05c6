//! `WorldPosition`s: a vehicle placed by the file's own x, y and heading starts where the
//! same place given as a lane and station puts it (on the straight and on the arc of
//! `two-lanes.xodr`, the arc's points from the file's own numbers), a point off its lane's
//! centre starts there (its offset), one turned from the road along it with a warning, a reach
//! condition takes one, and a point off the road, off its lanes on the right or facing
//! against it is refused at its line.
//!
//! `cargo test --release -p sim-core --test openscenario_world`.

use sim_core::openscenario::{import, ImportOptions, Imported, OscError};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/openscenario")
}

/// `file` (in the test data) with each `(from, to)` replaced, imported from a copy in a
/// temporary folder beside the road and catalog.
fn imported(file: &str, edits: &[(&str, String)]) -> (Result<Imported, OscError>, String) {
    let dir = tempfile::tempdir().unwrap();
    for name in ["two-lanes.xodr", "catalogs/VehicleCatalog.xosc"] {
        let to = dir.path().join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(data().join(name), to).unwrap();
    }
    let mut text = std::fs::read_to_string(data().join(file)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from} not in {file}");
        text = text.replace(from, to);
    }
    let path = dir.path().join("world.xosc");
    std::fs::write(&path, &text).unwrap();
    (import(&path, &ImportOptions::default()), text)
}

/// Whether two scenario texts hold the same fields, numbers equal to within `tol`.
fn same(a: &toml::Value, b: &toml::Value, tol: f64, at: &str) {
    use toml::Value::*;
    match (a, b) {
        (Table(x), Table(y)) => {
            let keys = |t: &toml::Table| t.keys().cloned().collect::<Vec<_>>();
            assert_eq!(keys(x), keys(y), "{at}");
            for (k, v) in x {
                same(v, &y[k], tol, &format!("{at}.{k}"));
            }
        }
        (Array(x), Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (k, (v, w)) in x.iter().zip(y).enumerate() {
                same(v, w, tol, &format!("{at}[{k}]"));
            }
        }
        (Float(x), Float(y)) => assert!((x - y).abs() <= tol, "{at}: {x} against {y}"),
        (Float(x), Integer(y)) | (Integer(y), Float(x)) => {
            assert!((x - *y as f64).abs() <= tol, "{at}: {x} against {y}")
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

fn value(i: &Imported) -> toml::Value {
    toml::from_str(&i.text).unwrap()
}

const EGO: &str = "<LanePosition roadId=\"1\" laneId=\"-1\" offset=\"0\" s=\"20\"/>";
const VAN: &str = "<LanePosition roadId=\"1\" laneId=\"-2\" offset=\"0\" s=\"80\"/>";

fn world(x: f64, y: f64, h: f64) -> String {
    format!("<WorldPosition x=\"{x}\" y=\"{y}\" z=\"0\" h=\"{h}\"/>")
}

/// The point `t` to the left of station `s` on `two-lanes.xodr`'s arc (from s = 500, at
/// its start point and heading, curvature 0.002), and the heading there, from the file's
/// own numbers.
fn on_arc(s: f64, t: f64) -> (f64, f64, f64) {
    let (x0, y0, h0, k) = (499.900046285613, 3.330953138375, 0.1_f64, 0.002);
    let r = 1.0 / k;
    let (cx, cy) = (x0 - r * h0.sin(), y0 + r * h0.cos());
    let h = h0 + (s - 500.0) * k;
    (cx + (r - t) * h.sin(), cy - (r - t) * h.cos(), h)
}

#[test]
fn a_world_position_starts_a_vehicle_where_its_lane_and_station_do() {
    let (lanes, _) = imported("cut-in.xosc", &[]);
    let lanes = lanes.unwrap();
    let (worlds, _) = imported(
        "cut-in.xosc",
        &[
            (EGO, world(20.0, -1.75, 0.0)),
            (VAN, world(80.0, -5.25, 0.0)),
        ],
    );
    let worlds = worlds.unwrap();
    same(&value(&lanes), &value(&worlds), 1e-6, "");
    assert_eq!(lanes.warnings, worlds.warnings);
    // On the arc, 100 m into it, in lane −2.
    let (x, y, h) = on_arc(600.0, -5.25);
    let arc_lane = "<LanePosition roadId=\"1\" laneId=\"-2\" offset=\"0\" s=\"600\"/>".to_string();
    let (by_lane, _) = imported("cut-in.xosc", &[(VAN, arc_lane)]);
    let (by_world, _) = imported("cut-in.xosc", &[(VAN, world(x, y, h))]);
    same(
        &value(&by_lane.unwrap()),
        &value(&by_world.unwrap()),
        1e-6,
        "",
    );
}

#[test]
fn a_point_off_the_centre_is_placed_there_and_one_turned_along_the_road_with_a_warning() {
    let (lanes, _) = imported("cut-in.xosc", &[]);
    let mut lanes = value(&lanes.unwrap());
    let (off, text) = imported("cut-in.xosc", &[(VAN, world(80.0, -5.65, 0.1))]);
    let off = off.unwrap();
    // 0.40 m right of lane 2's centre (t = −5.25 m): the van's offset, the rest as before.
    lanes["actors"][0]
        .as_table_mut()
        .unwrap()
        .insert("offset_m".into(), toml::Value::Float(-0.4));
    same(&lanes, &value(&off), 1e-6, "");
    let line = 1 + text
        .lines()
        .position(|l| l.contains("WorldPosition"))
        .unwrap();
    let warning = off
        .warnings
        .iter()
        .find(|w| w.contains("WorldPosition"))
        .unwrap_or_else(|| panic!("no warning: {:?}", off.warnings));
    assert!(
        warning.starts_with(&format!("line {line}:"))
            && warning.contains("turned 5.7°")
            && !warning.contains("centre"),
        "{warning}"
    );
}

#[test]
fn a_reach_condition_takes_a_world_position() {
    let reach = "<LanePosition roadId=\"1\" laneId=\"-1\" offset=\"0\" s=\"150\"/>";
    let (lanes, _) = imported("reach-relative.xosc", &[]);
    let (worlds, _) = imported("reach-relative.xosc", &[(reach, world(150.0, -1.75, 0.0))]);
    same(&value(&lanes.unwrap()), &value(&worlds.unwrap()), 1e-6, "");
}

#[test]
fn a_world_position_off_the_road_its_lanes_or_its_direction_is_refused_at_its_line() {
    for (place, says) in [
        (
            world(-10.0, -1.75, 0.0),
            "before the start or past the end of road 1",
        ),
        (world(80.0, 1.75, 0.0), "is on no lane carfollow drives"),
        (world(80.0, -9.0, 0.0), "is on no lane carfollow drives"),
        (world(80.0, -5.25, 3.1), "faces against road 1"),
        ("<WorldPosition y=\"-5.25\"/>".to_string(), "x"),
    ] {
        let (result, text) = imported("cut-in.xosc", &[(VAN, place.clone())]);
        let line = 1 + text
            .lines()
            .position(|l| l.contains("WorldPosition"))
            .unwrap();
        let err = result.expect_err(&place).to_string();
        assert!(
            err.contains(&format!("world.xosc:{line}")) && err.contains(says),
            "{place}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
