//! An actuator with a range, a first-order lag and a rate limit.

use serde::{Deserialize, Serialize};

/// How fast and how far one actuator can move.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ActuatorLimits {
    /// Lowest value (units of the actuator: radians for steering, 0..1 for pedals).
    pub min: f32,
    /// Highest value.
    pub max: f32,
    /// Largest change per second (units per second).
    pub rate_per_s: f32,
    /// First-order lag time constant, seconds (0 = none).
    pub lag_s: f32,
}

/// One actuator's state: it follows its command through a first-order lag, never faster than
/// its rate limit, and never outside its range.
#[derive(Clone, Debug, PartialEq)]
pub struct Actuator {
    limits: ActuatorLimits,
    value: f32,
}

impl Actuator {
    /// An actuator at rest at `initial` (clamped to its range).
    pub fn new(limits: ActuatorLimits, initial: f32) -> Actuator {
        Actuator {
            limits,
            value: initial.clamp(limits.min, limits.max),
        }
    }

    /// The actuator's present output.
    pub fn value(&self) -> f32 {
        self.value
    }

    /// The actuator's limits.
    pub fn limits(&self) -> &ActuatorLimits {
        &self.limits
    }

    /// Moves one step of `dt_s` seconds toward `command` and returns the new output.
    pub fn update(&mut self, command: f32, dt_s: f32) -> f32 {
        let target = if command.is_finite() {
            command.clamp(self.limits.min, self.limits.max)
        } else {
            self.value
        };
        let lag_fraction = if self.limits.lag_s > 0.0 {
            1.0 - (-dt_s / self.limits.lag_s).exp()
        } else {
            1.0
        };
        let max_delta = self.limits.rate_per_s * dt_s;
        let delta = ((target - self.value) * lag_fraction).clamp(-max_delta, max_delta);
        self.value = (self.value + delta).clamp(self.limits.min, self.limits.max);
        self.value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_limit_bounds_each_step() {
        let limits = ActuatorLimits {
            min: -0.5,
            max: 0.5,
            rate_per_s: 0.6,
            lag_s: 0.0,
        };
        let mut a = Actuator::new(limits, 0.0);
        let v = a.update(0.5, 0.1);
        assert!((v - 0.06).abs() < 1e-6, "{v}");
        for _ in 0..100 {
            a.update(2.0, 0.1);
        }
        assert_eq!(a.value(), 0.5);
    }

    #[test]
    fn lag_reaches_63_percent_after_one_time_constant() {
        let limits = ActuatorLimits {
            min: 0.0,
            max: 1.0,
            rate_per_s: 100.0,
            lag_s: 0.2,
        };
        let mut a = Actuator::new(limits, 0.0);
        for _ in 0..24 {
            a.update(1.0, 1.0 / 120.0);
        }
        assert!((a.value() - 0.632).abs() < 0.01, "{}", a.value());
    }
}
