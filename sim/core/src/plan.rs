//! The plan of a run: everything a validated [`Scenario`] decides before the first frame,
//! built once. The drivers' route, the physics world with both vehicles on the ground at
//! their start, the controllers and the delay line, the scene and the camera rig, and the
//! first view of the target (the renderer's ground truth for the start poses, with the
//! teleoperator's placement of section 2.2).
//!
//! `carfollow check`, a sweep's pre-flight and `run` all build the plan, so a scenario that
//! checks, runs: the closed loop starts from the plan and builds none of it again. What
//! goes wrong in planning is the scenario's fault, and is said as a [`ScenarioError`]
//! naming the field to blame.

use crate::delayed::Delayed;
use crate::scenario::{Scenario, ScenarioError};
use crate::traffic::{Member, Road, Role, Vehicles};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use sim_render::{
    ground_truth_of, Backend, CameraRig, ChaseVehicle, GroundTruth, LeadVehicle, RenderOptions,
    Route as SceneRoute, Scene, SceneDescription, SceneError,
};
use std::sync::Arc;
use tracker::Location;
use vehicle::{
    ActorDriver, ChaseController, DelayLine, Events, Lanes, LeadDriver, LeadDriverConfig, PanHead,
    Pose, Route, Vector, VehicleId, VehicleParams, World, WorldConfig,
};

/// Spacing of the points that turn the route's lane centre into the drivers' polyline,
/// metres: fine enough that a 35 m radius bend is within 4 mm of its arc.
pub(crate) const ROUTE_SAMPLE_M: f64 = 1.0;
/// How far the physics ground reaches beyond the route's farthest point, metres: room for
/// a vehicle that overruns the route's end while braking.
const GROUND_BEYOND_ROUTE_M: f32 = 200.0;
/// Height of the lead's box body, metres (a small box truck: the board needs its back door).
const LEAD_BODY_HEIGHT_M: f64 = 2.7;
/// Height of the board's centre above the ground, metres.
const BOARD_CENTRE_HEIGHT_M: f64 = 1.6;

/// The lead's body as the scene draws it, and where its scene origin (the body's centre)
/// lies in its physics frame (the rear axle).
fn lead_body() -> (LeadVehicle, Isometry3<f64>) {
    let lead_params = VehicleParams::pickup();
    let body = LeadVehicle {
        length_m: f64::from(lead_params.length_m),
        width_m: f64::from(lead_params.width_m),
        height_m: LEAD_BODY_HEIGHT_M,
        board_centre_height_m: BOARD_CENTRE_HEIGHT_M,
        distractors: Vec::new(),
        tail_lamps: false,
    };
    let lead_from_scene = Isometry3::translation(
        0.5 * f64::from(lead_params.length_m) - f64::from(lead_params.rear_overhang_m),
        0.0,
        0.0,
    );
    (body, lead_from_scene)
}

/// The lead's body as the scene draws it, metres: length, height, width.
pub fn lead_body_size_m() -> [f64; 3] {
    let (body, _) = lead_body();
    [body.length_m, body.height_m, body.width_m]
}

/// The camera rig of a scenario: its intrinsics on its mount, 256 × 242 pixels.
fn camera_rig(s: &Scenario) -> CameraRig {
    let mount = s.chase.camera_mount;
    CameraRig {
        intrinsics: s.camera,
        width: 256,
        height: 242,
        mount: sim_render::CameraMount {
            height_m: f64::from(mount.height_m),
            forward_offset_m: f64::from(mount.forward_m),
            pitch_deg: f64::from(mount.pitch_down_deg),
        },
    }
}

/// What decides whether scenario `s` plans ([`Plan::new`] succeeds): a hash of its resolved
/// form without `[expect]`, and of `[tracker]` only its target. Scenarios with the same key
/// plan alike, so a sweep's pre-flight plans one point of each (a sweep over the tracker's
/// settings plans one point per scenario and seed).
pub fn planning_key(s: &Scenario) -> u64 {
    let mut v = s.resolved_json();
    if let Some(table) = v.as_object_mut() {
        table.remove("expect");
        let target = table.get("tracker").and_then(|t| t.get("target")).cloned();
        table.insert("tracker".into(), serde_json::json!({ "target": target }));
    }
    vehicle::fnv1a64(v.to_string().as_bytes())
}

