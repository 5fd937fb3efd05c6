//! Physical parameters of one ray-cast vehicle, with the HMMWV chase and pickup lead presets
//! and the traffic's kinds (sedan, hatchback, van, truck).
//!
//! The vehicle frame: x forward, y up, z right; its origin is the middle of the rear axle at
//! ground level when the vehicle stands at its nominal ride height on flat ground.

use crate::actuator::ActuatorLimits;
use crate::error::{check_range, VehicleError};
use serde::{Deserialize, Serialize};

/// Standard gravity, m/s².
pub const GRAVITY_MPS2: f32 = 9.81;
/// Air density at sea level and 15 °C, kg/m³.
pub const AIR_DENSITY_KGPM3: f32 = 1.225;

/// Physical parameters of a four-wheeled ray-cast vehicle. All lengths in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VehicleParams {
    /// Total mass, kg.
    pub mass_kg: f32,
    /// Distance between front and rear axles.
    pub wheelbase_m: f32,
    /// Distance between left and right wheel centres.
    pub track_m: f32,
    /// Body length, bumper to bumper.
    pub length_m: f32,
    /// Body width.
    pub width_m: f32,
    /// Height of the body's collision box (from its underside to its top). The box may stop
    /// short of the roof ([`VehicleParams::height_m`]): its centre is the centre of mass.
    pub body_height_m: f32,
    /// Overall height, ground to roof at rest: what is drawn and what hides the view (no
    /// part in the physics).
    pub height_m: f32,
    /// Height of the body's underside above the ground at rest.
    pub ground_clearance_m: f32,
    /// Length of body behind the rear axle.
    pub rear_overhang_m: f32,
    /// Tyre radius.
    pub wheel_radius_m: f32,
    /// Suspension spring length at rest (no load).
    pub suspension_rest_m: f32,
    /// Suspension travel allowed either side of the rest length.
    pub suspension_travel_m: f32,
    /// Natural frequency of the body bouncing on its springs, Hz (cars: 1–1.5 Hz).
    pub ride_frequency_hz: f32,
    /// Damping ratio of that bounce (0.3–0.5 for road vehicles).
    pub ride_damping_ratio: f32,
    /// Tyre–road friction coefficient (dry asphalt about 0.9).
    pub tyre_friction: f32,
    /// Largest road-wheel angle of the equivalent bicycle model, radians.
    pub max_steer_rad: f32,
    /// Fastest road-wheel steering rate, radians per second.
    pub steer_rate_radps: f32,
    /// Steering first-order lag, seconds (power-steering hydraulics).
    pub steer_lag_s: f32,
    /// Largest tractive force at the wheels, summed over all driven wheels, N.
    pub max_drive_force_n: f32,
    /// Largest power at the wheels, W (caps the force at speed).
    pub max_drive_power_w: f32,
    /// Fastest throttle change, full range per second.
    pub throttle_rate_per_s: f32,
    /// Engine response lag, seconds.
    pub throttle_lag_s: f32,
    /// Full brake force summed over all wheels, N.
    pub max_brake_force_n: f32,
    /// Fastest brake change, full range per second.
    pub brake_rate_per_s: f32,
    /// Brake hydraulics lag, seconds.
    pub brake_lag_s: f32,
    /// Aerodynamic drag area `Cd·A`, m².
    pub drag_area_m2: f32,
    /// Rolling resistance coefficient (dimensionless).
    pub rolling_resistance: f32,
    /// Whether all four wheels are driven (otherwise the rear pair).
    pub four_wheel_drive: bool,
}

impl Default for VehicleParams {
    /// The chase vehicle: [`VehicleParams::hmmwv_m998`].
    fn default() -> Self {
        VehicleParams::hmmwv_m998()
    }
}

