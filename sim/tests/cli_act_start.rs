//! OpenSCENARIO acts that start on a condition, through the command line: the act's start
//! trigger is latched before each of its events' own triggers, so that its events are
//! judged from the step it first holds, and go on being judged after it stops holding; a
//! wait for such an act's start waits for its trigger. Run with `cargo test --release -p sim
//! --test cli_act_start`.

mod osc_common;

use osc_common::*;

/// `cut-in.xosc`'s act start (a simulation time after 0).
const ACT_START: &str = r#"<SimulationTimeCondition value="0" rule="greaterThan"/>"#;

/// The cut-in's own trigger: the van within `$CutInGap` of the ego, on a rising edge.
const CUT_IN_CONDITION: &str = r#"<Condition name="close" delay="0" conditionEdge="rising">
                  <ByEntityCondition>
                    <TriggeringEntities triggeringEntitiesRule="any"><EntityRef entityRef="Ego"/></TriggeringEntities>
                    <EntityCondition>
                      <RelativeDistanceCondition entityRef="Cutter" relativeDistanceType="longitudinal" freespace="true" value="$CutInGap" rule="lessThan"/>
                    </EntityCondition>
                  </ByEntityCondition>
                </Condition>"#;

/// A simulation time condition `rule` `value` s, with its `delay`.
fn time_condition(value: f64, rule: &str, delay: f64) -> String {
    format!(
        r#"<Condition name="t" delay="{delay}" conditionEdge="none"><ByValueCondition><SimulationTimeCondition value="{value}" rule="{rule}"/></ByValueCondition></Condition>"#
    )
}

/// `cut-in.xosc` with its act starting at a simulation time `act` (`rule`, `delay`) and its
/// cut-in's own trigger `own` (a `Condition`).
fn act_on(act: &str, own: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let act = act.to_string();
    let own = own.to_string();
    mutant(move |text| {
        let start = format!("<Condition name=\"start\" delay=\"0\" conditionEdge=\"none\">\n            <ByValueCondition>{ACT_START}</ByValueCondition>\n          </Condition>");
        assert!(text.contains(&start), "the act's start is not as written");
        assert!(
            text.contains(CUT_IN_CONDITION),
            "the cut-in's trigger is not as written"
        );
        text.replace(&start, &act).replace(CUT_IN_CONDITION, &own)
    })
}

/// When the cut-in and the brake (1 s after the cut-in's end) start in a run of `path`.
fn starts(path: &std::path::Path, out: &std::path::Path) -> (Option<f64>, Option<f64>) {
    let frames = Frames::parse(&frames_of(path, out, &["--set", "duration_s=12"]));
    (
        frames.logged("cut-in:started"),
        frames.logged("brake:started"),
    )
}

/// An act that starts 1 s after a time of 3 s (its condition's delay) starts its cut-in,
/// whose own trigger holds from the first step, at 4 s; an event whose own trigger holds
/// only later (after 6 s) waits for it as well; imported, the act's trigger is written
/// latched before the event's own, and the file's own scenario runs the same imported as
/// read; exported and imported back, it runs the same again.
#[test]
fn an_acts_events_are_judged_from_the_step_its_start_trigger_holds() {
    let (dir, path) = act_on(
        &time_condition(3.0, "greaterThan", 1.0),
        &time_condition(0.0, "greaterThan", 0.0),
    );
    let (cut_in, brake) = starts(&path, &dir.path().join("a"));
    assert_eq!(cut_in, Some(4.0));
    let brake = brake.expect("the brake starts after the cut-in");
    assert!(brake > 5.0, "the brake waits for the cut-in's end: {brake}");
    // Imported: the act's trigger latched, first in an `all` with the event's own.
    let toml = dir.path().join("imported.toml");
    let text = import_to(&path, &toml);
    assert!(
        text.contains("latched = true"),
        "no latched member in:\n{text}"
    );
    let imported = frames_of(&toml, &dir.path().join("b"), &["--set", "duration_s=12"]);
    let read = std::fs::read_to_string(dir.path().join("a/frames.csv")).unwrap();
    assert_eq!(imported, read, "the imported scenario runs differently");
    // Exported: each event in an act of its own started by the act's trigger, nothing
    // carried; read back, the same run.
    let (back, exported) = export_to(&toml, &dir.path().join("exported"));
    for expected in [r#"<Act name="cut-in-act">"#, r#"<Act name="brake-act">"#] {
        assert!(
            exported.contains(expected),
            "{expected} not in:\n{exported}"
        );
    }
    assert!(
        !exported.contains("carfollow.actors"),
        "the events are carried:\n{exported}"
    );
    let again = frames_of(&back, &dir.path().join("c"), &["--set", "duration_s=12"]);
    assert_eq!(again, read, "the exported scenario runs differently");
    // The event's own trigger holding after the act's start: the later of the two.
    let (dir, path) = act_on(
        &time_condition(3.0, "greaterThan", 1.0),
        &time_condition(6.0, "greaterThan", 0.0),
    );
    assert_eq!(starts(&path, &dir.path().join("a")).0, Some(6.0));
    // The act's start after the event's own: the act's.
    let (dir, path) = act_on(
        &time_condition(7.0, "greaterThan", 0.0),
        &time_condition(2.0, "greaterThan", 0.0),
    );
    assert_eq!(starts(&path, &dir.path().join("a")).0, Some(7.0));
}

