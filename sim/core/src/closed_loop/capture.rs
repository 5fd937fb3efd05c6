//! A frame's capture (the world at its start, and the camera's input for it), and the
//! small helpers each step uses.

use super::drive::Drive;
use crate::auto_gain::AutoGainControl;
use crate::plan::iso;
use crate::plugin::LaneAhead;
use nalgebra::Isometry3;
use sim_render::{Braking, CameraRig, Field, FrameInput};
use std::time::{Duration, Instant};
use vehicle::{DelayLine, Pose, Step, VehicleState, STEPS_PER_FRAME};

/// The world at the start of a frame, and the camera's input for it.
pub(super) struct Captured {
    pub(super) now: Step,
    pub(super) chase: VehicleState,
    /// The lead's state (none in a run without a lead).
    pub(super) lead: Option<VehicleState>,
    pub(super) input: FrameInput,
    /// Every vehicle's state, in the traffic's list order (`None` without traffic).
    pub(super) traffic: Option<Vec<VehicleState>>,
    /// The pan head's encoder reading at capture, radians (0 without one).
    pub(super) pan_reading_rad: f64,
    /// The camera in the world (panned by the head's true angle).
    pub(super) world_from_camera: Isometry3<f64>,
    /// The chase's lane ahead in the camera's frame, for the tracker (`None` without
    /// traffic).
    pub(super) lane: Option<LaneAhead>,
}

impl Captured {
    /// The world of `drive` at the start of a frame, seen from `rig`.
    pub(super) fn of(
        drive: &Drive,
        rig: &CameraRig,
        lead_from_scene: &Isometry3<f64>,
        auto_gain: &AutoGainControl,
    ) -> Captured {
        let now = drive.world.now();
        debug_assert!(now.is_frame_start());
        let chase = drive.world.vehicle_state(drive.chase_id);
        // Without a lead, nothing of it is drawn or read: it stands still at the origin.
        let lead = drive.lead_id.map(|id| drive.world.vehicle_state(id));
        let frame_index = now.0 / u64::from(STEPS_PER_FRAME);
        let traffic = drive.traffic.as_ref().map(|t| t.states(&drive.world));
        let (world_from_actors, actors) = match (&drive.traffic, &traffic) {
            (Some(t), Some(states)) => (t.actor_poses(states), t.actor_states(states)),
            _ => (Vec::new(), &[][..]),
        };
        let input = FrameInput {
            frame_index,
            time_s: now.seconds(),
            world_from_chase: iso(&chase.world_from_vehicle),
            world_from_lead: lead.as_ref().map_or(*lead_from_scene, |l| {
                iso(&l.world_from_vehicle) * lead_from_scene
            }),
            world_from_actors,
            camera_pan_rad: drive.pan_angle_rad(),
            auto_gain: auto_gain.gain_for(frame_index),
            // The lead's and the actors' brake actuators.
            braking: Braking::of(
                lead.as_ref().map_or(0.0, |l| f64::from(l.brake)),
                actors.iter().map(|s| f64::from(s.brake)),
            ),
            // Before the first frame the world stood still.
            earlier_field: drive.interlaced.then(|| {
                let f = drive
                    .earlier_field
                    .clone()
                    .unwrap_or_else(|| drive.field_now());
                Field {
                    world_from_lead: f.world_from_lead * lead_from_scene,
                    ..f
                }
            }),
            chase_speed_mps: f64::from(chase.forward_speed_mps),
            lead_speed_mps: lead
                .as_ref()
                .map_or(0.0, |l| f64::from(l.forward_speed_mps)),
            actor_speeds_mps: actors
                .iter()
                .map(|s| f64::from(s.forward_speed_mps))
                .collect(),
        };
        let world_from_camera =
            rig.world_from_camera_panned(&input.world_from_chase, input.camera_pan_rad);
        let lane = drive
            .traffic
            .as_ref()
            .map(|t| t.lane_ahead(&chase, &world_from_camera));
        Captured {
            now,
            lane,
            chase,
            lead,
            input,
            traffic,
            pan_reading_rad: drive.pan_reading_rad(),
            world_from_camera,
        }
    }
}

/// A frame submitted but not yet tracked: rendering on this process's render thread
/// (`here`) or in the worker.
pub(super) struct InFlight {
    pub(super) captured: Captured,
    pub(super) here: bool,
}

/// Why this process's renderer must be at hand: only frames in flight take it away.
pub(super) const HERE: &str = "this process's renderer is here when no frame of its is in flight";

/// Whether no estimate through `delay` reaches the controller sooner than a frame after
/// its capture, so that the physics to the next frame needs none from this one.
pub(super) fn renders_ahead<T>(delay: &DelayLine<T>) -> bool {
    delay.min_latency_steps() >= u64::from(STEPS_PER_FRAME)
}

/// Runs `f`, adding its wall-clock time to `spent`.
pub(super) fn timed<T>(spent: &mut Duration, f: impl FnOnce() -> T) -> T {
    let started = Instant::now();
    let out = f();
    *spent += started.elapsed();
    out
}

pub(super) fn xz(p: &Pose) -> [f64; 2] {
    [f64::from(p.translation.x), f64::from(p.translation.z)]
}
