//! An OpenSCENARIO `StopTrigger` with conditions other than a simulation time: each such
//! condition group becomes an event whose action ends the run (`end_run`), the run's last
//! frame the one whose physics the event starts in; `summary.json` names it; the imported
//! and exported files run the same. Run with
//! `cargo test --release -p sim --test cli_stop_trigger`.

mod osc_common;

use osc_common::*;
use std::path::Path;

/// The cut-in test file's `StopTrigger` at 25 s, with `groups` added after it.
fn with_stop_groups(groups: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    mutant(|text| {
        let end = "</ConditionGroup></StopTrigger>";
        assert!(text.contains(end));
        text.replace(end, &format!("</ConditionGroup>{groups}</StopTrigger>"))
    })
}

/// A condition group of one entity condition of `entity`.
fn entity_group(name: &str, entity: &str, condition: &str) -> String {
    format!(
        "<ConditionGroup><Condition name=\"{name}\" delay=\"0\" conditionEdge=\"none\">\
         <ByEntityCondition><TriggeringEntities triggeringEntitiesRule=\"any\">\
         <EntityRef entityRef=\"{entity}\"/></TriggeringEntities>\
         <EntityCondition>{condition}</EntityCondition></ByEntityCondition>\
         </Condition></ConditionGroup>"
    )
}

/// The library's `cut-in` scenario, its target's path made absolute so that it runs from
/// anywhere.
fn cut_in_toml() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios");
    std::fs::read_to_string(root.join("cut-in.toml"))
        .unwrap()
        .replace(
            "target = \"targets/",
            &format!("target = \"{}/targets/", root.display()),
        )
}

