//! A scenario without a lead: the chase starts at `chase.start_m` in `chase.lane`, cruises
//! with its tracker searching its path, and follows what it finds. What such a scenario
//! needs is refused in one line naming the field; the lead is neither placed nor drawn;
//! an OpenSCENARIO file with no vehicle ahead of its ego imports so (esmini's own
//! `cut-in.xosc`), runs bit for bit as its imported TOML, and exports and imports back with
//! no lead. Run with `cargo test --release -p sim --test cli_no_lead`.

mod osc_common;

use osc_common::*;
use std::path::{Path, PathBuf};

/// The library's scenario without a lead.
fn stopped_car() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/stopped-car-ahead.toml")
}

/// `stopped-car-ahead.toml` with its text changed by `edit`, written in `dir` beside a copy
/// of its targets (its `tracker.target` is relative to the file).
fn mutant(dir: &Path, edit: impl Fn(&str) -> String) -> PathBuf {
    let text = std::fs::read_to_string(stopped_car()).unwrap();
    let edited = edit(&text);
    assert_ne!(edited, text, "the edit changed nothing");
    let targets = dir.join("targets");
    std::fs::create_dir_all(&targets).unwrap();
    let from = stopped_car().parent().unwrap().join("targets");
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, targets.join(path.file_name().unwrap())).unwrap();
    }
    let path = dir.join("mutant.toml");
    std::fs::write(&path, edited).unwrap();
    path
}

/// An edit of the scenario's text.
type Edit<'a> = &'a dyn Fn(&str) -> String;

