//! Rain (`SceneDescription::rain`), measured on the rendered frame: the wet road darker by
//! the stated factor and mirroring the sky by Fresnel's law; streaks that grow in number
//! with the rate, change with the frame and repeat with the seed; no rain (or a rate of 0)
//! the dry frame, bit for bit.
//!
//! Run: `cargo test -p sim-render --release --test rain`.

use image::GrayImage;
use nalgebra::{Point3, Vector3};
use sim_render::{FrameInput, Rain, Renderer, SceneDescription};

mod common;
use common::{bare_plain_sensor, lead_ahead, options, renderer};

/// A bare straight road, no noise, no vignetting, no automatic gain, in rain of `rate_mm_h`
/// (`None`: no table).
fn description(rate_mm_h: Option<f64>) -> SceneDescription {
    let mut d = bare_plain_sensor(5);
    d.rain = rate_mm_h.map(Rain::new);
    d
}

/// The frame `frame_index` with the chase in the right lane at station 40 m and the lead
/// 30 m ahead, the chase at `chase_speed_mps`.
fn frame(r: &mut Renderer, frame_index: u64, chase_speed_mps: f64) -> GrayImage {
    let route = r.scene().route();
    let lane = r.scene().description().route.lane_width_m;
    let input = FrameInput {
        chase_speed_mps,
        ..FrameInput::fixed_camera(
            frame_index,
            0.0,
            route.pose_at(40.0, 0.5 * lane),
            route.pose_at(70.0, 0.5 * lane),
        )
    };
    r.render(&input).expect("frame").image
}

/// Pixels that differ between `a` and `b`.
fn differing(a: &GrayImage, b: &GrayImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
}

#[test]
fn no_rain_and_a_rate_of_zero_draw_the_dry_frame() {
    let opts = options();
    let dry = lead_ahead(&mut renderer(description(None), &opts), 20.0).0;
    let zero = lead_ahead(&mut renderer(description(Some(0.0)), &opts), 20.0).0;
    assert_eq!(dry, zero);
    let wet = lead_ahead(&mut renderer(description(Some(8.0)), &opts), 20.0).0;
    assert!(differing(&dry, &wet) > 10_000, "rain changes the frame");
}

/// The road seen in rain is `air + (k · dry + film · F(θ) · sky − air) · exp(−β d)` per
/// pixel: k the wet albedo's factor, film the water film's share, F water's Fresnel
/// reflectance at the camera's angle of incidence θ, `sky` the sky's grey, `air` the
/// airlight's, d the distance along the pixel's ray to the flat ground. Over the road's
/// pixels straight ahead (between the lead and the hood), the median of
/// `(seen_wet_part) / dry` is the factor 0.6 within 0.02, and the seen grey matches the
/// formula within 1.5 grey levels for 95 % of them (streaks and rounding the rest).
#[test]
fn the_wet_road_is_darker_by_the_factor_and_mirrors_the_sky() {
    let opts = options();
    let rain = Rain::new(16.0);
    let mut dry_r = renderer(description(None), &opts);
    let mut wet_r = renderer(description(Some(rain.rate_mm_h)), &opts);
    let dry = frame(&mut dry_r, 0, 0.0);
    let wet = frame(&mut wet_r, 0, 0.0);

    let d = wet_r.scene().description().clone();
    let brightness = d.sensor.brightness();
    let sun = d.sun.lighting();
    let air = 255.0 * Rain::airlight(&sun) * brightness;
    let sky = 255.0 * (d.sky_light(&sun) * brightness).min(1.0);
    let route = wet_r.scene().route();
    let world_from_chase = route.pose_at(40.0, 0.5 * d.route.lane_width_m);
    let rig = wet_r.rig();
    let world_from_camera = rig.world_from_camera_panned(&world_from_chase, 0.0);
    let eye = world_from_camera * Point3::origin();
    let [fx, fy] = rig.intrinsics.focal_px();
    let [cx, cy] = rig.intrinsics.image_center_px;

    let (mut factors, mut within, mut n) = (Vec::new(), 0, 0);
    // Rows from 25 m ahead to just above the hood, columns within the lane.
    for y in 150..200u32 {
        for x in 110..150u32 {
            let ray = world_from_camera.rotation
                * Vector3::new((f64::from(x) - cx) / fx, (f64::from(y) - cy) / fy, 1.0);
            let t = -eye.y / ray.y;
            let distance = t * ray.norm();
            let cos = ray.y.abs() / ray.norm();
            let film = rain.film_share() * Rain::water_reflectance(cos) * sky;
            let transmit = (-rain.extinction_per_m() * distance).exp();
            let seen = f64::from(wet.get_pixel(x, y)[0]);
            let dry_grey = f64::from(dry.get_pixel(x, y)[0]);
            // Undo the air, then the mirror: what is left is the darkened road.
            let road = (seen - air) / transmit + air - film;
            factors.push(road / dry_grey);
            let predicted = air + (rain.wet_albedo_factor() * dry_grey + film - air) * transmit;
            n += 1;
            if (seen - predicted).abs() <= 1.5 {
                within += 1;
            }
        }
    }
    factors.sort_by(f64::total_cmp);
    let median = factors[factors.len() / 2];
    println!(
        "wet road: median factor {median:.3} (stated {:.3}); {within}/{n} pixels within 1.5 grey of the formula",
        rain.wet_albedo_factor()
    );
    assert!((median - rain.wet_albedo_factor()).abs() < 0.02, "{median}");
    assert!(within * 100 >= n * 95, "{within}/{n}");
}

