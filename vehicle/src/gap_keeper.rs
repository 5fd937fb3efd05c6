//! The gap keeper: a speed reference that holds a gap to the lead, with acceleration and jerk
//! limits, and an emergency brake when comfort braking would not be enough.
//!
//! # The law
//!
//! It is an adaptive-cruise-control law of the constant-time-gap kind (Rajamani, *Vehicle
//! Dynamics and Control*, 2nd ed., ch. 6): the wanted gap is d* = s₀ + h·v (a standstill
//! distance plus a time gap at the chase's speed v; [`GapPolicy::TimeHeadway`], or h = 0
//! for [`GapPolicy::ConstantDistance`]), clamped to the band `[min_gap_m, max_gap_m]`, and
//! the acceleration asked of the speed reference is
//!
//! a = k_v·(v_lead − v_ref) + k_v·k_d·(d − d*),
//!
//! with k_v = `speed_gain_per_s` and k_d = `gap_gain_per_s` (the reference chases
//! v_lead + k_d·(d − d*)). The lead's speed v_lead is the chase's own plus the range filter's
//! rate, and d the range carried forward over the 128 ms latency (`ChaseController`); the
//! latency is never hidden. [`GapPolicy::Idm`] puts the Intelligent Driver Model (Treiber,
//! Hennecke & Helbing 2000) in place of the linear law. Either way the acceleration is
//! limited to `[-max_decel_mps2, max_accel_mps2]` and its changes to the jerk limits, safety
//! comes first (the wanted gap is never below the RSS safe gap, and collision braking and
//! the emergency brake override the law), and braking beyond `max_decel_mps2` is left to the
//! emergency brake.
//!
//! A constant time gap is what holds stop-and-go traffic: at a stop the chase closes to s₀,
//! and when the lead pulls away the gap it wants grows with its own speed, so it sets off as
//! soon as the gap opens beyond s₀ instead of waiting for the lead to be a full constant gap
//! ahead (which left the gap 6 m over its aim after each start).

use crate::error::{check_range, VehicleError};
use serde::{Deserialize, Serialize};

/// How the wanted gap is chosen.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "policy", deny_unknown_fields)]
pub enum GapPolicy {
    /// The same gap at every speed.
    ConstantDistance {
        /// The wanted gap, m.
        gap_m: f32,
    },
    /// A gap growing with speed: `standstill_gap_m + headway_s × speed` (the constant time
    /// gap of ACC).
    TimeHeadway {
        /// Gap at standstill, m.
        standstill_gap_m: f32,
        /// Time headway, s.
        headway_s: f32,
    },
    /// The Intelligent Driver Model in place of the linear law: the acceleration is
    /// a_max·[1 − (v/v₀)⁴ − (s*/d)²] with s* = s₀ + max(0, v·T + v·(v − v_lead)/(2√(a_max·b))),
    /// a_max = `max_accel_mps2` and v₀ = `max_speed_mps`.
    Idm {
        /// s₀, the gap at standstill, m.
        standstill_gap_m: f32,
        /// T, the time headway, s.
        headway_s: f32,
        /// b, the comfortable deceleration, m/s².
        comfortable_decel_mps2: f32,
    },
}

/// The exponent of IDM's free-road term.
const IDM_EXPONENT: i32 = 4;

