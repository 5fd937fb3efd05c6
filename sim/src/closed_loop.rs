//! The closed loop (DESIGN.md, "One camera frame"): every 1/15 s the camera renders a frame,
//! the tracker processes it, its 3-D estimate enters the delay line, and the controllers
//! drive both vehicles through eight 120 Hz physics steps.
//!
//! Data flows one way. The tracker sees only the image; the chase controller sees only the
//! delayed estimates and its own odometry; only the recorder (the [`FrameRecord`] built here)
//! sees the truth.

use crate::auto_gain::AutoGainControl;
use crate::camera::{
    target_occluded, Backend, CameraRig, Field, Frame, FrameInput, RenderError, RenderOptions,
    Renderer,
};
use crate::driven_path::DrivenPath;
use crate::frame_parts::{camera_turn, track_part, FrameParts};
use crate::record::{FrameRecord, LossCause, TrackerStatus};
use crate::render_thread::RenderThread;
use crate::render_worker::{fingerprint, RemoteRenderer, StartedWorker};
use crate::scenario::Scenario;
use crate::scene::{self, ChaseVehicle, LeadVehicle, Scene, SceneDescription, SceneError};
use image::GrayImage;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use serde::Serialize;
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};
use thiserror::Error;
use tracker::{EdgeDiagnostic, EgoMotion, GrayView, Location, TrackOutput, Tracker, TrackerMode};
use vehicle::{
    direction_heading, ChaseController, DelayLine, Gyro, GyroConfig, LeadDriver, LeadEstimate,
    Odometry, PanHead, Pose, Rotation, Route, Step, TrackStatus, Vector, VehicleId, VehicleParams,
    VehicleState, World, STEPS_PER_FRAME,
};

/// Spacing of the points that turn the route's lane centre into the drivers' polyline,
/// metres: fine enough that a 35 m radius bend is within 4 mm of its arc.
const ROUTE_SAMPLE_M: f64 = 1.0;
/// How far the physics ground reaches beyond the route's farthest point, metres: room for
/// a vehicle that overruns the route's end while braking.
const GROUND_BEYOND_ROUTE_M: f32 = 200.0;
/// Height of the lead's box body, metres (a small box truck: the board needs its back door).
const LEAD_BODY_HEIGHT_M: f64 = 2.7;
/// Height of the board's centre above the ground, metres.
const BOARD_CENTRE_HEIGHT_M: f64 = 1.6;

/// A run that could not start or go on.
#[derive(Debug, Error)]
pub enum LoopError {
    /// The scenario cannot be set up (vehicles, route, tracker).
    #[error("scenario `{scenario}`: {message}")]
    Setup {
        /// Scenario name.
        scenario: String,
        /// What is wrong.
        message: String,
    },
    /// The renderer failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The second renderer (a thread with a llvmpipe of its own, or a worker process)
    /// failed.
    #[error("the second renderer: {0}")]
    Worker(String),
}

/// Everything one frame of the loop produced.
pub struct FrameOutput {
    /// The recorder's row.
    pub record: FrameRecord,
    /// The camera frame.
    pub image: GrayImage,
    /// The tracker's output.
    pub track: TrackOutput,
    /// Edge fates, when diagnostics were asked for.
    pub edges: Vec<EdgeDiagnostic>,
    /// Where the vehicles and the camera were at the frame's capture.
    pub poses: FramePoses,
    /// The gyro's reading of the camera's rotation that the tracker was given with this
    /// frame (robust mode, from the second frame on).
    pub ego: Option<EgoMotion>,
}

/// Where the vehicles and the camera were when a frame was captured (world frame, y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePoses {
    /// The chase's rear axle, on the ground (its vehicle frame: x forward, y up, z right).
    pub world_from_chase: Isometry3<f64>,
    /// The lead's body centre, as the scene draws it.
    pub world_from_lead: Isometry3<f64>,
    /// The camera (x right, y down, z forward).
    pub world_from_camera: Isometry3<f64>,
}

/// Where a run's wall-clock time went, seconds in all: for speed reports only, never part
/// of the results (it differs from run to run).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LoopTiming {
    /// Building the world, the scene and the renderer, and the first frame.
    pub setup_s: f64,
    /// Frames stepped.
    pub frames: u64,
    /// The whole of every [`ClosedLoop::step`].
    pub step_s: f64,
    /// Rendering and reading back the frames (with the sensor model and ground truth).
    pub render_s: f64,
    /// The tracker.
    pub track_s: f64,
    /// The controllers and physics (on a second thread when pipelined, so the parts can add
    /// up to more than `step_s`).
    pub physics_s: f64,
    /// The caller's own work per frame (records, CSV, video), when it measures it.
    pub outputs_s: f64,
    /// Whether physics overlapped rendering and tracking.
    pub pipelined: bool,
    /// Camera frames rendered at once: 2 with a render worker, else 1.
    pub frames_in_flight: usize,
    /// Frames rendered only in part whose tracking read beyond that part, and which were
    /// rendered again (a larger part, or whole) and tracked again (see
    /// [`ClosedLoop::set_whole_frames`]).
    pub rerendered_frames: u64,
}

