//! Where others plug in (ARCHITECTURE.md, "The plug-in boundary"): a [`FrameTracker`] stands
//! where the paper's tracker stands, a [`Controller`] where the built-in chase controller
//! stands, and the loop keeps everything else: the clock, the camera, the delay line with
//! its latency, jitter and drops, the physics, and the scoring against ground truth.
//!
//! A tracker sees a camera frame, its time and the camera model, never the truth. A
//! controller sees what came out of the delay line and the chase's own odometry, never the
//! image or the truth. Neither can see the future: a tracker's estimate of frame k reaches
//! the controller no sooner than the scenario's latency after frame k's capture, as the
//! built-in's do.
//!
//! The paper's tracker ([`BuiltinTracker`]) and the built-in controller
//! ([`BuiltinController`]) implement the traits; the loop runs them directly (see
//! [`TrackerChoice`]), so that a built-in run renders only the part of each frame the
//! tracker reads and records its diagnostics, and the same estimates come out either way.

mod builtin;
mod types;

pub(crate) use builtin::estimate_of;
pub use builtin::{BuiltinController, BuiltinTracker};
pub use types::{CameraModel, Command, ControlInput, Estimate, EstimateStatus, TrackerInput};

use thiserror::Error;
use tracker::PixelRect;

/// A plug-in's failure, which ends the run (see [`crate::LoopError::Plugin`]).
#[derive(Debug, Error)]
pub enum PluginError {
    /// The plug-in said what went wrong.
    #[error("{0}")]
    Failed(String),
    /// It returned something the loop cannot use (a range that is not finite, a throttle
    /// out of 0–1, ...).
    #[error("it returned {0}")]
    Invalid(String),
}

/// A tracker in the loop: one camera frame in, an estimate of the target out.
///
/// Called once per camera frame, in order, from one thread at a time. `reset` comes first,
/// once, with the camera and the scenario's starting estimate (the teleoperator's
/// placement of section 2.2, or `None` when the tracker must find the target itself).
pub trait FrameTracker: Send {
    /// A short name for reports (`summary.json`'s `tracker.name`).
    fn name(&self) -> String;

    /// Before the first frame: the camera, and where the target starts (if given).
    fn reset(&mut self, camera: &CameraModel, start: Option<&Estimate>) -> Result<(), PluginError> {
        let _ = (camera, start);
        Ok(())
    }

    /// One frame: the estimate, or `None` for no estimate this frame (coasting: the
    /// controller hears nothing new).
    fn track(&mut self, input: &TrackerInput<'_>) -> Result<Option<Estimate>, PluginError>;

    /// The pixels the next frame's [`FrameTracker::track`] will read, if it can say: the
    /// loop then renders only those (and the automatic gain control's metering window),
    /// which is faster; the rest of that frame is unspecified. `None`, the default, gets
    /// whole frames.
    fn will_read(&self) -> Option<PixelRect> {
        None
    }
}

/// A chase controller in the loop: what came through the delay line and the chase's own
/// state in, steering, throttle, brake and the pan head's rate out.
///
/// Called at every physics step (120 Hz, eight times a camera frame), in order.
pub trait Controller: Send {
    /// A short name for reports (`summary.json`'s `controller.name`).
    fn name(&self) -> String;

    /// The commands for this physics step.
    fn control(&mut self, input: &ControlInput) -> Result<Command, PluginError>;
}

/// Which tracker a loop runs.
pub enum TrackerChoice {
    /// The paper's tracker as the scenario sets it up (`[tracker]`, both modes), run
    /// directly by the loop: only the part of each frame it reads is rendered, and its
    /// diagnostics (confidences, coverage, σ², edge points) are recorded.
    Builtin,
    /// A plug-in; its columns of `frames.csv` that it cannot fill stay empty.
    Plugin(Box<dyn FrameTracker>),
}

/// Which controller a loop runs.
pub enum ControllerChoice {
    /// The built-in controller as the scenario sets it up (`[chase.controller]`): pure
    /// pursuit on breadcrumbs, the gap keeper, loss handling and the pan head's aim.
    Builtin,
    /// A plug-in.
    Plugin(Box<dyn Controller>),
}

impl std::fmt::Debug for TrackerChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TrackerChoice::Builtin => write!(f, "Builtin"),
            TrackerChoice::Plugin(t) => write!(f, "Plugin({})", t.name()),
        }
    }
}

impl std::fmt::Debug for ControllerChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ControllerChoice::Builtin => write!(f, "Builtin"),
            ControllerChoice::Plugin(c) => write!(f, "Plugin({})", c.name()),
        }
    }
}
