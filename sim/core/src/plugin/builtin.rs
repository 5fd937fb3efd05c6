//! The built-in tracker and controller behind the plug-in traits: the paper's tracker
//! (either mode) as a [`FrameTracker`], the built-in chase controller as a [`Controller`].
//! The loop runs them as it runs any plug-in; they are as much for whoever wants them as
//! plug-ins: a comparison, a wrapper in Python, a controller of one's own over the paper's
//! tracker.

use super::{
    CameraModel, Command, ControlInput, Controller, Delivered, Drawn, Estimate, EstimateStatus,
    FrameTracker, PluginError, StepDetails, TrackerInput,
};
use tracker::{
    EdgeDiagnostic, EgoMotion, Location, PixelRect, TrackOutput, Tracker, TrackerConfig,
    TrackerMode,
};
use vehicle::{
    ChaseController, ChaseControllerConfig, LeadEstimate, Odometry, Step, TrackStatus, Vector,
    VehicleParams,
};

/// The paper's tracker (stages 1–8), in the mode its settings give, as a plug-in.
pub struct BuiltinTracker {
    config: TrackerConfig,
    tracker: Option<Tracker>,
    last: Option<TrackOutput>,
    /// Whether each step records its edge points' fates.
    diagnostics: bool,
    /// The last step's edge points' fates, with diagnostics on.
    edges: Vec<EdgeDiagnostic>,
}

impl BuiltinTracker {
    /// The tracker with these settings; it starts at [`FrameTracker::reset`].
    pub fn new(config: TrackerConfig) -> BuiltinTracker {
        BuiltinTracker {
            config,
            tracker: None,
            last: None,
            diagnostics: false,
            edges: Vec::new(),
        }
    }

    /// The tracker itself, once reset.
    pub fn tracker(&self) -> Option<&Tracker> {
        self.tracker.as_ref()
    }

    /// Everything the last frame's step made (stages 1–8), until
    /// [`FrameTracker::take_details`] takes it.
    pub fn last_output(&self) -> Option<&TrackOutput> {
        self.last.as_ref()
    }
}

/// The estimate of a tracker's output: stage 8's position, the located target, the status.
pub(crate) fn estimate_of(out: &TrackOutput) -> Estimate {
    let [x, y, z] = out.position_3d;
    Estimate {
        range_m: z,
        lateral_m: x,
        vertical_m: Some(y),
        cx: Some(out.estimate.c_x),
        cy: Some(out.estimate.c_y),
        scale: Some(out.estimate.scale),
        status: out.status.into(),
    }
}

impl FrameTracker for BuiltinTracker {
    fn name(&self) -> String {
        format!("paper tracker ({} mode)", self.config.mode.as_str())
    }

    fn reset(&mut self, camera: &CameraModel, start: Option<&Estimate>) -> Result<(), PluginError> {
        let (model, config) = (camera.target.clone(), self.config.clone());
        let placed = start.map(|s| match (s.cx, s.cy, s.scale) {
            (Some(cx), Some(cy), Some(scale)) => Ok(Location::new(cx, cy, scale)),
            _ => Err(PluginError::Failed(
                "the paper's tracker starts from an image location: the start needs cx, cy \
                 and scale"
                    .into(),
            )),
        });
        let tracker = match placed.transpose()? {
            Some(init) => Tracker::new(model, camera.intrinsics, config, init),
            None => Tracker::new_searching(model, camera.intrinsics, config),
        };
        let mut tracker = tracker.map_err(|e| PluginError::Failed(e.to_string()))?;
        // The overlay and recordings draw associated and rejected points only.
        tracker.set_association_fates_only(true);
        self.tracker = Some(tracker);
        self.last = None;
        self.edges.clear();
        Ok(())
    }

    fn track(&mut self, input: &TrackerInput<'_>) -> Result<Option<Estimate>, PluginError> {
        let tracker = self
            .tracker
            .as_mut()
            .ok_or_else(|| PluginError::Failed("track before reset".into()))?;
        // Robust mode's prediction turns with the camera, by the gyro (the paper's ignores it).
        let ego = (self.config.mode == TrackerMode::Robust)
            .then_some(input.gyro_rad)
            .flatten()
            .map(|rotation_rad| EgoMotion { rotation_rad });
        let (frame, t_s) = (input.frame, input.t_s);
        let (out, edges) = match (ego, self.diagnostics) {
            (Some(ego), true) => tracker.step_aided_with_diagnostics(frame, t_s, ego),
            (Some(ego), false) => (tracker.step_aided(frame, t_s, ego), Vec::new()),
            (None, true) => tracker.step_with_diagnostics(frame, t_s),
            (None, false) => (tracker.step(frame, t_s), Vec::new()),
        };
        let estimate = estimate_of(&out);
        self.last = Some(out);
        self.edges = edges;
        Ok(Some(estimate))
    }

