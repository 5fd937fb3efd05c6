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
//! ([`BuiltinController`]) implement the traits, and the loop runs them through the traits
//! as it runs any plug-in. What they do beyond a plug-in's minimum goes through the traits'
//! optional methods, open to any plug-in: a tracker may say it needs more of a frame drawn
//! only in part ([`FrameTracker::track_drawn`]), and give its step's details for the
//! records ([`FrameTracker::take_details`]); a controller may hear every estimate the
//! delay line delivers ([`Controller::receive`]).

mod acquisition;
mod builtin;
mod closing;
mod lane;
mod types;

pub use builtin::{BuiltinController, BuiltinTracker};
pub use lane::LaneAhead;
pub use types::{
    CameraModel, Command, ControlInput, Delivered, Drawn, Estimate, EstimateStatus, StepDetails,
    TrackerInput,
};

use thiserror::Error;
use tracker::{PixelRect, TargetModel};
use vehicle::ChaseController;

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

    /// Before [`FrameTracker::reset`], in traffic: the targets of the other vehicles that
    /// may come to be in the chase's path (each kind's back, `scenarios/targets/`), besides
    /// [`CameraModel::target`]. A tracker may acquire any of them when it holds nothing;
    /// the default ignores them.
    fn set_other_targets(&mut self, targets: &[TargetModel]) {
        let _ = targets;
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

    /// Whether the step `ahead` frames on (1: the next frame's) will read no pixels at
    /// all, if it can say: the loop then renders none of that frame but the automatic gain
    /// control's metering window. A tracker that turns out to read some after all asks for
    /// them ([`FrameTracker::track_drawn`]). The default: `false`.
    fn will_rest(&self, ahead: u64) -> bool {
        let _ = ahead;
        false
    }

    /// Whether the step `ahead` frames on (1: the next frame's) is likely to read the whole
    /// frame (a search), if it can say: the loop then renders that frame whole rather than
    /// the part [`FrameTracker::will_read`] names, sparing a frame drawn in part and drawn
    /// again ([`FrameTracker::track_drawn`]). A guess: it changes no result, only the time
    /// spent rendering. The default: `false`.
    fn may_read_whole(&self, ahead: u64) -> bool {
        let _ = ahead;
        false
    }

    /// Whether the tracker reads [`TrackerInput::gyro_rad`] (the default): the loop reads
    /// the chase's gyro only for a tracker that does.
    fn reads_gyro(&self) -> bool {
        true
    }

    /// One frame drawn only in part: `input.frame` holds the camera's pixels within
    /// `drawn`, the rest is unspecified. A tracker that finds it needs pixels beyond
    /// `drawn` goes back to its state before the frame and returns [`Drawn::Needs`] with
    /// them; the loop draws more of the frame and calls again, at last with the whole
    /// frame, of which no more may be asked. The default tracks the frame as it is
    /// ([`FrameTracker::track`]): a plug-in is drawn what [`FrameTracker::will_read`]
    /// asked for.
    fn track_drawn(
        &mut self,
        input: &TrackerInput<'_>,
        drawn: PixelRect,
    ) -> Result<Drawn, PluginError> {
        let _ = drawn;
        self.track(input).map(Drawn::Tracked)
    }

    /// Asks for each step's edge points' fates in [`StepDetails::edges`] (for the overlay
    /// and recordings). A tracker without them ignores it (the default).
    fn set_diagnostics(&mut self, on: bool) {
        let _ = on;
    }

    /// What the last step made beyond its estimate, once: the paper's tracker's stages
    /// 1–8, the pixels it read and its edge points' fates, for the records. `None`, the
    /// default, for a tracker that says no more.
    fn take_details(&mut self) -> Option<StepDetails> {
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

    /// Each estimate the delay line delivers, in the order delivered, before
    /// [`Controller::control`] at that step: with jitter several can arrive at one step,
    /// and [`ControlInput::estimate`] holds only the latest by capture time. The default
    /// does nothing with them.
    fn receive(&mut self, delivered: &Delivered) {
        let _ = delivered;
    }

    /// The built-in controller's state (its mode, telemetry and events log), for the
    /// records; `None`, the default, for any other controller.
    fn chase_controller(&self) -> Option<&ChaseController> {
        None
    }
}

/// Which tracker a loop runs.
pub enum TrackerChoice {
    /// The paper's tracker as the scenario sets it up (`[tracker]`, both modes): a
    /// [`BuiltinTracker`], which has only the part of each frame it reads rendered, and its
    /// diagnostics (confidences, coverage, σ², edge points) recorded.
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
