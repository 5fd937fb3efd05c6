//! Weather, light and the sensor in scenario files: fog, rain and its spray, headlamps, the
//! sun below the horizon, tail lamps and read noise are off (or as before) by default, set by
//! their dotted paths, and refused with the field named.
//! Run with `cargo test -p sim-core --test weather_files`.

mod common;
use common::{line_of, load, text};

#[test]
fn fog_is_off_by_default_set_by_its_path_and_checked() {
    let s = load(&text(), &[]).unwrap();
    assert_eq!(s.fog, None);
    assert!(s.resolved_json().pointer("/environment/fog").is_none());
    let s = load(&text(), &["environment.fog.visual_range_m=60"]).unwrap();
    let fog = s.fog.expect("fog");
    assert_eq!(fog.visual_range_m, 60.0);
    assert!((fog.extinction_per_m() - 3.912 / 60.0).abs() < 1e-15);
    assert_eq!(
        s.resolved_json().pointer("/environment/fog/visual_range_m"),
        Some(&serde_json::json!(60.0))
    );
    for bad in ["0.5", "-3", "nan", "inf", "1e6"] {
        let e = load(&text(), &[&format!("environment.fog.visual_range_m={bad}")]).unwrap_err();
        assert!(
            e.contains("`environment.fog.visual_range_m`") && e.contains("must be 1–100000 m"),
            "{bad}: {e}"
        );
    }
    let t = text().replace(
        "sensor = { noise_sigma_grey = 2.0 }",
        "sensor = { noise_sigma_grey = 2.0 }\nfog = { visual_range_m = 0.0 }",
    );
    let e = load(&t, &[]).unwrap_err();
    assert!(
        e.starts_with(&format!(
            "/bad.toml:{}:",
            line_of(&t, "fog = { visual_range_m")
        )) && e.contains("`environment.fog.visual_range_m` = 0: must be 1–100000 m"),
        "{e}"
    );
    let e = load(&text(), &["environment.fog.visibility_m=60"]).unwrap_err();
    assert!(e.contains("unknown field `visibility_m`"), "{e}");
}

/// `[environment.rain]`: off by default (and then absent from the resolved scenario, so a
/// scenario without it writes what it wrote before rain existed); its rate is set by the
/// file or by `--set`, and a bad one (negative, too large, not a number, an unknown key) is
/// refused with the file, line and field.
#[test]
fn rain_is_off_by_default_set_by_its_path_and_checked() {
    let s = load(&text(), &[]).unwrap();
    assert_eq!(s.rain, None);
    assert!(s.resolved_json().pointer("/environment/rain").is_none());
    let s = load(&text(), &["environment.rain.rate_mm_h=16"]).unwrap();
    let rain = s.rain.expect("rain");
    assert_eq!(rain.rate_mm_h, 16.0);
    assert_eq!(rain.band(), sim_render::RainBand::Heavy);
    assert_eq!(
        s.resolved_json().pointer("/environment/rain/rate_mm_h"),
        Some(&serde_json::json!(16.0))
    );
    for bad in ["-0.5", "-3", "nan", "inf", "201"] {
        let e = load(&text(), &[&format!("environment.rain.rate_mm_h={bad}")]).unwrap_err();
        assert!(
            e.contains("`environment.rain.rate_mm_h`") && e.contains("must be 0–200 mm/h"),
            "{bad}: {e}"
        );
    }
    let t = text().replace(
        "sensor = { noise_sigma_grey = 2.0 }",
        "sensor = { noise_sigma_grey = 2.0 }\nrain = { rate_mm_h = -1.0 }",
    );
    let e = load(&t, &[]).unwrap_err();
    assert!(
        e.starts_with(&format!("/bad.toml:{}:", line_of(&t, "rain = { rate_mm_h")))
            && e.contains("`environment.rain.rate_mm_h` = -1: must be 0–200 mm/h"),
        "{e}"
    );
    let e = load(&text(), &["environment.rain.intensity=16"]).unwrap_err();
    assert!(e.contains("unknown field `intensity`"), "{e}");
}

