//! The standing clutter's shapes: houses, flat-roofed buildings, cars (parked and
//! oncoming), and the overpass, each built in its own frame or placed by its footprint.

use super::build::{Bins, Layer, ObjectSlot};
use super::mesh::Mesh;
use super::route::Route;

/// An overpass across the route at `station_m`: a deck 1 m thick, `deck_m` wide along the
/// route and reaching 12 m beyond the road's edges, on two abutment walls.
pub(super) fn overpass(
    bins: &mut Bins,
    route: &Route,
    road_half: f64,
    station_m: f64,
    deck_m: f64,
    height_m: f64,
) {
    let [x, z, heading] = route.at(station_m);
    let along = [heading.cos(), 0.0, -heading.sin()];
    let across = [heading.sin(), 0.0, heading.cos()];
    let reach = road_half + 12.0;
    let mesh = bins.at(x, z, Layer::Clutter);
    mesh.oriented_box(
        [x, height_m + 0.5, z],
        [along, [0.0, 1.0, 0.0], across],
        [0.5 * deck_m, 0.5, reach],
        0.5,
        ObjectSlot::WORLD,
    );
    for side in [-1.0, 1.0] {
        let l = side * (road_half + 4.0);
        mesh.oriented_box(
            [x + l * across[0], 0.5 * height_m, z + l * across[2]],
            [along, [0.0, 1.0, 0.0], across],
            [0.5 * deck_m, 0.5 * height_m, 0.4],
            0.55,
            ObjectSlot::WORLD,
        );
    }
}

/// A car in its own frame (x forward): body, a dark glass cabin, wheels.
pub(super) fn car(mesh: &mut Mesh, slot: u32, albedo: f64) {
    mesh.aabb([-2.2, 0.3, -0.9], [2.2, 1.0, 0.9], albedo, slot);
    mesh.aabb([-1.5, 1.0, -0.8], [0.8, 1.5, 0.8], 0.12, slot);
    for (x, z) in [(-1.4, -0.9), (-1.4, 0.9), (1.4, -0.9), (1.4, 0.9)] {
        mesh.aabb(
            [x - 0.33, 0.0, z - 0.12],
            [x + 0.33, 0.62, z + 0.12],
            0.05,
            slot,
        );
    }
}

/// Axes of a ground-standing object with the given heading: forward, up, right.
fn axes(heading: f64) -> [[f64; 3]; 3] {
    let (s, c) = heading.sin_cos();
    [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]]
}

/// A gabled house: walls, roof, and windows on its long walls and a door.
pub(super) fn house(
    mesh: &mut Mesh,
    at: [f64; 2],
    heading: f64,
    half: [f64; 2],
    walls: f64,
    wall_albedo: f64,
    roof_albedo: f64,
) {
    let [u, _, w] = axes(heading);
    let p = |a: f64, y: f64, b: f64| [at[0] + a * u[0] + b * w[0], y, at[1] + a * u[2] + b * w[2]];
    mesh.upright_box(
        at[0],
        at[1],
        heading,
        half[0],
        half[1],
        0.0,
        walls,
        wall_albedo,
    );
    let ridge = walls + 2.5;
    for side in [-1.0, 1.0] {
        mesh.polygon(
            &[
                p(-half[0] - 0.3, walls, side * (half[1] + 0.3)),
                p(half[0] + 0.3, walls, side * (half[1] + 0.3)),
                p(half[0] + 0.3, ridge, 0.0),
                p(-half[0] - 0.3, ridge, 0.0),
            ],
            roof_albedo,
            ObjectSlot::WORLD,
        );
        // The gable, wound so that its normal points out of the house.
        let (b0, b1) = (side * half[1], -side * half[1]);
        mesh.polygon(
            &[
                p(side * half[0], walls, b0),
                p(side * half[0], walls, b1),
                p(side * half[0], ridge, 0.0),
            ],
            wall_albedo,
            ObjectSlot::WORLD,
        );
    }
    let floors = if walls > 4.0 { 2 } else { 1 };
    let windows = ((2.0 * half[0]) / 3.0).floor() as usize;
    for side in [-1.0, 1.0] {
        let b = side * (half[1] + 0.03);
        let normal = [side * w[0], 0.0, side * w[2]];
        for floor in 0..floors {
            let y0 = 1.0 + 2.8 * floor as f64;
            for k in 0..windows {
                let a = -half[0] + (k as f64 + 0.5) * 2.0 * half[0] / windows as f64;
                mesh.quad_with_normal(
                    [
                        p(a - 0.5, y0, b),
                        p(a + 0.5, y0, b),
                        p(a + 0.5, y0 + 1.2, b),
                        p(a - 0.5, y0 + 1.2, b),
                    ],
                    normal,
                    0.08,
                    ObjectSlot::WORLD,
                );
            }
        }
    }
}

/// A flat-roofed building with a grid of windows on all four walls.
pub(super) fn building(
    mesh: &mut Mesh,
    at: [f64; 2],
    heading: f64,
    half: [f64; 2],
    height: f64,
    albedo: f64,
) {
    let [u, _, w] = axes(heading);
    let p = |a: f64, y: f64, b: f64| [at[0] + a * u[0] + b * w[0], y, at[1] + a * u[2] + b * w[2]];
    mesh.upright_box(at[0], at[1], heading, half[0], half[1], 0.0, height, albedo);
    let floors = (height / 3.0).floor() as usize;
    for (axis, extent, across) in [(0usize, half[0], half[1]), (1, half[1], half[0])] {
        let columns = (2.0 * extent / 2.5).floor() as usize;
        for side in [-1.0, 1.0] {
            let off = side * (across + 0.03);
            let normal = if axis == 0 {
                [side * w[0], 0.0, side * w[2]]
            } else {
                [side * u[0], 0.0, side * u[2]]
            };
            for floor in 0..floors.saturating_sub(0) {
                let y0 = 0.9 + 3.0 * floor as f64;
                if y0 + 1.4 > height {
                    break;
                }
                for k in 0..columns {
                    let a = -extent + (k as f64 + 0.5) * 2.0 * extent / columns as f64;
                    let q = |da: f64, y: f64| {
                        if axis == 0 {
                            p(a + da, y, off)
                        } else {
                            p(off, y, a + da)
                        }
                    };
                    mesh.quad_with_normal(
                        [q(-0.6, y0), q(0.6, y0), q(0.6, y0 + 1.4), q(-0.6, y0 + 1.4)],
                        normal,
                        0.08,
                        ObjectSlot::WORLD,
                    );
                }
            }
        }
    }
}
