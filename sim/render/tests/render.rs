//! The camera renderer's guarantees, on wgpu's GL backend over Mesa llvmpipe (no GPU or
//! display needed; `WGPU_BACKEND=vulkan` runs them on lavapipe):
//! - golden images: frames of the built-in scene match reference PNGs in `tests/golden/`
//!   to ±2 grey levels, with at most 0.5 % of pixels beyond (a missing reference is
//!   written fresh; a failure leaves `-actual.png` and `-difference.png` beside it);
//! - the same seed gives bit-identical frames;
//! - a frame rendered only in part has, inside that part, the whole frame's pixels bit for
//!   bit (with blur, anti-aliasing and soft shadows too);
//! - the renderer puts the target's edges (step paint and stripes) where the tracker's camera
//!   model projects them, to within 0.5 px;
//! - a pole's shadow on the target darkens it;
//! - the target is found in the frame where the ground truth says, also with the camera
//!   panned;
//! - the ground truth's occlusion test sees poles standing between the camera and the board;
//! - over bumps, the road is drawn on the physics' height field: its lane paint appears
//!   where the physics surface projects, not where flat ground would;
//! - an interlaced frame's even rows are its own time's and its odd rows its earlier field's.
//!
//! Textures and shadows are `render_light.rs`'s; traffic is `traffic.rs`'s.
//!
//! Run: `cargo test -p sim --release --test render`.

use image::{GrayImage, Luma};
use nalgebra::{Isometry3, Point3};
use sim_render::{
    builtin_description, builtin_poses, builtin_target, Placement, Scene, SceneDescription,
    STRIPE_OVERRUN_M, STRIPE_WIDTH_M,
};
use sim_render::{target_occluded, CameraRig, Field, FrameInput, RenderOptions, Renderer};
use tracker::paint::Paint;

mod common;
use common::{bare, builtin_frame, builtin_frame_panned, options, reference, renderer};

fn camera_from_target(
    renderer: &Renderer,
    chase: &Isometry3<f64>,
    lead: &Isometry3<f64>,
) -> Isometry3<f64> {
    renderer.rig().world_from_camera(chase).inverse() * lead * renderer.scene().lead_from_target()
}

/// Projects a point of the target plane (metres, x right, y up; z out of the board) with the
/// tracker's camera model.
fn project(renderer: &Renderer, cam_from_target: &Isometry3<f64>, p: [f64; 3]) -> [f64; 2] {
    let c = cam_from_target * Point3::new(p[0], p[1], p[2]);
    renderer
        .rig()
        .intrinsics
        .project([c.x, c.y, c.z])
        .expect("in front")
}

fn golden(name: &str, image: &GrayImage) {
    let (dir, Some(reference)) = reference(name, image) else {
        return;
    };
    assert_eq!(
        reference.dimensions(),
        image.dimensions(),
        "{name}: size differs"
    );
    let mut difference = GrayImage::new(image.width(), image.height());
    let mut beyond = 0usize;
    for (x, y, p) in image.enumerate_pixels() {
        let d = (i32::from(p[0]) - i32::from(reference.get_pixel(x, y)[0])).unsigned_abs();
        if d > 2 {
            beyond += 1;
        }
        difference.put_pixel(x, y, Luma([(d * 8).min(255) as u8]));
    }
    let fraction = beyond as f64 / (image.width() * image.height()) as f64;
    if fraction > 0.005 {
        image.save(dir.join(format!("{name}-actual.png"))).unwrap();
        difference
            .save(dir.join(format!("{name}-difference.png")))
            .unwrap();
        panic!("{name}: {:.2} % of pixels differ by more than 2 grey levels (0.5 % allowed); see {name}-actual.png and {name}-difference.png", 100.0 * fraction);
    }
}

#[test]
fn golden_frames_of_the_builtin_scene() {
    let mut renderer = renderer(builtin_description(builtin_target(), 1), &options());
    for (name, t) in [
        ("builtin-t00", 0.0),
        ("builtin-t12", 12.0),
        ("builtin-t30", 30.0),
    ] {
        golden(name, &builtin_frame(&mut renderer, t).image);
    }
}