/// The running loop.
pub struct ClosedLoop {
    name: String,
    frames: u64,
    frame: u64,
    drive: Drive,
    /// Whether the physics to the next frame runs on a second thread while this frame is
    /// rendered and tracked (see [`ClosedLoop::set_pipelined`]).
    pipelined: bool,
    /// This process's renderer: `None` while it renders a frame on `render_thread`.
    renderer: Option<Box<Renderer>>,
    /// The thread this process's frames render on with two in flight, once started.
    render_thread: Option<RenderThread>,
    /// The renderer's scene, for the records while the renderer is away.
    scene: Arc<Scene>,
    /// The renderer's adapter.
    adapter_name: String,
    /// The second renderer, in a worker process, when two frames are in flight.
    remote: Option<RemoteRenderer>,
    /// Frames submitted by earlier steps and not yet tracked, in order (two in flight).
    in_flight: VecDeque<InFlight>,
    /// What the physics to the frame after the first in flight left, when an earlier step
    /// has run it already (two in flight).
    advanced: Option<Driven>,
    /// The scene's fingerprint, which a render worker must match.
    fingerprint: u64,
    timing: LoopTiming,
    /// Which part of each frame to render.
    parts: FrameParts,
    /// The camera's automatic gain control (gain 1 when off).
    auto_gain: AutoGainControl,
    rig: CameraRig,
    tracker: Tracker,
    /// Scene origin (body centre) in the lead's vehicle frame (rear axle).
    lead_from_scene: Isometry3<f64>,
    target_width_px: f64,
    /// The lead's driven path, for the chase's lateral deviation.
    lead_path: DrivenPath,
    chase_distance_m: f64,
    last_chase_xz: [f64; 2],
    diagnostics: bool,
    /// The chase's rate gyro, read between tracked frames for robust mode's ego-motion
    /// aided prediction (`None` in the paper's mode, which has no use for it).
    gyro: Option<Gyro>,
    /// The camera's orientation at the last tracked frame.
    last_camera: Option<UnitQuaternion<f64>>,
    /// The gyro's reading handed to the tracker with the last tracked frame.
    last_ego: Option<EgoMotion>,
    /// The teleoperator's placement the tracker started from.
    start: Location,
}

/// The physics side of the loop: both vehicles, their drivers and the delay line between
/// the tracker and the chase controller.
struct Drive {
    world: World,
    chase_id: VehicleId,
    lead_id: VehicleId,
    chase: ChaseController,
    lead: LeadDriver,
    delay: DelayLine<LeadEstimate>,
    /// The camera's pan head, when the scenario has one (`[camera.pan]`).
    pan: Option<PanHead>,
    /// With an interlaced camera, the world one field period before the next frame
    /// (its earlier field, the lead's pose that of its vehicle frame, not yet the scene's;
    /// `Some` once the first frame's physics has run).
    interlaced: bool,
    earlier_field: Option<Field>,
    /// The steps of the physics to the next frame run so far (see
    /// [`Drive::advance_before`]).
    ahead: Option<FrameSteps>,
}

/// The steps of one frame's physics run so far, and what they did.
#[derive(Clone, Copy, Debug, Default)]
struct FrameSteps {
    steps: u64,
    controls: vehicle::Controls,
    collision: bool,
}

impl Drive {
    /// The controllers and the physics, eight steps to the next frame (the rest of them,
    /// when [`Drive::advance_before`] has run some already). Returns the chase's last
    /// controls and whether the vehicles touched.
    fn advance_frame(&mut self) -> Driven {
        self.advance_steps(None);
        let ahead = self.ahead.take().expect("the frame's steps have run");
        Driven {
            controls: ahead.controls,
            collision: ahead.collision,
            chase_mode: self.chase.mode(),
            desired_gap_m: self.chase.telemetry().desired_gap_m,
        }
    }

    /// Runs the steps of the physics to the next frame that come before step `due` (the
    /// earliest an estimate not yet queued can be due), without completing the frame: what
    /// they do depends on no estimate still to come, so they may run while the frames whose
    /// estimates those are are still being rendered and tracked. [`Drive::advance_frame`]
    /// runs the rest; the outcome is the same, step for step, as running them all then.
    fn advance_before(&mut self, due: Step) {
        self.advance_steps(Some(due));
    }

    /// The frame's steps not yet run, or those before `until`.
    fn advance_steps(&mut self, until: Option<Step>) {
        let mut ahead = self.ahead.take().unwrap_or_default();
        while ahead.steps < u64::from(STEPS_PER_FRAME) {
            let step_now: Step = self.world.now();
            if until.is_some_and(|until| step_now >= until) {
                break;
            }
            if self.interlaced
                && ahead.steps == u64::from(STEPS_PER_FRAME) - scene::FIELD_PERIOD_STEPS
            {
                self.earlier_field = Some(self.field_now());
            }
            for estimate in self.delay.pop_due(step_now) {
                self.chase.receive(estimate);
            }
            let chase = self.world.vehicle_state(self.chase_id);
            let lead = self.world.vehicle_state(self.lead_id);
            ahead.controls = self.chase.update(&Odometry {
                step: step_now,
                world_from_chase: chase.world_from_vehicle,
                forward_speed_mps: chase.forward_speed_mps,
                camera_pan_rad: self.pan_reading_rad() as f32,
            });
            if let Some(pan) = &mut self.pan {
                pan.step(f64::from(self.chase.telemetry().pan_rate_cmd_rad_s));
            }
            let lead_controls = self.lead.update(step_now, &lead);
            self.world.set_controls(self.chase_id, ahead.controls);
            self.world.set_controls(self.lead_id, lead_controls);
            self.world.step();
            ahead.collision |= self.world.vehicles_touch(self.chase_id, self.lead_id);
            ahead.steps += 1;
        }
        self.ahead = Some(ahead);
    }

    /// The earliest step at which the estimate of frame `frame_index` (not yet queued) can
    /// fall due.
    fn earliest_due(&self, frame_index: u64) -> Step {
        Step(frame_index * u64::from(STEPS_PER_FRAME) + self.delay.min_latency_steps())
    }

    /// The world now, as an interlaced frame's earlier field sees it.
    fn field_now(&self) -> Field {
        Field {
            time_s: self.world.now().seconds(),
            world_from_chase: iso(&self.world.vehicle_state(self.chase_id).world_from_vehicle),
            world_from_lead: iso(&self.world.vehicle_state(self.lead_id).world_from_vehicle),
            camera_pan_rad: self.pan_angle_rad(),
        }
    }

    /// The pan head's true angle, radians (0 without one).
    fn pan_angle_rad(&self) -> f64 {
        self.pan.as_ref().map_or(0.0, PanHead::angle_rad)
    }

    /// The pan head's encoder reading, radians (0 without one).
    fn pan_reading_rad(&self) -> f64 {
        self.pan.as_ref().map_or(0.0, PanHead::reading_rad)
    }

