//! Events the chase controller reports: loss, stops, resumption, discarded estimates.

use crate::clock::Step;
use serde::{Deserialize, Serialize};

/// What happened.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ControllerEventKind {
    /// The tracker reported the lead lost: braking to a stop.
    TrackLost,
    /// No estimate arrived for `silent_ms`: braking to a stop.
    EstimateTimeout {
        /// Time since the last estimate arrived, ms.
        silent_ms: f64,
    },
    /// The gap closed faster than comfort braking can handle: full brake.
    EmergencyBrake {
        /// Measured gap when it started, m.
        gap_m: f32,
    },
    /// The vehicle came to a stop after a loss.
    Stopped,
    /// Tracking came back: following again. With lane keeping, also a target tracked in the
    /// lane after cruising, the first one included.
    Resumed,
    /// Stopped after a loss for `resume_after_s`: cruising again, as a driver resuming an
    /// adaptive cruise control.
    CruiseResumed,
    /// An estimate was discarded: its capture time is older than the pose history.
    EstimateTooOld {
        /// Its capture step.
        capture_step: Step,
    },
    /// With lane keeping, the followed target's estimates lay outside the chase's lane for
    /// `LEFT_LANE_ARRIVALS` arrivals in a row: it is no longer followed, and the chase cruises
    /// or, without a cruise speed, brakes to a stop.
    TargetLeftLane {
        /// The last estimate's offset from the lane's centre line, m (positive to the left).
        offset_m: f32,
    },
}

/// One event with its time.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ControllerEvent {
    /// When it happened.
    pub step: Step,
    /// What happened.
    pub kind: ControllerEventKind,
}
