//! # vehicle: the physics and the drivers of the car-following loop
//!
//! Two rapier3d ray-cast vehicles on a flat ground (optionally gently bumpy, optionally
//! rising and falling with a road's [`GroundProfile`]), stepped at a fixed 120 Hz
//! ([`World`]): an HMMWV M998-class chase vehicle and a pickup lead ([`VehicleParams`]),
//! each with rate-limited, lagging actuators ([`Actuator`]).
//!
//! - The **lead driver** ([`LeadDriver`]) follows a [`Route`] by pure pursuit on ground truth,
//!   at a scripted [`SpeedProfile`], slowing for turns and optionally weaving.
//! - The **chase controller** ([`ChaseController`]) sees only the tracker's delayed 3-D
//!   estimates of the lead ([`LeadEstimate`], camera frame) and its own [`Odometry`]. It
//!   turns each estimate into a breadcrumb of the lead's path through its own pose at the
//!   frame's capture time, steers by pure pursuit on the breadcrumbs, keeps the gap
//!   ([`GapKeeper`]) or replays a scripted speed ([`SpeedMode::Manual`]), and brakes to a
//!   stop when the lead is lost ([`ControllerEvent`]). With lane keeping it steers along its
//!   own lane ([`ChaseController::set_lane`]), follows only a target in it and otherwise
//!   cruises ([`ChaseMode::Cruising`]).
//! - The **traffic** ([`ActorDriver`]): other vehicles ([`VehicleParams::sedan`],
//!   [`VehicleParams::truck`], …) driven like the lead, each scripted by events
//!   ([`EventScript`]: a trigger on time, distance, gap, time gap, time to collision or
//!   another event; a lane change, a speed change or a stop) that [`Events`] runs at every
//!   step against a [`TrafficView`].
//! - The **delay line** ([`DelayLine`]) holds each estimate for the latency (128 ms by
//!   default), to the physics step, with optional seeded jitter and drops.
//!
//! ## Invariants
//! - No rendering, no tracker types, no files or TOML: estimates are plain positions with a
//!   capture step. Configs derive serde so `sim` can embed them in its scenario files.
//! - One clock: [`Step`] counts physics steps; seconds are computed from it.
//! - Frames: world right-handed, y up, ground at y = 0; vehicle x forward, y up, z right,
//!   origin at the middle of the rear axle on the ground; camera x right, y down, z forward.
//!   Transforms are named `a_from_b`.
//! - Deterministic: fixed steps, no hash-map iteration, randomness only from seeded named
//!   streams ([`named_stream`]).
//!
//! ## One physics step, as `sim` runs it
//! ```no_run
//! # use vehicle::*;
//! # fn run(world: &mut World, chase_id: VehicleId, lead_id: VehicleId,
//! #        chase: &mut ChaseController, lead: &mut LeadDriver,
//! #        delay: &mut DelayLine<LeadEstimate>) {
//! let now = world.now();
//! for estimate in delay.pop_due(now) {
//!     chase.receive(estimate);
//! }
//! let chase_state = world.vehicle_state(chase_id);
//! let odometry = Odometry {
//!     step: now,
//!     world_from_chase: chase_state.world_from_vehicle,
//!     forward_speed_mps: chase_state.forward_speed_mps,
//!     camera_pan_rad: 0.0, // the pan head's encoder reading, if there is one
//! };
//! world.set_controls(chase_id, chase.update(&odometry));
//! world.set_controls(lead_id, lead.update(now, &world.vehicle_state(lead_id)));
//! world.step();
//! # }
//! ```
//! At every frame start (`now.is_frame_start()`) `sim` renders, runs the tracker and pushes
//! its estimate with `delay.push(now, estimate)` before the lines above.

#![warn(missing_docs)]

mod actor_driver;
mod actuator;
mod breadcrumb_trail;
mod camera_mount;
mod chase_controller;
mod clock;
mod controller_event;
mod controls;
mod delay_line;
mod error;
mod event_spec;
mod events;
mod gap_keeper;
mod ground;
mod ground_profile;
mod gyro;
mod lead_driver;
mod lead_estimate;
mod pan_head;
mod pose_history;
mod pure_pursuit;
mod range_filter;
mod ray_cast_vehicle;
mod rng_stream;
mod route;
mod speed_controller;
mod speed_profile;
mod vehicle_params;
mod world;

pub use actor_driver::ActorDriver;
pub use actuator::{Actuator, ActuatorLimits};
pub use breadcrumb_trail::{Breadcrumb, BreadcrumbTrail};
pub use camera_mount::CameraMount;
pub use chase_controller::{
    ChaseController, ChaseControllerConfig, ChaseMode, ChaseTelemetry, Odometry, SpeedMode,
    LANE_MARGIN_M, LEFT_LANE_ARRIVALS, MAX_HALF_FOV_DEG, MIN_HALF_FOV_DEG,
};
pub use clock::{
    ms_from_steps, steps_from_ms, Step, CAMERA_HZ, PHYSICS_DT_S, PHYSICS_HZ, STEPS_PER_FRAME,
};
pub use controller_event::{ControllerEvent, ControllerEventKind};
pub use controls::Controls;
pub use delay_line::{DelayLine, DelayLineConfig};
pub use error::VehicleError;
pub use event_spec::{
    ActionSpec, EventScript, EventSpec, KeepSide, KeepSpec, ProfileEntry, ReachSpec, Rule, Shape,
    TriggerSpec, EQUAL_TOLERANCE, KEEP_GAIN_PER_S, KEEP_LAG_S, KEEP_MAX_ACCEL_MPS2,
    KEEP_MAX_DECEL_MPS2, KEEP_REACHED_M, KEEP_REACHED_MPS, MAX_LANES, MAX_PROFILE_ENTRIES,
    MAX_TRIGGER_DEPTH, MAX_TRIGGER_GROUPS,
};
pub use events::{
    Events, Fired, FiredKind, Lanes, TrafficView, VehicleView, ROAD_END_M, STANDSTILL_MPS,
};
pub use gap_keeper::{GapKeeper, GapKeeperConfig, GapPolicy, SpeedCommand, Threat};
pub use ground::{BumpsConfig, Ground, GroundConfig, GroundGrid};
pub use ground_profile::{GroundProfile, MAX_PROFILE_GRID_POINTS};
pub use gyro::{Gyro, GyroConfig};
pub use lead_driver::{LeadDriver, LeadDriverConfig, SpeedOverride};
pub use lead_estimate::{LeadEstimate, TrackStatus};
pub use pan_head::{PanHead, PanHeadConfig};
pub use pose_history::{OwnMotion, PoseHistory};
pub use pure_pursuit::{
    curvature_to, curvature_toward, lookahead_point, steer_for_curvature, LookAhead,
};
pub use range_filter::{Gains, RangeFilter, RangeGate, RangeState};
pub use ray_cast_vehicle::{Vehicle, VehicleState};
pub use rng_stream::{fnv1a64, named_stream};
pub use route::{
    direction_heading, heading_direction, CurvatureWalk, Route, RouteBuilder, RouteProjection,
};
pub use speed_controller::{Pedals, SpeedController, SpeedGains};
pub use speed_profile::{ProfileBasis, SpeedKnot, SpeedProfile, MAX_SPEED_MPS};
pub use vehicle_params::{VehicleParams, AIR_DENSITY_KGPM3, GRAVITY_MPS2};
pub use world::{VehicleId, World, WorldConfig};

/// The maths types used in this crate's interface (rapier's glam types, f32).
pub use rapier3d::math::{Pose, Rotation, Vector};
