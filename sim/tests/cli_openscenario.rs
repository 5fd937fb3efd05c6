//! OpenSCENARIO files through the command line: `carfollow import` writes a scenario file
//! that runs bit for bit as `carfollow run FILE.xosc` does; `--param` sets the file's own
//! parameters; what carfollow cannot run as the standard defines it is refused in one line
//! naming the file, the line and the element, with exit status 2, and a refused file writes
//! nothing. The files are carfollow's own (`sim/core/tests/data/openscenario/`) and
//! esmini's (MPL-2.0, `sim/core/tests/data/openscenario/esmini/`). Run with
//! `cargo test --release -p sim --test cli_openscenario`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim/core/tests/data/openscenario")
}

fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `frames.csv` of `carfollow run SCENARIO --quiet --out OUT` with `extra` arguments; the
/// run must complete (passed or not).
fn frames_of(scenario: &Path, out: &Path, extra: &[&str]) -> String {
    let args = [
        &[
            "run",
            scenario.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ][..],
        extra,
    ]
    .concat();
    let o = carfollow(&args);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    std::fs::read_to_string(out.join("frames.csv")).unwrap()
}

/// `carfollow import FILE -o TOML`, which must succeed, and the scenario text it wrote.
fn import_to(file: &Path, toml: &Path) -> String {
    let o = carfollow(&[
        "import",
        file.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    std::fs::read_to_string(toml).unwrap()
}

/// A run's `frames.csv`, its rows read by column name.
struct Frames {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Frames {
    fn parse(csv: &str) -> Frames {
        let split = |l: &str| l.split(',').map(String::from).collect::<Vec<_>>();
        let mut lines = csv.lines();
        Frames {
            header: split(lines.next().unwrap()),
            rows: lines.map(split).collect(),
        }
    }

    /// Column `name` of row `r`, a number.
    fn num(&self, r: &[String], name: &str) -> f64 {
        let col = self.header.iter().position(|c| c == name).unwrap();
        r[col].parse().unwrap()
    }

    /// The time of the first frame whose `event` column holds `event`
    /// (`vehicle/name:started`).
    fn logged(&self, event: &str) -> Option<f64> {
        let col = self.header.iter().position(|c| c == "event").unwrap();
        self.rows
            .iter()
            .find(|r| r[col].contains(event))
            .map(|r| self.num(r, "t_s"))
    }
}

/// A copy of the test files in a temporary folder, with `cut-in.xosc`'s text changed by
/// `edit` and written as `mutant.xosc`.
fn mutant(edit: impl Fn(&str) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for name in ["two-lanes.xodr", "catalogs/VehicleCatalog.xosc"] {
        let to = dir.path().join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(data().join(name), to).unwrap();
    }
    let text = std::fs::read_to_string(data().join("cut-in.xosc")).unwrap();
    let path = dir.path().join("mutant.xosc");
    std::fs::write(&path, edit(&text)).unwrap();
    (dir, path)
}

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
    let cases: [(&str, &str, &str, &str); 13] = [
        ("dynamicsShape=\"sinusoidal\"", "dynamicsShape=\"linear\"", "lane changes are cubic or sinusoidal", "LaneChangeActionDynamics"),
        ("relativeDistanceType=\"longitudinal\"", "relativeDistanceType=\"lateral\"", "gaps are longitudinal", "RelativeDistanceCondition"),
        ("freespace=\"true\"", "freespace=\"false\"", "bumper to bumper", "RelativeDistanceCondition"),
        ("name=\"close\" delay=\"0\" conditionEdge=\"rising\"", "name=\"close\" delay=\"0\" conditionEdge=\"falling\"", "conditionEdge=\"falling\"", "name=\"close\""),
        ("revMinor=\"1\"", "revMinor=\"4\"", "1.0 to 1.3", "<FileHeader"),
        ("laneId=\"-2\"", "laneId=\"-3\"", "lane -3 is not a lane carfollow drives", "laneId=\"-3\""),
        ("<SimulationTimeCondition value=\"25\"", "<SimulationTimeCondition value=\"${25 / 0}\"", "divides by zero", "${25 / 0}"),
        ("entryName=\"$VanKind\"", "entryName=\"bus_blue\"", "no such vehicle", "bus_blue"),
        ("<RelativeTargetLane entityRef=\"Ego\" value=\"0\"/>", "<AbsoluteTargetLane value=\"1\"/>", "lane 1 is not a lane carfollow drives", "AbsoluteTargetLane"),
        ("priority=\"overwrite\" maximumExecutionCount=\"1\"", "priority=\"parallel\" maximumExecutionCount=\"1\"", "priority=\"parallel\"", "priority=\"parallel\""),
        ("<AbsoluteTargetSpeed value=\"5\"/>", "<RelativeTargetSpeed entityRef=\"Ego\" value=\"0\" speedTargetValueType=\"delta\" continuous=\"false\"/>", "unsupported speed target <RelativeTargetSpeed>", "RelativeTargetSpeed"),
        ("ds=\"30\"", "ds=\"300\"", "3–250 m behind", "<Private entityRef=\"Ego\">"),
        ("<LaneChangeAction>", "<LaneChangeAction targetLaneOffset=\"0.5\">", "targetLaneOffset", "targetLaneOffset"),
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
            "xosc/cut-in_simple.xosc",
            "cut-in_simple.xosc:69",
            "not the centre of a lane",
        ),
        (
            "xosc/acc-test.xosc",
            "acc-test.xosc:124",
            "lane 0 is not a lane carfollow drives",
        ),
        (
            "xosc/straight_500m.xosc",
            "straight_500m.xosc:55",
            "296.6 m behind the lead",
        ),
    ];
    for (file, at, says) in cases {
        let path = esmini.join(file);
        let o = carfollow(&["check", path.to_str().unwrap()]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{file}: {e}");
        // The error, and the count of files refused.
        assert_eq!(e.lines().count(), 2, "{file}: {e}");
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

#[test]
fn speed_and_standstill_conditions_are_imported_and_fire_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("speed-standstill.xosc");
    let toml = dir.path().join("speed-standstill.toml");
    let text = import_to(&file, &toml);
    for expected in [
        "speed_mps = 5.0\nof = \"lead\"\nrule = \"less\"",
        "standstill_s = 2.0\nof = \"lead\"\ndelay_s = 0.5",
        "standstill_s = 3.0\n\n",
    ] {
        assert!(text.contains(expected), "{expected:?} not in:\n{text}");
    }
    let run = |scenario: &Path, out: &str| frames_of(scenario, &dir.path().join(out), &[]);
    let csv = run(&file, "xosc");
    assert!(
        csv == run(&toml, "toml"),
        "the imported scenario runs differently"
    );
    let frames = Frames::parse(&csv);
    let (rows, num) = (&frames.rows, |r: &[String], c: &str| frames.num(r, c));
    let at = |event: &str| {
        frames
            .logged(event)
            .unwrap_or_else(|| panic!("{event} not logged"))
    };
    // The van slows at the step the lead's speed falls to 5 m/s (logged a frame later).
    let slow = rows
        .iter()
        .position(|r| num(r, "lead_speed_mps") <= 5.0)
        .unwrap();
    let slow_at = at("Cutter/slow:started");
    assert!(
        slow_at == num(&rows[slow], "t_s") || slow_at == num(&rows[slow - 1], "t_s"),
        "{slow_at}"
    );
    // It stops 2 s (and the delay, 0.5 s) after the lead stands; the lead moves off after 3 s.
    let still = num(
        rows.iter()
            .find(|r| num(r, "lead_speed_mps").abs() < 0.05)
            .unwrap(),
        "t_s",
    );
    let frame = 1.0 / 15.0 + 1e-9;
    assert!(
        (at("Cutter/halt:started") - still - 2.5).abs() <= frame,
        "{still}"
    );
    assert!(
        (at("lead/creep:started") - still - 3.0).abs() <= frame,
        "{still}"
    );
    // A speed condition by direction is refused at its line.
    let text = std::fs::read_to_string(&file).unwrap();
    let bad = dir.path().join("bad.xosc");
    for name in ["two-lanes.xodr", "catalogs/VehicleCatalog.xosc"] {
        let to = dir.path().join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(data().join(name), to).unwrap();
    }
    let from = "<SpeedCondition value=\"$SlowAt\" rule=\"lessThan\"/>";
    assert!(text.contains(from));
    std::fs::write(
        &bad,
        text.replace(
            from,
            "<SpeedCondition value=\"$SlowAt\" rule=\"lessThan\" direction=\"lateral\"/>",
        ),
    )
    .unwrap();
    let line = 1 + text.lines().position(|l| l.contains(from)).unwrap();
    let o = carfollow(&["check", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&format!("bad.xosc:{line}")) && stderr(&o).contains("direction"),
        "{}",
        stderr(&o)
    );
}

/// `reach-relative.xosc` imported, checked and run; `edit` applied to its text first.
fn reach_relative(dir: &Path, edit: impl Fn(&str) -> String) -> (PathBuf, String) {
    for name in ["two-lanes.xodr", "catalogs/VehicleCatalog.xosc"] {
        let to = dir.join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(data().join(name), to).unwrap();
    }
    let text = std::fs::read_to_string(data().join("reach-relative.xosc")).unwrap();
    let path = dir.join("rr.xosc");
    std::fs::write(&path, edit(&text)).unwrap();
    (path, text)
}

#[test]
fn reach_position_relative_speed_and_equal_to_are_imported_and_fire_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let (file, text) = reach_relative(dir.path(), |t| t.to_string());
    let toml = dir.path().join("rr.toml");
    let written = import_to(&file, &toml);
    for expected in [
        "[lead.events.trigger.reach]\nstation_m = 150.0\nlane = 1\ntolerance_m = 1.5\n",
        "time_s = 12.0\nrule = \"equal\"",
        // The lead's speed less the van's at most −0.5: the van's less the lead's at least 0.5.
        "relative_speed_mps = 0.5\nto = \"lead\"\nrule = \"greater\"",
    ] {
        assert!(
            written.contains(expected),
            "{expected:?} not in:\n{written}"
        );
    }
    let o = carfollow(&["check", toml.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // `check` refuses a reach's lane the road lacks, at its line.
    let bad_toml = dir.path().join("bad-lane.toml");
    let reach = "[lead.events.trigger.reach]\nstation_m = 150.0\nlane = 1";
    std::fs::write(
        &bad_toml,
        written.replace(reach, &reach.replace("lane = 1", "lane = 3")),
    )
    .unwrap();
    let line = 3 + written[..written.find(reach).unwrap()].lines().count();
    let o = carfollow(&["check", bad_toml.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with(&format!(
            "error: {}:{line}:1: `lead.events[0].trigger.reach.lane` = 3: no such lane",
            bad_toml.display()
        )),
        "{}",
        stderr(&o)
    );
    let run = |scenario: &Path, out: &str| frames_of(scenario, &dir.path().join(out), &[]);
    let csv = run(&file, "xosc");
    assert!(
        csv == run(&toml, "toml"),
        "the imported scenario runs differently"
    );
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let num = |r: &Vec<&str>, c: &str| r[col(c)].parse::<f64>().unwrap();
    let row_of = |event: &str| {
        rows.iter()
            .position(|r| r[col("event")].contains(event))
            .unwrap_or_else(|| panic!("{event} not logged"))
    };
    // The lead slows once its rear axle is within 1.5 m of s = 150 (the straight runs
    // along x from 0), logged in the frame before or at the one past it.
    let reached = rows
        .iter()
        .position(|r| num(r, "lead_x_m") >= 148.5)
        .unwrap();
    let slow = row_of("lead/slow:started");
    assert!(slow == reached || slow + 1 == reached, "{slow} {reached}");
    // It speeds up again at t = 12 s exactly: the frame at 12 s logs it.
    assert_eq!(num(&rows[row_of("lead/resume:started")], "t_s"), 12.0);
    // The van (9.72 m/s) passes once the lead is 0.5 m/s slower than it: logged in the
    // frame whose capture saw the lead at most one frame's fall (2 m/s² × 1/15 s) above
    // 9.22 m/s.
    let pass = &rows[row_of("Cutter/pass:started")];
    let lead = num(pass, "lead_speed_mps");
    assert!((9.15..=9.36).contains(&lead), "{lead}");
    // 1.2's DistanceCondition to a position, at most 1.5 m, is the same reach trigger.
    let from = "<ReachPositionCondition tolerance=\"1.5\">";
    let (distance, _) = reach_relative(dir.path(), |t| {
        t.replace(from, "<DistanceCondition value=\"1.5\" freespace=\"false\" rule=\"lessOrEqual\" relativeDistanceType=\"euclidianDistance\">")
            .replace("</ReachPositionCondition>", "</DistanceCondition>")
    });
    let again = dir.path().join("again.toml");
    let o = carfollow(&[
        "import",
        distance.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let again = std::fs::read_to_string(&again).unwrap();
    assert_eq!(
        again.replace("rr.xosc", ""),
        written.replace("rr.xosc", ""),
        "a DistanceCondition to a position imports differently"
    );
    // An act started at a time equal to 0 starts at once, as one started after 0.
    let start = "<SimulationTimeCondition value=\"0\" rule=\"greaterThan\"/>";
    let (equal, _) = reach_relative(dir.path(), |t| {
        assert!(t.contains(start));
        t.replace(start, &start.replace("greaterThan", "equalTo"))
    });
    let o = carfollow(&[
        "import",
        equal.to_str().unwrap(),
        "-o",
        dir.path().join("eq.toml").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let eq = std::fs::read_to_string(dir.path().join("eq.toml")).unwrap();
    assert_eq!(eq.replace("rr.xosc", ""), written.replace("rr.xosc", ""));
    // What the reach, relative speed and rules cannot be is refused at its line.
    let reach_line = 1 + text.lines().position(|l| l.contains(from)).unwrap();
    let position = "<LanePosition roadId=\"1\" laneId=\"-1\" offset=\"0\" s=\"150\"/>";
    let relative =
        "<RelativeSpeedCondition entityRef=\"Cutter\" value=\"-0.5\" rule=\"lessThan\"/>";
    let relative_line = 1 + text.lines().position(|l| l.contains(relative)).unwrap();
    let cases: [(String, String, usize, &str); 6] = [
        (
            position.into(),
            "<GeoPosition latitude=\"0.1\" longitude=\"0.2\"/>".into(),
            reach_line + 1,
            "position",
        ),
        (
            position.into(),
            position.replace("-1\"", "-3\""),
            reach_line + 1,
            "lane -3 is not a lane",
        ),
        (
            from.into(),
            "<ReachPositionCondition tolerance=\"0\">".into(),
            reach_line,
            "must be above 0",
        ),
        (
            relative.into(),
            relative.replace("/>", " direction=\"lateral\"/>"),
            relative_line,
            "direction",
        ),
        (
            relative.into(),
            relative.replace("lessThan", "nearlyEqualTo"),
            relative_line,
            "not a rule of the standard",
        ),
        // Not equal to 0 holds from the second step: not the act's start.
        (
            start.into(),
            start.replace("greaterThan", "notEqualTo"),
            1 + text.lines().position(|l| l.contains(start)).unwrap() - 1,
            "<Act> starts on a condition",
        ),
    ];
    for (from, to, line, why) in cases {
        let (bad, _) = reach_relative(dir.path(), |t| {
            assert!(t.contains(&from), "{from}");
            t.replace(&from, &to)
        });
        let o = carfollow(&["check", bad.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{to}: {}", stderr(&o));
        let e = stderr(&o);
        let first = e.lines().next().unwrap_or_default();
        assert!(
            first.contains(&format!("rr.xosc:{line}")) && first.contains(why),
            "{to}: {e}"
        );
    }
    // Exported back, the scenario imports to the same scenario.
    let back_dir = dir.path().join("back");
    let o = carfollow(&[
        "export",
        toml.to_str().unwrap(),
        "-o",
        back_dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let back = back_dir.join("rr.xosc");
    let exported = std::fs::read_to_string(&back).unwrap();
    for expected in [
        "<ReachPositionCondition tolerance=\"1.5\">",
        "rule=\"equalTo\"",
        "<RelativeSpeedCondition",
    ] {
        assert!(
            exported.contains(expected),
            "{expected:?} not in:\n{exported}"
        );
    }
    let back_toml = dir.path().join("back.toml");
    let o = carfollow(&[
        "import",
        back.to_str().unwrap(),
        "-o",
        back_toml.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        frames_of(&back_toml, &dir.path().join("back-run"), &[]) == csv,
        "the exported file runs differently"
    );
}

/// Triggers of several conditions: `condition-groups.xosc`'s lead brakes on either of two
/// condition groups (t > `$LateBrake`; or t > 3 s, 2 s ago, and the ego faster than
/// `$EgoFast`), and its van slows on one condition of two triggering entities (the lead and
/// the ego below 12 m/s, rule `$Both`). Imported as `any` and `all`, run as written, and each
/// parameter changed shows the group's logic: a group fires only when all its conditions
/// hold, a trigger when any group does.
#[test]
fn condition_groups_and_several_triggering_entities_fire_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("condition-groups.xosc");
    let toml = dir.path().join("groups.toml");
    let text = import_to(&file, &toml);
    for expected in [
        "[[lead.events.trigger.any]]",
        "delay_s = 2.0",
        "[[lead.events.trigger.any.all]]",
        "[[actors.events.trigger.all]]",
        "offset_m = 0.6\nlateral_accel_mps2 = 0.5\nshape = \"sinusoidal\"",
        "profile = [",
    ] {
        assert!(text.contains(expected), "{expected:?} not in:\n{text}");
    }
    let run = |out: &str, param: &[&str]| {
        let csv = frames_of(&file, &dir.path().join(out), param);
        (Frames::parse(&csv), csv)
    };
    let (frames, csv) = run("xosc", &[]);
    assert!(
        csv == frames_of(&toml, &dir.path().join("toml"), &[]),
        "the imported scenario runs differently"
    );
    let started = |f: &Frames, event: &str| f.logged(&format!("{event}:started"));
    let frame = 1.0 / 15.0 + 1e-9;
    // The second group: 3 s, delayed 2 s, and the ego at about 13.9 m/s.
    let brake = started(&frames, "lead/brake").expect("the lead brakes");
    assert!((brake - 5.0).abs() <= frame, "{brake}");
    // Both below 12 m/s: the van slows at the first frame they are (or the one before),
    // later than the lead alone falls below it.
    let below = |f: &Frames, r: &[String], speed: &str| f.num(r, speed) < 12.0;
    let both =
        |f: &Frames, r: &[String]| below(f, r, "lead_speed_mps") && below(f, r, "chase_speed_mps");
    let either =
        |f: &Frames, r: &[String]| below(f, r, "lead_speed_mps") || below(f, r, "chase_speed_mps");
    let logged_at = |f: &Frames, when: &dyn Fn(&Frames, &[String]) -> bool| {
        let k = f
            .rows
            .iter()
            .position(|r| when(f, r))
            .expect("the speeds fall below 12 m/s");
        let slow = started(f, "Cutter/slow").expect("the van slows");
        assert!(
            slow == f.num(&f.rows[k], "t_s") || slow == f.num(&f.rows[k - 1], "t_s"),
            "slow at {slow}, the condition from {}",
            f.num(&f.rows[k], "t_s")
        );
        slow
    };
    let all_at = logged_at(&frames, &both);
    // A group holds only when every condition does: an ego never that fast, no braking.
    let (never, _) = run("fast", &["--param", "EgoFast=30"]);
    assert_eq!(started(&never, "lead/brake"), None);
    // A trigger holds when any group does: the first group at 2 s.
    let (early, _) = run("early", &["--param", "LateBrake=2"]);
    let brake = started(&early, "lead/brake").unwrap();
    assert!((brake - 2.0).abs() <= frame, "{brake}");
    // Either entity, with rule any: as soon as the lead is below 12 m/s.
    let (any, _) = run("any", &["--param", "Both=any"]);
    let any_at = logged_at(&any, &either);
    assert!(any_at < all_at, "any at {any_at}, all at {all_at}");
    // The van's drift, 0.6 m at a peak of 0.5 m/s² (π √(0.6 / 1) s), then back 1 s later.
    let drift = started(&frames, "Cutter/drift").unwrap();
    assert!((drift - 1.0).abs() <= frame, "{drift}");
    let ended = frames.logged("Cutter/drift:ended").unwrap();
    let lasts = std::f64::consts::PI * 0.6_f64.sqrt();
    assert!(
        (ended - drift - lasts).abs() <= 2.0 * frame,
        "{drift} to {ended}"
    );
    let back = started(&frames, "Cutter/recentre").unwrap();
    assert!(
        (back - ended - 1.0).abs() <= 2.0 * frame,
        "{ended} to {back}"
    );
    // The van's profile from 10 s: 1 s, 0.5 s, then 8 to 6 m/s at the 2 m/s² deceleration.
    let cruise = started(&frames, "Cutter/cruise").unwrap();
    let done = frames.logged("Cutter/cruise:ended").unwrap();
    assert!((cruise - 10.0).abs() <= frame, "{cruise}");
    assert!((done - cruise - 2.5).abs() <= frame, "{cruise} to {done}");
    let o = carfollow(&[
        "check",
        file.to_str().unwrap(),
        "--param",
        "ProfileMode=follow",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("followingMode"), "{}", stderr(&o));
    // A continuous offset never ends: nothing may wait for its end.
    let o = carfollow(&[
        "check",
        file.to_str().unwrap(),
        "--param",
        "Continuous=true",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("never ends"), "{}", stderr(&o));
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
    let line = 1 + std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .position(|l| l.contains("<StopTrigger><ConditionGroup><Condition name=\"later\""))
        .unwrap();
    let o = carfollow(&["check", path.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("unsupported act stop trigger") && e.contains(&format!("mutant.xosc:{line}")),
        "{e}"
    );
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
    let line = 1 + std::fs::read_to_string(&file)
        .unwrap()
        .lines()
        .position(|l| l.contains("<ActivateControllerAction"))
        .unwrap();
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
