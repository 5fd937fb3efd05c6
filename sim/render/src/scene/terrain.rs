//! The ground's height, as the physics has it: the heightfield of `vehicle::Ground` (the bump
//! patch, or the road's profile with its margin), sampled on the same grid and cut into the
//! same triangles as the rapier heightfield the wheels roll on, so that the rendered road
//! rises and falls exactly where the vehicles pitch.

use super::error::SceneError;
use super::mesh::{Mesh, Vertex};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::Arc;
use vehicle::{Ground, GroundConfig, GroundGrid};

/// The physics' ground surface: flat at y = 0, with the heightfield when the ground has
/// bumps or a profile.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    /// The grid, its heights rows along z and columns along x, column-major
    /// (`i + j * rows`), as `vehicle::Ground::grid` gives them to rapier (with a profile,
    /// the one grid the physics was built from: `vehicle::Ground::shared_grid`).
    grid: Arc<GroundGrid>,
    /// Grid points along z.
    rows: usize,
    /// Grid points along x.
    cols: usize,
    /// Cell side, metres.
    cell_m: f64,
    /// The grid's corners, metres: `[x0, z0, x1, z1]`.
    corners: [f64; 4],
    /// Whether the heightfield follows a road's profile (it covers the whole site).
    profile: bool,
}

impl Terrain {
    /// The surface of `ground`; `None` when it is flat.
    pub fn new(ground: &GroundConfig) -> Result<Option<Terrain>, SceneError> {
        let ground = Ground::new(ground).map_err(|e| SceneError::Invalid {
            field: "ground".into(),
            reason: e.to_string(),
        })?;
        Ok(ground.shared_grid().map(|g| {
            let (x0, z0) = (f64::from(g.x0_m), f64::from(g.z0_m));
            let cell = f64::from(g.cell_m);
            // The bump patch alone is centred on the origin: its far corner is minus its
            // near one, exactly.
            let (x1, z1) = if ground.config().profile.is_none() {
                (-x0, -z0)
            } else {
                (
                    x0 + cell * (g.cols - 1) as f64,
                    z0 + cell * (g.rows - 1) as f64,
                )
            };
            Terrain {
                rows: g.rows,
                cols: g.cols,
                grid: g,
                cell_m: cell,
                corners: [x0, z0, x1, z1],
                profile: ground.config().profile.is_some(),
            }
        }))
    }

    /// Whether (x, z) lies on the heightfield (outside it the ground is flat at y = 0).
    pub fn covers(&self, x: f64, z: f64) -> bool {
        let [x0, z0, x1, z1] = self.corners;
        x > x0 && x < x1 && z > z0 && z < z1
    }

    /// Height of the physics' ground surface at world (x, z), metres: the heightfield's
    /// triangle over that point (rapier's cell split: the diagonal from the cell's corner at
    /// (x0, z1) to the one at (x1, z0)), and 0 off the patch.
    pub fn height_m(&self, x: f64, z: f64) -> f64 {
        if !self.covers(x, z) {
            return 0.0;
        }
        let [x0, z0, ..] = self.corners;
        let fx = ((x - x0) / self.cell_m).clamp(0.0, (self.cols - 1) as f64);
        let fz = ((z - z0) / self.cell_m).clamp(0.0, (self.rows - 1) as f64);
        // `fx`, `fz` are at least 0 (or NaN): the cast truncates as `floor` would, without
        // its library call (a draped scene asks millions of heights).
        let j = (fx as usize).min(self.cols - 2);
        let i = (fz as usize).min(self.rows - 2);
        let (u, v) = (fx - j as f64, fz - i as f64);
        let heights = &self.grid.heights;
        let h = |i: usize, j: usize| f64::from(heights[i + j * self.rows]);
        let (y00, y10, y01, y11) = (h(i, j), h(i + 1, j), h(i, j + 1), h(i + 1, j + 1));
        if u + v <= 1.0 {
            // Triangle (p00, p10, p01).
            y00 + u * (y01 - y00) + v * (y10 - y00)
        } else {
            // Triangle (p10, p11, p01).
            y11 + (1.0 - u) * (y10 - y11) + (1.0 - v) * (y01 - y11)
        }
    }

