//! `carfollow export`: a scenario written as OpenSCENARIO on an OpenDRIVE road, which
//! `carfollow import` reads back as a scenario that runs bit for bit as the original
//! does; a failed export writes nothing; ASAM's Quality Checker finds no issue in the files
//! (when it is installed: `.ci/install` puts it in `target/qc-venv`). Run with
//! `cargo test --release -p sim --test cli_export`.

mod osc_common;

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

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exports the shipped scenario `name` (with `set`) into `dir`, returning the `.xosc`.
fn export(name: &str, dir: &Path, set: &[&str]) -> PathBuf {
    let file = scenarios().join(format!("{name}.toml"));
    let mut args = vec![
        "export",
        file.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
    ];
    for s in set {
        args.extend(["--set", s]);
    }
    let o = carfollow(&args);
    assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
    dir.join(format!("{name}.xosc"))
}

/// `frames.csv` of a run of `scenario` (with `set`) into `out`.
fn frames(scenario: &Path, out: &Path, set: &[&str]) -> String {
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
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    std::fs::read_to_string(out.join("frames.csv")).unwrap()
}

#[test]
fn an_exported_scenario_imported_back_runs_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    // Straight and curved roads (arcs; an OpenDRIVE road of spirals and arcs; one of
    // paramPoly3s with a median and lanes of their own widths), a cut-in, a
    // cut-out, fog, and Euro NCAP's braking target; a few seconds each; and the cut-in
    // from the oncoming side, driven with the road.
    let oncoming = ["actors.0.lane=1", "actors.0.offset_m=3.5"];
    for (k, (name, seconds, more)) in [
        ("nist-grounds", "6", &[][..]),
        ("opendrive-curves", "6", &[]),
        ("divided-highway", "6", &[]),
        ("cut-in", "10", &[]),
        ("cut-out", "8", &[]),
        ("fog", "5", &[]),
        ("ncap-ccrb", "5", &[]),
        ("cut-in", "14", &oncoming[..]),
    ]
    .into_iter()
    .enumerate()
    {
        let duration = format!("duration_s={seconds}");
        let set: Vec<&str> = std::iter::once(duration.as_str())
            .chain(more.iter().copied())
            .collect();
        let out = dir.path().join(format!("{k}-{name}"));
        let xosc = export(name, &out.join("export"), &set);
        let toml = out.join("imported").join(format!("{name}.toml"));
        std::fs::create_dir_all(toml.parent().unwrap()).unwrap();
        let o = carfollow(&[
            "import",
            xosc.to_str().unwrap(),
            "-o",
            toml.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
        let original = frames(
            &scenarios().join(format!("{name}.toml")),
            &out.join("original"),
            &set,
        );
        let imported = frames(&toml, &out.join("round-trip"), &[]);
        assert!(original.lines().count() > 10, "{name}: too short a run");
        assert!(
            original == imported,
            "{name}: frames.csv of the round trip differs"
        );
        // And the .xosc itself runs as the original.
        let direct = frames(&xosc, &out.join("direct"), &[]);
        assert!(
            original == direct,
            "{name}: frames.csv of the .xosc differs"
        );
    }
}

#[test]
fn the_files_hold_what_esmini_reads() {
    let dir = tempfile::tempdir().unwrap();
    let xosc = export("cut-in", dir.path(), &[]);
    let text = std::fs::read_to_string(&xosc).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "OpenSCENARIO");
    let find = |name: &'static str| doc.descendants().filter(move |n| n.has_tag_name(name));
    let header = find("FileHeader").next().unwrap();
    assert_eq!(header.attribute("revMajor"), Some("1"));
    assert_eq!(header.attribute("revMinor"), Some("2"));
    let logic = find("LogicFile").next().unwrap();
    let xodr = dir.path().join(logic.attribute("filepath").unwrap());
    assert!(xodr.is_file(), "{}", xodr.display());
    let names: Vec<&str> = find("ScenarioObject")
        .map(|o| o.attribute("name").unwrap())
        .collect();
    assert_eq!(names, ["Ego", "Lead", "van"]);
    for object in find("ScenarioObject") {
        let dims = object
            .descendants()
            .find(|n| n.has_tag_name("Dimensions"))
            .unwrap();
        for a in ["width", "length", "height"] {
            assert!(dims.attribute(a).unwrap().parse::<f64>().unwrap() > 1.0);
        }
    }
    // Each vehicle placed on a lane with a speed; the cut-in a lane change on a gap.
    assert_eq!(find("Private").count(), 3);
    assert_eq!(find("LanePosition").count(), 3);
    assert!(find("LaneChangeAction").count() >= 1);
    assert!(find("RelativeDistanceCondition").count() >= 1);
    assert!(find("EnvironmentAction").count() == 1);
    let stop = find("StopTrigger").next().unwrap();
    let t = stop
        .descendants()
        .find(|n| n.has_tag_name("SimulationTimeCondition"))
        .unwrap();
    assert_eq!(t.attribute("value"), Some("30"));
    // carfollow's own settings as parameters of the `carfollow.` prefix.
    assert!(find("ParameterDeclaration")
        .all(|p| p.attribute("name").unwrap().starts_with("carfollow.")));
    assert!(find("ParameterDeclaration")
        .any(|p| p.attribute("name") == Some("carfollow.chase.controller")));
    let road = std::fs::read_to_string(&xodr).unwrap();
    let road = roxmltree::Document::parse(&road).unwrap();
    let h = road
        .descendants()
        .find(|n| n.has_tag_name("header"))
        .unwrap();
    assert_eq!(h.attribute("revMinor"), Some("7"));
    let lanes = road
        .descendants()
        .filter(|n| n.has_tag_name("lane"))
        .count();
    assert_eq!(lanes, 5, "two driving lanes each way and the centre lane");
    // The same scenario exports the same files, byte for byte.
    let again = tempfile::tempdir().unwrap();
    let xosc2 = export("cut-in", again.path(), &[]);
    assert_eq!(text, std::fs::read_to_string(xosc2).unwrap());
}