/// Streaks: two frames of the same poses and different indices differ only by their
/// streaks; more rain, more pixels differ (light, moderate, heavy, violent), and a chase at
/// 25 m/s streaks them longer than one standing.
#[test]
fn streaks_grow_with_the_rate_and_change_from_frame_to_frame() {
    let opts = options();
    let mut counts = Vec::new();
    for rate in [1.0, 4.0, 16.0, 50.0] {
        let mut r = renderer(description(Some(rate)), &opts);
        let (a, b) = (frame(&mut r, 10, 0.0), frame(&mut r, 11, 0.0));
        assert_eq!(
            a,
            frame(&mut r, 10, 0.0),
            "the same frame again, {rate} mm/h"
        );
        counts.push(differing(&a, &b));
    }
    println!("pixels streaked differently between two frames at 1, 4, 16, 50 mm/h: {counts:?}");
    assert!(counts.windows(2).all(|w| w[0] < w[1]), "{counts:?}");
    assert!(counts[0] > 0);
    let mut r = renderer(description(Some(16.0)), &opts);
    let moving = differing(&frame(&mut r, 10, 25.0), &frame(&mut r, 11, 25.0));
    println!("at 16 mm/h, standing: {}, at 25 m/s: {moving}", counts[2]);
    assert!(moving > counts[2], "{moving} vs {}", counts[2]);
}

/// The same seed gives the same rainy frames, renderer after renderer; another seed, other
/// streaks.
#[test]
fn rainy_frames_repeat_with_the_seed() {
    let opts = options();
    let a = frame(&mut renderer(description(Some(8.0)), &opts), 3, 10.0);
    let b = frame(&mut renderer(description(Some(8.0)), &opts), 3, 10.0);
    assert_eq!(a, b);
    let mut other = description(Some(8.0));
    other.seed = 6;
    let c = frame(&mut renderer(other, &opts), 3, 10.0);
    assert!(differing(&a, &c) > 0);
}

/// The expected number of streaks a frame draws: as stated for the paper's camera, and
/// rising with the rate as `Λ⁻⁴` (`R^0.84`).
#[test]
fn the_visible_drops_follow_marshall_palmer() {
    let drops = |rate_mm_h: f64| Rain::new(rate_mm_h).visible_drops([320.0, 320.0], 256.0, 242.0);
    let (light, heavy) = (drops(2.0), drops(16.0));
    println!("visible drops a frame: 2 mm/h {light:.0}, 16 mm/h {heavy:.0}");
    assert!((heavy / light - 8f64.powf(0.84)).abs() < 1e-9);
    assert!((120.0..140.0).contains(&light), "{light}");
    assert!((700.0..780.0).contains(&heavy), "{heavy}");
    assert_eq!(drops(0.0), 0.0);
}

/// A negative, too large or non-finite rate is refused naming the field.
#[test]
fn bad_rates_are_refused() {
    for rate in [-1.0, 201.0, f64::NAN] {
        let err = description(Some(rate)).validate().expect_err("refused");
        assert!(err.to_string().contains("rain.rate_mm_h"), "{err}");
    }
}