#[test]
fn same_seed_gives_bit_identical_frames() {
    let mut a = renderer(builtin_description(builtin_target(), 7), &options());
    let mut b = renderer(builtin_description(builtin_target(), 7), &options());
    let first = builtin_frame(&mut a, 5.0);
    let _other = builtin_frame(&mut a, 9.0);
    assert_eq!(
        first,
        builtin_frame(&mut a, 5.0),
        "same renderer, same frame twice"
    );
    assert_eq!(first, builtin_frame(&mut b, 5.0), "a second renderer");
    let mut c = renderer(builtin_description(builtin_target(), 8), &options());
    assert_ne!(
        first.image,
        builtin_frame(&mut c, 5.0).image,
        "another seed differs"
    );
}

/// The device holds only the static chunks near the camera and those a frame draws (see
/// `RenderOptions::resident_m`), uploaded again as the camera moves on; the frames are
/// those of a renderer that holds the whole scene from the first frame. Along the whole
/// built-in route (11 m/s, a frame every 5 s), with the sun's shadows cached and not.
#[test]
fn frames_drawn_from_the_geometry_near_the_camera_are_those_drawn_from_all_of_it() {
    for cached_shadows in [true, false] {
        let d = builtin_description(builtin_target(), 3);
        let with = |resident_m| RenderOptions {
            resident_m,
            cached_shadows,
            ..options()
        };
        let mut near = renderer(d.clone(), &with(0.0));
        let mut all = renderer(d, &with(1e6));
        for k in 0..20 {
            let t = 5.0 * k as f64;
            let frame = builtin_frame(&mut near, t);
            assert!(
                frame == builtin_frame(&mut all, t),
                "t = {t} s, cached shadows {cached_shadows}"
            );
        }
        assert_eq!(all.geometry_loads(), 1, "the whole scene, once");
        assert!(
            near.geometry_loads() >= 10,
            "uploaded again as the camera moves on: {} times",
            near.geometry_loads()
        );
    }
    let bad = RenderOptions {
        resident_m: f64::NAN,
        ..options()
    };
    let scene = std::sync::Arc::new(Scene::build(bare(1)).expect("scene"));
    match Renderer::new(scene, CameraRig::default(), &bad) {
        Err(e) => assert!(e.to_string().contains("resident_m"), "{e}"),
        Ok(_) => panic!("a NaN reach is refused"),
    }
}

#[test]
fn a_part_of_a_frame_is_the_whole_frame_there() {
    let part = tracker::PixelRect {
        x0: 97,
        y0: 61,
        x1: 171,
        y1: 139,
    };
    let blurred = |mut d: SceneDescription| {
        d.sensor.blur_sigma_px = Some(0.8);
        d
    };
    let soft = |mut d: SceneDescription| {
        d.sun.soft_shadows = true;
        d
    };
    let msaa = RenderOptions {
        msaa_samples: 4,
        ..options()
    };
    let cases = [
        ("plain", builtin_description(builtin_target(), 3), options()),
        (
            "blurred",
            blurred(builtin_description(builtin_target(), 3)),
            options(),
        ),
        (
            "soft shadows",
            soft(builtin_description(builtin_target(), 3)),
            options(),
        ),
        ("4x msaa", builtin_description(builtin_target(), 3), msaa),
    ];
    for (name, description, options) in cases {
        let mut r = renderer(description, &options);
        // The last with the camera panned 8° right: the hood's rows move with the head.
        for (time_s, camera_pan_rad) in [(2.0, 0.0), (11.0, 0.0), (2.0, 0.14)] {
            let whole = builtin_frame_panned(&mut r, time_s, camera_pan_rad);
            let (world_from_chase, world_from_lead) = builtin_poses(
                r.scene().description(),
                r.scene().route(),
                &r.rig().mount,
                time_s,
            );
            let input = FrameInput {
                frame_index: (time_s * 15.0).round() as u64,
                time_s,
                world_from_chase,
                world_from_lead,
                world_from_actors: Vec::new(),
                camera_pan_rad,
                auto_gain: 1.0,
                braking: Default::default(),
                earlier_field: None,
                chase_speed_mps: 0.0,
                lead_speed_mps: 0.0,
                actor_speeds_mps: Vec::new(),
            };
            let partial = r.render_part(&input, Some(part)).expect("frame");
            assert_eq!(partial.exact, part, "{name}");
            assert_eq!(partial.truth, whole.truth, "{name}");
            let mut outside_differs = 0;
            for (x, y, p) in whole.image.enumerate_pixels() {
                let q = partial.image.get_pixel(x, y);
                let (x, y) = (x as usize, y as usize);
                if (part.x0..part.x1).contains(&x) && (part.y0..part.y1).contains(&y) {
                    assert_eq!(p, q, "{name} at t = {time_s} s: pixel ({x}, {y})");
                } else if p != q {
                    outside_differs += 1;
                }
            }
            // (Multisampled, the rest is whatever the multisampled target last held.)
            if options.msaa_samples == 1 {
                assert!(outside_differs > 10_000, "{name}: the rest was not drawn");
            }
        }
    }
}

