//! The closed loop (ARCHITECTURE.md, "Bird's-eye view"): every 1/15 s the camera renders a frame,
//! the tracker processes it, its 3-D estimate enters the delay line, and the controllers
//! drive both vehicles through eight 120 Hz physics steps.
//!
//! Data flows one way. The tracker sees only the image; the chase controller sees only the
//! delayed estimates and its own odometry; only the recorder (the [`FrameRecord`] built here)
//! sees the truth.

mod capture;
mod drive;
mod recorder;
mod renderers;
mod step;
mod tracking;
mod two_in_flight;

pub use renderers::LoopOptions;

use capture::{renders_ahead, xz, Captured, InFlight};
use drive::{Chase, Drive, Driven, PluginChase};
use tracking::{PluginTracking, Tracking};

use crate::auto_gain::AutoGainControl;
use crate::driven_path::DrivenPath;
use crate::frame_parts::FrameParts;
use crate::plan::{iso, render_options, Plan};
use crate::plugin::{CameraModel, ControllerChoice, Estimate, PluginError, TrackerChoice};
use crate::record::FrameRecord;
use crate::render_thread::RenderThread;
use crate::render_worker::{fingerprint, RemoteRenderer};
use crate::scenario::Scenario;
use image::GrayImage;
use nalgebra::{Isometry3, UnitQuaternion};
use serde::Serialize;
use sim_render::Scene;
use sim_render::{Backend, CameraRig, RenderError, Renderer};
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Instant;
use thiserror::Error;
use tracker::{EdgeDiagnostic, EgoMotion, Location, TrackOutput, Tracker, TrackerMode};
use vehicle::{ChaseController, DelayLine, Gyro, GyroConfig};

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
    /// A plug-in tracker or controller failed, which ends the run.
    #[error("the {what}{}: {error}", at(*frame, *t_s))]
    Plugin {
        /// `tracker` or `controller`.
        what: &'static str,
        /// The camera frame it failed at (`None` before the first).
        frame: Option<u64>,
        /// The time it failed at, seconds.
        t_s: Option<f64>,
        /// What it said.
        error: PluginError,
    },
}

/// " at frame k (t = s s)", or " before the first frame".
fn at(frame: Option<u64>, t_s: Option<f64>) -> String {
    match (frame, t_s) {
        (Some(k), Some(t)) => format!(" failed at frame {k} (t = {t:.3} s)"),
        (Some(k), None) => format!(" failed at frame {k}"),
        _ => " failed before the first frame".into(),
    }
}

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

/// The running loop.
pub struct ClosedLoop {
    name: String,
    frames: u64,
    frame: u64,
    drive: Drive,
    /// Whether the physics to the next frame runs on a second thread while this frame is
    /// rendered and tracked (see [`ClosedLoop::set_pipelined`]).
    pipelined: bool,
    /// Whether anything may run beside the tracker at all (not with two plug-ins).
    overlap: bool,
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
    tracking: Tracking,
    /// Scene origin (body centre) in the lead's vehicle frame (rear axle).
    lead_from_scene: Isometry3<f64>,
    target_width_px: f64,
    /// The target's width, metres.
    target_width_m: f64,
    /// The lead's driven path, for the chase's lateral deviation.
    lead_path: DrivenPath,
    chase_distance_m: f64,
    last_chase_xz: [f64; 2],
    diagnostics: bool,
    /// The chase's rate gyro, read between tracked frames for robust mode's ego-motion
    /// aided prediction and for plug-in trackers (`None` for the paper's mode, which has no
    /// use for it).
    gyro: Option<Gyro>,
    /// The camera's orientation at the last tracked frame.
    last_camera: Option<UnitQuaternion<f64>>,
    /// The gyro's reading handed to the tracker with the last tracked frame.
    last_ego: Option<EgoMotion>,
    /// The teleoperator's placement the tracker started from.
    start: Location,
    /// What the set-up has to say that is not an error (see [`ClosedLoop::notes`]).
    notes: Vec<String>,
}

