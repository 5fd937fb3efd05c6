//! The built-in tracker and controller behind the plug-in traits: the paper's tracker
//! (either mode) as a [`FrameTracker`], the built-in chase controller as a [`Controller`].
//! The loop runs them as it runs any plug-in; they are as much for whoever wants them as
//! plug-ins: a comparison, a wrapper in Python, a controller of one's own over the paper's
//! tracker.

use super::acquisition::Acquisition;
use super::{
    CameraModel, Command, ControlInput, Controller, Delivered, Drawn, Estimate, EstimateStatus,
    FrameTracker, PluginError, StepDetails, TrackerInput,
};
use tracker::{
    EdgeDiagnostic, EgoMotion, Location, PixelRect, TargetModel, TrackOutput, Tracker,
    TrackerConfig, TrackerMode,
};
use vehicle::{
    ChaseController, ChaseControllerConfig, LeadEstimate, Odometry, Step, TrackStatus, Vector,
    VehicleParams,
};

/// The paper's tracker (stages 1–8), in the mode its settings give, as a plug-in. In
/// traffic (given other targets, or no start in the paper's mode) it also chooses what to
/// hold: see the `acquisition` module.
pub struct BuiltinTracker {
    config: TrackerConfig,
    /// The tracker of the target held (without acquisition: the one tracker).
    tracker: Option<Tracker>,
    /// Traffic's acquisition, when on.
    acquisition: Option<Acquisition>,
    /// The other vehicles' targets ([`FrameTracker::set_other_targets`]).
    others: Vec<TargetModel>,
    last: Option<TrackOutput>,
    /// The last estimate given.
    last_estimate: Option<Estimate>,
    /// The pixels the last step read.
    read: Option<PixelRect>,
    /// Whether each step records its edge points' fates.
    diagnostics: bool,
    /// The last step's edge points' fates, with diagnostics on.
    edges: Vec<EdgeDiagnostic>,
    /// Whether the frame stepped is drawn in part only ([`FrameTracker::track_drawn`]): a
    /// check of the target held against the other models then asks for the whole.
    drawn_in_part: bool,
}

impl BuiltinTracker {
    /// The tracker with these settings; it starts at [`FrameTracker::reset`].
    pub fn new(config: TrackerConfig) -> BuiltinTracker {
        BuiltinTracker {
            config,
            tracker: None,
            acquisition: None,
            others: Vec::new(),
            last: None,
            last_estimate: None,
            read: None,
            diagnostics: false,
            drawn_in_part: false,
            edges: Vec::new(),
        }
    }

    /// The tracker of the target held, once reset (`None` while it searches in traffic).
    pub fn tracker(&self) -> Option<&Tracker> {
        self.tracker.as_ref()
    }

    /// Everything the last frame's step made (stages 1–8), until
    /// [`FrameTracker::take_details`] takes it.
    pub fn last_output(&self) -> Option<&TrackOutput> {
        self.last.as_ref()
    }

    /// In traffic, which target it holds: 0 for the lead's ([`CameraModel::target`]), k
    /// for the k-th of [`FrameTracker::set_other_targets`]; `None` while it searches, and
    /// always without traffic.
    pub fn held_target(&self) -> Option<usize> {
        self.acquisition.as_ref().and_then(Acquisition::held)
    }

    /// Steps `tracker` on `input`'s frame, with the gyro in robust mode.
    fn step(
        diagnostics: bool,
        tracker: &mut Tracker,
        input: &TrackerInput<'_>,
    ) -> (TrackOutput, Vec<EdgeDiagnostic>) {
        // Robust mode's prediction turns with the camera, by the gyro (the paper's ignores it).
        let ego = (tracker.config().mode == TrackerMode::Robust)
            .then_some(input.gyro_rad)
            .flatten()
            .map(|rotation_rad| EgoMotion { rotation_rad });
        let (frame, t_s) = (input.frame, input.t_s);
        match (ego, diagnostics) {
            (Some(ego), true) => tracker.step_aided_with_diagnostics(frame, t_s, ego),
            (Some(ego), false) => (tracker.step_aided(frame, t_s, ego), Vec::new()),
            (None, true) => tracker.step_with_diagnostics(frame, t_s),
            (None, false) => (tracker.step(frame, t_s), Vec::new()),
        }
    }

