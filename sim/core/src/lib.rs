//! carfollow's loop as a library: scenario files and their validation, the plan of a run,
//! and the closed loop that runs it, one camera frame at a time, with the record of every
//! frame.
//!
//! The layers, each using only those before it:
//! 1. [`Scenario`]: a scenario file (or text) parsed, `--set` overrides applied, every field
//!    checked against its documented bounds; its target model ([`load_target`]).
//! 2. [`Plan`]: everything the scenario decides before the first frame, built once (the
//!    drivers' route, the physics world with both vehicles at their start, the
//!    controllers, the scene, the camera rig and the first view). `check`, a sweep's
//!    pre-flight and `run` all build it, so what checks, runs.
//! 3. [`ClosedLoop`]: the plan run frame by frame (the camera renders, the tracker
//!    tracks, the estimate goes through the delay line to the controllers, the physics
//!    steps), one [`FrameRecord`] of truth against estimate per frame.
//!
//! It depends on `sim-render` (the camera world), `tracker` and `vehicle`; it writes no
//! files and prints nothing (the reports, recordings and the command line are `sim`'s).
#![warn(missing_docs)]

mod auto_gain;
mod child;
mod closed_loop;
mod delayed;
mod driven_path;
mod frame_parts;
pub mod opendrive;
pub mod openscenario;
mod plan;
mod plugin;
mod record;
mod render_thread;
mod render_worker;
mod scenario;
mod target;
mod traffic;

pub use child::{Child, RASTER_THREADS_ENV};
pub use closed_loop::{
    ClosedLoop, FrameOutput, FramePoses, LoopError, LoopOptions, LoopTiming, RunEnd,
};
pub use driven_path::DrivenPath;
pub use plan::{lead_body_size_m, planning_key, render_options, Plan};
pub use plugin::{
    BuiltinController, BuiltinTracker, CameraModel, Command, ControlInput, Controller,
    ControllerChoice, Delivered, Drawn, Estimate, EstimateStatus, FrameTracker, LaneAhead,
    PluginError, StepDetails, TrackerChoice, TrackerInput,
};
pub use record::{Contact, FrameRecord, LossCause, TrackerStatus, TrafficFrame, VehicleTruth};
pub use render_worker::{fingerprint, receive_scene, send_scene, serve_frames};
pub use scenario::MAX_ACTORS;
pub use scenario::{
    apply_override, from_toml_naming_field, kind_albedo, kind_params, locate as locate_field,
    scenario_schema_json, shipped_scenarios, ActorFile, ActorSpec, AutoGainFile, CameraFile,
    ChaseFile, ClutterFile, DistractorFile, EnvironmentFile, Expect, HeadlampsFile, LeadFile,
    LoopFile, OverpassFile, RoadFile, RouteFile, Scenario, ScenarioError, ScenarioFile,
    ScenarioSpec, SegmentFile, SensorFile, StartFile, SunFile, TexturesFile, TrackerFile,
    BUILTIN_NAME, BUILTIN_TARGET_TEXT, FOCAL_LENGTH_MM, MAX_ARC_RADIUS_M, MAX_BLUR_SIGMA_PX,
    MAX_BREADCRUMBS, MAX_GRADE, MAX_HEIGHT_M, MAX_INITIAL_GAP_M, MAX_INIT_OFFSET_PX,
    MAX_PLACED_GAP_M, MAX_ROUTE_M, MAX_STEP_M, MIN_ARC_RADIUS_M, SCHEMA_FILE_NAME,
};
pub use target::{
    line_column, load as load_target, parse as parse_target, to_file_text as target_file_text,
    TargetFileError, MAX_CORNER_M, NOMINAL_RANGE_M,
};
pub use traffic::{Member, Place, Role, Vehicles};