/// The gap keeper's tuning.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct GapKeeperConfig {
    /// How the wanted gap is chosen (default: a constant time gap of 0.4 s on a 6 m
    /// standstill distance: 10 m at 10 m/s, the middle of the paper's 5–15 m, and 6 m at a
    /// stop, where the board is 1.7 times its nominal size in the image; at 5 m the paper's
    /// tracker lost the board through `hard-braking`'s stops).
    pub policy: GapPolicy,
    /// The wanted gap is never below this, m (default 5 m).
    #[schemars(extend("minimum" = 0.5, "maximum" = 100.0))]
    pub min_gap_m: f32,
    /// The wanted gap is never above this, m (default 15 m: beyond it the paper's tracker
    /// sees the target too small).
    pub max_gap_m: f32,
    /// Speed asked per metre of gap error, 1/s (0.4 /s: a gap error closes in a few seconds,
    /// well below the speed loop's bandwidth so the two loops do not fight).
    #[schemars(extend("minimum" = 0.01, "maximum" = 10.0))]
    pub gap_gain_per_s: f32,
    /// Acceleration asked per m/s between wanted and reference speed, 1/s.
    #[schemars(extend("minimum" = 0.01, "maximum" = 20.0))]
    pub speed_gain_per_s: f32,
    /// Largest acceleration, m/s² (1.5 m/s²: brisk for a 2.4 t vehicle).
    #[schemars(extend("minimum" = 0.05, "maximum" = 10.0))]
    pub max_accel_mps2: f32,
    /// Largest deceleration in normal following, m/s² (3.5 m/s²: firm but not emergency).
    #[schemars(extend("minimum" = 0.05, "maximum" = 10.0))]
    pub max_decel_mps2: f32,
    /// Largest rate of change of the acceleration, m/s³ (2.5 m/s³: comfortable). Applies
    /// to speeding up and to easing off the brake.
    #[schemars(extend("minimum" = 0.05, "maximum" = 100.0))]
    pub max_jerk_mps3: f32,
    /// Largest rate at which braking may build up, m/s³ (12 m/s³: a driver moving to the
    /// brake pedal; braking onset must not wait on comfort).
    pub max_brake_jerk_mps3: f32,
    /// Time the chase needs to turn a measurement into braking, s, counted in the emergency
    /// test as distance already lost (default 0.3 s: half a frame, the brake lag and margin;
    /// the measurement's own latency is already compensated).
    #[schemars(extend("minimum" = 0.0, "maximum" = 5.0))]
    pub reaction_time_s: f32,
    /// The gap the emergency brake protects, m: below it, or when stopping before it needs
    /// more than `max_decel_mps2`, the controller brakes fully (default 2.5 m).
    pub stop_gap_m: f32,
    /// Highest speed the chase vehicle is asked for, m/s (default 20 m/s = 72 km/h).
    #[schemars(extend("minimum" = 0.1, "maximum" = 60.0))]
    pub max_speed_mps: f32,
    /// When keeping the stop gap needs more than this deceleration, the reference brakes
    /// at least that hard, m/s² (default 1.0 m/s²: above what tracker noise at 10 m asks
    /// for, below any real closing).
    pub collision_braking_mps2: f32,
    /// The hardest braking assumed of the lead in the safe-gap test, m/s² (default
    /// 8.5 m/s²: a light truck with ABS on dry asphalt).
    #[schemars(extend("minimum" = 0.5, "maximum" = 15.0))]
    pub assumed_lead_decel_mps2: f32,
    /// The braking the chase can count on in an emergency, m/s² (default 7.0 m/s²: the
    /// HMMWV's 0.8 g less a margin for the brake's build-up).
    #[schemars(extend("minimum" = 0.5, "maximum" = 15.0))]
    pub own_emergency_decel_mps2: f32,
    /// Below the RSS safe gap, a closing speed above this calls the emergency brake, m/s
    /// (default 2.5 m/s: what the lead braking at 0.85 g opens within 0.3 s; about four
    /// times the alarm filter's rate noise at 10 m with 1 % range noise, which a lead merely
    /// slowing for a bend reached at 1.5 m/s).
    #[schemars(extend("minimum" = 0.0, "maximum" = 100.0))]
    pub emergency_closing_mps: f32,
}