    /// A frame in traffic: the held target's tracker steps and is judged against the
    /// lane, or, holding nothing, the next model's search.
    fn track_in_traffic(
        &mut self,
        input: &TrackerInput<'_>,
    ) -> Result<Option<(TrackOutput, Vec<EdgeDiagnostic>, bool)>, PluginError> {
        let acquisition = self.acquisition.as_mut().expect("in traffic");
        let diagnostics = self.diagnostics;
        if acquisition.resting() {
            acquisition.rest();
            self.read = None;
            return Ok(None);
        }
        if acquisition.searching() {
            let (out, (edges, read), acquired) = acquisition
                .search(input.lane, |t| {
                    let (out, e) = Self::step(diagnostics, t, input);
                    (out, (e, t.last_read()))
                })
                .map_err(|e| PluginError::Failed(e.to_string()))?;
            self.read = Some(read);
            if let Some(holder) = acquired {
                self.tracker = Some(holder);
            }
            return Ok(Some((out, edges, false)));
        }
        let tracker = self.tracker.as_mut().expect("a held target has a tracker");
        let (out, edges) = Self::step(diagnostics, tracker, input);
        self.read = Some(tracker.last_read());
        let released = acquisition.judge_held(&out, input);
        if released || !acquisition.rechecks(&out) {
            return Ok(Some((out, edges, released)));
        }
        if self.drawn_in_part {
            // The check reads the whole image: `track_drawn` puts the step back and asks.
            self.read = Some(PixelRect::whole(input.frame.width(), input.frame.height()));
            return Ok(Some((out, edges, false)));
        }
        let step = |t: &mut Tracker| {
            let (out, e) = Self::step(diagnostics, t, input);
            (out, (e, t.last_read()))
        };
        let failed = |e: tracker::TrackerError| PluginError::Failed(e.to_string());
        match acquisition
            .recheck(&out, input.lane, step)
            .map_err(failed)?
        {
            Some((better, (edges, read), holder)) => {
                // What was followed is let go of: the controller hears it lost, and
                // measures the new target first.
                self.tracker = Some(holder);
                self.read = Some(read);
                Ok(Some((better, edges, true)))
            }
            None => {
                // A fit that slid off its target, with no target found instead, is let go.
                let released = acquisition.let_go_of_slid();
                Ok(Some((out, edges, released)))
            }
        }
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
        vehicle: None,
    }
}

impl FrameTracker for BuiltinTracker {
    fn name(&self) -> String {
        format!("paper tracker ({} mode)", self.config.mode.as_str())
    }

    fn set_other_targets(&mut self, targets: &[TargetModel]) {
        self.others = targets.to_vec();
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
        let placed = placed.transpose()?;
        let failed = |e: tracker::TrackerError| PluginError::Failed(e.to_string());
        // Traffic's acquisition: with other targets to hold, or with no start (the paper's
        // mode takes its start from robust mode's search), in the chase's lane.
        let acquire = !self.others.is_empty() || placed.is_none();
        self.acquisition = if acquire {
            let mut models = vec![model.clone()];
            models.extend(self.others.iter().cloned());
            Some(
                Acquisition::new(models, camera.intrinsics, config.clone(), placed.is_some())
                    .map_err(failed)?,
            )
        } else {
            None
        };
        let tracker = match placed {
            Some(init) => Some(Tracker::new(model, camera.intrinsics, config, init)),
            None if acquire => None,
            None => Some(Tracker::new_searching(model, camera.intrinsics, config)),
        };
        self.tracker = tracker.transpose().map_err(failed)?;
        // The overlay and recordings draw associated and rejected points only.
        if let Some(t) = &mut self.tracker {
            t.set_association_fates_only(true);
        }
        self.last = None;
        self.last_estimate = None;
        self.read = None;
        self.edges.clear();
        Ok(())
    }

    fn track(&mut self, input: &TrackerInput<'_>) -> Result<Option<Estimate>, PluginError> {
        let (out, edges, released) = if self.acquisition.is_some() {
            match self.track_in_traffic(input)? {
                Some(stepped) => stepped,
                None => {
                    // A frame the search rests: still nothing held.
                    self.last = None;
                    self.edges.clear();
                    return Ok(self.last_estimate.map(|e| Estimate {
                        status: EstimateStatus::Lost,
                        ..e
                    }));
                }
            }
        } else {
            let tracker = self
                .tracker
                .as_mut()
                .ok_or_else(|| PluginError::Failed("track before reset".into()))?;
            let (out, edges) = Self::step(self.diagnostics, tracker, input);
            self.read = Some(tracker.last_read());
            (out, edges, false)
        };
        let mut estimate = estimate_of(&out);
        if released {
            // Let go of: the controller hears it lost.
            estimate.status = EstimateStatus::Lost;
        }
        self.last = Some(out);
        self.edges = edges;
        self.last_estimate = Some(estimate);
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
        let whole = PixelRect::whole(input.frame.width(), input.frame.height());
        if drawn == whole {
            return self.track(input).map(Drawn::Tracked);
        }
        if self
            .acquisition
            .as_ref()
            .is_some_and(|a| a.searching() && !a.resting())
        {
            // A search reads the whole image.
            return Ok(Drawn::Needs(whole));
        }
        // Holding a target, a step changes only the held tracker and the hold's counters.
        let held = self.acquisition.as_ref().map(Acquisition::hold);
        let before = (self.tracker.clone(), self.read);
        let last = self.last.take();
        self.drawn_in_part = true;
        let estimate = self.track(input);
        self.drawn_in_part = false;
        let estimate = estimate?;
        match self.read {
            Some(read) if !drawn.contains(&read) => {
                (self.tracker, self.read) = before;
                if let (Some(a), Some(h)) = (&mut self.acquisition, held) {
                    a.restore(h);
                }
                self.last = last;
                self.edges.clear();
                Ok(Drawn::Needs(read))
            }
            _ => Ok(Drawn::Tracked(estimate)),
        }
    }

    /// In traffic, holding nothing, on the frames its search rests (the next frame's
    /// search may still acquire a target, and then asks for its pixels).
    fn will_rest(&self, ahead: u64) -> bool {
        self.acquisition.as_ref().is_some_and(|a| a.rests_in(ahead))
    }

    fn may_read_whole(&self, ahead: u64) -> bool {
        self.acquisition
            .as_ref()
            .is_some_and(|a| a.may_read_whole(ahead))
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
            read: self.read?,
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
