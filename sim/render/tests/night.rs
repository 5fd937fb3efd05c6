//! Night (`Sun::elevation_deg` below the horizon, `SceneDescription::headlamps`), measured on
//! the rendered frame. With the sun 18° below the horizon and the lamps off the frame is
//! black; the chase's headlamps light the lead's board with an irradiance that follows the
//! beam's intensity, the cosine on the board and the inverse square of the distance; the
//! high beam reaches farther than the low.
//!
//! Run: `cargo test -p sim-render --release --test night`.

use image::GrayImage;
use sim_render::{
    twilight_factor, Beam, CameraRig, GroundTruth, Headlamps, SceneDescription, BOARD_ALBEDO,
};

mod common;
use common::{bare_plain_sensor, board_paint, lead_ahead, mean, options, renderer};

/// A bare straight road, no noise, no vignetting, no automatic gain (the sensor's gain
/// fixed at `gain`), the sun at `elevation_deg`, the headlamps on `beam`.
fn description(elevation_deg: f64, beam: Option<Beam>, gain: f64) -> SceneDescription {
    let mut d = bare_plain_sensor(5);
    d.sensor.gain = gain;
    d.sun.elevation_deg = elevation_deg;
    d.headlamps = beam;
    d
}

/// Mean grey of `image`.
fn frame_mean(image: &GrayImage) -> f64 {
    image.pixels().map(|p| f64::from(p[0])).sum::<f64>() / (image.width() * image.height()) as f64
}

/// The headlamps' irradiance (scene units) on the board's centre, from the model's own
/// formula: the board's centre in the chase's frame (from the truth, through the default
/// rig on a level road), each lamp's intensity towards it over `LUX_PER_UNIT`, times the
/// cosine on the board (facing the chase) over the squared distance.
fn predicted_irradiance(beam: Beam, truth: &GroundTruth, d: &SceneDescription) -> f64 {
    let mount = CameraRig::default().mount;
    let p = mount.pitch_deg.to_radians();
    let [cx, cy, cz] = truth.target_cam_m;
    // Camera axes (x right, y down, z forward, pitched down) in the chase's (x forward,
    // y up, z right).
    let board = [
        mount.forward_offset_m + cz * p.cos() - cy * p.sin(),
        mount.height_m - cz * p.sin() - cy * p.cos(),
        cx,
    ];
    let lamp = Headlamps::of(beam);
    Headlamps::positions(&d.chase)
        .iter()
        .map(|l| {
            let v = [board[0] - l[0], board[1] - l[1], board[2] - l[2]];
            let d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            let r = d2.sqrt();
            let h = v[2].atan2(v[0]).to_degrees();
            let e = (v[1] / r).asin().to_degrees();
            let cos = v[0] / r;
            lamp.intensity_cd(h, e) * cos / d2 / Headlamps::LUX_PER_UNIT
        })
        .sum()
}

/// The light paint's mean grey with the lead `gap_m` ahead at night on `beam` at `gain`,
/// the predicted grey (irradiance × albedo × gain × 255) and the board's distance.
fn board_at_night(beam: Beam, gain: f64, gap_m: f64) -> (f64, f64, f64) {
    let mut day = renderer(description(40.0, None, 1.0), &options());
    let (day_image, truth) = lead_ahead(&mut day, gap_m);
    let (pixels, _) = board_paint(&day_image, &truth, 0.25);
    assert!(pixels.len() >= 8, "at {gap_m} m: {} pixels", pixels.len());
    let d = description(-18.0, Some(beam), gain);
    let predicted = predicted_irradiance(beam, &truth, &d) * BOARD_ALBEDO * gain * 255.0;
    let mut night = renderer(d, &options());
    let (image, night_truth) = lead_ahead(&mut night, gap_m);
    assert_eq!(truth.target_cam_m, night_truth.target_cam_m);
    let [x, y, z] = truth.target_cam_m;
    (
        mean(&image, &pixels),
        predicted,
        (x * x + y * y + z * z).sqrt(),
    )
}

