//! The chase controller: from the tracker's delayed 3-D estimates and its own odometry, it
//! steers along the lead's path (pure pursuit on breadcrumbs) and keeps the gap; when the
//! lead is lost it brakes to a safe stop and says so.
//!
//! It never sees the ground truth or the image. Call [`ChaseController::receive`] with each
//! estimate as it comes out of the delay line, then [`ChaseController::update`] once per
//! physics step.

use crate::breadcrumb_trail::{Breadcrumb, BreadcrumbTrail};
use crate::camera_mount::CameraMount;
use crate::clock::{ms_from_steps, steps_from_ms, Step, PHYSICS_DT_S};
use crate::controller_event::{ControllerEvent, ControllerEventKind};
use crate::controls::Controls;
use crate::error::{check_range, VehicleError};
use crate::gap_keeper::{GapKeeper, GapKeeperConfig, Threat};
use crate::lead_estimate::{LeadEstimate, TrackStatus};
use crate::pose_history::{OwnMotion, PoseHistory};
use crate::pure_pursuit::{curvature_toward, lookahead_point, steer_for_curvature, LookAhead};
use crate::range_filter::{Gains, RangeFilter, RangeGate};
use crate::speed_controller::{SpeedController, SpeedGains};
use crate::speed_profile::{ProfileBasis, SpeedProfile};
use crate::vehicle_params::VehicleParams;
use rapier3d::math::{Pose, Vector};
use serde::{Deserialize, Serialize};

/// Below this speed a stopping vehicle counts as stopped, m/s.
const STOPPED_MPS: f32 = 0.1;

/// How the chase vehicle chooses its speed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "mode")]
pub enum SpeedMode {
    /// Keep the gap to the lead (the gap keeper).
    GapKeeping,
    /// Replay a scripted speed, as the paper's human driver worked the throttle. The
    /// emergency brake still guards the gap.
    Manual {
        /// The scripted speed (by time, or by distance driven).
        profile: SpeedProfile,
    },
}

/// The chase controller's configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChaseControllerConfig {
    /// Where the camera sits on the chase vehicle.
    pub camera_mount: CameraMount,
    /// Pure-pursuit look-ahead on the breadcrumbs.
    pub lookahead: LookAhead,
    /// Gap keeping or a scripted speed.
    pub speed_mode: SpeedMode,
    /// The gap keeper's tuning (its emergency brake also guards manual mode).
    pub gap_keeper: GapKeeperConfig,
    /// Speed-loop gains.
    pub speed_gains: SpeedGains,
    /// With no estimate for this long the lead counts as lost, ms (default 500 ms: about 4
    /// missing frames after the 128 ms latency).
    pub estimate_timeout_ms: f64,
    /// Deceleration of the stop after a loss, m/s² (default 3.5 m/s²: firm, controlled).
    pub loss_decel_mps2: f32,
    /// How long the pose history reaches back, ms (default 2,000 ms: far more than any
    /// latency studied).
    pub pose_history_ms: f64,
    /// Breadcrumbs closer together than this are merged, m (default 0.25 m).
    pub breadcrumb_spacing_m: f32,
    /// Most breadcrumbs kept (default 2,000: 500 m of path).
    pub max_breadcrumbs: usize,
    /// Tracking index of the gap-keeping range filter at 10 m (default 0.21: gains α = 0.47
    /// and β = 0.15 there, 0.35 and 0.075 at 15 m). The gap keeper takes the lead's speed as
    /// its own plus this filter's rate, so rate noise becomes throttle and brake chatter, and
    /// every brake pitches the camera; but a slow rate lags, and the gap oscillates. The
    /// gains follow the tracker's range noise, which grows as the square of the range
    /// ([`Gains::TrackingIndex`]). (A filter on the range itself, at one β for every range,
    /// could not have both: at β = 0.15 the gap hunted between 15 and 24 m at 15 m, at
    /// β = 0.05 it swung ±0.6 m every 4 s at 10 m.)
    pub range_tracking_index: f32,
    /// Tracking index of the alarm range filter at 10 m (default 0.6, gains α = 0.66 and
    /// β = 0.35 there). This second filter only feeds the emergency-brake test, so it must
    /// show a lead's hard braking within a few frames; its gains follow the tracker's range
    /// noise, which grows as the square of the range ([`Gains::TrackingIndex`]): β is 0.85
    /// at 5 m and 0.19 at 15 m. (Fixed at 10 m's gains, the noise at 14 m gave closing
    /// speeds of several m/s out of nothing, and full brakes that pitched the target out of
    /// the tracker's window.)
    pub alarm_tracking_index: f32,
    /// Both range filters refuse a measurement further than this fraction of the predicted
    /// range from their prediction (default 0.08: several times the tracker's range noise at
    /// 15 m. One frame of background edges taken for features can put the scale 16 % off; a
    /// lead braking at 0.85 g moves the range a few centimetres a frame beyond the
    /// prediction).
    pub range_gate_fraction: f32,
    /// The smallest gate, m (default 0.5 m).
    pub range_gate_min_m: f32,
}

