//! The physics side of the loop: both vehicles, their drivers and the delay line between
//! the tracker and the chase controller, stepped eight 120 Hz steps to each camera frame.

use super::traffic_drive::TrafficDrive;
use crate::delayed::Delayed;
use crate::plan::iso;
use crate::plugin::{ControlInput, Controller, Delivered, Estimate, EstimateStatus, PluginError};
use nalgebra::Isometry3;
use sim_render::Field;
use vehicle::{
    ChaseController, Controls, DelayLine, LeadDriver, LeadEstimate, PanHead, Step, TrackStatus,
    Vector, VehicleId, World, STEPS_PER_FRAME,
};

/// The chase's controller, through the plug-in trait whatever it is (the built-in
/// [`crate::BuiltinController`] or anyone's), and what it has heard.
pub(super) struct Chase {
    pub(super) controller: Box<dyn Controller>,
    /// The latest estimate delivered, by capture time.
    latest: Option<Delayed>,
    /// Why it failed, and at which step; the physics stops there.
    pub(super) failed: Option<(Step, PluginError)>,
}

impl Chase {
    pub(super) fn new(controller: Box<dyn Controller>) -> Chase {
        Chase {
            controller,
            latest: None,
            failed: None,
        }
    }
}

/// A physics step's commands from the controller: the vehicle's controls and the pan
/// head's rate.
fn commands(
    p: &mut Chase,
    delivered: Vec<Delayed>,
    step: Step,
    chase: &vehicle::VehicleState,
    pan_reading_rad: f64,
) -> Result<(Controls, f64), PluginError> {
    let fresh = !delivered.is_empty();
    for d in delivered {
        let [x, y, z] = d.lead.target_in_camera_m.into();
        p.controller.receive(&Delivered {
            estimate: d.estimate,
            position_m: [x, y, z].map(f64::from),
            captured_t_s: d.lead.capture_step.seconds(),
            captured_pan_rad: f64::from(d.lead.camera_pan_rad),
        });
        if p.latest
            .is_none_or(|l| l.lead.capture_step <= d.lead.capture_step)
        {
            p.latest = Some(d);
        }
    }
    let input = ControlInput {
        estimate: p.latest.map(|d| d.estimate),
        fresh,
        captured_t_s: p.latest.map(|d| d.lead.capture_step.seconds()),
        captured_pan_rad: p.latest.map(|d| f64::from(d.lead.camera_pan_rad)),
        t_s: step.seconds(),
        world_from_chase: chase.world_from_vehicle,
        speed_mps: f64::from(chase.forward_speed_mps),
        // The vehicle's angles turn positive to the left (ISO 8855); the plug-ins' to the
        // right, as the estimate's lateral offset and the pan head's angle do.
        yaw_rate_rad_s: -f64::from(chase.yaw_rate_radps),
        steering_rad: -f64::from(chase.steer_rad),
        pan_rad: pan_reading_rad,
    };
    let command = p.controller.control(&input)?;
    command.validate()?;
    Ok((
        Controls {
            steer_rad: -command.steering_rad as f32,
            throttle: command.throttle as f32,
            brake: command.brake as f32,
        },
        command.pan_rate_rad_s,
    ))
}

/// The physics side of the loop: both vehicles, their drivers and the delay line between
/// the tracker and the chase controller.
pub(super) struct Drive {
    pub(super) world: World,
    pub(super) chase_id: VehicleId,
    /// The lead's physics and driver (none in a run without a lead).
    pub(super) lead_id: Option<VehicleId>,
    pub(super) chase: Chase,
    pub(super) lead: Option<LeadDriver>,
    pub(super) delay: DelayLine<Delayed>,
    /// The camera's pan head, when the scenario has one (`[camera.pan]`).
    pub(super) pan: Option<PanHead>,
    /// With an interlaced camera, the world one field period before the next frame
    /// (its earlier field, the lead's pose that of its vehicle frame, not yet the scene's;
    /// `Some` once the first frame's physics has run).
    pub(super) interlaced: bool,
    pub(super) earlier_field: Option<Field>,
    /// The steps of the physics to the next frame run so far (see
    /// [`Drive::advance_before`]).
    pub(super) ahead: Option<FrameSteps>,
    /// The step at which the lead came within [`ROAD_END_M`] of its route's end, where its
    /// driver stops it.
    pub(super) lead_at_road_end: Option<Step>,
    /// The other vehicles and the events, when the scenario has traffic.
    pub(super) traffic: Option<TrafficDrive>,
}

