//! What passes between the loop and its plug-ins.

use super::{LaneAhead, PluginError};
use tracker::{Camera, EdgeDiagnostic, GrayView, PixelRect, TargetModel, TrackOutput};

/// What a tracker knows of its camera and its target: the intrinsics (those of stage 8,
/// eq. 36), the image size, the mount on the chase vehicle, the pan head's encoder reading
/// at the frame's capture, and the target model (section 2.1.1's static model: its
/// features and physical size at the nominal range).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraModel {
    /// Focal length, pixel size and principal point (pixel centres at integer coordinates).
    pub intrinsics: Camera,
    /// Image width, pixels (256).
    pub width: u32,
    /// Image height, pixels (242).
    pub height: u32,
    /// The camera's height above the ground, metres.
    pub mount_height_m: f64,
    /// How far ahead of the chase's rear axle the camera sits, metres.
    pub mount_forward_m: f64,
    /// How far the camera is pitched down, degrees.
    pub mount_pitch_down_deg: f64,
    /// The pan head's encoder reading at the frame's capture, radians, positive to the
    /// right (0 for a fixed camera).
    pub pan_rad: f64,
    /// The target on the lead's back.
    pub target: TargetModel,
}

/// A tracker's status for one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EstimateStatus {
    /// The target was measured in this frame.
    Tracking,
    /// Not measured in this frame; the estimate is a prediction.
    Coasting,
    /// The tracker says it has lost the target: the controller discards the estimate.
    Lost,
}

impl EstimateStatus {
    /// Lower-case name, as written in tables (`tracking`, `coasting`, `lost`).
    pub fn as_str(self) -> &'static str {
        match self {
            EstimateStatus::Tracking => "tracking",
            EstimateStatus::Coasting => "coasting",
            EstimateStatus::Lost => "lost",
        }
    }

    /// The status named `text` (as [`EstimateStatus::as_str`] writes it).
    pub fn parse(text: &str) -> Option<EstimateStatus> {
        [
            EstimateStatus::Tracking,
            EstimateStatus::Coasting,
            EstimateStatus::Lost,
        ]
        .into_iter()
        .find(|s| s.as_str() == text)
    }
}

impl From<tracker::Status> for EstimateStatus {
    fn from(s: tracker::Status) -> EstimateStatus {
        match s {
            tracker::Status::Tracking => EstimateStatus::Tracking,
            tracker::Status::Coasting => EstimateStatus::Coasting,
            tracker::Status::Lost => EstimateStatus::Lost,
        }
    }
}

/// Where a tracker puts the target, in the camera's frame (x right, y down, z forward,
/// metres), with its image location where it has one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Distance ahead along the optical axis, metres (z; stage 8's z).
    pub range_m: f64,
    /// Offset to the right, metres (x).
    pub lateral_m: f64,
    /// Offset downwards, metres (y). `None`: from `cy` when given (eq. 36), else on the
    /// optical axis (0).
    pub vertical_m: Option<f64>,
    /// The target's centre in the image, pixels (x), where the tracker has it.
    pub cx: Option<f64>,
    /// The target's centre in the image, pixels (y).
    pub cy: Option<f64>,
    /// The target's size relative to its size at the nominal range (section 2.1.2).
    pub scale: Option<f64>,
    /// How sure the tracker is.
    pub status: EstimateStatus,
    /// Which vehicle the tracker says it holds, where it knows: its place in the scenario's
    /// vehicle list, 1 for the lead and 2 + k for the k-th `[[actors]]` entry (1 + k in a
    /// scenario without a lead: the order of the truth's `vehicles`; 0, the chase, is never
    /// a target). `None`: the tracker does
    /// not say, and the loop's truth takes the vehicle whose target the estimate lies on.
    pub vehicle: Option<usize>,
}

impl Estimate {
    /// An estimate of the target at `range_m` ahead and `lateral_m` to the right, tracking.
    pub fn new(range_m: f64, lateral_m: f64) -> Estimate {
        Estimate {
            range_m,
            lateral_m,
            vertical_m: None,
            cx: None,
            cy: None,
            scale: None,
            status: EstimateStatus::Tracking,
            vehicle: None,
        }
    }

    /// Checks what the loop relies on: a finite range ahead of the camera, finite offsets,
    /// and finite image figures where given (a positive scale).
    pub fn validate(&self) -> Result<(), PluginError> {
        let bad = |what: String| Err(PluginError::Invalid(what));
        if !(self.range_m.is_finite() && self.range_m > 0.0) {
            return bad(format!(
                "range_m = {}: must be finite and > 0",
                self.range_m
            ));
        }
        for (name, v) in [
            ("lateral_m", Some(self.lateral_m)),
            ("vertical_m", self.vertical_m),
            ("cx", self.cx),
            ("cy", self.cy),
        ] {
            if let Some(v) = v.filter(|v| !v.is_finite()) {
                return bad(format!("{name} = {v}: must be finite"));
            }
        }
        if let Some(s) = self.scale.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return bad(format!("scale = {s}: must be finite and > 0"));
        }
        Ok(())
    }

    /// The target's position in the camera frame, metres `[x, y, z]`: `vertical_m`, or
    /// from `cy` by eq. 36 with `camera`'s intrinsics, or 0.
    pub fn position_m(&self, camera: &Camera) -> [f64; 3] {
        let y = self.vertical_m.unwrap_or_else(|| {
            self.cy.map_or(0.0, |cy| {
                (cy - camera.image_center_px[1]) * self.range_m / camera.focal_px()[1]
            })
        });
        [self.lateral_m, y, self.range_m]
    }
}