/// An act's start trigger that holds at one step only (a time equal to 2 s) starts the act
/// for good: its cut-in, whose own trigger holds from 5 s, starts at 5 s, when the act's
/// condition has long stopped holding. A condition group that never holds (a parameter
/// condition false) leaves the act's start to the other groups.
#[test]
fn an_act_once_started_stays_started() {
    let (dir, path) = act_on(
        &time_condition(2.0, "equalTo", 0.0),
        &time_condition(5.0, "greaterThan", 0.0),
    );
    assert_eq!(starts(&path, &dir.path().join("a")).0, Some(5.0));
    // The act's trigger in two groups: one never holds, the other from 3 s.
    let never = r#"<Condition name="p" delay="0" conditionEdge="none"><ByValueCondition><ParameterCondition parameterRef="VanKind" value="truck" rule="equalTo"/></ByValueCondition></Condition>"#;
    let act = format!(
        "{never}</ConditionGroup><ConditionGroup>{}",
        time_condition(3.0, "greaterThan", 0.0)
    );
    let (dir, path) = act_on(&act, &time_condition(0.0, "greaterThan", 0.0));
    assert_eq!(starts(&path, &dir.path().join("a")).0, Some(3.0));
}

/// The cut-in's own rising edge comes before a late act's start: the event waits for an
/// edge in the act, which never comes here (the van stays within the gap), so the cut-in
/// never starts; a level condition starts it at the act's start.
#[test]
fn an_edge_before_the_act_starts_is_not_the_events() {
    let (dir, path) = act_on(&time_condition(0.0, "greaterThan", 0.0), CUT_IN_CONDITION);
    let (first, _) = starts(&path, &dir.path().join("a"));
    let first = first.expect("the cut-in starts in the file as written");
    let late = first + 1.0;
    let (dir, path) = act_on(&time_condition(late, "greaterThan", 0.0), CUT_IN_CONDITION);
    let (cut_in, _) = starts(&path, &dir.path().join("b"));
    assert_eq!(
        cut_in, None,
        "the rising edge was before the act (at {first} s)"
    );
    let level = CUT_IN_CONDITION.replace("conditionEdge=\"rising\"", "conditionEdge=\"none\"");
    let (dir, path) = act_on(&time_condition(late, "greaterThan", 0.0), &level);
    assert_eq!(starts(&path, &dir.path().join("c")).0, Some(late));
}

/// A wait for the start of an act that starts on a condition (the brake waits for the
/// act's `startTransition`, 1 s after) waits for that act's trigger; acts that wait for each
/// other's starts are refused in one line.
#[test]
fn a_wait_for_a_conditional_acts_start_waits_for_its_trigger() {
    let after = r#"<StoryboardElementStateCondition storyboardElementType="event" storyboardElementRef="cut-in" state="endTransition"/>"#;
    let on_start = r#"<StoryboardElementStateCondition storyboardElementType="act" storyboardElementRef="CutInAct" state="startTransition"/>"#;
    let act = time_condition(4.0, "greaterThan", 0.0);
    let (dir, path) = mutant(move |text| {
        let start = format!("<Condition name=\"start\" delay=\"0\" conditionEdge=\"none\">\n            <ByValueCondition>{ACT_START}</ByValueCondition>\n          </Condition>");
        text.replace(&start, &act).replace(after, on_start)
    });
    assert_eq!(starts(&path, &dir.path().join("a")).1, Some(5.0));
    // The act waits for its own start: a loop.
    let act = format!(
        r#"<Condition name="self" delay="0" conditionEdge="none"><ByValueCondition>{on_start}</ByValueCondition></Condition>"#
    );
    let (_dir, path) = mutant(move |text| {
        let start = format!("<Condition name=\"start\" delay=\"0\" conditionEdge=\"none\">\n            <ByValueCondition>{ACT_START}</ByValueCondition>\n          </Condition>");
        text.replace(&start, &act)
    });
    let o = carfollow(&["check", path.to_str().unwrap()]);
    let e = refusal(&o, "an act waiting for its own start");
    assert!(e.contains("mutant.xosc:") && e.contains("in a loop"), "{e}");
}

