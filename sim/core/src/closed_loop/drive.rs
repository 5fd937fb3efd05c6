//! The physics side of the loop: both vehicles, their drivers and the delay line between
//! the tracker and the chase controller, stepped eight 120 Hz steps to each camera frame.

use super::iso;
use sim_render::Field;
use tracker::TrackOutput;
use vehicle::{
    ChaseController, DelayLine, LeadDriver, LeadEstimate, Odometry, PanHead, Step, TrackStatus,
    Vector, VehicleId, World, STEPS_PER_FRAME,
};

/// The physics side of the loop: both vehicles, their drivers and the delay line between
/// the tracker and the chase controller.
pub(super) struct Drive {
    pub(super) world: World,
    pub(super) chase_id: VehicleId,
    pub(super) lead_id: VehicleId,
    pub(super) chase: ChaseController,
    pub(super) lead: LeadDriver,
    pub(super) delay: DelayLine<LeadEstimate>,
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
}

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
    pub(super) fn earliest_due(&self, frame_index: u64) -> Step {
        Step(frame_index * u64::from(STEPS_PER_FRAME) + self.delay.min_latency_steps())
    }

    /// The world now, as an interlaced frame's earlier field sees it.
    pub(super) fn field_now(&self) -> Field {
        Field {
            time_s: self.world.now().seconds(),
            world_from_chase: iso(&self.world.vehicle_state(self.chase_id).world_from_vehicle),
            world_from_lead: iso(&self.world.vehicle_state(self.lead_id).world_from_vehicle),
            camera_pan_rad: self.pan_angle_rad(),
        }
    }

    /// The pan head's true angle, radians (0 without one).
    pub(super) fn pan_angle_rad(&self) -> f64 {
        self.pan.as_ref().map_or(0.0, PanHead::angle_rad)
    }

    /// The pan head's encoder reading, radians (0 without one).
    pub(super) fn pan_reading_rad(&self) -> f64 {
        self.pan.as_ref().map_or(0.0, PanHead::reading_rad)
    }

    /// Queues the tracker's output for a frame captured at `captured`, when the pan head's
    /// encoder read `pan_reading_rad`.
    pub(super) fn push_estimate(
        &mut self,
        captured: Step,
        track: &TrackOutput,
        pan_reading_rad: f64,
    ) {
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

/// What the physics from a frame to the next leaves for the frame's record: the last
/// controls, whether the vehicles touched, and the chase controller's mode and desired gap
/// at its end (taken then: with two frames in flight the physics runs on before the
/// record is made).
#[derive(Clone, Copy, Debug)]
pub(super) struct Driven {
    pub(super) controls: vehicle::Controls,
    pub(super) collision: bool,
    pub(super) chase_mode: vehicle::ChaseMode,
    pub(super) desired_gap_m: f32,
}