/// How near its route's end the lead counts as having reached it, m: its driver stops it
/// 2 m before (as a road end trigger counts a vehicle there).
const ROAD_END_M: f32 = vehicle::ROAD_END_M as f32;

/// The steps of one frame's physics run so far, and what they did.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct FrameSteps {
    pub(super) steps: u64,
    pub(super) controls: vehicle::Controls,
    pub(super) collision: bool,
}

impl Drive {
    /// The controllers and the physics, eight steps to the next frame (the rest of them,
    /// when [`Drive::advance_before`] has run some already). Returns the chase's last
    /// controls and whether the vehicles touched.
    pub(super) fn advance_frame(&mut self) -> Driven {
        self.advance_steps(None);
        let ahead = self.ahead.take().expect("the frame's steps have run");
        let traffic_log = self.traffic.as_mut().map(TrafficDrive::take_log);
        let (chase_mode, desired_gap_m) = match self.builtin() {
            Some(c) => (Some(c.mode()), c.telemetry().desired_gap_m),
            None => (None, f32::NAN),
        };
        Driven {
            controls: ahead.controls,
            collision: ahead.collision,
            chase_mode,
            desired_gap_m,
            traffic_log,
        }
    }

    /// Runs the steps of the physics to the next frame that come before step `due` (the
    /// earliest an estimate not yet queued can be due), without completing the frame: what
    /// they do depends on no estimate still to come, so they may run while the frames whose
    /// estimates those are are still being rendered and tracked. [`Drive::advance_frame`]
    /// runs the rest; the outcome is the same, step for step, as running them all then.
    pub(super) fn advance_before(&mut self, due: Step) {
        self.advance_steps(Some(due));
    }

    /// The frame's steps not yet run, or those before `until`.
    pub(super) fn advance_steps(&mut self, until: Option<Step>) {
        let mut ahead = self.ahead.take().unwrap_or_default();
        while ahead.steps < u64::from(STEPS_PER_FRAME) {
            let step_now: Step = self.world.now();
            if until.is_some_and(|until| step_now >= until) {
                break;
            }
            if self.interlaced
                && ahead.steps == u64::from(STEPS_PER_FRAME) - sim_render::FIELD_PERIOD_STEPS
            {
                self.earlier_field = Some(self.field_now());
            }
            let delivered = self.delay.pop_due(step_now);
            let chase = self.world.vehicle_state(self.chase_id);
            let lead = self.lead_id.map(|id| self.world.vehicle_state(id));
            let pan_reading_rad = self.pan_reading_rad();
            if self.chase.failed.is_some() {
                break;
            }
            let pan_rate_rad_s = match commands(
                &mut self.chase,
                delivered,
                step_now,
                &chase,
                pan_reading_rad,
            ) {
                Ok((controls, pan_rate)) => {
                    ahead.controls = controls;
                    pan_rate
                }
                Err(e) => {
                    // The run ends here: nothing more is stepped.
                    self.chase.failed = Some((step_now, e));
                    break;
                }
            };
            if let Some(pan) = &mut self.pan {
                pan.step(pan_rate_rad_s);
            }
            let lead_and_state = self.lead.as_mut().zip(lead.as_ref());
            let lead_controls = match &mut self.traffic {
                None => lead_and_state.map(|(l, state)| l.update(step_now, state)),
                Some(t) => t.drive(&mut self.world, lead_and_state, step_now),
            };
            if let Some(l) = &self.lead {
                if self.lead_at_road_end.is_none()
                    && l.progress_m() >= l.route().length_m() - ROAD_END_M
                {
                    self.lead_at_road_end = Some(step_now);
                }
            }
            self.world.set_controls(self.chase_id, ahead.controls);
            if let (Some(id), Some(controls)) = (self.lead_id, lead_controls) {
                self.world.set_controls(id, controls);
            }
            self.world.step();
            ahead.collision |= match (&mut self.traffic, self.lead_id) {
                (Some(t), _) => t.touching(&self.world),
                (None, Some(lead)) => self.world.vehicles_touch(self.chase_id, lead),
                (None, None) => false,
            };
            ahead.steps += 1;
        }
        self.ahead = Some(ahead);
    }

