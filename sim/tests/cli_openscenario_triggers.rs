//! OpenSCENARIO conditions through the command line: speed, standstill, reach-position,
//! relative-speed and relative-distance conditions, condition groups and several
//! triggering entities are imported as carfollow's triggers and fire as written. Run with
//! `cargo test --release -p sim --test cli_openscenario_triggers`.

mod osc_common;

use osc_common::*;
use std::path::{Path, PathBuf};

#[test]
fn speed_and_standstill_conditions_are_imported_and_fire_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let file = data().join("speed-standstill.xosc");
    let toml = dir.path().join("speed-standstill.toml");
    let text = import_to(&file, &toml);
    for expected in [
        "speed_mps = 5.0\nof = \"lead\"\nrule = \"less\"",
        "standstill_s = 2.0\nof = \"lead\"\ndelay_s = 0.5",
        "standstill_s = 3.0\nrising = true\n",
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
    let cases: [(String, String, usize, &str); 5] = [
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

/// A relative distance between reference points (`freespace="false"`, esmini's
/// `drive_when_close`) is imported as a spacing trigger (`spacing_m`), rear axle to rear
/// axle: the same value fires later than as a gap, bumper to bumper, since the spacing is the
/// longer by the chase's length ahead of its axle and the van's behind its own; and it is
/// exported back as written.
#[test]
fn a_distance_between_reference_points_is_a_spacing() {
    let gap = "freespace=\"true\" value=\"$CutInGap\"";
    let (dir, path) = mutant(|text| {
        assert!(text.contains(gap));
        text.replace(gap, "freespace=\"false\" value=\"$CutInGap\"")
    });
    let toml = dir.path().join("imported/spacing.toml");
    let text = import_to(&path, &toml);
    assert!(
        text.contains("spacing_m = 12.0") && !text.contains("gap_m = 12.0"),
        "{text}"
    );
    let set = ["--set", "duration_s=16"];
    let started = |frames: &str| {
        let f = Frames::parse(frames);
        f.logged("cut-in:started")
            .unwrap_or_else(|| panic!("the cut-in never started"))
    };
    let as_gap = started(&frames_of(
        &data().join("cut-in.xosc"),
        &dir.path().join("g"),
        &set,
    ));
    let from_xosc = frames_of(&path, &dir.path().join("x"), &set);
    let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
    assert!(
        from_xosc == from_toml,
        "the imported scenario runs differently"
    );
    let as_spacing = started(&from_xosc);
    assert!(
        as_spacing > as_gap + 0.1,
        "spacing fired at {as_spacing} s, the gap at {as_gap} s"
    );
    let (_, written) = export_to(&toml, &dir.path().join("export"));
    assert!(
        written.contains("freespace=\"false\"") && written.contains("value=\"12\""),
        "{written}"
    );
}

/// A time headway between reference points (`freespace="false"`, as esmini's `cut-in`
/// writes it) is imported as a time gap measured on the spacing (`between_axles`): the
/// same headway fires later than bumper to bumper, the spacing being the longer; the
/// imported scenario runs as the file does, and is exported back as written.
#[test]
fn a_headway_between_reference_points_is_measured_on_the_spacing() {
    let gap = "<RelativeDistanceCondition entityRef=\"Cutter\" relativeDistanceType=\"longitudinal\" freespace=\"true\" value=\"$CutInGap\" rule=\"lessThan\"/>";
    let headway = |freespace: &str| {
        format!("<TimeHeadwayCondition entityRef=\"Cutter\" relativeDistanceType=\"longitudinal\" coordinateSystem=\"road\" freespace=\"{freespace}\" value=\"0.8\" rule=\"lessThan\"/>")
    };
    let (dir, bumpers) = mutant(|text| {
        assert!(text.contains(gap));
        text.replace(gap, &headway("true"))
    });
    let (_axles_dir, axles) = mutant(|text| text.replace(gap, &headway("false")));
    let toml = dir.path().join("imported/headway.toml");
    let text = import_to(&axles, &toml);
    assert!(
        text.contains("time_gap_s = 0.8") && text.contains("between_axles = true"),
        "{text}"
    );
    let set = ["--set", "duration_s=16"];
    let started = |frames: &str| {
        Frames::parse(frames)
            .logged("cut-in:started")
            .unwrap_or_else(|| panic!("the cut-in never started"))
    };
    let on_gap = started(&frames_of(&bumpers, &dir.path().join("g"), &set));
    let from_xosc = frames_of(&axles, &dir.path().join("x"), &set);
    let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
    assert!(
        from_xosc == from_toml,
        "the imported scenario runs differently"
    );
    let on_spacing = started(&from_xosc);
    assert!(
        on_spacing > on_gap + 0.1,
        "on the spacing it fired at {on_spacing} s, on the gap at {on_gap} s"
    );
    let (_, written) = export_to(&toml, &dir.path().join("export"));
    let condition = written
        .lines()
        .find(|l| l.contains("<TimeHeadwayCondition"))
        .unwrap_or_else(|| panic!("no headway written: {written}"));
    assert!(condition.contains("freespace=\"false\""), "{condition}");
}

/// An event's priority `parallel` is carfollow's own way (a new action ends only the
/// running action of its kind): read as written, it runs as `overwrite` does here, and
/// with no warning; a maneuver of speed and lane events under `overwrite`, which the
/// standard would have end each other, is run the same way and said in one warning line.
#[test]
fn parallel_events_run_side_by_side_and_an_override_says_it_does_too() {
    let (dir, parallel) =
        mutant(|text| text.replace("priority=\"overwrite\"", "priority=\"parallel\""));
    let cut_in = data().join("cut-in.xosc");
    let warned = |path: &std::path::Path| {
        let o = carfollow(&["check", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        stderr(&o)
            .lines()
            .filter(|l| l.contains("run side by side"))
            .count()
    };
    assert_eq!(warned(&cut_in), 1);
    assert_eq!(warned(&parallel), 0);
    let set = ["--set", "duration_s=16"];
    assert!(
        frames_of(&cut_in, &dir.path().join("o"), &set)
            == frames_of(&parallel, &dir.path().join("p"), &set),
        "parallel runs differently"
    );
}

/// A `RelativeTargetSpeed` (esmini's `cut-in` family sets its overtaker's speed so) is
/// imported as a speed relative to the vehicle it names (`speed_of`, with `speed_factor`
/// or a difference in `speed_mps`, and `continuous`), runs as the file does, differs from
/// the absolute speed it replaced, and is exported back as written.
#[test]
fn a_relative_target_speed_is_a_speed_of_another_vehicle() {
    let absolute = "<AbsoluteTargetSpeed value=\"5\"/>";
    let relative = "<RelativeTargetSpeed entityRef=\"Ego\" value=\"0.5\" speedTargetValueType=\"factor\" continuous=\"true\"/>";
    let (dir, path) = mutant(|text| {
        assert!(text.contains(absolute));
        text.replace(absolute, relative)
    });
    let toml = dir.path().join("imported/relative.toml");
    let text = import_to(&path, &toml);
    for field in [
        "speed_of = \"chase\"",
        "speed_factor = 0.5",
        "continuous = true",
    ] {
        assert!(text.contains(field), "{field} not in {text}");
    }
    let set = ["--set", "duration_s=20"];
    let from_xosc = frames_of(&path, &dir.path().join("x"), &set);
    let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
    assert!(
        from_xosc == from_toml,
        "the imported scenario runs differently"
    );
    let as_written = frames_of(&data().join("cut-in.xosc"), &dir.path().join("a"), &set);
    assert!(
        from_xosc != as_written,
        "the relative speed changed nothing"
    );
    let (xosc, written) = export_to(&toml, &dir.path().join("export"));
    let target = written
        .lines()
        .find(|l| l.contains("<RelativeTargetSpeed"))
        .unwrap_or_else(|| panic!("no relative speed written: {written}"));
    for attribute in [
        "entityRef=\"Ego\"",
        "value=\"0.5\"",
        "speedTargetValueType=\"factor\"",
        "continuous=\"true\"",
    ] {
        assert!(target.contains(attribute), "{attribute} not in {target}");
    }
    assert!(
        frames_of(&xosc, &dir.path().join("e"), &set) == from_toml,
        "the exported file runs differently"
    );
}

/// A condition's `falling` and `risingOrFalling` edges are imported as `falling` (with
/// `rising` for both), run as the file does, and are exported back as written.
#[test]
fn falling_edges_are_imported_and_exported() {
    let rising = "name=\"close\" delay=\"0\" conditionEdge=\"rising\"";
    for (edge, fields) in [
        ("falling", &["falling = true"][..]),
        ("risingOrFalling", &["rising = true", "falling = true"][..]),
    ] {
        let (dir, path) = mutant(|text| {
            assert!(text.contains(rising));
            text.replace(
                rising,
                &rising.replace("\"rising\"", &format!("\"{edge}\"")),
            )
        });
        let toml = dir.path().join("imported/edge.toml");
        let text = import_to(&path, &toml);
        for field in fields {
            assert!(text.contains(field), "{edge}: {field} not in {text}");
        }
        let set = ["--set", "duration_s=12"];
        let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
        assert!(
            frames_of(&path, &dir.path().join("x"), &set) == from_toml,
            "{edge}: the imported scenario runs differently"
        );
        let (xosc, written) = export_to(&toml, &dir.path().join("export"));
        assert!(
            written.contains(&format!("conditionEdge=\"{edge}\"")),
            "{edge}: {written}"
        );
        assert!(
            frames_of(&xosc, &dir.path().join("e"), &set) == from_toml,
            "{edge}: the exported file runs differently"
        );
    }
}

/// A wait for an act's (or a story's, maneuver group's, maneuver's) start or running state
/// (esmini's `cut-in` starts its cutter's speed on its act's `startTransition`) holds from
/// the first step, when every act starts here: with a delay of 1 s the event starts at 1 s.
/// A wait for an act's skipping, for the end of an act the waiting event is in, or for an
/// element the file does not have, is refused in one line.
#[test]
fn a_wait_for_an_acts_start_holds_from_the_first_step() {
    let after = r#"<StoryboardElementStateCondition storyboardElementType="event" storyboardElementRef="cut-in" state="endTransition"/>"#;
    let wait = |kind: &str, name: &str, state: &str| {
        let on = format!(
            r#"<StoryboardElementStateCondition storyboardElementType="{kind}" storyboardElementRef="{name}" state="{state}"/>"#
        );
        mutant(move |text| {
            assert!(text.contains(after));
            text.replace(after, &on)
        })
    };
    for (kind, name, state) in [
        ("act", "CutInAct", "startTransition"),
        ("story", "CutInStory", "runningState"),
        ("maneuver", "CutInManeuver", "startTransition"),
    ] {
        let (dir, path) = wait(kind, name, state);
        let frames = frames_of(&path, &dir.path().join("x"), &["--set", "duration_s=3"]);
        let at = Frames::parse(&frames).logged("brake:started");
        assert_eq!(at, Some(1.0), "{kind} {state}");
    }
    for (kind, name, state, says) in [
        (
            "act",
            "CutInAct",
            "skipTransition",
            "carfollow waits for an element's end",
        ),
        // The brake is in the act: it would wait for its own end.
        ("act", "CutInAct", "endTransition", "is this event itself"),
        (
            "act",
            "NoSuchAct",
            "startTransition",
            "no <Act> is named `NoSuchAct`",
        ),
    ] {
        let (_dir, path) = wait(kind, name, state);
        let o = carfollow(&["check", path.to_str().unwrap()]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.contains(says) && e.contains("mutant.xosc:"), "{e}");
    }
}

/// A reference qualified by the names around its element (`Event::Action`, up to
/// `Story::Act::ManeuverGroup::Maneuver::Event`) finds the same event as the bare name
/// does, and runs the same; a name two elements share must be qualified, and a
/// qualification the file does not have is refused, each in one line naming the file.
#[test]
fn a_qualified_reference_names_the_element_its_parents_place() {
    let after = r#"<StoryboardElementStateCondition storyboardElementType="event" storyboardElementRef="cut-in" state="endTransition"/>"#;
    let wait = |kind: &str, name: &str, twin_actions: bool| {
        let on = format!(
            r#"<StoryboardElementStateCondition storyboardElementType="{kind}" storyboardElementRef="{name}" state="endTransition"/>"#
        );
        mutant(move |text| {
            assert!(text.contains(after) && text.contains(r#"<Action name="BrakeAction">"#));
            let text = text.replace(after, &on);
            if twin_actions {
                text.replace(
                    r#"<Action name="BrakeAction">"#,
                    r#"<Action name="CutInAction">"#,
                )
            } else {
                text
            }
        })
    };
    let set = ["--set", "duration_s=12"];
    let (dir, plain) = wait("event", "cut-in", false);
    let bare = frames_of(&plain, &dir.path().join("bare"), &set);
    assert!(Frames::parse(&bare).logged("brake:started").is_some());
    for (kind, name, twins) in [
        ("action", "CutInAction", false),
        ("action", "cut-in::CutInAction", true),
        ("event", "CutInManeuver::cut-in", false),
        (
            "event",
            "CutInStory::CutInAct::CutInGroup::CutInManeuver::cut-in",
            false,
        ),
    ] {
        let (dir, path) = wait(kind, name, twins);
        let frames = frames_of(&path, &dir.path().join("x"), &set);
        assert!(frames == bare, "{kind} `{name}` runs differently");
    }
    for (kind, name, twins, says) in [
        (
            "action",
            "CutInAction",
            true,
            "more than one <Action> is named `CutInAction`",
        ),
        (
            "event",
            "CutInAct::cut-in",
            false,
            "no <Event> is named `CutInAct::cut-in`",
        ),
        (
            "event",
            "OtherStory::CutInAct::CutInGroup::CutInManeuver::cut-in",
            false,
            "no <Event> is named",
        ),
    ] {
        let (_dir, path) = wait(kind, name, twins);
        let o = carfollow(&["check", path.to_str().unwrap()]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.contains(says) && e.contains("mutant.xosc:"), "{e}");
    }
}

/// A wait for an event's start (`startTransition`; esmini's `alks_r157_cut_in_quick_brake`
/// brakes a set time after its lane change starts) is a `started` trigger: the brake starts
/// the condition's delay after the cut-in starts, while the cut-in still runs, and 2.5 s
/// (the cut-in's length) sooner than the wait for its end; imported, exported and read back,
/// each runs bit for bit as the file. A wait for an event's running state is refused.
#[test]
fn a_wait_for_an_events_start_is_a_started_trigger() {
    let end = r#"storyboardElementRef="cut-in" state="endTransition""#;
    let set = ["--set", "duration_s=12"];
    let (dir, path) = mutant(|text| {
        assert!(text.contains(end));
        text.replace(end, &end.replace("endTransition", "startTransition"))
    });
    let frames = Frames::parse(&frames_of(&path, &dir.path().join("x"), &set));
    let (started, brake) = (
        frames.logged("cut-in:started"),
        frames.logged("brake:started"),
    );
    let (started, brake) = (started.unwrap(), brake.expect("the brake starts"));
    assert!(
        (brake - started - 1.0).abs() <= 1.0 / 15.0 + 1e-9,
        "{started} {brake}"
    );
    let (edir, plain) = mutant(|text| text.to_string());
    let ended = Frames::parse(&frames_of(&plain, &edir.path().join("x"), &set));
    let after_end = ended.logged("brake:started").expect("the brake starts");
    assert!(
        (after_end - brake - 2.5).abs() <= 1.0 / 15.0 + 1e-9,
        "{after_end} {brake}"
    );

    let toml = dir.path().join("imported/start.toml");
    let text = import_to(&path, &toml);
    assert!(text.contains(r#"started = "cut-in""#), "{text}");
    let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
    assert!(frames_of(&path, &dir.path().join("x2"), &set) == from_toml);
    let (xosc, written) = export_to(&toml, &dir.path().join("export"));
    assert!(written.contains(r#"state="startTransition""#), "{written}");
    assert!(frames_of(&xosc, &dir.path().join("e"), &set) == from_toml);

    let (_dir, running) =
        mutant(|text| text.replace(end, &end.replace("endTransition", "runningState")));
    let o = carfollow(&["check", running.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.contains("an event, startTransition") && e.contains("mutant.xosc:"),
        "{e}"
    );
}
