//! What the closed loop records: one [`FrameRecord`] per camera frame, holding the truth,
//! the tracker's estimate and status, the gap and the controls. Only the recorder sees
//! everything, and it only reads.

use serde::{Deserialize, Serialize};

/// The tracker's own view of its state, as recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackerStatus {
    /// A usable measurement this frame.
    Tracking,
    /// No measurement; the prediction carries on.
    Coasting,
    /// The tracker says it has lost the target.
    Lost,
}

impl TrackerStatus {
    /// Lower-case name.
    pub fn as_str(self) -> &'static str {
        match self {
            TrackerStatus::Tracking => "tracking",
            TrackerStatus::Coasting => "coasting",
            TrackerStatus::Lost => "lost",
        }
    }
}

impl From<tracker::Status> for TrackerStatus {
    fn from(s: tracker::Status) -> Self {
        match s {
            tracker::Status::Tracking => TrackerStatus::Tracking,
            tracker::Status::Coasting => TrackerStatus::Coasting,
            tracker::Status::Lost => TrackerStatus::Lost,
        }
    }
}

/// Why ground truth judges a frame lost (see [`FrameRecord::lost_truth`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LossCause {
    /// Not lost.
    #[default]
    None,
    /// The target is wholly or partly outside the image, and the estimate is off.
    OutOfView,
    /// The target is in the image, but scenery stands between it and the camera
    /// (`camera::target_occluded`).
    Occluded,
    /// The target is in view and not hidden: the tracker lost it.
    Tracker,
    /// In traffic: the vehicle held was the one in the chase's path, and has left it.
    LeftPath,
    /// In traffic: the vehicle held has never been the one in the chase's path.
    WrongVehicle,
    /// Not yet acquired: the tracker started with nothing placed (`tracker.start =
    /// "search"`) and has not held the target (in traffic, the vehicle in the chase's path)
    /// since, and does not say `tracking`. The estimate is not on it
    /// ([`FrameRecord::lost_truth`] is true), but the method has yet to find it, so reports
    /// count the frame apart (`not_acquired_s`), not as a lost track. A tracker that says
    /// `tracking` off the target before it has held it has lost it, as after: a silent
    /// loss. After the first acquisition a loss is a loss.
    NotAcquired,
    /// The target is in view and not hidden, but too faint for the paper's edge
    /// threshold in the pixels the tracker read: less than half its outline steps
    /// `2 × tracker.edge_threshold` grey levels (fog, the dark, a deep shadow). Judged on
    /// the model of the vehicle the frame is judged against (the lead's board; in traffic
    /// the path vehicle's), in the pixels the built-in tracker says it read.
    LowContrast,
}

impl LossCause {
    /// The name written in `frames.csv` and `summary.json` (empty for [`LossCause::None`]).
    pub fn as_str(self) -> &'static str {
        match self {
            LossCause::None => "",
            LossCause::OutOfView => "out_of_view",
            LossCause::Occluded => "occluded",
            LossCause::Tracker => "tracker",
            LossCause::LeftPath => "left_path",
            LossCause::WrongVehicle => "wrong_vehicle",
            LossCause::NotAcquired => "not_acquired",
            LossCause::LowContrast => "low_contrast",
        }
    }

    /// Whether a frame judged lost by the ground truth (`lost_truth`) with this cause
    /// counts as a lost track: every cause but [`LossCause::NotAcquired`].
    pub fn is_track_loss(self) -> bool {
        self != LossCause::NotAcquired
    }

    /// The causes of a loss, in the order reports list them (not
    /// [`LossCause::NotAcquired`], which is no lost track).
    pub const ALL: [LossCause; 6] = [
        LossCause::OutOfView,
        LossCause::Occluded,
        LossCause::LowContrast,
        LossCause::Tracker,
        LossCause::LeftPath,
        LossCause::WrongVehicle,
    ];
}

