//! The driver's commands to one vehicle.

use serde::{Deserialize, Serialize};

/// Commands for one vehicle: what a driver (human or controller) asks of the actuators.
///
/// The actuators then apply their rate limits and lag before the wheels see them.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Controls {
    /// Road-wheel steering angle of the equivalent bicycle model, radians; positive turns left
    /// (counter-clockwise seen from above, a positive rotation about the world's +y).
    pub steer_rad: f32,
    /// Throttle, 0 (off) to 1 (full engine force).
    pub throttle: f32,
    /// Brake, 0 (off) to 1 (full brake force). Any brake cuts the engine force.
    pub brake: f32,
}

impl Controls {
    /// Full brake, wheels straight: what a controller sends to stop now.
    pub fn full_brake() -> Controls {
        Controls {
            steer_rad: 0.0,
            throttle: 0.0,
            brake: 1.0,
        }
    }
}
