//! Houses: the gabled house's shape, and the row of them along the route.

use super::bins::Bins;
use super::footing::Footing;
use super::layer::Layer;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::site::Site;
use super::standing::stand;
use super::wall::{frame_albedo, Wall, PANE_ALBEDO};
use rand::Rng;

/// Size of a house's door, metres (width, height).
pub(super) const DOOR_M: [f64; 2] = [1.0, 2.1];

/// A house's shape: its size, its walls' height, its colours, which wall faces the road
/// (the door's), and the seeded details.
pub(super) struct HouseSpec {
    /// Half its length (along its heading) and width, metres.
    pub half: [f64; 2],
    /// Height of its walls under the eaves, metres.
    pub walls: f64,
    /// Albedo of its walls.
    pub wall_albedo: f64,
    /// Albedo of its roof.
    pub roof_albedo: f64,
    /// The side (±1 along its right) of the long wall that faces the road.
    pub road_side: f64,
    /// Where the door is along that wall, as a share of it in [0, 1).
    pub door_at: f64,
    /// Where a chimney stands along the ridge, as a share in [0, 1), if it has one.
    pub chimney_at: Option<f64>,
}

/// A gabled house: walls, a roof with eaves, framed windows with sills on its long walls
/// and one in each gable end, a framed door with a step on the wall facing the road, and
/// maybe a chimney.
pub(super) fn house(mesh: &mut Mesh, at: [f64; 2], heading: f64, spec: &HouseSpec) {
    let f = Footing::new(at, heading);
    let [h0, h1] = spec.half;
    let walls = spec.walls;
    let slot = ObjectSlot::WORLD;
    f.body(mesh, spec.half, walls, spec.wall_albedo);
    let ridge = walls + 2.5;
    let eave = h1 + 0.3;
    for side in [-1.0, 1.0] {
        mesh.polygon(
            &[
                f.p(-h0 - 0.3, walls, side * eave),
                f.p(h0 + 0.3, walls, side * eave),
                f.p(h0 + 0.3, ridge, 0.0),
                f.p(-h0 - 0.3, ridge, 0.0),
            ],
            spec.roof_albedo,
            slot,
        );
        // The gable, wound so that its normal points out of the house.
        let (b0, b1) = (side * h1, -side * h1);
        mesh.polygon(
            &[
                f.p(side * h0, walls, b0),
                f.p(side * h0, walls, b1),
                f.p(side * h0, ridge, 0.0),
            ],
            spec.wall_albedo,
            slot,
        );
    }
    if let Some(c) = spec.chimney_at {
        // On the slope away from the road, from below the roof to above the ridge.
        let a = -h0 + 1.0 + c * (2.0 * h0 - 2.0);
        let b = -spec.road_side * 0.45 * h1;
        let low = walls + 2.5 * (1.0 - (b.abs() + 0.35) / eave) - 0.1;
        mesh.standing_box(
            f.p(a, 0.5 * (low + ridge + 0.8), b),
            f.axes(),
            [0.35, 0.5 * (ridge + 0.8 - low), 0.35],
            0.5 * spec.wall_albedo + 0.1,
            slot,
        );
    }
    let frame = frame_albedo(spec.wall_albedo);
    let floors = if walls > 4.0 { 2 } else { 1 };
    let windows = ((2.0 * h0) / 3.0).floor() as usize;
    let door = ((spec.door_at * windows as f64) as usize).min(windows - 1);
    for side in [-1.0, 1.0] {
        let wall = Wall {
            across: 0,
            side,
            offset: h1,
        };
        for floor in 0..floors {
            let y0 = 1.0 + 2.8 * floor as f64;
            for k in 0..windows {
                let a = -h0 + (k as f64 + 0.5) * 2.0 * h0 / windows as f64;
                if floor == 0 && side == spec.road_side && k == door {
                    // The door, in a frame, with a step before it.
                    wall.opening(mesh, &f, a, 0.15, DOOR_M, 0.1, frame, PANE_ALBEDO, false);
                    mesh.standing_box(
                        wall.p(&f, a, 0.075, 0.25),
                        f.axes(),
                        [0.8, 0.075, 0.25],
                        0.55,
                        slot,
                    );
                    continue;
                }
                wall.opening(mesh, &f, a, y0, [1.0, 1.2], 0.08, frame, PANE_ALBEDO, true);
            }
        }
    }
    for side in [-1.0, 1.0] {
        let wall = Wall {
            across: 1,
            side,
            offset: h0,
        };
        wall.opening(
            mesh,
            &f,
            0.0,
            1.0,
            [1.0, 1.2],
            0.08,
            frame,
            PANE_ALBEDO,
            true,
        );
    }
}