#[test]
fn renderer_matrix_agrees_with_the_tracker_camera() {
    let r = renderer(bare(1), &options());
    let (chase, lead) = builtin_poses(
        r.scene().description(),
        r.scene().route(),
        &r.rig().mount,
        0.0,
    );
    let cam = camera_from_target(&r, &chase, &lead);
    let world_from_target = lead * r.scene().lead_from_target();
    for &[x, y] in r.scene().description().target.corners_m() {
        let tracker = project(&r, &cam, [x, y, 0.0]);
        let w = world_from_target * Point3::new(x, y, 0.0);
        let renderer = r.rig().project_world(&chase, [w.x, w.y, w.z]).unwrap();
        let error =
            ((tracker[0] - renderer[0]).powi(2) + (tracker[1] - renderer[1]).powi(2)).sqrt();
        assert!(
            error < 1e-6,
            "corner ({x}, {y}): tracker {tracker:?}, renderer matrix {renderer:?}"
        );
    }
}

/// Where the renderer actually puts each segment's edge, measured in the image on a line
/// across it through its middle, with 4× MSAA so edges carry sub-pixel information, and
/// compared with the tracker's projection of the segment. Step paint (the default): the
/// gradient-weighted centroid of the one step edge. Stripes: the dark-weighted centroid
/// across the stripe, whose two edges straddle the segment.
#[test]
fn target_edges_land_where_the_tracker_projects_them() {
    for paint in [Paint::Steps, Paint::Stripes] {
        let options = RenderOptions {
            msaa_samples: 4,
            ..options()
        };
        let mut description = bare(1);
        description.sun.elevation_deg = 30.0;
        description.target = description.target.clone().with_paint(paint);
        let mut r = renderer(description, &options);
        // Closer than nominal range so each stripe is ~3 px wide.
        let (chase, lead) = builtin_poses(
            r.scene().description(),
            r.scene().route(),
            &r.rig().mount,
            1.0,
        );
        let lead = lead * Isometry3::translation(-4.0, 0.0, 0.0);
        let frame = r
            .render(&FrameInput::fixed_camera(0, 1.0, chase, lead))
            .unwrap();
        let cam = camera_from_target(&r, &chase, &lead);
        let target = r.scene().description().target.clone();
        let corners = target.corners_m();
        let image = &frame.image;
        let mut worst: f64 = 0.0;
        for &[a, b] in target.segments() {
            let ([ax, ay], [bx, by]) = (corners[a], corners[b]);
            let horizontal = (ay - by).abs() < 1e-9;
            // 30 % along the segment: away from the junctions where another segment meets it.
            let mid = [ax + 0.3 * (bx - ax), ay + 0.3 * (by - ay), 0.003];
            let [u, v] = project(&r, &cam, mid);
            // Sample across the segment (image y for horizontal ones, x for vertical ones).
            let (across, along) = if horizontal { (v, u) } else { (u, v) };
            let line = along.round() as i64;
            let pixel = |k: i64| -> f64 {
                let (x, y) = if horizontal { (line, k) } else { (k, line) };
                f64::from(image.get_pixel(x as u32, y as u32)[0])
            };
            let centre = across.round() as i64;
            let window: Vec<i64> = (centre - 4..=centre + 4).collect();
            let (mut sum, mut weight) = (0.0, 0.0);
            match paint {
                Paint::Steps => {
                    // Pixel centres are at integers: the step between k and k + 1 is at k + ½.
                    for pair in window.windows(2) {
                        let w = (pixel(pair[1]) - pixel(pair[0])).abs();
                        sum += w * (pair[0] as f64 + 0.5);
                        weight += w;
                    }
                }
                Paint::Stripes => {
                    let light = window.iter().map(|&k| pixel(k)).fold(0.0, f64::max);
                    for &k in &window {
                        let w = light - pixel(k);
                        sum += w * k as f64;
                        weight += w;
                    }
                }
            }
            let measured = sum / weight;
            let error = (measured - across).abs();
            worst = worst.max(error);
            assert!(
                error <= 0.5,
                "{paint:?}, segment {a}-{b}: measured at {measured:.2} px, tracker projects {across:.2} px"
            );
        }
        eprintln!(
            "{paint:?}: worst disagreement {worst:.3} px (stripes {STRIPE_WIDTH_M} m, overrun {STRIPE_OVERRUN_M} m)"
        );
    }
}