impl VehicleParams {
    /// The chase vehicle, an HMMWV of the M998 class (cargo/troop carrier).
    ///
    /// Figures from the M998's published data: curb weight about 2,340 kg (2,400 kg with a
    /// driver and the vision computer), wheelbase 3.30 m, track 1.82 m, length 4.57 m, width
    /// 2.16 m, 37-inch tyres (0.47 m radius), 16 in ground clearance (0.41 m), turning circle
    /// 15.2 m, 150 hp diesel, top speed about 105 km/h.
    pub fn hmmwv_m998() -> VehicleParams {
        VehicleParams {
            mass_kg: 2400.0,
            wheelbase_m: 3.30,
            track_m: 1.80,
            length_m: 4.57,
            width_m: 2.16,
            // The collision box stands for the body up to the bonnet line; the cab top is
            // not needed for collisions and would raise the centre of mass too high.
            body_height_m: 0.95,
            // 72 in to the top of the cab.
            height_m: 1.83,
            ground_clearance_m: 0.41,
            rear_overhang_m: 0.62,
            wheel_radius_m: 0.47,
            suspension_rest_m: 0.35,
            suspension_travel_m: 0.2,
            // Off-road vehicles ride softer than cars.
            ride_frequency_hz: 1.4,
            ride_damping_ratio: 0.45,
            tyre_friction: 0.9,
            // Turning circle 15.2 m on 3.3 m wheelbase: atan(3.3 / 7.6) = 0.41 rad.
            max_steer_rad: 0.41,
            // About 3.5 steering-wheel turns lock to lock in 2.5 s.
            steer_rate_radps: 0.35,
            steer_lag_s: 0.08,
            // 0.25 g at low speed: the M998 is no sprinter (0–48 km/h in about 9 s).
            max_drive_force_n: 6000.0,
            // 112 kW engine; about half reaches the wheels through the three-speed automatic
            // and its torque converter in the gears used below 60 km/h.
            max_drive_power_w: 55_000.0,
            throttle_rate_per_s: 2.0,
            throttle_lag_s: 0.25,
            // 0.8 g on dry road.
            max_brake_force_n: 18_800.0,
            brake_rate_per_s: 6.0,
            brake_lag_s: 0.06,
            // Cd about 0.7 on 3.9 m² of frontal area (a brick).
            drag_area_m2: 2.7,
            rolling_resistance: 0.015,
            four_wheel_drive: true,
        }
    }

    /// The lead vehicle: a full-size pickup or van carrying the target on its back.
    pub fn pickup() -> VehicleParams {
        VehicleParams {
            mass_kg: 2100.0,
            wheelbase_m: 3.20,
            track_m: 1.70,
            length_m: 5.30,
            width_m: 2.00,
            body_height_m: 0.90,
            // The cab's roof; the target board it carries stands higher.
            height_m: 1.90,
            ground_clearance_m: 0.30,
            rear_overhang_m: 1.20,
            wheel_radius_m: 0.38,
            suspension_rest_m: 0.30,
            suspension_travel_m: 0.18,
            ride_frequency_hz: 1.3,
            ride_damping_ratio: 0.4,
            tyre_friction: 0.9,
            // Turning circle 13 m: atan(3.2 / 6.5) = 0.46 rad.
            max_steer_rad: 0.46,
            steer_rate_radps: 0.45,
            steer_lag_s: 0.06,
            max_drive_force_n: 8000.0,
            max_drive_power_w: 120_000.0,
            throttle_rate_per_s: 2.0,
            throttle_lag_s: 0.2,
            // 0.85 g: a modern pickup with ABS stops a little harder than the HMMWV.
            max_brake_force_n: 17_500.0,
            brake_rate_per_s: 6.0,
            brake_lag_s: 0.06,
            drag_area_m2: 1.6,
            rolling_resistance: 0.013,
            four_wheel_drive: false,
        }
    }

    /// A family saloon of the traffic, about 1,450 kg with its driver: the renderer's drawn
    /// sedan, 4.4 m over the bumpers, 1.8 m wide and 1.45 m to the roof, axles 1.35 m either
    /// side of the body's centre (wheelbase 2.7 m, overhangs 0.85 m). The collision box
    /// stops at the belt line (0.95 m), so that the centre of mass is at about 0.55 m.
    pub fn sedan() -> VehicleParams {
        VehicleParams {
            mass_kg: 1450.0,
            wheelbase_m: 2.70,
            track_m: 1.58,
            length_m: 4.40,
            width_m: 1.80,
            body_height_m: 0.80,
            height_m: 1.45,
            ground_clearance_m: 0.15,
            rear_overhang_m: 0.85,
            wheel_radius_m: 0.32,
            suspension_rest_m: 0.28,
            suspension_travel_m: 0.18,
            ride_frequency_hz: 1.3,
            ride_damping_ratio: 0.4,
            tyre_friction: 0.9,
            // Turning circle 11 m: atan(2.7 / 5.2) = 0.48 rad.
            max_steer_rad: 0.48,
            steer_rate_radps: 0.5,
            steer_lag_s: 0.05,
            // 0.35 g at low speed; 85 kW of a 110 kW engine reaches the wheels.
            max_drive_force_n: 5000.0,
            max_drive_power_w: 85_000.0,
            throttle_rate_per_s: 2.5,
            throttle_lag_s: 0.15,
            // 0.9 g with ABS on dry road.
            max_brake_force_n: 12_800.0,
            brake_rate_per_s: 6.0,
            brake_lag_s: 0.05,
            // Cd 0.30 on 2.2 m².
            drag_area_m2: 0.66,
            rolling_resistance: 0.011,
            // Most are driven at the front; the model drives the rear pair or all four, and
            // on a dry road the difference does not show.
            four_wheel_drive: false,
        }
    }