impl Default for GapKeeperConfig {
    fn default() -> Self {
        GapKeeperConfig {
            policy: GapPolicy::TimeHeadway {
                standstill_gap_m: 6.0,
                headway_s: 0.4,
            },
            min_gap_m: 5.0,
            max_gap_m: 15.0,
            gap_gain_per_s: 0.4,
            speed_gain_per_s: 1.5,
            max_accel_mps2: 1.5,
            max_decel_mps2: 3.5,
            max_jerk_mps3: 2.5,
            max_brake_jerk_mps3: 12.0,
            reaction_time_s: 0.3,
            stop_gap_m: 2.5,
            max_speed_mps: 20.0,
            collision_braking_mps2: 1.0,
            assumed_lead_decel_mps2: 8.5,
            own_emergency_decel_mps2: 7.0,
            emergency_closing_mps: 2.5,
        }
    }
}

impl GapKeeperConfig {
    /// Checks the values.
    pub fn validate(&self) -> Result<(), VehicleError> {
        let f = f64::from;
        check_range("min_gap_m", f(self.min_gap_m), 0.5, 100.0)?;
        check_range("max_gap_m", f(self.max_gap_m), f(self.min_gap_m), 200.0)?;
        check_range("stop_gap_m", f(self.stop_gap_m), 0.1, f(self.min_gap_m))?;
        check_range("gap_gain_per_s", f(self.gap_gain_per_s), 0.01, 10.0)?;
        check_range("speed_gain_per_s", f(self.speed_gain_per_s), 0.01, 20.0)?;
        check_range("max_accel_mps2", f(self.max_accel_mps2), 0.05, 10.0)?;
        check_range("max_decel_mps2", f(self.max_decel_mps2), 0.05, 10.0)?;
        check_range("max_jerk_mps3", f(self.max_jerk_mps3), 0.05, 100.0)?;
        check_range(
            "max_brake_jerk_mps3",
            f(self.max_brake_jerk_mps3),
            f(self.max_jerk_mps3),
            1000.0,
        )?;
        check_range("reaction_time_s", f(self.reaction_time_s), 0.0, 5.0)?;
        check_range(
            "assumed_lead_decel_mps2",
            f(self.assumed_lead_decel_mps2),
            0.5,
            15.0,
        )?;
        check_range(
            "own_emergency_decel_mps2",
            f(self.own_emergency_decel_mps2),
            0.5,
            15.0,
        )?;
        check_range("max_speed_mps", f(self.max_speed_mps), 0.1, 60.0)?;
        check_range(
            "emergency_closing_mps",
            f(self.emergency_closing_mps),
            0.0,
            100.0,
        )?;
        check_range(
            "collision_braking_mps2",
            f(self.collision_braking_mps2),
            0.0,
            f(self.max_decel_mps2),
        )?;
        match self.policy {
            GapPolicy::ConstantDistance { gap_m } => {
                check_range("policy.gap_m", f(gap_m), 0.5, 200.0)
            }
            GapPolicy::TimeHeadway {
                standstill_gap_m,
                headway_s,
            } => {
                check_range("policy.standstill_gap_m", f(standstill_gap_m), 0.0, 200.0)?;
                check_range("policy.headway_s", f(headway_s), 0.0, 10.0)
            }
            GapPolicy::Idm {
                standstill_gap_m,
                headway_s,
                comfortable_decel_mps2,
            } => {
                check_range("policy.standstill_gap_m", f(standstill_gap_m), 0.5, 200.0)?;
                check_range("policy.headway_s", f(headway_s), 0.0, 10.0)?;
                check_range(
                    "policy.comfortable_decel_mps2",
                    f(comfortable_decel_mps2),
                    0.1,
                    f(self.max_decel_mps2),
                )
            }
        }
    }

