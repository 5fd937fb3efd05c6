//! The chase controller: from the tracker's delayed 3-D estimates and its own odometry, it
//! steers along the lead's path (pure pursuit on breadcrumbs) and keeps the gap; when the
//! lead is lost it brakes to a safe stop and says so. With `lane_keeping` it steers along its
//! own lane instead and follows only a target in that lane ([`ChaseController::set_lane`]).
//!
//! It never sees the ground truth or the image. Call [`ChaseController::receive`] with each
//! estimate as it comes out of the delay line, then [`ChaseController::update`] once per
//! physics step.

use crate::breadcrumb_trail::{Breadcrumb, BreadcrumbTrail};
use crate::camera_mount::CameraMount;
use crate::clock::{steps_from_ms, Step, PHYSICS_DT_S};
use crate::controller_event::{ControllerEvent, ControllerEventKind};
use crate::controls::Controls;
use crate::error::{check_range, VehicleError};
use crate::event_spec::is_false;
use crate::gap_keeper::{GapKeeper, GapKeeperConfig};
use crate::lead_estimate::{LeadEstimate, TrackStatus};
use crate::pan_head::PanHeadConfig;
use crate::pose_history::{OwnMotion, PoseHistory};
use crate::pure_pursuit::{curvature_toward, lookahead_point, steer_for_curvature, LookAhead};
use crate::range_filter::{Gains, RangeFilter, RangeGate};
use crate::speed_controller::{SpeedController, SpeedGains};
use crate::speed_profile::{ProfileBasis, SpeedProfile};
use crate::vehicle_params::VehicleParams;
use rapier3d::math::{Pose, Vector};
use serde::{Deserialize, Serialize};

mod lane_keeping;
mod safety;
pub use lane_keeping::{LANE_MARGIN_M, LEFT_LANE_ARRIVALS};

/// Below this speed a stopping vehicle counts as stopped, m/s.
const STOPPED_MPS: f32 = 0.1;

/// The chord over which the breadcrumbs' curvature is measured, m: long enough that the
/// estimates' lateral noise (a few centimetres at 10 m) gives a curvature noise near
/// 0.005 /m, a tenth of an 18 m bend's.
const CURVATURE_CHORD_M: f32 = 5.0;

/// The largest curvature of a path on the ground (x, z), 1/m: over each three points about
/// `chord_m` apart along it, the curvature of the circle through them (2·sin(turn)/chord).
/// 0 for a path shorter than two chords.
fn max_curvature(path: &[Vector], chord_m: f32) -> f32 {
    // Resample at about `chord_m` along the path.
    let mut picked: Vec<Vector> = Vec::new();
    for p in path {
        let flat = Vector::new(p.x, 0.0, p.z);
        match picked.last() {
            Some(last) if last.distance(flat) < chord_m => {}
            _ => picked.push(flat),
        }
    }
    picked
        .windows(3)
        .map(|w| {
            let (a, b) = (w[1] - w[0], w[2] - w[1]);
            let cross = a.x * b.z - a.z * b.x;
            let chord = (w[2] - w[0]).length();
            if chord <= 0.0 {
                0.0
            } else {
                // |a × b| = |a||b| sin(turn); the circle through three points has
                // curvature 2·sin(angle at b)/|ac|.
                (2.0 * cross / (a.length() * b.length() * chord)).abs()
            }
        })
        .fold(0.0, f32::max)
}

/// How the chase vehicle chooses its speed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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

/// The narrowest half field of view the controller takes, degrees: a 200 mm lens with its
/// principal point at the frame's edge gives 0.004°.
pub const MIN_HALF_FOV_DEG: f64 = 1e-3;
/// The widest, degrees.
pub const MAX_HALF_FOV_DEG: f64 = 89.9;

