//! OpenSCENARIO files through the command line: `carfollow import` writes a scenario file
//! that runs bit for bit as `carfollow run FILE.xosc` does; `--param` sets the file's own
//! parameters; what carfollow cannot run as the standard defines it is refused in one line
//! naming the file, the line and the element, with exit status 2, and a refused file writes
//! nothing. The files are carfollow's own (`sim/core/tests/data/openscenario/`) and
//! esmini's (MPL-2.0, `sim/core/tests/data/openscenario/esmini/`). Run with
//! `cargo test --release -p sim --test cli_openscenario`.

mod osc_common;

use osc_common::*;
use std::path::Path;

#[test]
fn an_imported_file_runs_as_the_file_does_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("cut-in.xosc");
    let toml = dir.path().join("imported/cut-in.toml");
    let text = import_to(&file, &toml);
    for expected in [
        "[route.opendrive]",
        "kind = \"van\"",
        "name = \"Cutter\"",
        "gap_m = 12.0",
        "to = \"chase\"",
        "after = \"cut-in\"",
        "shape = \"sinusoidal\"",
        "duration_s = 25.0",
    ] {
        assert!(text.contains(expected), "{expected} not in:\n{text}");
    }
    let frames = |scenario: &Path, out: &str| {
        frames_of(scenario, &dir.path().join(out), &["--set", "duration_s=16"])
    };
    let from_xosc = frames(&file, "xosc");
    let from_toml = frames(&toml, "toml");
    assert!(
        from_xosc == from_toml,
        "the imported scenario runs differently"
    );
    assert!(
        from_xosc.contains("Cutter/cut-in:started"),
        "the storyboard's event did not fire"
    );
}