    /// A small hatchback of the traffic, about 1,250 kg with its driver: the drawn
    /// hatchback has the sedan's footprint (4.4 × 1.8 m, 1.45 m high, wheelbase 2.7 m), a
    /// lighter car with a smaller engine.
    pub fn hatchback() -> VehicleParams {
        VehicleParams {
            mass_kg: 1250.0,
            max_drive_force_n: 4500.0,
            max_drive_power_w: 65_000.0,
            // 0.9 g.
            max_brake_force_n: 11_000.0,
            // Cd 0.31 on 2.1 m².
            drag_area_m2: 0.65,
            ..VehicleParams::sedan()
        }
    }

    /// A panel van of the traffic, about 1,900 kg: the drawn van, 4.4 m over the bumpers,
    /// 1.8 m wide and 1.9 m to the roof, axles 1.45 m either side of the body's centre
    /// (wheelbase 2.9 m, overhangs 0.75 m). The collision box stops at the belt line
    /// (1.05 m); the light upper box adds little to the height of the centre of mass.
    pub fn van() -> VehicleParams {
        VehicleParams {
            mass_kg: 1900.0,
            wheelbase_m: 2.90,
            track_m: 1.58,
            length_m: 4.40,
            width_m: 1.80,
            body_height_m: 0.88,
            height_m: 1.90,
            ground_clearance_m: 0.17,
            rear_overhang_m: 0.75,
            wheel_radius_m: 0.32,
            suspension_rest_m: 0.28,
            suspension_travel_m: 0.18,
            ride_frequency_hz: 1.4,
            ride_damping_ratio: 0.4,
            tyre_friction: 0.9,
            // Turning circle 12 m: atan(2.9 / 5.6) = 0.48 rad.
            max_steer_rad: 0.47,
            steer_rate_radps: 0.45,
            steer_lag_s: 0.06,
            // 0.3 g at low speed; 80 kW at the wheels.
            max_drive_force_n: 6000.0,
            max_drive_power_w: 80_000.0,
            throttle_rate_per_s: 2.0,
            throttle_lag_s: 0.2,
            // 0.85 g.
            max_brake_force_n: 15_800.0,
            brake_rate_per_s: 6.0,
            brake_lag_s: 0.06,
            // Cd 0.35 on 2.9 m².
            drag_area_m2: 1.0,
            rolling_resistance: 0.012,
            four_wheel_drive: false,
        }
    }

    /// A medium rigid box truck of the traffic, 12 t half laden: 7.5 m over the bumpers,
    /// 2.5 m wide and 3.4 m to the box's roof; wheelbase 4.2 m, front overhang 1.3 m, rear
    /// 2.0 m. The collision box stops at 2.7 m, so that the centre of mass is at 1.5 m, a
    /// half-laden box truck's. Air brakes: slower and weaker than a car's.
    pub fn truck() -> VehicleParams {
        VehicleParams {
            mass_kg: 12_000.0,
            wheelbase_m: 4.20,
            track_m: 2.00,
            length_m: 7.50,
            width_m: 2.50,
            body_height_m: 2.40,
            height_m: 3.40,
            ground_clearance_m: 0.30,
            rear_overhang_m: 2.00,
            wheel_radius_m: 0.48,
            suspension_rest_m: 0.30,
            suspension_travel_m: 0.15,
            ride_frequency_hz: 1.8,
            ride_damping_ratio: 0.3,
            tyre_friction: 0.8,
            // Turning circle 16 m: atan(4.2 / 7.0) = 0.54 rad.
            max_steer_rad: 0.54,
            steer_rate_radps: 0.3,
            steer_lag_s: 0.1,
            // 0.15 g at low speed; 150 kW of a 184 kW diesel at the wheels.
            max_drive_force_n: 18_000.0,
            max_drive_power_w: 150_000.0,
            throttle_rate_per_s: 1.5,
            throttle_lag_s: 0.35,
            // 0.6 g through air brakes.
            max_brake_force_n: 70_000.0,
            brake_rate_per_s: 4.0,
            brake_lag_s: 0.25,
            // Cd 0.8 on 8.5 m².
            drag_area_m2: 6.8,
            rolling_resistance: 0.007,
            four_wheel_drive: false,
        }
    }

