//! Fog (`SceneDescription::fog`): Koschmieder's law, measured on the rendered frame. The
//! target board (light paint and dark stripes, flat, facing the camera) at known distances
//! keeps exp(−β d) of its contrast, β = 3.912 / V; the sky, at infinite distance, is the
//! fog's own luminance; and fog is seeded by nothing, so a frame in fog is the same frame
//! every time.
//!
//! Run: `cargo test -p sim-render --release --test fog`.

use sim_render::{Fog, Renderer, SceneDescription};

mod common;
use common::{bare_plain_sensor, board_paint, lead_ahead, mean, options, renderer};

/// The fog's visual range in the contrast test, metres (β = 0.078 per metre).
const VISUAL_RANGE_M: f64 = 50.0;

/// The tolerance on the contrast ratio: `|C_fog / C_clear − exp(−β d)|` within
/// `ABS_TOLERANCE + REL_TOLERANCE · exp(−β d)`. The board's pixels lie a few centimetres
/// either side of its centre's distance (0.3 % of the transmittance), and each mean
/// grey is rounded to whole levels (at most 0.5 / C_clear, 0.3 %, on each of the four means).
const ABS_TOLERANCE: f64 = 0.01;
const REL_TOLERANCE: f64 = 0.03;

/// A bare straight road, no noise, no vignetting, no automatic gain (the sensor's gain
/// fixed), in fog of visual range `visual_range_m` (`None`: clear).
fn description(visual_range_m: Option<f64>) -> SceneDescription {
    let mut d = bare_plain_sensor(5);
    d.fog = visual_range_m.map(|visual_range_m| Fog { visual_range_m });
    d
}

/// The board's contrast in fog over its contrast in the clear (`C_fog / C_clear`, light
/// paint's mean grey minus the stripes', on the same pixels), at `gap_m`; and the camera's
/// distance to the board's centre.
fn contrast_ratio(clear: &mut Renderer, fogged: &mut Renderer, gap_m: f64) -> (f64, f64) {
    let (clear_image, truth) = lead_ahead(clear, gap_m);
    let (fog_image, fog_truth) = lead_ahead(fogged, gap_m);
    assert_eq!(truth.target_cam_m, fog_truth.target_cam_m);
    let (light, dark) = board_paint(&clear_image, &truth, 0.35);
    assert!(
        light.len() >= 8 && dark.len() >= 8,
        "at {gap_m} m: {} light and {} dark pixels",
        light.len(),
        dark.len()
    );
    let brightest = clear_image.pixels().map(|p| p[0]).max().unwrap();
    assert!(brightest < 250, "the clear frame clips ({brightest})");
    let c_clear = mean(&clear_image, &light) - mean(&clear_image, &dark);
    let c_fog = mean(&fog_image, &light) - mean(&fog_image, &dark);
    assert!(
        c_clear > 100.0,
        "at {gap_m} m the board's contrast is {c_clear:.1}"
    );
    let [x, y, z] = truth.target_cam_m;
    (c_fog / c_clear, (x * x + y * y + z * z).sqrt())
}

/// The board with the lead 8, 15 and 25 m ahead (5.2, 12.2 and 22.2 m from the camera) in
/// fog of 50 m visual range keeps exp(−β d) of its contrast (0.66, 0.38, 0.18; measured
/// 0.662, 0.384, 0.172) within 0.01 + 3 % of it. With β doubled every distance would miss
/// by far more than the tolerance (0.44 for 0.66 at 5.2 m).
#[test]
fn the_boards_contrast_falls_as_koschmieders_law() {
    let mut clear = renderer(description(None), &options());
    let mut fogged = renderer(description(Some(VISUAL_RANGE_M)), &options());
    let beta = Fog {
        visual_range_m: VISUAL_RANGE_M,
    }
    .extinction_per_m();
    assert!((beta - 3.912 / VISUAL_RANGE_M).abs() < 1e-12);
    for gap_m in [8.0, 15.0, 25.0] {
        let (ratio, distance_m) = contrast_ratio(&mut clear, &mut fogged, gap_m);
        let expected = (-beta * distance_m).exp();
        let tolerance = ABS_TOLERANCE + REL_TOLERANCE * expected;
        eprintln!(
            "board at {distance_m:.2} m: contrast ratio {ratio:.4}, exp(-beta d) {expected:.4}"
        );
        assert!(
            (ratio - expected).abs() <= tolerance,
            "at {distance_m:.2} m: contrast ratio {ratio:.4}, exp(-beta d) = {expected:.4} \
             (tolerance {tolerance:.4})"
        );
        // Twice the extinction would be far outside it: the test can fail.
        let doubled = (-2.0 * beta * distance_m).exp();
        assert!((ratio - doubled).abs() > 3.0 * tolerance);
    }
}

/// The sky, where a ray hits nothing (an infinite distance), is the fog's own luminance
/// (the sun's strength over 4 and the ambient light) times the sensor's brightness; the
/// clear sky is the scene's sky grey. Fog is seeded by nothing: the same frame twice.
#[test]
fn the_sky_in_fog_is_the_fogs_luminance() {
    let d = description(Some(VISUAL_RANGE_M));
    let fog = d.fog.unwrap();
    let expected = fog.luminance(&d.sun) * d.sensor.brightness() * 255.0;
    let sky_clear = d.sun.sky * d.sensor.brightness() * 255.0;
    let mut fogged = renderer(d, &options());
    let (image, _) = lead_ahead(&mut fogged, 15.0);
    // The top row: sky alone, the camera pitched down 3°.
    for x in [0, 128, 255] {
        let v = f64::from(image.get_pixel(x, 0)[0]);
        assert!(
            (v - expected).abs() <= 1.0,
            "sky in fog {v}, the fog's luminance {expected:.1} (clear sky {sky_clear:.1})"
        );
    }
    let (again, _) = lead_ahead(&mut fogged, 15.0);
    assert_eq!(image, again, "fog is deterministic");
    let mut clear = renderer(description(None), &options());
    let (clear_image, _) = lead_ahead(&mut clear, 15.0);
    let v = f64::from(clear_image.get_pixel(128, 0)[0]);
    assert!((v - sky_clear.min(255.0)).abs() <= 1.0, "clear sky {v}");
}

/// Thicker fog hides more: the mean grey of the road 6–20 m ahead moves towards the fog's
/// luminance as the visual range shortens, and a visual range of 2 m leaves it within two
/// grey levels of it.
#[test]
fn thicker_fog_moves_the_road_towards_the_fogs_luminance() {
    let road = |visual_range_m: Option<f64>| {
        let d = description(visual_range_m);
        let fog_grey = Fog {
            visual_range_m: 1.0,
        }
        .luminance(&d.sun)
            * d.sensor.brightness()
            * 255.0;
        let mut r = renderer(d, &options());
        let (image, _) = lead_ahead(&mut r, 200.0);
        let (mut sum, mut n) = (0.0, 0.0);
        for y in 140..210 {
            for x in 110..146 {
                sum += f64::from(image.get_pixel(x, y)[0]);
                n += 1.0;
            }
        }
        ((sum / n - fog_grey).abs(), fog_grey)
    };
    let (clear, _) = road(None);
    let (thin, _) = road(Some(200.0));
    let (thick, _) = road(Some(30.0));
    let (opaque, fog_grey) = road(Some(2.0));
    assert!(
        clear > thin && thin > thick && thick > opaque && opaque < 2.0,
        "distance from the fog's grey {fog_grey:.1}: clear {clear:.1}, 200 m {thin:.1}, \
         30 m {thick:.1}, 2 m {opaque:.1}"
    );
}
