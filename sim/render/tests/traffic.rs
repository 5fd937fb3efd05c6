//! Traffic in the camera world: roads of several lanes each way, and actors (vehicles the
//! description places and the caller poses each frame). What it guarantees:
//! - the lane lines of a road of two lanes each way are painted where the lane rule
//!   (`RouteSpec::lane_centre_m`, lines at whole lane widths) puts them, and its edge lines
//!   on what was grass beside a road of one lane;
//! - an actor is drawn where its pose puts it, and casts a shadow;
//! - an actor between the camera and the lead's board hides it (the ground truth's
//!   occlusion test), and a frame whose actor poses are not one per actor is an error;
//! - an actor out of view leaves a frame as it was without it, bit for bit;
//! - each kind's back model (`vehicle_back_model`) lies on strong edges of its drawn back;
//! - the whole-image search finds a truck's back by its model 10-22 m ahead in the lane
//!   through the 8 mm and the 16 mm lens, and a van's through the 16 mm and within 14 m
//!   through the 8 mm.
//!
//! Run: `cargo test --release -p sim-render --test traffic`.

use image::GrayImage;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use sim_render::{
    body_from_back_model, builtin_description, builtin_target, vehicle_back_model, ActorBody,
    CameraRig, FrameInput, RenderError, Renderer, Scene, SceneDescription, VehicleKind,
};

mod common;

/// Where the chase's rear axle stands, metres along the (straight) route.
const CHASE_S_M: f64 = 20.0;

/// A straight road of `lanes` lanes each way without clutter, noise or textures: only what
/// a test puts there.
fn bare(lanes: u32) -> SceneDescription {
    let mut d = common::bare(5);
    d.route.lanes = lanes;
    d.textures.enabled = false;
    d
}

fn renderer(description: SceneDescription) -> Renderer {
    common::renderer(description, &common::options())
}

/// The ground pose at station `s_m`, `lateral_m` right of the centre line, heading along
/// the route (the straight route runs along world +x).
fn on_road(s_m: f64, lateral_m: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(s_m, 0.0, lateral_m),
        UnitQuaternion::identity(),
    )
}

/// The chase in lane 1 at [`CHASE_S_M`], and the lead out of sight behind it.
fn poses(d: &SceneDescription) -> (Isometry3<f64>, Isometry3<f64>) {
    let lane = d.route.lane_centre_m(1);
    (on_road(CHASE_S_M, lane), on_road(-200.0, lane))
}

/// Where world point `p` is in the image of the camera on the chase at `chase`.
fn project(rig: &CameraRig, chase: &Isometry3<f64>, p: [f64; 3]) -> [f64; 2] {
    let c = rig.world_from_camera(chase).inverse() * Point3::new(p[0], p[1], p[2]);
    rig.intrinsics
        .project([c.x, c.y, c.z])
        .expect("in front of the camera")
}

fn grey(image: &GrayImage, [x, y]: [f64; 2]) -> f64 {
    let (x, y) = (x.round() as u32, y.round() as u32);
    f64::from(image.get_pixel(x, y)[0])
}

fn frame(r: &mut Renderer, actors: Vec<Isometry3<f64>>) -> GrayImage {
    let (chase, lead) = poses(r.scene().description());
    r.render(&FrameInput::fixed_camera(3, 0.2, chase, lead).with_actors(actors))
        .expect("frame")
        .image
}

/// The brightest grey within `reach` pixels of `at` along its row, less the darker of
/// the greys 7 pixels to either side: how much a line of paint there stands out.
fn line_contrast(image: &GrayImage, [x, y]: [f64; 2], reach: i32) -> f64 {
    let at = |dx: i32| grey(image, [x + f64::from(dx), y]);
    let peak = (-reach..=reach).map(at).fold(f64::MIN, f64::max);
    peak - at(-7).min(at(7))
}

