//! Scenario files: every shipped scenario validates; bad files are refused with the file,
//! line, column and field, and what is allowed; `--set` overrides any field by its dotted path.
//! Run with `cargo test -p sim --test scenario_files`.

use sim_core::{Plan, Scenario};

mod common;
use common::{line_of, load, scenarios_dir, text};

#[test]
fn every_shipped_scenario_validates() {
    let mut n = 0;
    for entry in std::fs::read_dir(scenarios_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            Plan::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 1);
    Plan::builtin(&[]).unwrap();
}

#[test]
fn a_mistyped_field_is_named_with_its_line() {
    let t = text().replace("duration_s = 90.0", "duraton_s = 90.0");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "duraton_s");
    assert!(
        e.starts_with(&format!("/bad.toml:{line}:1: unknown field `duraton_s`")),
        "{e}"
    );
}

#[test]
fn a_wrong_type_is_named_with_its_line() {
    let t = text().replace("lambda = 0.8", "lambda = \"high\"");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "lambda =");
    assert!(e.starts_with(&format!("/bad.toml:{line}:")), "{e}");
    assert!(e.contains("invalid type") && e.contains("f64"), "{e}");
}

#[test]
fn a_negative_duration_is_refused_with_what_is_allowed() {
    let t = text().replace("duration_s = 90.0", "duration_s = -5.0");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "duration_s");
    assert_eq!(
        e,
        format!("/bad.toml:{line}:1: `duration_s` = -5: must be at least one camera frame (1/15 s) and at most 86400 seconds")
    );
}

#[test]
fn a_duration_shorter_than_a_frame_is_refused() {
    for short in ["0.01", "1e-300"] {
        let t = text().replace("duration_s = 90.0", &format!("duration_s = {short}"));
        let e = load(&t, &[]).unwrap_err();
        assert!(
            e.contains("`duration_s`") && e.contains("one camera frame"),
            "{e}"
        );
    }
    // One frame is enough.
    let t = text().replace("duration_s = 90.0", "duration_s = 0.0667");
    load(&t, &[]).unwrap();
}

/// `[chase]` may be left out: it means what an empty `[chase]` means.
#[test]
fn a_scenario_without_a_chase_table_takes_the_defaults() {
    let without = text().replace("[chase]\ninitial_gap_m = 10.0\n", "");
    assert!(!without.contains("[chase]"));
    let s = load(&without, &[]).unwrap_or_else(|e| panic!("{e}"));
    let empty = load(&text().replace("initial_gap_m = 10.0\n", ""), &[]).unwrap();
    assert_eq!(format!("{:?}", s.chase), format!("{:?}", empty.chase));
    let start = |s: &Scenario| Plan::new(s).unwrap().chase_start_m();
    assert_eq!(start(&s), start(&empty));
}

/// The controller's half field of view comes from the camera: when it is out of range,
/// the error names the camera's field, not the controller's.
#[test]
fn a_field_of_view_out_of_range_names_the_camera() {
    let t = text().replace(
        "pixel_size_mm = [0.025, 0.025]",
        "pixel_size_mm = [1e-7, 1e-7]",
    );
    let e = load(&t, &["camera.focal_length_mm=200"]).unwrap_err();
    assert!(
        e.contains("`camera.focal_length_mm`") && e.contains("half field of view"),
        "{e}"
    );
}

/// A target given by `--set` that cannot be read is the override's fault.
#[test]
fn a_missing_target_given_by_set_names_the_override() {
    let e = load(&text(), &["tracker.target=targets/missing.toml"]).unwrap_err();
    assert!(
        e.starts_with("--set tracker.target=targets/missing.toml:") && e.contains("missing.toml"),
        "{e}"
    );
}

#[test]
fn a_missing_target_file_is_named() {
    let t = text().replace("targets/nist-ten-segment.toml", "targets/missing.toml");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "targets/missing.toml");
    assert!(
        e.starts_with(&format!("/bad.toml:{line}:1: `tracker.target`:")),
        "{e}"
    );
    assert!(
        e.contains("missing.toml") && e.contains("cannot read"),
        "{e}"
    );
}