fn summary(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_stop_condition_ends_the_run_at_the_frame_it_holds() {
    // The cutter brakes to 5 m/s after its cut-in: the run ends once it is below 6 m/s.
    // The ego's standstill, about the chase, goes on the lead's events and never holds.
    let groups = entity_group(
        "slow",
        "Cutter",
        "<SpeedCondition value=\"6\" rule=\"lessThan\"/>",
    ) + &entity_group("parked", "Ego", "<StandStillCondition duration=\"1\"/>")
        + &entity_group(
            "road-end",
            "Lead car",
            "<EndOfRoadCondition duration=\"2\"/>",
        );
    let (dir, file) = with_stop_groups(&groups);
    let toml = dir.path().join("stop.toml");
    let text = import_to(&file, &toml);
    for expected in [
        "[[actors.events]]\nname = \"stop\"\n\n[actors.events.trigger]\nspeed_mps = 6.0\nrule = \"less\"",
        "[[lead.events]]\nname = \"stop\"\n\n[lead.events.trigger]\nstandstill_s = 1.0\nof = \"chase\"",
        "end_run = true",
        "[[lead.events]]\nname = \"stop-2\"\n\n[lead.events.trigger]\nroad_end_s = 2.0\n",
    ] {
        assert!(text.contains(expected), "{expected:?} not in:\n{text}");
    }
    assert!(text.contains("duration_s = 25.0"), "{text}");
    let csv = frames_of(&file, &dir.path().join("xosc"), &[]);
    assert!(
        csv == frames_of(&toml, &dir.path().join("toml"), &[]),
        "the imported scenario runs differently"
    );
    let frames = Frames::parse(&csv);
    let rows = &frames.rows;
    let last_t = frames.num(rows.last().unwrap(), "t_s");
    let ended = summary(&dir.path().join("xosc"))["ended_by"].clone();
    assert_eq!(ended["vehicle"], "Cutter", "{ended}");
    assert_eq!(ended["event"], "stop", "{ended}");
    let t = ended["t_s"].as_f64().unwrap();
    // The last frame is the one whose physics (to the next frame) holds the end.
    assert!(
        last_t <= t && t < last_t + 1.0 / 15.0,
        "{t} after the last frame {last_t}"
    );
    assert!(t < 24.0, "the run went on to {t} s");
    assert_eq!(frames.logged("Cutter/stop:started"), Some(last_t));
    // Exported again, each end event is a group of the StopTrigger, its condition as read.
    let (_, exported) = export_to(&toml, &dir.path().join("exported"));
    let stop = &exported[exported.find("<StopTrigger>").unwrap()..];
    assert_eq!(stop.matches("<ConditionGroup>").count(), 4, "{stop}");
    assert!(
        stop.contains("<EndOfRoadCondition duration=\"2\"/>"),
        "{stop}"
    );
    // With the duration given, the StopTrigger is not read: the run goes its length.
    let out = dir.path().join("set");
    let csv = frames_of(&file, &out, &["--set", "duration_s=20"]);
    let frames = Frames::parse(&csv);
    assert_eq!(frames.rows.len(), 300);
    assert!(summary(&out).get("ended_by").is_none());
}

#[test]
fn a_stop_trigger_without_a_time_runs_to_a_stated_limit() {
    let (_dir, file) = mutant(|text| {
        let a = text.find("<StopTrigger>").unwrap();
        let b = text.find("</StopTrigger>").unwrap();
        let group = entity_group(
            "slow",
            "Cutter",
            "<SpeedCondition value=\"6\" rule=\"lessThan\"/>",
        );
        format!("{}<StopTrigger>{group}{}", &text[..a], &text[b..])
    });
    let o = carfollow(&["check", file.to_str().unwrap()]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert_eq!(
        err.matches("<StopTrigger> gives no simulation time: the run ends when one of its conditions holds, or at 120 s").count(),
        1,
        "{err}"
    );
    assert!(String::from_utf8_lossy(&o.stdout).contains("120 s"));
}

#[test]
fn an_end_run_action_is_checked_like_any_other() {
    let dir = tempfile::tempdir().unwrap();
    let base = cut_in_toml();
    for (action, says) in [
        ("{ end_run = false }", "end_run` = false: write end_run = true"),
        (
            "{ end_run = true, duration_s = 1.0 }",
            "not for the run's end",
        ),
        (
            "{ end_run = true, lane = 1 }",
            "must give exactly one of lane, offset_m, speed_mps (or speed_factor), profile, stop, keep and end_run",
        ),
    ] {
        let path = dir.path().join("bad.toml");
        std::fs::write(
            &path,
            format!("{base}\n[[actors.events]]\nname = \"done\"\ntrigger = {{ time_s = 5.0 }}\naction = {action}\n"),
        )
        .unwrap();
        let o = carfollow(&["check", path.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{action}: {err}");
        assert!(err.contains(says), "{action}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

#[test]
fn an_end_run_event_exports_to_the_stop_trigger_and_runs_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("end.toml");
    let base = cut_in_toml();
    std::fs::write(
        &toml,
        format!("{base}\n[[actors.events]]\nname = \"done\"\ntrigger = {{ after = \"cut-in\", delay_s = 1.0 }}\naction = {{ end_run = true }}\n"),
    )
    .unwrap();
    let (xosc, text) = export_to(&toml, &dir.path().join("x"));
    let stop = &text[text.find("<StopTrigger>").unwrap()..];
    assert_eq!(stop.matches("<ConditionGroup>").count(), 2, "{stop}");
    assert!(
        stop.contains("storyboardElementRef=\"cut-in\" state=\"endTransition\""),
        "{stop}"
    );
    let csv = frames_of(&toml, &dir.path().join("toml"), &[]);
    assert!(csv == frames_of(&xosc, &dir.path().join("xosc"), &[]));
    let ended = summary(&dir.path().join("toml"))["ended_by"].clone();
    assert_eq!(ended["vehicle"], "van", "{ended}");
    assert!(ended["t_s"].as_f64().unwrap() < 20.0, "{ended}");
}

/// A wait for a story's, act's, maneuver group's or maneuver's end (esmini's `cut-in` stops
/// 5 s after its cutter's maneuver ends) is a wait for every event under it to have ended:
/// here the cutter's brake, the maneuver's last, so the run ends 2 s after the brake ends,
/// however the element is named. An element with an event of another vehicle is refused.
#[test]
fn a_wait_for_an_elements_end_is_a_wait_for_its_last_event() {
    let wait = |kind: &str, name: &str| {
        format!(
            "<ConditionGroup><Condition name=\"done\" delay=\"2\" conditionEdge=\"rising\">\
             <ByValueCondition><StoryboardElementStateCondition storyboardElementType=\"{kind}\" \
             storyboardElementRef=\"{name}\" state=\"endTransition\"/></ByValueCondition>\
             </Condition></ConditionGroup>"
        )
    };
    let mut ends = Vec::new();
    for (kind, name) in [
        ("maneuver", "CutInManeuver"),
        ("maneuverGroup", "CutInGroup"),
        ("act", "CutInStory::CutInAct"),
        ("story", "CutInStory"),
    ] {
        let (dir, file) = with_stop_groups(&wait(kind, name));
        let out = dir.path().join("x");
        let frames = Frames::parse(&frames_of(&file, &out, &[]));
        let braked = frames.logged("brake:ended").expect("the brake ends");
        let ended = summary(&out)["ended_by"].clone();
        assert_eq!(ended["vehicle"], "Cutter", "{kind}: {ended}");
        let t = ended["t_s"].as_f64().unwrap();
        assert!(
            (t - (braked + 2.0)).abs() < 0.07,
            "{kind}: {t} s, brake ended {braked} s"
        );
        ends.push(t);
    }
    assert!(ends.windows(2).all(|w| w[0] == w[1]), "{ends:?}");
    // The act with a maneuver group of the lead's besides: not one vehicle's events.
    let (_dir, file) = mutant(|text| {
        let lead = "<ManeuverGroup maximumExecutionCount=\"1\" name=\"LeadGroup\">\
            <Actors selectTriggeringEntities=\"false\"><EntityRef entityRef=\"Lead car\"/></Actors>\
            <Maneuver name=\"LeadManeuver\"><Event name=\"slow\" priority=\"parallel\">\
            <Action name=\"SlowAction\"><PrivateAction><LongitudinalAction><SpeedAction>\
            <SpeedActionDynamics dynamicsShape=\"step\" value=\"0\" dynamicsDimension=\"time\"/>\
            <SpeedActionTarget><AbsoluteTargetSpeed value=\"10\"/></SpeedActionTarget>\
            </SpeedAction></LongitudinalAction></PrivateAction></Action>\
            <StartTrigger><ConditionGroup><Condition name=\"t\" delay=\"0\" conditionEdge=\"none\">\
            <ByValueCondition><SimulationTimeCondition value=\"3\" rule=\"greaterThan\"/></ByValueCondition>\
            </Condition></ConditionGroup></StartTrigger></Event></Maneuver></ManeuverGroup>";
        let end = "</ConditionGroup></StopTrigger>";
        assert!(text.contains("</ManeuverGroup>") && text.contains(end));
        text.replacen("</ManeuverGroup>", &format!("</ManeuverGroup>{lead}"), 1)
            .replace(
                end,
                &format!("</ConditionGroup>{}</StopTrigger>", wait("act", "CutInAct")),
            )
    });
    let o = carfollow(&["check", file.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.contains("storyboardElementRef=\"CutInAct\"") && e.contains("mutant.xosc:"),
        "{e}"
    );
}

/// esmini's `alks_r157_cut_in_quick_brake` (MPL-2.0, under `esmini/`): its target cuts in
/// at 2 s and brakes 2 s after that lane change starts (a wait for an event's start); its
/// `StopTrigger` ends the run at a `CollisionCondition` of the ego and the target, a
/// contact trigger. The chase, cruising with no lead, does not hold the target it is given
/// so near, touches it, and the run ends at the frame of that contact, in both modes;
/// imported and exported, the file runs bit for bit the same.
#[test]
fn a_collision_in_the_stop_trigger_ends_the_run_at_the_contact() {
    let file = data().join("esmini/xosc/alks_r157_cut_in_quick_brake.xosc");
    let dir = tempfile::tempdir().unwrap();
    for mode in ["paper", "robust"] {
        let out = dir.path().join(mode);
        let set = format!("tracker.mode={mode}");
        let frames = Frames::parse(&frames_of(&file, &out, &["--set", &set]));
        let s = summary(&out);
        let contact = &s["traffic"]["collisions"][0];
        assert_eq!(contact["vehicle"], "Target", "{mode}: {s}");
        let (hit, ended) = (contact["t_s"].as_f64().unwrap(), &s["ended_by"]);
        assert_eq!(ended["vehicle"], "Target", "{mode}: {ended}");
        assert!(
            (ended["t_s"].as_f64().unwrap() - hit).abs() < 1e-9,
            "{mode}: {s}"
        );
        let last = frames.num(frames.rows.last().unwrap(), "t_s");
        assert!((last - hit).abs() <= 1.0 / 15.0, "{mode}: {last} {hit}");
        let change = frames.logged("Target/LaneChange1Event:started").unwrap();
        let brake = frames
            .logged("Target/TargetreduceSpeedEvent:started")
            .unwrap();
        assert!(
            (brake - change - 2.0).abs() <= 1.0 / 15.0 + 1e-9,
            "{change} {brake}"
        );
    }
    let toml = dir.path().join("imported/r157.toml");
    let text = import_to(&file, &toml);
    assert!(
        text.contains("contact = true") && text.contains("started = "),
        "{text}"
    );
    let from_toml = frames_of(&toml, &dir.path().join("t"), &[]);
    assert!(frames_of(&file, &dir.path().join("x"), &[]) == from_toml);
    let (xosc, written) = export_to(&toml, &dir.path().join("export"));
    assert!(written.contains("<CollisionCondition>"), "{written}");
    assert!(frames_of(&xosc, &dir.path().join("e"), &[]) == from_toml);
}