#[test]
fn a_pole_shadow_darkens_the_target() {
    // Sun behind the camera and to its right, 30° up; a pole placed on the ray from the
    // board point (−1, 0) towards the sun, 3 m in front of the board.
    let mut description = bare(1);
    description.sun.azimuth_deg = 135.0;
    description.sun.elevation_deg = 30.0;
    let probe = |with_pole: bool| {
        let mut d = description.clone();
        let scene = Scene::build(d.clone()).unwrap();
        let rig = CameraRig::default();
        let (chase, lead) = builtin_poses(scene.description(), scene.route(), &rig.mount, 1.0);
        let world_from_target = lead * scene.lead_from_target();
        let shaded = world_from_target * Point3::new(-1.0, 0.0, 0.0);
        let sun = d.sun.direction();
        let t = 3.0 / -sun[0];
        if with_pole {
            d.placements.push(Placement::Pole {
                x_m: shaded.x + t * sun[0],
                z_m: shaded.z + t * sun[2],
            });
        }
        let mut r = renderer(d, &options());
        let frame = r
            .render(&FrameInput::fixed_camera(0, 1.0, chase, lead))
            .unwrap();
        let cam = camera_from_target(&r, &chase, &lead);
        let value = |x: f64, y: f64| {
            let [u, v] = project(&r, &cam, [x, y, 0.0]);
            i32::from(frame.image.get_pixel(u.round() as u32, v.round() as u32)[0])
        };
        // Two points of the board's margin, on its light paint, 2 m apart.
        (value(-1.0, 0.0), value(1.0, 0.0))
    };
    let (shadowed, sunlit) = probe(true);
    assert!(
        shadowed + 20 < sunlit,
        "pole shadow on the board: {shadowed} should be well below its sunlit neighbour {sunlit}"
    );
    let (left, right) = probe(false);
    assert!(
        (left - right).abs() <= 3,
        "without the pole both points are sunlit alike: {left} vs {right}"
    );
}

