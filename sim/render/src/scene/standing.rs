//! Standing items built on flat ground on the terrain: the lowest ground under a footprint,
//! and an item moved down (or up) to it, so that over bumps nothing floats.

use super::mesh::Mesh;
use super::terrain::Terrain;

/// The lowest height of the ground under a footprint (world plan points: its corners, or
/// any points it spans): sampled at the corners and at the terrain's cells over their
/// bounding box, so that nothing standing at that height leaves a gap under it. 0 on flat
/// ground.
pub(super) fn ground_under(terrain: Option<&Terrain>, footprint: &[[f64; 2]]) -> f64 {
    let Some(t) = terrain else {
        return 0.0;
    };
    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
    let mut lowest = f64::MAX;
    for &[x, z] in footprint {
        min = [min[0].min(x), min[1].min(z)];
        max = [max[0].max(x), max[1].max(z)];
        lowest = lowest.min(t.height_m(x, z));
    }
    if footprint.is_empty() {
        return 0.0;
    }
    let pitch = t.cell_m();
    let n = [
        ((max[0] - min[0]) / pitch).ceil() as usize,
        ((max[1] - min[1]) / pitch).ceil() as usize,
    ];
    for i in 0..=n[0] {
        for j in 0..=n[1] {
            let x = (min[0] + i as f64 * pitch).min(max[0]);
            let z = (min[1] + j as f64 * pitch).min(max[1]);
            lowest = lowest.min(t.height_m(x, z));
        }
    }
    lowest
}

/// Stands an item built on flat ground (world frame, its footprint the vertices at y = 0)
/// on the terrain: raises (or lowers) all of it to the lowest ground under its footprint,
/// so that its base meets the ground there and sinks into it elsewhere, never floating.
/// Returns the height it was moved by (0 with no terrain, leaving it untouched).
pub(super) fn stand(terrain: Option<&Terrain>, mesh: &mut Mesh) -> f64 {
    if terrain.is_none() {
        return 0.0;
    }
    let footprint: Vec<[f64; 2]> = mesh
        .vertices
        .iter()
        .filter(|v| v.position[1].abs() < 1e-4)
        .map(|v| [f64::from(v.position[0]), f64::from(v.position[2])])
        .collect();
    let base = ground_under(terrain, &footprint);
    if base != 0.0 {
        for v in &mut mesh.vertices {
            v.position[1] = (f64::from(v.position[1]) + base) as f32;
        }
    }
    base
}