/// The chase controller's configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct ChaseControllerConfig {
    /// Where the camera sits on the chase vehicle. (Not a scenario field: a scenario sets
    /// it by `[camera.mount]`.)
    #[schemars(skip)]
    pub camera_mount: CameraMount,
    /// The camera's pan head (default: none, the paper's fixed camera). When it is on, the
    /// controller aims it at the lead. (Not a scenario field: a scenario sets it by
    /// `[camera.pan]`.)
    #[schemars(skip)]
    pub pan_head: PanHeadConfig,
    /// Half the camera's horizontal field of view, degrees (default 21.8°: 128 px at a
    /// 320 px focal length). The scenario sets it from the camera's intrinsics; the
    /// curve-aware gap keeping uses it ([`ChaseController::view_limited_gap_m`]). (Not a
    /// scenario field.)
    #[schemars(skip)]
    pub half_fov_deg: f32,
    /// How far inside the field of view's edge the target's centre must stay, degrees
    /// (default 6°: the board's half-width at 5 m, 5.7°, and the estimate's latency); 0–45°,
    /// and a margin wider than half the field of view leaves none.
    #[schemars(extend("minimum" = 0.0, "maximum" = 45.0))]
    pub view_margin_deg: f32,
    /// Whether the gap shortens where the road curves so that the lead stays in view
    /// (default true; see [`ChaseController::view_limited_gap_m`]).
    pub curve_aware_gap: bool,
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
    #[schemars(extend("minimum" = 1.0, "maximum" = 60000.0))]
    pub estimate_timeout_ms: f64,
    /// Whether the chase stops, as after a loss, as soon as the tracker says `coasting`, and
    /// follows no coasting estimate (default false: a coasting estimate, the tracker's
    /// prediction, is followed until the tracker says `lost`). In traffic, a target that
    /// stops being measured may be hidden by a vehicle that has cut in: on, the chase
    /// starts braking about `tracker.lost_after_s` sooner. It resumes on the next
    /// `tracking` estimate. (Written only when on, so that a scenario without it resolves
    /// as before it existed.)
    #[serde(skip_serializing_if = "is_false")]
    pub stop_on_coasting: bool,
    /// Whether the chase steers by pure pursuit along its own lane's centre line
    /// ([`ChaseController::set_lane`]), as a lane-keeping assist does, instead of along the
    /// breadcrumbs (default false); the estimates then set only its speed, and only while
    /// the target is in the lane ([`LEFT_LANE_ARRIVALS`]). (Written only when on.)
    #[serde(skip_serializing_if = "is_false")]
    pub lane_keeping: bool,
    /// With `lane_keeping`, the speed driven at while no target in the lane is followed,
    /// m/s, as an adaptive cruise control does (default none: stop as after a loss);
    /// 0.5–70 m/s, refused without `lane_keeping`. (Written only when set.)
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.5, "maximum" = 70.0))]
    pub cruise_speed_mps: Option<f32>,
    /// With `cruise_speed_mps`, how long the chase stands after a loss's stop before it
    /// drives on at the cruise speed, s, as a driver resuming an adaptive cruise control
    /// does (default none: it stands until the tracker holds a target in the lane again);
    /// 0–600 s. (Written only when set.)
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 600.0))]
    pub resume_after_s: Option<f32>,
    /// Deceleration of the stop after a loss, m/s² (default 3.5 m/s²: firm, controlled). A
    /// loss while the emergency brake is on does not relax it: that stop brakes fully, as
    /// the emergency did, until the chase stands or the target is held again.
    #[schemars(extend("minimum" = 0.1, "maximum" = 15.0))]
    pub loss_decel_mps2: f32,
    /// How long the pose history reaches back, ms (default 2,000 ms: far more than any
    /// latency studied).
    #[schemars(extend("minimum" = 10.0, "maximum" = 600000.0))]
    pub pose_history_ms: f64,
    /// Breadcrumbs closer together than this are merged, m (default 0.25 m).
    #[schemars(extend("minimum" = 0.0, "maximum" = 10.0))]
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
    #[schemars(extend("minimum" = 0.001, "maximum" = 100.0))]
    pub range_tracking_index: f32,
    /// Tracking index of the alarm range filter at 10 m (default 0.6, gains α = 0.66 and
    /// β = 0.35 there). This second filter only feeds the emergency-brake test, so it must
    /// show a lead's hard braking within a few frames; its gains follow the tracker's range
    /// noise, which grows as the square of the range ([`Gains::TrackingIndex`]): β is 0.85
    /// at 5 m and 0.19 at 15 m. (Fixed at 10 m's gains, the noise at 14 m gave closing
    /// speeds of several m/s out of nothing, and full brakes that pitched the target out of
    /// the tracker's window.)
    #[schemars(extend("minimum" = 0.001, "maximum" = 100.0))]
    pub alarm_tracking_index: f32,
    /// Both range filters refuse a measurement further than this fraction of the predicted
    /// range from their prediction (default 0.08: several times the tracker's range noise at
    /// 15 m. One frame of background edges taken for features can put the scale 16 % off; a
    /// lead braking at 0.85 g moves the range a few centimetres a frame beyond the
    /// prediction).
    #[schemars(extend("minimum" = 0.01, "maximum" = 10.0))]
    pub range_gate_fraction: f32,
    /// The smallest gate, m (default 0.5 m).
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub range_gate_min_m: f32,
}

