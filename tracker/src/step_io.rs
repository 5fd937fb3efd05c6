//! What a step of the tracker takes besides the image ([`EgoMotion`]) and what it gives
//! ([`TrackOutput`], with its [`Status`] and [`TrackEvent`]), and why a tracker cannot be
//! built ([`TrackerError`]).

use crate::camera::Camera;
use crate::config::ConfigError;
use crate::feature_location::FeatureLocation;
use crate::location::Location;
use crate::object_location::Measurement;
use crate::window::Window;
use thiserror::Error;

/// What the tracker says of its own state after a frame. It judges from its own signals
/// only (support, the fit, the coverage of the located outline by edges), never the truth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// This frame gave a measurement that passed its checks.
    Tracking,
    /// No trusted measurement this frame; the prediction carries on.
    Coasting,
    /// No trusted measurement for `lost_after_s`: the estimate is not to be trusted. The
    /// tracker keeps looking and says `tracking` again when a measurement passes its checks.
    Lost,
}

impl Status {
    /// Lower-case name, as written in tables.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Tracking => "tracking",
            Status::Coasting => "coasting",
            Status::Lost => "lost",
        }
    }
}

/// Something a frame did that a log should show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TrackEvent {
    /// Robust mode found the target by searching the whole image, with no start given.
    Acquired,
    /// Robust mode found the target again by search after coasting or a loss.
    Reacquired,
    /// The target went beyond the tracker's resolution: two of its parallel features that
    /// compete for edge points came closer in the image than association tells apart
    /// (`tracker::resolvability`). The tracker goes on measuring, but stops saying
    /// `tracking` until the target is well resolved again.
    Unresolved,
}

impl TrackEvent {
    /// Whether the event is a find by search (an acquisition or re-acquisition).
    pub fn is_acquisition(self) -> bool {
        matches!(self, TrackEvent::Acquired | TrackEvent::Reacquired)
    }

    /// Lower-case name, as written in tables.
    pub fn as_str(self) -> &'static str {
        match self {
            TrackEvent::Acquired => "acquired",
            TrackEvent::Reacquired => "reacquired",
            TrackEvent::Unresolved => "unresolved",
        }
    }
}

/// The chase camera's own rotation between the previous frame and this one, from the
/// vehicle's gyro (robust mode's ego-motion aided prediction). The paper's mode ignores it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EgoMotion {
    /// Rotation vector (axis times angle, radians) that takes the previous frame's camera
    /// orientation to this frame's, in the previous camera frame (x right, y down, z
    /// forward): +y turns the camera right, +x tilts it up.
    pub rotation_rad: [f64; 3],
}

impl EgoMotion {
    /// How far a point seen at `at` moves in the image of `camera` when the camera turns
    /// by this rotation, pixels: its ray in the old camera frame, rotated into the new one
    /// (R⁻¹), projected again. Zero for a rotation that is not finite or that turns the
    /// point behind the camera.
    pub fn image_shift(&self, camera: &Camera, at: Location) -> [f64; 2] {
        let [fx, fy] = camera.focal_px();
        let [cx, cy] = camera.image_center_px;
        let ray = [(at.c_x - cx) / fx, (at.c_y - cy) / fy, 1.0];
        let r = self.rotation_rad;
        if !r.iter().all(|v| v.is_finite()) {
            return [0.0; 2];
        }
        // R⁻¹ is the rotation by −r (Rodrigues' formula).
        let seen = rotate(ray, [-r[0], -r[1], -r[2]]);
        if seen[2] <= 1e-6 {
            return [0.0; 2];
        }
        [
            cx + fx * seen[0] / seen[2] - at.c_x,
            cy + fy * seen[1] / seen[2] - at.c_y,
        ]
    }
}

/// Everything the tracker made of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackOutput {
    /// Frame index, from 0 since the last (re)initialisation.
    pub frame: u64,
    /// The frame's time, seconds, as given to [`crate::Tracker::step`].
    pub t_s: f64,
    /// Tracking, coasting or lost.
    pub status: Status,
    /// The stage-4 measurement with its confidences, when there was one.
    pub measurement: Option<Measurement>,
    /// The location predicted for this frame (stage 6 of the previous cycle), against which
    /// the edges were associated.
    pub predicted: Location,
    /// The best estimate of the target in this frame: the measurement when there was one,
    /// otherwise the prediction.
    pub estimate: Location,
    /// Stage 6: the location predicted for the next frame (eq. 34).
    pub next: Location,
    /// Stage 8 (eq. 36): the target's position in the camera frame (metres: x right, y down,
    /// z forward), from `estimate`.
    pub position_3d: [f64; 3],
    /// The window of interest used for stage 1.
    pub window: Window,
    /// Stages 3 and 7 for every feature, in the model's segment order.
    pub features: Vec<FeatureLocation>,
    /// The share of the measured outline covered by edge points, `[horizontal, vertical]`
    /// (0 without a measurement): the check that decides whether it is trusted.
    pub coverage: [f64; 2],
    /// The track's reference coverage this frame was judged against (see
    /// [`crate::robust::CoverageReference`]), before this frame; `None` before the first
    /// trusted measurement.
    pub coverage_reference: Option<f64>,
    /// How much more of the outline a move of a few pixels would cover (see
    /// [`crate::robust::coverage_gain`]): above a small margin, the fit is not on the
    /// target's edges. −∞ where it was not needed: a fit covered at least
    /// [`crate::robust::SEARCH_BELOW_COVERAGE`] in both orientations.
    pub coverage_gain: f64,
    /// The edge threshold used, on eq. 4's |∇f| in grey levels per pixel (the paper's 8, or
    /// robust mode's adaptive one).
    pub edge_threshold: f64,
    /// Whether a chamfer search ran this frame (robust mode).
    pub searched: bool,
    /// Acquisition or re-acquisition, when it happened this frame.
    pub event: Option<TrackEvent>,
}

/// A tracker that cannot be built.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum TrackerError {
    /// A setting is out of range.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The initial location is not finite or has a non-positive scale.
    #[error("initial location ({}, {}, scale {}) is not valid: the position must be finite and the scale positive", .0.c_x, .0.c_y, .0.scale)]
    BadInit(Location),
    /// Only robust mode can start without a location.
    #[error("the paper's tracker starts from the teleoperator's placement (2.2): give an initial location, or use robust mode, which searches for the target")]
    NeedsInit,
}

/// `v` rotated by the rotation vector `r` (axis times angle, radians): Rodrigues' formula.
fn rotate(v: [f64; 3], r: [f64; 3]) -> [f64; 3] {
    let angle = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    if angle < 1e-15 {
        return v;
    }
    let k = [r[0] / angle, r[1] / angle, r[2] / angle];
    let (s, c) = angle.sin_cos();
    let kxv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kdv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    [0, 1, 2].map(|i| v[i] * c + kxv[i] * s + k[i] * kdv * (1.0 - c))
}
