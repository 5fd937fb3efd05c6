//! What the chase controller is told about the lead: a 3-D position in the camera frame,
//! when its frame was captured, and how sure the tracker is.

use crate::clock::Step;
use rapier3d::math::Vector;
use serde::{Deserialize, Serialize};

/// The tracker's status for one frame.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TrackStatus {
    /// The target was measured in this frame.
    Tracking,
    /// Not measured in this frame; the position is the tracker's prediction.
    Coasting,
    /// The tracker has lost the target; the position means nothing.
    Lost,
}

/// The lead's position as the tracker's stage 8 gives it for one captured frame.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LeadEstimate {
    /// The physics step at which the frame was captured.
    pub capture_step: Step,
    /// The tracked target on the lead, in the camera frame (x right, y down, z forward), m.
    pub target_in_camera_m: Vector,
    /// The tracker's status.
    pub status: TrackStatus,
    /// The pan head's encoder reading when the frame was captured, radians (positive to
    /// the right; 0 for a fixed camera): stage 8's camera frame turned by it is the
    /// mount's frame.
    pub camera_pan_rad: f32,
}
