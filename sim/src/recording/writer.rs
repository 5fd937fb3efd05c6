//! The recorder: each frame of a closed-loop run as Foxglove messages, to an MCAP file, to
//! the live view's WebSocket server, or both (one logging context feeds them all).

use super::convert::{annotations, finite_or_nan, timestamp, tracker_state, transform, vector3};
use super::messages::{ControllerState, GroundTruth, TrackerInput, TrackerState};
use super::{log_time_ns, topics, ReplaySetup, METADATA_NAME};
use crate::report::Summary;
use foxglove::bytes::Bytes;
use foxglove::messages::{
    scene_entity_deletion, CameraCalibration, Color, CubePrimitive, FrameTransforms,
    ImageAnnotations, LinePrimitive, Log, Point3, Pose, Quaternion, RawImage, SceneEntity,
    SceneEntityDeletion, SceneUpdate, Timestamp, Vector3,
};
use foxglove::websocket::{Capability, ChannelView, Client, ServerListener};
use foxglove::{
    Channel, Context, McapCompression, McapWriteOptions, McapWriterHandle, WebSocketServerHandle,
};
use nalgebra::{Isometry3, UnitQuaternion, Vector3 as NaVector3};
use sim_core::FrameOutput;
use sim_core::TrackerStatus;
use sim_render::shift_noise;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use thiserror::Error;
use tracker::EdgeFate;
use vehicle::{ChaseController, ChaseTelemetry, VehicleParams};

/// Uncompressed bytes per MCAP chunk before it is compressed: 1 MiB, about 17 frames
/// (1.1 s), so that Foxglove seeks quickly and a crash loses little.
const CHUNK_BYTES: u64 = 1 << 20;
/// zstd's level for the chunks, which compress the raw camera frames (the bulk) and the
/// rest: level 1 compresses nist-grounds' frames as well as level 3 (4.0 MB) in 70 % of the
/// time.
const ZSTD_LEVEL: u32 = 1;
/// Frames per segment of the lead's driven path in the scene (one second): each segment is
/// its own entity, so the path is sent once, not again every frame.
const PATH_SEGMENT_FRAMES: u64 = 15;

/// A recording or live view that cannot start or be written.
#[derive(Debug, Error)]
pub enum RecordError {
    /// The file cannot be created or written.
    #[error("{path}: cannot write the recording: {message}")]
    File {
        /// The recording.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The live view's server cannot start.
    #[error("the live view cannot listen on 127.0.0.1:{port}: {message}")]
    Live {
        /// The port asked for.
        port: u16,
        /// Why.
        message: String,
    },
}

/// The live view: Foxglove's WebSocket protocol on 127.0.0.1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LiveOptions {
    /// The port (0: any free port; the one chosen is printed).
    pub port: u16,
    /// Hold the run until a client has subscribed to a channel, so that it misses nothing.
    pub wait_for_client: bool,
}

/// Where a [`Recorder`] sends the run.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RecorderOptions {
    /// The MCAP file to write, if any.
    pub mcap: Option<PathBuf>,
    /// The live view, if any.
    pub live: Option<LiveOptions>,
}

/// Unblocks a run that waits for a live client.
#[derive(Default)]
struct FirstSubscriber {
    subscribed: Mutex<bool>,
    ready: Condvar,
}

impl ServerListener for FirstSubscriber {
    fn on_subscribe(&self, _client: Client, _channel: ChannelView) {
        let mut subscribed = self.subscribed.lock().unwrap_or_else(|e| e.into_inner());
        *subscribed = true;
        self.ready.notify_all();
    }
}

/// The channels of a recording, one per topic (see [`topics`]).
struct Channels {
    image: Channel<RawImage>,
    calibration: Channel<CameraCalibration>,
    annotations: Channel<ImageAnnotations>,
    transforms: Channel<FrameTransforms>,
    scene: Channel<SceneUpdate>,
    tracker: Channel<TrackerState>,
    input: Channel<TrackerInput>,
    controller: Channel<ControllerState>,
    truth: Channel<GroundTruth>,
    events: Channel<Log>,
}

/// One frame as the recorder needs it: the loop's output, and the chase controller's state
/// after it.
struct FrameData {
    out: FrameOutput,
    /// The built-in controller's telemetry (`None` for a plug-in controller).
    telemetry: Option<ChaseTelemetry>,
    trail: Vec<vehicle::Vector>,
    /// The chase controller's events since the last frame.
    controller_events: Vec<String>,
}