#[test]
fn a_failed_export_writes_nothing_and_says_why_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    let text = std::fs::read_to_string(scenarios().join("nist-grounds.toml"))
        .unwrap()
        .replace("duration_s = ", "duration_s = -");
    std::fs::write(&bad, text).unwrap();
    let out = dir.path().join("out");
    let o = carfollow(&["export", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("duration_s"), "{}", stderr(&o));
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().next().is_none());
    // A `--set` that does not apply, and a file that is not there.
    let nist = scenarios().join("nist-grounds.toml");
    for args in [
        vec![
            "export",
            nist.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "nonsense",
        ],
        vec!["export", "no-such.toml", "-o", out.to_str().unwrap()],
        vec!["export", nist.to_str().unwrap()],
    ] {
        let o = carfollow(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&o)
                .trim()
                .lines()
                .next()
                .unwrap()
                .starts_with("error"),
            "{}",
            stderr(&o)
        );
        assert!(!out.exists() || std::fs::read_dir(&out).unwrap().next().is_none());
    }
    // An output folder that cannot be made (a file stands in its way).
    let blocked = dir.path().join("blocked");
    std::fs::write(&blocked, "").unwrap();
    let o = carfollow(&[
        "export",
        nist.to_str().unwrap(),
        "-o",
        blocked.join("x").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
}

/// The Python of the virtual environment holding ASAM's Quality Checker:
/// `CARFOLLOW_QC_VENV`, else `target/qc-venv` (where `.ci/install` puts it).
fn qc_python() -> Option<PathBuf> {
    let venv = std::env::var_os("CARFOLLOW_QC_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/qc-venv"));
    let python = venv.join("bin/python");
    let installed =
        venv.join("bin/qc_openscenario").is_file() && venv.join("bin/qc_opendrive").is_file();
    (python.is_file() && installed).then_some(python)
}

