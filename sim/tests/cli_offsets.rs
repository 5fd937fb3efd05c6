//! Vehicles that start and drive off their lane's centre (`[lead] offset_m`, `[[actors]]
//! offset_m`, positive to the left): Euro NCAP's car-to-car rear tests offset the target
//! for their overlaps. The lead stands or drives that far from its lane's centre, as the
//! camera's truth shows; an actor passes a point off its lane's centre, as a trigger on
//! reaching it shows; an offset beyond half the lane is refused in one line. Run with
//! `cargo test --release -p sim --test cli_offsets`.

mod osc_common;

use osc_common::{carfollow, frames_of, refusal, Frames};
use std::path::{Path, PathBuf};

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios")
}

/// `frames.csv` of `scenario` run into `out` with each of `set` as a `--set`.
fn frames(scenario: &Path, out: &Path, set: &[&str]) -> Frames {
    let extra: Vec<&str> = set.iter().flat_map(|s| ["--set", s]).collect();
    Frames::parse(&frames_of(scenario, out, &extra))
}

/// How far the truth's lateral position moved between two runs, frame by frame, m.
fn moved(a: &Frames, b: &Frames) -> Vec<f64> {
    let lateral =
        |f: &Frames| -> Vec<f64> { f.rows.iter().map(|r| f.num(r, "true_lateral_m")).collect() };
    lateral(b)
        .iter()
        .zip(lateral(a))
        .map(|(b, a)| b - a)
        .collect()
}

#[test]
fn the_lead_stands_and_drives_off_its_lanes_centre() {
    let dir = tempfile::tempdir().unwrap();
    // Standing (`ncap-ccrs`, the target 60 m ahead): the truth's lateral position moves by
    // the offset, to the camera's left (negative), and stays.
    let ccrs = scenarios().join("ncap-ccrs.toml");
    let centred = frames(&ccrs, &dir.path().join("c0"), &["duration_s=2"]);
    let offset = frames(
        &ccrs,
        &dir.path().join("c1"),
        &["duration_s=2", "lead.offset_m=0.9"],
    );
    for (k, m) in moved(&centred, &offset).iter().enumerate().take(20) {
        assert!((m + 0.9).abs() < 0.05, "frame {k}: moved {m} m");
    }
    // Driving (`cut-in` before its cut-in, the chase keeping its lane's centre): the lead
    // keeps the offset.
    let cut_in = scenarios().join("cut-in.toml");
    let set = ["duration_s=10"];
    let centred = frames(&cut_in, &dir.path().join("d0"), &set);
    let offset = frames(
        &cut_in,
        &dir.path().join("d1"),
        &[set[0], "lead.offset_m=-0.6"],
    );
    for (k, m) in moved(&centred, &offset).iter().enumerate().skip(75) {
        assert!((m - 0.6).abs() < 0.1, "frame {k}: moved {m} m");
    }
}

#[test]
fn an_actor_passes_a_point_off_its_lanes_centre() {
    let dir = tempfile::tempdir().unwrap();
    let root = scenarios();
    // The cut-in's van, watched passing 150 m along the road 0.8 m left of its lane's
    // centre (within 0.3 m), before its cut-in at 11.4 s.
    let text = std::fs::read_to_string(root.join("cut-in.toml"))
        .unwrap()
        .replace("target = \"targets/", &format!("target = \"{}/targets/", root.display()))
        + "\n[[actors.events]]\nname = \"passed\"\n\
           trigger = { reach = { station_m = 150.0, lane = 2, offset_m = 0.8, tolerance_m = 0.3 } }\n\
           action = { speed_mps = 9.7, rate_mps2 = 1.0 }\n";
    let file = dir.path().join("offset-van.toml");
    std::fs::write(&file, text).unwrap();
    let passed = |set: &[&str]| {
        let out = dir.path().join(format!("run{}", set.len()));
        frames(&file, &out, set)
            .logged("van/passed:started")
            .is_some()
    };
    assert!(!passed(&["duration_s=10"]), "passed on its lane's centre");
    assert!(
        passed(&["duration_s=10", "actors.0.offset_m=0.8"]),
        "not passed 0.8 m left"
    );
}