/// What the recording thread is told.
enum Message {
    /// A frame to record.
    Frame(Box<FrameData>),
    /// The run is over: its failed criteria and verdict, if it completed.
    Finish(Option<(Vec<String>, String)>),
}

/// Writes a run's frames as Foxglove messages on the simulation clock (frame k at k/15 s),
/// on a thread of its own so that the loop does not wait for protobuf and zstd: the
/// loop hands each frame over and goes on. One thread writes, in frame order, so the file
/// is the same every time.
pub struct Recorder {
    mcap: Option<PathBuf>,
    to_writer: Option<SyncSender<Message>>,
    thread: Option<JoinHandle<Result<(), RecordError>>>,
    controller_events: usize,
}

/// Frames handed over but not yet written, at most (about 70 kB each): on a busy machine
/// the writer falls behind the loop and catches up while the run's report is written, so
/// the loop waits for it only when this many are queued (about 18 MB).
const QUEUE_FRAMES: usize = 256;

/// The recording thread's side.
struct Writer {
    context: Arc<Context>,
    mcap: Option<(PathBuf, McapWriterHandle<BufWriter<File>>)>,
    server: Option<WebSocketServerHandle>,
    channels: Channels,
    calibration: CameraCalibration,
    chase_box: (NaVector3<f64>, [f64; 3]),
    lead_box: [f64; 3],
    /// The lead's driven path since the last segment was sent (world x, z).
    path: Vec<[f64; 2]>,
    last_status: Option<TrackerStatus>,
    last_lost_truth: bool,
    /// Whether the last frame's vehicles were in contact: a collision is logged when it
    /// starts, not on every frame of contact.
    last_collision: bool,
    last_log_time: u64,
    /// The sensor noise the images are recorded without, and the seed it comes from (see
    /// [`ReplaySetup::noise_removed_sigma`]).
    noise: (f64, u64),
    /// The last frame without its noise (the buffer is reused).
    quiet: Vec<u8>,
}

impl Recorder {
    /// Starts recording the run that `setup` describes: creates the MCAP file and writes its
    /// metadata record, and starts the live view's server (waiting for a client when asked).
    pub fn start(setup: &ReplaySetup, options: &RecorderOptions) -> Result<Recorder, RecordError> {
        let writer = Writer::start(setup, options)?;
        let (to_writer, from_loop) = sync_channel(QUEUE_FRAMES);
        let thread = std::thread::Builder::new()
            .name("recorder".into())
            .spawn(move || writer.serve(from_loop))
            .map_err(|e| RecordError::File {
                path: options.mcap.clone().unwrap_or_default(),
                message: format!("cannot start the recording thread: {e}"),
            })?;
        Ok(Recorder {
            mcap: options.mcap.clone(),
            to_writer: Some(to_writer),
            thread: Some(thread),
            controller_events: 0,
        })
    }

    /// The MCAP file being written, if any.
    pub fn mcap_path(&self) -> Option<&Path> {
        self.mcap.as_deref()
    }

    /// Records one frame of the loop, with the chase controller as it stands after it
    /// (`None` for a plug-in controller, whose inner state the recording cannot know).
    pub fn frame(&mut self, out: &FrameOutput, chase: Option<&ChaseController>) {
        let events = chase.map_or(&[][..], |c| c.events());
        let controller_events = events[self.controller_events.min(events.len())..]
            .iter()
            .map(|e| {
                format!(
                    "chase controller at {:.3} s: {:?}",
                    e.step.seconds(),
                    e.kind
                )
            })
            .collect();
        self.controller_events = events.len();
        let data = FrameData {
            out: FrameOutput {
                record: out.record.clone(),
                image: out.image.clone(),
                track: out.track.clone(),
                // Only the points the overlay draws.
                edges: out
                    .edges
                    .iter()
                    .filter(|e| matches!(e.fate, EdgeFate::Associated(_) | EdgeFate::TooFar))
                    .copied()
                    .collect(),
                poses: out.poses,
                ego: out.ego,
                estimate: out.estimate,
            },
            telemetry: chase.map(|c| *c.telemetry()),
            trail: chase.map_or_else(Vec::new, |c| c.trail().positions()),
            controller_events,
        };
        if let Some(to) = &self.to_writer {
            // A writer that stopped has said why; `finish` reports it.
            if to.send(Message::Frame(Box::new(data))).is_err() {
                self.to_writer = None;
            }
        }
    }

