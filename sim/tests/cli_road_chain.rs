//! An OpenSCENARIO file on a chain of OpenDRIVE roads, through the command line: the test
//! files' `two-lanes.xodr` cut into two roads linked end to start runs as the one road
//! does, bit for bit; a `LanePosition` on the second road is placed at that road's start
//! along the route plus its `s`; a road the route does not hold, or an `s` past its road's
//! end, is refused in one line. Run with `cargo test --release -p sim --test
//! cli_road_chain`.

mod osc_common;

use osc_common::*;

/// `two-lanes.xodr` cut at s = 400 m into road 1 (its line) and road 2 (its spiral and arc,
/// their stations from 400 m on), road 1's successor road 2's start.
fn two_roads() -> String {
    let text = std::fs::read_to_string(data().join("two-lanes.xodr")).unwrap();
    let spiral = r#"      <geometry s="400.0" x="400.0" y="0.0" hdg="0.0" length="100.0">"#;
    let arc = r#"      <geometry s="500.0" x="499.900046285613""#;
    assert!(text.contains(spiral) && text.contains(arc));
    let road = r#"  <road name="two-lanes" length="900.0" id="1" junction="-1">"#;
    let start = text.find(road).unwrap();
    let end = text.find("  </road>").unwrap() + "  </road>\n".len();
    let whole = &text[start..end];
    let cut = whole.find(spiral).unwrap();
    let plan_end = whole.find("    </planView>").unwrap();
    let first = format!(
        "{}\n{}",
        &whole[..cut].replace(
            r#"length="900.0" id="1" junction="-1">"#,
            r#"length="400.0" id="1" junction="-1">
    <link><successor elementType="road" elementId="2" contactPoint="start"/></link>"#
        ),
        &whole[plan_end..]
    );
    let second = format!(
        "{}{}{}",
        &whole[..whole.find("<planView>").unwrap() + "<planView>\n".len()].replace(
            r#"length="900.0" id="1" junction="-1">"#,
            r#"length="500.0" id="2" junction="-1">
    <link><predecessor elementType="road" elementId="1" contactPoint="end"/></link>"#
        ),
        whole[cut..plan_end]
            .replace(r#"s="400.0""#, r#"s="0.0""#)
            .replace(r#"s="500.0""#, r#"s="100.0""#),
        &whole[plan_end..]
    );
    format!("{}{first}{second}{}", &text[..start], &text[end..])
}

/// `cut-in.xosc` (with `edit`) in a folder holding the test files and the chain as
/// `chain.xodr`, on the chain when `chained`.
fn on_chain(
    chained: bool,
    edit: impl Fn(&str) -> String,
) -> (tempfile::TempDir, std::path::PathBuf) {
    let (dir, path) = mutant(|text| {
        let text = edit(text);
        if chained {
            text.replace(r#"filepath="two-lanes.xodr""#, r#"filepath="chain.xodr""#)
        } else {
            text
        }
    });
    std::fs::write(dir.path().join("chain.xodr"), two_roads()).unwrap();
    (dir, path)
}

#[test]
fn a_scenario_on_a_chain_of_roads_runs_as_on_the_one_road() {
    let cutter = r#"<LanePosition roadId="1" laneId="-2" offset="0" s="80"/>"#;
    for (one, two) in [
        (cutter.to_string(), cutter.to_string()),
        // The cutter placed on the second road, 50 m along it: 450 m along the one road.
        (
            cutter.replace(r#"s="80""#, r#"s="450""#),
            cutter
                .replace(r#"roadId="1""#, r#"roadId="2""#)
                .replace(r#"s="80""#, r#"s="50""#),
        ),
    ] {
        let (dir, one_file) = on_chain(false, |t| t.replace(cutter, &one));
        let a = frames_of(&one_file, &dir.path().join("a"), &["--set", "duration_s=8"]);
        let (dir, two_file) = on_chain(true, |t| t.replace(cutter, &two));
        let b = frames_of(&two_file, &dir.path().join("b"), &["--set", "duration_s=8"]);
        assert!(
            a == b,
            "{two}: the chain runs differently from the one road"
        );
    }
}

#[test]
fn a_position_off_the_chains_roads_is_refused_in_one_line() {
    let cutter = r#"<LanePosition roadId="1" laneId="-2" offset="0" s="80"/>"#;
    for (to, says) in [
        (
            cutter.replace(r#"roadId="1""#, r#"roadId="3""#),
            "carfollow's route is road 1, 2",
        ),
        (
            cutter
                .replace(r#"roadId="1""#, r#"roadId="2""#)
                .replace(r#"s="80""#, r#"s="600""#),
            "s = 600 m is past the end of road 2 (500 m long)",
        ),
    ] {
        let (_dir, path) = on_chain(true, |t| t.replace(cutter, &to));
        let o = carfollow(&["check", path.to_str().unwrap()]);
        let e = refusal(&o, &to);
        assert!(e.contains(says) && e.contains("mutant.xosc:"), "{to}: {e}");
    }
}
