//! The ground: a grass quad under the whole route, mottled by the renderer, and, over
//! bumps, the road's surfaces laid on the physics' height field.

use super::bins::Bins;
use super::layer::Layer;
use super::material::Material;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::site::{Site, ROAD_RUNOUT_M};
use super::terrain::Terrain;

/// Grass margin around the road's bounding box, metres: beyond the far plane's useful range.
const GROUND_MARGIN_M: f64 = 250.0;
/// Grass mottling cell, metres: the renderer gives each corner of a square lattice of this
/// pitch its own albedo, hashed from the scene's grass key, and interpolates between them.
pub const GROUND_CELL_M: f64 = 25.0;
/// The albedo that marks a vertex as grass: the renderer computes the real albedo per
/// fragment from the world position (see [`GROUND_CELL_M`], [`GRASS_ALBEDO_RANGE`]).
pub const GRASS_ALBEDO: f64 = -1.0;
/// Range of grass albedo, from dry to lush patches.
pub const GRASS_ALBEDO_RANGE: [f64; 2] = [0.17, 0.30];

/// Under a road's profile, the side of the grass tiles laid on the height field, metres: one
/// bin each, so that culling keeps working on a draped ground.
const PROFILE_GRASS_TILE_M: f64 = 50.0;
/// Under a road's profile, the longest edge of the grass's pieces, metres: between vertices
/// a piece departs from the height field by the profile's curvature times the edge squared
/// over 8, under 1 cm for vertical curves of radius 500 m and more.
const PROFILE_GRASS_EDGE_M: f64 = 6.0;
/// Under a road's profile, how far the grass lies below the height field, metres: so that
/// where the ground sags, the chords of its pieces stay under the verges (5 mm above it)
/// for vertical curves down to 150 m radius (4.5 m²·κ ≤ 3 cm).
const PROFILE_GRASS_BELOW_M: f64 = 0.03;

/// Lays the ground: a mottled grass grid covering the road's bounding box.
pub(super) fn lay_grass(site: &Site<'_>, bins: &mut Bins) {
    let route = site.route;
    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
    let mut s = -ROAD_RUNOUT_M;
    while s <= site.length + ROAD_RUNOUT_M {
        let [x, z] = route.point(s, 0.0);
        min = [min[0].min(x), min[1].min(z)];
        max = [max[0].max(x), max[1].max(z)];
        s += 10.0;
    }
    let origin = [min[0] - GROUND_MARGIN_M, min[1] - GROUND_MARGIN_M];
    let cells = [
        ((max[0] - min[0] + 2.0 * GROUND_MARGIN_M) / GROUND_CELL_M).ceil() as usize,
        ((max[1] - min[1] + 2.0 * GROUND_MARGIN_M) / GROUND_CELL_M).ceil() as usize,
    ];
    // One quad: the mottling is computed per fragment from the world position (see
    // `GRASS_ALBEDO`), so the grass costs two triangles instead of a grid.
    let size = [
        cells[0] as f64 * GROUND_CELL_M,
        cells[1] as f64 * GROUND_CELL_M,
    ];
    if let Some(t) = site.terrain.filter(|t| t.follows_profile()) {
        lay_draped_grass(t, origin, size, bins);
        return;
    }
    bins.at(
        origin[0] + 0.5 * size[0],
        origin[1] + 0.5 * size[1],
        Layer::Ground,
    )
    .polygon(
        &[
            [origin[0], 0.0, origin[1]],
            [origin[0] + size[0], 0.0, origin[1]],
            [origin[0] + size[0], 0.0, origin[1] + size[1]],
            [origin[0], 0.0, origin[1] + size[1]],
        ],
        GRASS_ALBEDO,
        ObjectSlot::WORLD | Material::GRASS,
    );
}

/// The grass of [`lay_grass`] on a road's profile: tiles of [`PROFILE_GRASS_TILE_M`] over
/// the box at `origin` of `size` (metres), draped on the height field.
fn lay_draped_grass(t: &Terrain, origin: [f64; 2], size: [f64; 2], bins: &mut Bins) {
    let n = size.map(|v| (v / PROFILE_GRASS_TILE_M).ceil().max(1.0) as usize);
    let step = [size[0] / n[0] as f64, size[1] / n[1] as f64];
    for i in 0..n[0] {
        for j in 0..n[1] {
            let x0 = origin[0] + i as f64 * step[0];
            let z0 = origin[1] + j as f64 * step[1];
            let (x1, z1) = (x0 + step[0], z0 + step[1]);
            let y = -PROFILE_GRASS_BELOW_M;
            let mut tile = Mesh::default();
            tile.polygon(
                &[[x0, y, z0], [x1, y, z0], [x1, y, z1], [x0, y, z1]],
                GRASS_ALBEDO,
                ObjectSlot::WORLD | Material::GRASS,
            );
            bins.at(0.5 * (x0 + x1), 0.5 * (z0 + z1), Layer::Ground)
                .append(&t.drape(&tile, PROFILE_GRASS_EDGE_M));
        }
    }
}

/// Over bumps, lays the road's surfaces (everything in [`Layer::Surface`]: the road, the
/// crossing roads, the paint and the marks) on the physics' height field, keeping their
/// parts. Nothing to do on flat ground.
pub(super) fn drape_surfaces(site: &Site<'_>, bins: &mut Bins) {
    if let Some(t) = site.terrain {
        // Strips come in cells already; the diagonal of a cell is the longest edge that
        // needs no cutting.
        bins.drape(Layer::Surface, t, t.cell_m() * std::f64::consts::SQRT_2);
    }
}