/// One frame, for a tracker.
#[derive(Clone, Copy, Debug)]
pub struct TrackerInput<'a> {
    /// The camera frame: 8-bit grey, row-major, `camera.width × camera.height` (only the
    /// part [`super::FrameTracker::will_read`] asked for is sure to be rendered).
    pub frame: GrayView<'a>,
    /// Its capture time, seconds (frame k at k / 15 s).
    pub t_s: f64,
    /// The camera at capture.
    pub camera: &'a CameraModel,
    /// The chase's rate gyro: the camera's rotation since the previous frame, radians,
    /// as a rotation vector in the previous camera frame (+y turns the camera right, +x
    /// tilts it up), with the gyro's bias and noise; `None` on the first frame.
    pub gyro_rad: Option<[f64; 3]>,
    /// The chase's own lane ahead at capture, in traffic (`None` without traffic): where a
    /// tracker should look for the vehicle to follow.
    pub lane: Option<&'a LaneAhead>,
    /// The chase's odometer: its speed over the ground at capture, m/s (`None` where it is
    /// not known, as in a tracker stepped from Python on frames alone). A vehicle ahead
    /// cannot close on the chase faster than the chase drives.
    pub speed_mps: Option<f64>,
}

/// One physics step, for a controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlInput {
    /// The latest estimate the delay line has delivered (`None` before the first).
    pub estimate: Option<Estimate>,
    /// Whether `estimate` arrived at this step.
    pub fresh: bool,
    /// The capture time of `estimate`'s frame, seconds.
    pub captured_t_s: Option<f64>,
    /// The pan head's encoder reading at `estimate`'s capture, radians: its camera frame is
    /// the mount's turned by this (0 for a fixed camera).
    pub captured_pan_rad: Option<f64>,
    /// The time now, seconds (a multiple of 1/120 s).
    pub t_s: f64,
    /// The chase's own pose by its odometry: its rear axle on the ground in the world
    /// frame (y up; the vehicle frame x forward, y up, z right; rapier's f32 pose).
    pub world_from_chase: vehicle::Pose,
    /// The chase's forward speed, m/s.
    pub speed_mps: f64,
    /// The chase's yaw rate, rad/s (positive turning right).
    pub yaw_rate_rad_s: f64,
    /// The chase's road-wheel steering angle now, radians (positive to the right).
    pub steering_rad: f64,
    /// The pan head's encoder reading, radians (0 for a fixed camera).
    pub pan_rad: f64,
}

/// A controller's commands for one physics step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Command {
    /// Road-wheel steering angle asked for, radians, positive to the right (the steering
    /// actuator follows it at its own rate, up to full lock).
    pub steering_rad: f64,
    /// Throttle, 0–1.
    pub throttle: f64,
    /// Brake, 0–1.
    pub brake: f64,
    /// The pan head's rate asked for, rad/s (ignored without a pan head).
    pub pan_rate_rad_s: f64,
}

impl Command {
    /// Checks what the loop relies on: finite values, throttle and brake in 0–1.
    pub fn validate(&self) -> Result<(), PluginError> {
        for (name, v) in [
            ("steering_rad", self.steering_rad),
            ("pan_rate_rad_s", self.pan_rate_rad_s),
        ] {
            if !v.is_finite() {
                return Err(PluginError::Invalid(format!(
                    "{name} = {v}: must be finite"
                )));
            }
        }
        for (name, v) in [("throttle", self.throttle), ("brake", self.brake)] {
            if !(0.0..=1.0).contains(&v) {
                return Err(PluginError::Invalid(format!("{name} = {v}: must be 0–1")));
            }
        }
        Ok(())
    }
}

/// What a tracker made of a frame drawn only in part (see
/// [`super::FrameTracker::track_drawn`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drawn {
    /// Tracked: the estimate, or `None` for none this frame.
    Tracked(Option<Estimate>),
    /// Not tracked: the tracker needs these pixels too, and is back in its state before
    /// the frame.
    Needs(PixelRect),
}

/// What a tracker's step made beyond its estimate (see
/// [`super::FrameTracker::take_details`]).
#[derive(Clone, Debug)]
pub struct StepDetails {
    /// The paper's tracker's whole output (stages 1–8).
    pub output: TrackOutput,
    /// The pixels the step read.
    pub read: PixelRect,
    /// Its edge points' fates, when diagnostics are on.
    pub edges: Vec<EdgeDiagnostic>,
}

/// An estimate as the delay line delivers it to a controller (see
/// [`super::Controller::receive`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Delivered {
    /// The estimate.
    pub estimate: Estimate,
    /// Where it puts the target in the camera frame, metres `[x, y, z]`
    /// ([`Estimate::position_m`] with the camera's intrinsics).
    pub position_m: [f64; 3],
    /// Its frame's capture time, seconds.
    pub captured_t_s: f64,
    /// The pan head's encoder reading at that capture, radians (0 for a fixed camera).
    pub captured_pan_rad: f64,
}