/// The range at which the range filters' tracking indices hold, m: the middle of the
/// paper's 5–15 m.
const REFERENCE_RANGE_M: f32 = 10.0;

/// After this many gated measurements in a row the range filters take the next one: the
/// range has really moved (three frames, 0.2 s).
const RANGE_GATE_ACCEPT_AFTER: u32 = 3;

/// How long a closing alone (below the safe gap, closing fast, with room to stop still; see
/// [`crate::gap_keeper::Threat::closing_only`]) must last beyond the alarm filter's reference
/// range before it calls the emergency brake, ms: three frames at 15 Hz. Nearer than the
/// reference range, and when stopping needs more than the gap keeper's deceleration, the
/// brake comes at once. (At 90 km/h with the 8 mm lens, a 28 px target 25 m ahead, one
/// frame's scale noise made the alarm filter read a 4 m/s closing and the chase braked
/// fully from 25 m/s for a lead driving steadily on.)
const CLOSING_CONFIRM_MS: f64 = 200.0;

/// How many tracked estimates of a target the range filters take, once nothing is being
/// followed (after a loss, a target that left the lane, or cruising from the start), before
/// they give its range and speed and the chase resumes following it: 6, a third of a second
/// at the paper's 15 Hz. The speed is the slope of a least-squares line through them
/// (`RangeFilter::reset_measuring`); with ranges of noise σ at 15 Hz its error is 3.6 σ
/// per second (the least-squares slope's standard deviation, σ / √(Σ (t − t̄)²)), a few
/// m/s for a target 30 m ahead through a 16 mm lens, whose ranges scatter by about a metre
/// (`cut-out`'s standing car). Until then the chase goes on stopping or cruising, so more
/// estimates cost distance: with 10, `slow-vehicle-ahead`'s chase, cruising 30 km/h faster
/// than its lead, closed to 3.8 m instead of 6.0 m.
pub(crate) const RESUME_MEASUREMENTS: usize = 6;