    /// Queues the tracker's output for a frame captured at `captured`, when the pan head's
    /// encoder read `pan_reading_rad`.
    fn push_estimate(&mut self, captured: Step, track: &TrackOutput, pan_reading_rad: f64) {
        let [x, y, z] = track.position_3d;
        let status = match track.status {
            tracker::Status::Tracking => TrackStatus::Tracking,
            tracker::Status::Coasting => TrackStatus::Coasting,
            tracker::Status::Lost => TrackStatus::Lost,
        };
        self.delay.push(
            captured,
            LeadEstimate {
                capture_step: captured,
                target_in_camera_m: Vector::new(x as f32, y as f32, z as f32),
                status,
                camera_pan_rad: pan_reading_rad as f32,
            },
        );
    }
}

/// What the camera needs from a scenario: the scene, the rig, and where the lead's scene
/// origin lies in its physics frame. The closed loop and its render workers build it alike.
pub struct CameraSetup {
    /// The scene's geometry.
    pub scene: Scene,
    /// The camera rig.
    pub rig: CameraRig,
    /// Scene origin (body centre) in the lead's vehicle frame (rear axle).
    pub lead_from_scene: Isometry3<f64>,
}

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
    };
    let lead_from_scene = Isometry3::translation(
        0.5 * f64::from(lead_params.length_m) - f64::from(lead_params.rear_overhang_m),
        0.0,
        0.0,
    );
    (body, lead_from_scene)
}

/// The lead's body as the scene draws it, metres: length, height, width.
pub(crate) fn lead_body_size_m() -> [f64; 3] {
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
        mount: scene::CameraMount {
            height_m: f64::from(mount.height_m),
            forward_offset_m: f64::from(mount.forward_m),
            pitch_deg: f64::from(mount.pitch_down_deg),
        },
    }
}

/// The scene description of a scenario.
fn scene_description(s: &Scenario) -> SceneDescription {
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
            ..lead_body
        },
        chase: hood,
        ground: s.world.ground.clone(),
        road_surface: s.road_surface,
        textures: s.textures,
    }
}

/// Where a vehicle starts: `s_m` along the drivers' route, facing along it, lifted onto
/// the ground (as [`World::add_vehicle`] places it).
fn start_pose(route: &Route, ground: &vehicle::Ground, s_m: f64) -> Pose {
    let s = s_m as f32;
    let mut pose = Pose::from_parts(
        route.point_at(s),
        Rotation::from_rotation_y(direction_heading(route.tangent_at(s))),
    );
    let t = pose.translation;
    pose.translation.y = ground.height_m(t.x, t.z);
    pose
}

/// The checks `ClosedLoop::new` makes of a validated scenario's scene and first view,
/// made without a renderer, for scenario validation: the scene builds (its description is
/// valid, and its geometry fits the renderer's buffers), and the whole target is in the
/// camera's view at t = 0 (the renderer's ground truth, for the poses the vehicles start
/// at). `Err` names the field to blame and says what is wrong.
pub(crate) fn check_start(
    s: &Scenario,
    route: &Route,
    ground: &vehicle::Ground,
) -> Result<(), (&'static str, String)> {
    // Built and dropped: the geometry's size is known only once it is built.
    Scene::build(scene_description(s)).map_err(|e| match e {
        SceneError::TooLarge { .. } => ("route.segments", format!(": {e}")),
        SceneError::Invalid { .. } => ("environment", format!(": {e}")),
    })?;
    let (body, lead_from_scene) = lead_body();
    let world_from_chase = iso(&start_pose(route, ground, s.chase_start_m));
    let world_from_lead = iso(&start_pose(route, ground, s.lead_start_m)) * lead_from_scene;
    let truth = crate::camera::ground_truth_of(
        &camera_rig(s),
        &scene::lead_from_target_of(&body),
        &s.target,
        &world_from_chase,
        &world_from_lead,
        0.0,
    );
    if truth.in_view {
        Ok(())
    } else {
        Err((
            "camera.mount",
            format!(
                "puts the target out of the camera's view at t = 0 (its centre at ({:.0}, {:.0}) \
                 px of 256 × 242, range {:.1} m): check the mount's pitch and height, the focal \
                 length, chase.initial_gap_m and the route at the start",
                truth.c_x, truth.c_y, truth.target_cam_m[2]
            ),
        ))
    }
}

impl CameraSetup {
    /// Builds the scene and rig of scenario `s`.
    pub fn new(s: &Scenario) -> Result<CameraSetup, LoopError> {
        let (_, lead_from_scene) = lead_body();
        let scene = Scene::build(scene_description(s)).map_err(|e| LoopError::Setup {
            scenario: s.name.clone(),
            message: format!("scene: {e}"),
        })?;
        Ok(CameraSetup {
            scene,
            rig: camera_rig(s),
            lead_from_scene,
        })
    }
}

/// The render options the loop uses with `backend` (a render worker uses the same).
pub fn render_options(backend: Backend) -> RenderOptions {
    RenderOptions {
        backend,
        ..RenderOptions::default()
    }
}

/// The world at the start of a frame, and the camera's input for it.
struct Captured {
    now: Step,
    chase: VehicleState,
    lead: VehicleState,
    input: FrameInput,
    /// The pan head's encoder reading at capture, radians (0 without one).
    pan_reading_rad: f64,
    /// The camera in the world (panned by the head's true angle).
    world_from_camera: Isometry3<f64>,
}

