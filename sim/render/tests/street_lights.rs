//! Street lights (`Densities::street_lights_per_km`), measured on the rendered frame: at
//! night the road under a lamp and midway between two are lit as the model's inverse-square
//! law predicts (a fall as 1/d misses by far); a lens in view glows at night and not by day;
//! without street lights a description reads and writes as before (the stored frame hashes
//! of `render.rs` hold the frames).
//!
//! Run: `cargo test -p sim-render --release --test street_lights`.

use image::GrayImage;
use nalgebra::Isometry3;
use sim_render::{CameraRig, FrameInput, SceneDescription, StreetLights};

mod common;
use common::{bare_plain_sensor, options, renderer};

/// Lamps every 40 m: at stations −30, 10, 50, 90, 130, 170, … of the bare straight road.
const PER_KM: f64 = 25.0;
/// The chase's station: the lamp at 90 m is 15 m ahead, the next at 130 m 55 m ahead.
const CHASE_S: f64 = 75.0;
/// The chase's station for the lens: the lamp at 130 m is 30 m ahead, in view.
const LENS_CHASE_S: f64 = 100.0;
/// How far right of the centreline the road is sampled, metres: inside the right lane,
/// clear of the paint, 0.5 m nearer the centre than the lamps' heads.
const SAMPLE_LATERAL_M: f64 = 2.5;

/// A bare straight road without textures, noise or automatic gain (the gain fixed at
/// `gain`), the sun at `elevation_deg`, `per_km` street lights.
fn description(elevation_deg: f64, per_km: f64, gain: f64) -> SceneDescription {
    let mut d = bare_plain_sensor(5);
    d.textures.enabled = false;
    d.sensor.gain = gain;
    d.sun.elevation_deg = elevation_deg;
    d.densities.street_lights_per_km = per_km;
    d
}

/// The frame from the chase at station `chase_s` in the right lane (the lead 180 m ahead,
/// out of the way), the chase's pose, and the lamps' sources.
fn frame(d: SceneDescription, chase_s: f64) -> (GrayImage, Isometry3<f64>, Vec<[f64; 3]>) {
    let mut r = renderer(d, &options());
    let lane = r.scene().description().route.lane_width_m;
    let world_from_chase = r.scene().route().pose_at(chase_s, 0.5 * lane);
    let world_from_lead = r.scene().route().pose_at(chase_s + 180.0, 0.5 * lane);
    let sources = StreetLights::sources(r.scene());
    let frame = r
        .render(&FrameInput::fixed_camera(
            0,
            0.0,
            world_from_chase,
            world_from_lead,
        ))
        .expect("frame");
    (frame.image, world_from_chase, sources)
}

/// The pixel nearest where the camera sees the world point `p`.
fn pixel(world_from_chase: &Isometry3<f64>, p: [f64; 3]) -> (u32, u32) {
    let [x, y] = CameraRig::default()
        .project_world(world_from_chase, p)
        .expect("in front");
    (x.round() as u32, y.round() as u32)
}

/// Mean grey of the pixel at `(x, y)` and its left and right neighbours (a row: on the road
/// far ahead a pixel spans metres along it, across it centimetres).
fn row_mean(image: &GrayImage, (x, y): (u32, u32)) -> f64 {
    (x - 1..=x + 1)
        .map(|x| f64::from(image.get_pixel(x, y)[0]))
        .sum::<f64>()
        / 3.0
}

/// The road's point at station `s`, [`SAMPLE_LATERAL_M`] right of the centreline.
fn road_point(d: &SceneDescription, s: f64) -> [f64; 3] {
    let scene = sim_render::Scene::build(d.clone()).expect("scene");
    let [x, z] = scene.route().point(s, SAMPLE_LATERAL_M);
    [x, 0.0, z]
}

/// The illuminance (lux) every lamp gives the road (facing up) at `p`, by the model's
/// formula: I(θ) cos θ / d² (with `inverse_square` false, I(θ) cos θ / d, a law that is
/// not the model's).
fn illuminance(sources: &[[f64; 3]], p: [f64; 3], inverse_square: bool) -> f64 {
    sources
        .iter()
        .map(|&l| {
            let e = StreetLights::illuminance_lux(l, p, [0.0, 1.0, 0.0]);
            if inverse_square {
                e
            } else {
                let d =
                    ((p[0] - l[0]).powi(2) + (p[1] - l[1]).powi(2) + (p[2] - l[2]).powi(2)).sqrt();
                e * d
            }
        })
        .sum()
}

