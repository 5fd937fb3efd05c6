//! The lead vehicle's driver: pure pursuit on ground truth along the route, a scripted speed
//! profile, slowing for turns, and optional weaving within the lane. The same driver drives
//! the traffic's scripted vehicles ([`crate::ActorDriver`]): a lateral offset from the route
//! (a lane change) and a speed that replaces the profile's (a speed event) can be set at
//! each step; left unset, the driver computes exactly what it did without them.

use crate::clock::{Step, PHYSICS_DT_S};
use crate::controls::Controls;
use crate::error::{check_range, VehicleError};
use crate::pure_pursuit::{curvature_toward, steer_for_curvature, LookAhead};
use crate::ray_cast_vehicle::VehicleState;
use crate::route::Route;
use crate::speed_controller::{SpeedController, SpeedGains};
use crate::speed_profile::{ProfileBasis, SpeedProfile};
use crate::vehicle_params::VehicleParams;
use serde::{Deserialize, Serialize};

/// How far either side of the last progress the driver looks for itself on the route, m.
const PROJECTION_WINDOW_M: f32 = 25.0;
/// Spacing of the curvature samples ahead when slowing for turns, m.
const PREVIEW_STEP_M: f32 = 1.0;
/// Extra preview beyond the braking distance, m.
const PREVIEW_MARGIN_M: f32 = 5.0;
/// Distance before the route's end at which the driver aims to have stopped, m.
const END_MARGIN_M: f32 = 2.0;

/// The lead driver's tuning.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct LeadDriverConfig {
    /// Pure-pursuit look-ahead.
    pub lookahead: LookAhead,
    /// Largest lateral acceleration the driver accepts in turns, m/s² (2.5 m/s²: a calm
    /// driver; the profile's speed is lowered ahead of tighter turns).
    #[schemars(extend("minimum" = 0.1, "maximum" = 15.0))]
    pub max_lateral_accel_mps2: f32,
    /// Deceleration used to slow down ahead of turns and the route's end, m/s².
    #[schemars(extend("minimum" = 0.1, "maximum" = 15.0))]
    pub comfort_decel_mps2: f32,
    /// Weaving: amplitude of the sinusoidal offset from the centreline, m (0 = none; keep
    /// under about 0.8 m to stay in a 3.6 m lane).
    #[schemars(extend("minimum" = 0.0, "maximum" = 5.0))]
    pub weave_amplitude_m: f32,
    /// Weaving: distance along the route of one full weave, m.
    #[schemars(extend("minimum" = 1.0, "maximum" = 10000.0))]
    pub weave_wavelength_m: f32,
    /// When the vehicle is this much faster than the profile asks, the driver stamps on the
    /// brake (full brake) instead of easing off, m/s (default 2 m/s: a scripted drop in
    /// speed is a hard stop, a gentle slope is not).
    #[schemars(extend("minimum" = 0.1, "maximum" = 100.0))]
    pub panic_brake_error_mps: f32,
    /// Speed-loop gains.
    pub speed_gains: SpeedGains,
}

impl Default for LeadDriverConfig {
    fn default() -> Self {
        LeadDriverConfig {
            lookahead: LookAhead::default(),
            max_lateral_accel_mps2: 2.5,
            comfort_decel_mps2: 2.0,
            weave_amplitude_m: 0.0,
            weave_wavelength_m: 40.0,
            panic_brake_error_mps: 2.0,
            speed_gains: SpeedGains::default(),
        }
    }
}

/// A speed that replaces the profile's for one step: what a speed event asks.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SpeedOverride {
    /// The speed to aim for now, m/s.
    pub speed_mps: f32,
    /// Its rate of change now, m/s² (the speed loop's feedforward).
    pub accel_mps2: f32,
}

/// Drives the lead vehicle along its route at its speed profile, from ground truth.
///
/// For a scripted vehicle of the traffic, [`LeadDriver::set_lateral_offset_m`] shifts the
/// path it follows sideways and [`LeadDriver::set_speed_override`] replaces the profile's
/// speed; the slowing for turns and the route's end still applies.
#[derive(Clone, Debug)]
pub struct LeadDriver {
    route: Route,
    profile: SpeedProfile,
    config: LeadDriverConfig,
    wheelbase_m: f32,
    speed: SpeedController,
    progress_m: f32,
    speed_ref_mps: f32,
    panic_braking: bool,
    /// Lateral offset from the route, m (positive left); 0 leaves the path as the lead's.
    offset_m: f32,
    /// The speed that replaces the profile's, if any.
    speed_override: Option<SpeedOverride>,
}

impl LeadDriver {
    /// A driver for the vehicle `params` on `route` with `profile`.
    pub fn new(
        route: Route,
        profile: SpeedProfile,
        config: LeadDriverConfig,
        params: &VehicleParams,
    ) -> Result<LeadDriver, VehicleError> {
        profile.validate()?;
        check_range(
            "max_lateral_accel_mps2",
            f64::from(config.max_lateral_accel_mps2),
            0.1,
            15.0,
        )?;
        check_range(
            "comfort_decel_mps2",
            f64::from(config.comfort_decel_mps2),
            0.1,
            15.0,
        )?;
        check_range(
            "weave_amplitude_m",
            f64::from(config.weave_amplitude_m),
            0.0,
            5.0,
        )?;
        check_range(
            "weave_wavelength_m",
            f64::from(config.weave_wavelength_m),
            1.0,
            1e4,
        )?;
        check_range(
            "panic_brake_error_mps",
            f64::from(config.panic_brake_error_mps),
            0.1,
            100.0,
        )?;
        Ok(LeadDriver {
            route,
            profile,
            speed: SpeedController::new(params, config.speed_gains),
            config,
            wheelbase_m: params.wheelbase_m,
            progress_m: 0.0,
            speed_ref_mps: 0.0,
            panic_braking: false,
            offset_m: 0.0,
            speed_override: None,
        })
    }

