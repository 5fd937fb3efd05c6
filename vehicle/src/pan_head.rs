//! The camera's pan head: a motor that turns the camera about the chase vehicle's vertical
//! axis, so that the lead stays in view through turns a fixed camera's field of view cannot
//! hold, and its encoder, which tells the controller and stage 8 where the camera points.
//!
//! The head is a rate-commanded axis, as pan-tilt units are driven: it follows the
//! commanded rate within its acceleration limit, never faster than its rate limit, and stops
//! at its mechanical limits. The encoder reads the angle some time ago (its sampling and
//! bus latency) plus white noise; nobody but the renderer and the ground truth sees the
//! true angle.
//!
//! Angles are positive to the right (clockwise seen from above): a camera panned by θ
//! looks along the vehicle's forward axis turned θ towards its right side.

use crate::clock::{steps_from_ms, PHYSICS_DT_S};
use crate::error::{check_range, VehicleError};
use crate::rng_stream::named_stream;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The pan head's configuration (scenario `[camera.pan]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct PanHeadConfig {
    /// Whether the camera pans (default `false`: the paper's camera, fixed above the cab).
    pub enabled: bool,
    /// Fastest turn, degrees per second (default 90 °/s: a mid-range pan-tilt unit; the
    /// lead's bearing changes at up to about 45 °/s through a right-angle turn of 18 m
    /// radius at 7 m/s and a 10 m gap).
    #[schemars(extend("minimum" = 0.1, "maximum" = 2000.0))]
    pub max_rate_deg_s: f64,
    /// Largest angular acceleration, degrees per second squared (default 360 °/s²: full
    /// rate in a quarter of a second).
    #[schemars(extend("minimum" = 0.1, "maximum" = 100000.0))]
    pub max_accel_deg_s2: f64,
    /// Mechanical limit either side of straight ahead, degrees (default 100°).
    #[schemars(extend("minimum" = 0.0, "maximum" = 180.0))]
    pub limit_deg: f64,
    /// Encoder latency: the reading is the angle this long ago, ms (default 8 ms: one
    /// sample of a 125 Hz encoder bus).
    #[schemars(extend("minimum" = 0.0, "maximum" = 1000.0))]
    pub encoder_latency_ms: f64,
    /// Encoder noise, one standard deviation, degrees (default 0.02°: a 14-bit encoder's
    /// quantisation; a hundredth of a pixel's angle is 0.18° for the default camera).
    #[schemars(extend("minimum" = 0.0, "maximum" = 10.0))]
    pub encoder_noise_deg: f64,
    /// The aim's proportional gain: commanded rate per angle of aim error, 1/s (default
    /// 6 /s: the head settles within about half a second, three times faster than the
    /// lead's bearing changes through a turn, and slow enough that the tracker's 15 Hz
    /// estimates, 128 ms late, do not make it hunt).
    #[schemars(extend("minimum" = 0.01, "maximum" = 100.0))]
    pub gain_per_s: f64,
}

impl Default for PanHeadConfig {
    fn default() -> Self {
        PanHeadConfig {
            enabled: false,
            max_rate_deg_s: 90.0,
            max_accel_deg_s2: 360.0,
            limit_deg: 100.0,
            encoder_latency_ms: 8.0,
            encoder_noise_deg: 0.02,
            gain_per_s: 6.0,
        }
    }
}

impl PanHeadConfig {
    /// Checks the values (all of them, enabled or not, so that a scenario that turns the
    /// head on later is not refused then).
    pub fn validate(&self) -> Result<(), VehicleError> {
        check_range("max_rate_deg_s", self.max_rate_deg_s, 0.1, 2000.0)?;
        check_range("max_accel_deg_s2", self.max_accel_deg_s2, 0.1, 100_000.0)?;
        check_range("limit_deg", self.limit_deg, 0.0, 180.0)?;
        check_range("encoder_latency_ms", self.encoder_latency_ms, 0.0, 1000.0)?;
        check_range("encoder_noise_deg", self.encoder_noise_deg, 0.0, 10.0)?;
        check_range("gain_per_s", self.gain_per_s, 0.01, 100.0)
    }

    /// The rate to command for an aim error `error_rad` (the wanted angle less the
    /// encoder's), rad/s: proportional, but never faster than the head can stop from
    /// within the error at its acceleration limit (√(2·a·|e|)), so that it does not
    /// overshoot; the head's own limits apply on top.
    pub fn rate_for_error(&self, error_rad: f64) -> f64 {
        let accel = self.max_accel_deg_s2.to_radians();
        let stoppable = (2.0 * accel * error_rad.abs()).sqrt();
        let rate = (self.gain_per_s * error_rad.abs())
            .min(stoppable)
            .min(self.max_rate_deg_s.to_radians());
        rate.copysign(error_rad)
    }
}

/// The pan head and its encoder.
#[derive(Clone, Debug)]
pub struct PanHead {
    config: PanHeadConfig,
    angle_rad: f64,
    rate_rad_s: f64,
    /// True angles of the last `latency + 1` steps, oldest first.
    history: VecDeque<f64>,
    latency_steps: usize,
    reading_rad: f64,
    noise: Normal<f64>,
    rng: ChaCha8Rng,
}