/// Finds the target by normalised cross-correlation of a template painted by the paint rule
/// (`tracker::paint::layout`)
/// at the true scale, over the whole frame, and checks the best match is at the ground truth.
/// Also with the camera on a pan head turned 7° right, 4° left: the frame follows the head,
/// the board moves about 39 px (22 px) across the image, and the ground truth with it.
#[test]
fn target_is_found_where_the_ground_truth_says() {
    let mut r = renderer(builtin_description(builtin_target(), 3), &options());
    let straight = builtin_frame(&mut r, 0.0).truth.c_x;
    for (t, pan_deg) in [(0.0, 0.0), (20.0, 0.0), (0.0, 7.0), (0.0, -4.0)] {
        let pan = f64::to_radians(pan_deg);
        let frame = builtin_frame_panned(&mut r, t, pan);
        if t == 0.0 {
            // Turning the camera right moves the board left by about f·tan(pan).
            let shift = straight - frame.truth.c_x;
            let want = r.rig().intrinsics.focal_px()[0] * pan.tan();
            assert!(
                (shift - want).abs() < 2.0,
                "pan {pan_deg}°: shift {shift:.1} px, want {want:.1}"
            );
        }
        let truth = frame.truth;
        assert!(truth.in_view, "t = {t}: target not in view: {truth:?}");
        let target = r.scene().description().target.clone();
        let px_per_m = r.rig().intrinsics.focal_px()[0] / truth.target_cam_m[2];
        let paint = tracker::paint::layout(&target).unwrap();
        let half = [0.9 * px_per_m, 0.6 * px_per_m];
        let mut template = Vec::new();
        for dv in -(half[1] as i64)..=half[1] as i64 {
            for du in -(half[0] as i64)..=half[0] as i64 {
                let (x, y) = (du as f64 / px_per_m, -dv as f64 / px_per_m);
                // The tone of the last painted rectangle holding the point.
                let tone = paint
                    .iter()
                    .rev()
                    .find(|r| {
                        let [x0, y0, x1, y1] = r.bounds_m;
                        (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
                    })
                    .map_or(1.0, |r| r.tone);
                template.push((du, dv, tone));
            }
        }
        let tm = template.iter().map(|t| t.2).sum::<f64>() / template.len() as f64;
        let (w, h) = (frame.image.width() as i64, frame.image.height() as i64);
        let mut best = (f64::MIN, 0, 0);
        for cy in half[1] as i64 + 1..h - half[1] as i64 - 1 {
            for cx in half[0] as i64 + 1..w - half[0] as i64 - 1 {
                let values: Vec<f64> = template
                    .iter()
                    .map(|&(du, dv, _)| {
                        f64::from(frame.image.get_pixel((cx + du) as u32, (cy + dv) as u32)[0])
                    })
                    .collect();
                let im = values.iter().sum::<f64>() / values.len() as f64;
                let (mut num, mut ii, mut tt) = (0.0, 0.0, 0.0);
                for (value, t) in values.iter().zip(&template) {
                    num += (value - im) * (t.2 - tm);
                    ii += (value - im).powi(2);
                    tt += (t.2 - tm).powi(2);
                }
                let ncc = num / (ii * tt).sqrt().max(1e-9);
                if ncc > best.0 {
                    best = (ncc, cx, cy);
                }
            }
        }
        let (ncc, cx, cy) = best;
        assert!(
            ncc > 0.5,
            "t = {t}, pan {pan_deg}°: best match only {ncc:.2}"
        );
        assert!(
            (cx as f64 - truth.c_x).abs() <= 1.0 && (cy as f64 - truth.c_y).abs() <= 1.0,
            "t = {t}, pan {pan_deg}°: found the target at ({cx}, {cy}) (ncc {ncc:.2}), ground truth says ({:.2}, {:.2})",
            truth.c_x,
            truth.c_y
        );
    }
}

/// The sensor's noise has the configured standard deviation and no bias, and neighbouring
/// pixels are uncorrelated (the per-pixel hash must not leave structure behind).
#[test]
fn sensor_noise_has_the_configured_sigma() {
    let sensor = builtin_description(builtin_target(), 1).sensor;
    let mut image = GrayImage::from_pixel(256, 242, Luma([128]));
    sim_render::apply_sensor(&mut image, &sensor, &tracker::Camera::default(), 1, 17);
    let values: Vec<f64> = image.iter().map(|&p| f64::from(p) - 128.0).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let sigma = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    let lag1 = values
        .windows(2)
        .map(|w| (w[0] - mean) * (w[1] - mean))
        .sum::<f64>()
        / (n - 1.0)
        / sigma.powi(2);
    let want = sensor.noise_sigma_grey;
    assert!(mean.abs() < 0.05, "noise mean {mean:.3}");
    // Rounding to whole grey levels adds 1/12 to the variance.
    let rounded = (want * want + 1.0 / 12.0).sqrt();
    assert!(
        (sigma - rounded).abs() < 0.05 * rounded,
        "noise sigma {sigma:.3}, want {rounded:.3}"
    );
    assert!(
        lag1.abs() < 0.02,
        "neighbouring pixels correlate: {lag1:.3}"
    );
}

/// A controlled distractor moves with the lead beside its feature: a dark pole 6 px (at the
/// nominal range) outside the outer left feature darkens the board's margin there, and
/// nowhere else on the row.
#[test]
fn a_distractor_pole_stands_where_it_is_put() {
    let offset_m = 6.0 * 10.0 / 320.0;
    let probe = |with_pole: bool| {
        let mut d = bare(1);
        if with_pole {
            d.lead.distractors.push(sim_render::Distractor {
                kind: sim_render::DistractorKind::Pole,
                feature: 3,
                offset_m,
                width_m: 0.08,
                albedo: 0.05,
            });
        }
        let mut r = renderer(d, &options());
        let (chase, lead) = builtin_poses(
            r.scene().description(),
            r.scene().route(),
            &r.rig().mount,
            1.0,
        );
        let frame = r
            .render(&FrameInput::fixed_camera(0, 1.0, chase, lead))
            .unwrap();
        let cam = camera_from_target(&r, &chase, &lead);
        let value = |x: f64, y: f64| {
            let [u, v] = project(&r, &cam, [x, y, 0.02]);
            i32::from(frame.image.get_pixel(u.round() as u32, v.round() as u32)[0])
        };
        // The pole's middle, and the margin on the right at the same offset.
        let x = -0.8 - offset_m - 0.04;
        (value(x, 0.0), value(-x, 0.0))
    };
    let (pole, other_side) = probe(true);
    let (bare_left, _) = probe(false);
    assert!(pole + 40 < bare_left, "pole {pole}, bare board {bare_left}");
    assert!(
        (other_side - bare_left).abs() <= 3,
        "{other_side} vs {bare_left}"
    );
}

/// With `soft_shadows`, shadow edges on the target are as soft as the sun's disc makes them:
/// a pole's shadow on
/// the board has a penumbra as wide as 0.53° seen across the pole's distance (2.8 cm from
/// 3 m, under a pixel at this range; 13 cm from 12 m, four pixels), where the main shadow
/// map alone would blur every edge over its 11 cm texels.
#[test]
fn shadow_edges_on_the_board_widen_with_the_occluder_distance() {
    let mut description = bare(1);
    description.sun.soft_shadows = true;
    description.sun.azimuth_deg = 135.0;
    description.sun.elevation_deg = 30.0;
    // Pixels along the inner rectangle's middle row that are neither lit nor shadowed.
    let soft_pixels = |distance_m: f64| {
        let mut d = description.clone();
        let scene = Scene::build(d.clone()).unwrap();
        let rig = CameraRig::default();
        let (chase, lead) = builtin_poses(scene.description(), scene.route(), &rig.mount, 1.0);
        let world_from_target = lead * scene.lead_from_target();
        let shaded = world_from_target * Point3::new(0.0, 0.0, 0.0);
        let sun = d.sun.direction();
        let t = distance_m / (sun[0] * sun[0] + sun[2] * sun[2]).sqrt();
        d.placements.push(Placement::Pole {
            x_m: shaded.x + t * sun[0],
            z_m: shaded.z + t * sun[2],
        });
        let mut r = renderer(d, &options());
        let frame = r
            .render(&FrameInput::fixed_camera(0, 1.0, chase, lead))
            .unwrap();
        let cam = camera_from_target(&r, &chase, &lead);
        let [u0, v] = project(&r, &cam, [-0.38, 0.0, 0.0]);
        let [u1, _] = project(&r, &cam, [0.38, 0.0, 0.0]);
        let row: Vec<f64> = (u0.ceil() as u32..=u1.floor() as u32)
            .map(|u| f64::from(frame.image.get_pixel(u, v.round() as u32)[0]))
            .collect();
        let (lo, hi) = row
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo > 40.0, "no shadow on the board: {row:?}");
        row.iter()
            .filter(|&&x| x > lo + 0.2 * (hi - lo) && x < hi - 0.2 * (hi - lo))
            .count()
    };
    let near = soft_pixels(3.0);
    // 12 m away along the ground (the ray from the board's centre passes the 9 m pole's
    // top at 15 m).
    let far = soft_pixels(12.0);
    eprintln!("soft pixels across the shadow's two edges: occluder 3 m: {near}, 12 m: {far}");
    assert!(near <= 4, "a pole 3 m away casts {near} soft pixels");
    assert!(far >= near + 3, "12 m away: {far} soft pixels, 3 m: {near}");
}