impl Default for ChaseControllerConfig {
    fn default() -> Self {
        ChaseControllerConfig {
            camera_mount: CameraMount::default(),
            pan_head: PanHeadConfig::default(),
            half_fov_deg: 21.8,
            view_margin_deg: 6.0,
            curve_aware_gap: true,
            lookahead: LookAhead::default(),
            speed_mode: SpeedMode::GapKeeping,
            gap_keeper: GapKeeperConfig::default(),
            speed_gains: SpeedGains::default(),
            estimate_timeout_ms: 500.0,
            stop_on_coasting: false,
            lane_keeping: false,
            cruise_speed_mps: None,
            resume_after_s: None,
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
    /// The pan head's encoder reading, radians (0 for a fixed camera).
    pub camera_pan_rad: f32,
}

/// What the chase controller is doing.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ChaseMode {
    /// Following the lead.
    Following,
    /// The lead is lost: braking to a stop.
    Stopping,
    /// Stopped after a loss, waiting for the tracker.
    Stopped,
    /// No target in the lane: driving at the cruise speed (`lane_keeping` only).
    Cruising,
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
    /// The largest curvature of the lead's path ahead (the breadcrumbs; the lane with
    /// `lane_keeping`), 1/m.
    pub curvature_ahead: f32,
    /// Where the pan head is aimed, radians (positive to the right; 0 without one).
    pub pan_aim_rad: f32,
    /// The rate commanded of the pan head, rad/s (0 without one).
    pub pan_rate_cmd_rad_s: f32,
}

/// The chase vehicle's controller.
#[derive(Clone, Debug)]
pub struct ChaseController {
    config: ChaseControllerConfig,
    wheelbase_m: f32,
    max_steer_rad: f32,
    /// The camera's centre in the vehicle frame (the pan head turns about it).
    camera_pivot: Vector,
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
    /// Whether the stop after a loss brakes fully: the loss came during an emergency brake,
    /// and no tracked estimate has arrived since.
    stop_in_emergency: bool,
    /// When the current run of closing-only alarms began (see [`CLOSING_CONFIRM_MS`]).
    closing_since: Option<Step>,
    odometer_m: f32,
    /// The lane and the target's place in it (`lane_keeping`).
    lane: lane_keeping::LaneState,
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
        config.pan_head.validate()?;
        check_range(
            "half_fov_deg",
            f64::from(config.half_fov_deg),
            MIN_HALF_FOV_DEG,
            MAX_HALF_FOV_DEG,
        )?;
        check_range(
            "view_margin_deg",
            f64::from(config.view_margin_deg),
            0.0,
            45.0,
        )?;
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
        let mode = lane_keeping::validate_and_start(&config)?;
        let gap_keeper = GapKeeper::new(config.gap_keeper.clone(), speed_mps)?;
        let gate = RangeGate {
            fraction: config.range_gate_fraction,
            min_m: config.range_gate_min_m,
            accept_after: RANGE_GATE_ACCEPT_AFTER,
        };
        Ok(ChaseController {
            wheelbase_m: params.wheelbase_m,
            max_steer_rad: params.max_steer_rad,
            camera_pivot: config.camera_mount.vehicle_from_camera().translation,
            history: PoseHistory::new(steps_from_ms(config.pose_history_ms) as usize),
            pending: Vec::new(),
            trail: BreadcrumbTrail::new(config.breadcrumb_spacing_m, config.max_breadcrumbs),
            range: Self::range_filter(config.range_tracking_index, gate, mode),
            alarm_range: Self::range_filter(config.alarm_tracking_index, gate, mode),
            gap_keeper,
            speed: SpeedController::new(params, config.speed_gains),
            timeout_steps: steps_from_ms(config.estimate_timeout_ms),
            mode,
            started: None,
            last_arrival: None,
            last_status: None,
            stop_ref_mps: 0.0,
            stop_in_emergency: false,
            closing_since: None,
            odometer_m: 0.0,
            lane: lane_keeping::LaneState::new(speed_mps),
            events: Vec::new(),
            telemetry: ChaseTelemetry {
                mode,
                gap_m: None,
                range_rate_mps: None,
                desired_gap_m: 0.0,
                speed_ref_mps: speed_mps,
                lookahead_world_m: None,
                curvature: 0.0,
                emergency: false,
                curvature_ahead: 0.0,
                pan_aim_rad: 0.0,
                pan_rate_cmd_rad_s: 0.0,
            },
            config,
        })
    }