    /// The route.
    pub fn route(&self) -> &Route {
        &self.route
    }

    /// Arc length along the route reached so far, m.
    pub fn progress_m(&self) -> f32 {
        self.progress_m
    }

    /// The speed the driver is aiming for now, m/s.
    pub fn speed_ref_mps(&self) -> f32 {
        self.speed_ref_mps
    }

    /// Drives `offset_m` to the left of the route from the next [`LeadDriver::update`] on
    /// (negative: to the right), on top of any weave: the pure-pursuit target is
    /// `route.point_at(s) + route.left_at(s) × (weave + offset)`. A lane change moves it.
    pub fn set_lateral_offset_m(&mut self, offset_m: f32) {
        self.offset_m = offset_m;
    }

    /// The lateral offset from the route now asked for, m (positive left).
    pub fn lateral_offset_m(&self) -> f32 {
        self.offset_m
    }

    /// Replaces the profile's speed and its slope by `speed` from the next
    /// [`LeadDriver::update`] on (`None`: the profile again). The turn limit still applies.
    pub fn set_speed_override(&mut self, speed: Option<SpeedOverride>) {
        self.speed_override = speed;
    }

    /// The speed that replaces the profile's now, if any.
    pub fn speed_override(&self) -> Option<SpeedOverride> {
        self.speed_override
    }

    /// The centreline offset of the weave at arc length `s_m`, m (positive left).
    fn weave_m(&self, s_m: f32) -> f32 {
        self.config.weave_amplitude_m
            * (std::f32::consts::TAU * s_m / self.config.weave_wavelength_m).sin()
    }

    /// The fastest speed that can still slow down for the turns and the route's end ahead.
    fn turn_limit_mps(&self, speed_mps: f32) -> f32 {
        let a_lat = self.config.max_lateral_accel_mps2;
        let decel = self.config.comfort_decel_mps2;
        let preview = speed_mps * speed_mps / (2.0 * decel) + PREVIEW_MARGIN_M;
        let end = self.route.length_m() - END_MARGIN_M;
        let mut limit = f32::INFINITY;
        let mut d = 0.0;
        // The preview's arc lengths only grow.
        let mut curvature = self.route.curvature_walk();
        while d <= preview {
            let s = self.progress_m + d;
            let at_s = if s >= end {
                0.0
            } else {
                let k = curvature.at(s).abs();
                if k > 1e-4 {
                    (a_lat / k).sqrt()
                } else {
                    f32::INFINITY
                }
            };
            limit = limit.min((at_s * at_s + 2.0 * decel * d).sqrt());
            if s >= end {
                break;
            }
            d += PREVIEW_STEP_M;
        }
        limit
    }

    /// The profile's speed and its rate of change at step `now` and speed `v`.
    fn profile_speed(&self, now: Step, v: f32) -> (f32, f32) {
        let (profile_speed, slope) = match self.profile.basis {
            ProfileBasis::Time => self.profile.sample(now.seconds() as f32),
            ProfileBasis::Distance => self.profile.sample(self.progress_m),
        };
        let profile_accel = match self.profile.basis {
            ProfileBasis::Time => slope,
            ProfileBasis::Distance => slope * v,
        };
        (profile_speed, profile_accel)
    }

    /// Commands for the lead at step `now` from its true state.
    pub fn update(&mut self, now: Step, state: &VehicleState) -> Controls {
        let pose = &state.world_from_vehicle;
        let here = self
            .route
            .project_near(pose.translation, self.progress_m, PROJECTION_WINDOW_M);
        self.progress_m = here.s_m.max(self.progress_m);
        let v = state.forward_speed_mps;

        let s_target = self.progress_m + self.config.lookahead.distance_m(v);
        // Without an offset, exactly the lead's arithmetic.
        let target = if self.offset_m != 0.0 {
            self.route.point_at(s_target)
                + self.route.left_at(s_target) * (self.weave_m(s_target) + self.offset_m)
        } else {
            self.route.point_at(s_target) + self.route.left_at(s_target) * self.weave_m(s_target)
        };
        let curvature = curvature_toward(pose, target);
        let steer_rad = steer_for_curvature(curvature, self.wheelbase_m);

        let (profile_speed, profile_accel) = match self.speed_override {
            Some(o) => (o.speed_mps, o.accel_mps2),
            None => self.profile_speed(now, v),
        };
        let limit = self.turn_limit_mps(v);
        let (speed_ref, accel_ref) = if limit < profile_speed {
            (limit, 0.0)
        } else {
            (profile_speed, profile_accel)
        };
        self.speed_ref_mps = speed_ref;
        let mut pedals = self.speed.update(speed_ref, accel_ref, v, PHYSICS_DT_S);
        // A panic stop holds the pedal down until the speed is back under the profile.
        if v - speed_ref > self.config.panic_brake_error_mps {
            self.panic_braking = true;
        } else if v <= speed_ref {
            self.panic_braking = false;
        }
        if self.panic_braking {
            pedals.throttle = 0.0;
            pedals.brake = 1.0;
        }
        Controls {
            steer_rad,
            throttle: pedals.throttle,
            brake: pedals.brake,
        }
    }
}
