//! A road whose lanes lie beside its reference line (OpenDRIVE's `<laneOffset>`,
//! `route.lane_offset`): OpenSCENARIO positions given from the reference line (`RoadPosition`
//! `t`) land in the lanes the offset moved, the import runs as the file does, and the export
//! writes the offset back.

mod osc_common;

use osc_common::*;

/// The test files with two-lanes.xodr's lanes moved `offset_m` to the left of its
/// reference line, and cut-in.xosc's ego and cutter placed by `RoadPosition`s: the ego at
/// `t` = offset − 1.75 (lane −1's centre with the offset), the cutter 0.4 m left of lane
/// −2's centre.
fn shifted(offset_m: f64) -> (tempfile::TempDir, std::path::PathBuf) {
    let ego = r#"<LanePosition roadId="1" laneId="-1" offset="0" s="20"/>"#;
    let cutter = r#"<LanePosition roadId="1" laneId="-2" offset="0" s="80"/>"#;
    let (dir, path) = mutant(|text| {
        assert!(text.contains(ego) && text.contains(cutter));
        text.replace(
            ego,
            &format!(
                r#"<RoadPosition roadId="1" s="20" t="{}"/>"#,
                offset_m - 1.75
            ),
        )
        .replace(
            cutter,
            &format!(
                r#"<RoadPosition roadId="1" s="80" t="{}"/>"#,
                offset_m - 5.25 + 0.4
            ),
        )
    });
    let road = dir.path().join("two-lanes.xodr");
    let text = std::fs::read_to_string(&road).unwrap().replacen(
        "<laneSection s=",
        &format!(r#"<laneOffset s="0.0" a="{offset_m}" b="0.0" c="0.0" d="0.0"/><laneSection s="#),
        1,
    );
    std::fs::write(&road, text).unwrap();
    (dir, path)
}

#[test]
fn road_positions_land_in_the_lanes_the_offset_moved() {
    let (dir, path) = shifted(1.0);
    let toml = dir.path().join("shifted.toml");
    let text = import_to(&path, &toml);
    // The ego on its lane's centre (else refused), the cutter 0.4 m left of its own.
    assert!(text.contains("offset_m = 0.4"), "{text}");
    let set = ["--set", "duration_s=6"];
    let from_toml = frames_of(&toml, &dir.path().join("t"), &set);
    assert!(
        frames_of(&path, &dir.path().join("x"), &set) == from_toml,
        "the imported scenario runs differently"
    );
    // The export writes the road with its offset, and runs the same.
    let (xosc, _) = export_to(&toml, &dir.path().join("export"));
    let road = std::fs::read_dir(xosc.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "xodr"))
        .expect("an .xodr beside the export");
    let written = std::fs::read_to_string(&road).unwrap();
    assert!(
        written.contains("<laneOffset") && written.contains("a=\"1\""),
        "{written}"
    );
    assert!(
        frames_of(&xosc, &dir.path().join("e"), &set) == from_toml,
        "the exported file runs differently"
    );
    // Without the offset the same `t` is 1 m left of lane −1's centre: the ego's start
    // off its lane's centre is refused, naming it.
    let (_dir, path) = shifted(0.0);
    let unshifted =
        std::fs::read_to_string(&path)
            .unwrap()
            .replacen(r#"t="-1.75""#, r#"t="-0.75""#, 1);
    std::fs::write(&path, unshifted).unwrap();
    let e = refusal(&carfollow(&["check", path.to_str().unwrap()]), "unshifted");
    assert!(e.contains("1.00 m left of its lane's centre"), "{e}");
}

#[test]
fn a_lane_offset_that_bends_the_road_too_tightly_is_refused_at_its_line() {
    let (dir, path) = shifted(1.0);
    let road = dir.path().join("two-lanes.xodr");
    let text = std::fs::read_to_string(&road).unwrap().replacen(
        r#"<laneOffset s="0.0" a="1" b="0.0""#,
        r#"<laneOffset s="0.0" a="1" b="0.3""#,
        1,
    );
    std::fs::write(&road, &text).unwrap();
    let e = refusal(&carfollow(&["check", path.to_str().unwrap()]), "steep");
    let line = line_of(&road, "<laneOffset");
    assert!(
        e.contains(&format!("two-lanes.xodr:{line}")) && e.contains("changes by 0.300 m a metre"),
        "{e}"
    );
}
