//! The closed loop (ARCHITECTURE.md, "Bird's-eye view"): every 1/15 s the camera renders a frame,
//! the tracker processes it, its 3-D estimate enters the delay line, and the controllers
//! drive both vehicles through eight 120 Hz physics steps.
//!
//! Data flows one way. The tracker sees only the image; the chase controller sees only the
//! delayed estimates and its own odometry; only the recorder (the [`FrameRecord`] built here)
//! sees the truth.

mod capture;
mod contrast;
mod drive;
mod error;
mod eye;
mod recorder;
mod renderers;
mod schedule;
mod tracking;
mod traffic_drive;
mod traffic_truth;
mod two_in_flight;

pub use error::LoopError;
pub use renderers::LoopOptions;
pub use traffic_drive::RunEnd;

use capture::{renders_ahead, xz};
use drive::{Chase, Drive};
use error::at_frame;
use eye::Eye;
use recorder::Recorder;
use schedule::{Schedule, Shot, Spent};
use tracking::Tracking;
use traffic_truth::TrafficTruth;

use crate::auto_gain::AutoGainControl;
use crate::driven_path::DrivenPath;
use crate::frame_parts::FrameParts;
use crate::plan::{render_options, Plan};
use crate::plugin::{
    BuiltinController, BuiltinTracker, CameraModel, ControllerChoice, Estimate, TrackerChoice,
};
use crate::record::FrameRecord;
use crate::render_worker::fingerprint;
use crate::scenario::Scenario;
use image::GrayImage;
use nalgebra::Isometry3;
use serde::Serialize;
use sim_render::{Backend, CameraRig, Renderer, Route as SceneRoute};
use std::collections::VecDeque;
use std::time::{Duration, Instant};
use tracker::{EdgeDiagnostic, EgoMotion, Location, TrackOutput, Tracker, TrackerMode};
use vehicle::{ChaseController, DelayLine, Gyro, GyroConfig};

/// Everything one frame of the loop produced.
pub struct FrameOutput {
    /// The recorder's row.
    pub record: FrameRecord,
    /// The camera frame.
    pub image: GrayImage,
    /// The tracker's estimate (`None`: a plug-in had none this frame).
    pub estimate: Option<Estimate>,
    /// The paper's tracker's whole output (stages 1–8), when it is the tracker.
    pub track: Option<TrackOutput>,
    /// Edge fates, when diagnostics were asked for (the paper's tracker only).
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

impl LoopTiming {
    /// Adds one step's times: `spent` rendering, tracking and in physics, `step` in all.
    fn add(&mut self, spent: Spent, step: Duration) {
        let [render_t, track_t, physics_t] = spent;
        self.frames += 1;
        self.render_s += render_t.as_secs_f64();
        self.track_s += track_t.as_secs_f64();
        self.physics_s += physics_t.as_secs_f64();
        self.step_s += step.as_secs_f64();
    }
}

/// The running loop: the paper's loop, one camera frame per [`ClosedLoop::step`].
pub struct ClosedLoop {
    name: String,
    frames: u64,
    frame: u64,
    /// The physics: the vehicles, their controllers, the delay line between.
    drive: Drive,
    /// The camera and the tracker.
    eye: Eye,
    /// The renderers and the frames in flight.
    schedule: Schedule,
    /// The truth against the estimate.
    recorder: Recorder,
    timing: LoopTiming,
    /// The teleoperator's placement the tracker started from.
    start: Location,
    /// What the set-up has to say that is not an error (see [`ClosedLoop::notes`]).
    notes: Vec<String>,
}

impl ClosedLoop {
    /// Runs one camera frame and the physics up to the next one. `None` when the scenario's
    /// duration is over.
    ///
    /// A frame is the paper's loop in order: 1. the camera captures the world, 2. renders
    /// it, 3. the tracker tracks the image, 4. its estimate enters the delay line, 5. the
    /// controllers and the physics run eight 120 Hz steps to the next frame, and 6. the
    /// recorder holds the truth against the estimate. The schedule may run 2 and 3 beside
    /// 5, or the next frame's 2 beside this one's 3, but never so that any result differs
    /// from running them in order (see `schedule`).
    pub fn step(&mut self) -> Result<Option<FrameOutput>, LoopError> {
        if self.frame >= self.frames || self.ended_before(self.frame) {
            return Ok(None);
        }
        let started = Instant::now();
        let mut spent = Spent::default();
        // 1 to 5.
        let shot = self
            .schedule
            .run(&mut self.drive, &mut self.eye, &mut spent)
            .map_err(|e| at_frame(e, self.frame))?;
        if let Some((step, error)) = self.drive.take_failure() {
            // The frame whose physics the step belongs to (it may run ahead of this one).
            return Err(LoopError::Plugin {
                what: "controller",
                frame: Some(step.0 / u64::from(vehicle::STEPS_PER_FRAME)),
                t_s: Some(step.seconds()),
                error,
            });
        }
        let Shot {
            captured,
            frame,
            tracked,
            driven,
        } = shot;
        debug_assert_eq!(captured.input.frame_index, self.frame);
        // 6.
        let record = self
            .recorder
            .record(self.frame, &captured, &frame, &tracked, driven);
        self.frame += 1;
        self.timing.add(spent, started.elapsed());
        Ok(Some(FrameOutput {
            record,
            image: frame.image,
            estimate: tracked.estimate,
            track: tracked.out,
            edges: tracked.edges,
            poses: FramePoses {
                world_from_chase: captured.input.world_from_chase,
                world_from_lead: captured.input.world_from_lead,
                world_from_camera: captured.world_from_camera,
            },
            ego: self.eye.last_ego,
        }))
    }