/// At night, with no other light, the road's grey under the lamp 15 m ahead (station 90)
/// and midway to the next (station 110, 35 m ahead) stand in the ratio of the model's
/// illuminances, I cos θ / d² summed over the lamps, within 8 % (the road's albedo is the
/// same at both and divides out; each grey is a row of three pixels, the midway one about
/// 19 grey levels at gain 100); a fall as 1/d would give a ratio less than half of it. The ambient
/// light of the night sky is 2.5e-6 of sunset's, far below the lamps' light.
#[test]
fn the_road_is_lit_as_the_inverse_square() {
    let d = description(-18.0, PER_KM, 100.0);
    let (under_p, mid_p) = (road_point(&d, 90.0), road_point(&d, 110.0));
    let (image, chase, sources) = frame(d, CHASE_S);
    assert!(sources.len() >= 7, "{} lamps", sources.len());
    let under = row_mean(&image, pixel(&chase, under_p));
    let mid = row_mean(&image, pixel(&chase, mid_p));
    let predicted = illuminance(&sources, under_p, true) / illuminance(&sources, mid_p, true);
    let one_over_d = illuminance(&sources, under_p, false) / illuminance(&sources, mid_p, false);
    let ratio = under / mid;
    eprintln!(
        "under the lamp {under:.1}, midway {mid:.1}: ratio {ratio:.2}, predicted {predicted:.2} \
         (as 1/d: {one_over_d:.2}); {:.1} and {:.1} lux",
        illuminance(&sources, under_p, true),
        illuminance(&sources, mid_p, true)
    );
    assert!(under < 250.0, "the road under the lamp clips ({under})");
    assert!(mid > 8.0, "midway too dark to measure ({mid})");
    assert!(
        (ratio / predicted - 1.0).abs() < 0.08,
        "ratio {ratio:.3}, predicted {predicted:.3}"
    );
    assert!(
        ratio > 2.0 * one_over_d,
        "{ratio} against 1/d's {one_over_d}"
    );
}

/// A lens in view (the lamp 30 m ahead, seen from outside its cone, by its stray light)
/// glows white at night; by day, at the gain that shows the day, it does not; at night
/// without street lights the same place is black.
#[test]
fn a_lens_glows_at_night() {
    let brightest = |image: &GrayImage, (x, y): (u32, u32)| {
        let mut max = 0u8;
        for yy in y.saturating_sub(2)..=(y + 2).min(image.height() - 1) {
            for xx in x.saturating_sub(2)..=(x + 2).min(image.width() - 1) {
                max = max.max(image.get_pixel(xx, yy)[0]);
            }
        }
        max
    };
    let d = description(-18.0, PER_KM, 200.0);
    let below = road_point(&d, 130.0);
    let (night, chase, sources) = frame(d, LENS_CHASE_S);
    let plan = |l: &[f64; 3]| (l[0] - below[0]).hypot(l[2] - below[2]);
    let lens = *sources
        .iter()
        .min_by(|a, b| plan(a).total_cmp(&plan(b)))
        .expect("lamps");
    assert!(plan(&lens) < 1.0, "no lamp at station 130: {sources:?}");
    let at = pixel(&chase, [lens[0], lens[1] + 0.05, lens[2]]);
    let (day, _, _) = frame(description(40.0, PER_KM, 1.0), LENS_CHASE_S);
    let (dark, _, _) = frame(description(-18.0, 0.0, 200.0), LENS_CHASE_S);
    let (n, dy, dk) = (
        brightest(&night, at),
        brightest(&day, at),
        brightest(&dark, at),
    );
    eprintln!("lens at {at:?}: night {n}, day {dy}, night without lamps {dk}");
    assert!(n >= 250, "night {n}");
    assert!(dy < 245, "day {dy}");
    assert!(dk < 5, "night without lamps {dk}");
}

/// Without street lights a description writes nothing of them and reads back the same: a
/// scene description (and so a render worker's) is as before street lights existed.
#[test]
fn no_street_lights_write_nothing() {
    let d = description(-18.0, 0.0, 1.0);
    let json = serde_json::to_string(&d).expect("json");
    assert!(!json.contains("street_lights"), "{json}");
    let back: SceneDescription = serde_json::from_str(&json).expect("reads back");
    assert_eq!(back, d);
    let lit = description(-18.0, PER_KM, 1.0);
    assert!(serde_json::to_string(&lit)
        .expect("json")
        .contains("\"street_lights_per_km\":25.0"));
    assert!(StreetLights::lit(&lit));
    assert!(!StreetLights::lit(&description(40.0, PER_KM, 1.0)));
}