/// One camera frame of a closed-loop run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    /// Frame index from 0.
    pub frame: u64,
    /// Capture time, seconds (from the physics step count).
    pub t_s: f64,

    /// True target centre in the image, pixels.
    pub true_cx: f64,
    /// True target centre in the image, pixels.
    pub true_cy: f64,
    /// True scale (nominal range / true range).
    pub true_scale: f64,
    /// True range, camera to target along the optical axis, metres.
    pub true_range_m: f64,
    /// True lateral offset of the target in the camera frame (x right), metres.
    pub true_lateral_m: f64,
    /// Whether the whole target is in the camera's view (every corner inside the image).
    pub target_in_view: bool,
    /// Whether the target is partly out of view: some of it inside the image, not all. A
    /// frame partly out of view is judged like any other (lost only when the estimate is
    /// off); its loss, if any, is put down to [`LossCause::OutOfView`].
    pub target_partly_out_of_view: bool,

    /// Tracker's estimate of the centre, pixels (measurement, else prediction).
    pub est_cx: f64,
    /// Tracker's estimate of the centre, pixels.
    pub est_cy: f64,
    /// Tracker's estimated scale.
    pub est_scale: f64,
    /// Stage-8 range, metres.
    pub est_range_m: f64,
    /// Stage-8 lateral offset, metres.
    pub est_lateral_m: f64,
    /// Eq. 17 confidences (w_x, w_y, w_scale); zero without a measurement.
    pub confidence: [f64; 3],
    /// The tracker's own status.
    pub status: TrackerStatus,
    /// Ground truth's judgement: there is no estimate, or it is off by more than a quarter
    /// of the target's width in position, or by more than 25 % in scale. Where the target
    /// is wholly or partly out of view the same holds: a target partly outside the image but
    /// tracked within that tolerance is not lost.
    pub lost_truth: bool,

    /// Following distance, metres: the true horizontal distance from the chase camera to the
    /// lead's target board.
    pub gap_m: f64,
    /// Chase vehicle's forward speed, m/s.
    pub chase_speed_mps: f64,
    /// Lead vehicle's forward speed, m/s.
    pub lead_speed_mps: f64,
    /// Chase steering angle (front wheels), radians, positive left.
    pub steering_rad: f64,
    /// Chase throttle, 0–1.
    pub throttle: f64,
    /// Chase brake, 0–1.
    pub brake: f64,
    /// Distance of the chase vehicle from the path the lead actually drove, metres.
    pub lateral_deviation_m: f64,
    /// Distance the chase vehicle has driven since the start, metres.
    pub chase_distance_m: f64,
    /// Chase position on the ground (world x, z), metres.
    pub chase_xz: [f64; 2],
    /// Lead position on the ground (world x, z), metres.
    pub lead_xz: [f64; 2],
    /// The vehicles touched during this frame.
    pub collision: bool,
    /// The chase controller's mode ("following", "stopping", "stopped", or with lane
    /// keeping and a cruise speed "cruising").
    pub chase_mode: String,
    /// The share of the measured outline covered by edges, `[horizontal, vertical]`: the
    /// tracker's own check of its measurement (0 without one).
    pub coverage: [f64; 2],
    /// How much more of the outline a move of a few pixels would cover: the tracker's check
    /// that its fit sits on the target's edges.
    pub coverage_gain: f64,
    /// `acquired` or `reacquired` on a frame where robust mode found the target by search;
    /// empty otherwise.
    pub tracker_event: String,
    /// J_l of eq. 15 at the stage-4 fit (before any floor); NaN without a measurement.
    pub fit_residual: f64,
    /// σ² of eq. 13 for each feature, in the model's segment order, pixels²; NaN where no
    /// point was associated.
    pub feature_sigma2: Vec<f64>,
    /// Why the frame is lost by the ground truth ([`LossCause::None`] when it is not).
    pub loss_cause: LossCause,
    /// The camera's pan, degrees, positive to the right (0 for a fixed camera): the pan
    /// head's true angle.
    pub camera_pan_deg: f64,
    /// The gap the chase controller aimed for, metres (its policy, the view limit in bends
    /// and the safe gap; see `vehicle::GapKeeper`).
    pub desired_gap_m: f64,
    /// A false alarm, the dual of a silent loss: the tracker did not say `tracking`, though
    /// its estimate was within the ground truth's tolerance ([`FrameRecord::lost_truth`] is
    /// false) of a target wholly in view and not hidden by scenery. A car that trusts its
    /// tracker's word brakes for nothing on such a frame.
    #[serde(default)]
    pub false_alarm: bool,
    /// The traffic's truth at the frame, when the scenario has traffic (other vehicles, or
    /// events): `None` otherwise, and then left out of every output.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traffic: Option<TrafficFrame>,
}

/// The traffic's truth at a frame's capture, and what happened in the physics since the
/// frame before (events, contacts).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrafficFrame {
    /// The vehicle in the chase's path: the nearest ahead of it whose body reaches into the
    /// chase's lane corridor (see `sim_core::PathCorridor`); `None` with the road clear.
    pub path_vehicle: Option<String>,
    /// The gap to it along the road, bumper to bumper, metres (NaN without one).
    pub path_gap_m: f64,
    /// The chase's speed towards it, m/s (positive closing; NaN without one).
    pub path_closing_mps: f64,
    /// The true range to its target (the lead's board, an actor's back) along the camera's
    /// axis, metres (NaN without one). For the summary; in no file.
    #[serde(skip, default = "nan")]
    pub path_range_m: f64,
    /// Time to collision with it, seconds: the gap over the closing speed while closing
    /// (infinite when not closing, NaN without one).
    pub path_ttc_s: f64,
    /// The vehicle whose target (the lead's board, an actor's back) the tracker's estimate
    /// lies on, by the ground truth's tolerance (the nearest in the image, should two be);
    /// `None` otherwise.
    pub tracked_vehicle: Option<String>,
    /// Events that started or ended in the physics since the previous frame, in order, as
    /// `vehicle/event:started` or `vehicle/event:ended`.
    pub events: Vec<String>,
    /// The first contacts of the chase with another vehicle since the previous frame.
    pub contacts: Vec<Contact>,
    /// Every vehicle, in the run's order (`chase`, `lead`, the actors).
    pub vehicles: Vec<VehicleTruth>,
}

/// Not a number: the default of a value that is in no file.
fn nan() -> f64 {
    f64::NAN
}

/// A contact's first step: what the chase touched, and how fast it was closing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// The vehicle touched.
    pub vehicle: String,
    /// When, seconds.
    pub t_s: f64,
    /// The speed of the chase towards it along the road as they came into contact (at the
    /// start of the physics step that made it), m/s.
    pub closing_mps: f64,
}

/// One vehicle's truth at a frame's capture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VehicleTruth {
    /// Its name (`chase`, `lead`, or the actor's).
    pub name: String,
    /// What it is (`hmmwv`, `pickup`, or the actor's kind).
    pub kind: String,
    /// Its rear axle on the ground (world x, z), metres.
    pub xz: [f64; 2],
    /// Its heading, radians (the world's yaw: positive turns left).
    pub heading_rad: f64,
    /// Its forward speed, m/s.
    pub speed_mps: f64,
    /// Its rear axle's station along the route, metres.
    pub station_m: f64,
    /// Its lateral offset from the route's lane 1 centre, metres (positive left).
    pub offset_m: f64,
}