/// Lays the houses (gabled, windows on every wall) along the route, on either side, drawn
/// from the scene's `"houses"` stream, their details from `"house-details"`.
pub(super) fn lay_row(site: &Site<'_>, bins: &mut Bins) {
    let (route, road_half, length) = (site.route, site.road_half, site.length);
    let mut houses = site.stream("houses");
    let mut house_details = site.stream("house-details");
    for _ in 0..Site::count(site.description.densities.houses_per_km, length + 150.0) {
        let Some(s) = site.clear_station(&mut houses, road_half + 16.0) else {
            continue;
        };
        let side = if houses.random_bool(0.5) { 1.0 } else { -1.0 };
        let half = [houses.random_range(4.0..6.5), houses.random_range(3.5..5.0)];
        let l = side * (road_half + houses.random_range(10.0..22.0) + half[1]);
        let walls = if houses.random_bool(0.3) { 5.8 } else { 3.0 };
        let [x, z] = route.point(s, l);
        let heading = route.at(s)[2] + houses.random_range(-0.1..0.1);
        let wall_albedo = houses.random_range(0.45..0.8);
        let roof_albedo = houses.random_range(0.12..0.3);
        // The details from their own stream, so the houses stand where they did.
        let door_at = house_details.random_range(0.0..1.0);
        let chimney = house_details.random_range(0.0..1.0);
        let chimney_at = house_details.random_bool(0.5).then_some(chimney);
        let mut item = Mesh::default();
        house(
            &mut item,
            [x, z],
            heading,
            &HouseSpec {
                half,
                walls,
                wall_albedo,
                roof_albedo,
                road_side: -side,
                door_at,
                chimney_at,
            },
        );
        stand(site.terrain, &mut item);
        bins.at(x, z, Layer::Clutter).append(&item);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::terrain::Terrain;
    use crate::scene::test_support::{quads_of, triangles};
    use crate::scene::wall::{OPENING_FRAME_PROUD_M, OPENING_PANE_PROUD_M};

    fn spec(road_side: f64) -> HouseSpec {
        HouseSpec {
            half: [5.5, 4.0],
            walls: 3.0,
            wall_albedo: 0.5,
            roof_albedo: 0.2,
            road_side,
            door_at: 0.4,
            chimney_at: Some(0.3),
        }
    }

    #[test]
    fn a_house_has_a_framed_door_with_a_step_on_the_wall_facing_the_road() {
        for road_side in [-1.0, 1.0] {
            let mut mesh = Mesh::default();
            // Heading 0: the house's right (w) is world +z.
            house(&mut mesh, [10.0, 20.0], 0.0, &spec(road_side));
            let wall_z = 20.0 + road_side * 4.0;
            // Dark leaves reaching down to the step: doors; on the road's side only.
            let doors: Vec<_> = quads_of(&mesh, PANE_ALBEDO)
                .into_iter()
                .filter(|q| q.iter().map(|p| p[1]).fold(f64::MAX, f64::min) < 0.2)
                .collect();
            assert_eq!(doors.len(), 1, "one door");
            let door = doors[0];
            for p in door {
                assert!(
                    (p[2] - (wall_z + road_side * OPENING_PANE_PROUD_M)).abs() < 1e-4,
                    "on the wall facing the road: {p:?}"
                );
            }
            let height = door.iter().map(|p| p[1]).fold(f64::MIN, f64::max)
                - door.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
            assert!((height - DOOR_M[1]).abs() < 1e-4, "door height {height}");
            // Its frame: a lighter quad just behind it, larger all round but at the foot.
            let frame = frame_albedo(0.5);
            assert!(quads_of(&mesh, frame).iter().any(|q| {
                q.iter()
                    .all(|p| (p[2] - (wall_z + road_side * OPENING_FRAME_PROUD_M)).abs() < 1e-4)
                    && q.iter().map(|p| p[1]).fold(f64::MIN, f64::max) > 0.15 + DOOR_M[1]
            }));
            // The step: something standing on the ground in front of the door.
            assert!(mesh.vertices.iter().any(|v| {
                v.position[1] == 0.0
                    && (f64::from(v.position[2]) - (wall_z + road_side * 0.5)).abs() < 1e-3
            }));
        }
    }

    #[test]
    fn every_window_has_a_frame_and_a_pane() {
        let mut mesh = Mesh::default();
        house(&mut mesh, [0.0, 0.0], 0.3, &spec(-1.0));
        let panes = quads_of(&mesh, PANE_ALBEDO).len();
        // Three windows on each long wall (one of them the door), one in each gable end.
        assert_eq!(panes, 3 + 3 + 2);
        // Each pane's frame and (but for the door) its sill's front.
        let frames = quads_of(&mesh, frame_albedo(0.5)).len();
        assert_eq!(
            frames,
            panes + 2 * (panes - 1),
            "frames, and sills but under the door"
        );
    }

    fn bumpy() -> Terrain {
        Terrain::new(&super::super::terrain::tests::bumpy_ground())
            .unwrap()
            .unwrap()
    }

    #[test]
    fn standing_puts_an_item_on_the_lowest_ground_under_it() {
        let t = bumpy();
        for (k, heading) in [0.0, 0.4, 1.3].into_iter().enumerate() {
            let at = [-20.0 + 17.0 * k as f64, 11.0 - 9.0 * k as f64];
            let mut flat = Mesh::default();
            house(&mut flat, at, heading, &spec(1.0));
            let mut item = flat.clone();
            let base = stand(Some(&t), &mut item);
            // Its base, at the lowest ground under its plan within a centimetre: sampled
            // every 5 cm over the footprint's bounding box.
            let footprint: Vec<[f64; 2]> = flat
                .vertices
                .iter()
                .filter(|v| v.position[1] == 0.0)
                .map(|v| [f64::from(v.position[0]), f64::from(v.position[2])])
                .collect();
            let lo = |k: usize| footprint.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
            let hi = |k: usize| footprint.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
            let mut lowest = f64::MAX;
            let mut x = lo(0);
            while x <= hi(0) {
                let mut z = lo(1);
                while z <= hi(1) {
                    lowest = lowest.min(t.height_m(x, z));
                    z += 0.05;
                }
                x += 0.05;
            }
            assert!((base - lowest).abs() < 0.01, "base {base}, lowest {lowest}");
            assert!(base.abs() > 0.005, "it moved: {base}");
            // Nowhere does its foot float above the ground; all of it moved by `base`.
            for (v, w) in flat.vertices.iter().zip(&item.vertices) {
                let [x, y, z] = w.position.map(f64::from);
                assert!((y - f64::from(v.position[1]) - base).abs() < 1e-4);
                if v.position[1] == 0.0 {
                    assert!(y <= t.height_m(x, z) + 0.01, "floats at ({x}, {z})");
                }
            }
            // No terrain: untouched.
            let mut same = flat.clone();
            assert_eq!(stand(None, &mut same), 0.0);
            assert_eq!(same, flat);
        }
    }

    #[test]
    fn a_house_keeps_to_a_modest_triangle_budget() {
        let mut mesh = Mesh::default();
        house(&mut mesh, [0.0, 0.0], 0.0, &spec(1.0));
        eprintln!("house: {} triangles", triangles(&mesh));
        assert!(triangles(&mesh) < 200, "house: {}", triangles(&mesh));
    }
}