impl ClosedLoop {
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
            ..
        } = plan;
        let options = render_options(backend);
        let renderer = Renderer::new(scene.clone(), rig.clone(), &options)?;
        let fingerprint = fingerprint(scene.description(), &rig, &options);
        let mut paper =
            Tracker::new(s.target.clone(), s.camera, s.tracker.clone(), init).map_err(|e| {
                LoopError::Setup {
                    scenario: s.name.clone(),
                    message: format!("tracker: {e}"),
                }
            })?;
        // The overlay and the recording draw associated and rejected points only.
        paper.set_association_fates_only(true);
        let target_width_px = paper.target_width_px();
        let tracking = match tracker {
            TrackerChoice::Builtin => Tracking::Builtin(paper),
            TrackerChoice::Plugin(mut plugin) => {
                let camera = CameraModel {
                    intrinsics: rig.intrinsics,
                    width: rig.width,
                    height: rig.height,
                    mount_height_m: rig.mount.height_m,
                    mount_forward_m: rig.mount.forward_offset_m,
                    mount_pitch_down_deg: rig.mount.pitch_deg,
                    pan_rad: pan.as_ref().map_or(0.0, vehicle::PanHead::reading_rad),
                    target: s.target.clone(),
                };
                plugin
                    .reset(&camera, Some(&start_estimate))
                    .map_err(|error| LoopError::Plugin {
                        what: "tracker",
                        frame: None,
                        t_s: None,
                        error,
                    })?;
                let next_read = plugin.will_read();
                Tracking::Plugin(PluginTracking {
                    tracker: plugin,
                    camera,
                    next_read,
                })
            }
        };
        let chase = match controller {
            ControllerChoice::Builtin => Chase::Builtin(chase),
            ControllerChoice::Plugin(plugin) => Chase::Plugin(PluginChase::new(plugin)),
        };
        // Two plug-ins may share state (one object behind both, say): then nothing runs
        // beside anything else, so that their calls come in one order, run after run.
        let overlap =
            !(matches!(tracking, Tracking::Plugin(_)) && matches!(chase, Chase::Plugin(_)));

        // The lead's path so far: the lane behind its start, so the chase has a path from t = 0.
        let lateral = 0.5 * s.route.lane_width_m;
        let mut lead_path = DrivenPath::new();
        for k in 0..=((s.lead_start_m - chase_start_m + 10.0) as usize) {
            let st = (chase_start_m - 10.0 + k as f64).max(0.0);
            lead_path.push(scene_route.point(st, lateral));
        }
        let last_chase_xz = xz(&world.vehicle_state(chase_id).world_from_vehicle);
        let robust = s.tracker.mode == TrackerMode::Robust;
        let plugin_tracker = matches!(tracking, Tracking::Plugin(_));
        Ok(ClosedLoop {
            name: s.name.clone(),
            frames: s.frames(),
            frame: 0,
            pipelined: overlap && renders_ahead(&delay),
            overlap,
            drive: Drive {
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
            },
            scene,
            adapter_name: renderer.adapter_name().to_string(),
            renderer: Some(Box::new(renderer)),
            render_thread: None,
            remote: None,
            in_flight: VecDeque::new(),
            advanced: None,
            fingerprint,
            timing: LoopTiming {
                setup_s: planned_s + started.elapsed().as_secs_f64(),
                ..LoopTiming::default()
            },
            parts: FrameParts::new(
                rig.width,
                rig.height,
                // Robust mode turns its prediction with the gyro's reading.
                (robust && !plugin_tracker).then_some(rig.intrinsics),
            ),
            auto_gain: AutoGainControl::new(
                s.sensor.auto_gain,
                rig.width,
                rig.height,
                f64::from(vehicle::CAMERA_HZ),
            ),
            rig,
            tracking,
            lead_from_scene,
            target_width_px,
            target_width_m: s.target.size_m()[0],
            lead_path,
            chase_distance_m: 0.0,
            last_chase_xz,
            diagnostics,
            gyro: (robust || plugin_tracker).then(|| Gyro::new(&GyroConfig::default(), s.seed)),
            last_camera: None,
            last_ego: None,
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

    /// The built-in chase controller, when it drives (its events log says when and why it
    /// stopped).
    pub fn chase(&self) -> Option<&ChaseController> {
        self.drive.builtin()
    }

    /// The tracker's name, for reports: the paper's with its mode, or the plug-in's own.
    pub fn tracker_name(&self) -> String {
        self.tracking.name()
    }

    /// The controller's name, for reports.
    pub fn controller_name(&self) -> String {
        match &self.drive.chase {
            Chase::Builtin(_) => "pure pursuit and gap keeper".into(),
            Chase::Plugin(p) => p.controller.name(),
        }
    }

    /// The part of the frame `captured` to render: what the tracker will read, or the
    /// whole frame (`None`).
    fn needed(&self, captured: &Captured) -> Option<tracker::PixelRect> {
        match &self.tracking {
            _ if self.parts.whole_frames => None,
            Tracking::Builtin(_) => self.parts.needed(
                captured.input.frame_index,
                &captured.world_from_camera.rotation,
            ),
            Tracking::Plugin(p) => p.next_read,
        }
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
    /// frame the tracker reads (see `frame_parts`): several times faster, and the
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
        self.pipelined = on && self.overlap && renders_ahead(&self.drive.delay);
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
}
