//! Rain's options (`Rain::spray`, `Rain::lamp_reflections`), measured on the rendered frame:
//! the lead's spray veils its board more at 100 km/h than at 80, not at all at 40 km/h
//! (below the onset, whichever frame came before) nor when off, and is depth-tested (the
//! hood, a metre from the camera, changes far less than the board); the wet road mirrors
//! the lit tail lamps below them and each street light along the line from its foot
//! towards the camera, and a dry road mirrors nothing.
//!
//! Run: `cargo test -p sim-render --release --test spray`.

use image::GrayImage;
use sim_render::{Braking, CameraRig, FrameInput, Rain, Renderer, SceneDescription, StreetLights};

mod common;
use common::{bare_plain_sensor, board_paint, mean, options, renderer, Pixels};

/// A bare straight road seen by a plain sensor in rain of 16 mm/h, with spray `spray`.
fn rainy(spray: bool) -> SceneDescription {
    let mut d = bare_plain_sensor(5);
    d.rain = Some(Rain {
        spray,
        ..Rain::new(16.0)
    });
    d
}

/// The frame with the chase in the right lane at station 40 m and the lead `gap_m` ahead at
/// `lead_speed_mps` (the chase at the same speed), braking or not.
fn frame(r: &mut Renderer, gap_m: f64, lead_speed_mps: f64, braking: bool) -> GrayImage {
    let route = r.scene().route();
    let lane = r.scene().description().route.lane_width_m;
    let input = FrameInput {
        chase_speed_mps: lead_speed_mps,
        lead_speed_mps,
        braking: Braking(u64::from(braking)),
        ..FrameInput::fixed_camera(
            3,
            0.0,
            route.pose_at(40.0, 0.5 * lane),
            route.pose_at(40.0 + gap_m, 0.5 * lane),
        )
    };
    r.render(&input).expect("frame").image
}

/// The board's contrast in `image` over the light and dark `paint` pixels.
fn contrast(image: &GrayImage, paint: &(Pixels, Pixels)) -> f64 {
    mean(image, &paint.0) - mean(image, &paint.1)
}

#[test]
fn spray_veils_the_board_with_speed_and_not_below_its_onset() {
    let opts = options();
    let gap = 20.0;
    let kmh = |v: f64| v / 3.6;
    let mut off = renderer(rainy(false), &opts);
    let mut on = renderer(rainy(true), &opts);
    let (plain, truth) = {
        let route = off.scene().route();
        let lane = off.scene().description().route.lane_width_m;
        let f = off
            .render(&FrameInput::fixed_camera(
                3,
                0.0,
                route.pose_at(40.0, 0.5 * lane),
                route.pose_at(40.0 + gap, 0.5 * lane),
            ))
            .expect("frame");
        (f.image, f.truth)
    };
    let paint = board_paint(&plain, &truth, 0.2);
    assert!(paint.0.len() > 20 && paint.1.len() > 20, "board found");

    // Off, or below the onset: the frame without spray, bit for bit (the streaks too: the
    // spray draws from its own stream).
    let slow = frame(&mut on, gap, kmh(40.0), false);
    assert_eq!(frame(&mut off, gap, kmh(40.0), false), slow);
    let off_100 = frame(&mut off, gap, kmh(100.0), false);
    let c_off = contrast(&off_100, &paint);

    let fast = frame(&mut on, gap, kmh(100.0), false);
    let mid = frame(&mut on, gap, kmh(80.0), false);
    let (c_80, c_100) = (contrast(&mid, &paint), contrast(&fast, &paint));
    // A frame in which no vehicle throws spray is drawn without the spray's march (its own
    // pipelines): one renderer goes back and forth, and each frame is as before.
    assert_eq!(frame(&mut on, gap, kmh(40.0), false), slow);
    assert_eq!(frame(&mut on, gap, kmh(100.0), false), fast);
    eprintln!("board contrast: off {c_off:.1}, 80 km/h {c_80:.1}, 100 km/h {c_100:.1}");
    assert!(
        c_80 < c_off - 1.0,
        "80 km/h veils the board: {c_80} vs {c_off}"
    );
    assert!(
        c_100 < c_80 - 1.0,
        "100 km/h veils it more: {c_100} vs {c_80}"
    );
    assert!(
        c_100 > 0.2 * c_off,
        "the board still shows: {c_100} vs {c_off}"
    );

    // Depth-tested: the hood's bottom rows (a metre or so from the camera) lie in front of
    // the plume's dense part and change far less than the board's paint.
    let rows = plain.height();
    let hood: Vec<(u32, u32)> = (0..plain.width()).map(|x| (x, rows - 2)).collect();
    let change = |pixels: &[(u32, u32)]| {
        (mean(&fast, pixels) - mean(&off_100, pixels)).abs() / mean(&off_100, pixels).max(1.0)
    };
    let board_change = (c_off - c_100) / c_off;
    eprintln!(
        "relative change: hood {:.3}, board {board_change:.3}",
        change(&hood)
    );
    assert!(change(&hood) < 0.25 * board_change);
}