#[test]
fn asams_quality_checker_finds_no_issue() {
    let Some(python) = qc_python() else {
        eprintln!(
            "SKIPPED: ASAM's Quality Checker is not installed (run .ci/install, or \
             `python3 -m venv target/qc-venv && target/qc-venv/bin/pip install \
             asam-qc-openscenarioxml asam-qc-opendrive`)"
        );
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for name in [
        "nist-grounds",
        "opendrive-curves",
        "cut-in",
        "cut-out",
        "fog",
        "ncap-ccrb",
        "weave",
    ] {
        let xosc = export(name, &dir.path().join(name), &[]);
        files.push(xosc.with_extension("xodr"));
        files.push(xosc);
    }
    // An event judged once a latched condition holds, written in an act of its own.
    let latched = "actors.0.events.0.trigger={ all = [{ gap_m = 30.0, to = \"chase\", \
                   latched = true }, { time_gap_s = 1.0, to = \"chase\" }] }";
    let xosc = export("cut-in", &dir.path().join("latched"), &[latched]);
    assert!(std::fs::read_to_string(&xosc)
        .unwrap()
        .contains("<Act name=\"cut-in-act\">"));
    files.push(xosc.with_extension("xodr"));
    files.push(xosc);
    // An actor that starts on the oncoming side, driving with the road.
    let xosc = export(
        "cut-in",
        &dir.path().join("oncoming"),
        &["actors.0.lane=1", "actors.0.offset_m=3.5"],
    );
    files.push(xosc);
    // Waits for an event's start and end, and a collision (esmini's
    // `alks_r157_cut_in_quick_brake`, imported and written again): each event's name,
    // and its action's, resolve to one element.
    let r157 = osc_common::data().join("esmini/xosc/alks_r157_cut_in_quick_brake.xosc");
    let toml = dir.path().join("r157/r157.toml");
    osc_common::import_to(&r157, &toml);
    let (xosc, text) = osc_common::export_to(&toml, &dir.path().join("r157/out"));
    for said in ["startTransition", "endTransition", "<CollisionCondition>"] {
        assert!(text.contains(said), "{said}: {text}");
    }
    files.push(xosc);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/qc/asam_qc.py");
    let o = Command::new(python)
        .arg(script)
        .args(&files)
        .output()
        .unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(o.status.code(), Some(0), "{said}");
    assert_eq!(said.matches("checkers of").count(), files.len(), "{said}");
}

/// `cut-in.toml` with `from` (which it must hold) made `to`, the lead's events
/// `lead_events` appended and its target named by its full path, exported with
/// `--set duration_s=SECONDS` and imported back: the `.xosc` written, and `frames.csv` of
/// the original run for that long and of the imported scenario.
fn round_trip(from: &str, to: &str, lead_events: &str, seconds: &str) -> [String; 3] {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scenarios().join("cut-in.toml")).unwrap();
    assert!(text.contains(from));
    let targets = scenarios().join("targets/");
    let text = text
        .replace(from, to)
        .replace("\"targets/", &format!("\"{}", targets.to_str().unwrap()))
        + lead_events;
    let original = dir.path().join("original.toml");
    std::fs::write(&original, text).unwrap();
    let export = dir.path().join("export");
    let duration = format!("duration_s={seconds}");
    let o = carfollow(&[
        "export",
        original.to_str().unwrap(),
        "-o",
        export.to_str().unwrap(),
        "--set",
        &duration,
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let xosc = export.join("cut-in.xosc");
    let written = std::fs::read_to_string(&xosc).unwrap();
    let toml = dir.path().join("imported/cut-in.toml");
    let o = carfollow(&[
        "import",
        xosc.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let before = frames(&original, &dir.path().join("original"), &[&duration]);
    let after = frames(&toml, &dir.path().join("round-trip"), &[]);
    [written, before, after]
}

/// Speed and standstill triggers go out as `SpeedCondition` and `StandStillCondition` of the
/// vehicle they watch, and come back as they were: the round trip runs bit for bit.
#[test]
fn speed_and_standstill_triggers_round_trip_exactly() {
    let [written, before, after] = round_trip(
        "trigger = { gap_m = 12.0, to = \"chase\" }\naction = { lane = 1, duration_s = 2.5, shape = \"sinusoidal\" }\n",
        "trigger = { speed_mps = 5.0, of = \"lead\" }\naction = { speed_mps = 6.0, rate_mps2 = 2.0 }\n\n\
         [[actors.events]]\nname = \"halt\"\ntrigger = { standstill_s = 2.0, of = \"lead\", delay_s = 0.5 }\n\
         action = { stop = true, decel_mps2 = 3.0 }\n",
        "\n[[lead.events]]\nname = \"brake\"\ntrigger = { time_s = 2.0 }\n\
         action = { stop = true, decel_mps2 = 4.0 }\n\n\
         [[lead.events]]\nname = \"creep\"\ntrigger = { standstill_s = 3.0 }\n\
         action = { speed_mps = 3.0, rate_mps2 = 1.0 }\n\n\
         [[lead.events]]\nname = \"hurry\"\ntrigger = { speed_mps = 12.0, rule = \"greater\", of = \"van\" }\n\
         action = { speed_mps = 4.0, rate_mps2 = 1.0 }\n",
        "12",
    );
    for expected in [
        "<SpeedCondition value=\"5\" rule=\"lessThan\"/>",
        "<StandStillCondition duration=\"2\"/>",
        "<StandStillCondition duration=\"3\"/>",
        "rule=\"greaterThan\"",
    ] {
        assert!(written.contains(expected), "{expected} not in:\n{written}");
    }
    assert!(before.contains("van/halt:started") && before.contains("lead/creep:started"));
    assert!(before == after, "frames.csv of the round trip differs");
}

/// Triggers of several conditions go out as OpenSCENARIO writes them, any of condition
/// groups each all of conditions (an `all` of an `any` multiplied out), each member's
/// delay on its condition, and an offset as a `LaneOffsetAction`; they come back as a
/// trigger that holds at the same steps and the same offset: the round trip runs bit for
/// bit.
#[test]
fn triggers_of_several_conditions_round_trip_exactly() {
    let [written, before, after] = round_trip(
        "trigger = { gap_m = 12.0, to = \"chase\" }\n",
        "trigger = { all = [{ any = [{ gap_m = 12.0, to = \"chase\" }, { time_s = 25.0 }] }, \
         { time_s = 4.0, delay_s = 1.5 }] }\n",
        "\n[[lead.events]]\nname = \"brake\"\n\
         trigger = { any = [{ time_s = 9.0 }, { distance_m = 2000.0 }] }\n\
         action = { speed_mps = 11.0, rate_mps2 = 1.0 }\n\n\
         [[lead.events]]\nname = \"edge\"\ntrigger = { time_s = 3.0 }\n\
         action = { offset_m = 0.4, lateral_accel_mps2 = 0.3, shape = \"sinusoidal\" }\n\n\
         [[lead.events]]\nname = \"wave\"\ntrigger = { time_s = 11.0 }\n\
         action = { profile = [{ speed_mps = 9.0, rate_mps2 = 1.5 }, \
         { speed_mps = 10.0, duration_s = 1.0 }, { speed_mps = 8.0, rate_mps2 = 2.0 }] }\n",
        "16",
    );
    for expected in [
        "name=\"cut-in-1-1\"",
        "name=\"cut-in-2-2\" delay=\"1.5\"",
        "name=\"brake-2-1\"",
        "<AbsoluteTargetLaneOffset value=\"0.4\"/>",
        "<SpeedProfileEntry speed=\"8\" time=\"1\"/>",
    ] {
        assert!(written.contains(expected), "{expected} not in:\n{written}");
    }
    assert!(!written.contains("name=\"cut-in-3-1\""), "{written}");
    assert!(
        before.contains("van/cut-in:started")
            && before.contains("lead/brake:started")
            && before.contains("lead/edge:ended")
            && before.contains("lead/wave:ended")
    );
    assert!(before == after, "frames.csv of the round trip differs");
}

/// An event judged once a latched condition holds goes out in an act of its own, which
/// that condition starts, its own trigger the rest; it comes back as it went: the round
/// trip runs bit for bit.
#[test]
fn a_latched_member_round_trips_as_an_acts_start() {
    let [written, before, after] = round_trip(
        "trigger = { gap_m = 12.0, to = \"chase\" }\n",
        "trigger = { all = [{ gap_m = 30.0, to = \"chase\", latched = true }, \
         { time_gap_s = 1.0, to = \"chase\" }] }\n",
        "",
        "16",
    );
    for expected in ["<Act name=\"cut-in-act\">", "name=\"cut-in-act-start\""] {
        assert!(written.contains(expected), "{expected} not in:\n{written}");
    }
    assert!(before.contains("van/cut-in:started"));
    assert!(before == after, "frames.csv of the round trip differs");
}

/// An event that repeats goes out with its runs as `maximumExecutionCount`: `max_runs`
/// as it is, no limit as the most runs the duration allows (one a 120 Hz step, and one);
/// both come back running at the same steps: the round trip runs bit for bit.
#[test]
fn repeating_events_round_trip_exactly() {
    let [written, before, after] = round_trip(
        "trigger = { gap_m = 12.0, to = \"chase\" }\n",
        "trigger = { gap_m = 12.0, to = \"chase\" }\n",
        "\n[[lead.events]]\nname = \"nudge\"\ntrigger = { time_s = 2.0 }\n\
         action = { speed_mps = 13.0, duration_s = 1.0 }\nrepeat = true\nmax_runs = 3\n\n\
         [[lead.events]]\nname = \"sway\"\ntrigger = { time_s = 5.0 }\n\
         action = { offset_m = 0.3, lateral_accel_mps2 = 0.5, shape = \"sinusoidal\" }\n\
         repeat = true\n",
        "12",
    );
    for expected in [
        "<Event name=\"nudge\" priority=\"parallel\" maximumExecutionCount=\"3\">",
        "<Event name=\"sway\" priority=\"parallel\" maximumExecutionCount=\"1441\">",
        "<Event name=\"cut-in\" priority=\"parallel\" maximumExecutionCount=\"1\">",
    ] {
        assert!(written.contains(expected), "{expected} not in:\n{written}");
    }
    assert_eq!(before.matches("lead/nudge:started").count(), 3);
    assert!(before.matches("lead/sway:started").count() >= 2);
    assert!(before == after, "frames.csv of the round trip differs");
}