    /// The loop of `plan` on one renderer of `backend` (see [`ClosedLoop::start`] for
    /// two), with the built-in tracker and controller: the plan's world, controllers and
    /// scene, this process's renderer, and the paper's tracker, which the teleoperator
    /// places on the first frame as the plan says (the frame itself is rendered by the
    /// loop's first step). With `diagnostics`, each frame's output carries its edge points'
    /// fates (for the overlay and recordings).
    pub fn new(plan: Plan, backend: Backend, diagnostics: bool) -> Result<ClosedLoop, LoopError> {
        ClosedLoop::with(
            plan,
            backend,
            diagnostics,
            TrackerChoice::Builtin,
            ControllerChoice::Builtin,
        )
    }

    /// [`ClosedLoop::new`] with the tracker and the controller chosen. A plug-in tracker is
    /// reset with the camera and the teleoperator's placement (the plan's start); a
    /// plug-in controller takes the built-in's place from the first physics step.
    pub fn with(
        plan: Plan,
        backend: Backend,
        diagnostics: bool,
        tracker: TrackerChoice,
        controller: ControllerChoice,
    ) -> Result<ClosedLoop, LoopError> {
        let started = Instant::now();
        let planned_s = plan.built_s;
        let start_estimate = plan.start_estimate();
        let Plan {
            scenario: s,
            scene_route,
            chase_start_m,
            world,
            chase_id,
            lead_id,
            chase,
            lead,
            delay,
            pan,
            scene,
            rig,
            lead_from_scene,
            tracker_start: init,
            traffic,
            ..
        } = plan;
        let kinds: Vec<_> = s.actors.iter().map(|a| a.kind).collect();
        let recorder_traffic = traffic.as_ref().map(|t| {
            TrafficTruth::new(
                t.road.clone(),
                t.vehicles.clone(),
                rig.clone(),
                &kinds,
                s.tracker.edge_threshold,
            )
        });
        let options = render_options(backend);
        let renderer = Renderer::new(scene.clone(), rig.clone(), &options)?;
        let fingerprint = fingerprint(scene.description(), &rig, &options);
        // Two plug-ins may share state (one object behind both, say): then nothing runs
        // beside anything else, so that their calls come in one order, run after run.
        let overlap = !(matches!(tracker, TrackerChoice::Plugin(_))
            && matches!(controller, ControllerChoice::Plugin(_)));
        let can_overlap = overlap && renders_ahead(&delay);
        // Robust mode's prediction, and so the parts rendered, turn with the gyro.
        let turning =
            matches!(tracker, TrackerChoice::Builtin) && s.tracker.mode == TrackerMode::Robust;
        let pan_rad = pan.as_ref().map_or(0.0, vehicle::PanHead::reading_rad);
        let (mut tracking, target_width_px) =
            tracking_of(tracker, &s, &rig, pan_rad, init, &start_estimate)?;
        tracking.tracker.set_diagnostics(diagnostics);
        let gyro = tracking
            .tracker
            .reads_gyro()
            .then(|| Gyro::new(&GyroConfig::default(), s.seed));
        let chase = Chase::new(match controller {
            ControllerChoice::Builtin => Box::new(BuiltinController::from(chase)),
            ControllerChoice::Plugin(plugin) => plugin,
        });
        let drive = Drive {
            world,
            chase_id,
            lead_id,
            chase,
            lead,
            delay,
            pan,
            interlaced: s.sensor.interlaced,
            earlier_field: None,
            ahead: None,
            lead_at_road_end: None,
            traffic: traffic.map(|t| traffic_drive::TrafficDrive::new(t, chase_id, lead_id)),
        };
        let recorder = Recorder {
            scene: scene.clone(),
            target_width_px,
            target_width_m: s.target.size_m()[0],
            faint: contrast::Faintness::new(
                s.target.features_px(&s.camera),
                s.tracker.edge_threshold,
            ),
            // The lead's path so far: the lane behind its start, so the chase has a path
            // from t = 0.
            lead_path: lane_behind(&scene_route, &s, chase_start_m),
            chase_distance_m: 0.0,
            last_chase_xz: xz(&drive.world.vehicle_state(chase_id).world_from_vehicle),
            traffic: recorder_traffic,
            // A tracker placed on the target holds it from the start; one that searches
            // has yet to find it.
            acquired: !s.search_start,
        };
        let eye = Eye {
            parts: FrameParts::new(rig.width, rig.height, turning.then_some(rig.intrinsics)),
            auto_gain: AutoGainControl::new(
                s.sensor.auto_gain,
                rig.width,
                rig.height,
                f64::from(vehicle::CAMERA_HZ),
            ),
            rig,
            lead_from_scene,
            tracking,
            diagnostics,
            gyro,
            last_camera: None,
            last_ego: None,
        };
        let schedule = Schedule {
            frames: s.frames(),
            pipelined: can_overlap,
            can_overlap,
            adapter_name: renderer.adapter_name().to_string(),
            renderer: Some(Box::new(renderer)),
            fingerprint,
            render_thread: None,
            remote: None,
            solo: None,
            in_flight: VecDeque::new(),
            advanced: None,
        };
        Ok(ClosedLoop {
            name: s.name.clone(),
            frames: s.frames(),
            frame: 0,
            drive,
            eye,
            schedule,
            recorder,
            timing: LoopTiming {
                setup_s: planned_s + started.elapsed().as_secs_f64(),
                ..LoopTiming::default()
            },
            start: init,
            notes: Vec::new(),
        })
    }