/// The scene description of a scenario.
fn scene_description(s: &Scenario, world: &WorldConfig) -> SceneDescription {
    let chase_params = VehicleParams::hmmwv_m998();
    let mount = s.chase.camera_mount;
    // The scene: its vehicle origins are the body centres; physics' are the rear axles.
    let (lead_body, _) = lead_body();
    // The chase's scene origin is its rear axle, so the camera mount is the same number
    // in both; the hood runs from the windscreen to the front bumper.
    let front = f64::from(chase_params.front_bumper_x_m());
    let hood = ChaseVehicle {
        hood_front_m: front - 0.1,
        hood_back_m: f64::from(mount.forward_m) - 0.2,
        hood_height_m: 1.3,
        hood_width_m: f64::from(chase_params.width_m) - 0.2,
    };
    SceneDescription {
        seed: s.seed,
        route: s.route.clone(),
        densities: s.densities.clone(),
        placements: s.placements.clone(),
        sun: s.sun.clone(),
        sensor: s.sensor.clone(),
        target: s.target.clone(),
        lead: LeadVehicle {
            distractors: s.distractors.clone(),
            tail_lamps: s.lead_tail_lamps,
            ..lead_body
        },
        chase: hood,
        ground: world.ground.clone(),
        road_surface: s.road_surface,
        textures: s.textures,
        actors: s
            .actors
            .iter()
            .map(|a| sim_render::ActorBody {
                kind: a.kind,
                albedo: a.albedo,
                tail_lamps: a.tail_lamps,
            })
            .collect(),
        fog: s.fog,
        rain: s.rain,
        without_lead: !s.has_lead,
        headlamps: s.headlamps,
    }
}

/// The render options the loop uses with `backend` (a render worker uses the same).
pub fn render_options(backend: Backend) -> RenderOptions {
    RenderOptions {
        backend,
        ..RenderOptions::default()
    }
}

/// rapier's pose (f32, glam) as a nalgebra isometry (f64).
pub(crate) fn iso(p: &Pose) -> Isometry3<f64> {
    let t = p.translation;
    let q = p.rotation;
    Isometry3::from_parts(
        Translation3::new(f64::from(t.x), f64::from(t.y), f64::from(t.z)),
        UnitQuaternion::from_quaternion(Quaternion::new(
            f64::from(q.w),
            f64::from(q.x),
            f64::from(q.y),
            f64::from(q.z),
        )),
    )
}

/// The lane centre of the right lane as the drivers' polyline, one point every
/// [`ROUTE_SAMPLE_M`], and how far it reaches from the origin along x or z, metres.
fn lane_polyline(route: &SceneRoute, lateral_m: f64) -> (Vec<Vector>, f32) {
    let n = (route.length_m() / ROUTE_SAMPLE_M).ceil() as usize;
    let points: Vec<Vector> = (0..=n)
        .map(|k| {
            let [x, z] = route.point((k as f64 * ROUTE_SAMPLE_M).min(route.length_m()), lateral_m);
            Vector::new(x as f32, 0.0, z as f32)
        })
        .collect();
    let reach = points
        .iter()
        .fold(0.0f32, |m, p| m.max(p.x.abs()).max(p.z.abs()));
    (points, reach)
}

/// Where the chase's rear axle starts, metres along the route: `initial_gap_m` from its
/// camera to the lead's rear bumper, the lead's rear axle at `lead_start_m`.
pub(crate) fn chase_start_m(lead_start_m: f64, initial_gap_m: f64, camera_forward_m: f32) -> f64 {
    let lead_params = VehicleParams::pickup();
    lead_start_m + f64::from(lead_params.rear_bumper_x_m())
        - initial_gap_m
        - f64::from(camera_forward_m)
}