#[test]
fn out_of_range_values_deep_in_a_table_are_located() {
    let t = text().replace("latency_ms = 128.0", "latency_ms = -1.0");
    let e = load(&t, &[]).unwrap_err();
    assert!(
        e.starts_with(&format!(
            "/bad.toml:{}:1: `loop.latency_ms` = -1: must be 0–2000 ms",
            line_of(&t, "latency_ms")
        )),
        "{e}"
    );
    let e = load(&text(), &["tracker.lambda=1.5"]).unwrap_err();
    assert_eq!(
        e,
        "--set tracker.lambda=1.5: `tracker.lambda` = 1.5: must be in (0, 1) (eq. 18: 0 < λ < 1)"
    );
}

#[test]
fn set_overrides_any_field_by_its_dotted_path() {
    let s = load(
        &text(),
        &[
            "tracker.lambda=0.7",
            "environment.sun.strength=0.5",
            "expect.gap_band_m=[4, 16]",
            "duration_s=12",
        ],
    )
    .unwrap();
    assert_eq!(s.tracker.lambda, 0.7);
    assert_eq!(s.sun.strength, 0.5);
    assert_eq!(s.expect.gap_band_m, Some([4.0, 16.0]));
    assert_eq!(s.duration_s, 12.0);
    // A new nested field (the lead driver's weave) is created on the way.
    let s = load(&text(), &["lead.driver.weave_amplitude_m=0.6"]).unwrap();
    assert_eq!(s.lead_driver.weave_amplitude_m, 0.6);
}

#[test]
fn a_bad_set_path_is_refused_and_named() {
    let e = load(&text(), &["tracker.lamda=0.7"]).unwrap_err();
    assert!(
        e.starts_with("--set tracker.lamda=0.7:") && e.contains("unknown field `lamda`"),
        "{e}"
    );
    let e = load(&text(), &["duration_s.x=1"]).unwrap_err();
    assert!(e.contains("`duration_s` is a value, not a table"), "{e}");
    let e = load(&text(), &["novalue"]).unwrap_err();
    assert!(e.contains("expected KEY.PATH=VALUE"), "{e}");
}

/// What the closed loop used to refuse only when it started (so `check` and a sweep's
/// pre-flight passed it) is refused by validation, naming the field or the override.
#[test]
fn what_the_loop_would_refuse_is_refused_by_validation() {
    for (set, needle) in [
        (
            "lead.start_m=0",
            "--set lead.start_m=0: `lead.start_m` puts the chase vehicle 13.4 m before the route's start",
        ),
        (
            "chase.controller.gap_keeper.min_gap_m=0",
            "--set chase.controller.gap_keeper.min_gap_m=0: `chase.controller.gap_keeper.min_gap_m` = 0:",
        ),
        (
            "lead.driver.weave_amplitude_m=-inf",
            "`lead.driver.weave_amplitude_m` = -inf:",
        ),
        (
            "camera.mount.pitch_down_deg=60",
            "--set camera.mount.pitch_down_deg=60: `camera.mount.pitch_down_deg` = 60:",
        ),
        (
            "camera.mount.right_m=0.5",
            "`camera.mount.right_m` = 0.5: must be 0",
        ),
        (
            "route.segments=[{straight_m = 40000}, {straight_m = 40000}]",
            "`route.segments` = 80000 m in all: the route must be at most 50000 m long",
        ),
        (
            "route.segments=[{arc_radius_m = 1e308, arc_angle_deg = 30}]",
            "`route.segments` = 1e308: segment 0: arc_radius_m must be 8–10000 m",
        ),
        (
            "environment.sensor.blur_sigma_px=1e300",
            "`environment.sensor.blur_sigma_px` = 1e300: must be 0–10 px",
        ),
        (
            "camera.focal_length_mm=1e300",
            "`camera.focal_length_mm` = 1e300: must be 1–200 mm",
        ),
        ("tracker.init_offset=[1e300, 0, 0]", "`tracker.init_offset`"),
        (
            "camera.mount.pitch_down_deg=30",
            "puts the target out of the camera's view at t = 0",
        ),
        (
            "camera.focal_length_mm=50",
            "`camera.focal_length_mm` puts the target out of the camera's view at t = 0",
        ),
        ("environment.sun.azimuth_deg=nan", "`environment.sun.azimuth_deg` = NaN"),
        (
            "camera.pan.max_rate_deg_s=0",
            "`camera.pan.max_rate_deg_s` = 0: must be finite and within 0.1–2000",
        ),
        (
            "camera.pan.encoder_noise_deg=-1",
            "`camera.pan.encoder_noise_deg` = -1:",
        ),
        (
            "chase.controller.pan_head.enabled=true",
            "`chase.controller.pan_head` is set by `[camera.pan]`",
        ),
        (
            "chase.controller.gap_keeper.policy={policy=\"idm\",standstill_gap_m=5,headway_s=1,comfortable_decel_mps2=9}",
            "`chase.controller.gap_keeper.policy.comfortable_decel_mps2` = 9:",
        ),
    ] {
        let e = load(&text(), &[set]).unwrap_err();
        assert!(e.contains(needle), "{set}: {e}");
        assert!(e.starts_with(&format!("--set {set}: ")), "{set}: {e}");
    }
    // The same in the file is blamed on its line.
    let t = text().replace("start_m = 30.0", "start_m = 0.0");
    assert_ne!(t, text());
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "start_m = 0.0");
    assert!(e.starts_with(&format!("/bad.toml:{line}:")), "{e}");
    assert!(e.contains("`lead.start_m` puts the chase vehicle"), "{e}");
}