/// `[environment.rain]`'s options, spray and mirrored lamps: off by default (and then absent
/// from the resolved scenario), set by the file or by `--set`, and refused without rain
/// (a rate of 0) or when not a boolean, with the file, line and field.
#[test]
fn spray_and_mirrored_lamps_are_off_by_default_set_and_checked() {
    let s = load(&text(), &["environment.rain.rate_mm_h=16"]).unwrap();
    let rain = s.rain.expect("rain");
    assert!(!rain.spray && !rain.lamp_reflections);
    assert!(s
        .resolved_json()
        .pointer("/environment/rain/spray")
        .is_none());
    let s = load(
        &text(),
        &[
            "environment.rain.rate_mm_h=16",
            "environment.rain.spray=true",
            "environment.rain.lamp_reflections=true",
        ],
    )
    .unwrap();
    let rain = s.rain.expect("rain");
    assert!(rain.spray && rain.lamp_reflections);
    for field in ["spray", "lamp_reflections"] {
        let e = load(
            &text(),
            &[
                "environment.rain.rate_mm_h=0",
                &format!("environment.rain.{field}=true"),
            ],
        )
        .unwrap_err();
        assert!(
            e.contains(&format!("`environment.rain.{field}` = true: needs rain")),
            "{e}"
        );
        let e = load(
            &text(),
            &[
                "environment.rain.rate_mm_h=8",
                &format!("environment.rain.{field}=2"),
            ],
        )
        .unwrap_err();
        assert!(e.contains("expected a boolean"), "{field}: {e}");
    }
    let t = text().replace(
        "sensor = { noise_sigma_grey = 2.0 }",
        "sensor = { noise_sigma_grey = 2.0 }\nrain = { rate_mm_h = 0.0, spray = true }",
    );
    let e = load(&t, &[]).unwrap_err();
    assert!(
        e.starts_with(&format!("/bad.toml:{}:", line_of(&t, "rain = { rate_mm_h")))
            && e.contains("`environment.rain.spray` = true: needs rain"),
        "{e}"
    );
}

/// `[chase.headlamps]`: off by default (and then absent from the resolved scenario); the
/// beam is set by the file or by `--set`, and a bad one is refused with the file, line and
/// field.
#[test]
fn headlamps_are_off_by_default_set_by_their_path_and_checked() {
    let s = load(&text(), &[]).unwrap();
    assert_eq!(s.headlamps, None);
    assert!(s.resolved_json().pointer("/chase/headlamps").is_none());
    for (beam, want) in [
        ("off", None),
        ("low", Some(sim_render::Beam::Low)),
        ("high", Some(sim_render::Beam::High)),
    ] {
        let s = load(&text(), &[&format!("chase.headlamps.beam={beam}")]).unwrap();
        assert_eq!(s.headlamps, want, "{beam}");
    }
    let e = load(&text(), &["chase.headlamps.beam=full"]).unwrap_err();
    assert!(
        e.contains("`chase.headlamps.beam` = \"full\": must be \"off\", \"low\" or \"high\""),
        "{e}"
    );
    let t = text().replace(
        "initial_gap_m = 10.0\n",
        "initial_gap_m = 10.0\nheadlamps = { beam = \"dipped\" }\n",
    );
    let e = load(&t, &[]).unwrap_err();
    assert!(
        e.starts_with(&format!("/bad.toml:{}:", line_of(&t, "headlamps = {"))),
        "{e}"
    );
    let e = load(&text(), &["chase.headlamps.dip=low"]).unwrap_err();
    assert!(e.contains("unknown field `dip`"), "{e}");
}