/// The physics world of a scenario: its ground reaches [`GROUND_BEYOND_ROUTE_M`] past
/// every point of the route (`reach_m`, from [`lane_polyline`]), or a vehicle drives off it.
fn world_config(
    base: &vehicle::WorldConfig,
    reach_m: f32,
    route: &SceneRoute,
) -> vehicle::WorldConfig {
    let mut world = base.clone();
    // A road that rises and falls: the ground follows it (none when it is level).
    world.ground.profile = sim_render::ground_profile(route);
    world.ground.half_extent_m = world
        .ground
        .half_extent_m
        .max(reach_m + GROUND_BEYOND_ROUTE_M);
    world
}

/// A scenario's run, planned: built from a validated [`Scenario`] by [`Plan::new`], and
/// consumed by the closed loop.
pub struct Plan {
    pub(crate) scenario: Scenario,
    /// The lane centre of the scene's route, for the lead's driven path before t = 0.
    pub(crate) scene_route: SceneRoute,
    /// Where the chase's rear axle starts, metres along the route.
    pub(crate) chase_start_m: f64,
    /// The physics at step 0, both vehicles on the ground at their start.
    pub(crate) world: World,
    pub(crate) chase_id: VehicleId,
    /// The lead's physics and driver (none in a scenario without a lead).
    pub(crate) lead_id: Option<VehicleId>,
    pub(crate) chase: ChaseController,
    pub(crate) lead: Option<LeadDriver>,
    pub(crate) delay: DelayLine<Delayed>,
    /// The camera's pan head, when the scenario has one (`[camera.pan]`).
    pub(crate) pan: Option<PanHead>,
    pub(crate) scene: Arc<Scene>,
    pub(crate) rig: CameraRig,
    /// Scene origin (body centre) in the lead's vehicle frame (rear axle).
    pub(crate) lead_from_scene: Isometry3<f64>,
    /// The renderer's ground truth of the first frame.
    pub(crate) first_view: GroundTruth,
    /// The teleoperator's placement of the model on the first frame (section 2.2): the
    /// first view with the scenario's `tracker.init_offset`.
    pub(crate) tracker_start: Location,
    /// Wall-clock seconds the plan took to build (for speed reports only).
    pub(crate) built_s: f64,
    /// The other vehicles and the events, when the scenario has traffic.
    pub(crate) traffic: Option<PlannedTraffic>,
}

/// The traffic of a plan: every vehicle in one list, the actors in the physics with their
/// drivers, and the lead's events.
pub(crate) struct PlannedTraffic {
    pub(crate) vehicles: Vehicles,
    /// The actors' physics, in the list's order after the chase and the lead.
    pub(crate) actor_ids: Vec<VehicleId>,
    pub(crate) actors: Vec<ActorDriver>,
    /// The lead's events (none, when only the actors have traffic).
    pub(crate) lead_events: Events,
    /// Where the vehicles are on the road.
    pub(crate) road: Road,
}