#[test]
fn lane_lines_are_painted_where_the_lane_rule_puts_them() {
    let one = bare(1);
    let two = bare(2);
    let rig = CameraRig::default();
    let (chase, _) = poses(&two);
    // Dashes run 3 m in every 12 from 250 m before the route's start: 38–41 m is one.
    let s = 39.5;
    let image2 = frame(&mut renderer(two.clone()), Vec::new());
    let image1 = frame(&mut renderer(one), Vec::new());
    let lane = two.route.lane_width_m;
    // The centre line and the lines between lanes, dashed; the edge lines.
    for lateral in [0.0, -lane, lane, -(2.0 * lane + 0.1), 2.0 * lane + 0.1] {
        let at = project(&rig, &chase, [s, 0.03, lateral]);
        if !(8.0..248.0).contains(&at[0]) {
            continue;
        }
        let contrast = line_contrast(&image2, at, 1);
        assert!(
            contrast > 25.0,
            "two lanes: a line {lateral} m right of the centre line at column {:.1}: contrast \
             {contrast}",
            at[0]
        );
        if lateral.abs() > 2.0 * lane {
            // One lane each way: that is grass beyond the verge, no line.
            let contrast = line_contrast(&image1, at, 1);
            assert!(contrast < 10.0, "one lane: {lateral} m: {contrast}");
        }
    }
    // Between the lines, bare asphalt: half a lane either side of lane 1's centre.
    for lateral in [0.5 * lane, 1.5 * lane, -0.5 * lane] {
        let at = project(&rig, &chase, [s, 0.03, lateral]);
        assert!(line_contrast(&image2, at, 1) < 10.0, "{lateral} m: no line");
    }
}

#[test]
fn a_medians_solid_lines_and_lanes_of_their_own_widths_are_painted_where_they_lie() {
    // Two lanes each way of 3.65 and 3.5 m beyond a 2.6 m median (e6mini's inner lanes).
    let mut d = bare(2);
    d.route.median_m = 2.6;
    d.route.lane_widths_m = vec![3.65, 3.5];
    d.route.lane_width_m = 3.65;
    let rig = CameraRig::default();
    let (chase, _) = poses(&d);
    assert!((chase.translation.z - (2.6 + 0.5 * 3.65)).abs() < 1e-12);
    let image = frame(&mut renderer(d.clone()), Vec::new());
    // In a dash (38–41 m), and on a solid line's stretch alike.
    let s = 39.5;
    let mut seen = 0;
    // The median's edge lines (0.1 m inside it), the dashed line between lanes 1 and 2
    // (2.6 + 3.65 m), the edge lines (2.6 + 7.15 + 0.1 m).
    for lateral in [2.5, -2.5, 6.25, -6.25, 9.85, -9.85] {
        let at = project(&rig, &chase, [s, 0.03, lateral]);
        if !(8.0..248.0).contains(&at[0]) {
            continue;
        }
        seen += 1;
        let contrast = line_contrast(&image, at, 1);
        assert!(
            contrast > 25.0,
            "a line {lateral} m right of the centre line at column {:.1}: contrast {contrast}",
            at[0]
        );
    }
    assert!(seen >= 4, "{seen} lines in view");
    // No centre line, and bare asphalt on each lane's centre and where lines of one lane
    // width without a median would run (3.65 m and 7.3 m).
    for lateral in [0.0, 2.6 + 1.825, 2.6 + 3.65 + 1.75, 3.65, -3.65] {
        let at = project(&rig, &chase, [s, 0.03, lateral]);
        if !(8.0..248.0).contains(&at[0]) {
            continue;
        }
        let contrast = line_contrast(&image, at, 1);
        assert!(contrast < 10.0, "{lateral} m: no line, contrast {contrast}");
    }
}

/// The corners of the box from `min` to `max` in the frame `world_from_body`.
fn box_corners(world_from_body: &Isometry3<f64>, min: [f64; 3], max: [f64; 3]) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for x in [min[0], max[0]] {
        for y in [min[1], max[1]] {
            for z in [min[2], max[2]] {
                let p = world_from_body * Point3::new(x, y, z);
                out.push([p.x, p.y, p.z]);
            }
        }
    }
    out
}