/// A bare straight road at night (the sun 10° below the horizon), seen by a plain sensor at
/// a gain the brake lamps do not clip at, the lead's tail lamps lit, in rain of `rate_mm_h`
/// (`None`: dry) with mirrored lamps `mirror`.
fn night(rate_mm_h: Option<f64>, mirror: bool) -> SceneDescription {
    let mut d = bare_plain_sensor(3);
    d.sensor.gain = 0.5;
    d.sun.elevation_deg = -10.0;
    d.lead.tail_lamps = true;
    d.rain = rate_mm_h.map(|r| Rain {
        lamp_reflections: mirror,
        ..Rain::new(r)
    });
    d
}

#[test]
fn the_wet_road_mirrors_the_lamps_below_them_and_a_dry_one_does_not() {
    let opts = options();
    let gap = 20.0;
    // Dry: a rate of 0 with mirrored lamps asked for is the dry frame, bit for bit.
    let dry = frame(&mut renderer(night(None, false), &opts), gap, 0.0, true);
    let zero = frame(&mut renderer(night(Some(0.0), true), &opts), gap, 0.0, true);
    assert_eq!(dry, zero);

    let plain = frame(
        &mut renderer(night(Some(16.0), false), &opts),
        gap,
        0.0,
        true,
    );
    let mirrored = frame(
        &mut renderer(night(Some(16.0), true), &opts),
        gap,
        0.0,
        true,
    );
    // The lamps: the brightest pixels of the dry frame; their columns and lowest row.
    let top = dry.pixels().map(|p| p[0]).max().unwrap();
    assert!(top > 100, "the lamps glow: {top}");
    let lamps: Vec<(u32, u32)> = dry
        .enumerate_pixels()
        .filter(|(_, _, p)| u16::from(p[0]) + 20 >= u16::from(top))
        .map(|(x, y, _)| (x, y))
        .collect();
    let lowest = lamps.iter().map(|&(_, y)| y).max().unwrap();
    let near_lamp_column = |x: u32| lamps.iter().any(|&(lx, _)| x.abs_diff(lx) <= 3);
    let (mut below, mut elsewhere, mut peak) = (0.0, 0.0, 0u8);
    for (x, y, p) in mirrored.enumerate_pixels() {
        let gain = f64::from(p[0]) - f64::from(plain.get_pixel(x, y)[0]);
        assert!(
            gain >= -1.0,
            "the mirror only adds light: {gain} at ({x}, {y})"
        );
        if gain <= 0.0 {
            continue;
        }
        if y > lowest && near_lamp_column(x) {
            below += gain;
            peak = peak.max(p[0] - plain.get_pixel(x, y)[0]);
        } else {
            elsewhere += gain;
        }
    }
    eprintln!("mirrored light: below the lamps {below:.0}, elsewhere {elsewhere:.0}, peak {peak}");
    assert!(
        peak >= 5,
        "a visible streak below a lamp: {peak} grey levels"
    );
    assert!(
        below > 2.0 * elsewhere,
        "{below} below the lamps, {elsewhere} elsewhere"
    );
}

