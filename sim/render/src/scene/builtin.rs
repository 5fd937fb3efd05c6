//! The built-in scene `carfollow render` uses until scenario files exist: a rural road with
//! two bends and two intersections, the shipped ten-segment target, and both vehicles placed
//! on the route at a fixed gap (physics will supply the poses later).

use super::description::{
    CameraMount, ChaseVehicle, Densities, LeadVehicle, RoadSurface, SceneDescription, Sensor, Sun,
    Textures,
};
use super::route::{Route, RouteSegment, RouteSpec};
use nalgebra::Isometry3;
use tracker::TargetModel;

/// Built-in scene: the chase vehicle's speed, m/s (about 40 km/h, a speed the paper drove).
pub const BUILTIN_SPEED_M_S: f64 = 11.0;
/// Built-in scene: distance from the camera to the board along the route, metres; the
/// shipped target's nominal range, so the scale is about 1.
pub const BUILTIN_GAP_M: f64 = 10.0;
/// Built-in scene: where the chase vehicle starts, metres along the route.
const BUILTIN_START_M: f64 = 20.0;

/// The built-in scene with the given target and seed.
pub fn builtin_description(target: TargetModel, seed: u64) -> SceneDescription {
    SceneDescription {
        seed,
        route: RouteSpec {
            segments: vec![
                RouteSegment::Straight { length_m: 160.0 },
                RouteSegment::Arc {
                    radius_m: 150.0,
                    angle_deg: 50.0,
                },
                RouteSegment::Straight { length_m: 180.0 },
                RouteSegment::Arc {
                    radius_m: 100.0,
                    angle_deg: -60.0,
                },
                RouteSegment::Straight { length_m: 300.0 },
            ],
            intersections_m: vec![110.0, 480.0],
            lane_width_m: 3.5,
            lanes: 1,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset: Vec::new(),
        },
        densities: Densities::default(),
        placements: Vec::new(),
        sun: Sun::default(),
        sensor: Sensor::default(),
        target,
        lead: LeadVehicle::default(),
        chase: ChaseVehicle::default(),
        ground: vehicle::GroundConfig::default(),
        road_surface: RoadSurface::default(),
        textures: Textures::default(),
        actors: Vec::new(),
        fog: None,
        rain: None,
        without_lead: false,
        headlamps: None,
    }
}

/// `(world_from_chase, world_from_lead)` at time `time_s` in the built-in scene: both in the
/// right lane (lane 1, beside the centre line), the chase at constant speed, the lead so that its board is
/// [`BUILTIN_GAP_M`] ahead of the camera along the route.
pub fn builtin_poses(
    description: &SceneDescription,
    route: &Route,
    mount: &CameraMount,
    time_s: f64,
) -> (Isometry3<f64>, Isometry3<f64>) {
    let lateral = description.route.lane_centre_m(1);
    let chase_s = BUILTIN_START_M + BUILTIN_SPEED_M_S * time_s;
    let lead_s = chase_s + mount.forward_offset_m + BUILTIN_GAP_M + 0.5 * description.lead.length_m;
    (
        route.pose_at(chase_s, lateral),
        route.pose_at(lead_s, lateral),
    )
}

/// The shipped NIST ten-segment target (`scenarios/targets/nist-ten-segment.toml`), built
/// in so the built-in scene needs no files.
pub fn builtin_target() -> TargetModel {
    tracker::synth::nist_ten_segment()
}