    /// The lowest and highest heights of the grid, metres.
    pub fn height_range_m(&self) -> [f64; 2] {
        let (lo, hi) = self
            .grid
            .heights
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)));
        [f64::from(lo), f64::from(hi)]
    }

    /// Whether the heightfield follows a road's profile (and so lies under all the grass).
    pub fn follows_profile(&self) -> bool {
        self.profile
    }

    /// The cell side, metres: surfaces drawn on the terrain are cut at least this fine.
    pub fn cell_m(&self) -> f64 {
        self.cell_m
    }
}

impl Terrain {
    /// `mesh` (flat ground-level surfaces in the world frame: road, paint, marks, verges)
    /// laid on the terrain: every triangle over the patch is cut by halving its longest edge
    /// until no edge is longer than `max_edge_m` (in plan), and every vertex is raised by the
    /// ground's height beneath it. Each vertex is then on the physics' surface (plus its
    /// height above the ground); between vertices the surface departs from it by at most
    /// the bump field's curvature times the edge squared over 8.
    /// Triangles short enough already keep their (shared) vertices; windings are kept;
    /// normals are the surface's. Triangles off the patch are kept as they are.
    pub fn drape(&self, mesh: &Mesh, max_edge_m: f64) -> Mesh {
        self.drape_marked(mesh, max_edge_m, &mut [])
    }

    /// [`Terrain::drape`], moving each of `marks` (a position in `mesh`'s indices, at the
    /// start of a triangle, in increasing order) to where that triangle's pieces start in the
    /// draped mesh: triangles come out in the order they went in.
    pub fn drape_marked(&self, mesh: &Mesh, max_edge_m: f64, marks: &mut [usize]) -> Mesh {
        // Every vertex raised, shared by the triangles already fine enough.
        let mut out = Mesh {
            vertices: mesh.vertices.iter().map(|v| self.lifted(*v)).collect(),
            indices: Vec::with_capacity(mesh.indices.len()),
        };
        let max2 = max_edge_m * max_edge_m * (1.0 + 1e-9);
        let d2 = |x: [f64; 3], y: [f64; 3]| (x[0] - y[0]).powi(2) + (x[2] - y[2]).powi(2);
        let mut next_mark = 0;
        // The cut triangles share their corners: each position is lifted once.
        let mut lifted: HashMap<(u32, u32, u32), Option<Lift>, BuildHasherDefault<BitsHasher>> =
            HashMap::default();
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            while next_mark < marks.len() && marks[next_mark] <= 3 * t {
                marks[next_mark] = out.indices.len();
                next_mark += 1;
            }
            let v = [0, 1, 2].map(|k| mesh.vertices[tri[k] as usize]);
            let p = v.map(|v| v.position.map(f64::from));
            let fine = d2(p[0], p[1]) <= max2 && d2(p[1], p[2]) <= max2 && d2(p[2], p[0]) <= max2;
            if fine || !p.iter().any(|q| self.covers_near(q[0], q[2])) {
                out.indices.extend_from_slice(tri);
                continue;
            }
            // Halve the longest edge until every edge is short enough; both halves keep the
            // winding.
            let mut stack = vec![p];
            while let Some([a, b, c]) = stack.pop() {
                let edges = [d2(a, b), d2(b, c), d2(c, a)];
                let (longest, &len2) = edges
                    .iter()
                    .enumerate()
                    .max_by(|x, y| x.1.total_cmp(y.1))
                    .expect("three edges");
                if len2 > max2 {
                    let mid = |x: [f64; 3], y: [f64; 3]| [0, 1, 2].map(|k| 0.5 * (x[k] + y[k]));
                    match longest {
                        0 => {
                            let m = mid(a, b);
                            stack.extend([[a, m, c], [m, b, c]]);
                        }
                        1 => {
                            let m = mid(b, c);
                            stack.extend([[a, b, m], [a, m, c]]);
                        }
                        _ => {
                            let m = mid(c, a);
                            stack.extend([[a, b, m], [m, b, c]]);
                        }
                    }
                    continue;
                }
                let base = out.vertices.len() as u32;
                for q in [a, b, c] {
                    let position = q.map(|x| x as f32);
                    let key = (
                        position[0].to_bits(),
                        position[1].to_bits(),
                        position[2].to_bits(),
                    );
                    let lift = *lifted.entry(key).or_insert_with(|| self.lift(position));
                    let flat = Vertex { position, ..v[0] };
                    out.vertices.push(lift.map_or(flat, |l| Vertex {
                        position: l.position,
                        normal: l.normal,
                        ..flat
                    }));
                }
                out.indices.extend_from_slice(&[base, base + 1, base + 2]);
            }
        }
        for mark in &mut marks[next_mark..] {
            *mark = out.indices.len();
        }
        out
    }

    /// `v` (on flat ground) raised by the ground's height beneath it, its normal the
    /// surface's there (from the height's slope over a cell); unchanged off the patch.
    fn lifted(&self, v: Vertex) -> Vertex {
        match self.lift(v.position) {
            Some(l) => Vertex {
                position: l.position,
                normal: l.normal,
                ..v
            },
            None => v,
        }
    }

    /// The position and normal of [`Terrain::lifted`] for a vertex at `position`; `None` off
    /// the patch.
    fn lift(&self, position: [f32; 3]) -> Option<Lift> {
        let [x, y, z] = position.map(f64::from);
        if !self.covers_near(x, z) {
            return None;
        }
        let d = 0.5 * self.cell_m;
        let dx = (self.height_m(x + d, z) - self.height_m(x - d, z)) / (2.0 * d);
        let dz = (self.height_m(x, z + d) - self.height_m(x, z - d)) / (2.0 * d);
        let n = (dx * dx + 1.0 + dz * dz).sqrt();
        Some(Lift {
            position: [x as f32, (y + self.height_m(x, z)) as f32, z as f32],
            normal: [(-dx / n) as f32, (1.0 / n) as f32, (-dz / n) as f32],
        })
    }

    /// Whether (x, z) is on the patch or within a cell of it.
    fn covers_near(&self, x: f64, z: f64) -> bool {
        let [x0, z0, x1, z1] = self.corners;
        let c = self.cell_m;
        x > x0 - c && x < x1 + c && z > z0 - c && z < z1 + c
    }
}