    /// IDM's acceleration for the gap `gap_m` at `speed_mps` behind a lead at
    /// `lead_speed_mps`, m/s², and its dynamic desired gap s*, m (see [`GapPolicy::Idm`]);
    /// `None` for the other policies.
    pub fn idm(&self, gap_m: f32, speed_mps: f32, lead_speed_mps: f32) -> Option<(f32, f32)> {
        let GapPolicy::Idm {
            standstill_gap_m,
            headway_s,
            comfortable_decel_mps2,
        } = self.policy
        else {
            return None;
        };
        let v = speed_mps.max(0.0);
        let a = self.max_accel_mps2;
        let dynamic =
            v * headway_s + v * (v - lead_speed_mps) / (2.0 * (a * comfortable_decel_mps2).sqrt());
        let s_star = standstill_gap_m + dynamic.max(0.0);
        let free = (v / self.max_speed_mps).powi(IDM_EXPONENT);
        let interaction = (s_star / gap_m.max(0.1)).powi(2);
        Some((a * (1.0 - free - interaction), s_star))
    }

    /// The wanted gap at `speed_mps`, inside the band `[min_gap_m, max_gap_m]`.
    pub fn desired_gap_m(&self, speed_mps: f32) -> f32 {
        let raw = match self.policy {
            GapPolicy::ConstantDistance { gap_m } => gap_m,
            GapPolicy::TimeHeadway {
                standstill_gap_m,
                headway_s,
            }
            | GapPolicy::Idm {
                standstill_gap_m,
                headway_s,
                ..
            } => standstill_gap_m + headway_s * speed_mps.max(0.0),
        };
        raw.clamp(self.min_gap_m, self.max_gap_m)
    }

    /// The constant deceleration that would stop the gap `gap_m`, closing at
    /// `-range_rate_mps`, from shrinking below `stop_gap_m` after the reaction time, m/s²
    /// (0 when opening, infinite when there is no room left).
    pub fn required_decel_mps2(&self, gap_m: f32, range_rate_mps: f32) -> f32 {
        if gap_m <= self.stop_gap_m {
            return f32::INFINITY;
        }
        let closing = -range_rate_mps;
        if closing <= 0.0 {
            return 0.0;
        }
        let room = gap_m - self.stop_gap_m - closing * self.reaction_time_s;
        if room <= 0.0 {
            f32::INFINITY
        } else {
            closing * closing / (2.0 * room)
        }
    }

    /// The safe gap of Responsibility-Sensitive Safety (Shalev-Shwartz et al. 2017), m:
    /// the chase at `speed_mps`, reacting after `reaction_time_s` and then braking at
    /// `own_emergency_decel_mps2`, stops `stop_gap_m` behind a lead at `lead_speed_mps`
    /// that brakes at `assumed_lead_decel_mps2` from now.
    pub fn safe_gap_m(&self, speed_mps: f32, lead_speed_mps: f32) -> f32 {
        let v = speed_mps.max(0.0);
        let vl = lead_speed_mps.max(0.0);
        let own = v * self.reaction_time_s + v * v / (2.0 * self.own_emergency_decel_mps2);
        let lead = vl * vl / (2.0 * self.assumed_lead_decel_mps2);
        (own - lead).max(0.0) + self.stop_gap_m
    }

    /// How threatening the gap `gap_m`, changing at `range_rate_mps`, is for the chase at
    /// `speed_mps`: an emergency when keeping the stop gap at the present closing speed
    /// needs more than `max_decel_mps2` (or there is no room left), or when the gap is below
    /// the RSS safe gap ([`GapKeeperConfig::safe_gap_m`]) *and* closing faster than
    /// `emergency_closing_mps`: the lead is braking, and the test has to assume it brakes
    /// hard, since the closing speed alone shows a hard stop too late.
    ///
    /// A gap below the safe gap that is not closing is no emergency: RSS's proper response
    /// is to brake at a reasonable rate until the gap is safe again, which
    /// [`GapKeeper::update`] does by never wanting less than the safe gap. (Slamming the
    /// brakes there pitched the chassis 2°, and the camera with it, whenever the lead merely
    /// slowed at a 5 m gap.)
    pub fn threat(&self, gap_m: f32, range_rate_mps: f32, speed_mps: f32) -> Threat {
        self.threat_in_noise(gap_m, range_rate_mps, speed_mps, 1.0)
    }