/// An array with too many numbers is the file's fault at its line, whether or not an
/// unrelated override is given.
#[test]
fn a_long_array_in_the_file_is_blamed_on_the_file_not_an_override() {
    let t = text().replace(
        "pixel_size_mm = [0.025, 0.025]",
        "pixel_size_mm = [0.025, 0.025, 0.1, 0.1]",
    );
    assert_ne!(t, text());
    let line = line_of(&t, "pixel_size_mm");
    for overrides in [&[][..], &["duration_s=2"][..]] {
        let e = load(&t, overrides).unwrap_err();
        assert!(
            e.starts_with(&format!(
                "/bad.toml:{line}:17: `camera.pixel_size_mm`: invalid length 4, expected an array of exactly 2 numbers"
            )),
            "{overrides:?}: {e}"
        );
    }
}

/// `summary.json` gets the scenario as resolved: the overrides applied, defaults filled in.
#[test]
fn the_resolved_scenario_holds_the_overrides() {
    let s = load(&text(), &["tracker.lambda=0.7", "duration_s=3"]).unwrap();
    assert_eq!(s.overrides, ["tracker.lambda=0.7", "duration_s=3"]);
    assert_eq!(s.resolved.tracker.lambda, Some(0.7));
    assert_eq!(s.resolved.duration_s, 3.0);
    let json = serde_json::to_value(&s.resolved).unwrap();
    assert_eq!(json["tracker"]["lambda"], 0.7);
    assert_eq!(json["route"]["lane_width_m"], 3.5);
}

/// The controllers' look-ahead and speed gains are bounded too (a look-ahead whose
/// minimum exceeds its maximum used to panic when the run started).
#[test]
fn look_ahead_and_gains_are_bounded() {
    let e = load(
        &text(),
        &["chase.controller.lookahead={ base_m = 3, gain_s = 0.5, min_m = 40, max_m = 1 }"],
    )
    .unwrap_err();
    assert!(
        e.contains("`chase.controller.lookahead.max_m` = 1: must be from min_m to 200 m"),
        "{e}"
    );
    let e = load(
        &text(),
        &["lead.driver.speed_gains={ kp_per_s = nan, ki_per_s2 = 1, integral_limit_mps2 = 1 }"],
    )
    .unwrap_err();
    assert!(
        e.contains("`lead.driver.speed_gains.kp_per_s` = NaN"),
        "{e}"
    );
    let e = load(&text(), &["chase.controller.max_breadcrumbs=0"]).unwrap_err();
    assert!(
        e.contains("`chase.controller.max_breadcrumbs` = 0: must be 2–1000000"),
        "{e}"
    );
}

