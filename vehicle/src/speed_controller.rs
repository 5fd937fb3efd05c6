//! Longitudinal control: a speed reference and its acceleration in, throttle and brake out.
//!
//! Feedforward of mass × acceleration plus the modelled resistance, with a PI correction on
//! the speed error. Shared by the lead driver and the chase controller.

use crate::vehicle_params::VehicleParams;
use serde::{Deserialize, Serialize};

/// Below this speed reference the vehicle is asked to stand still, m/s.
const STANDSTILL_REF_MPS: f32 = 0.05;
/// Below this speed a vehicle asked to stand still holds its brake, m/s.
const STANDSTILL_MPS: f32 = 0.3;
/// Brake held at standstill, 0..1 (enough to hold on the gentle bumps).
const HOLD_BRAKE: f32 = 0.4;

/// Gains of the speed loop.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpeedGains {
    /// Acceleration asked per m/s of speed error, 1/s (2 /s: half a second to close an error,
    /// fast beside the 0.25 s engine lag but slow enough not to ring).
    pub kp_per_s: f32,
    /// Acceleration asked per metre of integrated speed error, 1/s² (removes the residual
    /// error of an imperfect resistance model).
    pub ki_per_s2: f32,
    /// Largest integral contribution, m/s².
    pub integral_limit_mps2: f32,
}

impl Default for SpeedGains {
    fn default() -> Self {
        SpeedGains {
            kp_per_s: 2.0,
            ki_per_s2: 0.4,
            integral_limit_mps2: 1.0,
        }
    }
}

/// A PI speed controller with force feedforward for one vehicle.
#[derive(Clone, Debug)]
pub struct SpeedController {
    params: VehicleParams,
    gains: SpeedGains,
    integral_mps: f32,
}

/// Pedal commands from the speed controller.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Pedals {
    /// Throttle, 0..1.
    pub throttle: f32,
    /// Brake, 0..1.
    pub brake: f32,
}

impl SpeedController {
    /// A controller for the vehicle `params` with `gains`.
    pub fn new(params: &VehicleParams, gains: SpeedGains) -> SpeedController {
        SpeedController {
            params: params.clone(),
            gains,
            integral_mps: 0.0,
        }
    }

    /// Pedals to follow `speed_ref_mps` with acceleration `accel_ref_mps2` from the present
    /// `speed_mps`, for one step of `dt_s`.
    pub fn update(
        &mut self,
        speed_ref_mps: f32,
        accel_ref_mps2: f32,
        speed_mps: f32,
        dt_s: f32,
    ) -> Pedals {
        if speed_ref_mps <= STANDSTILL_REF_MPS && speed_mps < STANDSTILL_MPS {
            self.integral_mps = 0.0;
            return Pedals {
                throttle: 0.0,
                brake: HOLD_BRAKE,
            };
        }
        let p = &self.params;
        let error = speed_ref_mps - speed_mps;
        let integral_term = self.gains.ki_per_s2 * self.integral_mps;
        let accel = accel_ref_mps2 + self.gains.kp_per_s * error + integral_term;
        let force = p.mass_kg * accel + p.resistance_n(speed_mps);
        let (throttle, brake) = if force >= 0.0 {
            (force / p.available_drive_force_n(speed_mps), 0.0)
        } else {
            (0.0, -force / p.max_brake_force_n)
        };
        let saturated = throttle > 1.0 || brake > 1.0;
        if !saturated || error * self.integral_mps < 0.0 {
            self.integral_mps += error * dt_s;
            let limit = self.gains.integral_limit_mps2 / self.gains.ki_per_s2.max(1e-6);
            self.integral_mps = self.integral_mps.clamp(-limit, limit);
        }
        Pedals {
            throttle: throttle.clamp(0.0, 1.0),
            brake: brake.clamp(0.0, 1.0),
        }
    }

    /// Forgets the integral (after a mode change).
    pub fn reset(&mut self) {
        self.integral_mps = 0.0;
    }
}
