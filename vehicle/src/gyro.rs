//! The chase vehicle's rate gyro: its own rotation between camera frames, as a strapdown
//! inertial sensor measures it, for the tracker's ego-motion aided prediction.
//!
//! The model is the usual one for a MEMS rate gyro (IEEE Std 952-1997's terms): each axis
//! reads the true rate plus a constant bias, drawn once per run, plus white rate noise.
//! Integrated over an interval Δt, the angle error is bias·Δt plus a random walk of
//! standard deviation N·√Δt, N the noise density. The defaults are those of an automotive
//! MEMS inertial unit after its turn-on calibration.

use crate::rng_stream::named_stream;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// The gyro's error model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct GyroConfig {
    /// Rate noise density, degrees per second per √Hz (default 0.014: a current automotive
    /// MEMS gyro's data sheet figure; over one 1/15 s frame it is a 0.004° angle error,
    /// a fiftieth of a pixel for the default camera).
    pub noise_density_dps_per_rthz: f64,
    /// Standard deviation of each axis's constant bias, degrees per second (default 0.1:
    /// the residual offset after turn-on calibration; 0.007° a frame).
    pub bias_sigma_dps: f64,
}

impl Default for GyroConfig {
    fn default() -> Self {
        GyroConfig {
            noise_density_dps_per_rthz: 0.014,
            bias_sigma_dps: 0.1,
        }
    }
}

/// A rate gyro with its bias, drawn once from the run's seed (stream `"gyro"`).
#[derive(Clone, Debug)]
pub struct Gyro {
    bias_rad_s: [f64; 3],
    noise: Normal<f64>,
    rng: ChaCha8Rng,
}

impl Gyro {
    /// A gyro with the error model `config`, seeded by `seed`. Non-finite or negative
    /// settings count as zero.
    pub fn new(config: &GyroConfig, seed: u64) -> Gyro {
        let clean = |v: f64| if v.is_finite() { v.max(0.0) } else { 0.0 };
        let mut rng = named_stream(seed, "gyro");
        let bias = Normal::new(0.0, clean(config.bias_sigma_dps).to_radians())
            .expect("finite, non-negative sigma");
        let bias_rad_s = [0; 3].map(|_| bias.sample(&mut rng));
        Gyro {
            bias_rad_s,
            noise: Normal::new(0.0, clean(config.noise_density_dps_per_rthz).to_radians())
                .expect("finite, non-negative sigma"),
            rng,
        }
    }

    /// The measured rotation over an interval of `dt_s` seconds whose true rotation vector
    /// is `true_rotation_rad` (axis times angle, any frame fixed to the vehicle): the truth
    /// plus bias·Δt plus an angle random walk of N·√Δt on each axis.
    pub fn measure(&mut self, true_rotation_rad: [f64; 3], dt_s: f64) -> [f64; 3] {
        let dt = if dt_s.is_finite() { dt_s.max(0.0) } else { 0.0 };
        let walk = dt.sqrt();
        let mut out = true_rotation_rad;
        for (v, b) in out.iter_mut().zip(self.bias_rad_s) {
            *v += b * dt + self.noise.sample(&mut self.rng) * walk;
        }
        out
    }

    /// The bias drawn for this run, radians per second per axis.
    pub fn bias_rad_s(&self) -> [f64; 3] {
        self.bias_rad_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_follow_the_model() {
        let config = GyroConfig::default();
        let mut g = Gyro::new(&config, 7);
        let dt = 1.0 / 15.0;
        let n = 20_000;
        let mut errors = [0.0f64; 3];
        let mut squares = [0.0f64; 3];
        for _ in 0..n {
            let m = g.measure([0.01, -0.02, 0.0], dt);
            for (k, (e, s)) in errors.iter_mut().zip(&mut squares).enumerate() {
                let err = m[k] - [0.01, -0.02, 0.0][k] - g.bias_rad_s()[k] * dt;
                *e += err;
                *s += err * err;
            }
        }
        let sigma = config.noise_density_dps_per_rthz.to_radians() * dt.sqrt();
        for k in 0..3 {
            let mean = errors[k] / n as f64;
            let sd = (squares[k] / n as f64 - mean * mean).sqrt();
            assert!(mean.abs() < 4.0 * sigma / (n as f64).sqrt(), "mean {mean}");
            assert!((sd / sigma - 1.0).abs() < 0.05, "sd {sd} vs {sigma}");
        }
        // The same seed gives the same readings.
        let mut a = Gyro::new(&config, 3);
        let mut b = Gyro::new(&config, 3);
        assert_eq!(a.measure([0.0; 3], dt), b.measure([0.0; 3], dt));
    }
}