/// The range at which the range filters' tracking indices hold, m: the middle of the
/// paper's 5–15 m.
const REFERENCE_RANGE_M: f32 = 10.0;

/// After this many gated measurements in a row the range filters take the next one: the
/// range has really moved (three frames, 0.2 s).
const RANGE_GATE_ACCEPT_AFTER: u32 = 3;

impl Default for ChaseControllerConfig {
    fn default() -> Self {
        ChaseControllerConfig {
            camera_mount: CameraMount::default(),
            lookahead: LookAhead::default(),
            speed_mode: SpeedMode::GapKeeping,
            gap_keeper: GapKeeperConfig::default(),
            speed_gains: SpeedGains::default(),
            estimate_timeout_ms: 500.0,
            loss_decel_mps2: 3.5,
            pose_history_ms: 2000.0,
            breadcrumb_spacing_m: 0.25,
            max_breadcrumbs: 2000,
            range_tracking_index: 0.21,
            alarm_tracking_index: 0.6,
            range_gate_fraction: 0.08,
            range_gate_min_m: 0.5,
        }
    }
}

/// The chase vehicle's own odometry for one physics step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Odometry {
    /// The step.
    pub step: Step,
    /// The chase vehicle frame in the world frame.
    pub world_from_chase: Pose,
    /// Speed along the chase vehicle's x axis, m/s.
    pub forward_speed_mps: f32,
}

/// What the chase controller is doing.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ChaseMode {
    /// Following the lead.
    Following,
    /// The lead is lost: braking to a stop.
    Stopping,
    /// Stopped after a loss, waiting for the tracker.
    Stopped,
}

/// The controller's inner values for one step, for the recorder and plots.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ChaseTelemetry {
    /// The mode.
    pub mode: ChaseMode,
    /// The gap now, predicted from the latest estimate over its latency, m.
    pub gap_m: Option<f32>,
    /// Range rate from the range filter, m/s.
    pub range_rate_mps: Option<f32>,
    /// The wanted gap, m.
    pub desired_gap_m: f32,
    /// The speed reference, m/s.
    pub speed_ref_mps: f32,
    /// Pure pursuit's look-ahead point in the world frame.
    pub lookahead_world_m: Option<Vector>,
    /// Commanded path curvature, 1/m.
    pub curvature: f32,
    /// Whether the emergency brake is on.
    pub emergency: bool,
}

/// The chase vehicle's controller.
#[derive(Clone, Debug)]
pub struct ChaseController {
    config: ChaseControllerConfig,
    wheelbase_m: f32,
    max_steer_rad: f32,
    vehicle_from_camera: Pose,
    history: PoseHistory,
    pending: Vec<LeadEstimate>,
    trail: BreadcrumbTrail,
    range: RangeFilter,
    alarm_range: RangeFilter,
    gap_keeper: GapKeeper,
    speed: SpeedController,
    timeout_steps: u64,
    mode: ChaseMode,
    started: Option<Step>,
    last_arrival: Option<Step>,
    last_status: Option<TrackStatus>,
    stop_ref_mps: f32,
    odometer_m: f32,
    events: Vec<ControllerEvent>,
    telemetry: ChaseTelemetry,
}