    /// Steps on the part drawn, from a copy of the tracker's state; should the step read
    /// beyond it ([`Tracker::last_read`]), the copy is put back and the pixels read asked
    /// for.
    fn track_drawn(
        &mut self,
        input: &TrackerInput<'_>,
        drawn: PixelRect,
    ) -> Result<Drawn, PluginError> {
        if drawn == PixelRect::whole(input.frame.width(), input.frame.height()) {
            return self.track(input).map(Drawn::Tracked);
        }
        let before = self.tracker.clone();
        let last = self.last.take();
        let estimate = self.track(input)?;
        let read = self.tracker.as_ref().map(Tracker::last_read);
        match read {
            Some(read) if !drawn.contains(&read) => {
                self.tracker = before;
                self.last = last;
                self.edges.clear();
                Ok(Drawn::Needs(read))
            }
            _ => Ok(Drawn::Tracked(estimate)),
        }
    }

    fn reads_gyro(&self) -> bool {
        self.config.mode == TrackerMode::Robust
    }

    fn set_diagnostics(&mut self, on: bool) {
        self.diagnostics = on;
    }

    fn take_details(&mut self) -> Option<StepDetails> {
        Some(StepDetails {
            // Taken, not copied: the loop takes it every frame.
            output: self.last.take()?,
            read: self.tracker.as_ref()?.last_read(),
            edges: std::mem::take(&mut self.edges),
        })
    }
}

/// The built-in chase controller (pure pursuit on breadcrumbs from the delayed estimates,
/// the gap keeper, loss handling and the pan head's aim) as a plug-in. It hears every
/// estimate the delay line delivers ([`Controller::receive`]).
pub struct BuiltinController {
    controller: ChaseController,
}

impl BuiltinController {
    /// The controller with these settings, for an HMMWV moving at `speed_mps`.
    pub fn new(
        config: ChaseControllerConfig,
        speed_mps: f64,
    ) -> Result<BuiltinController, PluginError> {
        ChaseController::new(config, &VehicleParams::hmmwv_m998(), speed_mps as f32)
            .map(|controller| BuiltinController { controller })
            .map_err(|e| PluginError::Failed(e.to_string()))
    }

    /// The controller itself (its mode, telemetry and events).
    pub fn controller(&self) -> &ChaseController {
        &self.controller
    }
}

impl From<ChaseController> for BuiltinController {
    fn from(controller: ChaseController) -> BuiltinController {
        BuiltinController { controller }
    }
}

impl Controller for BuiltinController {
    fn name(&self) -> String {
        "pure pursuit and gap keeper".into()
    }

    fn receive(&mut self, d: &Delivered) {
        let [x, y, z] = d.position_m;
        self.controller.receive(LeadEstimate {
            capture_step: Step::from_seconds(d.captured_t_s),
            target_in_camera_m: Vector::new(x as f32, y as f32, z as f32),
            status: match d.estimate.status {
                EstimateStatus::Tracking => TrackStatus::Tracking,
                EstimateStatus::Coasting => TrackStatus::Coasting,
                EstimateStatus::Lost => TrackStatus::Lost,
            },
            camera_pan_rad: d.captured_pan_rad as f32,
        });
    }

    fn chase_controller(&self) -> Option<&ChaseController> {
        Some(&self.controller)
    }

    fn control(&mut self, input: &ControlInput) -> Result<Command, PluginError> {
        let controls = self.controller.update(&Odometry {
            step: Step::from_seconds(input.t_s),
            world_from_chase: input.world_from_chase,
            forward_speed_mps: input.speed_mps as f32,
            camera_pan_rad: input.pan_rad as f32,
        });
        Ok(Command {
            // The vehicle's steering turns positive to the left, the plug-ins' to the right.
            steering_rad: -f64::from(controls.steer_rad),
            throttle: f64::from(controls.throttle),
            brake: f64::from(controls.brake),
            pan_rate_rad_s: f64::from(self.controller.telemetry().pan_rate_cmd_rad_s),
        })
    }
}