impl Captured {
    /// The world of `drive` at the start of a frame, seen from `rig`.
    fn of(
        drive: &Drive,
        rig: &CameraRig,
        lead_from_scene: &Isometry3<f64>,
        auto_gain: &AutoGainControl,
    ) -> Captured {
        let now = drive.world.now();
        debug_assert!(now.is_frame_start());
        let chase = drive.world.vehicle_state(drive.chase_id);
        let lead = drive.world.vehicle_state(drive.lead_id);
        let frame_index = now.0 / u64::from(STEPS_PER_FRAME);
        let input = FrameInput {
            frame_index,
            time_s: now.seconds(),
            world_from_chase: iso(&chase.world_from_vehicle),
            world_from_lead: iso(&lead.world_from_vehicle) * lead_from_scene,
            camera_pan_rad: drive.pan_angle_rad(),
            auto_gain: auto_gain.gain_for(frame_index),
            // Before the first frame the world stood still.
            earlier_field: drive.interlaced.then(|| {
                let f = drive.earlier_field.unwrap_or_else(|| drive.field_now());
                Field {
                    world_from_lead: f.world_from_lead * lead_from_scene,
                    ..f
                }
            }),
        };
        let world_from_camera =
            rig.world_from_camera_panned(&input.world_from_chase, input.camera_pan_rad);
        Captured {
            now,
            chase,
            lead,
            input,
            pan_reading_rad: drive.pan_reading_rad(),
            world_from_camera,
        }
    }
}

/// What the physics from a frame to the next leaves for the frame's record: the last
/// controls, whether the vehicles touched, and the chase controller's mode and desired gap
/// at its end (taken then: with two frames in flight the physics runs on before the
/// record is made).
#[derive(Clone, Copy, Debug)]
struct Driven {
    controls: vehicle::Controls,
    collision: bool,
    chase_mode: vehicle::ChaseMode,
    desired_gap_m: f32,
}

/// A frame submitted but not yet tracked: rendering on this process's render thread
/// (`here`) or in the worker.
struct InFlight {
    captured: Captured,
    here: bool,
}

/// Why this process's renderer must be at hand: only frames in flight take it away.
const HERE: &str = "this process's renderer is here when no frame of its is in flight";

/// Whether no estimate through `delay` reaches the controller sooner than a frame after
/// its capture, so that the physics to the next frame needs none from this one.
fn renders_ahead<T>(delay: &DelayLine<T>) -> bool {
    delay.min_latency_steps() >= u64::from(STEPS_PER_FRAME)
}

/// Runs `f`, adding its wall-clock time to `spent`.
fn timed<T>(spent: &mut Duration, f: impl FnOnce() -> T) -> T {
    let started = Instant::now();
    let out = f();
    *spent += started.elapsed();
    out
}

/// The tracker's step on one frame: the image only, and in robust mode the gyro's reading
/// of the camera's rotation since the last frame.
fn track_frame(
    tracker: &mut Tracker,
    image: &GrayImage,
    t_s: f64,
    ego: Option<EgoMotion>,
    diagnostics: bool,
) -> (TrackOutput, Vec<EdgeDiagnostic>) {
    let view = GrayView::new(
        image.width() as usize,
        image.height() as usize,
        image.as_raw(),
    )
    .expect("the renderer's frame matches its size");
    match (ego, diagnostics) {
        (Some(ego), true) => tracker.step_aided_with_diagnostics(view, t_s, ego),
        (Some(ego), false) => (tracker.step_aided(view, t_s, ego), Vec::new()),
        (None, true) => tracker.step_with_diagnostics(view, t_s),
        (None, false) => (tracker.step(view, t_s), Vec::new()),
    }
}