impl PanHead {
    /// A head pointing straight ahead, its encoder noise seeded from `seed` (stream
    /// `"pan-encoder"`).
    pub fn new(config: PanHeadConfig, seed: u64) -> Result<PanHead, VehicleError> {
        config.validate()?;
        let latency_steps = steps_from_ms(config.encoder_latency_ms) as usize;
        Ok(PanHead {
            noise: Normal::new(0.0, config.encoder_noise_deg.to_radians())
                .expect("validated: finite, non-negative"),
            rng: named_stream(seed, "pan-encoder"),
            history: std::iter::repeat_n(0.0, latency_steps + 1).collect(),
            latency_steps,
            angle_rad: 0.0,
            rate_rad_s: 0.0,
            reading_rad: 0.0,
            config,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PanHeadConfig {
        &self.config
    }

    /// The true angle, radians (positive to the right): for the renderer and the truth only.
    pub fn angle_rad(&self) -> f64 {
        self.angle_rad
    }

    /// The true rate, rad/s.
    pub fn rate_rad_s(&self) -> f64 {
        self.rate_rad_s
    }

    /// The encoder's reading at the last step, radians.
    pub fn reading_rad(&self) -> f64 {
        self.reading_rad
    }

    /// The encoder's latency in physics steps.
    pub fn latency_steps(&self) -> usize {
        self.latency_steps
    }

    /// One physics step with the commanded rate `rate_cmd_rad_s`: the rate moves towards it
    /// within the acceleration limit and stays within the rate limit, the angle within the
    /// mechanical limits (reaching one stops the head); then the encoder is read.
    pub fn step(&mut self, rate_cmd_rad_s: f64) {
        let dt = f64::from(PHYSICS_DT_S);
        let c = &self.config;
        let max_rate = c.max_rate_deg_s.to_radians();
        let limit = c.limit_deg.to_radians();
        let cmd = if rate_cmd_rad_s.is_finite() {
            rate_cmd_rad_s.clamp(-max_rate, max_rate)
        } else {
            0.0
        };
        let dv = c.max_accel_deg_s2.to_radians() * dt;
        self.rate_rad_s += (cmd - self.rate_rad_s).clamp(-dv, dv);
        self.angle_rad += self.rate_rad_s * dt;
        if self.angle_rad.abs() > limit {
            self.angle_rad = self.angle_rad.clamp(-limit, limit);
            self.rate_rad_s = 0.0;
        }
        self.history.push_back(self.angle_rad);
        if self.history.len() > self.latency_steps + 1 {
            self.history.pop_front();
        }
        let seen = self.history.front().copied().unwrap_or(self.angle_rad);
        self.reading_rad = seen + self.noise.sample(&mut self.rng);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head(config: PanHeadConfig) -> PanHead {
        PanHead::new(config, 1).unwrap()
    }

    #[test]
    fn the_rate_and_acceleration_limits_hold() {
        let mut h = head(PanHeadConfig::default());
        let dt = f64::from(PHYSICS_DT_S);
        let mut last = 0.0;
        for _ in 0..120 {
            h.step(10.0);
            let rate = h.rate_rad_s();
            assert!(rate <= 90f64.to_radians() + 1e-12);
            assert!(rate - last <= 360f64.to_radians() * dt + 1e-12);
            last = rate;
        }
        // Full rate after 0.25 s of acceleration, so 1 s turns 90·0.75 + 90·0.25/2 degrees.
        let want = 90.0 * 0.75 + 0.5 * 90.0 * 0.25;
        assert!(
            (h.angle_rad().to_degrees() - want).abs() < 0.5,
            "{}",
            h.angle_rad().to_degrees()
        );
    }

    #[test]
    fn the_mechanical_limit_stops_the_head() {
        let mut h = head(PanHeadConfig {
            limit_deg: 30.0,
            ..PanHeadConfig::default()
        });
        for _ in 0..600 {
            h.step(-10.0);
        }
        assert_eq!(h.angle_rad(), -(30f64.to_radians()));
        assert_eq!(h.rate_rad_s(), 0.0);
    }

    #[test]
    fn the_encoder_reads_the_angle_its_latency_ago_with_its_noise() {
        let config = PanHeadConfig {
            encoder_latency_ms: 25.0,
            encoder_noise_deg: 0.0,
            ..PanHeadConfig::default()
        };
        let mut h = head(config);
        assert_eq!(h.latency_steps(), 3);
        let mut angles = Vec::new();
        for _ in 0..60 {
            h.step(1.0);
            angles.push(h.angle_rad());
            if angles.len() > 3 {
                assert_eq!(h.reading_rad(), angles[angles.len() - 4]);
            }
        }
        // With noise: the readings scatter about the delayed angle by the noise's σ.
        let mut noisy = head(PanHeadConfig {
            encoder_noise_deg: 0.5,
            ..PanHeadConfig::default()
        });
        let n = 4000;
        let mut sum2 = 0.0;
        for _ in 0..n {
            noisy.step(0.0);
            sum2 += noisy.reading_rad().powi(2);
        }
        let sigma = (sum2 / f64::from(n)).sqrt().to_degrees();
        assert!((sigma - 0.5).abs() < 0.03, "σ {sigma}");
    }

    #[test]
    fn the_aim_settles_without_overshoot() {
        let c = PanHeadConfig {
            encoder_noise_deg: 0.0,
            ..PanHeadConfig::default()
        };
        let mut h = head(c.clone());
        let want = 40f64.to_radians();
        let mut peak: f64 = 0.0;
        for _ in 0..240 {
            let cmd = c.rate_for_error(want - h.reading_rad());
            h.step(cmd);
            peak = peak.max(h.angle_rad());
        }
        assert!((h.angle_rad() - want).abs() < 0.2f64.to_radians());
        assert!(
            peak < want + 1f64.to_radians(),
            "overshoot to {}",
            peak.to_degrees()
        );
    }

    #[test]
    fn bad_settings_are_refused_by_name() {
        let e = PanHeadConfig {
            max_rate_deg_s: 0.0,
            ..PanHeadConfig::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("max_rate_deg_s"), "{e}");
    }
}
