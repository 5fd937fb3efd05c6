//! Buildings: the flat-roofed building's shape, and the row of them along the route.

use super::bins::Bins;
use super::footing::Footing;
use super::layer::Layer;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::site::Site;
use super::standing::stand;
use super::wall::{frame_albedo, Wall, PANE_ALBEDO};
use rand::Rng;

/// A flat-roofed building's shape.
pub(super) struct BuildingSpec {
    /// Half its length (along its heading) and width, metres.
    pub half: [f64; 2],
    /// Height of its roof, metres.
    pub height: f64,
    /// Albedo of its walls.
    pub albedo: f64,
    /// The side (±1 along its right) of the long wall that faces the road.
    pub road_side: f64,
    /// Where its entrance is along that wall, as a share of it in [0, 1).
    pub entrance_at: f64,
}

/// A flat-roofed building: walls, a cornice round the top standing above the roof as a
/// parapet, a grid of framed windows on all four walls, and a glazed, framed entrance
/// under a canopy on the wall facing the road.
pub(super) fn building(mesh: &mut Mesh, at: [f64; 2], heading: f64, spec: &BuildingSpec) {
    let f = Footing::new(at, heading);
    let [h0, h1] = spec.half;
    let height = spec.height;
    let slot = ObjectSlot::WORLD;
    f.body(mesh, spec.half, height, spec.albedo);
    let trim = (spec.albedo + 0.2).min(0.92);
    // The cornice: a band 15 cm proud of the walls, from 40 cm under the roof to 60 cm
    // above it (the parapet; the roof behind it is never seen from the road).
    mesh.oriented_box(
        f.p(0.0, height + 0.1, 0.0),
        f.axes(),
        [h0 + 0.15, 0.5, h1 + 0.15],
        trim,
        slot,
    );
    let frame = frame_albedo(spec.albedo);
    // The entrance: glazed doors in a frame, under a canopy.
    let entrance = -h0 + 2.5 + spec.entrance_at * (2.0 * h0 - 5.0);
    let front = Wall {
        across: 0,
        side: spec.road_side,
        offset: h1,
    };
    front.opening(
        mesh,
        &f,
        entrance,
        0.0,
        [2.4, 2.5],
        0.15,
        frame,
        PANE_ALBEDO,
        false,
    );
    mesh.oriented_box(
        front.p(&f, entrance, 2.85, 0.6),
        f.axes(),
        [1.6, 0.08, 0.6],
        trim,
        slot,
    );
    let floors = (height / 3.0).floor() as usize;
    for (across, extent, offset) in [(0usize, h0, h1), (1, h1, h0)] {
        let columns = (2.0 * extent / 2.5).floor() as usize;
        for side in [-1.0, 1.0] {
            let wall = Wall {
                across,
                side,
                offset,
            };
            for floor in 0..floors {
                let y0 = 0.9 + 3.0 * floor as f64;
                if y0 + 1.4 > height - 0.5 {
                    break;
                }
                for k in 0..columns {
                    let a = -extent + (k as f64 + 0.5) * 2.0 * extent / columns as f64;
                    if floor == 0
                        && across == 0
                        && side == spec.road_side
                        && (a - entrance).abs() < 2.1
                    {
                        continue;
                    }
                    wall.opening(mesh, &f, a, y0, [1.2, 1.4], 0.08, frame, PANE_ALBEDO, false);
                }
            }
        }
    }
}

/// Lays the buildings (taller, with a window grid) along the route, on either side, drawn
/// from the scene's `"buildings"` stream, their entrances from `"building-details"`.
pub(super) fn lay_row(site: &Site<'_>, bins: &mut Bins) {
    let (route, road_half, length) = (site.route, site.road_half, site.length);
    let mut buildings = site.stream("buildings");
    let mut building_details = site.stream("building-details");
    for _ in 0..Site::count(site.description.densities.buildings_per_km, length + 150.0) {
        let Some(s) = site.clear_station(&mut buildings, road_half + 20.0) else {
            continue;
        };
        let side = if buildings.random_bool(0.5) {
            1.0
        } else {
            -1.0
        };
        let half = [
            buildings.random_range(6.0..12.0),
            buildings.random_range(5.0..9.0),
        ];
        let l = side * (road_half + buildings.random_range(12.0..30.0) + half[1]);
        let height = buildings.random_range(8.0..20.0);
        let [x, z] = route.point(s, l);
        let heading = route.at(s)[2];
        let albedo = buildings.random_range(0.35..0.7);
        let mut item = Mesh::default();
        building(
            &mut item,
            [x, z],
            heading,
            &BuildingSpec {
                half,
                height,
                albedo,
                road_side: -side,
                entrance_at: building_details.random_range(0.0..1.0),
            },
        );
        stand(site.terrain, &mut item);
        bins.at(x, z, Layer::Clutter).append(&item);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::test_support::{quads_of, triangles};
    use crate::scene::wall::OPENING_PANE_PROUD_M;

    #[test]
    fn a_building_has_an_entrance_a_cornice_and_framed_windows() {
        let mut mesh = Mesh::default();
        let spec = BuildingSpec {
            half: [9.0, 7.0],
            height: 14.0,
            albedo: 0.5,
            road_side: 1.0,
            entrance_at: 0.5,
        };
        building(&mut mesh, [0.0, 0.0], 0.0, &spec);
        // The entrance: a dark pane 2.5 m tall from the ground on the +z wall.
        let panes = quads_of(&mesh, PANE_ALBEDO);
        assert!(panes.iter().any(|q| {
            q.iter()
                .all(|p| (p[2] - (7.0 + OPENING_PANE_PROUD_M)).abs() < 1e-4)
                && q.iter().map(|p| p[1]).fold(f64::MAX, f64::min) == 0.0
                && q.iter().map(|p| p[1]).fold(f64::MIN, f64::max) == 2.5
        }));
        // The cornice and parapet stand proud of the walls and above the roof.
        let top = mesh
            .vertices
            .iter()
            .map(|v| f64::from(v.position[1]))
            .fold(f64::MIN, f64::max);
        assert!((top - 14.6).abs() < 1e-4, "parapet top {top}");
        let widest = mesh
            .vertices
            .iter()
            .map(|v| f64::from(v.position[0]).abs())
            .fold(0.0, f64::max);
        assert!((widest - 9.15).abs() < 1e-4, "cornice {widest}");
        assert!(panes.len() > 50, "{} windows", panes.len());
    }

    #[test]
    fn a_building_keeps_to_a_modest_triangle_budget() {
        let mut mesh = Mesh::default();
        building(
            &mut mesh,
            [0.0, 0.0],
            0.0,
            &BuildingSpec {
                half: [9.0, 7.0],
                height: 14.0,
                albedo: 0.5,
                road_side: 1.0,
                entrance_at: 0.5,
            },
        );
        eprintln!("building: {} triangles", triangles(&mesh));
        assert!(triangles(&mesh) < 500, "building: {}", triangles(&mesh));
    }
}
