//! The ground's height, as the physics has it: the bump patch of `vehicle::Ground`, sampled
//! on the same grid and cut into the same triangles as the rapier heightfield the wheels
//! roll on, so that the rendered road rises and falls exactly where the vehicles pitch.

use super::error::SceneError;
use super::mesh::{Mesh, Vertex};
use vehicle::{Ground, GroundConfig};

/// The physics' ground surface: flat at y = 0, with the bump patch's heightfield when the
/// ground has bumps.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    /// Heights of the grid, rows along z and columns along x, column-major (`i + j * n`),
    /// as `vehicle::Ground::bump_grid` gives them to rapier.
    heights: Vec<f32>,
    /// Grid points per side.
    n: usize,
    /// Cell side, metres.
    cell_m: f64,
    /// Half the side of the patch, metres (centred on the world origin).
    half_m: f64,
}

impl Terrain {
    /// The surface of `ground`; `None` when it is flat.
    pub fn new(ground: &GroundConfig) -> Result<Option<Terrain>, SceneError> {
        let ground = Ground::new(ground).map_err(|e| SceneError::Invalid {
            field: "ground".into(),
            reason: e.to_string(),
        })?;
        Ok(ground.bump_grid().map(|(heights, rows, cols, cell, half)| {
            debug_assert_eq!(rows, cols);
            Terrain {
                heights,
                n: rows,
                cell_m: f64::from(cell),
                half_m: f64::from(half),
            }
        }))
    }

    /// Whether (x, z) lies on the bump patch (outside it the ground is flat at y = 0).
    pub fn covers(&self, x: f64, z: f64) -> bool {
        x.abs() < self.half_m && z.abs() < self.half_m
    }

    /// Height of the physics' ground surface at world (x, z), metres: the heightfield's
    /// triangle over that point (rapier's cell split: the diagonal from the cell's corner at
    /// (x0, z1) to the one at (x1, z0)), and 0 off the patch.
    pub fn height_m(&self, x: f64, z: f64) -> f64 {
        if !self.covers(x, z) {
            return 0.0;
        }
        let cells = (self.n - 1) as f64;
        let fx = ((x + self.half_m) / self.cell_m).clamp(0.0, cells);
        let fz = ((z + self.half_m) / self.cell_m).clamp(0.0, cells);
        let j = (fx.floor() as usize).min(self.n - 2);
        let i = (fz.floor() as usize).min(self.n - 2);
        let (u, v) = (fx - j as f64, fz - i as f64);
        let h = |i: usize, j: usize| f64::from(self.heights[i + j * self.n]);
        let (y00, y10, y01, y11) = (h(i, j), h(i + 1, j), h(i, j + 1), h(i + 1, j + 1));
        if u + v <= 1.0 {
            // Triangle (p00, p10, p01).
            y00 + u * (y01 - y00) + v * (y10 - y00)
        } else {
            // Triangle (p10, p11, p01).
            y11 + (1.0 - u) * (y10 - y11) + (1.0 - v) * (y01 - y11)
        }
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
                    out.vertices.push(self.lifted(Vertex {
                        position: q.map(|x| x as f32),
                        ..v[0]
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
        let [x, y, z] = v.position.map(f64::from);
        if !self.covers_near(x, z) {
            return v;
        }
        let d = 0.5 * self.cell_m;
        let dx = (self.height_m(x + d, z) - self.height_m(x - d, z)) / (2.0 * d);
        let dz = (self.height_m(x, z + d) - self.height_m(x, z - d)) / (2.0 * d);
        let n = (dx * dx + 1.0 + dz * dz).sqrt();
        Vertex {
            position: [x as f32, (y + self.height_m(x, z)) as f32, z as f32],
            normal: [(-dx / n) as f32, (1.0 / n) as f32, (-dz / n) as f32],
            ..v
        }
    }

    /// Whether (x, z) is on the patch or within a cell of it.
    fn covers_near(&self, x: f64, z: f64) -> bool {
        let reach = self.half_m + self.cell_m;
        x.abs() < reach && z.abs() < reach
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
