//! Vehicles that start and drive off their lane's centre (`[lead] offset_m`, `[[actors]]
//! offset_m`, positive to the left): Euro NCAP's car-to-car rear tests offset the target
//! for their overlaps. The lead stands or drives that far from its lane's centre, as the
//! camera's truth shows; an actor passes a point off its lane's centre, as a trigger on
//! reaching it shows; an offset beyond half the lane is refused in one line. Run with
//! `cargo test --release -p sim --test cli_offsets`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios")
}

fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .output()
        .unwrap()
}

/// Runs `scenario` into `out` with `set`; the rows of its `frames.csv`, by column.
fn frames(
    scenario: &Path,
    out: &Path,
    set: &[&str],
) -> Vec<std::collections::BTreeMap<String, String>> {
    let mut args = vec![
        "run",
        scenario.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    for s in set {
        args.extend(["--set", s]);
    }
    let o = carfollow(&args);
    assert!(
        matches!(o.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let mut reader = csv::Reader::from_path(out.join("frames.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            header
                .iter()
                .zip(r.iter())
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

fn num(row: &std::collections::BTreeMap<String, String>, column: &str) -> f64 {
    row[column].parse().unwrap()
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
    for (a, b) in centred.iter().zip(&offset).take(20) {
        let moved = num(b, "true_lateral_m") - num(a, "true_lateral_m");
        assert!(
            (moved + 0.9).abs() < 0.05,
            "frame {}: moved {moved} m",
            a["frame"]
        );
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
    for (a, b) in centred.iter().zip(&offset).skip(75) {
        let moved = num(b, "true_lateral_m") - num(a, "true_lateral_m");
        assert!(
            (moved - 0.6).abs() < 0.1,
            "frame {}: moved {moved} m",
            a["frame"]
        );
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
            .iter()
            .any(|r| r["event"].contains("van/passed:started"))
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
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{set}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
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