/// `[environment.sun] elevation_deg` takes the sun down to 18° below the horizon (night),
/// and no lower; a shadow distractor needs the sun above the horizon.
#[test]
fn the_sun_sets_down_to_minus_18_degrees() {
    for ok in ["0", "-6", "-10", "-18"] {
        let s = load(&text(), &[&format!("environment.sun.elevation_deg={ok}")])
            .unwrap_or_else(|e| panic!("{ok}: {e}"));
        assert_eq!(s.sun.elevation_deg, ok.parse::<f64>().unwrap());
    }
    for bad in ["-18.5", "-90", "91", "nan"] {
        let e = load(&text(), &[&format!("environment.sun.elevation_deg={bad}")]).unwrap_err();
        assert!(
            e.contains("`environment.sun.elevation_deg`") && e.contains("must be -18–90 degrees"),
            "{bad}: {e}"
        );
    }
}

/// `[lead.lamps] tail`: lit by default with the sun at or below the horizon and off by day
/// (and absent from the resolved scenario unless given); set by the file or by `--set`;
/// a bad value is refused naming the field.
#[test]
fn tail_lamps_are_lit_at_night_by_default_and_set_by_their_path() {
    let s = load(&text(), &[]).unwrap();
    assert!(!s.lead_tail_lamps);
    assert!(s.resolved_json().pointer("/lead/lamps").is_none());
    let night = load(&text(), &["environment.sun.elevation_deg=-10"]).unwrap();
    assert!(night.lead_tail_lamps);
    let s = load(
        &text(),
        &["environment.sun.elevation_deg=-10", "lead.lamps.tail=false"],
    )
    .unwrap();
    assert!(!s.lead_tail_lamps);
    let s = load(&text(), &["lead.lamps.tail=true"]).unwrap();
    assert!(s.lead_tail_lamps);
    let e = load(&text(), &["lead.lamps.tail=7"]).unwrap_err();
    assert!(
        e.contains("lead.lamps.tail") || e.contains("expected a boolean"),
        "{e}"
    );
    let e = load(&text(), &["lead.lamps.brake=true"]).unwrap_err();
    assert!(e.contains("unknown field `brake`"), "{e}");
}

/// `[environment.sensor] read_noise_e`: off by default (and absent from the resolved
/// scenario); 0–1000 electrons; it needs `shot_noise_full_well_e`.
#[test]
fn read_noise_in_electrons_needs_the_full_well_and_is_checked() {
    let s = load(&text(), &[]).unwrap();
    assert_eq!(s.sensor.read_noise_e, None);
    assert!(s
        .resolved_json()
        .pointer("/environment/sensor/read_noise_e")
        .is_none());
    let full = "environment.sensor.shot_noise_full_well_e=20000";
    let s = load(&text(), &[full, "environment.sensor.read_noise_e=20"]).unwrap();
    assert_eq!(s.sensor.read_noise_e, Some(20.0));
    let e = load(&text(), &[full, "environment.sensor.read_noise_e=-1"]).unwrap_err();
    assert!(
        e.contains("`environment.sensor.read_noise_e`") && e.contains("must be 0–1000 electrons"),
        "{e}"
    );
    let e = load(&text(), &["environment.sensor.read_noise_e=20"]).unwrap_err();
    assert!(
        e.contains("`environment.sensor.read_noise_e`")
            && e.contains("needs environment.sensor.shot_noise_full_well_e"),
        "{e}"
    );
}

#[test]
fn highlight_protection_is_off_by_default_set_by_its_path_and_checked() {
    let on = "environment.sensor.auto_gain.max_gain=64";
    let s = load(&text(), &[on]).unwrap();
    assert_eq!(s.sensor.auto_gain.unwrap().max_clipped_share, None);
    assert!(s
        .resolved_json()
        .pointer("/environment/sensor/auto_gain/max_clipped_share")
        .is_none());
    let share = "environment.sensor.auto_gain.max_clipped_share=0.01";
    let s = load(&text(), &[on, share]).unwrap();
    assert_eq!(s.sensor.auto_gain.unwrap().max_clipped_share, Some(0.01));
    for bad in ["-0.1", "0.6"] {
        let set = format!("environment.sensor.auto_gain.max_clipped_share={bad}");
        let e = load(&text(), &[on, &set]).unwrap_err();
        assert!(
            e.contains("`environment.sensor.auto_gain.max_clipped_share`")
                && e.contains("must be 0–0.5"),
            "{e}"
        );
    }
}