    /// Checks every field for a physically meaningful value.
    pub fn validate(&self) -> Result<(), VehicleError> {
        let f = |v: f32| f64::from(v);
        check_range("mass_kg", f(self.mass_kg), 100.0, 50_000.0)?;
        check_range("wheelbase_m", f(self.wheelbase_m), 0.5, 10.0)?;
        check_range("track_m", f(self.track_m), 0.5, 4.0)?;
        check_range("length_m", f(self.length_m), f(self.wheelbase_m), 20.0)?;
        check_range("width_m", f(self.width_m), 0.5, 4.0)?;
        check_range("body_height_m", f(self.body_height_m), 0.1, 5.0)?;
        check_range("ground_clearance_m", f(self.ground_clearance_m), 0.05, 2.0)?;
        check_range(
            "height_m",
            f(self.height_m),
            f(self.ground_clearance_m) + f(self.body_height_m),
            10.0,
        )?;
        check_range(
            "rear_overhang_m",
            f(self.rear_overhang_m),
            0.0,
            f(self.length_m - self.wheelbase_m),
        )?;
        check_range("wheel_radius_m", f(self.wheel_radius_m), 0.1, 1.5)?;
        check_range("suspension_rest_m", f(self.suspension_rest_m), 0.05, 1.5)?;
        check_range(
            "suspension_travel_m",
            f(self.suspension_travel_m),
            0.01,
            1.0,
        )?;
        check_range("ride_frequency_hz", f(self.ride_frequency_hz), 0.3, 5.0)?;
        check_range("ride_damping_ratio", f(self.ride_damping_ratio), 0.0, 2.0)?;
        check_range("tyre_friction", f(self.tyre_friction), 0.05, 2.0)?;
        check_range("max_steer_rad", f(self.max_steer_rad), 0.05, 1.2)?;
        check_range("steer_rate_radps", f(self.steer_rate_radps), 0.01, 10.0)?;
        check_range("steer_lag_s", f(self.steer_lag_s), 0.0, 2.0)?;
        check_range("max_drive_force_n", f(self.max_drive_force_n), 1.0, 1e6)?;
        check_range("max_drive_power_w", f(self.max_drive_power_w), 1.0, 1e7)?;
        check_range(
            "throttle_rate_per_s",
            f(self.throttle_rate_per_s),
            0.01,
            100.0,
        )?;
        check_range("throttle_lag_s", f(self.throttle_lag_s), 0.0, 5.0)?;
        check_range("max_brake_force_n", f(self.max_brake_force_n), 1.0, 1e6)?;
        check_range("brake_rate_per_s", f(self.brake_rate_per_s), 0.01, 100.0)?;
        check_range("brake_lag_s", f(self.brake_lag_s), 0.0, 5.0)?;
        check_range("drag_area_m2", f(self.drag_area_m2), 0.0, 50.0)?;
        check_range("rolling_resistance", f(self.rolling_resistance), 0.0, 0.5)?;
        Ok(())
    }

    /// x of the front bumper in the vehicle frame.
    pub fn front_bumper_x_m(&self) -> f32 {
        self.length_m - self.rear_overhang_m
    }

    /// x of the rear bumper in the vehicle frame (negative: behind the rear axle).
    pub fn rear_bumper_x_m(&self) -> f32 {
        -self.rear_overhang_m
    }

    /// x of the body's centre (halfway between the bumpers) in the vehicle frame: where a
    /// mesh drawn about the body's centre is placed (as `sim-core` places the lead's).
    pub fn body_centre_x_m(&self) -> f32 {
        0.5 * self.length_m - self.rear_overhang_m
    }

    /// Rapier's suspension stiffness: spring force per unit of chassis mass per metre of
    /// compression, 1/s². Four springs carry the whole mass, so the body's bounce frequency is
    /// `sqrt(4 k) / 2π`.
    pub fn suspension_stiffness_per_s2(&self) -> f32 {
        let omega = 2.0 * std::f32::consts::PI * self.ride_frequency_hz;
        omega * omega / 4.0
    }