#[test]
fn parameters_of_the_file_are_set_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("cut-in.xosc");
    let out = dir.path().join("p.toml");
    let o = carfollow(&[
        "import",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--param",
        "CutInGap=20",
        "--param",
        "LeadSpeed=36",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("gap_m = 20.0"), "{text}");
    // `${$LeadSpeed / 3.6}` of 36 km/h.
    assert!(text.contains("initial_speed_mps = 10.0"), "{text}");
    let bad = dir.path().join("bad.toml");
    let o = carfollow(&[
        "import",
        file.to_str().unwrap(),
        "-o",
        bad.to_str().unwrap(),
        "--param",
        "Nope=1",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.contains("--param Nope=1") && e.contains("CutInGap"),
        "{e}"
    );
    assert!(!bad.exists(), "a refused file wrote something");
    let o = carfollow(&["check", file.to_str().unwrap(), "--param", "Nope=1"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
}

#[test]
fn what_carfollow_cannot_run_is_refused_at_its_line() {
    // (text replaced, its replacement, what the error says, a text on the line it names)
    let cases: [(&str, &str, &str, &str); 15] = [
        ("dynamicsShape=\"sinusoidal\"", "dynamicsShape=\"linear\"", "lane changes are cubic or sinusoidal", "LaneChangeActionDynamics"),
        ("relativeDistanceType=\"longitudinal\"", "relativeDistanceType=\"lateral\"", "gaps are longitudinal", "RelativeDistanceCondition"),
        ("RelativeDistanceCondition entityRef=\"Cutter\" relativeDistanceType=\"longitudinal\" freespace=\"true\"", "RelativeDistanceCondition entityRef=\"Cutter\" relativeDistanceType=\"longitudinal\" freespace=\"maybe\"", "freespace=\"maybe\">: not a boolean", "RelativeDistanceCondition"),
        ("name=\"close\" delay=\"0\" conditionEdge=\"rising\"", "name=\"close\" delay=\"0\" conditionEdge=\"sideways\"", "conditionEdge=\"sideways\">: not an edge", "name=\"close\""),
        ("revMinor=\"1\"", "revMinor=\"4\"", "1.0 to 1.3", "<FileHeader"),
        ("laneId=\"-2\"", "laneId=\"-3\"", "lane -3 is not a lane carfollow drives", "laneId=\"-3\""),
        ("<SimulationTimeCondition value=\"25\"", "<SimulationTimeCondition value=\"${25 / 0}\"", "divides by zero", "${25 / 0}"),
        ("entryName=\"$VanKind\"", "entryName=\"bus_blue\"", "no such vehicle", "bus_blue"),
        ("<RelativeTargetLane entityRef=\"Ego\" value=\"0\"/>", "<AbsoluteTargetLane value=\"1\"/>", "lane 1 is on the oncoming side", "AbsoluteTargetLane"),
        // One lane left of lane −1 is lane 1, the centre lane not counted.
        ("<RelativeTargetLane entityRef=\"Ego\" value=\"0\"/>", "<RelativeTargetLane entityRef=\"Ego\" value=\"1\"/>", "lane 1 is on the oncoming side", "RelativeTargetLane"),
        ("priority=\"overwrite\" maximumExecutionCount=\"1\"", "priority=\"skip\" maximumExecutionCount=\"1\"", "priority=\"skip\"", "priority=\"skip\""),
        ("<AbsoluteTargetSpeed value=\"5\"/>", "<RelativeTargetSpeed entityRef=\"Ego\" value=\"0\" speedTargetValueType=\"percent\" continuous=\"false\"/>", "speedTargetValueType=\"percent\">: delta or factor", "RelativeTargetSpeed"),
        ("ds=\"30\"", "ds=\"5\"", "3–250 m behind", "<Private entityRef=\"Ego\">"),
        ("<LaneChangeAction>", "<LaneChangeAction targetLaneOffset=\"0.5\">", "targetLaneOffset", "targetLaneOffset"),
        // An action of attributes alone is an action not read, not an empty element.
        ("<Action name=\"BrakeAction\">", "<Action name=\"BrakeAction\"><PrivateAction><VisibilityAction graphics=\"true\" traffic=\"true\" sensors=\"false\"/></PrivateAction></Action><Action name=\"Brake2\">", "unsupported action <VisibilityAction>", "VisibilityAction"),
    ];
    for (from, to, says, on_line_of) in cases {
        let (dir, path) = mutant(|text| {
            assert!(text.contains(from), "{from} is not in the test file");
            text.replacen(from, to, 1)
        });
        let text = std::fs::read_to_string(&path).unwrap();
        let line = 1 + text.lines().position(|l| l.contains(on_line_of)).unwrap();
        let out = dir.path().join("out.toml");
        let o = carfollow(&[
            "import",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{to}: {e}");
        assert_eq!(e.lines().count(), 1, "{to}: more than one line: {e}");
        assert!(e.contains(says), "{to}: `{says}` not in {e}");
        assert!(
            e.contains(&format!("mutant.xosc:{line}")),
            "{to}: not at line {line}: {e}"
        );
        assert!(!out.exists(), "{to}: a refused file wrote something");
        // `check` and `run` refuse it alike.
        for command in [&["check"][..], &["run", "--quiet"]] {
            let o = carfollow(&[command, &[path.to_str().unwrap()]].concat());
            assert_eq!(o.status.code(), Some(2), "{command:?} {to}: {}", stderr(&o));
            assert!(
                stderr(&o).contains(says),
                "{command:?} {to}: {}",
                stderr(&o)
            );
        }
    }
    // Not XML at all.
    let (_dir, path) = mutant(|text| text.replace("</OpenSCENARIO>", ""));
    let o = carfollow(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not well-formed XML"), "{}", stderr(&o));
}

#[test]
fn esminis_files_are_refused_in_one_line_naming_what_carfollow_does_not_run() {
    let esmini = data().join("esmini");
    let cases = [
        (
            // Its car starts on the oncoming side, driving with the road, and is read so.
            "xosc/cut-in_simple.xosc",
            "cut-in_simple.xosc:180",
            "unsupported condition <AccelerationCondition>",
        ),
        (
            "xosc/acc-test.xosc",
            "acc-test.xosc:124",
            "lane 1 is on the oncoming side",
        ),
    ];
    for (file, at, says) in cases {
        let path = esmini.join(file);
        let o = carfollow(&["check", path.to_str().unwrap()]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{file}: {e}");
        // The error, said once.
        assert_eq!(e.lines().count(), 1, "{file}: {e}");
        assert!(e.contains(at) && e.contains(says), "{file}: {e}");
    }
}

#[test]
fn an_environment_in_init_is_the_scenarios_environment() {
    let environment = r#"<GlobalAction><EnvironmentAction><Environment name="wet">
          <TimeOfDay animation="false" dateTime="2026-11-27T17:00:00"/>
          <Weather fractionalCloudCover="sevenOktas">
            <Sun azimuth="3.14159265358979" elevation="0.2" illuminance="20000"/>
            <Fog visualRange="80"/>
            <Precipitation precipitationType="rain" precipitationIntensity="6"/>
          </Weather>
        </Environment></EnvironmentAction></GlobalAction>
        <Private entityRef="Ego">"#;
    let (dir, path) = mutant(|text| text.replacen("<Private entityRef=\"Ego\">", environment, 1));
    let out = dir.path().join("env.toml");
    let o = carfollow(&[
        "import",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    for expected in [
        "[environment.sun]",
        "strength = 0.2",
        "[environment.fog]\nvisual_range_m = 80.0",
        "[environment.rain]\nrate_mm_h = 6.0",
    ] {
        assert!(text.contains(expected), "{expected} not in:\n{text}");
    }
    let number = |key: &str| -> f64 {
        text.lines()
            .find_map(|l| l.strip_prefix(key))
            .unwrap()
            .parse()
            .unwrap()
    };
    // 0.2 rad above the horizon.
    assert!((number("elevation_deg = ") - 0.2f64.to_degrees()).abs() < 1e-9);
    // The sun in the south over a road heading east: to the road's right, carfollow's +z
    // (azimuth 90°).
    let azimuth = number("azimuth_deg = ");
    assert!((azimuth - 90.0).abs() < 1e-9, "{azimuth}");
    let e = stderr(&o);
    assert!(
        e.contains("<TimeOfDay>") && e.contains("`fractionalCloudCover`"),
        "{e}"
    );
    // In a story, refused.
    let (_dir, path) = mutant(|text| {
        // The brake event's action becomes an environment's.
        let start = text.find("<Action name=\"BrakeAction\">").unwrap();
        let end = start + text[start..].find("</Action>").unwrap();
        format!(
            "{}<Action name=\"BrakeAction\"><GlobalAction><EnvironmentAction><Environment name=\"x\"/></EnvironmentAction></GlobalAction>{}",
            &text[..start],
            &text[end..]
        )
    });
    let o = carfollow(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("fixed for the run"), "{}", stderr(&o));
}

/// On a tight curve (esmini's `circle_300m`, 48 m radius) the lead 25 m ahead stands well
/// off the camera's axis: the lens the gap would ask for (21 mm) would not see it, so the
/// importer takes a shorter one that does, and the file checks and runs. A refusal found
/// in planning names the `.xosc` and carfollow's field, not a line of the text it became.
#[test]
fn on_a_tight_curve_the_lens_keeps_the_lead_in_view() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("circle-brake.xosc");
    let out = dir.path().join("c.toml");
    let o = carfollow(&[
        "import",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let focal: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("focal_length_mm = "))
        .unwrap()
        .parse()
        .unwrap();
    assert!((8.0..15.0).contains(&focal), "{focal}");
    let o = carfollow(&["check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // The lead 55 m ahead on the circle: out of even the widest lens's view.
    let far = dir.path().join("far.xosc");
    let moved = std::fs::read_to_string(&file)
        .unwrap()
        .replace("s=\"45\"", "s=\"75\"")
        .replace(
            "../opendrive/",
            &format!("{}/", data().join("../opendrive").display()),
        );
    std::fs::write(&far, moved).unwrap();
    let o = carfollow(&["check", far.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("far.xosc: as carfollow reads it: `"), "{e}");
    assert!(e.contains("out of the camera's view"), "{e}");
}

#[test]
fn a_pedestrian_from_a_catalog_is_refused_as_a_pedestrian() {
    let (dir, path) = mutant(|text| {
        text.replace(
            "<VehicleCatalog><Directory path=\"catalogs\"/></VehicleCatalog>",
            "<VehicleCatalog><Directory path=\"catalogs\"/></VehicleCatalog>\n    \
             <PedestrianCatalog><Directory path=\"people\"/></PedestrianCatalog>",
        )
        .replace(
            "catalogName=\"VehicleCatalog\" entryName=\"$VanKind\"",
            "catalogName=\"PedestrianCatalog\" entryName=\"walker\"",
        )
    });
    let people = dir.path().join("people");
    std::fs::create_dir_all(&people).unwrap();
    std::fs::write(
        people.join("PedestrianCatalog.xosc"),
        "<?xml version=\"1.0\"?>\n<OpenSCENARIO>\n  <FileHeader revMajor=\"1\" revMinor=\"1\" \
         date=\"2026-01-01T00:00:00\" description=\"people\" author=\"carfollow\"/>\n  \
         <Catalog name=\"PedestrianCatalog\">\n    <Pedestrian name=\"walker\" mass=\"80\" \
         pedestrianCategory=\"pedestrian\"/>\n  </Catalog>\n</OpenSCENARIO>\n",
    )
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let line = 1 + text.lines().position(|l| l.contains("walker")).unwrap();
    let out = dir.path().join("out.toml");
    let o = carfollow(&[
        "import",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert_eq!(e.lines().count(), 1, "more than one line: {e}");
    assert!(!out.exists(), "a refused file wrote something");
    assert!(
        e.contains(
            "a <Pedestrian> of the PedestrianCatalog, and carfollow's entities are vehicles"
        ),
        "{e}"
    );
    assert!(
        e.contains(&format!("mutant.xosc:{line}")),
        "not at line {line}: {e}"
    );
}

#[test]
fn import_makes_the_folder_it_writes_into_and_takes_it_away_when_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("new/deeper/cut-in.toml");
    let file = data().join("cut-in.xosc");
    let o = carfollow(&[
        "import",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = carfollow(&["check", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // Refused: nothing is left, not even the folder.
    let (bad_dir, bad) = mutant(|text| text.replacen("revMinor=\"1\"", "revMinor=\"4\"", 1));
    let out = bad_dir.path().join("made/here/x.toml");
    let o = carfollow(&["import", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        !bad_dir.path().join("made").exists(),
        "a refused import left a folder"
    );
}

/// The ego's speed change in `Init` (linear at a rate, as esmini's `follow_reference` and
/// `drive_when_close` write it) is read as the speed it reaches, with one warning that it
/// is not applied: the chase starts at that speed, and the run is the one of a step to it,
/// bit for bit. Another vehicle's speed change in `Init` is refused at its line.
#[test]
fn the_egos_speed_change_in_init_is_its_speed_with_a_warning() {
    let step =
        "<SpeedActionDynamics dynamicsShape=\"step\" dynamicsDimension=\"time\" value=\"0\"/>";
    let ramp =
        "<SpeedActionDynamics dynamicsShape=\"linear\" dynamicsDimension=\"rate\" value=\"5\"/>";
    // The first step in the file is the ego's, the second the lead's.
    let (dir, ego) = mutant(|text| text.replacen(step, ramp, 1));
    let text = std::fs::read_to_string(&ego).unwrap();
    let line = 1 + text.lines().position(|l| l.contains(ramp)).unwrap();
    let o = carfollow(&["check", ego.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let warned: Vec<_> = stderr(&o)
        .lines()
        .filter(|l| l.contains("speed change in <Init>"))
        .map(String::from)
        .collect();
    assert_eq!(warned.len(), 1, "{}", stderr(&o));
    assert!(
        warned[0].contains(&format!("line {line}:")) && warned[0].contains("not applied"),
        "{warned:?}"
    );
    let set = ["--set", "duration_s=6"];
    let (a, b) = (dir.path().join("ramp"), dir.path().join("step"));
    let original = data().join("cut-in.xosc");
    assert!(frames_of(&ego, &a, &set) == frames_of(&original, &b, &set));
    // The lead's: refused.
    let (_dir, lead) = mutant(|text| {
        let at = text.match_indices(step).nth(1).unwrap().0;
        format!("{}{ramp}{}", &text[..at], &text[at + step.len()..])
    });
    let text = std::fs::read_to_string(&lead).unwrap();
    let line = 1 + text.lines().position(|l| l.contains(ramp)).unwrap();
    let out = lead.with_file_name("lead.toml");
    let o = carfollow(&[
        "import",
        lead.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.contains("Init sets each speed at once") && e.contains(&format!("mutant.xosc:{line}")),
        "{e}"
    );
}

/// An act's empty `<StartTrigger/>` (esmini's `acc-toggle` and `drive_when_close` write
/// it; esmini starts such an act at once) and a start trigger of several condition groups
/// one of which holds from the first step both start the act at t = 0, and an act's empty
/// `<StopTrigger/>` (esmini's `alks_decelerate` writes it) never fires: the runs are the
/// file's, bit for bit. A stop trigger that can fire is refused at its line.
#[test]
fn an_act_with_an_empty_start_trigger_starts_at_once() {
    let start = "<StartTrigger><ConditionGroup>\n          <Condition name=\"start\" delay=\"0\" conditionEdge=\"none\">\n            <ByValueCondition><SimulationTimeCondition value=\"0\" rule=\"greaterThan\"/></ByValueCondition>\n          </Condition>\n        </ConditionGroup></StartTrigger>";
    let later = "<ConditionGroup><Condition name=\"later\" delay=\"0\" conditionEdge=\"none\"><ByValueCondition><SimulationTimeCondition value=\"5\" rule=\"greaterThan\"/></ByValueCondition></Condition></ConditionGroup>";
    let set = ["--set", "duration_s=16"];
    let dir = tempfile::tempdir().unwrap();
    let original = frames_of(&data().join("cut-in.xosc"), &dir.path().join("o"), &set);
    for to in [
        "<StartTrigger/>".to_string(),
        start.replace("<StartTrigger>", &format!("<StartTrigger>{later}")),
        format!("{start}<StopTrigger/>"),
        format!("{start}\n<StopTrigger>\n</StopTrigger>"),
    ] {
        let (d, path) = mutant(|text| {
            assert!(text.contains(start));
            text.replace(start, &to)
        });
        let o = carfollow(&["check", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{to}: {}", stderr(&o));
        let frames = frames_of(&path, &d.path().join("m"), &set);
        assert!(frames == original, "{to}: the run differs");
        assert!(frames.contains("cut-in:started"), "{to}");
    }
    let (_d, path) = mutant(|text| {
        text.replace(
            start,
            &format!("{start}\n<StopTrigger>{later}</StopTrigger>"),
        )
    });
    let line = line_of(
        &path,
        "<StopTrigger><ConditionGroup><Condition name=\"later\"",
    );
    let o = carfollow(&["check", path.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("unsupported act stop trigger") && e.contains(&format!("mutant.xosc:{line}")),
        "{e}"
    );
}

/// An event's empty `<StartTrigger/>` (esmini's `distance_test` writes one; esmini takes a
/// start trigger with no condition group as true) starts the event at once, as an event
/// with no start trigger does: the runs are the same, bit for bit, and the cut-in starts
/// on the first frame. It was refused as an event that would never start.
#[test]
fn an_events_empty_start_trigger_starts_it_at_once() {
    let close = "<StartTrigger><ConditionGroup>\n                <Condition name=\"close\"";
    let replace_trigger = |by: &'static str| {
        move |text: &str| {
            let from = text.find(close).expect("the cut-in's trigger");
            let end = "</StartTrigger>";
            let to = from + text[from..].find(end).unwrap() + end.len();
            format!("{}{by}{}", &text[..from], &text[to..])
        }
    };
    let set = ["--set", "duration_s=6"];
    let (d, empty) = mutant(replace_trigger("<StartTrigger/>"));
    let o = carfollow(&["check", empty.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let frames = frames_of(&empty, &d.path().join("empty"), &set);
    let (d2, none) = mutant(replace_trigger(""));
    let without = frames_of(&none, &d2.path().join("none"), &set);
    assert!(
        frames == without,
        "an empty start trigger runs otherwise than none"
    );
    let first = frames.lines().nth(1).unwrap();
    assert!(first.contains("cut-in:started"), "{first}");
}

/// An edit of the test file that places its cutter on lane `lane` with `inside` (an
/// `<Orientation>`, or nothing) in its `LanePosition`.
fn cutter_at(lane: &'static str, inside: &'static str) -> impl Fn(&str) -> String {
    move |text: &str| {
        let at = "<LanePosition roadId=\"1\" laneId=\"-2\" offset=\"0\" s=\"80\"/>";
        assert!(text.contains(at));
        text.replace(
            at,
            &format!("<LanePosition roadId=\"1\" laneId=\"{lane}\" offset=\"0\" s=\"80\">\n{inside}</LanePosition>"),
        )
    }
}

/// A vehicle's `<Orientation>` in `Init` is read, not passed over: turned against the road
/// (esmini's `lane_change_crest` turns a car in lane −1 by π) it is refused at its line;
/// turned a little, the vehicle starts along the road, said in one warning; along the road,
/// relative or absolute, the run is the file's, bit for bit.
#[test]
fn a_vehicles_orientation_is_read() {
    let turned = |o: &'static str| cutter_at("-2", o);
    let set = ["--set", "duration_s=6"];
    let dir = tempfile::tempdir().unwrap();
    let original = frames_of(&data().join("cut-in.xosc"), &dir.path().join("o"), &set);
    for o in [
        "<Orientation type=\"relative\" h=\"3.141593\"/>",
        "<Orientation h=\"-2.0\"/>",
        "<Orientation type=\"absolute\" h=\"3.2\"/>",
    ] {
        let (_d, path) = mutant(turned(o));
        let line = line_of(&path, o);
        let o_ = carfollow(&["check", path.to_str().unwrap()]);
        let e = stderr(&o_);
        assert_eq!(o_.status.code(), Some(2), "{o}: {e}");
        assert_eq!(e.lines().count(), 1, "{o}: {e}");
        assert!(
            e.contains("faces against road 1") && e.contains(&format!("mutant.xosc:{line}")),
            "{o}: {e}"
        );
    }
    let (_d, path) = mutant(turned("<Orientation type=\"relative\" h=\"0.1\"/>"));
    let o = carfollow(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        stderr(&o).matches("is turned 5.7° from the road").count(),
        1,
        "{}",
        stderr(&o)
    );
    for o in [
        "<Orientation type=\"relative\" h=\"0\"/>",
        "<Orientation type=\"absolute\" h=\"0\"/>",
    ] {
        let (d, path) = mutant(turned(o));
        let frames = frames_of(&path, &d.path().join("m"), &set);
        assert!(frames == original, "{o}: the run differs");
    }
}

/// A vehicle on a lane of the oncoming side turned to drive with the road (relative
/// `h` = π, as esmini's `alks_cut-in` places the car that cuts in) is an actor that far left
/// of lane 1's centre, and its cut-in brings it into the ego's lane; facing against the
/// road there (no orientation) it is refused as oncoming traffic, as is a lane counted from
/// it or a lead named that starts there.
#[test]
fn a_vehicle_driving_with_the_road_on_the_oncoming_side_is_read() {
    let on_left = |o: &'static str| cutter_at("1", o);
    let (d, path) = mutant(on_left("<Orientation type=\"relative\" h=\"3.141593\"/>"));
    let toml = d.path().join("left.toml");
    let text = import_to(&path, &toml);
    assert!(text.contains("offset_m = 3.5"), "{text}");
    let frames = frames_of(&toml, &d.path().join("run"), &["--set", "duration_s=12"]);
    assert!(frames.contains("cut-in:started"), "the cut-in never starts");
    let f = Frames::parse(&frames);
    let col = f.header.iter().position(|c| c == "path_vehicle").unwrap();
    assert!(
        f.rows.iter().any(|r| r[col] == "Cutter"),
        "the cutter never enters the path"
    );
    // A RoadPosition there too: t = 1.75 m is the oncoming lane 1's centre.
    let (d, path) = mutant(|text| {
        cutter_at("-2", "")(text).replace(
            "<LanePosition roadId=\"1\" laneId=\"-2\" offset=\"0\" s=\"80\">\n</LanePosition>",
            "<RoadPosition roadId=\"1\" s=\"80\" t=\"1.75\"><Orientation type=\"relative\" h=\"3.141593\"/></RoadPosition>",
        )
    });
    let text = import_to(&path, &d.path().join("road.toml"));
    assert!(text.contains("offset_m = 3.5"), "{text}");
    let (_d, path) = mutant(on_left(""));
    let line = line_of(&path, "laneId=\"1\"");
    let e = refusal(
        &carfollow(&["check", path.to_str().unwrap()]),
        "no orientation",
    );
    assert!(
        e.contains("oncoming traffic") && e.contains(&format!("mutant.xosc:{line}")),
        "{e}"
    );
    let (_d, path) = mutant(|text| {
        on_left("<Orientation type=\"relative\" h=\"3.141593\"/>")(text).replace(
            "<RelativeTargetLane entityRef=\"Ego\" value=\"0\"/>",
            "<RelativeTargetLane entityRef=\"Cutter\" value=\"-1\"/>",
        )
    });
    let e = refusal(&carfollow(&["check", path.to_str().unwrap()]), "relative");
    assert!(e.contains("starts on the oncoming side"), "{e}");
}

/// A controller assigned to the ego is read and not applied, and the one warning that says
/// so names the controller alone when the ego has no storyboard action; with a controller
/// action in `Init` too (esmini's `alks_decelerate` activates the ego's), the same one line
/// names both, with the action's line.
#[test]
fn the_egos_controller_alone_is_named_in_its_warning() {
    let ego = "<CatalogReference catalogName=\"VehicleCatalog\" entryName=\"car_white\"/>";
    let controlled = format!(
        "{ego}<ObjectController><Controller name=\"driver\"><Properties/></Controller></ObjectController>"
    );
    let (_dir, file) = mutant(|text| text.replacen(ego, &controlled, 1));
    let o = carfollow(&["check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let warned: Vec<_> = stderr(&o)
        .lines()
        .filter(|l| l.contains("the ego `Ego`'s"))
        .map(String::from)
        .collect();
    assert_eq!(warned.len(), 1, "{}", stderr(&o));
    assert!(
        warned[0].contains("controller is not applied") && !warned[0].contains("0 storyboard"),
        "{warned:?}"
    );
    let private = "<Private entityRef=\"Ego\">";
    let activate = "<PrivateAction><ActivateControllerAction longitudinal=\"true\" lateral=\"false\"/></PrivateAction>";
    let (_dir, file) = mutant(|text| {
        text.replacen(ego, &controlled, 1)
            .replacen(private, &format!("{private}\n{activate}"), 1)
    });
    let line = line_of(&file, "<ActivateControllerAction");
    let o = carfollow(&["check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let warned: Vec<_> = stderr(&o)
        .lines()
        .filter(|l| l.contains("Ego") && l.contains("not applied"))
        .map(String::from)
        .collect();
    assert_eq!(warned.len(), 1, "{}", stderr(&o));
    assert!(
        warned[0].contains(&format!(
            "controller and controller action(s) in <Init> (line {line}) are not applied"
        )),
        "{warned:?}"
    );
}

/// A start off the lane's centre (`LanePosition offset`, `RelativeLanePosition offset`) is
/// the vehicle's `offset_m`: imported, run the same as its TOML, and exported back; the
/// ego's is refused in one line (carfollow's chase starts on its lane's centre).
#[test]
fn a_start_off_the_lanes_centre_is_the_vehicles_offset() {
    let lead = r#"<RelativeLanePosition entityRef="Ego" dLane="0" ds="30" offset="0"/>"#;
    let cutter = r#"<LanePosition roadId="1" laneId="-2" offset="0" s="80"/>"#;
    let (dir, path) = mutant(|text| {
        assert!(text.contains(lead) && text.contains(cutter));
        text.replace(lead, &lead.replace("offset=\"0\"", "offset=\"-0.6\""))
            .replace(cutter, &cutter.replace("offset=\"0\"", "offset=\"0.4\""))
    });
    let toml = dir.path().join("offset.toml");
    let text = import_to(&path, &toml);
    assert!(
        text.contains("[lead]") && text.contains("offset_m = -0.6"),
        "{text}"
    );
    assert!(text.contains("offset_m = 0.4"), "{text}");
    let set = ["--set", "duration_s=6"];
    let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
    assert!(
        frames_of(&path, &dir.path().join("x"), &set) == from_toml,
        "the imported scenario runs differently"
    );
    let (xosc, written) = export_to(&toml, &dir.path().join("export"));
    assert!(
        written.contains("offset=\"-0.6\"") && written.contains("offset=\"0.4\""),
        "{written}"
    );
    assert!(
        frames_of(&xosc, &dir.path().join("e"), &set) == from_toml,
        "the exported file runs differently"
    );
    // The ego's own offset.
    let ego = r#"<LanePosition roadId="1" laneId="-1" offset="0" s="20"/>"#;
    let (_dir, path) = mutant(|text| {
        assert!(text.contains(ego));
        text.replace(ego, &ego.replace("offset=\"0\"", "offset=\"0.5\""))
    });
    let e = refusal(
        &carfollow(&["check", path.to_str().unwrap()]),
        "the ego's offset",
    );
    assert!(
        e.contains("0.50 m left of its lane's centre") && e.contains("mutant.xosc:"),
        "{e}"
    );
}
