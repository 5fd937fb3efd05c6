//! OpenSCENARIO's `LongitudinalDistanceAction` through the command line: imported as a kept
//! gap (`action = { keep = ... }`), run the same from the file and from the import,
//! exported back as the same element, and refused in one line where carfollow cannot keep
//! it as written. Run with `cargo test --release -p sim --test cli_keep_gap`.

mod osc_common;

use osc_common::*;

/// The cut-in test file with its cutter's braking after the cut-in replaced by `action`
/// (an element inside `<LongitudinalAction>`).
fn with_brake(action: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let action = action.to_string();
    mutant(move |text| {
        let at = text.find("<Action name=\"BrakeAction\">").unwrap();
        let a = at + text[at..].find("<SpeedAction>").unwrap();
        let b = at + text[at..].find("</SpeedAction>").unwrap() + "</SpeedAction>".len();
        format!("{}{action}{}", &text[..a], &text[b..])
    })
}

const KEEP: &str = "<LongitudinalDistanceAction entityRef=\"Lead car\" timeGap=\"1.2\" \
    freespace=\"true\" continuous=\"true\" coordinateSystem=\"road\">\
    <DynamicConstraints maxAcceleration=\"2\" maxDeceleration=\"5\" maxSpeed=\"30\" \
    maxAccelerationRate=\"4\" maxDecelerationRate=\"4\"/></LongitudinalDistanceAction>";

#[test]
fn a_longitudinal_distance_action_is_imported_run_and_exported_as_a_kept_gap() {
    let (dir, file) = with_brake(KEEP);
    let toml = dir.path().join("keep.toml");
    let text = import_to(&file, &toml);
    let expected =
        "[actors.events.action.keep]\nto = \"lead\"\ntime_gap_s = 1.2\nside = \"behind\"\n\
                    continuous = true\nmax_accel_mps2 = 2.0\nmax_decel_mps2 = 5.0\n\
                    max_jerk_mps3 = 4.0\nmax_speed_mps = 30.0\n";
    assert!(text.contains(expected), "{expected:?} not in:\n{text}");
    let csv = frames_of(&file, &dir.path().join("xosc"), &[]);
    assert!(csv == frames_of(&toml, &dir.path().join("toml"), &[]));
    // The cutter's action starts 1 s after its cut-in, and being continuous never ends.
    let frames = Frames::parse(&csv);
    let cut = frames
        .logged("Cutter/cut-in:ended")
        .expect("the cut-in ends");
    let kept = frames
        .logged("Cutter/brake:started")
        .expect("the gap is kept");
    assert!((kept - cut - 1.0).abs() < 0.1, "{cut} {kept}");
    assert_eq!(frames.logged("Cutter/brake:ended"), None);
    // Exported, it is the same element, and reads back to the same run.
    let (xosc, exported) = export_to(&toml, &dir.path().join("exported"));
    for attr in [
        "<LongitudinalDistanceAction entityRef=\"Lead\" timeGap=\"1.2\" freespace=\"true\" continuous=\"true\" displacement=\"trailingReferencedEntity\" coordinateSystem=\"road\">",
        "<DynamicConstraints maxAcceleration=\"2\" maxDeceleration=\"5\" maxSpeed=\"30\" maxAccelerationRate=\"4\" maxDecelerationRate=\"4\"/>",
    ] {
        assert!(exported.contains(attr), "{attr:?} not in the export");
    }
    assert!(csv == frames_of(&xosc, &dir.path().join("again"), &[]));
}

#[test]
fn a_longitudinal_distance_action_carfollow_cannot_keep_is_refused_at_its_line() {
    for (from, to, says) in [
        (
            "timeGap=\"1.2\"",
            "timeGap=\"1.2\" distance=\"10\"",
            "<LongitudinalDistanceAction> takes exactly one of distance and timeGap",
        ),
        (
            "coordinateSystem=\"road\"",
            "coordinateSystem=\"trajectory\"",
            "coordinateSystem=\"trajectory\">: carfollow measures gaps along the road",
        ),
        (
            "continuous=\"true\"",
            "continuous=\"true\" displacement=\"beside\"",
            "displacement=\"beside\">: not a displacement of the standard",
        ),
        (
            "maxDecelerationRate=\"4\"",
            "maxDecelerationRate=\"6\"",
            "carfollow's kept gap takes one jerk limit for both, or none",
        ),
        (
            "entityRef=\"Lead car\"",
            "entityRef=\"Nobody\"",
            "no entity is named `Nobody`",
        ),
    ] {
        assert!(KEEP.contains(from));
        let (_dir, file) = with_brake(&KEEP.replace(from, to));
        let o = carfollow(&["check", file.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{to}: {err}");
        assert!(err.contains(says), "{to}: {err}");
        assert!(
            err.contains(&format!(
                "mutant.xosc:{}",
                line_of(&file, "LongitudinalDistanceAction")
            )) || says.contains("Nobody"),
            "{err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}