impl ChaseController {
    /// A controller for the chase vehicle `params`, starting at `speed_mps`.
    pub fn new(
        config: ChaseControllerConfig,
        params: &VehicleParams,
        speed_mps: f32,
    ) -> Result<ChaseController, VehicleError> {
        params.validate()?;
        config.camera_mount.validate()?;
        check_range(
            "estimate_timeout_ms",
            config.estimate_timeout_ms,
            1.0,
            60_000.0,
        )?;
        check_range(
            "loss_decel_mps2",
            f64::from(config.loss_decel_mps2),
            0.1,
            15.0,
        )?;
        check_range("pose_history_ms", config.pose_history_ms, 10.0, 600_000.0)?;
        check_range(
            "breadcrumb_spacing_m",
            f64::from(config.breadcrumb_spacing_m),
            0.0,
            10.0,
        )?;
        check_range(
            "range_tracking_index",
            f64::from(config.range_tracking_index),
            0.001,
            100.0,
        )?;
        check_range(
            "alarm_tracking_index",
            f64::from(config.alarm_tracking_index),
            0.001,
            100.0,
        )?;
        check_range(
            "range_gate_fraction",
            f64::from(config.range_gate_fraction),
            0.01,
            10.0,
        )?;
        check_range(
            "range_gate_min_m",
            f64::from(config.range_gate_min_m),
            0.0,
            1000.0,
        )?;
        if let SpeedMode::Manual { profile } = &config.speed_mode {
            profile.validate()?;
        }
        let gap_keeper = GapKeeper::new(config.gap_keeper.clone(), speed_mps)?;
        let gate = RangeGate {
            fraction: config.range_gate_fraction,
            min_m: config.range_gate_min_m,
            accept_after: RANGE_GATE_ACCEPT_AFTER,
        };
        Ok(ChaseController {
            wheelbase_m: params.wheelbase_m,
            max_steer_rad: params.max_steer_rad,
            vehicle_from_camera: config.camera_mount.vehicle_from_camera(),
            history: PoseHistory::new(steps_from_ms(config.pose_history_ms) as usize),
            pending: Vec::new(),
            trail: BreadcrumbTrail::new(config.breadcrumb_spacing_m, config.max_breadcrumbs),
            range: RangeFilter::gated(
                Gains::TrackingIndex {
                    index_at_reference: config.range_tracking_index,
                    reference_m: REFERENCE_RANGE_M,
                },
                gate,
            ),
            alarm_range: RangeFilter::gated(
                Gains::TrackingIndex {
                    index_at_reference: config.alarm_tracking_index,
                    reference_m: REFERENCE_RANGE_M,
                },
                gate,
            ),
            gap_keeper,
            speed: SpeedController::new(params, config.speed_gains),
            timeout_steps: steps_from_ms(config.estimate_timeout_ms),
            mode: ChaseMode::Following,
            started: None,
            last_arrival: None,
            last_status: None,
            stop_ref_mps: 0.0,
            odometer_m: 0.0,
            events: Vec::new(),
            telemetry: ChaseTelemetry {
                mode: ChaseMode::Following,
                gap_m: None,
                range_rate_mps: None,
                desired_gap_m: 0.0,
                speed_ref_mps: speed_mps,
                lookahead_world_m: None,
                curvature: 0.0,
                emergency: false,
            },
            config,
        })
    }

    /// Hands over an estimate that has just come out of the delay line. It is used at the
    /// next [`ChaseController::update`].
    pub fn receive(&mut self, estimate: LeadEstimate) {
        self.pending.push(estimate);
    }

    /// The events so far (loss, stops, resumption, emergency brakes), oldest first.
    pub fn events(&self) -> &[ControllerEvent] {
        &self.events
    }

    /// The mode now.
    pub fn mode(&self) -> ChaseMode {
        self.mode
    }

    /// The breadcrumb trail.
    pub fn trail(&self) -> &BreadcrumbTrail {
        &self.trail
    }

    /// Inner values of the last update.
    pub fn telemetry(&self) -> &ChaseTelemetry {
        &self.telemetry
    }

    fn log(&mut self, step: Step, kind: ControllerEventKind) {
        self.events.push(ControllerEvent { step, kind });
    }

    /// Places the pending estimates in the world; returns whether a tracked (or coasting)
    /// estimate arrived.
    fn absorb_pending(&mut self, now: Step) -> bool {
        let mut fresh = false;
        let mut pending = std::mem::take(&mut self.pending);
        pending.sort_by_key(|e| e.capture_step);
        for estimate in pending {
            self.last_arrival = Some(now);
            self.last_status = Some(estimate.status);
            if estimate.status == TrackStatus::Lost {
                continue;
            }
            let Some((world_from_chase, own)) = self.history.at(estimate.capture_step) else {
                self.log(
                    now,
                    ControllerEventKind::EstimateTooOld {
                        capture_step: estimate.capture_step,
                    },
                );
                continue;
            };
            let in_vehicle = self
                .vehicle_from_camera
                .transform_point(estimate.target_in_camera_m);
            let camera = self.vehicle_from_camera.translation;
            let gap =
                ((in_vehicle.x - camera.x).powi(2) + (in_vehicle.z - camera.z).powi(2)).sqrt();
            let captured_s = estimate.capture_step.seconds();
            self.range.update(captured_s, gap, own);
            self.alarm_range.update(captured_s, gap, own);
            self.trail.drop_crumb(Breadcrumb {
                capture_step: estimate.capture_step,
                position_world_m: world_from_chase.transform_point(in_vehicle),
            });
            fresh = true;
        }
        fresh
    }