/// The bounding rectangle `[x0, y0, x1, y1]` of the pixels where `a` and `b` differ by more
/// than `by`, and how many there are.
fn changed(a: &GrayImage, b: &GrayImage, by: u8) -> ([u32; 4], usize) {
    let mut rect = [u32::MAX, u32::MAX, 0, 0];
    let mut count = 0;
    for (x, y, p) in a.enumerate_pixels() {
        if p[0].abs_diff(b.get_pixel(x, y)[0]) > by {
            rect = [
                rect[0].min(x),
                rect[1].min(y),
                rect[2].max(x),
                rect[3].max(y),
            ];
            count += 1;
        }
    }
    (rect, count)
}

#[test]
fn an_actor_is_drawn_where_its_pose_puts_it_and_casts_a_shadow() {
    let rig = CameraRig::default();
    let mut d = bare(1);
    d.actors = vec![ActorBody {
        kind: VehicleKind::Sedan,
        albedo: 0.6,
        tail_lamps: false,
    }];
    // The sun overhead: the car's shadow lies under it, unseen.
    d.sun.elevation_deg = 90.0;
    let (chase, _) = poses(&d);
    let away = on_road(-500.0, -50.0);
    // Ahead in the oncoming lane, turned a little.
    let pose = Isometry3::from_parts(
        Translation3::new(CHASE_S_M + 16.0, 0.0, -1.75),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.3),
    );
    let mut r = renderer(d.clone());
    let (without, with) = (frame(&mut r, vec![away]), frame(&mut r, vec![pose]));
    let (rect, count) = changed(&without, &with, 3);
    let (length, width, height) = VehicleKind::Sedan.dimensions();
    let corners = box_corners(
        &pose,
        [-0.5 * length, 0.0, -0.5 * width],
        [0.5 * length, height, 0.5 * width],
    );
    let projected: Vec<[f64; 2]> = corners.iter().map(|&p| project(&rig, &chase, p)).collect();
    let lo = |k: usize| projected.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
    let hi = |k: usize| projected.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
    let predicted = [lo(0), lo(1), hi(0), hi(1)];
    eprintln!("changed {rect:?} ({count} px), the car's box projects to {predicted:.1?}");
    assert!(count > 200, "{count} pixels changed");
    for k in 0..4 {
        assert!(
            (f64::from(rect[k]) - predicted[k]).abs() <= 3.0,
            "side {k}: drawn {rect:?}, predicted {predicted:.1?}"
        );
    }

    // A low sun on the right: the shadow falls to the car's left, on the road beside it.
    d.sun.elevation_deg = 25.0;
    d.sun.azimuth_deg = 90.0;
    let pose = on_road(CHASE_S_M + 16.0, d.route.lane_centre_m(1));
    let mut r = renderer(d);
    let (without, with) = (frame(&mut r, vec![away]), frame(&mut r, vec![pose]));
    let mut darker = Vec::new();
    for x in [-1.0, 0.0, 1.0] {
        let p = pose * Point3::new(x, 0.0, -2.0);
        let at = project(&rig, &chase, [p.x, 0.03, p.z]);
        darker.push(grey(&without, at) - grey(&with, at));
    }
    eprintln!("the road 2 m left of the car darkens by {darker:?}");
    assert!(darker.iter().all(|&d| d > 15.0), "{darker:?}");
}

#[test]
fn an_actor_between_the_camera_and_the_board_hides_it() {
    let rig = CameraRig::default();
    let mut d = bare(1);
    d.actors = vec![ActorBody {
        kind: VehicleKind::Truck,
        albedo: 0.7,
        tail_lamps: false,
    }];
    let lane = d.route.lane_centre_m(1);
    let chase = on_road(CHASE_S_M, lane);
    let lead = on_road(CHASE_S_M + 25.0, lane);
    let scene = Scene::build(d).expect("scene");
    let camera = rig.world_from_camera(&chase);
    let between = on_road(CHASE_S_M + 12.0, lane);
    let beside = on_road(CHASE_S_M + 12.0, lane + 4.0);
    let occluded = |actors: &[Isometry3<f64>]| {
        sim_render::target_occluded(&scene, &chase, &lead, actors, &camera, 0.2)
    };
    assert!(occluded(&[between]), "a truck in between hides the board");
    assert!(!occluded(&[beside]), "a truck beside the lane does not");
    assert!(!occluded(&[]), "an actor without a pose is nowhere");

    // A frame must pose every actor, and only those.
    let mut r = renderer(scene.description().clone());
    for actors in [vec![], vec![between, beside]] {
        let input = FrameInput::fixed_camera(0, 0.0, chase, lead).with_actors(actors.clone());
        match r.render(&input) {
            Err(RenderError::Actors { expected, got }) => {
                assert_eq!((expected, got), (1, actors.len()))
            }
            other => panic!("{:?}", other.map(|_| ())),
        }
    }
}