    /// The earliest step at which the estimate of frame `frame_index` (not yet queued) can
    /// fall due.
    pub(super) fn earliest_due(&self, frame_index: u64) -> Step {
        Step(frame_index * u64::from(STEPS_PER_FRAME) + self.delay.min_latency_steps())
    }

    /// The world now, as an interlaced frame's earlier field sees it.
    pub(super) fn field_now(&self) -> Field {
        Field {
            time_s: self.world.now().seconds(),
            world_from_chase: iso(&self.world.vehicle_state(self.chase_id).world_from_vehicle),
            world_from_lead: self.lead_id.map_or(Isometry3::identity(), |id| {
                iso(&self.world.vehicle_state(id).world_from_vehicle)
            }),
            world_from_actors: self.actor_poses(),
            camera_pan_rad: self.pan_angle_rad(),
        }
    }

    /// The actors' poses now, as the renderer draws them (none without traffic).
    pub(super) fn actor_poses(&self) -> Vec<nalgebra::Isometry3<f64>> {
        self.traffic
            .as_ref()
            .map_or_else(Vec::new, |t| t.actor_poses(&t.states(&self.world)))
    }

    /// The pan head's true angle, radians (0 without one).
    pub(super) fn pan_angle_rad(&self) -> f64 {
        self.pan.as_ref().map_or(0.0, PanHead::angle_rad)
    }

    /// The pan head's encoder reading, radians (0 without one).
    pub(super) fn pan_reading_rad(&self) -> f64 {
        self.pan.as_ref().map_or(0.0, PanHead::reading_rad)
    }

    /// Queues the tracker's estimate of a frame captured at `captured`, when the pan head's
    /// encoder read `pan_reading_rad`; `position_m` is where it puts the target in the
    /// camera frame.
    pub(super) fn push_estimate(
        &mut self,
        captured: Step,
        estimate: Estimate,
        position_m: [f64; 3],
        pan_reading_rad: f64,
    ) {
        let [x, y, z] = position_m;
        let status = match estimate.status {
            EstimateStatus::Tracking => TrackStatus::Tracking,
            EstimateStatus::Coasting => TrackStatus::Coasting,
            EstimateStatus::Lost => TrackStatus::Lost,
        };
        let lead = LeadEstimate {
            capture_step: captured,
            target_in_camera_m: Vector::new(x as f32, y as f32, z as f32),
            status,
            camera_pan_rad: pan_reading_rad as f32,
        };
        self.delay.push(captured, Delayed { lead, estimate });
    }

    /// The built-in controller's state, when it drives.
    pub(super) fn builtin(&self) -> Option<&ChaseController> {
        self.chase.controller.chase_controller()
    }

    /// The controller's failure, which ends the run.
    pub(super) fn take_failure(&mut self) -> Option<(Step, PluginError)> {
        self.chase.failed.take()
    }
}

/// What the physics from a frame to the next leaves for the frame's record: the last
/// controls, whether the vehicles touched, and the chase controller's mode and desired gap
/// at its end (taken then: with two frames in flight the physics runs on before the
/// record is made), and the traffic's events and contacts in it.
#[derive(Clone, Debug)]
pub(super) struct Driven {
    pub(super) controls: vehicle::Controls,
    pub(super) collision: bool,
    /// The built-in controller's mode (`None` for another).
    pub(super) chase_mode: Option<vehicle::ChaseMode>,
    /// The built-in controller's desired gap (NaN for another).
    pub(super) desired_gap_m: f32,
    /// The traffic's events and the chase's contacts in these steps (`None` without
    /// traffic).
    pub(super) traffic_log: Option<(Vec<String>, Vec<crate::record::Contact>)>,
}