    /// A range filter of tracking index `index` at [`REFERENCE_RANGE_M`] behind `gate`, for
    /// a controller starting in `mode`: following, its first measurement is the lead's
    /// range at the chase's speed (a scenario's lead starts so); else it measures first
    /// ([`RESUME_MEASUREMENTS`]).
    fn range_filter(index: f32, gate: RangeGate, mode: ChaseMode) -> RangeFilter {
        let gains = Gains::TrackingIndex {
            index_at_reference: index,
            reference_m: REFERENCE_RANGE_M,
        };
        let mut filter = RangeFilter::gated(gains, gate);
        if mode != ChaseMode::Following {
            filter.reset_measuring(RESUME_MEASUREMENTS);
        }
        filter
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

    /// The largest gap at which a lead on a path of curvature `curvature` (1/m) stays in
    /// the camera's view, m; `None` when the curvature asks for no limit.
    ///
    /// The rule, from the geometry of a circular bend of radius R = 1/κ: with the chase's
    /// rear axle on the arc and its camera f = `camera_mount.forward_m` ahead of it along
    /// the heading, a lead a chord d from the camera, also on the arc, lies at a bearing of
    /// about κ·(d + f)²/(2d) from the chase's heading (the small-angle chord geometry; exact
    /// to a few per cent below 40°). Keeping that within α, the half field of view less
    /// `view_margin_deg` (plus the pan head's mechanical limit when it has one), bounds the
    /// gap: d² + 2(f − αR)d + f² ≤ 0, whose larger root is the limit. The gap keeper aims
    /// at no more than this (never below its band's `min_gap_m`, and never closer than the
    /// safe gap: safety first). A bend too tight for any gap in the band (a fixed camera in
    /// an 18 m turn needs less than 4.5 m) gives the band's minimum.
    pub fn view_limited_gap_m(&self, curvature: f32) -> Option<f32> {
        let kappa = f64::from(curvature.abs());
        if kappa < 1e-4 {
            return None;
        }
        let c = &self.config;
        let pan = if c.pan_head.enabled {
            c.pan_head.limit_deg
        } else {
            0.0
        };
        // Beyond 60° the small-angle geometry says nothing useful: no limit.
        let alpha = (f64::from((c.half_fov_deg - c.view_margin_deg).max(0.0)) + pan).to_radians();
        if alpha >= 60f64.to_radians() {
            return None;
        }
        let f = f64::from(c.camera_mount.forward_m.max(0.0));
        let b = alpha / kappa - f;
        let disc = b * b - f * f;
        if b <= 0.0 || disc < 0.0 {
            return Some(0.0);
        }
        Some((b + disc.sqrt()) as f32)
    }

    /// The pan head's aim and the rate commanded of it: at the bearing, from the camera's
    /// pivot, of the newest breadcrumb (the lead where the last estimate put it, placed in
    /// the world with the chase's pose at capture, so the chase's own turning since is
    /// taken out), with [`PanHeadConfig::rate_for_error`] on the encoder's reading. Without
    /// a head, or while the lead is lost, the head is held.
    fn aim_pan_head(&self, pose: &Pose, encoder_rad: f32) -> (f32, f32) {
        let c = &self.config;
        if !c.pan_head.enabled {
            return (0.0, 0.0);
        }
        let lead = match (self.trail.newest(), self.mode) {
            (Some(crumb), ChaseMode::Following) => crumb.position_world_m,
            _ => return (encoder_rad, 0.0),
        };
        let v = pose.inverse_transform_point(lead) - self.camera_pivot;
        if v.x.hypot(v.z) < 0.5 {
            return (encoder_rad, 0.0);
        }
        let limit = c.pan_head.limit_deg.to_radians() as f32;
        let aim = v.z.atan2(v.x).clamp(-limit, limit);
        let rate = c.pan_head.rate_for_error(f64::from(aim - encoder_rad));
        (aim, rate as f32)
    }

    fn log(&mut self, step: Step, kind: ControllerEventKind) {
        self.events.push(ControllerEvent { step, kind });
    }

    /// Whether an estimate of `status` is not followed and, following, starts the stop:
    /// `lost`, or with `stop_on_coasting` `coasting` too.
    fn stops_on(&self, status: TrackStatus) -> bool {
        status == TrackStatus::Lost
            || (self.config.stop_on_coasting && status == TrackStatus::Coasting)
    }

    /// Places the pending estimates in the world; returns whether a tracked (or, without
    /// `stop_on_coasting`, coasting) estimate of a target to follow (in the lane, with
    /// `lane_keeping`) arrived.
    fn absorb_pending(&mut self, now: Step, speed_mps: f32) -> bool {
        let mut fresh = false;
        let mut pending = std::mem::take(&mut self.pending);
        pending.sort_by_key(|e| e.capture_step);
        for estimate in pending {
            self.last_arrival = Some(now);
            self.last_status = Some(estimate.status);
            if estimate.status == TrackStatus::Lost {
                // Measurements taken towards a new target's first estimate are of it alone.
                self.range.restart_measuring();
                self.alarm_range.restart_measuring();
            }
            if self.stops_on(estimate.status) {
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
            // Stage 8's position is in the camera's frame as it was: turned by the pan
            // head's measured angle, not the true one, which nobody on board knows.
            let in_vehicle = self
                .config
                .camera_mount
                .vehicle_from_camera_panned(estimate.camera_pan_rad)
                .transform_point(estimate.target_in_camera_m);
            let camera = self.camera_pivot;
            let gap =
                ((in_vehicle.x - camera.x).powi(2) + (in_vehicle.z - camera.z).powi(2)).sqrt();
            let captured_s = estimate.capture_step.seconds();
            let position_world_m = world_from_chase.transform_point(in_vehicle);
            let chase_m = world_from_chase.translation;
            let verdict = self.judge_target(now, &estimate, chase_m, position_world_m, speed_mps);
            // A filter measuring a new target takes tracked estimates only, not predictions.
            let measured = estimate.status == TrackStatus::Tracking;
            if verdict != lane_keeping::Verdict::Ignore {
                if measured || !self.range.is_measuring() {
                    self.range.update(captured_s, gap, own);
                }
                if measured || !self.alarm_range.is_measuring() {
                    self.alarm_range.update(captured_s, gap, own);
                }
            }
            self.trail.drop_crumb(Breadcrumb {
                capture_step: estimate.capture_step,
                position_world_m,
            });
            fresh |= verdict == lane_keeping::Verdict::Follow;
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
        let fresh = self.absorb_pending(now, v);

        self.handle_loss(now, started, v, fresh);

        // Steering: pure pursuit on the breadcrumbs, or on the lane with lane keeping.
        let pose = odometry.world_from_chase;
        self.trail.eat_passed(&pose);
        // With it, where the path bends most between here and the lead (or the lane ahead),
        // for the gap below.
        let (target, curvature_ahead) = if self.config.lane_keeping {
            let target = self.lane_aim(&pose, v);
            (target, self.lane_curvature_ahead(v))
        } else {
            let path = self.trail.positions();
            let lookahead_m = self.config.lookahead.distance_m(v);
            (
                lookahead_point(&path, pose.translation, lookahead_m),
                max_curvature(&path, CURVATURE_CHORD_M),
            )
        };
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

        // What the path's bend allows of the gap; the pan head's aim.
        let view_limit_m = self
            .config
            .curve_aware_gap
            .then(|| self.view_limited_gap_m(curvature_ahead))
            .flatten();
        self.gap_keeper.set_view_limit(view_limit_m);
        let (pan_aim_rad, pan_rate_cmd_rad_s) = self.aim_pan_head(&pose, odometry.camera_pan_rad);
        let threat = self.alarm_threat(now, carried(self.alarm_range.state()), v);

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
                emergency = self.stop_in_emergency;
                self.stop_ref_mps = (self.stop_ref_mps - self.config.loss_decel_mps2 * dt).max(0.0);
                if emergency {
                    // The controlled stop that may follow starts from the speed left.
                    self.stop_ref_mps = self.stop_ref_mps.min(v.max(0.0));
                }
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
            ChaseMode::Cruising => self.lane.cruise_ref(&self.config, dt),
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
            curvature_ahead,
            pan_aim_rad,
            pan_rate_cmd_rad_s,
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
            camera_pan_rad: 0.0,
        }
    }

    /// A controller that drove 25 steps and was then handed an estimate captured at step
    /// 10 (chase at x = 1.0) with the camera panned by `pan_rad`, delivered at step 26.
    fn delivered(target_in_camera_m: Vector, pan_rad: f32) -> ChaseController {
        let params = VehicleParams::hmmwv_m998();
        let mut c = ChaseController::new(level_mount(), &params, 12.0).unwrap();
        for s in 0..=25 {
            c.update(&odometry(s));
        }
        c.receive(LeadEstimate {
            capture_step: Step(10),
            target_in_camera_m,
            status: TrackStatus::Tracking,
            camera_pan_rad: pan_rad,
        });
        c.update(&odometry(26));
        c
    }

    #[test]
    fn breadcrumbs_use_the_pose_at_capture_time() {
        // 10 m straight ahead of the camera and 1 m to its right.
        let c = delivered(Vector::new(1.0, 0.0, 10.0), 0.0);
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
            camera_pan_rad: 0.0,
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
                camera_pan_rad: 0.0,
            });
            c.update(&odometry(s));
        }
        // 5 s into a 5 -> 15 m/s ramp over 10 s.
        assert!((c.telemetry().speed_ref_mps - 10.0).abs() < 0.01);
    }

    #[test]
    fn an_estimate_from_a_panned_camera_is_turned_by_the_encoder_reading() {
        // The camera panned 90° right saw the target 10 m along its axis: 10 m to the
        // right of the camera.
        let c = delivered(Vector::new(0.0, 0.0, 10.0), std::f32::consts::FRAC_PI_2);
        let crumb = c.trail().newest().unwrap().position_world_m;
        let want = Vector::new(1.0 + 2.2, 2.0, 10.0);
        assert!(
            (crumb - want).length() < 1e-4,
            "crumb at {crumb}, want {want}"
        );
    }

    #[test]
    fn the_pan_head_is_aimed_at_the_lead() {
        let params = VehicleParams::hmmwv_m998();
        let config = ChaseControllerConfig {
            pan_head: PanHeadConfig {
                enabled: true,
                ..PanHeadConfig::default()
            },
            ..level_mount()
        };
        let mut c = ChaseController::new(config, &params, 12.0).unwrap();
        for s in 0..=25 {
            c.update(&odometry(s));
        }
        // A lead 10 m ahead of the camera and 10 m to its right: 45° right.
        c.receive(LeadEstimate {
            capture_step: Step(25),
            target_in_camera_m: Vector::new(10.0, 0.0, 10.0),
            status: TrackStatus::Tracking,
            camera_pan_rad: 0.0,
        });
        let mut o = odometry(26);
        o.world_from_chase = odometry(25).world_from_chase;
        c.update(&o);
        let t = c.telemetry();
        assert!(
            (t.pan_aim_rad - std::f32::consts::FRAC_PI_4).abs() < 1e-3,
            "{t:?}"
        );
        assert!(t.pan_rate_cmd_rad_s > 0.0, "{t:?}");
        // A fixed camera is never aimed.
        let mut fixed = ChaseController::new(level_mount(), &params, 12.0).unwrap();
        fixed.update(&odometry(0));
        assert_eq!(fixed.telemetry().pan_rate_cmd_rad_s, 0.0);
    }

    #[test]
    fn curvature_comes_from_the_path_s_geometry() {
        // A quarter circle of radius 18 m, a point every 0.25 m, after 20 m of straight.
        let mut path: Vec<Vector> = (0..80)
            .map(|k| Vector::new(k as f32 * 0.25, 0.0, 0.0))
            .collect();
        for k in 0..=113 {
            let a = k as f32 * 0.25 / 18.0;
            path.push(Vector::new(
                20.0 + 18.0 * a.sin(),
                0.0,
                18.0 * (1.0 - a.cos()),
            ));
        }
        let k = max_curvature(&path, 5.0);
        assert!((k - 1.0 / 18.0).abs() < 0.002, "κ {k}");
        assert!(max_curvature(&path[..80], 5.0) < 1e-6);
        assert_eq!(max_curvature(&path[..10], 5.0), 0.0);
    }

    #[test]
    fn the_view_limits_the_gap_in_a_bend() {
        let params = VehicleParams::hmmwv_m998();
        let c = ChaseController::new(level_mount(), &params, 7.0).unwrap();
        // Straight: no limit.
        assert_eq!(c.view_limited_gap_m(0.0), None);
        // An 18 m bend with the fixed camera (α = 15.8°): under 4.5 m.
        let tight = c.view_limited_gap_m(1.0 / 18.0).unwrap();
        assert!(tight > 3.5 && tight < 4.6, "{tight}");
        // At the limit the bearing formula gives α back.
        let kappa = 1.0f64 / 18.0;
        let (d, f) = (f64::from(tight), 2.2);
        let bearing = kappa * (d + f).powi(2) / (2.0 * d);
        assert!((bearing - 15.8f64.to_radians()).abs() < 1e-3, "{bearing}");
        // A gentle 120 m bend allows a longer gap.
        assert!(c.view_limited_gap_m(1.0 / 120.0).unwrap() > 50.0);
        // With a pan head there is no limit to speak of.
        let panned = ChaseController::new(
            ChaseControllerConfig {
                pan_head: PanHeadConfig {
                    enabled: true,
                    ..PanHeadConfig::default()
                },
                ..level_mount()
            },
            &params,
            7.0,
        )
        .unwrap();
        assert_eq!(panned.view_limited_gap_m(1.0 / 18.0), None);
    }
}