#[test]
fn a_chase_speed_profile_scripts_the_throttle_and_is_checked() {
    let t = text().replace(
        "initial_gap_m = 10.0",
        "initial_gap_m = 10.0\nspeed_profile = [[0.0, 6.0], [10.0, 9.0]]",
    );
    let s = load(&t, &[]).unwrap();
    assert!(
        matches!(&s.chase.speed_mode, vehicle::SpeedMode::Manual { profile } if profile.knots.len() == 2),
        "{:?}",
        s.chase.speed_mode
    );
    // Refused: a speed out of range, a bad basis, a basis without a profile.
    let e = load(&t.replace("[10.0, 9.0]", "[10.0, 90.0]"), &[]).unwrap_err();
    assert!(e.contains("`chase.speed_profile` = [10, 90]"), "{e}");
    let e = load(&t, &["chase.speed_basis=\"lap\""]).unwrap_err();
    assert!(e.contains("`chase.speed_basis` = \"lap\""), "{e}");
    let e = load(&text(), &["chase.speed_basis=\"distance\""]).unwrap_err();
    assert!(e.contains("applies only with chase.speed_profile"), "{e}");
}

fn section4() -> String {
    std::fs::read_to_string(scenarios_dir().join("section4.toml")).unwrap()
}

/// An error in an item of a list of tables is reported at the item's own line, not at
/// `[environment]`.
#[test]
fn an_error_in_a_list_item_is_located_at_its_line() {
    let t = section4()
        .replace("feature = 3", "feature = 99")
        .replace("station_m = 200.0", "station_m = 1e6");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "feature = 99");
    assert!(
        e.starts_with(&format!(
            "/bad.toml:{line}:1: `environment.distractors[0].feature`"
        )),
        "{e}"
    );
    let t = section4().replace("station_m = 200.0", "station_m = 1e6");
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "station_m = 1e6");
    assert!(
        e.starts_with(&format!(
            "/bad.toml:{line}:1: `environment.overpasses[0].station_m`"
        )),
        "{e}"
    );
}

#[test]
fn distractors_and_overpasses_are_checked_and_list_items_can_be_set() {
    let s = load(&section4(), &[]).unwrap();
    assert_eq!(s.distractors.len(), 1);
    // 2 px at the nominal 10 m with a 320 px focal length: 2 × 10 / 320 m.
    assert!((s.distractors[0].offset_m - 2.0 * 10.0 / 320.0).abs() < 1e-12);
    assert_eq!(s.placements.len(), 1);
    // A list item's field by its index, as a sweep axis sets it.
    let s = load(&section4(), &["environment.distractors.0.offset_m=0.1"]).unwrap_err();
    assert!(
        s.contains("give exactly one of offset_px and offset_m"),
        "{s}"
    );
    let s = load(&section4(), &["environment.distractors.0.offset_px=-3"]).unwrap();
    assert!((s.distractors[0].offset_m + 3.0 * 10.0 / 320.0).abs() < 1e-12);
    let e = load(&section4(), &["environment.distractors.1.offset_px=3"]).unwrap_err();
    assert!(e.contains("has 1 item(s), so no item 1"), "{e}");
    // A list the file does not have.
    let e = load(&text(), &["environment.overpasses.0.height_m=7"]).unwrap_err();
    assert!(
        e.contains("`environment.overpasses` has no items, so no item 0"),
        "{e}"
    );
    let e = load(&section4(), &["environment.distractors.x=3"]).unwrap_err();
    assert!(e.contains("is a list: name an item by its index"), "{e}");
    // A pole beside a horizontal feature (segment 0 is the outer top) is refused.
    let e = load(&section4(), &["environment.distractors.0.feature=0"]).unwrap_err();
    assert!(
        e.contains("`environment.distractors[0].feature` = 0: segment 0 is horizontal"),
        "{e}"
    );
    let e = load(&section4(), &["environment.distractors.0.feature=10"]).unwrap_err();
    assert!(e.contains("must be a segment of the target, 0–9"), "{e}");
    let e = load(&section4(), &["environment.distractors.0.kind=\"tree\""]).unwrap_err();
    assert!(
        e.contains("must be \"pole\", \"wire\" or \"shadow\""),
        "{e}"
    );
    // A shadow edge beside any feature, while the sun lights the board; not with the sun
    // behind it.
    let s = load(&section4(), &["environment.distractors.0.kind=\"shadow\""]).unwrap();
    assert!(matches!(
        s.distractors[0].kind,
        sim_render::DistractorKind::Shadow { root_m, depth_m } if root_m.is_finite() && depth_m > 0.0
    ));
    let e = load(
        &section4(),
        &[
            "environment.distractors.0.kind=\"shadow\"",
            "environment.sun.azimuth_deg=-30",
        ],
    )
    .unwrap_err();
    assert!(e.contains("needs the sun in front of it"), "{e}");
    let e = load(&section4(), &["environment.distractors.0.albedo=1.5"]).unwrap_err();
    assert!(
        e.contains("`environment.distractors[0].albedo` = 1.5: must be 0–1"),
        "{e}"
    );
    let e = load(&section4(), &["environment.overpasses.0.height_m=2"]).unwrap_err();
    assert!(
        e.contains("`environment.overpasses[0].height_m` = 2: must be 4.5–20 m"),
        "{e}"
    );
    let e = load(&section4(), &["environment.overpasses.0.station_m=9000"]).unwrap_err();
    assert!(e.contains("must lie on the route"), "{e}");
}