/// Poles placed halfway along the rays from the camera to the board's left, middle and right
/// columns hide it (all nine rays blocked); one pole in the middle column hides three rays
/// of nine, which is not occlusion; none hides nothing.
#[test]
fn poles_between_the_camera_and_the_board_occlude_it() {
    let rig = CameraRig::default();
    let occluded = |columns: &[f64]| {
        let mut d = bare(1);
        let scene = Scene::build(d.clone()).unwrap();
        let (chase, lead) = builtin_poses(scene.description(), scene.route(), &rig.mount, 1.0);
        let eye = rig.world_from_camera(&chase).translation.vector;
        let world_from_target = lead * scene.lead_from_target();
        for &x in columns {
            let p = world_from_target * Point3::new(x, 0.0, 0.0);
            d.placements.push(Placement::Pole {
                x_m: 0.5 * (eye.x + p.x),
                z_m: 0.5 * (eye.z + p.z),
            });
        }
        let scene = Scene::build(d).unwrap();
        let camera = rig.world_from_camera(&chase);
        target_occluded(&scene, &chase, &lead, &[], &camera, 1.0)
    };
    let corners = builtin_target().corners_m().to_vec();
    let (lo, hi) = corners
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), c| (l.min(c[0]), h.max(c[0])));
    let inset = 0.05 * (hi - lo);
    let columns = [lo + inset, 0.5 * (lo + hi), hi - inset];
    assert!(!occluded(&[]));
    assert!(!occluded(&columns[1..2]));
    assert!(occluded(&columns));
}

