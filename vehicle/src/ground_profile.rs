//! A road's height along its centreline, spread sideways: the ground at a point is as high
//! as the road at the nearest point of its centreline, so the ground beside a road that
//! rises and falls follows the road.

use crate::error::{check_range, VehicleError};
use serde::{Deserialize, Serialize};

/// Side of the square buckets the centreline's pieces are filed in for the nearest-point
/// search, m: a few dozen one-metre pieces each, so a query looks at few pieces and few
/// empty buckets.
const BUCKET_M: f64 = 25.0;
/// The most grid points a profile's heightfield may have: 8 Mi points are 32 MB of heights
/// (rapier keeps one copy, the renderer another); a wider ground gets coarser cells.
pub const MAX_PROFILE_GRID_POINTS: f64 = 8.0 * 1024.0 * 1024.0;

/// A road's height along its centreline, for the ground to follow.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GroundProfile {
    /// Centreline samples in driving order: world x, world z and the road's height there,
    /// metres (at least two).
    pub points: Vec<[f64; 3]>,
    /// Heightfield cell side, metres (0.05–20; made coarser when the ground would need
    /// more than [`MAX_PROFILE_GRID_POINTS`] points).
    pub cell_m: f32,
    /// How far the heightfield reaches beyond the samples, metres (0–5,000).
    pub margin_m: f32,
}

impl GroundProfile {
    /// Checks the profile: at least two finite samples, a cell and margin within bounds.
    pub(crate) fn validate(&self) -> Result<(), VehicleError> {
        check_range("profile.cell_m", f64::from(self.cell_m), 0.05, 20.0)?;
        check_range("profile.margin_m", f64::from(self.margin_m), 0.0, 5000.0)?;
        check_range("profile.points", self.points.len() as f64, 2.0, 1e7)?;
        for p in &self.points {
            for &v in p {
                check_range("profile.points", v, -1e6, 1e6)?;
            }
        }
        Ok(())
    }

    /// The plan box the heightfield covers: `[min x, min z, max x, max z]`, metres.
    pub(crate) fn bounds(&self) -> [f64; 4] {
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for p in &self.points {
            b = [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ];
        }
        let m = f64::from(self.margin_m);
        [b[0] - m, b[1] - m, b[2] + m, b[3] + m]
    }
}

/// The centreline's pieces filed in square buckets, for the height at the nearest point.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NearestHeight {
    points: Vec<[f64; 3]>,
    /// The buckets' corner (min x, min z), metres.
    origin: [f64; 2],
    /// Buckets along x and along z.
    dims: [usize; 2],
    /// The pieces (index of their first point) touching each bucket, `bx + bz * dims[0]`.
    buckets: Vec<Vec<u32>>,
}

impl NearestHeight {
    /// Files `profile`'s pieces.
    pub(crate) fn new(profile: &GroundProfile) -> NearestHeight {
        let b = profile.bounds();
        let origin = [b[0], b[1]];
        let dims = [
            ((b[2] - b[0]) / BUCKET_M).ceil().max(1.0) as usize,
            ((b[3] - b[1]) / BUCKET_M).ceil().max(1.0) as usize,
        ];
        let mut buckets = vec![Vec::new(); dims[0] * dims[1]];
        let cell =
            |v: f64, o: f64, n: usize| (((v - o) / BUCKET_M).floor().max(0.0) as usize).min(n - 1);
        for (k, w) in profile.points.windows(2).enumerate() {
            let (x0, x1) = (w[0][0].min(w[1][0]), w[0][0].max(w[1][0]));
            let (z0, z1) = (w[0][1].min(w[1][1]), w[0][1].max(w[1][1]));
            for bz in cell(z0, origin[1], dims[1])..=cell(z1, origin[1], dims[1]) {
                for bx in cell(x0, origin[0], dims[0])..=cell(x1, origin[0], dims[0]) {
                    buckets[bx + bz * dims[0]].push(k as u32);
                }
            }
        }
        NearestHeight {
            points: profile.points.clone(),
            origin,
            dims,
            buckets,
        }
    }