/// With the sun 18° below the horizon (the sky's light 2.5e-6 of sunset's) and no lamps the
/// frame is black (mean grey under 0.5, the sensor's black 0 with noise off), where the same
/// scene by day has a mean grey above 50; civil dusk (−3°) lies between.
#[test]
fn night_without_headlamps_is_black() {
    assert!(twilight_factor(-18.0) < 3e-6);
    let mean_at = |elevation_deg: f64| {
        let mut r = renderer(description(elevation_deg, None, 1.0), &options());
        frame_mean(&lead_ahead(&mut r, 15.0).0)
    };
    let (day, dusk, night) = (mean_at(40.0), mean_at(-3.0), mean_at(-18.0));
    eprintln!("mean grey: day {day:.2}, dusk (-3 deg) {dusk:.2}, night (-18 deg) {night:.3}");
    assert!(day > 50.0, "day {day}");
    assert!(night < 0.5, "night {night}");
    assert!(dusk > night && dusk < day, "dusk {dusk}");
}

/// The high beam on the board at 20 and 40 m ahead (17.2 and 37.2 m from the camera), at
/// gain 4: each mean grey of the light paint within 6 % of the model's prediction (intensity × cosine / d², the pixels lying a few
/// centimetres off the board's centre and each mean rounded to whole levels), and the
/// ratio of the two within 10 % of the inverse square of the distances (the beam's pattern
/// changes little over the 1° between them). A fall as 1/d (or none) misses by far more.
#[test]
fn the_high_beam_falls_as_the_inverse_square() {
    let gain = 4.0;
    let (near, near_predicted, d_near) = board_at_night(Beam::High, gain, 20.0);
    let (far, far_predicted, d_far) = board_at_night(Beam::High, gain, 40.0);
    let ratio = near / far;
    let inverse_square = (d_far / d_near).powi(2);
    eprintln!(
        "high beam: {near:.2} at {d_near:.2} m (predicted {near_predicted:.2}), {far:.2} at \
         {d_far:.2} m (predicted {far_predicted:.2}); ratio {ratio:.3}, (d2/d1)^2 \
         {inverse_square:.3}"
    );
    assert!(near < 250.0, "the near board clips ({near})");
    for (got, want) in [(near, near_predicted), (far, far_predicted)] {
        assert!((got / want - 1.0).abs() < 0.06, "{got:.2} for {want:.2}");
    }
    assert!(
        (ratio / inverse_square - 1.0).abs() < 0.10,
        "ratio {ratio:.3}, inverse square {inverse_square:.3}"
    );
    assert!((ratio / (d_far / d_near) - 1.0).abs() > 0.3);
}

/// The low beam on the board 15 and 30 m ahead: the board (1.6 m up) stands above the cut-off
/// (the lamps' horizontal, 0.9 m up), in the stray light, and each mean grey is within 6 %
/// of the model's prediction; at 30 m the high beam lights it more than five times as much
/// as the low beam does.
#[test]
fn the_low_beam_is_cut_off_and_the_high_beam_reaches_farther() {
    let gain = 20.0;
    for gap_m in [15.0, 30.0] {
        let (got, want, d) = board_at_night(Beam::Low, gain, gap_m);
        eprintln!("low beam: {got:.2} at {d:.2} m (predicted {want:.2})");
        assert!(got > 2.0 && got < 250.0, "{got}");
        assert!((got / want - 1.0).abs() < 0.06, "{got:.2} for {want:.2}");
    }
    let (low, _, _) = board_at_night(Beam::Low, 4.0, 30.0);
    let (high, _, _) = board_at_night(Beam::High, 4.0, 30.0);
    eprintln!("at 30 m, gain 4: low beam {low:.2}, high beam {high:.2}");
    assert!(high > 5.0 * low.max(0.5), "low {low}, high {high}");
}

/// The headlamps are seeded by nothing: the same frame twice.
#[test]
fn headlamps_are_deterministic() {
    let mut r = renderer(description(-18.0, Some(Beam::Low), 20.0), &options());
    let (a, _) = lead_ahead(&mut r, 15.0);
    let (b, _) = lead_ahead(&mut r, 15.0);
    assert_eq!(a, b);
    assert!(frame_mean(&a) > 0.5);
}