/// The camera effects' fields: bad values are refused naming the field and what is
/// allowed, from a `--set` and from the file at its line; good ones are taken.
#[test]
fn camera_effects_are_validated_with_the_field_named() {
    for (set, needle) in [
        (
            "environment.sensor.vignetting=1.5",
            "`environment.sensor.vignetting` = 1.5: must be 0–1",
        ),
        (
            "environment.sensor.vignetting=nan",
            "`environment.sensor.vignetting` = NaN: must be 0–1",
        ),
        (
            "environment.sensor.shot_noise_full_well_e=10",
            "`environment.sensor.shot_noise_full_well_e` = 10: must be 100–1e7 electrons",
        ),
        (
            "environment.sensor.auto_gain={time_constant_s=0}",
            "`environment.sensor.auto_gain.time_constant_s` = 0: must be 0.1–60 s",
        ),
        (
            "environment.sensor.auto_gain={target_grey=250}",
            "`environment.sensor.auto_gain.target_grey` = 250: must be 10–245 grey levels",
        ),
        (
            "environment.sensor.auto_gain={max_gain=inf}",
            "`environment.sensor.auto_gain.max_gain` = inf: must be 1–64",
        ),
        (
            "environment.sensor.auto_gain={gain=2}",
            "unknown field `gain`",
        ),
    ] {
        let e = load(&text(), &[set]).unwrap_err();
        assert!(e.contains(needle), "{set}: {e}");
    }
    let t = text().replace(
        "sensor = { noise_sigma_grey = 2.0 }",
        "sensor = { noise_sigma_grey = 2.0, vignetting = -0.1 }",
    );
    assert_ne!(t, text());
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "vignetting = -0.1");
    assert!(e.starts_with(&format!("/bad.toml:{line}:")), "{e}");
    assert!(
        e.contains("`environment.sensor.vignetting` = -0.1: must be 0–1"),
        "{e}"
    );
    let t = text().replace(
        "sensor = { noise_sigma_grey = 2.0 }",
        "sensor = { noise_sigma_grey = 2.0, auto_gain = { max_gain = 0.5 } }",
    );
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "max_gain = 0.5");
    assert!(e.starts_with(&format!("/bad.toml:{line}:")), "{e}");
    assert!(
        e.contains("`environment.sensor.auto_gain.max_gain` = 0.5"),
        "{e}"
    );

    let s = load(
        &text(),
        &[
            "environment.sensor.vignetting=0.6",
            "environment.sensor.shot_noise_full_well_e=20000",
            "environment.sensor.auto_gain={time_constant_s=0.3}",
        ],
    )
    .unwrap();
    assert_eq!(s.sensor.vignetting, 0.6);
    assert_eq!(s.sensor.shot_noise_full_well_e, Some(20000.0));
    let a = s.sensor.auto_gain.unwrap();
    assert_eq!((a.time_constant_s, a.target_grey), (0.3, 110.0));
    // Off by default.
    let s = load(&text(), &[]).unwrap();
    assert_eq!(s.sensor, sim_render::Sensor::default());
}

