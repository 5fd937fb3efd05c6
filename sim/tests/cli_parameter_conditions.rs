//! OpenSCENARIO's `ParameterCondition`, decided when the file is read (nothing changes a
//! parameter during a run): an act or an event each of whose start trigger's condition
//! groups holds one that does not hold never starts, is not imported, and one warning line
//! names it; one that holds starts as it would without it; a group that never holds leaves
//! the trigger to its other groups, the storyboard's stop trigger's among them; waiting for
//! an event that never starts is refused at its line. Run with `cargo test --release -p sim --test cli_parameter_conditions`.

mod osc_common;

use osc_common::*;
use std::path::Path;

/// The act's start condition in `cut-in.xosc`.
const ACT_START: &str = r#"<ByValueCondition><SimulationTimeCondition value="0" rule="greaterThan"/></ByValueCondition>"#;
/// The start condition of its `brake` event.
const AFTER_CUT_IN: &str = r#"<StoryboardElementStateCondition storyboardElementType="event" storyboardElementRef="cut-in" state="endTransition"/>"#;

/// `cut-in.xosc` with a boolean parameter `CutIn` (false) declared.
fn declared(text: &str) -> String {
    let at = r#"<ParameterDeclaration name="VanKind" parameterType="string" value="van"/>"#;
    assert!(text.contains(at));
    text.replace(
        at,
        &format!(
            r#"{at}<ParameterDeclaration name="CutIn" parameterType="boolean" value="false"/>"#
        ),
    )
}

/// A condition on `CutIn`: `value` is what it must equal.
fn on_cut_in(value: &str) -> String {
    format!(
        r#"<ByValueCondition><ParameterCondition parameterRef="CutIn" value="{value}" rule="equalTo"/></ByValueCondition>"#
    )
}

/// `carfollow import` of `file` with `args`: its exit code, its stderr, and the scenario
/// it wrote without its first two lines (which name the file).
fn import(file: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let toml = file.with_extension("toml");
    let mut all = vec![
        "import",
        file.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let o = carfollow(&all);
    let text = std::fs::read_to_string(&toml).unwrap_or_default();
    let body = text.lines().skip(2).collect::<Vec<_>>().join("\n");
    (o.status.code(), stderr(&o), body)
}

#[test]
fn an_act_whose_parameter_condition_does_not_hold_is_not_imported() {
    let (_keep, plain) = mutant(|t| t.to_string());
    let (code, _, original) = import(&plain, &[]);
    assert_eq!(code, Some(0));
    assert!(original.contains("name = \"cut-in\"") && original.contains("name = \"brake\""));
    let (_keep2, file) = mutant(|t| declared(t).replace(ACT_START, &on_cut_in("true")));
    let (code, err, body) = import(&file, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        !body.contains("name = \"cut-in\"") && !body.contains("name = \"brake\""),
        "{body}"
    );
    let said: Vec<_> = err.lines().filter(|l| l.contains("never start")).collect();
    assert!(
        said.len() == 1 && said[0].contains("act `CutInAct` never starts"),
        "{err}"
    );
    // Set so that it holds, the act starts at once, as it did on simulation time.
    let (code, err, body) = import(&file, &["--param", "CutIn=true"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("never start"), "{err}");
    assert_eq!(body, original);
    // Checking it says so, once.
    let o = carfollow(&["check", file.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        stderr(&o).matches("never starts").count(),
        1,
        "{}",
        stderr(&o)
    );
}

#[test]
fn an_event_starts_on_its_other_groups_and_not_at_all_without_one() {
    let (_keep, plain) = mutant(|t| t.to_string());
    let (_, _, original) = import(&plain, &[]);
    // A second group that never holds: the first decides, as before.
    let group = format!(
        r#"<ConditionGroup><Condition name="never" delay="0" conditionEdge="none">{}</Condition></ConditionGroup></StartTrigger>"#,
        on_cut_in("true")
    );
    let (_keep2, file) = mutant(|t| {
        let at = t.find(AFTER_CUT_IN).unwrap();
        let end = at + t[at..].find("</StartTrigger>").unwrap();
        let mut out = declared(&t[..end]);
        out.push_str(&group);
        out.push_str(&t[end + "</StartTrigger>".len()..]);
        out
    });
    let (code, err, body) = import(&file, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("never start"), "{err}");
    assert_eq!(body, original);
    // Its only condition never holding: the event is not imported, the other one is.
    let (_keep3, file) = mutant(|t| {
        declared(t).replace(
        &format!("<ByValueCondition>\n                    {AFTER_CUT_IN}\n                  </ByValueCondition>"),
        &on_cut_in("true"),
    )
    });
    let (code, err, body) = import(&file, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("event `brake` never starts"), "{err}");
    assert!(
        body.contains("name = \"cut-in\"") && !body.contains("name = \"brake\""),
        "{body}"
    );
}

#[test]
fn waiting_for_an_event_that_never_starts_is_refused_at_its_line() {
    // The cut-in never starts; the brake waits for its end.
    let (_keep, file) = mutant(|t| {
        let at = t.find(r#"<Condition name="close""#).unwrap();
        let end = at + t[at..].find("</Condition>").unwrap() + "</Condition>".len();
        let never = format!(
            r#"<Condition name="close" delay="0" conditionEdge="none">{}</Condition>"#,
            on_cut_in("true")
        );
        declared(&format!("{}{never}{}", &t[..at], &t[end..]))
    });
    let (code, err, _) = import(&file, &[]);
    assert_eq!(code, Some(2), "{err}");
    let line = line_of(&file, AFTER_CUT_IN);
    assert!(
        err.lines().count() == 1
            && err.contains(&format!("mutant.xosc:{line}"))
            && err.contains("waits for an event that never starts"),
        "{err}"
    );
}

#[test]
fn a_stop_group_that_never_holds_never_ends_the_run() {
    let (_keep, plain) = mutant(|t| t.to_string());
    let (_, _, original) = import(&plain, &[]);
    let group = format!(
        r#"<ConditionGroup><Condition name="never" delay="0" conditionEdge="none">{}</Condition></ConditionGroup></StopTrigger>"#,
        on_cut_in("true")
    );
    let (_keep2, file) = mutant(|t| declared(t).replace("</StopTrigger>", &group));
    let (code, err, body) = import(&file, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(body, original);
    // Set so that it holds, it ends the run at once: an end event on the lead.
    let (code, err, body) = import(&file, &["--param", "CutIn=true"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(body.contains("end_run = true"), "{body}");
}