    /// Rapier's suspension damping per unit of chassis mass, 1/s, for the ride damping ratio:
    /// four dampers `c` on mass 1 give `ζ = 4c / (2 sqrt(4k))`.
    pub fn suspension_damping_per_s(&self) -> f32 {
        self.ride_damping_ratio * (4.0 * self.suspension_stiffness_per_s2()).sqrt() / 2.0
    }

    /// Spring compression under the static load, m.
    pub fn static_compression_m(&self) -> f32 {
        GRAVITY_MPS2 / (4.0 * self.suspension_stiffness_per_s2())
    }

    /// Resistance to motion at `speed_mps` (aerodynamic drag plus rolling resistance), N.
    pub fn resistance_n(&self, speed_mps: f32) -> f32 {
        let v = speed_mps.abs();
        // Rolling resistance fades in over the first 0.5 m/s so a stopped vehicle is not pushed.
        let rolling = self.rolling_resistance * self.mass_kg * GRAVITY_MPS2 * (v / 0.5).min(1.0);
        0.5 * AIR_DENSITY_KGPM3 * self.drag_area_m2 * v * v + rolling
    }

    /// Tractive force available at full throttle at `speed_mps`, N (force- then power-limited).
    pub fn available_drive_force_n(&self, speed_mps: f32) -> f32 {
        // Below 1 m/s the power limit would ask for more force than the tyres can give.
        self.max_drive_force_n
            .min(self.max_drive_power_w / speed_mps.abs().max(1.0))
    }

    /// The steering actuator's limits.
    pub fn steer_limits(&self) -> ActuatorLimits {
        ActuatorLimits {
            min: -self.max_steer_rad,
            max: self.max_steer_rad,
            rate_per_s: self.steer_rate_radps,
            lag_s: self.steer_lag_s,
        }
    }

    /// The throttle actuator's limits.
    pub fn throttle_limits(&self) -> ActuatorLimits {
        ActuatorLimits {
            min: 0.0,
            max: 1.0,
            rate_per_s: self.throttle_rate_per_s,
            lag_s: self.throttle_lag_s,
        }
    }

    /// The brake actuator's limits.
    pub fn brake_limits(&self) -> ActuatorLimits {
        ActuatorLimits {
            min: 0.0,
            max: 1.0,
            rate_per_s: self.brake_rate_per_s,
            lag_s: self.brake_lag_s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid() {
        VehicleParams::hmmwv_m998().validate().unwrap();
        VehicleParams::pickup().validate().unwrap();
        for p in [
            VehicleParams::sedan(),
            VehicleParams::hatchback(),
            VehicleParams::van(),
            VehicleParams::truck(),
        ] {
            p.validate().unwrap();
        }
    }

    /// The cars' bodies are the renderer's drawn cars: 4.4 m by 1.8 m, centred between the
    /// axles (the drawn axles stand 1.35 m, the van's 1.45 m, either side of the centre).
    #[test]
    fn the_cars_bodies_are_the_drawn_cars() {
        for (p, axle_m) in [
            (VehicleParams::sedan(), 1.35),
            (VehicleParams::hatchback(), 1.35),
            (VehicleParams::van(), 1.45),
        ] {
            assert_eq!((p.length_m, p.width_m), (4.4, 1.8));
            assert!((p.body_centre_x_m() - axle_m).abs() < 1e-6);
            assert!((p.wheelbase_m - 2.0 * axle_m).abs() < 1e-6);
            assert!((p.front_bumper_x_m() - p.body_centre_x_m() - 2.2).abs() < 1e-6);
        }
        let t = VehicleParams::truck();
        assert_eq!((t.length_m, t.width_m, t.height_m), (7.5, 2.5, 3.4));
    }

    #[test]
    fn hmmwv_can_exceed_35_kmh_on_power() {
        let p = VehicleParams::hmmwv_m998();
        let v = 35.0 / 3.6;
        assert!(p.available_drive_force_n(v) > 2.0 * p.resistance_n(v));
    }

    #[test]
    fn bad_wheelbase_is_rejected() {
        let p = VehicleParams {
            wheelbase_m: -1.0,
            ..VehicleParams::hmmwv_m998()
        };
        assert!(matches!(
            p.validate(),
            Err(VehicleError::InvalidParameter {
                field: "wheelbase_m",
                ..
            })
        ));
    }
}