/// Ground textures and the road's surface: bad values are refused naming the field, from a
/// `--set` and from the file; good ones are taken.
#[test]
fn textures_and_the_road_surface_are_validated_with_the_field_named() {
    for (set, needle) in [
        (
            "environment.textures.contrast=3",
            "`environment.textures.contrast` = 3: must be 0–2",
        ),
        (
            "environment.textures.contrast=nan",
            "`environment.textures.contrast` = NaN: must be 0–2",
        ),
        (
            "environment.road.surface=\"mud\"",
            "`environment.road.surface` = \"mud\": must be \"asphalt\" or \"gravel\"",
        ),
        (
            "environment.textures={enable=true}",
            "unknown field `enable`",
        ),
    ] {
        let e = load(&text(), &[set]).unwrap_err();
        assert!(e.contains(needle), "{set}: {e}");
    }
    let t = text().replace(
        "sensor = { noise_sigma_grey = 2.0 }",
        "sensor = { noise_sigma_grey = 2.0 }\nroad = { surface = \"tarmac\" }",
    );
    assert_ne!(t, text());
    let e = load(&t, &[]).unwrap_err();
    let line = line_of(&t, "surface = \"tarmac\"");
    assert!(e.starts_with(&format!("/bad.toml:{line}:")), "{e}");
    assert!(e.contains("`environment.road.surface`"), "{e}");

    let s = load(
        &text(),
        &[
            "environment.textures={enabled=true, contrast=0.5}",
            "environment.road.surface=\"gravel\"",
        ],
    )
    .unwrap();
    assert!(s.textures.enabled);
    assert_eq!(s.textures.contrast, 0.5);
    assert_eq!(s.road_surface, sim_render::RoadSurface::Gravel);
    let s = load(&text(), &[]).unwrap();
    assert_eq!(s.textures, sim_render::Textures::default());
    assert_eq!(s.road_surface, sim_render::RoadSurface::Asphalt);
}

/// `--set` on one key of a table the file does not have, whose other fields have no
/// defaults: the error says to give the table whole, with the defaults and the value asked
/// for, and what it says to write is accepted.
#[test]
fn a_set_on_a_table_without_defaults_says_what_to_write() {
    let e = load(&text(), &["chase.controller.lookahead.min_m=3"]).unwrap_err();
    assert!(
        e.contains("`chase.controller.lookahead` is not in the file")
            && e.contains("missing field `base_m`"),
        "{e}"
    );
    let suggested = e
        .split("--set '")
        .nth(1)
        .and_then(|rest| rest.split('\'').next())
        .unwrap_or_else(|| panic!("no suggestion in: {e}"));
    assert!(suggested.contains("min_m = 3"), "{suggested}");
    let s = load(&text(), &[suggested]).unwrap_or_else(|e| panic!("{suggested}: {e}"));
    assert_eq!(s.chase.lookahead.min_m, 3.0);
}

/// A lead whose speed profile drives it past the route's end is valid (it stops there), and
/// warned of with the distance against the route's length.
#[test]
fn a_lead_driven_past_the_roads_end_is_warned_of() {
    let s = load(&text(), &["duration_s=10000"]).unwrap();
    let w = s.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("beyond the route's") && w[0].contains("stop at the road's end"),
        "{w:?}"
    );
}

/// A lead faster than the chase's gap keeper will drive is valid, and warned of, naming
/// both fields; no shipped scenario is (one may be warned of what its road file holds and
/// carfollow does not draw).
#[test]
fn a_lead_faster_than_the_gap_keeper_is_warned_of() {
    // 40 s, so that the lead stays on the route's 1160 m.
    let s = load(
        &text(),
        &[
            "lead.speed_profile=[[0.0, 8.0], [20.0, 25.0]]",
            "duration_s=40",
        ],
    )
    .unwrap();
    let w = s.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("`lead.speed_profile` reaches 25 m/s")
            && w[0].contains("`chase.controller.gap_keeper.max_speed_mps` (20 m/s"),
        "{w:?}"
    );
    let s = load(
        &text(),
        &[
            "lead.speed_profile=[[0.0, 8.0], [20.0, 25.0]]",
            "chase.controller.gap_keeper.max_speed_mps=30",
            "duration_s=40",
        ],
    )
    .unwrap();
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    for name in sim_core::shipped_scenarios() {
        let s = Scenario::shipped(name, &[]).unwrap().unwrap();
        let w = s.warnings();
        assert!(
            w.iter()
                .all(|w| w.contains(".xodr:") && w.contains("are not drawn")),
            "{name}: {w:?}"
        );
    }
}