    /// The road's height at the point of its centreline nearest to world (x, z), metres
    /// (linear between samples; the first of equally near pieces).
    pub(crate) fn height_m(&self, x: f64, z: f64) -> f64 {
        let [nx, nz] = self.dims.map(|n| n as i64);
        let bx = ((x - self.origin[0]) / BUCKET_M).floor() as i64;
        let bz = ((z - self.origin[1]) / BUCKET_M).floor() as i64;
        let (mut best_d2, mut best_h) = (f64::MAX, self.points[0][2]);
        let mut r: i64 = 0;
        loop {
            let mut any_inside = false;
            for cz in bz - r..=bz + r {
                for cx in bx - r..=bx + r {
                    if (cx - bx).abs() != r && (cz - bz).abs() != r {
                        continue;
                    }
                    if cx < 0 || cz < 0 || cx >= nx || cz >= nz {
                        continue;
                    }
                    any_inside = true;
                    for &k in &self.buckets[cx as usize + cz as usize * self.dims[0]] {
                        let (d2, h) = self.piece(k as usize, x, z);
                        if d2 < best_d2 {
                            (best_d2, best_h) = (d2, h);
                        }
                    }
                }
            }
            // Every piece in a ring beyond r is at least r buckets away.
            let reach = r as f64 * BUCKET_M;
            if (best_d2 < f64::MAX && best_d2 <= reach * reach) || (!any_inside && r > nx + nz) {
                return best_h;
            }
            r += 1;
        }
    }