impl Plan {
    /// Plans scenario `s`. `Err` names the field to blame: the chase starting before the
    /// route, a ground the physics cannot build, a controller refused, a scene too large
    /// for the renderer's buffers, or the target out of the camera's view at t = 0.
    ///
    /// None of these depends on the tracker's settings but its target, nor on `[expect]`:
    /// scenarios of one [`planning_key`] plan alike. Keep it so, or change the key.
    pub fn new(s: &Scenario) -> Result<Plan, ScenarioError> {
        let started = std::time::Instant::now();
        let src = &s.source;
        let invalid = |field: &str, message: String| src.invalid(field, message);
        let vehicle_error = |prefix: &str, e: &vehicle::VehicleError| {
            let (field, message) = crate::scenario::vehicle_error(prefix, e);
            invalid(&field, message)
        };
        let scene_route = SceneRoute::new(s.route.clone());
        let (points, reach_m) = lane_polyline(&scene_route, s.route.lane_centre_m(1));
        let route = Route::new(points).map_err(|e| invalid("route.segments", format!(": {e}")))?;
        // The lead drives its own lane's centre (the same polyline in lane 1); without a lead,
        // this is the chase's lane.
        let lead_route = if s.lead_lane == 1 {
            route.clone()
        } else {
            let (points, _) = lane_polyline(&scene_route, s.route.lane_centre_m(s.lead_lane));
            Route::new(points).map_err(|e| invalid("route.segments", format!(": {e}")))?
        };
        let chase_start_m = s.chase_start_m;
        if chase_start_m < 0.0 {
            // Three fields decide it; blame an override among them if there is one.
            let field = src.blame(
                &["chase.initial_gap_m", "camera.mount.forward_m"],
                "lead.start_m",
            );
            return Err(invalid(
                field,
                format!(
                    "puts the chase vehicle {:.1} m before the route's start; raise lead.start_m \
                     to at least {:.1}",
                    -chase_start_m,
                    s.lead_start_m - chase_start_m
                ),
            ));
        }
        let world_config = world_config(&s.world, reach_m, &scene_route);
        let (mut world, chase_id, lead_id) =
            start_world(s, &world_config, &lead_route, chase_start_m).map_err(|e| match e {
                vehicle::VehicleError::InvalidParameter { field, .. }
                    if field.starts_with("bumps.") =>
                {
                    vehicle_error("environment", &e)
                }
                other => invalid("route.segments", format!(": the physics ground: {other}")),
            })?;
        let v0 = s.chase_initial_speed_mps as f32;
        let mut chase = ChaseController::new(s.chase.clone(), &VehicleParams::hmmwv_m998(), v0)
            .map_err(|e| vehicle_error("chase.controller", &e))?;
        if s.chase.lane_keeping {
            // The chase keeps the lane it starts in, the lead's.
            chase.set_lane(
                lead_route.clone(),
                (0.5 * s.route.lane_width_of(s.lead_lane)) as f32,
            );
        }
        let traffic = s
            .has_traffic()
            .then(|| plan_traffic(s, &scene_route, &route, &mut world, chase_start_m))
            .transpose()?;
        let lead = s
            .has_lead
            .then(|| lead_driver(s, lead_route))
            .transpose()
            .map_err(|e| vehicle_error("lead.driver", &e))?;
        let delay = DelayLine::new(&s.delay).map_err(|e| vehicle_error("loop", &e))?;
        let pan = s
            .chase
            .pan_head
            .enabled
            .then(|| PanHead::new(s.chase.pan_head.clone(), s.seed))
            .transpose()
            .map_err(|e| vehicle_error("camera.pan", &e))?;
        // Built once, here: only the built geometry says whether it fits the renderer's
        // buffers.
        let scene = Scene::build(scene_description(s, &world_config)).map_err(|e| match e {
            SceneError::TooLarge { .. } => invalid("route.segments", format!(": {e}")),
            SceneError::Invalid { .. } => invalid("environment", format!(": {e}")),
        })?;
        let rig = camera_rig(s);
        let (_, lead_from_scene) = lead_body();
        // The first view: the renderer's ground truth for the poses the vehicles start at.
        let world_from_chase = iso(&world.vehicle_state(chase_id).world_from_vehicle);
        let first_view = lead_id.map_or(GroundTruth::ABSENT, |id| {
            let world_from_lead =
                iso(&world.vehicle_state(id).world_from_vehicle) * lead_from_scene;
            ground_truth_of(
                &rig,
                &scene.lead_from_target(),
                &s.target,
                &world_from_chase,
                &world_from_lead,
                0.0,
            )
        });
        // A tracker that starts by searching needs no target in view at t = 0 (a lead far
        // ahead may be out of it, round a bend); one placed on the target does.
        if !first_view.in_view && !s.search_start {
            return Err(out_of_view(src, &first_view));
        }
        let [dx, dy, ds] = s.init_offset;
        let tracker_start = if s.has_lead {
            Location::new(
                first_view.c_x + dx,
                first_view.c_y + dy,
                first_view.scale + ds,
            )
        } else {
            // No target to place it on: a tracker that searches starts nowhere in
            // particular, here the image's centre at the nominal range.
            let [cx, cy] = s.camera.image_center_px;
            Location::new(cx, cy, 1.0)
        };
        Ok(Plan {
            scenario: s.clone(),
            scene_route,
            chase_start_m,
            world,
            chase_id,
            lead_id,
            chase,
            lead,
            delay,
            pan,
            scene: Arc::new(scene),
            rig,
            lead_from_scene,
            first_view,
            tracker_start,
            built_s: started.elapsed().as_secs_f64(),
            traffic,
        })
    }