/// A key given twice is named, at the line of its second use.
#[test]
fn a_duplicate_key_is_named() {
    let text = text().replacen(
        "duration_s = 90.0",
        "duration_s = 90.0\nduration_s = 60.0",
        1,
    );
    let e = load(&text, &[]).unwrap_err().to_string();
    assert!(e.contains(":13:1: duplicate key `duration_s`"), "{e}");
}

/// `[environment.fog]`: off by default (and then absent from the resolved scenario, so a
/// scenario without it writes what it wrote before fog existed); its visual range is set by
/// the file or by `--set`, and a bad one is refused with the file, line and field.
/// `chase.start_at_cruise_speed` starts the chase at its cruise speed; off, the chase starts
/// at the lead's speed; on without a cruise speed it is refused at its line.
#[test]
fn the_chase_starts_at_its_cruise_speed_only_when_asked() {
    let base = text();
    let s = load(&base, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.chase_initial_speed_mps, s.lead_initial_speed_mps);
    let cruising = base.replace(
        "[chase]\ninitial_gap_m = 10.0\n",
        "[chase]\ninitial_gap_m = 10.0\nstart_at_cruise_speed = true\n\
         controller = { lane_keeping = true, cruise_speed_mps = 12.5 }\n",
    );
    assert_ne!(cruising, base);
    let s = load(&cruising, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.chase_initial_speed_mps, 12.5);
    // A sweep's axis over the cruise speed moves the start with it.
    let s = load(&cruising, &["chase.controller.cruise_speed_mps=4.25"]).unwrap();
    assert_eq!(s.chase_initial_speed_mps, 4.25);

    let without = base.replace(
        "[chase]\ninitial_gap_m = 10.0\n",
        "[chase]\ninitial_gap_m = 10.0\nstart_at_cruise_speed = true\n",
    );
    let e = load(&without, &[]).unwrap_err();
    let line = line_of(&without, "start_at_cruise_speed");
    assert!(
        e.starts_with(&format!("/bad.toml:{line}:"))
            && e.contains("`chase.start_at_cruise_speed`")
            && e.contains("cruise_speed_mps"),
        "{e}"
    );
    // Reachable by --set, and refused the same way there.
    let e = load(&base, &["chase.start_at_cruise_speed=true"]).unwrap_err();
    assert!(e.contains("chase.start_at_cruise_speed"), "{e}");
}