    /// The road's height at the nearest centreline point of every point of a grid (`rows`
    /// along z, `cols` along x, column-major, corner (`x0`, `z0`), side `cell`): each piece
    /// seeds the grid points around it, then raster passes forward and back hand every
    /// point its neighbours' pieces, keeping the nearest (a distance transform carrying the
    /// pieces: a point's nearest piece is also nearest all along the way to it), each point
    /// also walking along the centreline from its best piece while the next is nearer.
    /// About 30 piece distances a point, where searching the buckets from far off costs
    /// hundreds.
    pub(crate) fn grid_heights(
        &self,
        rows: usize,
        cols: usize,
        x0: f64,
        z0: f64,
        cell: f64,
    ) -> Vec<f64> {
        const NONE: u32 = u32::MAX;
        let n = rows * cols;
        let (mut best, mut d2) = (vec![NONE; n], vec![f64::MAX; n]);
        let at = |i: usize, j: usize| (x0 + j as f64 * cell, z0 + i as f64 * cell);
        let offer = |best: &mut [u32], d2: &mut [f64], i: usize, j: usize, k: u32| {
            let (x, z) = at(i, j);
            let d = self.piece(k as usize, x, z).0;
            let q = i + j * rows;
            if d < d2[q] || (d == d2[q] && k < best[q]) {
                (best[q], d2[q]) = (k, d);
            }
        };
        let index = |v: f64, o: f64, n: usize| ((v - o) / cell).clamp(0.0, (n - 1) as f64);
        for k in 0..self.points.len() - 1 {
            let (a, b) = (self.points[k], self.points[k + 1]);
            let j0 = index(a[0].min(b[0]), x0, cols).floor() as usize;
            let j1 = index(a[0].max(b[0]), x0, cols).ceil() as usize;
            let i0 = index(a[1].min(b[1]), z0, rows).floor() as usize;
            let i1 = index(a[1].max(b[1]), z0, rows).ceil() as usize;
            for j in j0..=j1 {
                for i in i0..=i1 {
                    offer(&mut best, &mut d2, i, j, k as u32);
                }
            }
        }
        // Forward and backward raster passes, twice, each taking the pieces of the
        // neighbours already visited.
        for _ in 0..2 {
            for forward in [true, false] {
                for jj in 0..cols {
                    let j = if forward { jj } else { cols - 1 - jj };
                    for ii in 0..rows {
                        let i = if forward { ii } else { rows - 1 - ii };
                        let step: i64 = if forward { -1 } else { 1 };
                        for (di, dj) in [(step, 0), (0, step), (step, step), (-step, step)] {
                            let (ni, nj) = (i as i64 + di, j as i64 + dj);
                            if ni < 0 || nj < 0 || ni >= rows as i64 || nj >= cols as i64 {
                                continue;
                            }
                            let k = best[ni as usize + nj as usize * rows];
                            if k != NONE {
                                offer(&mut best, &mut d2, i, j, k);
                            }
                        }
                        // A piece whose region is narrower than a cell where it starts owns
                        // no point there to hand on: walk along the centreline from the
                        // best piece while the next one is nearer.
                        let q = i + j * rows;
                        if best[q] != NONE {
                            for dir in [-1i64, 1] {
                                loop {
                                    let k = best[q] as i64 + dir;
                                    if k < 0 || k as usize + 1 >= self.points.len() {
                                        break;
                                    }
                                    let before = best[q];
                                    offer(&mut best, &mut d2, i, j, k as u32);
                                    if best[q] == before {
                                        break;
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        (0..n)
            .map(|q| {
                let (i, j) = (q % rows, q / rows);
                let (x, z) = at(i, j);
                match best[q] {
                    NONE => self.height_m(x, z),
                    k => self.piece(k as usize, x, z).1,
                }
            })
            .collect()
    }

    /// Squared plan distance from (x, z) to piece `k` and the height at its nearest point.
    fn piece(&self, k: usize, x: f64, z: f64) -> (f64, f64) {
        let (a, b) = (self.points[k], self.points[k + 1]);
        let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dz * dz;
        let t = if len2 > 0.0 {
            (((x - a[0]) * dx + (z - a[1]) * dz) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (px, pz) = (a[0] + t * dx, a[1] + t * dz);
        (
            (x - px).powi(2) + (z - pz).powi(2),
            a[2] + t * (b[2] - a[2]),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bent centreline rising 1 m per 10 m, with its samples every metre.
    fn bent() -> GroundProfile {
        let mut points = Vec::new();
        for k in 0..=100 {
            points.push([k as f64, 0.0, 0.1 * k as f64]);
        }
        for k in 1..=100 {
            points.push([100.0, k as f64, 10.0 + 0.1 * k as f64]);
        }
        GroundProfile {
            points,
            cell_m: 1.0,
            margin_m: 60.0,
        }
    }

    #[test]
    fn the_nearest_search_is_the_brute_force_one() {
        let p = bent();
        let n = NearestHeight::new(&p);
        for k in 0..500 {
            let x = -50.0 + 0.37 * k as f64;
            let z = -55.0 + 0.33 * k as f64 + (k % 7) as f64 * 4.0;
            let mut best = (f64::MAX, 0.0);
            for i in 0..p.points.len() - 1 {
                let c = n.piece(i, x, z);
                if c.0 < best.0 {
                    best = c;
                }
            }
            assert_eq!(n.height_m(x, z), best.1, "({x}, {z})");
        }
        // The grid's distance transform finds the nearest piece's height, within what
        // choosing between pieces equally near can change (nothing, here).
        let (rows, cols, x0, z0, cell) = (90, 130, -58.0, -57.0, 1.3);
        let grid = n.grid_heights(rows, cols, x0, z0, cell);
        let mut worst = 0.0f64;
        for j in 0..cols {
            for i in 0..rows {
                let (x, z) = (x0 + j as f64 * cell, z0 + i as f64 * cell);
                worst = worst.max((grid[i + j * rows] - n.height_m(x, z)).abs());
            }
        }
        assert!(worst < 1e-9, "{worst}");
        // A tight arc (radius 40 m) of one-metre pieces climbing 10 %, on one-metre cells:
        // beyond the arc's outside a piece's region widens from less than a cell.
        let arc = GroundProfile {
            points: (0..=120)
                .map(|k| {
                    let a = k as f64 / 40.0;
                    [40.0 * a.sin(), 40.0 * (1.0 - a.cos()), 0.1 * k as f64]
                })
                .collect(),
            cell_m: 1.0,
            margin_m: 30.0,
        };
        let on_arc = NearestHeight::new(&arc);
        let (rows, cols, x0, z0, cell) = (130, 130, -45.0, -35.0, 1.0);
        let grid = on_arc.grid_heights(rows, cols, x0, z0, cell);
        // Away from the arc's centre, where every piece is nearly as near as any other (the
        // ground's height jumps across the medial axis there, whatever the search).
        let (mut worst, mut compared) = (0.0f64, 0);
        for j in 0..cols {
            for i in 0..rows {
                let (x, z) = (x0 + j as f64 * cell, z0 + i as f64 * cell);
                if (x.hypot(z - 40.0) - 40.0).abs() > 20.0 {
                    continue;
                }
                compared += 1;
                worst = worst.max((grid[i + j * rows] - on_arc.height_m(x, z)).abs());
            }
        }
        assert!(compared > 5000, "{compared}");
        assert!(worst < 1e-9, "arc: {worst}");
        // Beside the first leg the ground is as high as the road abreast.
        assert!((n.height_m(40.5, -30.0) - 4.05).abs() < 1e-12);
    }
}