/// A vertex lifted onto the terrain: its position and normal ([`Terrain::lift`]).
#[derive(Clone, Copy)]
struct Lift {
    position: [f32; 3],
    normal: [f32; 3],
}

/// A hasher for positions' bits: a multiply-rotate per word (the positions are the
/// draping's own, no adversary's), far cheaper than the default SipHash.
#[derive(Default)]
struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u32(u32::from(b));
        }
    }

    fn write_u32(&mut self, word: u32) {
        // 2^64 over the golden ratio: consecutive words spread over the table.
        self.0 = (self.0.rotate_left(26) ^ u64::from(word)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use vehicle::BumpsConfig;

    /// Bumps 12 cm high on a 0.5 m grid, 60 m around the origin (the other scene modules'
    /// tests stand things on them too).
    pub(in crate::scene) fn bumpy_ground() -> GroundConfig {
        GroundConfig {
            bumps: Some(BumpsConfig {
                amplitude_m: 0.12,
                wavelength_m: 7.0,
                half_extent_m: 60.0,
                cell_m: 0.5,
                seed: 4,
            }),
            ..GroundConfig::default()
        }
    }

    /// A road along a bend rising 4 % then falling, its profile sampled every metre, with
    /// bumps around the origin.
    pub(in crate::scene) fn profiled_ground() -> GroundConfig {
        let points = (0..=300)
            .map(|k| {
                let s = k as f64;
                let (x, z) = if s <= 150.0 {
                    (s, 0.0)
                } else {
                    (150.0 + 0.6 * (s - 150.0), 0.8 * (s - 150.0))
                };
                [x, z, 0.04 * s - 0.0002 * s * s]
            })
            .collect();
        GroundConfig {
            profile: Some(vehicle::GroundProfile {
                points,
                cell_m: 1.0,
                margin_m: 30.0,
            }),
            ..bumpy_ground()
        }
    }

    #[test]
    fn a_profiled_terrain_is_the_physics_heightfield() {
        let config = profiled_ground();
        let t = Terrain::new(&config).unwrap().unwrap();
        let ground = Ground::new(&config).unwrap();
        let grid = ground.grid().unwrap();
        assert!(t.follows_profile());
        // The bumps' finer cell, over the profile's box and the bump patch.
        assert_eq!(grid.cell_m, 0.5);
        let (mut worst, mut compared) = (0.0f64, 0);
        for k in 0..3000 {
            let x = -25.0 + 0.09 * k as f64;
            let z = -20.0 + 0.071 * k as f64;
            // Along the first leg, away from the bend's medial axis (where the height jumps
            // between the legs a point is equally near, and the grid's cells smooth the jump).
            if !t.covers(x, z) || x > 120.0 || z.abs() > 25.0 {
                continue;
            }
            compared += 1;
            let smooth = f64::from(ground.height_m(x as f32, z as f32));
            worst = worst.max((t.height_m(x, z) - smooth).abs());
        }
        assert!(compared > 500, "{compared}");
        assert!(worst < 0.005, "terrain off the field by {worst} m");
        // Off the grid, the flat ground (only far beyond the margin).
        assert!(!t.covers(0.0, 200.0));
        // At grid points, exactly the heights rapier is given.
        for (i, j) in [(3, 5), (100, 400), (grid.rows - 1, grid.cols - 2)] {
            let x = f64::from(grid.x0_m) + j as f64 * f64::from(grid.cell_m);
            let z = f64::from(grid.z0_m) + i as f64 * f64::from(grid.cell_m);
            if t.covers(x, z) {
                assert_eq!(t.height_m(x, z), f64::from(grid.heights[i + j * grid.rows]));
            }
        }
        // Beside the road, the road's height abreast (off the bump patch).
        let s: f64 = 120.0;
        assert!((t.height_m(s, 25.0) - (0.04 * s - 0.0002 * s * s)).abs() < 1e-3);
    }

    #[test]
    fn flat_ground_has_no_terrain() {
        assert!(Terrain::new(&GroundConfig::default()).unwrap().is_none());
    }

    #[test]
    fn grid_points_and_cell_interiors_follow_the_bump_field() {
        let t = Terrain::new(&bumpy_ground()).unwrap().unwrap();
        let ground = Ground::new(&bumpy_ground()).unwrap();
        let mut max = 0.0f64;
        for k in 0..2000 {
            let x = -59.0 + 0.0587 * k as f64;
            let z = 40.0 - 0.0413 * k as f64;
            let smooth = f64::from(ground.height_m(x as f32, z as f32));
            // Between grid points the triangles depart from the smooth field by at most its
            // curvature times the cell squared over 8: a few millimetres.
            assert!((t.height_m(x, z) - smooth).abs() < 0.005, "({x}, {z})");
            max = max.max(t.height_m(x, z));
        }
        assert!(max > 0.05, "bumps: {max}");
        // At grid points, exactly the physics' samples.
        let gx = -60.0 + 0.5 * 37.0;
        let gz = -60.0 + 0.5 * 101.0;
        assert_eq!(
            t.height_m(gx, gz),
            f64::from(ground.height_m(gx as f32, gz as f32))
        );
        assert_eq!(t.height_m(61.0, 0.0), 0.0);
    }

    #[test]
    fn draping_keeps_the_pieces_of_a_mesh_in_order() {
        let t = Terrain::new(&bumpy_ground()).unwrap().unwrap();
        let quad = |x: f64| {
            let mut m = Mesh::default();
            m.polygon(
                &[
                    [x, 0.0, 0.0],
                    [x + 3.0, 0.0, 0.0],
                    [x + 3.0, 0.0, 2.0],
                    [x, 0.0, 2.0],
                ],
                0.3,
                0,
            );
            m
        };
        let (a, b) = (quad(0.0), quad(10.0));
        let mut both = a.clone();
        both.append(&b);
        let mut marks = [0, a.indices.len()];
        let draped = t.drape_marked(&both, 0.7, &mut marks);
        // The second piece starts where the first one's pieces end, and is the second
        // piece draped alone, triangle for triangle.
        let (alone_a, alone_b) = (t.drape(&a, 0.7), t.drape(&b, 0.7));
        assert!(alone_a.indices.len() > a.indices.len(), "the quad was cut");
        assert_eq!(marks, [0, alone_a.indices.len()]);
        let corners = |m: &Mesh, from: usize| -> Vec<[f32; 3]> {
            m.indices[from..]
                .iter()
                .map(|&i| m.vertices[i as usize].position)
                .collect()
        };
        assert_eq!(corners(&draped, marks[1]), corners(&alone_b, 0));
        assert_eq!(t.drape(&both, 0.7), draped);
    }
}