    /// [`GapKeeperConfig::threat`] for a range rate whose noise is `rate_noise_ratio` times
    /// that at the alarm filter's reference range ([`crate::range_filter::Gains::rate_noise_ratio`]):
    /// a closing counts only when it is `emergency_closing_mps` times that ratio (at least
    /// 1), so that the rate noise of a small, far target (the range's error grows as its
    /// square) is not taken for a real closing. At 25 m that is 1.6 times the 10 m figure.
    pub fn threat_in_noise(
        &self,
        gap_m: f32,
        range_rate_mps: f32,
        speed_mps: f32,
        rate_noise_ratio: f32,
    ) -> Threat {
        let required_decel_mps2 = self.required_decel_mps2(gap_m, range_rate_mps);
        let unsafe_gap = gap_m < self.safe_gap_m(speed_mps, speed_mps + range_rate_mps);
        let closing = -range_rate_mps > self.emergency_closing_mps * rate_noise_ratio.max(1.0);
        let too_close = required_decel_mps2 > self.max_decel_mps2;
        Threat {
            required_decel_mps2,
            emergency: too_close || (unsafe_gap && closing),
            closing_only: !too_close && unsafe_gap && closing,
        }
    }

    /// Whether the gap `gap_m` closing at `-range_rate_mps` needs the emergency brake for
    /// the chase at `speed_mps` (see [`GapKeeperConfig::threat`]).
    pub fn emergency_needed(&self, gap_m: f32, range_rate_mps: f32, speed_mps: f32) -> bool {
        self.threat(gap_m, range_rate_mps, speed_mps).emergency
    }
}

/// How close the lead is to being hit.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Threat {
    /// Deceleration needed to keep the stop gap at the present closing speed, m/s².
    pub required_decel_mps2: f32,
    /// Whether to brake fully now: keeping the stop gap needs more than `max_decel_mps2`,
    /// or the gap is below the RSS safe gap and closing fast.
    pub emergency: bool,
    /// Whether the emergency is the second kind alone: below the safe gap and closing fast,
    /// with room to stop at `max_decel_mps2` still (what a noisy rate can fake).
    pub closing_only: bool,
}

/// The gap keeper's output for one step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SpeedCommand {
    /// Speed reference, m/s.
    pub speed_mps: f32,
    /// Acceleration of the reference, m/s² (feedforward for the speed loop).
    pub accel_mps2: f32,
    /// Brake fully now.
    pub emergency: bool,
    /// The wanted gap, m: the policy's, or the RSS safe gap when that is larger.
    pub desired_gap_m: f32,
}

/// The gap keeper's state: a jerk- and acceleration-limited speed reference.
#[derive(Clone, Debug)]
pub struct GapKeeper {
    config: GapKeeperConfig,
    speed_ref_mps: f32,
    accel_mps2: f32,
    emergency: bool,
    view_limit_m: Option<f32>,
}

/// Collision braking brakes this much harder than the bare requirement, so the gap it
/// keeps is not eaten by the brake's lag.
const COLLISION_BRAKING_MARGIN: f32 = 1.3;

/// How far the reference may run ahead of or behind the real speed, m/s (keeps the
/// reference honest when the vehicle cannot follow it, e.g. on full throttle).
const REFERENCE_LEASH_MPS: f32 = 1.5;

impl GapKeeper {
    /// A gap keeper starting at `speed_mps`.
    pub fn new(config: GapKeeperConfig, speed_mps: f32) -> Result<GapKeeper, VehicleError> {
        config.validate()?;
        Ok(GapKeeper {
            config,
            speed_ref_mps: speed_mps.max(0.0),
            accel_mps2: 0.0,
            emergency: false,
            view_limit_m: None,
        })
    }