/// A wait for the end of an event of the ego, whose actions carfollow does not apply (its
/// loop drives the chase), is refused in one line that says so.
#[test]
fn a_wait_for_an_ego_event_is_refused_saying_why() {
    let after = r#"storyboardElementRef="cut-in" state="endTransition""#;
    let ego_group = r#"<ManeuverGroup maximumExecutionCount="1" name="EgoGroup">
          <Actors selectTriggeringEntities="false"><EntityRef entityRef="Ego"/></Actors>
          <Maneuver name="EgoManeuver">
            <Event name="ego-speed" priority="parallel">
              <Action name="EgoSpeed">
                <PrivateAction><LongitudinalAction><SpeedAction>
                  <SpeedActionDynamics dynamicsShape="linear" dynamicsDimension="rate" value="1"/>
                  <SpeedActionTarget><AbsoluteTargetSpeed value="10"/></SpeedActionTarget>
                </SpeedAction></LongitudinalAction></PrivateAction>
              </Action>
              <StartTrigger><ConditionGroup>
                <Condition name="t" delay="0" conditionEdge="none"><ByValueCondition><SimulationTimeCondition value="1" rule="greaterThan"/></ByValueCondition></Condition>
              </ConditionGroup></StartTrigger>
            </Event>
          </Maneuver>
        </ManeuverGroup>
        <ManeuverGroup maximumExecutionCount="1" name="CutInGroup">"#;
    let (_dir, path) = mutant(move |text| {
        let group = r#"<ManeuverGroup maximumExecutionCount="1" name="CutInGroup">"#;
        assert!(text.contains(after) && text.contains(group));
        text.replace(group, ego_group).replace(
            after,
            r#"storyboardElementRef="ego-speed" state="endTransition""#,
        )
    });
    let o = carfollow(&["check", path.to_str().unwrap()]);
    let e = refusal(&o, "a wait for the ego's event");
    assert!(
        e.contains("waits for an event of the ego `Ego`") && e.contains("mutant.xosc:"),
        "{e}"
    );
}

/// The storyboard's `StopTrigger` waiting for the start of an act that starts on a
/// condition (here 2 s after the act, which starts at 3 s) ends the run then: its one
/// condition, latched, goes in an `all` of its own.
#[test]
fn a_stop_on_a_conditional_acts_start_waits_for_its_trigger() {
    let stop = r#"<Condition name="end" delay="0" conditionEdge="rising">
        <ByValueCondition><SimulationTimeCondition value="25" rule="greaterThan"/></ByValueCondition>
      </Condition>"#;
    let act = time_condition(3.0, "greaterThan", 0.0);
    let (dir, path) = mutant(move |text| {
        let start = format!("<Condition name=\"start\" delay=\"0\" conditionEdge=\"none\">\n            <ByValueCondition>{ACT_START}</ByValueCondition>\n          </Condition>");
        assert!(text.contains(stop), "the stop trigger is not as written");
        text.replace(&start, &act).replace(
            stop,
            &format!(
                "{stop}\n    </ConditionGroup><ConditionGroup>\n      <Condition name=\"after-act\" delay=\"2\" conditionEdge=\"none\"><ByValueCondition><StoryboardElementStateCondition storyboardElementType=\"act\" storyboardElementRef=\"CutInAct\" state=\"startTransition\"/></ByValueCondition></Condition>"
            ),
        )
    });
    let frames = Frames::parse(&frames_of(&path, &dir.path().join("a"), &[]));
    let last = frames.num(frames.rows.last().unwrap(), "t_s");
    assert!((last - 5.0).abs() < 0.1, "the run ended at {last} s");
}