#[test]
fn what_a_start_without_a_lead_needs_is_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let lead = "[lead]\nstart_m = 60.0\nspeed_profile = [[0.0, 10.0]]\n\n[chase]";
    let cases: [(&str, Edit, &str); 7] = [
        (
            "no start",
            &|t| t.replace("start_m = 20.0\n", ""),
            "`chase.start_m` is needed in a scenario without [lead]",
        ),
        (
            "a gap to no lead",
            &|t| t.replace("start_m = 20.0\n", "start_m = 20.0\ninitial_gap_m = 10.0\n"),
            "`chase.initial_gap_m`",
        ),
        (
            "no cruise speed",
            &|t| t.replace(", cruise_speed_mps = 13.9", ""),
            "`chase.controller.cruise_speed_mps` is needed",
        ),
        (
            "no lane keeping",
            &|t| t.replace("lane_keeping = true", "lane_keeping = false"),
            "`chase.controller.lane_keeping`",
        ),
        (
            "placed on a target",
            &|t| t.replace("start = \"search\"\n", ""),
            "`tracker.start` must be \"search\"",
        ),
        (
            "a lane off the road",
            &|t| t.replace("lane = 1\nstart_at", "lane = 3\nstart_at"),
            "`chase.lane`",
        ),
        (
            "a start beside a lead",
            &|t| t.replace("[chase]", lead),
            "`chase.start_m` = 20: is only for a scenario without [lead]",
        ),
    ];
    for (what, edit, says) in cases {
        let file = mutant(dir.path(), edit);
        let o = carfollow(&["check", file.to_str().unwrap()]);
        let e = refusal(&o, what);
        assert!(e.contains("mutant.toml") && e.contains(says), "{what}: {e}");
    }
    // Cruising past the road's end is said as the chase's, never as a lead's.
    let file = mutant(dir.path(), |t| {
        t.replace("duration_s = 30.0", "duration_s = 60.0")
    });
    let o = carfollow(&["check", file.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(
        e.contains("would reach the route's end") && !e.contains("lead.speed_profile"),
        "{e}"
    );
    // An event about the lead names a vehicle the scenario does not have.
    let file = mutant(dir.path(), |t| {
        format!("{t}\n[[actors.events]]\nname = \"go\"\ntrigger = {{ gap_m = 30.0, to = \"lead\" }}\naction = {{ speed_mps = 20.0, duration_s = 2.0 }}\n")
    });
    let e = refusal(
        &carfollow(&["check", file.to_str().unwrap()]),
        "to the lead",
    );
    assert!(
        e.contains("actors[1].events[0]") && e.contains("lead"),
        "{e}"
    );
}

#[test]
fn without_a_lead_the_chase_finds_the_car_in_its_path_and_nothing_of_a_lead_is_written() {
    let out = tempfile::tempdir().unwrap();
    let csv = frames_of(&stopped_car(), out.path(), &["--set", "duration_s=14"]);
    let f = Frames::parse(&csv);
    let col = |name: &str| f.header.iter().position(|c| c == name).unwrap();
    // No lead: its columns are empty and its target nowhere, in every frame.
    for r in &f.rows {
        for name in [
            "lead_speed_mps",
            "lead_x_m",
            "lead_z_m",
            "true_range_m",
            "gap_m",
        ] {
            let v = &r[col(name)];
            assert!(v.is_empty() || v == "NaN", "{name} = {v}");
        }
    }
    // The standing car is found and held, the passing van never.
    let held: Vec<&str> = f
        .rows
        .iter()
        .map(|r| r[col("tracked_vehicle")].as_str())
        .filter(|v| !v.is_empty())
        .collect();
    assert!(held.len() > 50, "held in {} frames", held.len());
    assert!(held.iter().all(|v| *v == "standing"), "{held:?}");
    let summary = std::fs::read_to_string(out.path().join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&summary).unwrap();
    assert!(
        s["acquisition"]["range_m"].as_f64().unwrap() > 35.0,
        "{summary}"
    );
    assert!(s["collisions"].as_u64() == Some(0), "{summary}");
}

#[test]
fn esminis_cut_in_has_no_lead_and_runs_as_its_import() {
    let file = data().join("esmini/xosc/cut-in.xosc");
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("cut-in.toml");
    let text = import_to(&file, &toml);
    assert!(!text.contains("[lead]"), "{text}");
    assert!(
        text.contains("[chase]\nstart_m = 50.0\nlane = 2\n"),
        "{text}"
    );
    assert!(text.contains("start = \"search\""), "{text}");
    // The overtaker starts at the speed its act's first step sets: 1.2 × 108 km/h.
    assert!(text.contains("initial_speed_mps = 36.0"), "{text}");
    // Its headways are measured towards the vehicle ahead, as the standard's are.
    assert_eq!(text.matches("side = \"ahead\"").count(), 2, "{text}");
    let short = ["--set", "duration_s=12"];
    let a = frames_of(&file, &dir.path().join("xosc"), &short);
    let b = frames_of(&toml, &dir.path().join("toml"), &short);
    assert!(a == b, "the file and its import ran apart");
    // The overtaker cuts in ahead of the chase, and the chase holds it.
    let f = Frames::parse(&a);
    let cut_in = f.logged("OverTaker/CutInEvent:started").expect("cut in");
    assert!((4.0..8.0).contains(&cut_in), "cut in at {cut_in} s");
    let col = f
        .header
        .iter()
        .position(|c| c == "tracked_vehicle")
        .unwrap();
    assert!(f.rows.iter().any(|r| r[col] == "OverTaker"), "never held");
}

#[test]
fn no_lead_is_said_on_the_command_line_and_exported_for_the_importer() {
    // `--lead none` on a file whose ego has a vehicle ahead.
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("none.toml");
    let o = carfollow(&[
        "import",
        data().join("cut-in.xosc").to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
        "--lead",
        "none",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(
        !text.contains("[lead]") && text.contains("start_m ="),
        "{text}"
    );
    // Exported, the chase says it follows none, and no `Lead` is written: imported back,
    // the car standing ahead of it is no lead, and the run is the same.
    let (xosc, written) = export_to(&stopped_car(), &dir.path().join("out"));
    assert!(
        written.contains(r#"<Property name="carfollow:lead" value="none"/>"#),
        "{written}"
    );
    assert!(!written.contains(r#"name="Lead""#), "{written}");
    let back = dir.path().join("back.toml");
    let text = import_to(&xosc, &back);
    assert!(!text.contains("[lead]"), "{text}");
    let short = ["--set", "duration_s=6"];
    let a = frames_of(&stopped_car(), &dir.path().join("a"), &short);
    let b = frames_of(&back, &dir.path().join("b"), &short);
    assert!(a == b, "the export read back ran apart");
}