/// rapier's pose (f32, glam) as a nalgebra isometry (f64).
fn iso(p: &Pose) -> Isometry3<f64> {
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

fn xz(p: &Pose) -> [f64; 2] {
    [f64::from(p.translation.x), f64::from(p.translation.z)]
}

/// The lane centre of the right lane as the drivers' polyline, one point every
/// [`ROUTE_SAMPLE_M`], and how far it reaches from the origin along x or z, metres.
/// Scenario validation and [`ClosedLoop::new`] both build it, so they agree.
pub(crate) fn lane_polyline(route: &scene::Route, lateral_m: f64) -> (Vec<Vector>, f32) {
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
pub(crate) fn world_config(base: &vehicle::WorldConfig, reach_m: f32) -> vehicle::WorldConfig {
    let mut world = base.clone();
    world.ground.half_extent_m = world
        .ground
        .half_extent_m
        .max(reach_m + GROUND_BEYOND_ROUTE_M);
    world
}

impl ClosedLoop {
    /// Sets up the world, vehicles, controllers, camera and tracker for a scenario.
    pub fn new(s: &Scenario, backend: Backend, diagnostics: bool) -> Result<ClosedLoop, LoopError> {
        let started = Instant::now();
        let setup = |message: String| LoopError::Setup {
            scenario: s.name.clone(),
            message,
        };
        let chase_params = VehicleParams::hmmwv_m998();
        let lead_params = VehicleParams::pickup();
        // Validation ([`Scenario`]) made every check below already: these errors cannot
        // happen for a validated scenario, and remain only as a guard.
        let scene_route = scene::Route::new(s.route.clone());
        let lateral = 0.5 * s.route.lane_width_m;
        let (points, _) = lane_polyline(&scene_route, lateral);
        let route = Route::new(points).map_err(|e| setup(format!("route: {e}")))?;
        let pose_at = |s_m: f64| {
            let s = s_m as f32;
            Pose::from_parts(
                route.point_at(s),
                Rotation::from_rotation_y(direction_heading(route.tangent_at(s))),
            )
        };
        let chase_start_m = s.chase_start_m;
        let world_config = s.world.clone();
        let mut world = World::new(&world_config).map_err(|e| setup(format!("physics: {e}")))?;
        let v0 = s.lead_initial_speed_mps as f32;
        let lead_id = world
            .add_vehicle(&lead_params, pose_at(s.lead_start_m), v0)
            .map_err(|e| setup(format!("lead vehicle: {e}")))?;
        let chase_id = world
            .add_vehicle(&chase_params, pose_at(chase_start_m), v0)
            .map_err(|e| setup(format!("chase vehicle: {e}")))?;
        let chase = ChaseController::new(s.chase.clone(), &chase_params, v0)
            .map_err(|e| setup(format!("chase controller: {e}")))?;
        let lead = LeadDriver::new(
            route.clone(),
            s.lead_profile.clone(),
            s.lead_driver.clone(),
            &lead_params,
        )
        .map_err(|e| setup(format!("lead driver: {e}")))?;
        let delay = DelayLine::new(&s.delay).map_err(|e| setup(format!("delay line: {e}")))?;

        let CameraSetup {
            scene,
            rig,
            lead_from_scene,
        } = CameraSetup::new(s)?;
        let options = render_options(backend);
        let renderer = Renderer::new(&scene, rig.clone(), &options)?;
        let fingerprint = fingerprint(scene.description(), &rig, &options);

        // The teleoperator places the model on the first frame (2.2), with the scenario's
        // placement error: where the first frame's truth puts it (the frame itself is
        // rendered by the loop's first step, so it is not rendered here too).
        let world_from_chase = iso(&world.vehicle_state(chase_id).world_from_vehicle);
        let world_from_lead =
            iso(&world.vehicle_state(lead_id).world_from_vehicle) * lead_from_scene;
        let t = renderer.ground_truth(&world_from_chase, &world_from_lead, 0.0);
        if !t.in_view {
            return Err(setup(
                "the target is not in the camera's view at t = 0".into(),
            ));
        }
        let [dx, dy, ds] = s.init_offset;
        let init = Location::new(t.c_x + dx, t.c_y + dy, t.scale + ds);
        let mut tracker = Tracker::new(s.target.clone(), s.camera, s.tracker.clone(), init)
            .map_err(|e| setup(format!("tracker: {e}")))?;
        // The overlay and the recording draw associated and rejected points only.
        tracker.set_association_fates_only(true);
        let target_width_px = tracker.target_width_px();

        // The lead's path so far: the lane behind its start, so the chase has a path from t = 0.
        let mut lead_path = DrivenPath::new();
        for k in 0..=((s.lead_start_m - chase_start_m + 10.0) as usize) {
            let st = (chase_start_m - 10.0 + k as f64).max(0.0);
            lead_path.push(scene_route.point(st, lateral));
        }
        let last_chase_xz = xz(&world.vehicle_state(chase_id).world_from_vehicle);
        Ok(ClosedLoop {
            name: s.name.clone(),
            frames: s.frames(),
            frame: 0,
            pipelined: renders_ahead(&delay),
            drive: Drive {
                world,
                chase_id,
                lead_id,
                chase,
                lead,
                delay,
                pan: s
                    .chase
                    .pan_head
                    .enabled
                    .then(|| PanHead::new(s.chase.pan_head.clone(), s.seed))
                    .transpose()
                    .map_err(|e| setup(format!("pan head: {e}")))?,
                interlaced: s.sensor.interlaced,
                earlier_field: None,
                ahead: None,
            },
            scene: renderer.shared_scene(),
            adapter_name: renderer.adapter_name().to_string(),
            renderer: Some(Box::new(renderer)),
            render_thread: None,
            remote: None,
            in_flight: VecDeque::new(),
            advanced: None,
            fingerprint,
            timing: LoopTiming {
                setup_s: started.elapsed().as_secs_f64(),
                ..LoopTiming::default()
            },
            parts: FrameParts::new(
                rig.width,
                rig.height,
                // Robust mode turns its prediction with the gyro's reading.
                (s.tracker.mode == TrackerMode::Robust).then_some(rig.intrinsics),
            ),
            auto_gain: AutoGainControl::new(
                s.sensor.auto_gain,
                rig.width,
                rig.height,
                f64::from(vehicle::CAMERA_HZ),
            ),
            rig,
            tracker,
            lead_from_scene,
            target_width_px,
            lead_path,
            chase_distance_m: 0.0,
            last_chase_xz,
            diagnostics,
            gyro: (s.tracker.mode == TrackerMode::Robust)
                .then(|| Gyro::new(&GyroConfig::default(), s.seed)),
            last_camera: None,
            last_ego: None,
            start: init,
        })
    }

    /// The teleoperator's placement the tracker started from (the first frame's truth with
    /// the scenario's `tracker.init_offset`).
    pub fn tracker_start(&self) -> Location {
        self.start
    }

    /// The camera rig.
    pub fn rig(&self) -> &CameraRig {
        &self.rig
    }

    /// The scenario's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// How many frames the scenario lasts.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Frames run so far.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// The chase controller (its events log says when and why it stopped).
    pub fn chase(&self) -> &ChaseController {
        &self.drive.chase
    }

    /// Starts a second renderer in a worker process (`command`: `carfollow render-worker`
    /// with this scenario's file and overrides), so that two camera frames render at once:
    /// frame k + 1 in one renderer while frame k finishes in the other. Results are
    /// identical to one renderer's (the worker checks it builds the same scene), so this
    /// only changes the speed. Possible only when the loop can overlap at all (see
    /// [`ClosedLoop::set_pipelined`]) and before the first step; returns whether two frames
    /// are now in flight.
    pub fn add_render_worker(&mut self, command: std::process::Command) -> Result<bool, LoopError> {
        if !self.pipelined || self.frame > 0 {
            return Ok(false);
        }
        let started = RemoteRenderer::spawn(command).map_err(LoopError::Worker)?;
        self.add_started_render_worker(started)
    }

    /// [`ClosedLoop::add_render_worker`] with a worker already started (before this loop
    /// set up, so that both set up at once: see [`ClosedLoop::renders_ahead`]). A worker
    /// this loop cannot use is dropped, which ends it.
    ///
    /// The first frame starts rendering on this process's render thread before the worker
    /// is waited for, so that it renders (its shaders compiling, its first shadow tiles
    /// drawing) while the worker finishes setting up. Should the worker fail, the loop
    /// takes its renderer back and renders that frame again on one renderer's path: a
    /// capture changes nothing, and a frame's pixels never depend on what its renderer drew
    /// before.
    pub fn add_started_render_worker(&mut self, worker: StartedWorker) -> Result<bool, LoopError> {
        if !self.pipelined || self.frame > 0 {
            return Ok(false);
        }
        if self.in_flight.is_empty() {
            let first = self.submit()?;
            self.in_flight.push_back(first);
        }
        match worker.ready(self.fingerprint, &self.adapter_name, &self.rig) {
            Ok(remote) => {
                self.remote = Some(remote);
                Ok(true)
            }
            Err(e) => {
                self.take_back_first_frame();
                Err(LoopError::Worker(e))
            }
        }
    }

    /// Before the first step: drops the first frame from the render thread, if it is on
    /// it, and takes its renderer back, for one renderer's path to render it again.
    fn take_back_first_frame(&mut self) {
        if self.frame == 0 && self.in_flight.len() == 1 && self.in_flight[0].here {
            self.in_flight.clear();
            let thread = self
                .render_thread
                .as_mut()
                .expect("the first frame's thread");
            self.renderer = Some(thread.wait().renderer);
        }
    }

    /// Whether the loop of scenario `s` renders frames ahead (see `set_pipelined`), so that
    /// it can take a render worker.
    pub fn renders_ahead(s: &Scenario) -> bool {
        DelayLine::<()>::new(&s.delay).is_ok_and(|d| renders_ahead(&d))
    }

    /// How many camera frames render at once: 2 with a render worker, else 1.
    pub fn frames_in_flight(&self) -> usize {
        if self.remote.is_some() {
            2
        } else {
            1
        }
    }

    /// Where the wall-clock time went so far.
    pub fn timing(&self) -> LoopTiming {
        LoopTiming {
            pipelined: self.pipelined,
            frames_in_flight: self.frames_in_flight(),
            rerendered_frames: self.parts.rerendered,
            ..self.timing
        }
    }

    /// Renders every frame whole (the default), or, with `false`, only the part of each
    /// frame the tracker reads (see `sim::frame_parts`): several times faster, and the
    /// estimates are the same bit for bit, but [`FrameOutput::image`] then holds only that
    /// part (the rest is unspecified). Whole frames are for whoever looks at the images:
    /// the video, recordings, stills.
    pub fn set_whole_frames(&mut self, on: bool) {
        self.parts.whole_frames = on;
    }

    /// Whether each frame's rendering and tracking overlap the physics to the next frame.
    pub fn pipelined(&self) -> bool {
        self.pipelined
    }

    /// Asks for each frame's rendering and tracking to run on this thread while a second
    /// thread runs the physics to the next frame (the default), or for the two to run one
    /// after the other. The results are identical either way: the physics to the next frame
    /// needs only estimates from earlier frames, because none arrives sooner than
    /// `loop.latency_ms − loop.jitter_ms` after its capture. So overlap is possible only
    /// when that is at least one frame; otherwise this keeps the loop sequential. Returns
    /// whether the loop is now pipelined.
    pub fn set_pipelined(&mut self, on: bool) -> bool {
        if !on && self.remote.is_some() {
            self.take_back_first_frame();
            if !self.in_flight.is_empty() {
                // A frame is rendering in the worker: too late to change.
                return self.pipelined;
            }
            // Two frames in flight overlap by nature.
            self.remote = None;
        }
        self.pipelined = on && renders_ahead(&self.drive.delay);
        self.pipelined
    }

    /// The renderer's adapter, for reports.
    pub fn adapter_name(&self) -> &str {
        &self.adapter_name
    }

    /// The state of the world at the start of frame `frame_index` (now), and the camera's
    /// input for it.
    fn capture(&self) -> Captured {
        Captured::of(
            &self.drive,
            &self.rig,
            &self.lead_from_scene,
            &self.auto_gain,
        )
    }

    /// Runs one camera frame and the physics up to the next one. `None` when the scenario's
    /// duration is over.
    pub fn step(&mut self) -> Result<Option<FrameOutput>, LoopError> {
        if self.frame >= self.frames {
            return Ok(None);
        }
        let step_started = Instant::now();
        let mut spent = [Duration::ZERO; 3];
        // 1. The camera; 2. the tracker, on the image only; 3. the delay line; 4. the
        // controllers and the physics to the next frame.
        let (captured, frame, track, edges, driven) = if self.remote.is_some() {
            self.step_two_in_flight(&mut spent)?
        } else if self.pipelined {
            // 4 needs no estimate from this frame (see `set_pipelined`), so it runs on a
            // second thread while this one renders and tracks; 3 waits for both.
            let captured = self.capture();
            let t_s = captured.input.time_s;
            let ego = self.ego_motion(&captured);
            let needed = self.parts.needed(
                captured.input.frame_index,
                &captured.world_from_camera.rotation,
            );
            let (renderer, tracker, drive) = (
                self.renderer.as_deref_mut().expect(HERE),
                &mut self.tracker,
                &mut self.drive,
            );
            let diagnostics = self.diagnostics;
            let [render_t, track_t, physics_t] = &mut spent;
            let input = &captured.input;
            let (seen, driven) = std::thread::scope(|scope| {
                let physics = scope.spawn(|| timed(physics_t, || drive.advance_frame()));
                let seen = timed(render_t, || renderer.render_part(input, needed)).and_then(
                    |mut frame| {
                        let ((track, edges), again) = timed(track_t, || {
                            track_part(
                                tracker,
                                &mut frame,
                                |part| renderer.render_part(input, part),
                                |t, f| track_frame(t, &f.image, t_s, ego, diagnostics),
                            )
                        })?;
                        Ok((frame, track, edges, again))
                    },
                );
                let driven = match physics.join() {
                    Ok(driven) => driven,
                    Err(panic) => std::panic::resume_unwind(panic),
                };
                (seen, driven)
            });
            let (frame, track, edges, again) = seen?;
            self.tracked(&captured, &track, again);
            (captured, frame, track, edges, driven)
        } else {
            let captured = self.capture();
            let ego = self.ego_motion(&captured);
            let needed = self.parts.needed(
                captured.input.frame_index,
                &captured.world_from_camera.rotation,
            );
            let [render_t, track_t, physics_t] = &mut spent;
            let renderer = self.renderer.as_deref_mut().expect(HERE);
            let mut frame = timed(render_t, || renderer.render_part(&captured.input, needed))?;
            let (t_s, diagnostics) = (captured.input.time_s, self.diagnostics);
            let ((track, edges), again) = timed(track_t, || {
                track_part(
                    &mut self.tracker,
                    &mut frame,
                    |part| renderer.render_part(&captured.input, part),
                    |t, f| track_frame(t, &f.image, t_s, ego, diagnostics),
                )
            })?;
            self.tracked(&captured, &track, again);
            let driven = timed(physics_t, || self.drive.advance_frame());
            (captured, frame, track, edges, driven)
        };
        debug_assert_eq!(captured.input.frame_index, self.frame);
        if self.remote.is_none() {
            // (With two in flight the step has metered the frame already.)
            self.auto_gain
                .observe(self.frame, captured.input.auto_gain, &frame.image);
        }
        let record = self.record(&captured, &frame, &track, driven);
        let poses = FramePoses {
            world_from_chase: captured.input.world_from_chase,
            world_from_lead: captured.input.world_from_lead,
            world_from_camera: captured.world_from_camera,
        };
        self.frame += 1;
        let [render_t, track_t, physics_t] = spent;
        self.timing.frames += 1;
        self.timing.render_s += render_t.as_secs_f64();
        self.timing.track_s += track_t.as_secs_f64();
        self.timing.physics_s += physics_t.as_secs_f64();
        self.timing.step_s += step_started.elapsed().as_secs_f64();
        Ok(Some(FrameOutput {
            record,
            image: frame.image,
            track,
            edges,
            poses,
            ego: self.last_ego,
        }))
    }

    /// Starts rendering the frame of the world as it is now: even frames on this process's
    /// render thread, odd ones in the render worker, both in the background.
    fn submit(&mut self) -> Result<InFlight, LoopError> {
        let captured = self.capture();
        let needed = self.parts.needed(
            captured.input.frame_index,
            &captured.world_from_camera.rotation,
        );
        let here = captured.input.frame_index.is_multiple_of(2);
        if here {
            let thread = match &mut self.render_thread {
                Some(thread) => thread,
                None => self
                    .render_thread
                    .insert(RenderThread::start().map_err(|e| {
                        LoopError::Worker(format!("cannot start the render thread: {e}"))
                    })?),
            };
            let renderer = self.renderer.take().expect(HERE);
            thread.render(renderer, captured.input.clone(), needed);
        } else {
            let remote = self.remote.as_mut().expect("two frames in flight");
            remote
                .submit(&captured.input, needed)
                .map_err(LoopError::Worker)?;
        }
        Ok(InFlight { captured, here })
    }

    /// One frame with two in flight (see [`ClosedLoop::add_render_worker`]). Frames
    /// alternate: even ones render on this process's render thread, odd ones in the worker,
    /// and each renderer starts its next frame as soon as that frame can be captured:
    /// - frame k is tracked (waiting for its render first), then, when frame k + 1 is still
    ///   to come, the physics to k + 2 runs (it needs estimates up to frame k alone: see
    ///   `set_pipelined`) and frame k + 2 goes to frame k's renderer, all before this step
    ///   returns frame k's outputs;
    /// - frame k's renderer is the worker: the physics to k + 2's steps before the estimate
    ///   of frame k can fall due run while frame k comes back, and after frame k + 2 is
    ///   submitted, those of the physics to k + 3 before frame k + 1's estimate can.
    ///
    /// With diagnostics on (a recording reads the chase controller after each frame) nothing
    /// runs ahead: the physics to k + 1 runs in step k, and frame k + 1 goes to its renderer
    /// then, before frame k is tracked.
    ///
    /// Should frame k's tracking need more of the frame, its own renderer renders it (the
    /// worker, or this process's, which is back from its thread by then). Each frame is
    /// metered for the automatic gain control as soon as it is tracked, before any later
    /// frame is captured. The order of all this is one renderer's, so the results are too.
    #[allow(clippy::type_complexity)]
    fn step_two_in_flight(
        &mut self,
        spent: &mut [Duration; 3],
    ) -> Result<(Captured, Frame, TrackOutput, Vec<EdgeDiagnostic>, Driven), LoopError> {
        let [render_t, track_t, physics_t] = spent;
        if self.in_flight.is_empty() {
            let first = self.submit()?;
            self.in_flight.push_back(first);
        }
        let pending = self.in_flight.pop_front().expect("a frame in flight");
        let k = pending.captured.input.frame_index;
        let more = k + 1 < self.frames;
        // The physics runs ahead of the outputs (not with diagnostics: the recording takes
        // the chase controller as it stands after each frame).
        let ahead = more && !self.diagnostics;
        let t_s = pending.captured.input.time_s;
        let ego = self.ego_motion(&pending.captured);
        let diagnostics = self.diagnostics;
        let step = |t: &mut Tracker, f: &Frame| track_frame(t, &f.image, t_s, ego, diagnostics);
        let input = &pending.captured.input;
        let driven = match self.advanced.take() {
            Some(advanced) => advanced,
            None => timed(physics_t, || self.drive.advance_frame()),
        };
        if more && self.in_flight.is_empty() {
            // Nothing ran ahead (diagnostics, or the first frame): frame k + 1 now.
            let next = self.submit()?;
            self.in_flight.push_back(next);
        }
        let (frame, ((track, edges), again)) = if pending.here {
            let thread = self
                .render_thread
                .as_mut()
                .expect("a frame on the render thread");
            let rendered = thread.wait();
            *render_t += rendered.spent;
            let renderer = self.renderer.insert(rendered.renderer);
            let mut frame = rendered.frame?;
            let seen = timed(track_t, || {
                track_part(
                    &mut self.tracker,
                    &mut frame,
                    |part| renderer.render_part(input, part),
                    step,
                )
            })?;
            (frame, seen)
        } else {
            if ahead {
                let due = self.drive.earliest_due(k);
                timed(physics_t, || self.drive.advance_before(due));
            }
            let remote = self.remote.as_mut().expect("two frames in flight");
            let mut frame = timed(render_t, || remote.receive()).map_err(LoopError::Worker)?;
            let seen = timed(track_t, || {
                track_part(
                    &mut self.tracker,
                    &mut frame,
                    |part| {
                        remote.submit(input, part)?;
                        remote.receive()
                    },
                    step,
                )
            })
            .map_err(LoopError::Worker)?;
            (frame, seen)
        };
        self.tracked(&pending.captured, &track, again);
        self.auto_gain.observe(k, input.auto_gain, &frame.image);
        if ahead {
            // The physics to k + 2, and frame k + 2 to the renderer frame k came from.
            let advanced = timed(physics_t, || self.drive.advance_frame());
            self.advanced = Some(advanced);
            if k + 2 < self.frames {
                let next = self.submit()?;
                self.in_flight.push_back(next);
                if !pending.here {
                    // The physics to k + 3 needs frame k + 1 tracked only from the step its
                    // estimate can fall due: the steps before run now, while frame k + 1
                    // finishes rendering here.
                    let due = self.drive.earliest_due(k + 1);
                    timed(physics_t, || self.drive.advance_before(due));
                }
            }
        }
        Ok((pending.captured, frame, track, edges, driven))
    }

    /// After frame `captured` is tracked: its estimate into the delay line, and what it
    /// read for the part of the next frames to render.
    fn tracked(&mut self, captured: &Captured, track: &TrackOutput, rerendered: bool) {
        self.drive
            .push_estimate(captured.now, track, captured.pan_reading_rad);
        self.parts.observe(
            captured.input.frame_index,
            track.estimate,
            track.next,
            self.tracker.last_read(),
            captured.world_from_camera.rotation,
        );
        self.parts.rerendered += u64::from(rerendered);
    }

    /// The gyro's reading of the camera's rotation since the last tracked frame, for the
    /// frame `captured` (robust mode only), kept for the frame's output. Frames are tracked
    /// in order, so this is called once per frame, in order.
    fn ego_motion(&mut self, captured: &Captured) -> Option<EgoMotion> {
        let ego = self.gyro_reading(captured);
        self.last_ego = ego;
        ego
    }

    /// See [`ClosedLoop::ego_motion`].
    fn gyro_reading(&mut self, captured: &Captured) -> Option<EgoMotion> {
        let gyro = self.gyro.as_mut()?;
        let now = captured.world_from_camera.rotation;
        let previous = self.last_camera.replace(now)?;
        // The rotation from the last camera orientation to this one, in the last camera's
        // frame; the gyro rides on the camera (on the pan head when there is one), so its
        // axes are the camera's up to a constant rotation.
        let measured = gyro.measure(
            camera_turn(&previous, &now),
            1.0 / f64::from(vehicle::CAMERA_HZ),
        );
        Some(EgoMotion {
            rotation_rad: measured,
        })
    }

    /// The recorder: truth against estimate, at the frame's capture time.
    fn record(
        &mut self,
        captured: &Captured,
        frame: &Frame,
        track: &TrackOutput,
        driven: Driven,
    ) -> FrameRecord {
        let Driven {
            controls,
            collision,
            chase_mode,
            desired_gap_m,
        } = driven;
        let (chase_state, lead_state) = (&captured.chase, &captured.lead);
        let truth = frame.truth;
        let est = track.estimate;
        let [x, _, z] = track.position_3d;
        let width_px = truth.scale * self.target_width_px;
        let lost_truth = !truth.in_view
            || (est.c_x - truth.c_x).hypot(est.c_y - truth.c_y) > 0.25 * width_px
            || (est.scale / truth.scale - 1.0).abs() > 0.25;
        let world_from_camera = captured.world_from_camera;
        let loss_cause = if !lost_truth {
            LossCause::None
        } else if !truth.in_view {
            LossCause::OutOfView
        } else if target_occluded(
            &self.scene,
            &captured.input.world_from_chase,
            &captured.input.world_from_lead,
            &world_from_camera,
            captured.input.time_s,
        ) {
            LossCause::Occluded
        } else {
            LossCause::Tracker
        };
        let cam = world_from_camera.translation.vector;
        let [tx, ty, tz] = truth.target_cam_m;
        let target_world = world_from_camera * nalgebra::Point3::new(tx, ty, tz);
        let gap_m = (target_world.x - cam.x).hypot(target_world.z - cam.z);
        let chase_xz = xz(&chase_state.world_from_vehicle);
        let lead_xz = xz(&lead_state.world_from_vehicle);
        self.chase_distance_m +=
            (chase_xz[0] - self.last_chase_xz[0]).hypot(chase_xz[1] - self.last_chase_xz[1]);
        self.last_chase_xz = chase_xz;
        self.lead_path.push(lead_xz);
        let lateral_deviation_m = self.lead_path.distance(chase_xz);
        FrameRecord {
            frame: self.frame,
            t_s: captured.input.time_s,
            true_cx: truth.c_x,
            true_cy: truth.c_y,
            true_scale: truth.scale,
            true_range_m: tz,
            true_lateral_m: tx,
            target_in_view: truth.in_view,
            est_cx: est.c_x,
            est_cy: est.c_y,
            est_scale: est.scale,
            est_range_m: z,
            est_lateral_m: x,
            confidence: track.measurement.map_or([0.0; 3], |m| m.confidence),
            status: TrackerStatus::from(track.status),
            lost_truth,
            gap_m,
            chase_speed_mps: f64::from(chase_state.forward_speed_mps),
            lead_speed_mps: f64::from(lead_state.forward_speed_mps),
            steering_rad: f64::from(controls.steer_rad),
            throttle: f64::from(controls.throttle),
            brake: f64::from(controls.brake),
            lateral_deviation_m,
            chase_distance_m: self.chase_distance_m,
            chase_xz,
            lead_xz,
            collision,
            chase_mode: format!("{chase_mode:?}").to_lowercase(),
            coverage: track.coverage,
            coverage_gain: track.coverage_gain,
            tracker_event: track
                .event
                .map_or_else(String::new, |e| e.as_str().to_string()),
            fit_residual: track.measurement.map_or(f64::NAN, |m| m.residual),
            feature_sigma2: track
                .features
                .iter()
                .map(|f| f.variance.unwrap_or(f64::NAN))
                .collect(),
            loss_cause,
            camera_pan_deg: captured.input.camera_pan_rad.to_degrees(),
            desired_gap_m: f64::from(desired_gap_m),
        }
    }
}