#[test]
fn the_road_is_drawn_on_the_physics_height_field() {
    let mut d = bare(3);
    d.ground.bumps = Some(vehicle::BumpsConfig {
        amplitude_m: 0.8,
        wavelength_m: 25.0,
        half_extent_m: 400.0,
        cell_m: 0.5,
        seed: 11,
    });
    let mut r = renderer(d.clone(), &options());
    let physics = vehicle::World::new(&vehicle::WorldConfig {
        ground: d.ground.clone(),
    })
    .unwrap();
    let terrain = r.scene().terrain().expect("bumps").clone();
    let time_s = 4.0;
    let (world_from_chase, world_from_lead) =
        builtin_poses(&d, r.scene().route(), &r.rig().mount, time_s);
    // The lead far ahead, out of the way of the paint looked at.
    let lead_far = nalgebra::Translation3::new(0.0, 0.0, 150.0) * world_from_lead;
    let frame = r
        .render(&FrameInput::fixed_camera(
            60,
            time_s,
            world_from_chase,
            lead_far,
        ))
        .expect("frame");
    let lane = d.route.lane_width_m;
    let chase_s = {
        let p = world_from_chase.translation.vector;
        // The straight runs along the route from its start: its station is the distance.
        let [x0, z0] = r.scene().route().point(0.0, 0.0);
        ((p.x - x0).powi(2) + (p.z - z0).powi(2)).sqrt()
    };
    let (mut on_bumps, mut on_flat, mut checked) = (0, 0, 0);
    for k in 0..40 {
        // The right edge line, 8 to 28 m ahead of the chase.
        let s = chase_s + 8.0 + 0.5 * k as f64;
        let [x, z] = r.scene().route().point(s, lane + 0.1);
        let h = terrain.height_m(x, z);
        // The physics' own surface there (its ground as the wheels feel it).
        let felt = f64::from(physics.ground().height_m(x as f32, z as f32));
        assert!(
            (h - felt).abs() < 0.02,
            "terrain {h} against the bump field {felt}"
        );
        if h < 0.25 {
            continue;
        }
        checked += 1;
        let px = |y: f64| {
            r.rig()
                .project_world(&world_from_chase, [x, y, z])
                .map(|[u, v]| frame.image.get_pixel(u.round() as u32, v.round() as u32)[0])
                .expect("in view")
        };
        let paint = |v: u8| v > 110;
        on_bumps += usize::from(paint(px(h + 0.03)));
        on_flat += usize::from(paint(px(0.03)));
    }
    assert!(checked >= 8, "only {checked} stations over a bump");
    assert!(
        on_bumps * 10 >= checked * 9,
        "paint where the physics surface projects at {on_bumps} of {checked} stations"
    );
    assert!(
        on_flat * 2 <= checked,
        "paint where flat ground would project at {on_flat} of {checked} stations"
    );
}

