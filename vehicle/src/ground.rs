//! The ground: a flat plane at y = 0, optionally with gentle bumps so the chassis pitches and
//! rolls, and optionally rising and falling with a road's height (a [`GroundProfile`]).
//!
//! Bumps are a rapier heightfield over a square patch centred on the origin. They only rise
//! above the plane (heights are never negative) and fade to zero at the patch's edge, so the
//! patch joins the flat plane without a step. With a profile, one heightfield covers the
//! road and its margin: the profile's height at the nearest centreline point, plus the bumps.

use crate::error::{check_range, VehicleError};
use crate::ground_profile::{GroundProfile, NearestHeight, MAX_PROFILE_GRID_POINTS};
use crate::rng_stream::named_stream;
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::f32::consts::TAU;
use std::sync::{Arc, Mutex};

/// The last profile grid built in this process and the configuration it was built from:
/// the physics and the renderer build their grounds from one configuration, and a profile's
/// grid (a million points over a 1.5 km road) is filled once for both
/// ([`Ground::shared_grid`]).
static LAST_PROFILE_GRID: Mutex<Option<(GroundConfig, Arc<GroundGrid>)>> = Mutex::new(None);

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
    /// The road's height along its centreline, when it rises and falls (none: flat).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<GroundProfile>,
}

impl Default for GroundConfig {
    fn default() -> Self {
        GroundConfig {
            half_extent_m: 2000.0,
            bumps: None,
            profile: None,
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

/// A heightfield's samples as rapier takes them: rows along z and columns along x,
/// column-major (`i + j * rows`), the grid's corner at (`x0_m`, `z0_m`).
#[derive(Clone, Debug, PartialEq)]
pub struct GroundGrid {
    /// The heights, metres.
    pub heights: Vec<f32>,
    /// Grid points along z.
    pub rows: usize,
    /// Grid points along x.
    pub cols: usize,
    /// Cell side, metres.
    pub cell_m: f32,
    /// World x of the first column, metres.
    pub x0_m: f32,
    /// World z of the first row, metres.
    pub z0_m: f32,
}

impl GroundGrid {
    /// World x of the last column, metres.
    pub fn x1_m(&self) -> f32 {
        self.x0_m + self.cell_m * (self.cols - 1) as f32
    }

    /// World z of the last row, metres.
    pub fn z1_m(&self) -> f32 {
        self.z0_m + self.cell_m * (self.rows - 1) as f32
    }
}

/// The ground as built: a flat plane, an optional bump field and an optional profile.
#[derive(Clone, Debug, PartialEq)]
pub struct Ground {
    config: GroundConfig,
    waves: Vec<BumpWave>,
    nearest: Option<NearestHeight>,
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
        let nearest = match &config.profile {
            Some(p) => {
                p.validate()?;
                Some(NearestHeight::new(p))
            }
            None => None,
        };
        Ok(Ground {
            config: config.clone(),
            waves,
            nearest,
        })
    }

    /// The configuration this ground was built from.
    pub fn config(&self) -> &GroundConfig {
        &self.config
    }

    /// Height of the ground surface above y = 0 at world (x, z), m (the smooth field; the
    /// physics uses it sampled on the heightfield grid): the profile's, plus the bumps'.
    pub fn height_m(&self, x: f32, z: f32) -> f32 {
        match &self.nearest {
            Some(n) => {
                (n.height_m(f64::from(x), f64::from(z)) + f64::from(self.bump_m(x, z))) as f32
            }
            None => self.bump_m(x, z),
        }
    }

    /// Height of the bumps at world (x, z), m (0 without bumps).
    fn bump_m(&self, x: f32, z: f32) -> f32 {
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

    /// The ground sampled for a rapier heightfield: the bump patch alone (centred on the
    /// origin, its own cell), or with a profile the box of the profile's samples plus its
    /// margin (and the bump patch), at the finer of the two cells, made coarser if the grid
    /// would pass [`MAX_PROFILE_GRID_POINTS`]. `None` when the ground is flat.
    pub fn grid(&self) -> Option<GroundGrid> {
        let Some(p) = &self.config.profile else {
            return self.bump_grid();
        };
        let mut b = p.bounds();
        let mut cell = f64::from(p.cell_m);
        if let Some(bumps) = &self.config.bumps {
            let h = f64::from(bumps.half_extent_m);
            b = [b[0].min(-h), b[1].min(-h), b[2].max(h), b[3].max(h)];
            cell = cell.min(f64::from(bumps.cell_m));
        }
        let area = (b[2] - b[0]) * (b[3] - b[1]);
        cell = cell.max((area / MAX_PROFILE_GRID_POINTS).sqrt());
        let cell = cell as f32;
        let cols = ((b[2] - b[0]) / f64::from(cell)).ceil() as usize + 1;
        let rows = ((b[3] - b[1]) / f64::from(cell)).ceil() as usize + 1;
        let (x0, z0) = (b[0] as f32, b[1] as f32);
        let nearest = self.nearest.as_ref().expect("a profile has its search");
        let road = nearest.grid_heights(rows, cols, f64::from(x0), f64::from(z0), f64::from(cell));
        let mut heights = vec![0.0; rows * cols];
        for j in 0..cols {
            let x = x0 + j as f32 * cell;
            for i in 0..rows {
                let z = z0 + i as f32 * cell;
                let q = i + j * rows;
                heights[q] = (road[q] + f64::from(self.bump_m(x, z))) as f32;
            }
        }
        Some(GroundGrid {
            heights,
            rows,
            cols,
            cell_m: cell,
            x0_m: x0,
            z0_m: z0,
        })
    }

    /// [`Ground::grid`], shared: with a profile, the grid last built in this process from
    /// an equal configuration (the same heights, filled once), else a new one. The lock is
    /// held while a grid is filled, so a second caller with the same configuration waits
    /// for it rather than filling it again.
    pub fn shared_grid(&self) -> Option<Arc<GroundGrid>> {
        if self.config.profile.is_none() {
            return self.grid().map(Arc::new);
        }
        let mut last = LAST_PROFILE_GRID
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((config, grid)) = last.as_ref() {
            if *config == self.config {
                return Some(Arc::clone(grid));
            }
        }
        let grid = Arc::new(self.grid()?);
        *last = Some((self.config.clone(), Arc::clone(&grid)));
        Some(grid)
    }

    /// The bump patch alone, as [`Ground::grid`] gives it.
    fn bump_grid(&self) -> Option<GroundGrid> {
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
        Some(GroundGrid {
            heights,
            rows: n,
            cols: n,
            cell_m: cell,
            x0_m: -b.half_extent_m,
            z0_m: -b.half_extent_m,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_ground_is_zero() {
        let g = Ground::new(&GroundConfig::default()).unwrap();
        assert_eq!(g.height_m(12.0, -3.0), 0.0);
        assert!(g.grid().is_none());
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
