//! The ground: a flat plane at y = 0, optionally with gentle bumps so the chassis pitches and
//! rolls.
//!
//! Bumps are a rapier heightfield over a square patch centred on the origin. They only rise
//! above the plane (heights are never negative) and fade to zero at the patch's edge, so the
//! patch joins the flat plane without a step.

use crate::error::{check_range, VehicleError};
use crate::rng_stream::named_stream;
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::f32::consts::TAU;

/// How many sinusoidal waves are summed to make the bumps: enough to look irregular.
const BUMP_WAVES: usize = 4;
/// Width of the band along the patch's edge over which bumps fade to zero, m.
const BUMP_FADE_M: f32 = 10.0;

/// The ground's shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct GroundConfig {
    /// Half the side of the flat square ground, m (default 2,000 m: room for any route).
    pub half_extent_m: f32,
    /// Optional bumps.
    pub bumps: Option<BumpsConfig>,
}

impl Default for GroundConfig {
    fn default() -> Self {
        GroundConfig {
            half_extent_m: 2000.0,
            bumps: None,
        }
    }
}

/// Gentle bumps over a square patch centred on the world origin.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct BumpsConfig {
    /// Largest bump height, m (default 0.08 m: the chassis visibly pitches and rolls a few
    /// tenths of a degree, as on a rough paved road).
    #[schemars(extend("minimum" = 0.0, "maximum" = 1.0))]
    pub amplitude_m: f32,
    /// Typical distance between bump crests, m (default 9 m, between the wheelbase and three
    /// wheelbases, so front and rear axles see different heights).
    #[schemars(extend("minimum" = 1.0, "maximum" = 200.0))]
    pub wavelength_m: f32,
    /// Half the side of the bumpy patch, m (default 300 m).
    pub half_extent_m: f32,
    /// Heightfield cell size, m (default 0.5 m, fine enough for 0.47 m wheels).
    #[schemars(extend("minimum" = 0.05, "maximum" = 5.0))]
    pub cell_m: f32,
    /// Seed of the bumps' random phases and directions (a named stream `"ground_bumps"`).
    pub seed: u64,
}

impl Default for BumpsConfig {
    fn default() -> Self {
        BumpsConfig {
            amplitude_m: 0.08,
            wavelength_m: 9.0,
            half_extent_m: 300.0,
            cell_m: 0.5,
            seed: 0,
        }
    }
}

/// One plane wave of the bump field: `h = a (1 + sin(k·p + φ)) / 2`.
#[derive(Copy, Clone, Debug, PartialEq)]
struct BumpWave {
    kx: f32,
    kz: f32,
    phase: f32,
}

/// The ground as built: a flat plane and an optional bump field.
#[derive(Clone, Debug, PartialEq)]
pub struct Ground {
    config: GroundConfig,
    waves: Vec<BumpWave>,
}

impl Ground {
    /// Checks the configuration and draws the bump waves from the seed.
    pub fn new(config: &GroundConfig) -> Result<Ground, VehicleError> {
        check_range("half_extent_m", f64::from(config.half_extent_m), 10.0, 1e5)?;
        let mut waves = Vec::new();
        if let Some(b) = &config.bumps {
            check_range("bumps.amplitude_m", f64::from(b.amplitude_m), 0.0, 1.0)?;
            check_range("bumps.wavelength_m", f64::from(b.wavelength_m), 1.0, 200.0)?;
            check_range(
                "bumps.half_extent_m",
                f64::from(b.half_extent_m),
                f64::from(2.0 * BUMP_FADE_M),
                f64::from(config.half_extent_m),
            )?;
            check_range("bumps.cell_m", f64::from(b.cell_m), 0.05, 5.0)?;
            let mut rng = named_stream(b.seed, "ground_bumps");
            for _ in 0..BUMP_WAVES {
                let direction = rng.random_range(0.0..TAU);
                let wavelength = b.wavelength_m * rng.random_range(0.6..1.4);
                let k = TAU / wavelength;
                waves.push(BumpWave {
                    kx: k * direction.cos(),
                    kz: k * direction.sin(),
                    phase: rng.random_range(0.0..TAU),
                });
            }
        }
        Ok(Ground {
            config: config.clone(),
            waves,
        })
    }

    /// The configuration this ground was built from.
    pub fn config(&self) -> &GroundConfig {
        &self.config
    }

    /// Height of the ground surface above y = 0 at world (x, z), m (the smooth field; the
    /// physics uses it sampled on the heightfield grid).
    pub fn height_m(&self, x: f32, z: f32) -> f32 {
        let Some(b) = &self.config.bumps else {
            return 0.0;
        };
        let edge = b.half_extent_m - x.abs().max(z.abs());
        if edge <= 0.0 {
            return 0.0;
        }
        let t = (edge / BUMP_FADE_M).min(1.0);
        let fade = t * t * (3.0 - 2.0 * t);
        let mut sum = 0.0;
        for w in &self.waves {
            sum += 0.5 * (1.0 + (w.kx * x + w.kz * z + w.phase).sin());
        }
        b.amplitude_m * fade * sum / BUMP_WAVES as f32
    }

    /// The bump patch sampled for a rapier heightfield: `(heights, rows, cols, cell_m,
    /// half_extent_m)`, rows along z and columns along x, column-major (`i + j * rows`).
    /// `None` when the ground is flat.
    pub fn bump_grid(&self) -> Option<(Vec<f32>, usize, usize, f32, f32)> {
        let b = self.config.bumps.as_ref()?;
        let cells = (2.0 * b.half_extent_m / b.cell_m).round() as usize;
        let n = cells + 1;
        let cell = 2.0 * b.half_extent_m / cells as f32;
        let mut heights = vec![0.0; n * n];
        for j in 0..n {
            let x = -b.half_extent_m + j as f32 * cell;
            for i in 0..n {
                let z = -b.half_extent_m + i as f32 * cell;
                heights[i + j * n] = self.height_m(x, z);
            }
        }
        Some((heights, n, n, cell, b.half_extent_m))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_ground_is_zero() {
        let g = Ground::new(&GroundConfig::default()).unwrap();
        assert_eq!(g.height_m(12.0, -3.0), 0.0);
        assert!(g.bump_grid().is_none());
    }

    #[test]
    fn bumps_are_bounded_and_fade_at_the_edge() {
        let cfg = GroundConfig {
            bumps: Some(BumpsConfig::default()),
            ..GroundConfig::default()
        };
        let g = Ground::new(&cfg).unwrap();
        let mut max: f32 = 0.0;
        for i in 0..200 {
            let h = g.height_m(i as f32 * 0.37, i as f32 * 0.11);
            assert!((0.0..=0.08 + 1e-6).contains(&h));
            max = max.max(h);
        }
        assert!(max > 0.03, "bumps too flat: {max}");
        assert_eq!(g.height_m(300.0, 0.0), 0.0);
    }
}