    /// Loads and plans a scenario file, with `--set` overrides.
    pub fn load(path: &std::path::Path, overrides: &[String]) -> Result<Plan, ScenarioError> {
        Plan::new(&Scenario::load(path, overrides)?)
    }

    /// Plans the built-in `nist-grounds`, with `--set` overrides.
    pub fn builtin(overrides: &[String]) -> Result<Plan, ScenarioError> {
        Plan::new(&Scenario::builtin(overrides)?)
    }

    /// The scenario planned.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// Where the chase's rear axle starts, metres along the route (from the lead's start,
    /// the initial gap and the camera mount; at least 0).
    pub fn chase_start_m(&self) -> f64 {
        self.chase_start_m
    }

    /// Every vehicle of the run, in order (the chase, the lead, the actors), when the
    /// scenario has traffic.
    pub fn vehicles(&self) -> Option<&Vehicles> {
        self.traffic.as_ref().map(|t| &t.vehicles)
    }

    /// The scene's geometry.
    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    /// The camera rig: the intrinsics on their mount, 256 × 242 pixels.
    pub fn rig(&self) -> &CameraRig {
        &self.rig
    }

    /// The renderer's ground truth of the first frame.
    pub fn first_view(&self) -> &GroundTruth {
        &self.first_view
    }

    /// The teleoperator's placement the tracker starts from (section 2.2): the first
    /// view with the scenario's `tracker.init_offset`.
    pub fn tracker_start(&self) -> Location {
        self.tracker_start
    }

    /// The teleoperator's placement as an estimate (stage 8's position of it, eq. 36), for
    /// a plug-in tracker's start.
    pub fn start_estimate(&self) -> crate::plugin::Estimate {
        let s = &self.scenario;
        let at = self.tracker_start;
        let width_px = tracker::Tracker::new(s.target.clone(), s.camera, s.tracker.clone(), at)
            .map_or(f64::NAN, |t| t.target_width_px());
        let [x, y, z] =
            s.camera
                .position_3d(at.c_x, at.c_y, at.scale * width_px, s.target.size_m()[0]);
        crate::plugin::Estimate {
            range_m: z,
            lateral_m: x,
            vertical_m: Some(y),
            cx: Some(at.c_x),
            cy: Some(at.c_y),
            scale: Some(at.scale),
            status: crate::plugin::EstimateStatus::Tracking,
            vehicle: None,
        }
    }

    /// Where the chase and the lead (when there is one) stand at t = 0: the rear axles, on
    /// the ground (vehicle frame: x forward, y up, z right).
    pub fn start_poses(&self) -> (Pose, Option<Pose>) {
        let pose = |id| self.world.vehicle_state(id).world_from_vehicle;
        (pose(self.chase_id), self.lead_id.map(pose))
    }
}