#[test]
fn an_offset_beyond_half_the_lane_is_refused_in_one_line() {
    let ccrs = scenarios().join("ncap-ccrs.toml");
    for (set, field) in [
        ("lead.offset_m=1.8", "lead.offset_m"),
        ("lead.offset_m=nan", "lead.offset_m"),
    ] {
        let o = carfollow(&["check", ccrs.to_str().unwrap(), "--set", set]);
        let e = refusal(&o, set);
        assert!(e.contains(field) && e.contains("half its lane"), "{e}");
    }
    let cut_in = scenarios().join("cut-in.toml");
    let o = carfollow(&[
        "check",
        cut_in.to_str().unwrap(),
        "--set",
        "actors.0.offset_m=-2",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("actors[0].offset_m") && e.contains("half its lane"),
        "{e}"
    );
}

/// Offsets that put two vehicles' bodies side by side in each other across a lane line are
/// refused as overlapping starts are, in one line; apart, they run.
#[test]
fn offset_bodies_that_overlap_across_lanes_are_refused() {
    let cut_in = scenarios().join("cut-in.toml");
    let check = |set: &[&str]| {
        let mut args = vec!["check", cut_in.to_str().unwrap()];
        for s in set {
            args.extend(["--set", s]);
        }
        carfollow(&args)
    };
    // The van in lane 2 level with the lead in lane 1.
    let level = "actors.0.start.gap_m=30";
    assert_eq!(check(&[level]).status.code(), Some(0));
    assert_eq!(
        check(&[level, "actors.0.offset_m=0.2"]).status.code(),
        Some(0)
    );
    for offsets in [
        ["actors.0.offset_m=1.7", "lead.offset_m=0"],
        ["actors.0.offset_m=1.0", "lead.offset_m=-1.0"],
    ] {
        let e = refusal(&check(&[level, offsets[0], offsets[1]]), &offsets.join(" "));
        assert!(
            e.contains("actors[0].start") && e.contains("puts its body against `lead`'s"),
            "{e}"
        );
    }
}

/// An actor may start on a lane of the oncoming side, driving with the road, as a car
/// overtaking on a two-lane road does (OpenSCENARIO's ALKS tests place the car that cuts
/// in there): `cut-in`'s van, 3.5 m left of lane 1's centre (the oncoming lane 1), is out
/// of the chase's path until its cut-in, which brings it in as from lane 2. Offsets that
/// put it on neither side's lanes are refused in one line, naming both ranges.
#[test]
fn an_actor_drives_with_the_road_on_the_oncoming_side() {
    let cut_in = scenarios().join("cut-in.toml");
    let dir = tempfile::tempdir().unwrap();
    let set = ["duration_s=16"];
    let right = frames(&cut_in, &dir.path().join("right"), &set);
    let left = frames(
        &cut_in,
        &dir.path().join("left"),
        &["duration_s=16", "actors.0.lane=1", "actors.0.offset_m=3.5"],
    );
    let entered = |f: &Frames| {
        let col = f.header.iter().position(|c| c == "path_vehicle").unwrap();
        f.rows
            .iter()
            .position(|r| r[col] == "van")
            .map(|i| f.num(&f.rows[i], "t_s"))
    };
    let (from_right, from_left) = (entered(&right).unwrap(), entered(&left).unwrap());
    // The cut-in starts at the same gap and crosses the same width either way.
    assert!(
        (from_right - from_left).abs() < 0.3,
        "in the path at {from_right} s from lane 2, {from_left} s from the oncoming side"
    );
    assert!(from_left > 11.0, "in the path at {from_left} s");
    for (value, says) in [("9", "1.75–8.75 m"), ("-2", "half its lane")] {
        let set = format!("actors.0.offset_m={value}");
        let o = carfollow(&[
            "check",
            cut_in.to_str().unwrap(),
            "--set",
            "actors.0.lane=1",
            "--set",
            &set,
        ]);
        let e = refusal(&o, &set);
        assert!(e.contains("actors[0].offset_m") && e.contains(says), "{e}");
    }
}