/// `route.elevation`: a road that rises and falls, off by default; given by the file or by
/// `--set`; a profile the vehicles cannot drive is refused naming the file's line and the
/// field; the vehicles start on it and the ground follows it.
#[test]
fn an_elevation_profile_is_checked_and_the_ground_follows_it() {
    let plain = load(&text(), &[]).unwrap();
    assert!(plain.route.elevation.is_empty());
    let profile = "route.elevation=[[0.0, 0.0, 0.04, 0.0, 0.0], \
                   [100.0, 4.0, 0.04, -0.0002, 0.0], [200.0, 6.0, 0.0, 0.0, 0.0]]";
    let s = load(&text(), &[profile]).unwrap();
    assert_eq!(s.route.elevation.len(), 3);
    let plan = Plan::new(&s).unwrap();
    let terrain = plan
        .scene()
        .terrain()
        .expect("a ground that follows the road");
    let route = sim_render::Route::new(s.route.clone());
    for st in [0.0, 50.0, 100.0, 150.0, 250.0] {
        let [x, z] = route.point(st, 0.0);
        let want = if st <= 100.0 {
            0.04 * st
        } else if st <= 200.0 {
            let d = st - 100.0;
            4.0 + 0.04 * d - 0.0002 * d * d
        } else {
            6.0
        };
        assert!((terrain.height_m(x, z) - want).abs() < 0.005, "{st}");
    }
    // The lead starts on the slope, at its height there.
    let lead_y = f64::from(plan.start_poses().1.unwrap().translation.y);
    let at_start = 0.04 * s.lead_start_m.min(100.0);
    assert!((lead_y - at_start).abs() < 0.1, "{lead_y} vs {at_start}");

    // In the file: refused at its line.
    let bad = text().replacen(
        "[route]\n",
        "[route]\nelevation = [[0.0, 0.0, 0.3, 0.0, 0.0]]\n",
        1,
    );
    let e = load(&bad, &[]).unwrap_err();
    let line = line_of(&bad, "elevation = ");
    assert!(
        e.contains(&format!("bad.toml:{line}")) && e.contains("`route.elevation`"),
        "{e}"
    );
    assert!(e.contains("grade") && e.contains("at most 20 %"), "{e}");
    assert!(!e.contains('\n'), "{e}");
    for (set, says) in [
        ("route.elevation=[[5.0, 0.0, 0.0, 0.0, 0.0]]", "station 0"),
        (
            "route.elevation=[[0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0]]",
            "after the one before",
        ),
        (
            "route.elevation=[[0.0, 0.0, 0.01, 0.0, 0.0], [50.0, 2.0, 0.0, 0.0, 0.0]]",
            "a step",
        ),
        ("route.elevation=[[0.0, 0.0, 0.0, 0.001, 0.0]]", "grade"),
        ("route.elevation=[[0.0, 0.0, 0.0, 0.0]]", "route.elevation"),
    ] {
        let e = load(&text(), &[set]).unwrap_err();
        assert!(
            e.contains("route.elevation") && e.contains(says),
            "{set}: {e}"
        );
    }
}

/// `route.lane_offset`: the centre line moved off the reference line, off by default; given
/// by the file or by `--set`; an offset the vehicles cannot drive is refused naming the
/// file's line and the field; the vehicles start in the moved lanes.
#[test]
fn a_lane_offset_is_checked_and_moves_the_lanes() {
    let plain = load(&text(), &[]).unwrap();
    assert!(plain.route.lane_offset.is_empty());
    let s = load(&text(), &["route.lane_offset=[[0.0, 2.0, 0.0, 0.0, 0.0]]"]).unwrap();
    assert_eq!(s.route.lane_offset, vec![[0.0, 2.0, 0.0, 0.0, 0.0]]);
    // The lead starts 2 m to the left of where it starts without the offset.
    let at = |s: &sim_core::Scenario| {
        let p = Plan::new(s).unwrap().start_poses().1.unwrap().translation;
        [f64::from(p.x), f64::from(p.z)]
    };
    let ([x0, z0], [x1, z1]) = (at(&plain), at(&s));
    let heading = sim_render::Route::new(plain.route.clone()).at(plain.lead_start_m)[2];
    let (dx, dz) = (x1 - x0, z1 - z0);
    assert!(
        (dx + 2.0 * heading.sin()).abs() < 0.01 && (dz + 2.0 * heading.cos()).abs() < 0.01,
        "moved by ({dx}, {dz})"
    );
    // In the file: refused at its line.
    let bad = text().replacen(
        "[route]\n",
        "[route]\nlane_offset = [[0.0, 0.0, 0.5, 0.0, 0.0]]\n",
        1,
    );
    let e = load(&bad, &[]).unwrap_err();
    let line = line_of(&bad, "lane_offset = ");
    assert!(
        e.contains(&format!("bad.toml:{line}")) && e.contains("`route.lane_offset`"),
        "{e}"
    );
    assert!(e.contains("changes by 0.500 m a metre"), "{e}");
    for (set, says) in [
        ("route.lane_offset=[[5.0, 0.0, 0.0, 0.0, 0.0]]", "station 0"),
        (
            "route.lane_offset=[[0.0, 30.0, 0.0, 0.0, 0.0]]",
            "at most 25 m",
        ),
        (
            "route.lane_offset=[[0.0, 0.0, 0.0, 0.0, 0.0], [50.0, 2.0, 0.0, 0.0, 0.0]]",
            "a step",
        ),
    ] {
        let e = load(&text(), &[set]).unwrap_err();
        assert!(
            e.contains("route.lane_offset") && e.contains(says),
            "{set}: {e}"
        );
    }
}
