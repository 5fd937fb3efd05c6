//! Tail and brake lamps (`LeadVehicle::tail_lamps`, `ActorBody::tail_lamps`,
//! `FrameInput::braking`), measured on the rendered frame: at night the lamps are the only
//! bright pixels, as bright as their luminance says; the scene's light adds only what
//! their lens reflects; braking, they are 17 times brighter (85 cd over 5 cd).
//!
//! Run: `cargo test -p sim-render --release --test tail_lamps`.

use image::GrayImage;
use sim_render::{
    ActorBody, Braking, FrameInput, Renderer, SceneDescription, TailLamps, VehicleKind,
};

mod common;
use common::{bare_plain_sensor, lead_ahead, options, renderer};

/// The sensor's gain the lamps are measured at: low enough that a brake lamp does not
/// clip (6.7 units of radiance times 0.12 times 255 is 206 grey levels).
const GAIN: f64 = 0.12;

/// A bare straight road seen by a plain sensor at [`GAIN`], the sun at `elevation_deg`
/// with `strength`, the lead's lamps `lamps`.
fn description(elevation_deg: f64, strength: f64, lamps: bool) -> SceneDescription {
    let mut d = bare_plain_sensor(3);
    d.sensor.gain = GAIN;
    d.sun.elevation_deg = elevation_deg;
    d.sun.strength = strength;
    d.lead.tail_lamps = lamps;
    d
}

/// The brightest grey of `image`.
fn brightest(image: &GrayImage) -> f64 {
    image.pixels().map(|p| f64::from(p[0])).fold(0.0, f64::max)
}

/// The frame with the lead `gap_m` ahead, its brake lamps lit or not.
fn lead_frame(r: &mut Renderer, gap_m: f64, braking: bool) -> GrayImage {
    if !braking {
        return lead_ahead(r, gap_m).0;
    }
    let route = r.scene().route();
    let lane = r.scene().description().route.lane_width_m;
    let input = FrameInput {
        braking: Braking(1),
        ..FrameInput::fixed_camera(
            0,
            0.0,
            route.pose_at(40.0, 0.5 * lane),
            route.pose_at(40.0 + gap_m, 0.5 * lane),
        )
    };
    r.render(&input).expect("frame").image
}

/// The grey a lens of radiance `radiance` (scene units) shows at [`GAIN`].
fn grey_of(radiance: f64) -> f64 {
    radiance * GAIN * 255.0
}

#[test]
fn at_night_the_lamps_glow_by_their_luminance() {
    let mut dark = renderer(description(-18.0, 0.75, false), &options());
    let (black, _) = lead_ahead(&mut dark, 12.0);
    assert!(brightest(&black) <= 1.0, "{}", brightest(&black));
    let mut lit = renderer(description(-18.0, 0.75, true), &options());
    let (image, _) = lead_ahead(&mut lit, 12.0);
    let expected = grey_of(TailLamps::radiance(false));
    let got = brightest(&image);
    assert!((got - expected).abs() <= 1.0, "{got} vs {expected}");
    // Two lamps of 0.2 × 0.12 m, 12 m off: about 5 × 3 pixels each, lit (the rest black).
    let bright = image
        .pixels()
        .filter(|p| f64::from(p[0]) > 0.5 * expected)
        .count();
    assert!((16..=50).contains(&bright), "{bright} lamp pixels");
}

#[test]
fn the_scenes_light_adds_only_what_the_lens_reflects() {
    // The lamps' pixels, from the night's frame (where nothing else is lit).
    let mut night = renderer(description(-18.0, 0.75, true), &options());
    let (dark, _) = lead_ahead(&mut night, 12.0);
    let glow = grey_of(TailLamps::radiance(false));
    let lamps: Vec<(u32, u32)> = dark
        .enumerate_pixels()
        .filter(|(_, _, p)| f64::from(p[0]) > 0.5 * glow)
        .map(|(x, y, _)| (x, y))
        .collect();
    // By day under the ambient light alone (0.25), a lens shows its glow plus 0.1 × 0.25
    // of the light: the glow does not depend on the light.
    let mut day = renderer(description(40.0, 0.0, true), &options());
    let (image, _) = lead_ahead(&mut day, 12.0);
    let expected = grey_of(TailLamps::radiance(false) + TailLamps::LENS_ALBEDO * 0.25);
    let got = lamps
        .iter()
        .map(|&(x, y)| f64::from(image.get_pixel(x, y)[0]))
        .fold(0.0, f64::max);
    assert!((got - expected).abs() <= 1.0, "{got} vs {expected}");
}

#[test]
fn braking_lights_the_brake_lamps() {
    let mut r = renderer(description(-18.0, 0.75, true), &options());
    let tail = brightest(&lead_frame(&mut r, 12.0, false));
    let brake = brightest(&lead_frame(&mut r, 12.0, true));
    let expected = TailLamps::radiance(true) / TailLamps::radiance(false);
    assert!((expected - 17.0).abs() < 1e-9);
    assert!(
        (brake / tail / expected - 1.0).abs() < 0.1,
        "{brake} / {tail} vs {expected}"
    );
    assert!((brake - grey_of(TailLamps::radiance(true))).abs() <= 1.0);
}

#[test]
fn an_actors_lamps_glow_and_brake_as_the_leads() {
    let mut d = description(-18.0, 0.75, false);
    d.actors = vec![ActorBody {
        kind: VehicleKind::Sedan,
        albedo: 0.5,
        tail_lamps: true,
    }];
    let mut r = renderer(d, &options());
    let route = r.scene().route().clone();
    let lane = r.scene().description().route.lane_width_m;
    let chase = route.pose_at(40.0, 0.5 * lane);
    // The lead far behind the camera; the sedan 12 m ahead (its body's centre).
    let lead = route.pose_at(5.0, 0.5 * lane);
    let sedan = route.pose_at(52.0, 0.5 * lane);
    let mut frame = |braking| {
        let input = FrameInput {
            braking,
            ..FrameInput::fixed_camera(0, 0.0, chase, lead).with_actors(vec![sedan])
        };
        brightest(&r.render(&input).expect("frame").image)
    };
    let tail = frame(Braking::default());
    let lead_braking = frame(Braking(1));
    let braking = frame(Braking(0b10));
    assert!(
        (tail - grey_of(TailLamps::radiance(false))).abs() <= 1.0,
        "{tail}"
    );
    assert_eq!(lead_braking, tail, "the lead's brake is not the sedan's");
    assert!(
        (braking - grey_of(TailLamps::radiance(true))).abs() <= 1.0,
        "{braking}"
    );
}