/// The physics world of scenario `s` at step 0: the ground of `config`, and both vehicles
/// on it, the lead at `lead.start_m` (when the scenario has one), the chase at
/// `chase_start_m`, facing along `route`, each at its initial speed. Returns the world and
/// the chase's and lead's ids.
fn start_world(
    s: &Scenario,
    config: &WorldConfig,
    route: &Route,
    chase_start_m: f64,
) -> Result<(World, VehicleId, Option<VehicleId>), vehicle::VehicleError> {
    let pose_at = |s_m: f64| {
        let s = s_m as f32;
        Pose::from_parts(
            route.point_at(s),
            vehicle::Rotation::from_rotation_y(vehicle::direction_heading(route.tangent_at(s))),
        )
    };
    let mut world = World::new(config)?;
    // The lead first: the physics then holds what it held before runs without a lead.
    let lead_id = if s.has_lead {
        let v0 = s.lead_initial_speed_mps as f32;
        let lead_pose = offset_pose(
            route,
            pose_at(s.lead_start_m),
            s.lead_start_m,
            s.lead_offset_m,
        );
        Some(world.add_vehicle(&VehicleParams::pickup(), lead_pose, v0)?)
    } else {
        None
    };
    let chase_v0 = s.chase_initial_speed_mps as f32;
    let chase_id = world.add_vehicle(
        &VehicleParams::hmmwv_m998(),
        pose_at(chase_start_m),
        chase_v0,
    )?;
    Ok((world, chase_id, lead_id))
}

/// The error of a target placed out of the camera's view at t = 0 (`first_view`), blamed
/// on what decides it (an override among them if there is one).
fn out_of_view(src: &crate::scenario::Source, first_view: &GroundTruth) -> ScenarioError {
    let field = src.blame(
        &[
            "camera.mount",
            "camera.focal_length_mm",
            "camera.pixel_size_mm",
            "camera.image_center_px",
            "chase.initial_gap_m",
            "lead.start_m",
            "route.segments",
            "environment",
        ],
        "camera.mount",
    );
    src.invalid(
        field,
        format!(
            "puts the target out of the camera's view at t = 0 (its centre at ({:.0}, {:.0}) \
             px of 256 × 242, range {:.1} m): check the mount's pitch and height, the focal \
             length, chase.initial_gap_m and the route at the start",
            first_view.c_x, first_view.c_y, first_view.target_cam_m[2]
        ),
    )
}

/// The lead's driver on `route`, its lane, at its offset from the start (with traffic, its
/// events set the offset at every step).
fn lead_driver(s: &Scenario, route: Route) -> Result<LeadDriver, vehicle::VehicleError> {
    let mut lead = LeadDriver::new(
        route,
        s.lead_profile.clone(),
        s.lead_driver.clone(),
        &VehicleParams::pickup(),
    )?;
    lead.set_lateral_offset_m(s.lead_offset_m as f32);
    Ok(lead)
}

/// `pose`, at `s_m` along `route`, moved `offset_m` to the route's left (unmoved at 0).
fn offset_pose(route: &Route, pose: Pose, s_m: f64, offset_m: f64) -> Pose {
    if offset_m == 0.0 {
        return pose;
    }
    let left = route.left_at(s_m as f32) * offset_m as f32;
    Pose::from_parts(pose.translation + left, pose.rotation)
}