/// A bare straight road at night, 25 street lights a km, the gain fixed at
/// 20, in rain of 16 mm/h with mirrored lamps `mirror`: the frame from the chase at station
/// 75 m (the lead 180 m ahead, out of the way), the chase's pose and the lamps' sources.
fn street(mirror: bool) -> (GrayImage, nalgebra::Isometry3<f64>, Vec<[f64; 3]>) {
    let mut d = bare_plain_sensor(5);
    d.sensor.gain = 20.0;
    d.sun.elevation_deg = -18.0;
    d.densities.street_lights_per_km = 25.0;
    d.rain = Some(Rain {
        lamp_reflections: mirror,
        ..Rain::new(16.0)
    });
    let mut r = renderer(d, &options());
    let lane = r.scene().description().route.lane_width_m;
    let chase = r.scene().route().pose_at(75.0, 0.5 * lane);
    let lead = r.scene().route().pose_at(255.0, 0.5 * lane);
    let sources = StreetLights::sources(r.scene());
    let image = r
        .render(&FrameInput::fixed_camera(0, 0.0, chase, lead))
        .expect("frame")
        .image;
    (image, chase, sources)
}

/// The columns left of this, pixels, hold no street light's foot.
const LEFT_OF_LAMPS_PX: u32 = 100;

/// Each street light 20–100 m ahead is mirrored in its own column: the road straight below
/// its foot in the image (the line from the foot towards the camera's foot is one column
/// for a camera looking along the road) gains light; the road below the lamps' feet holds
/// most of what the frame gains, and the columns left of [`LEFT_OF_LAMPS_PX`], where no
/// lamp stands (the lamps stand right of the road, their feet at columns 129–155), gain
/// little.
#[test]
fn the_wet_road_mirrors_each_street_light_in_its_column() {
    let (plain, chase, sources) = street(false);
    let (mirrored, _, _) = street(true);
    let (w, h) = plain.dimensions();
    let gain = |x: u32, y: u32| {
        (f64::from(mirrored.get_pixel(x, y)[0]) - f64::from(plain.get_pixel(x, y)[0])).max(0.0)
    };
    let ahead = |p: &[f64; 3]| (chase.inverse() * nalgebra::Point3::new(p[0], p[1], p[2])).x;
    // The feet of the lamps ahead, in the image.
    let mut feet = Vec::new();
    for lamp in sources.iter().filter(|p| ahead(p) > 5.0) {
        let foot = [lamp[0], lamp[1] - StreetLights::HEIGHT_M, lamp[2]];
        if let Some([fx, fy]) = CameraRig::default().project_world(&chase, foot) {
            if (4.0..f64::from(w) - 4.0).contains(&fx) && (0.0..f64::from(h)).contains(&fy) {
                feet.push((ahead(lamp), fx.round() as u32, fy.round() as u32));
            }
        }
    }
    let below = |x: u32, y: u32, &(_, fx, fy): &(f64, u32, u32)| y >= fy && x.abs_diff(fx) <= 4;
    let mut checked = 0;
    for foot in feet.iter().filter(|f| (20.0..100.0).contains(&f.0)) {
        let band: f64 = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| below(x, y, foot))
            .map(|(x, y)| gain(x, y))
            .sum();
        eprintln!(
            "lamp {:.0} m ahead, foot at ({}, {}): {band:.0} grey levels below it",
            foot.0, foot.1, foot.2
        );
        assert!(
            band > 20.0,
            "the lamp {:.0} m ahead is mirrored below it",
            foot.0
        );
        checked += 1;
    }
    let (mut under, mut total, mut left) = (0.0, 0.0, 0.0);
    for (x, y) in (0..h).flat_map(|y| (0..w).map(move |x| (x, y))) {
        let g = gain(x, y);
        total += g;
        if feet.iter().any(|f| below(x, y, f)) {
            under += g;
        }
        if x < LEFT_OF_LAMPS_PX {
            left += g;
        }
    }
    eprintln!("{checked} lamps checked; the frame gains {total:.0}: {under:.0} below the lamps, {left:.0} left of them");
    assert!(checked >= 2, "{checked} lamps 20–100 m ahead in view");
    assert!(under > 0.5 * total, "{under} below the lamps of {total}");
    assert!(
        left < 0.1 * under,
        "{left} left of the lamps against {under} below them"
    );
}