    /// Commands for the chase vehicle at this step.
    pub fn update(&mut self, odometry: &Odometry) -> Controls {
        let now = odometry.step;
        let v = odometry.forward_speed_mps;
        let dt = PHYSICS_DT_S;
        let started = *self.started.get_or_insert(now);
        self.odometer_m += v.max(0.0) * dt;
        let own = OwnMotion {
            travel_m: self.odometer_m,
            speed_mps: v,
        };
        self.history.push(now, odometry.world_from_chase, own);
        let fresh = self.absorb_pending(now);

        // Loss handling.
        let silent_steps = now.since(self.last_arrival.unwrap_or(started));
        let lost = self.last_status == Some(TrackStatus::Lost);
        let timed_out = silent_steps > self.timeout_steps;
        match self.mode {
            ChaseMode::Following if lost || timed_out => {
                let kind = if lost {
                    ControllerEventKind::TrackLost
                } else {
                    ControllerEventKind::EstimateTimeout {
                        silent_ms: ms_from_steps(silent_steps),
                    }
                };
                self.log(now, kind);
                self.mode = ChaseMode::Stopping;
                self.stop_ref_mps = v.max(0.0);
                self.range.reset();
                self.alarm_range.reset();
            }
            ChaseMode::Stopping | ChaseMode::Stopped
                if fresh && self.last_status == Some(TrackStatus::Tracking) =>
            {
                self.log(now, ControllerEventKind::Resumed);
                self.mode = ChaseMode::Following;
                self.gap_keeper.reset(v);
                self.speed.reset();
            }
            _ => {}
        }

        // Steering: pure pursuit on the breadcrumbs.
        let pose = odometry.world_from_chase;
        self.trail.eat_passed(&pose);
        let path = self.trail.positions();
        let target = lookahead_point(&path, pose.translation, self.config.lookahead.distance_m(v));
        let curvature = target.map_or(0.0, |t| curvature_toward(&pose, t));
        let steer_rad = steer_for_curvature(curvature, self.wheelbase_m)
            .clamp(-self.max_steer_rad, self.max_steer_rad);

        // Gap now: the latest range carried forward over its latency, the lead at its
        // estimated speed and the chase as its odometry says; the range rate now.
        let carried = |s: Option<crate::range_filter::RangeState>| match s {
            Some(s) => (
                Some(s.range_at(now.seconds(), own)),
                Some(s.lead_speed_mps - v),
            ),
            None => (None, None),
        };
        let (gap_m, range_rate) = carried(self.range.state());
        let threat = match carried(self.alarm_range.state()) {
            (Some(gap), Some(rate)) => self.config.gap_keeper.threat(gap, rate, v),
            _ => Threat::default(),
        };

        // Speed.
        let was_emergency = self.telemetry.emergency;
        let mut emergency = false;
        let mut desired_gap_m = self.config.gap_keeper.desired_gap_m(v);
        let (speed_ref, accel_ref) = match self.mode {
            ChaseMode::Following => match (&self.config.speed_mode, gap_m, range_rate) {
                (SpeedMode::GapKeeping, Some(gap), Some(rate)) => {
                    let cmd = self.gap_keeper.update(gap, rate, threat, v, dt);
                    emergency = cmd.emergency;
                    desired_gap_m = cmd.desired_gap_m;
                    (cmd.speed_mps, cmd.accel_mps2)
                }
                (SpeedMode::GapKeeping, _, _) => {
                    // Nothing measured yet: hold speed until the first estimate or timeout.
                    self.gap_keeper.reset(v);
                    (v.max(0.0), 0.0)
                }
                (SpeedMode::Manual { profile }, _, _) => {
                    emergency = threat.emergency;
                    let (speed, slope) = match profile.basis {
                        ProfileBasis::Time => profile.sample(now.since(started) as f32 * dt),
                        ProfileBasis::Distance => profile.sample(self.odometer_m),
                    };
                    let accel = match profile.basis {
                        ProfileBasis::Time => slope,
                        ProfileBasis::Distance => slope * v,
                    };
                    (speed, accel)
                }
            },
            ChaseMode::Stopping => {
                self.stop_ref_mps = (self.stop_ref_mps - self.config.loss_decel_mps2 * dt).max(0.0);
                if v < STOPPED_MPS {
                    self.mode = ChaseMode::Stopped;
                    self.log(now, ControllerEventKind::Stopped);
                }
                let accel = if self.stop_ref_mps > 0.0 {
                    -self.config.loss_decel_mps2
                } else {
                    0.0
                };
                (self.stop_ref_mps, accel)
            }
            ChaseMode::Stopped => (0.0, 0.0),
        };
        if emergency && !was_emergency {
            self.log(
                now,
                ControllerEventKind::EmergencyBrake {
                    gap_m: gap_m.unwrap_or(0.0),
                },
            );
        }

        let pedals = self.speed.update(speed_ref, accel_ref, v, dt);
        self.telemetry = ChaseTelemetry {
            mode: self.mode,
            gap_m,
            range_rate_mps: range_rate,
            desired_gap_m,
            speed_ref_mps: speed_ref,
            lookahead_world_m: target,
            curvature,
            emergency,
        };
        if emergency {
            self.speed.reset();
            return Controls {
                steer_rad,
                throttle: 0.0,
                brake: 1.0,
            };
        }
        Controls {
            steer_rad,
            throttle: pedals.throttle,
            brake: pedals.brake,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level_mount() -> ChaseControllerConfig {
        ChaseControllerConfig {
            camera_mount: CameraMount {
                pitch_down_deg: 0.0,
                ..CameraMount::default()
            },
            ..ChaseControllerConfig::default()
        }
    }

    /// The chase drives along +x at 12 m/s (0.1 m per step).
    fn odometry(step: u64) -> Odometry {
        Odometry {
            step: Step(step),
            world_from_chase: Pose::from_translation(Vector::new(step as f32 * 0.1, 0.0, 0.0)),
            forward_speed_mps: 12.0,
        }
    }

    #[test]
    fn breadcrumbs_use_the_pose_at_capture_time() {
        let params = VehicleParams::hmmwv_m998();
        let mut c = ChaseController::new(level_mount(), &params, 12.0).unwrap();
        for s in 0..=25 {
            c.update(&odometry(s));
        }
        // Captured at step 10 (chase at x = 1.0), 10 m straight ahead of the camera and
        // 1 m to its right; delivered at step 26.
        c.receive(LeadEstimate {
            capture_step: Step(10),
            target_in_camera_m: Vector::new(1.0, 0.0, 10.0),
            status: TrackStatus::Tracking,
        });
        c.update(&odometry(26));
        let crumb = c.trail().newest().unwrap();
        let want = Vector::new(1.0 + 2.2 + 10.0, 2.0, 1.0);
        assert!(
            (crumb.position_world_m - want).length() < 1e-4,
            "crumb at {}, want {want}",
            crumb.position_world_m
        );
        // The gap now is carried forward from capture time: 10 m measured, not yet a rate.
        let gap = c.telemetry().gap_m.unwrap();
        assert!((gap - (1.0f32 + 100.0).sqrt()).abs() < 1e-4, "gap {gap}");
    }

    #[test]
    fn estimate_older_than_the_history_is_dropped_and_logged() {
        let params = VehicleParams::hmmwv_m998();
        let config = ChaseControllerConfig {
            pose_history_ms: 100.0,
            ..level_mount()
        };
        let mut c = ChaseController::new(config, &params, 12.0).unwrap();
        for s in 0..=100 {
            c.update(&odometry(s));
        }
        c.receive(LeadEstimate {
            capture_step: Step(10),
            target_in_camera_m: Vector::new(0.0, 0.0, 10.0),
            status: TrackStatus::Tracking,
        });
        c.update(&odometry(101));
        assert!(c.trail().is_empty());
        assert!(matches!(
            c.events().last().unwrap().kind,
            ControllerEventKind::EstimateTooOld { .. }
        ));
    }

    #[test]
    fn manual_mode_replays_the_scripted_speed() {
        let params = VehicleParams::hmmwv_m998();
        let profile = SpeedProfile::new(ProfileBasis::Time, &[(0.0, 5.0), (10.0, 15.0)]).unwrap();
        let config = ChaseControllerConfig {
            speed_mode: SpeedMode::Manual { profile },
            ..level_mount()
        };
        let mut c = ChaseController::new(config, &params, 5.0).unwrap();
        for s in 0..=600u64 {
            c.receive(LeadEstimate {
                capture_step: Step(s),
                target_in_camera_m: Vector::new(0.0, 0.0, 30.0),
                status: TrackStatus::Tracking,
            });
            c.update(&odometry(s));
        }
        // 5 s into a 5 -> 15 m/s ramp over 10 s.
        assert!((c.telemetry().speed_ref_mps - 10.0).abs() < 0.01);
    }
}