/// The traffic of scenario `s`: the actors placed in `world` on their lanes (on the road of
/// `scene_route`; `route` is lane 1's centre, the road's measure of stations) with their
/// drivers, the lead's events, and every vehicle in one list.
fn plan_traffic(
    s: &Scenario,
    scene_route: &SceneRoute,
    route: &Route,
    world: &mut World,
    chase_start_m: f64,
) -> Result<PlannedTraffic, ScenarioError> {
    let src = &s.source;
    let (_, lead_from_scene) = lead_body();
    let mut members = vec![Member {
        name: "chase".into(),
        kind: "hmmwv".into(),
        role: Role::Follower,
        params: VehicleParams::hmmwv_m998(),
        centre_x_m: 0.0,
    }];
    if s.has_lead {
        members.push(Member {
            name: "lead".into(),
            kind: "pickup".into(),
            role: Role::Lead,
            params: VehicleParams::pickup(),
            centre_x_m: lead_from_scene.translation.x,
        });
    }
    for a in &s.actors {
        let params = crate::scenario::kind_params(a.kind);
        members.push(Member {
            name: a.name.clone(),
            kind: a.kind.as_str().into(),
            role: Role::Actor,
            centre_x_m: f64::from(params.body_centre_x_m()),
            params,
        });
    }
    let vehicles = Vehicles::new(members);
    let names: Vec<&str> = vehicles.members().iter().map(|m| m.name.as_str()).collect();
    let widths_m = (!s.route.lane_widths_m.is_empty()).then(|| {
        let mut w = [s.route.lane_width_m; Lanes::MAX];
        for (k, slot) in w.iter_mut().enumerate() {
            *slot = s.route.lane_width_of(k as u32 + 1);
        }
        w
    });
    let lanes = |route_lane: u32| Lanes {
        width_m: s.route.lane_width_m,
        count: s.route.lanes,
        route_lane,
        widths_m,
    };
    // The views' stations are along lane 1's centre, `route`: the road ends at its end.
    let road_end_m = f64::from(route.length_m());
    let lead_events = Events::new(&s.lead_events, &names, lanes(s.lead_lane))
        .map_err(|e| vehicle_field_error(src, "lead.events", &e))?
        .with_road_end_m(road_end_m)
        .with_lateral_offset_m(s.lead_offset_m);
    let mut lane_routes: Vec<(u32, Route)> = Vec::new();
    let mut actor_ids = Vec::new();
    let mut actors = Vec::new();
    let mut stations = vec![chase_start_m];
    if s.has_lead {
        stations.push(s.lead_start_m);
    }
    let actor_members = &vehicles.members()[vehicles.first_actor()..];
    for (i, (a, member)) in s.actors.iter().zip(actor_members).enumerate() {
        let at = format!("actors[{i}]");
        let lane_route = match lane_routes.iter().find(|(l, _)| *l == a.lane) {
            Some((_, r)) => r.clone(),
            None => {
                let (points, _) = lane_polyline(scene_route, s.route.lane_centre_m(a.lane));
                let r = Route::new(points)
                    .map_err(|e| src.invalid("route.segments", format!(": {e}")))?;
                lane_routes.push((a.lane, r.clone()));
                r
            }
        };
        // Its start: the station along the road, on its lane's centre.
        let [x, z] = scene_route.point(a.start_m, s.route.lane_centre_m(a.lane));
        let on_lane = lane_route.project(Vector::new(x as f32, 0.0, z as f32)).s_m;
        let pose = Pose::from_parts(
            lane_route.point_at(on_lane),
            vehicle::Rotation::from_rotation_y(vehicle::direction_heading(
                lane_route.tangent_at(on_lane),
            )),
        );
        let pose = offset_pose(&lane_route, pose, f64::from(on_lane), a.offset_m);
        let id = world
            .add_vehicle(&member.params, pose, a.initial_speed_mps as f32)
            .map_err(|e| vehicle_field_error(src, &at, &e))?;
        let driver = LeadDriver::new(
            lane_route,
            a.profile.clone(),
            LeadDriverConfig::default(),
            &member.params,
        )
        .map_err(|e| vehicle_field_error(src, &at, &e))?;
        let events = Events::new(&a.events, &names, lanes(a.lane))
            .map_err(|e| vehicle_field_error(src, &format!("{at}.events"), &e))?
            .with_road_end_m(road_end_m)
            .with_lateral_offset_m(a.offset_m);
        actor_ids.push(id);
        actors.push(ActorDriver::new(driver, events));
        stations.push(a.start_m);
    }
    let road = Road::new(route.clone(), &s.route, &stations);
    Ok(PlannedTraffic {
        vehicles,
        actor_ids,
        actors,
        lead_events,
        road,
    })
}

/// A vehicle crate's error about the part of the scenario at `prefix`, placed in its file.
fn vehicle_field_error(
    src: &crate::scenario::Source,
    prefix: &str,
    e: &vehicle::VehicleError,
) -> ScenarioError {
    let (field, message) = crate::scenario::vehicle_error(prefix, e);
    src.invalid(&field, message)
}