#[test]
fn an_actor_out_of_view_leaves_the_frame_bit_for_bit() {
    let mut d = builtin_description(builtin_target(), 2);
    let without = {
        let mut r = renderer(d.clone());
        let (chase, lead) = sim_render::builtin_poses(
            r.scene().description(),
            r.scene().route(),
            &r.rig().mount,
            3.0,
        );
        let input = FrameInput::fixed_camera(45, 3.0, chase, lead);
        (r.render(&input).expect("frame"), input)
    };
    d.actors = VehicleKind::ALL
        .iter()
        .map(|&kind| ActorBody {
            kind,
            albedo: 0.5,
            tail_lamps: false,
        })
        .collect();
    let mut r = renderer(d);
    let (frame, input) = without;
    let far = vec![on_road(-3000.0, 900.0); VehicleKind::ALL.len()];
    let with = r.render(&input.with_actors(far)).expect("frame");
    assert!(with == frame, "an actor out of view changed the frame");
}

/// The image gradient across a model segment from `a` to `b` (pixels): at each of its
/// pixels, the largest |∇| across it within 2 px; the median of those, grey levels per
/// pixel.
fn gradient_along(image: &GrayImage, a: [f64; 2], b: [f64; 2]) -> f64 {
    let horizontal = (b[1] - a[1]).abs() < (b[0] - a[0]).abs();
    let steps = ((b[0] - a[0]).abs().max((b[1] - a[1]).abs()).round() as usize).max(2);
    let mut samples = Vec::new();
    // The ends are corners, where the edge turns: their middle 80 %.
    for k in steps / 10..=steps - steps / 10 {
        let t = k as f64 / steps as f64;
        let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        let mut best: f64 = 0.0;
        for d in -2..=2 {
            let d = f64::from(d);
            let (before, after) = if horizontal {
                ([p[0], p[1] + d - 1.0], [p[0], p[1] + d + 1.0])
            } else {
                ([p[0] + d - 1.0, p[1]], [p[0] + d + 1.0, p[1]])
            };
            best = best.max(0.5 * (grey(image, after) - grey(image, before)).abs());
        }
        samples.push(best);
    }
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

#[test]
fn each_kinds_back_model_lies_on_the_edges_of_its_drawn_back() {
    let rig = CameraRig::default();
    for kind in VehicleKind::ALL {
        let mut d = bare(1);
        d.actors = vec![ActorBody {
            kind,
            albedo: 0.5,
            tail_lamps: false,
        }];
        let (chase, _) = poses(&d);
        let model = vehicle_back_model(kind);
        let body_from_model = body_from_back_model(kind);
        // The back 12 m ahead of the camera, in lane 1.
        let camera_x = rig.world_from_camera(&chase).translation.x;
        let back_x = body_from_model.translation.x;
        let pose = on_road(camera_x + 12.0 - back_x, d.route.lane_centre_m(1));
        let mut r = renderer(d);
        let image = frame(&mut r, vec![pose]);
        // The model where it is, and (a control) 0.3 m up and to the right of it: about
        // 8 px at 12 m, beyond the 2 px the gradient is looked for within.
        let strengths = |offset: f64| -> Vec<f64> {
            let world_from_model = pose * body_from_model;
            let corner = |k: usize| {
                let [x, y] = model.corners_m()[k];
                let p = world_from_model * Point3::new(x + offset, y + offset, 0.0);
                project(&rig, &chase, [p.x, p.y, p.z])
            };
            (model.segments().iter())
                .map(|&[a, b]| gradient_along(&image, corner(a), corner(b)))
                .collect()
        };
        // The paper's edge threshold, 8 grey levels a pixel (2.3).
        let strong = |s: &[f64]| s.iter().filter(|&&g| g >= 8.0).count();
        let (on, off) = (strengths(0.0), strengths(0.3));
        let n = on.len();
        eprintln!(
            "{kind:?}: {} of {n} segments on strong edges ({} when 0.3 m off): {on:.0?}",
            strong(&on),
            strong(&off)
        );
        assert!(
            4 * strong(&on) >= 3 * n,
            "{kind:?}: only {} of {n} segments on strong edges: {on:.0?}",
            strong(&on)
        );
        assert!(
            strong(&off) + n / 4 <= strong(&on),
            "{kind:?}: the control finds edges too: {off:.0?}"
        );
    }
}

/// The whole-image search (robust mode's, which the paper's mode takes its start from)
/// finds a vehicle standing in the chase's lane by its back's model, at the range it is:
/// a truck 10-22 m ahead of the camera through the 8 mm and the 16 mm lens (whose search
/// covers the same image sizes, `tracker::robust::acquire_scales`) in seven frames of
/// eight, a van through the 16 mm lens and within 14 m through the 8 mm. The other finds are printed, not
/// asserted: a sedan's and a hatchback's backs are found at some ranges only.
#[test]
fn the_search_finds_a_van_and_a_truck_by_their_backs() {
    use tracker::{GrayView, Status, Tracker, TrackerConfig, TrackerMode};
    let config = TrackerConfig {
        mode: TrackerMode::Robust,
        ..TrackerConfig::default()
    };
    for kind in VehicleKind::ALL {
        // Painted as a scenario paints each kind (`sim_core::kind_albedo`).
        let albedo = match kind {
            VehicleKind::Sedan => 0.55,
            VehicleKind::Hatchback => 0.35,
            VehicleKind::Van => 0.7,
            VehicleKind::Truck => 0.8,
        };
        let mut found = Vec::new();
        for focal_length_mm in [8.0, 16.0] {
            let mut rig = CameraRig::default();
            rig.intrinsics.focal_length_mm = focal_length_mm;
            for range_m in [10.0, 14.0, 18.0, 22.0] {
                let mut d = bare(1);
                d.actors = vec![ActorBody {
                    kind,
                    albedo,
                    tail_lamps: false,
                }];
                let (chase, _) = poses(&d);
                let body_from_model = body_from_back_model(kind);
                let camera_x = rig.world_from_camera(&chase).translation.x;
                let back_x = body_from_model.translation.x;
                let pose = on_road(camera_x + range_m - back_x, d.route.lane_centre_m(1));
                let scene = std::sync::Arc::new(Scene::build(d).expect("scene"));
                let mut r = Renderer::new(scene, rig.clone(), &common::options()).unwrap();
                let image = frame(&mut r, vec![pose]);
                let view = GrayView::new(
                    image.width() as usize,
                    image.height() as usize,
                    image.as_raw(),
                )
                .unwrap();
                let mut t = Tracker::new_searching(
                    vehicle_back_model(kind),
                    rig.intrinsics,
                    config.clone(),
                )
                .unwrap();
                let out = t.step(view, 0.0);
                let range = out.position_3d[2];
                let held = out.status == Status::Tracking && (range / range_m - 1.0).abs() < 0.05;
                eprintln!(
                    "{kind:?}, {focal_length_mm} mm, {range_m} m: {:?} at {range:.2} m, \
                     coverage {:.2}/{:.2}",
                    out.status, out.coverage[0], out.coverage[1]
                );
                // Asserted: a van through the 16 mm lens, and through the 8 mm lens within
                // 14 m (beyond, its tail lamps are 3 px tall and the fit's coverage falls
                // short); a truck in all but one of the eight frames (one search a frame:
                // the loop searches again on the next).
                let asserted = match kind {
                    VehicleKind::Truck => true,
                    VehicleKind::Van => focal_length_mm == 16.0 || range_m <= 14.0,
                    _ => false,
                };
                found.push((asserted, held, focal_length_mm, range_m));
            }
        }
        let missed: Vec<_> = found.iter().filter(|f| f.0 && !f.1).collect();
        let allowed = usize::from(kind == VehicleKind::Truck);
        assert!(missed.len() <= allowed, "{kind:?} not found: {missed:?}");
    }
}