    /// The teleoperator's placement the tracker started from (the first frame's truth with
    /// the scenario's `tracker.init_offset`).
    pub fn tracker_start(&self) -> Location {
        self.start
    }

    /// The camera rig.
    pub fn rig(&self) -> &CameraRig {
        &self.eye.rig
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

    /// The built-in chase controller, when it drives (its events log says when and why it
    /// stopped).
    pub fn chase(&self) -> Option<&ChaseController> {
        self.drive.builtin()
    }

    /// When the lead reached its route's end, where its driver stops it, seconds (`None`
    /// while it has not): the rest of the run follows a standing lead, which a log should
    /// say. (The physics may run a frame ahead of the frames returned.)
    pub fn lead_at_road_end_s(&self) -> Option<f64> {
        self.drive.lead_at_road_end.map(|step| step.seconds())
    }

    /// The event whose action ended the run before its duration (`end_run`), once the
    /// frames returned have reached the frame whose physics it started in (`None` while
    /// none has). That frame is the run's last.
    pub fn run_ended(&self) -> Option<&RunEnd> {
        self.end_noted().filter(|_| self.ended_before(self.frame))
    }

    /// The event that ended the run, as the physics noted it (it may run a frame ahead).
    fn end_noted(&self) -> Option<&RunEnd> {
        self.drive.traffic.as_ref().and_then(|t| t.ended.as_ref())
    }

    /// Whether an event ended the run in the physics of a frame before `frame` (the
    /// physics may have run on past it; what it did after is not the run's).
    fn ended_before(&self, frame: u64) -> bool {
        let per_frame = u64::from(vehicle::STEPS_PER_FRAME);
        self.end_noted()
            .is_some_and(|e| e.step.0 / per_frame < frame)
    }

    /// The tracker's name, for reports: the paper's with its mode, or the plug-in's own.
    pub fn tracker_name(&self) -> String {
        self.eye.tracking.name()
    }

    /// The controller's name, for reports.
    pub fn controller_name(&self) -> String {
        self.drive.chase.controller.name()
    }

    /// Whether the loop of scenario `s` renders frames ahead (see `set_pipelined`), so that
    /// it can take a render worker.
    pub fn renders_ahead(s: &Scenario) -> bool {
        DelayLine::<()>::new(&s.delay).is_ok_and(|d| renders_ahead(&d))
    }

    /// What the loop's set-up has to say that is not an error (a second renderer that could
    /// not be had, so frames render one at a time): one line each, for a log.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// How many camera frames render at once: 2 with a render worker, else 1.
    pub fn frames_in_flight(&self) -> usize {
        self.schedule.frames_in_flight()
    }

    /// Where the wall-clock time went so far.
    pub fn timing(&self) -> LoopTiming {
        LoopTiming {
            pipelined: self.schedule.pipelined,
            frames_in_flight: self.frames_in_flight(),
            rerendered_frames: self.eye.parts.rerendered,
            ..self.timing
        }
    }

    /// Renders every frame whole (the default), or, with `false`, only the part of each
    /// frame the tracker reads (see `frame_parts`): several times faster, and the
    /// estimates are the same bit for bit, but [`FrameOutput::image`] then holds only that
    /// part (the rest is unspecified). Whole frames are for whoever looks at the images:
    /// the video, recordings, stills.
    pub fn set_whole_frames(&mut self, on: bool) {
        self.eye.parts.whole_frames = on;
    }

    /// Whether each frame's rendering and tracking overlap the physics to the next frame.
    pub fn pipelined(&self) -> bool {
        self.schedule.pipelined
    }

    /// Asks for each frame's rendering and tracking to run on this thread while a second
    /// thread runs the physics to the next frame (the default), or for the two to run one
    /// after the other. The results are identical either way: the physics to the next frame
    /// needs only estimates from earlier frames, because none arrives sooner than
    /// `loop.latency_ms − loop.jitter_ms` after its capture. So overlap is possible only
    /// when that is at least one frame; otherwise this keeps the loop sequential. Returns
    /// whether the loop is now pipelined.
    pub fn set_pipelined(&mut self, on: bool) -> bool {
        self.schedule.set_pipelined(on)
    }

    /// Starts rendering the next frame now, on this process's render thread, so that it
    /// renders while the caller does something else (a Gymnasium agent choosing its
    /// action); the next [`ClosedLoop::step`] takes it. Only with one renderer, and it
    /// changes nothing of the results: the frame is the one the step would render.
    pub fn prefetch(&mut self) -> Result<(), LoopError> {
        self.schedule.prefetch(&self.drive, &self.eye, self.frame)
    }

    /// The renderer's adapter, for reports.
    pub fn adapter_name(&self) -> &str {
        &self.schedule.adapter_name
    }
}

/// The loop's tracker, as `choice` says, reset with the camera and `start` (the
/// teleoperator's placement `init` as an estimate), and the target's width in the image at
/// the nominal range, pixels.
fn tracking_of(
    choice: TrackerChoice,
    s: &Scenario,
    rig: &CameraRig,
    pan_rad: f64,
    init: Location,
    start: &Estimate,
) -> Result<(Tracking, f64), LoopError> {
    let paper = Tracker::new(s.target.clone(), s.camera, s.tracker.clone(), init).map_err(|e| {
        LoopError::Setup {
            scenario: s.name.clone(),
            message: format!("tracker: {e}"),
        }
    })?;
    let mut tracker = match choice {
        TrackerChoice::Builtin => Box::new(BuiltinTracker::new(s.tracker.clone())),
        TrackerChoice::Plugin(plugin) => plugin,
    };
    let camera = CameraModel {
        intrinsics: rig.intrinsics,
        width: rig.width,
        height: rig.height,
        mount_height_m: rig.mount.height_m,
        mount_forward_m: rig.mount.forward_offset_m,
        mount_pitch_down_deg: rig.mount.pitch_deg,
        pan_rad,
        target: s.target.clone(),
    };
    // In traffic, the other vehicles' kinds' backs, which the tracker may come to hold.
    if s.has_traffic() {
        tracker.set_other_targets(&s.other_targets());
    }
    tracker
        .reset(&camera, (!s.search_start).then_some(start))
        .map_err(|error| LoopError::Plugin {
            what: "tracker",
            frame: None,
            t_s: None,
            error,
        })?;
    let tracking = Tracking {
        tracker,
        camera,
        targets: 1 + s.actors.len(),
    };
    Ok((tracking, paper.target_width_px()))
}

/// The lead's lane from 10 m behind the chase's start to the lead's start, metre by metre:
/// the lead's path before t = 0, so that the chase has a path from the first frame.
/// Without a lead, the chase's lane from there to the route's end: the path it keeps.
fn lane_behind(route: &SceneRoute, s: &Scenario, chase_start_m: f64) -> DrivenPath {
    let lateral = s.route.lane_centre_m(s.lead_lane);
    let mut path = DrivenPath::new();
    let end_m = if s.has_lead {
        s.lead_start_m
    } else {
        route.length_m()
    };
    for k in 0..=((end_m - chase_start_m + 10.0) as usize) {
        let station = (chase_start_m - 10.0 + k as f64).max(0.0);
        path.push(route.point(station, lateral));
    }
    path
}