    /// Caps the policy's gap at `limit_m` (the curve-aware gap keeping's view limit, see
    /// `ChaseController::view_limited_gap_m`), never below the band's `min_gap_m`; `None`
    /// lifts the cap.
    pub fn set_view_limit(&mut self, limit_m: Option<f32>) {
        self.view_limit_m = limit_m;
    }

    /// The configuration.
    pub fn config(&self) -> &GapKeeperConfig {
        &self.config
    }

    /// Restarts the reference at `speed_mps` (after a loss or a manual phase).
    pub fn reset(&mut self, speed_mps: f32) {
        self.speed_ref_mps = speed_mps.max(0.0);
        self.accel_mps2 = 0.0;
        self.emergency = false;
    }

    /// One step of `dt_s`: the gap `gap_m` now, its rate `range_rate_mps`, the `threat`
    /// (see [`GapKeeperConfig::threat`]; the caller may compute it from a faster, noisier
    /// range estimate), and own speed.
    ///
    /// On an emergency the brake goes on fully; when keeping the stop gap needs more than
    /// `collision_braking_mps2` the reference brakes at least that hard (with margin),
    /// whatever the gap policy says.
    pub fn update(
        &mut self,
        gap_m: f32,
        range_rate_mps: f32,
        threat: Threat,
        speed_mps: f32,
        dt_s: f32,
    ) -> SpeedCommand {
        let c = &self.config;
        let lead_speed = (speed_mps + range_rate_mps).max(0.0);
        // Safety before the policy and its band: never aim closer than the RSS safe gap.
        let policy = c.desired_gap_m(speed_mps);
        let viewable = self
            .view_limit_m
            .map_or(policy, |limit| policy.min(limit.max(c.min_gap_m)));
        let desired_gap_m = viewable.max(c.safe_gap_m(speed_mps, lead_speed));
        let required_decel_mps2 = threat.required_decel_mps2;
        let emergency_now = threat.emergency;

        if emergency_now {
            self.emergency = true;
        } else if self.emergency && (range_rate_mps >= 0.0 || speed_mps < 0.1) {
            // Out of danger: pick up again from the present speed.
            self.emergency = false;
            self.speed_ref_mps = speed_mps.max(0.0);
            self.accel_mps2 = 0.0;
        }
        if self.emergency {
            self.speed_ref_mps = speed_mps.min(lead_speed).max(0.0);
            self.accel_mps2 = -c.max_decel_mps2;
            return SpeedCommand {
                speed_mps: 0.0,
                accel_mps2: self.accel_mps2,
                emergency: true,
                desired_gap_m,
            };
        }

        let (mut accel_target, desired_gap_m) = match c.idm(gap_m, speed_mps, lead_speed) {
            Some((accel, s_star)) => (accel, s_star.max(desired_gap_m)),
            None => {
                let wanted = (lead_speed + c.gap_gain_per_s * (gap_m - desired_gap_m))
                    .clamp(0.0, c.max_speed_mps);
                (
                    c.speed_gain_per_s * (wanted - self.speed_ref_mps),
                    desired_gap_m,
                )
            }
        };
        accel_target = accel_target.clamp(-c.max_decel_mps2, c.max_accel_mps2);
        if required_decel_mps2 > c.collision_braking_mps2 {
            accel_target = accel_target
                .min(-(COLLISION_BRAKING_MARGIN * required_decel_mps2).min(c.max_decel_mps2));
        }
        // Firm braking may build up fast; everything else (including the small corrections
        // that noise asks for, which must not be rectified into a slower average speed)
        // moves at the comfortable jerk.
        let firm = accel_target < -0.5 * c.max_decel_mps2;
        let down = if firm && accel_target < self.accel_mps2.min(0.0) {
            c.max_brake_jerk_mps3
        } else {
            c.max_jerk_mps3
        } * dt_s;
        let up = c.max_jerk_mps3 * dt_s;
        self.accel_mps2 += (accel_target - self.accel_mps2).clamp(-down, up);
        self.speed_ref_mps += self.accel_mps2 * dt_s;
        let low = (speed_mps - REFERENCE_LEASH_MPS).max(0.0);
        let high = speed_mps.max(0.0) + REFERENCE_LEASH_MPS;
        self.speed_ref_mps = self.speed_ref_mps.clamp(low, high);
        if self.speed_ref_mps <= 0.0 {
            self.accel_mps2 = self.accel_mps2.max(0.0);
        }
        SpeedCommand {
            speed_mps: self.speed_ref_mps,
            accel_mps2: self.accel_mps2,
            emergency: false,
            desired_gap_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_clamps_the_time_headway() {
        let c = GapKeeperConfig {
            policy: GapPolicy::TimeHeadway {
                standstill_gap_m: 2.0,
                headway_s: 1.0,
            },
            ..GapKeeperConfig::default()
        };
        assert_eq!(c.desired_gap_m(0.0), 5.0);
        assert_eq!(c.desired_gap_m(8.0), 10.0);
        assert_eq!(c.desired_gap_m(30.0), 15.0);
    }

    #[test]
    fn jerk_limit_bounds_the_acceleration_change() {
        let mut g = GapKeeper::new(GapKeeperConfig::default(), 10.0).unwrap();
        let dt = 1.0 / 120.0;
        let mut last = 0.0;
        for _ in 0..240 {
            let cmd = g.update(14.0, 0.0, Threat::default(), 10.0, dt);
            assert!((cmd.accel_mps2 - last).abs() <= 2.5 * dt + 1e-6);
            assert!(cmd.accel_mps2 <= 1.5 + 1e-6);
            last = cmd.accel_mps2;
        }
        assert!(last > 0.0);
    }

    #[test]
    fn fast_closing_calls_the_emergency_brake() {
        let c = GapKeeperConfig::default();
        assert!(c.emergency_needed(6.0, -6.0, 10.0));
        assert!(!c.emergency_needed(10.0, -1.0, 10.0));
        assert!(c.emergency_needed(2.0, 0.0, 0.0));
        // Steady following at the default gap and 10 m/s is safe; a lead already 4 m/s
        // slower at 9 m may be stopping hard: inside the safe gap and closing.
        assert!(!c.emergency_needed(10.0, 0.0, 10.0));
        assert!(c.emergency_needed(9.0, -4.0, 10.0));
        // Inside the safe gap but holding it: brake, no emergency.
        assert!(c.safe_gap_m(7.0, 7.0) > 4.5);
        assert!(!c.emergency_needed(4.5, 0.0, 7.0));
        assert!(!c.emergency_needed(4.5, -1.0, 7.0));
    }

    #[test]
    fn a_gap_below_the_safe_gap_is_opened_by_braking_not_slammed() {
        let c = GapKeeperConfig {
            policy: GapPolicy::ConstantDistance { gap_m: 4.5 },
            min_gap_m: 4.0,
            ..GapKeeperConfig::default()
        };
        // At 7 m/s behind a lead at 7 m/s the safe gap is above the policy's 4.5 m.
        let safe = c.safe_gap_m(7.0, 7.0);
        assert!(safe > 4.5, "safe gap {safe}");
        let mut g = GapKeeper::new(c.clone(), 7.0).unwrap();
        let dt = 1.0 / 120.0;
        let mut cmd = g.update(4.5, 0.0, Threat::default(), 7.0, dt);
        for _ in 0..120 {
            cmd = g.update(4.5, 0.0, Threat::default(), 7.0, dt);
            assert!(!cmd.emergency);
        }
        assert_eq!(cmd.desired_gap_m, safe);
        assert!(cmd.accel_mps2 < -0.1, "not braking: {cmd:?}");
        assert!(
            cmd.accel_mps2 > -c.max_decel_mps2,
            "braking too hard: {cmd:?}"
        );
    }
}
