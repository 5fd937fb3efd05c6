//! The one simulation clock: a whole number of fixed physics steps.
//!
//! Times are step counts turned into seconds, never accumulated floats (`docs/src/conventions.md`,
//! "One clock").

use serde::{Deserialize, Serialize};

/// Physics steps per second. 120 Hz divides the 15 Hz camera rate exactly.
pub const PHYSICS_HZ: u32 = 120;
/// Camera frames per second (the paper's vision system ran at 15 Hz).
pub const CAMERA_HZ: u32 = 15;
/// Physics steps in one camera frame: 120 / 15 = 8.
pub const STEPS_PER_FRAME: u32 = PHYSICS_HZ / CAMERA_HZ;
/// The physics step length in seconds (1/120 s).
pub const PHYSICS_DT_S: f32 = 1.0 / PHYSICS_HZ as f32;

/// A point on the simulation clock, counted in physics steps since the start.
#[derive(
    Copy,
    Clone,
    Debug,
    Default,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Serialize,
    Deserialize,
    schemars::JsonSchema,
)]
pub struct Step(pub u64);

impl Step {
    /// The start of the simulation.
    pub const ZERO: Step = Step(0);

    /// This time in seconds since the start.
    pub fn seconds(self) -> f64 {
        self.0 as f64 / f64::from(PHYSICS_HZ)
    }

    /// The step after this one.
    pub fn next(self) -> Step {
        Step(self.0 + 1)
    }

    /// This step moved `steps` later.
    pub fn plus(self, steps: u64) -> Step {
        Step(self.0 + steps)
    }

    /// Steps elapsed from `earlier` to `self`, zero if `earlier` is later.
    pub fn since(self, earlier: Step) -> u64 {
        self.0.saturating_sub(earlier.0)
    }

    /// Whether a camera frame is captured at this step (every [`STEPS_PER_FRAME`] steps).
    pub fn is_frame_start(self) -> bool {
        self.0.is_multiple_of(u64::from(STEPS_PER_FRAME))
    }

    /// The step nearest to `seconds` (rounded to the nearest step).
    pub fn from_seconds(seconds: f64) -> Step {
        Step((seconds.max(0.0) * f64::from(PHYSICS_HZ)).round() as u64)
    }
}

/// A duration in milliseconds turned into the nearest whole number of physics steps.
///
/// The quantisation error is at most half a step (4.2 ms at 120 Hz).
pub fn steps_from_ms(ms: f64) -> u64 {
    (ms.max(0.0) * f64::from(PHYSICS_HZ) / 1000.0).round() as u64
}

/// A whole number of physics steps in milliseconds.
pub fn ms_from_steps(steps: u64) -> f64 {
    steps as f64 * 1000.0 / f64::from(PHYSICS_HZ)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_has_eight_steps() {
        assert_eq!(STEPS_PER_FRAME, 8);
        assert!(Step(16).is_frame_start());
        assert!(!Step(17).is_frame_start());
    }

    #[test]
    fn latency_rounds_to_nearest_step() {
        // 128 ms = 15.36 steps -> 15 steps = 125 ms.
        assert_eq!(steps_from_ms(128.0), 15);
        assert_eq!(steps_from_ms(125.0), 15);
        assert_eq!(Step(120).seconds(), 1.0);
    }
}