/// An interlaced frame is two fields: its even rows are the frame of its own time and its
/// odd rows the frame of its earlier field, pixel for pixel (the sensor noise is the
/// frame's own, added once to both), whole or in part.
#[test]
fn an_interlaced_frame_takes_its_odd_rows_from_the_earlier_field() {
    let mut r = renderer(builtin_description(builtin_target(), 3), &options());
    let time_s = 4.0;
    let poses = |r: &Renderer, t: f64| {
        builtin_poses(
            r.scene().description(),
            r.scene().route(),
            &r.rig().mount,
            t,
        )
    };
    let (world_from_chase, world_from_lead) = poses(&r, time_s);
    // One field earlier, with the lead a little further left than the route would put it,
    // so that the two fields differ around the target.
    let earlier_s = time_s - 1.0 / 60.0;
    let (chase0, lead0) = poses(&r, earlier_s);
    let earlier = Field {
        time_s: earlier_s,
        world_from_chase: chase0,
        world_from_lead: lead0 * Isometry3::translation(0.0, 0.0, -0.3),
        world_from_actors: Vec::new(),
        camera_pan_rad: 0.0,
    };
    let input = FrameInput {
        earlier_field: Some(earlier.clone()),
        ..FrameInput::fixed_camera(60, time_s, world_from_chase, world_from_lead)
    };
    let interlaced = r.render(&input).expect("frame");
    let own = r
        .render(&FrameInput::fixed_camera(
            60,
            time_s,
            world_from_chase,
            world_from_lead,
        ))
        .expect("frame");
    let other = r
        .render(&FrameInput {
            camera_pan_rad: earlier.camera_pan_rad,
            ..FrameInput::fixed_camera(
                60,
                earlier.time_s,
                earlier.world_from_chase,
                earlier.world_from_lead,
            )
        })
        .expect("frame");
    let width = interlaced.image.width() as usize;
    let rows = |image: &GrayImage, parity: usize| -> Vec<u8> {
        image
            .as_raw()
            .chunks_exact(width)
            .skip(parity)
            .step_by(2)
            .flatten()
            .copied()
            .collect()
    };
    assert_eq!(rows(&interlaced.image, 0), rows(&own.image, 0));
    assert_eq!(rows(&interlaced.image, 1), rows(&other.image, 1));
    let differing = rows(&own.image, 1)
        .iter()
        .zip(rows(&other.image, 1))
        .filter(|(a, b)| a.abs_diff(*b) > 8)
        .count();
    assert!(differing > 100, "the fields barely differ: {differing} px");
    // The ground truth is the frame's own time's.
    assert_eq!(interlaced.truth, own.truth);

    // In part: the part's pixels are the whole interlaced frame's.
    let t = own.truth;
    let part = tracker::PixelRect {
        x0: t.c_x as usize - 40,
        y0: t.c_y as usize - 30,
        x1: t.c_x as usize + 40,
        y1: t.c_y as usize + 30,
    };
    let partial = r.render_part(&input, Some(part)).expect("frame");
    for y in part.y0..part.y1 {
        for x in part.x0..part.x1 {
            assert_eq!(
                partial.image.get_pixel(x as u32, y as u32),
                interlaced.image.get_pixel(x as u32, y as u32),
                "({x}, {y})"
            );
        }
    }
}