    /// Ends the recording: logs each failed criterion of `summary` (at the last frame's time)
    /// and closes the file, which is kept only when `keep` says so for this summary (the
    /// file is removed otherwise). Returns the file kept, if any.
    pub fn finish(
        mut self,
        summary: Option<&Summary>,
        keep: impl FnOnce(Option<&Summary>) -> bool,
    ) -> Result<Option<PathBuf>, RecordError> {
        if let Some(to) = self.to_writer.take() {
            let verdict = summary.map(|s| {
                (
                    s.failures.clone(),
                    format!("{}: {}", s.scenario, if s.passed { "PASS" } else { "FAIL" }),
                )
            });
            let _ = to.send(Message::Finish(verdict));
        }
        let thread = self.thread.take().expect("finished once");
        let path = self.mcap.clone();
        match thread.join() {
            Ok(result) => result?,
            Err(panic) => std::panic::resume_unwind(panic),
        }
        let Some(path) = path else {
            return Ok(None);
        };
        if keep(summary) {
            Ok(Some(path))
        } else {
            std::fs::remove_file(&path).map_err(|e| RecordError::File {
                path: path.clone(),
                message: e.to_string(),
            })?;
            Ok(None)
        }
    }
}

impl Drop for Recorder {
    /// A run that stops early still leaves a readable recording of what ran.
    fn drop(&mut self) {
        if let Some(to) = self.to_writer.take() {
            let _ = to.send(Message::Finish(None));
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// How far below the loop the recording thread runs (a nice value, 0–19).
const RECORDER_NICENESS: i32 = 10;

/// Lowers the calling thread's scheduling priority by [`RECORDER_NICENESS`]: the recording
/// is background work, so on a machine whose cores the loop and its renderer keep busy the
/// writer takes the time they leave, and its queue ([`QUEUE_FRAMES`]) holds what it has not
/// written yet. Best effort: a refusal leaves the thread as it was, which changes no output.
fn yield_to_the_loop() {
    #[cfg(target_os = "linux")]
    // SAFETY: `gettid` has no preconditions; `setpriority` on the calling thread's id
    // changes only that thread's niceness (a Linux thread is its own scheduling entity).
    unsafe {
        let tid = libc::gettid();
        let _ = libc::setpriority(libc::PRIO_PROCESS, tid as libc::id_t, RECORDER_NICENESS);
    }
}

impl Writer {
    fn serve(mut self, from_loop: Receiver<Message>) -> Result<(), RecordError> {
        yield_to_the_loop();
        for message in from_loop {
            match message {
                Message::Frame(data) => self.frame(&data),
                Message::Finish(verdict) => return self.finish(verdict),
            }
        }
        // The loop went away without a word: close what was written.
        self.finish(None)
    }

    fn start(setup: &ReplaySetup, options: &RecorderOptions) -> Result<Writer, RecordError> {
        let context = Context::new();
        let mcap = match &options.mcap {
            None => None,
            Some(path) => {
                let file_err = |message: String| RecordError::File {
                    path: path.clone(),
                    message,
                };
                let file = File::create(path).map_err(|e| file_err(e.to_string()))?;
                let write_options = McapWriteOptions::new()
                    .compression(Some(McapCompression::Zstd))
                    .compression_level(ZSTD_LEVEL)
                    // One thread, so that the file is the same on every machine.
                    .compression_threads(0)
                    .chunk_size(Some(CHUNK_BYTES))
                    .profile("");
                let handle = context
                    .mcap_writer_with_options(write_options)
                    .create(BufWriter::new(file))
                    .map_err(|e| file_err(e.to_string()))?;
                handle
                    .write_metadata(METADATA_NAME, setup.metadata())
                    .map_err(|e| file_err(e.to_string()))?;
                Some((path.clone(), handle))
            }
        };
        let channels = Channels {
            image: context.channel_builder(topics::IMAGE).build(),
            calibration: context.channel_builder(topics::CALIBRATION).build(),
            annotations: context.channel_builder(topics::ANNOTATIONS).build(),
            transforms: context.channel_builder(topics::TRANSFORMS).build(),
            scene: context.channel_builder(topics::SCENE).build(),
            tracker: context.channel_builder(topics::TRACKER).build(),
            input: context.channel_builder(topics::INPUT).build(),
            controller: context.channel_builder(topics::CONTROLLER).build(),
            truth: context.channel_builder(topics::TRUTH).build(),
            events: context.channel_builder(topics::EVENTS).build(),
        };
        let server = match options.live {
            None => None,
            Some(live) => {
                let first = Arc::new(FirstSubscriber::default());
                let mut info = std::collections::HashMap::new();
                info.insert("scenario".to_string(), setup.scenario.clone());
                let server = context
                    .websocket_server()
                    .name(format!("carfollow {}", setup.scenario))
                    .bind("127.0.0.1", live.port)
                    .capabilities([Capability::Time])
                    .server_info(info)
                    .listener(first.clone())
                    .start_blocking()
                    .map_err(|e| RecordError::Live {
                        port: live.port,
                        message: e.to_string(),
                    })?;
                eprintln!(
                    "live view: ws://127.0.0.1:{} (open it in Foxglove: Open connection, Foxglove WebSocket)",
                    server.port()
                );
                if live.wait_for_client {
                    eprintln!("live view: waiting for a client to subscribe");
                    let mut subscribed = first.subscribed.lock().unwrap_or_else(|e| e.into_inner());
                    while !*subscribed {
                        subscribed = first
                            .ready
                            .wait(subscribed)
                            .unwrap_or_else(|e| e.into_inner());
                    }
                }
                Some(server)
            }
        };
        let camera = setup.camera;
        let fx = camera.focal_length_mm / camera.pixel_size_mm[0];
        let fy = camera.focal_length_mm / camera.pixel_size_mm[1];
        let [cx, cy] = camera.image_center_px;
        let calibration = CameraCalibration {
            timestamp: None,
            frame_id: "camera".into(),
            width: setup.width,
            height: setup.height,
            distortion_model: "plumb_bob".into(),
            d: vec![0.0; 5],
            k: vec![fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0],
            r: vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            p: vec![fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0],
        };
        let chase = VehicleParams::hmmwv_m998();
        let front = f64::from(chase.front_bumper_x_m());
        let rear = f64::from(chase.rear_bumper_x_m());
        let chase_height = 1.8;
        let chase_box = (
            NaVector3::new(0.5 * (front + rear), 0.5 * chase_height, 0.0),
            [front - rear, chase_height, f64::from(chase.width_m)],
        );
        Ok(Writer {
            context,
            mcap,
            server,
            channels,
            calibration,
            chase_box,
            lead_box: setup.lead_box_m,
            path: Vec::new(),
            last_status: None,
            last_lost_truth: false,
            last_collision: false,
            last_log_time: 0,
            noise: (setup.noise_removed_sigma, setup.seed),
            quiet: Vec::new(),
        })
    }

    fn frame(&mut self, data: &FrameData) {
        let out = &data.out;
        let r = &out.record;
        let ns = log_time_ns(r.frame);
        self.last_log_time = ns;
        let ts = timestamp(ns);
        let ch = &self.channels;
        let (width, height) = out.image.dimensions();

        // The sensor noise (σ = 2 grey levels is about 3 bits a pixel, which no lossless
        // coding removes: 33.4 kB a frame of nist-grounds as PNG) is a function of the seed
        // and the frame's index, so the image is recorded without it and replay adds it
        // back exactly (`camera::shift_noise`).
        shift_noise(
            out.image.as_raw(),
            &mut self.quiet,
            self.noise.0,
            self.noise.1,
            r.frame,
            -1,
        );
        // Raw mono8, left to the chunks' zstd: consecutive frames fall in one 1 MiB chunk,
        // so zstd finds what a frame repeats of the one before, which no per-frame codec
        // does. Measured on nist-grounds' 1,350 noise-free frames: 4.0 MB in 0.10 s as raw
        // frames in zstd level-1 chunks, against 5.9 MB and twice the time as fast PNG,
        // compressed again by the chunks.
        ch.image.log_with_time(
            &RawImage {
                timestamp: Some(ts),
                frame_id: "camera".into(),
                width,
                height,
                encoding: "mono8".into(),
                step: width,
                data: Bytes::copy_from_slice(&self.quiet),
            },
            ns,
        );
        self.calibration.timestamp = Some(ts);
        ch.calibration.log_with_time(&self.calibration, ns);
        ch.annotations.log_with_time(&annotations(out, ts), ns);

        let poses = &out.poses;
        let chase_from_camera = poses.world_from_chase.inverse() * poses.world_from_camera;
        // A run without a lead has none to place.
        let has_lead = out.record.lead_xz[0].is_finite();
        // The world is y up; `map` is the same place with z up, as Foxglove's 3D panel
        // expects of a root frame.
        let map_from_world = Isometry3::from_parts(
            nalgebra::Translation3::identity(),
            UnitQuaternion::from_axis_angle(&NaVector3::x_axis(), std::f64::consts::FRAC_PI_2),
        );
        ch.transforms.log_with_time(
            &FrameTransforms {
                transforms: [
                    Some(transform(ts, "map", "world", &map_from_world)),
                    Some(transform(ts, "world", "chase", &poses.world_from_chase)),
                    has_lead.then(|| transform(ts, "world", "lead", &poses.world_from_lead)),
                    Some(transform(ts, "chase", "camera", &chase_from_camera)),
                ]
                .into_iter()
                .flatten()
                .collect(),
            },
            ns,
        );
        let scene = self.scene(data, ts);
        let ch = &self.channels;
        ch.scene.log_with_time(&scene, ns);

        ch.tracker.log_with_time(&tracker_state(out), ns);
        let ego = out.ego.map(|e| e.rotation_rad);
        let [ego_x_rad, ego_y_rad, ego_z_rad] = ego.unwrap_or([0.0; 3]);
        ch.input.log_with_time(
            &TrackerInput {
                frame: r.frame,
                t_s: r.t_s,
                aided: ego.is_some(),
                ego_x_rad,
                ego_y_rad,
                ego_z_rad,
            },
            ns,
        );
        let none = |v: Option<f32>| v.map_or(f64::NAN, f64::from);
        let telemetry = data.telemetry.as_ref();
        ch.controller.log_with_time(
            &ControllerState {
                frame: r.frame,
                mode: r.chase_mode.clone(),
                steering_rad: r.steering_rad,
                throttle: r.throttle,
                brake: r.brake,
                chase_speed_mps: r.chase_speed_mps,
                gap_estimate_m: telemetry.map_or(f64::NAN, |t| finite_or_nan(t.gap_m)),
                desired_gap_m: none(telemetry.map(|t| t.desired_gap_m)),
                speed_ref_mps: none(telemetry.map(|t| t.speed_ref_mps)),
                curvature: none(telemetry.map(|t| t.curvature)),
                emergency: telemetry.is_some_and(|t| t.emergency),
                breadcrumbs: data.trail.len() as u32,
                curvature_ahead: none(telemetry.map(|t| t.curvature_ahead)),
                pan_aim_deg: none(telemetry.map(|t| t.pan_aim_rad)).to_degrees(),
                pan_rate_cmd_deg_s: none(telemetry.map(|t| t.pan_rate_cmd_rad_s)).to_degrees(),
            },
            ns,
        );
        ch.truth.log_with_time(
            &GroundTruth {
                frame: r.frame,
                true_cx_px: r.true_cx,
                true_cy_px: r.true_cy,
                true_scale: r.true_scale,
                true_range_m: r.true_range_m,
                true_lateral_m: r.true_lateral_m,
                range_error_m: r.est_range_m - r.true_range_m,
                image_error_px: (r.est_cx - r.true_cx).hypot(r.est_cy - r.true_cy),
                in_view: r.target_in_view,
                partly_out_of_view: r.target_partly_out_of_view,
                lost_truth: r.lost_truth,
                gap_m: r.gap_m,
                lead_speed_mps: r.lead_speed_mps,
                lateral_deviation_m: r.lateral_deviation_m,
                chase_distance_m: r.chase_distance_m,
                collision: r.collision,
                loss_cause: r.loss_cause.as_str().into(),
                camera_pan_deg: r.camera_pan_deg,
            },
            ns,
        );
        self.events(data, ts);
        if let Some(server) = &self.server {
            server.broadcast_time(ns);
        }
    }

    /// Both vehicles, the chase's breadcrumb trail, and a new segment of the lead's driven
    /// path once a second.
    fn scene(&mut self, data: &FrameData, ts: Timestamp) -> SceneUpdate {
        let r = &data.out.record;
        let cube = |centre: NaVector3<f64>, size: [f64; 3], c: Color| CubePrimitive {
            pose: Some(Pose {
                position: Some(vector3(&centre)),
                orientation: Some(Quaternion {
                    x: 0.0,
                    y: 0.0,
                    z: 0.0,
                    w: 1.0,
                }),
            }),
            size: Some(Vector3 {
                x: size[0],
                y: size[1],
                z: size[2],
            }),
            color: Some(c),
        };
        let entity = |frame_id: &str, id: &str| SceneEntity {
            timestamp: Some(ts),
            frame_id: frame_id.into(),
            id: id.into(),
            frame_locked: true,
            ..SceneEntity::default()
        };
        let mut chase_entity = entity("chase", "chase");
        chase_entity.cubes.push(cube(
            self.chase_box.0,
            self.chase_box.1,
            Color {
                r: 0.35,
                g: 0.45,
                b: 0.3,
                a: 0.8,
            },
        ));
        let mut lead_entity = entity("lead", "lead");
        let [l, h, w] = self.lead_box;
        lead_entity.cubes.push(cube(
            NaVector3::new(0.0, 0.5 * h, 0.0),
            [l, h, w],
            Color {
                r: 0.8,
                g: 0.8,
                b: 0.85,
                a: 0.8,
            },
        ));
        let line = |pts: Vec<Point3>, c: Color, thickness: f64| LinePrimitive {
            r#type: foxglove::messages::line_primitive::Type::LineStrip as i32,
            pose: None,
            thickness,
            scale_invariant: true,
            points: pts,
            color: Some(c),
            ..LinePrimitive::default()
        };
        let mut crumbs = entity("world", "breadcrumbs");
        crumbs.frame_locked = false;
        let trail: Vec<Point3> = data
            .trail
            .iter()
            .map(|p| Point3 {
                x: f64::from(p.x),
                y: f64::from(p.y) + 0.05,
                z: f64::from(p.z),
            })
            .collect();
        crumbs.lines.push(line(
            trail,
            Color {
                r: 1.0,
                g: 0.6,
                b: 0.0,
                a: 1.0,
            },
            3.0,
        ));
        // A run without a lead has neither its box nor its path.
        let has_lead = r.lead_xz[0].is_finite();
        let mut entities = vec![chase_entity];
        entities.extend(has_lead.then_some(lead_entity));
        entities.push(crumbs);
        entities.extend(actor_entities(r, ts));
        if has_lead {
            self.path.push(r.lead_xz);
        }
        if has_lead && r.frame % PATH_SEGMENT_FRAMES == PATH_SEGMENT_FRAMES - 1 {
            let mut segment = entity(
                "world",
                &format!("lead-path-{}", r.frame / PATH_SEGMENT_FRAMES),
            );
            segment.frame_locked = false;
            let pts = self
                .path
                .iter()
                .map(|[x, z]| Point3 {
                    x: *x,
                    y: 0.02,
                    z: *z,
                })
                .collect();
            segment.lines.push(line(
                pts,
                Color {
                    r: 0.2,
                    g: 0.5,
                    b: 1.0,
                    a: 1.0,
                },
                2.0,
            ));
            entities.push(segment);
            // The next segment starts where this one ends.
            let last = *self.path.last().expect("a point was just pushed");
            self.path.clear();
            self.path.push(last);
        }
        // At the first frame, clear what an earlier run left in a live viewer.
        let deletions = if r.frame == 0 {
            vec![SceneEntityDeletion {
                timestamp: Some(ts),
                r#type: scene_entity_deletion::Type::All as i32,
                id: String::new(),
            }]
        } else {
            Vec::new()
        };
        SceneUpdate {
            deletions,
            entities,
        }
    }

    /// Logs what happened this frame: the tracker's status changes and (re)acquisitions, a
    /// loss and its end by the ground truth, and the chase controller's events.
    fn events(&mut self, data: &FrameData, ts: Timestamp) {
        let r = &data.out.record;
        let mut lines: Vec<(foxglove::messages::log::Level, String)> = Vec::new();
        use foxglove::messages::log::Level;
        if self.last_status.is_some_and(|s| s != r.status)
            || (self.last_status.is_none() && r.status != TrackerStatus::Tracking)
        {
            let level = if r.status == TrackerStatus::Tracking {
                Level::Info
            } else {
                Level::Warning
            };
            lines.push((level, format!("tracker: {}", r.status.as_str())));
        }
        self.last_status = Some(r.status);
        if !r.tracker_event.is_empty() {
            lines.push((Level::Info, format!("tracker: {}", r.tracker_event)));
        }
        if r.lost_truth != self.last_lost_truth {
            lines.push(if r.lost_truth {
                (
                    Level::Error,
                    format!(
                        "loss: the estimate is off the target (ground truth; tracker says {})",
                        r.status.as_str()
                    ),
                )
            } else {
                (
                    Level::Info,
                    "loss over: the estimate is on the target again (ground truth)".into(),
                )
            });
            self.last_lost_truth = r.lost_truth;
        }
        if r.collision && !self.last_collision {
            lines.push((Level::Error, "collision".into()));
        }
        if let Some(t) = &r.traffic {
            for e in &t.events {
                lines.push((Level::Info, format!("traffic: {e}")));
            }
            for c in &t.contacts {
                lines.push((
                    Level::Error,
                    format!(
                        "contact: the chase touched `{}` at {:.2} s, closing at {:.1} km/h",
                        c.vehicle,
                        c.t_s,
                        3.6 * c.closing_mps
                    ),
                ));
            }
        }
        self.last_collision = r.collision;
        for e in &data.controller_events {
            lines.push((Level::Warning, e.clone()));
        }
        for (level, message) in lines {
            self.log(level, message, ts, "frame", r.frame);
        }
    }

    fn log(
        &self,
        level: foxglove::messages::log::Level,
        message: String,
        ts: Timestamp,
        name: &str,
        frame: u64,
    ) {
        self.channels.events.log_with_time(
            &Log {
                timestamp: Some(ts),
                level: level as i32,
                message,
                name: name.into(),
                file: String::new(),
                line: frame as u32,
            },
            self.last_log_time,
        );
    }

    /// Logs the run's failed criteria and verdict, if it completed, at the last frame's
    /// time; stops the live view; closes the file.
    fn finish(self, verdict: Option<(Vec<String>, String)>) -> Result<(), RecordError> {
        use foxglove::messages::log::Level;
        let ts = timestamp(self.last_log_time);
        if let Some((failures, line)) = verdict {
            for failure in failures {
                self.log(
                    Level::Error,
                    format!("criterion failed: {failure}"),
                    ts,
                    "expect",
                    0,
                );
            }
            self.log(Level::Info, line, ts, "expect", 0);
        }
        if let Some(server) = self.server {
            let _ = server.stop();
        }
        let Some((path, handle)) = self.mcap else {
            return Ok(());
        };
        let closed = handle.close();
        drop(self.context);
        let file_err = |message: String| RecordError::File {
            path: path.clone(),
            message,
        };
        let mut writer = closed.map_err(|e| file_err(e.to_string()))?;
        std::io::Write::flush(&mut writer).map_err(|e| file_err(e.to_string()))?;
        Ok(())
    }
}

/// The traffic's actors as boxes in the world (a run with traffic; none otherwise), each
/// its kind's drawn size at its body's centre, turned to its heading.
fn actor_entities(r: &sim_core::FrameRecord, ts: Timestamp) -> Vec<SceneEntity> {
    let Some(t) = &r.traffic else {
        return Vec::new();
    };
    // The chase and the lead are no actor kind.
    t.vehicles
        .iter()
        .skip(1)
        .filter_map(|v| {
            let kind = sim_render::VehicleKind::ALL
                .into_iter()
                .find(|k| k.as_str() == v.kind)?;
            let (length, width, height) = kind.dimensions();
            let centre = f64::from(sim_core::kind_params(kind).body_centre_x_m());
            let (s, c) = v.heading_rad.sin_cos();
            let (hs, hc) = (0.5 * v.heading_rad).sin_cos();
            Some(SceneEntity {
                timestamp: Some(ts),
                frame_id: "world".into(),
                id: format!("actor-{}", v.name),
                cubes: vec![CubePrimitive {
                    pose: Some(Pose {
                        position: Some(Vector3 {
                            x: v.xz[0] + centre * c,
                            y: 0.5 * height,
                            z: v.xz[1] - centre * s,
                        }),
                        orientation: Some(Quaternion {
                            x: 0.0,
                            y: hs,
                            z: 0.0,
                            w: hc,
                        }),
                    }),
                    size: Some(Vector3 {
                        x: length,
                        y: height,
                        z: width,
                    }),
                    color: Some(Color {
                        r: 0.3,
                        g: 0.5,
                        b: 0.9,
                        a: 0.8,
                    }),
                }],
                ..SceneEntity::default()
            })
        })
        .collect()
}
