//! What the renderer's test files share: the renderer on this machine's backend, the
//! built-in scene's frames, a bare road, the board's paint in a frame, and the reference
//! images.

#![allow(dead_code)] // each test file uses some of these

use image::GrayImage;
use sim_render::{
    builtin_description, builtin_poses, builtin_target, Backend, CameraRig, Densities, Frame,
    FrameInput, GroundTruth, RenderOptions, Renderer, RouteSegment, Scene, SceneDescription,
};
use std::path::PathBuf;

pub fn options() -> RenderOptions {
    RenderOptions {
        backend: Backend::choose(None).expect("backend"),
        ..RenderOptions::default()
    }
}

pub fn renderer(description: SceneDescription, options: &RenderOptions) -> Renderer {
    let scene = std::sync::Arc::new(Scene::build(description).expect("scene"));
    Renderer::new(scene.clone(), CameraRig::default(), options).unwrap_or_else(|e| panic!("{e}"))
}

pub fn builtin_frame(renderer: &mut Renderer, time_s: f64) -> Frame {
    builtin_frame_panned(renderer, time_s, 0.0)
}

/// The built-in scene at `time_s` with the camera panned by `camera_pan_rad` (right).
pub fn builtin_frame_panned(renderer: &mut Renderer, time_s: f64, camera_pan_rad: f64) -> Frame {
    let (world_from_chase, world_from_lead) = builtin_poses(
        renderer.scene().description(),
        renderer.scene().route(),
        &renderer.rig().mount,
        time_s,
    );
    renderer
        .render(&FrameInput {
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
        })
        .expect("frame")
}

/// A plain straight road with no clutter and no noise: only what a test puts there.
pub fn bare(seed: u64) -> SceneDescription {
    let mut d = builtin_description(builtin_target(), seed);
    d.route.segments = vec![RouteSegment::Straight { length_m: 300.0 }];
    d.route.intersections_m.clear();
    d.densities = Densities {
        trees_per_km: 0.0,
        poles_per_km: 0.0,
        houses_per_km: 0.0,
        buildings_per_km: 0.0,
        parked_vehicles_per_km: 0.0,
        oncoming_vehicles_per_km: 0.0,
        cracks_per_km: 0.0,
        patches_per_km: 0.0,
        potholes_per_km: 0.0,
        ..Densities::default()
    };
    d.sensor.noise_sigma_grey = 0.0;
    d
}

/// [`bare`] seen by a plain sensor: no noise, no vignetting, no blur, no automatic gain
/// (the gain fixed), so a pixel's grey is the light that reached it.
pub fn bare_plain_sensor(seed: u64) -> SceneDescription {
    let mut d = bare(seed);
    d.sensor.noise_sigma_grey = 0.0;
    d.sensor.vignetting = 0.0;
    d.sensor.blur_sigma_px = None;
    d.sensor.auto_gain = None;
    d
}

/// The frame with the chase in the right lane at station 40 m and the lead `gap_m` ahead
/// of it, and the truth.
pub fn lead_ahead(renderer: &mut Renderer, gap_m: f64) -> (GrayImage, GroundTruth) {
    let route = renderer.scene().route();
    let lane = renderer.scene().description().route.lane_width_m;
    let chase_s = 40.0;
    let world_from_chase = route.pose_at(chase_s, 0.5 * lane);
    let world_from_lead = route.pose_at(chase_s + gap_m, 0.5 * lane);
    let frame = renderer
        .render(&FrameInput::fixed_camera(
            0,
            0.0,
            world_from_chase,
            world_from_lead,
        ))
        .expect("frame");
    (frame.image, frame.truth)
}

/// The folder of reference images, and the reference `name` in it; a missing one is written
/// fresh from `image` (`None`).
pub fn reference(name: &str, image: &GrayImage) -> (PathBuf, Option<GrayImage>) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let reference_path = dir.join(format!("{name}.png"));
    let Ok(reference) = image::open(&reference_path) else {
        image.save(&reference_path).expect("write reference");
        eprintln!("wrote a fresh reference {}", reference_path.display());
        return (dir, None);
    };
    (dir, Some(reference.to_luma8()))
}

/// Pixel positions, (x, y).
pub type Pixels = Vec<(u32, u32)>;

/// The board's light and dark pixels in `image` (the board's box from the truth, the
/// shipped target being 1.6 m × 1.0 m): the pixels within `share` of the box's range of
/// its brightest and darkest grey whose four neighbours are of the same kind, so that no
/// pixel mixes paint and stripe.
pub fn board_paint(image: &GrayImage, truth: &GroundTruth, share: f64) -> (Pixels, Pixels) {
    // Pixels per metre on the board: the focal length over its depth.
    let per_m = 320.0 / truth.target_cam_m[2];
    let (x0, x1) = (truth.c_x - 0.75 * per_m, truth.c_x + 0.75 * per_m);
    let (y0, y1) = (truth.c_y - 0.45 * per_m, truth.c_y + 0.45 * per_m);
    let at = |x: u32, y: u32| f64::from(image.get_pixel(x, y)[0]);
    let xs = x0.ceil() as u32..=x1.floor() as u32;
    let ys = y0.ceil() as u32..=y1.floor() as u32;
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for y in ys.clone() {
        for x in xs.clone() {
            lo = lo.min(at(x, y));
            hi = hi.max(at(x, y));
        }
    }
    let kind = |x: u32, y: u32| {
        let v = at(x, y);
        if v >= hi - share * (hi - lo) {
            1
        } else if v <= lo + share * (hi - lo) {
            -1
        } else {
            0
        }
    };
    let (mut light, mut dark) = (Vec::new(), Vec::new());
    for y in ys.clone() {
        for x in xs.clone() {
            let k = kind(x, y);
            let interior = [(0i32, 1i32), (0, -1), (1, 0), (-1, 0)]
                .iter()
                .all(|&(dx, dy)| kind((x as i32 + dx) as u32, (y as i32 + dy) as u32) == k);
            match (k, interior) {
                (1, true) => light.push((x, y)),
                (-1, true) => dark.push((x, y)),
                _ => {}
            }
        }
    }
    (light, dark)
}

/// Mean grey of `image` over `pixels`.
pub fn mean(image: &GrayImage, pixels: &[(u32, u32)]) -> f64 {
    let sum: f64 = pixels
        .iter()
        .map(|&(x, y)| f64::from(image.get_pixel(x, y)[0]))
        .sum();
    sum / pixels.len() as f64
}
