//! The box truck: a cab and a tall cargo box, in its own frame (x forward, y up, z right,
//! origin on the ground under the body's centre), for the traffic the scenario places.
//! Its back is what a chase camera sees: the box's outline, a roll-up door of another
//! shade, a light bumper across the bottom with the tail lamps on it.

use super::car::{CAR_BUMPER_ALBEDO, CAR_GLASS_ALBEDO};
use super::mesh::Mesh;

/// Half the truck's length over its bumpers, metres.
pub(super) const TRUCK_HALF_LENGTH_M: f64 = 3.75;
/// Half the truck's width over its box, metres.
pub(super) const TRUCK_HALF_WIDTH_M: f64 = 1.25;
/// The truck's height over the ground: the top of its box, metres.
pub(super) const TRUCK_HEIGHT_M: f64 = 3.4;
/// The cargo box's back face (x), metres: the rear bumper stands out behind it.
pub(super) const BOX_BACK_X_M: f64 = -3.6;
/// The cargo box's front face (x), metres.
const BOX_FRONT_X_M: f64 = 1.25;
/// The cargo box's floor above the ground, metres.
pub(super) const BOX_FLOOR_M: f64 = 1.05;
/// Half the width of the roll-up door in the box's back, metres.
pub(super) const DOOR_HALF_WIDTH_M: f64 = 1.0;
/// The door's bottom and top above the ground, metres.
pub(super) const DOOR_Y_M: [f64; 2] = [1.25, 3.2];
/// The door's paint as a share of the box's: a step edge all round it.
const DOOR_SHADE: f64 = 0.6;
/// The rear bumper's bottom and top above the ground, metres.
pub(super) const REAR_BUMPER_Y_M: [f64; 2] = [0.45, 0.8];
/// Albedo of the rear bumper, a galvanised under-run bar: lighter than the dark chassis
/// and the shadow under the box, so its top and bottom are strong edges (a car's dark
/// bumper over the shadow under it shows no edge at its bottom).
const REAR_BUMPER_ALBEDO: f64 = 0.45;
/// Half the rear bumper's width, metres.
pub(super) const REAR_BUMPER_HALF_M: f64 = 1.2;
/// The tail lamps on the rear bumper: their bottom and top, metres.
pub(super) const TAIL_LAMP_Y_M: [f64; 2] = [0.52, 0.73];
/// Their inner and outer edges, metres from the centre line.
pub(super) const TAIL_LAMP_Z_M: [f64; 2] = [0.75, 1.1];
/// The cab: its back and front (x), bottom and top (y), and half width, metres.
const CAB: ([f64; 2], [f64; 2], f64) = ([1.35, 3.7], [0.55, 2.75], 1.15);
/// Albedo of lamp lenses catching the light (as a car's).
const LAMP_ALBEDO: f64 = 0.85;
/// Albedo of the chassis under the box.
const CHASSIS_ALBEDO: f64 = 0.08;
/// Albedo of the tyres.
const TYRE_ALBEDO: f64 = 0.04;
/// Albedo of the wheel hubs.
const HUB_ALBEDO: f64 = 0.55;
/// The tyres' radius, metres.
const TYRE_RADIUS_M: f64 = 0.48;

/// A box truck in `slot`, its box and cab painted `albedo`: about 150 triangles.
pub(super) fn truck(mesh: &mut Mesh, slot: u32, albedo: f64) {
    let hw = TRUCK_HALF_WIDTH_M;
    // The cargo box, and the chassis rails under it.
    mesh.aabb(
        [BOX_BACK_X_M, BOX_FLOOR_M, -hw],
        [BOX_FRONT_X_M, TRUCK_HEIGHT_M, hw],
        albedo,
        slot,
    );
    mesh.aabb(
        [BOX_BACK_X_M + 0.15, 0.55, -0.5],
        [CAB.0[0], BOX_FLOOR_M, 0.5],
        CHASSIS_ALBEDO,
        slot,
    );
    back(mesh, slot, albedo);
    cab(mesh, slot, albedo);
    // Wheels: one pair in front, twin pairs behind.
    for (x, inner) in [(2.55, hw - 0.35), (-2.2, hw - 0.6)] {
        for sz in [-1.0, 1.0] {
            let (z0, z1) = (sz * inner, sz * (hw - 0.05));
            mesh.aabb(
                [x - TYRE_RADIUS_M, 0.0, z0.min(z1)],
                [x + TYRE_RADIUS_M, 2.0 * TYRE_RADIUS_M, z0.max(z1)],
                TYRE_ALBEDO,
                slot,
            );
            let z = sz * (hw - 0.05 + 0.004);
            let (y0, y1) = (TYRE_RADIUS_M - 0.2, TYRE_RADIUS_M + 0.2);
            mesh.quad_with_normal(
                [
                    [x - 0.2, y0, z],
                    [x + 0.2, y0, z],
                    [x + 0.2, y1, z],
                    [x - 0.2, y1, z],
                ],
                [0.0, 0.0, sz],
                HUB_ALBEDO,
                slot,
            );
        }
    }
}

/// The back: the roll-up door on the box's back face, the rear bumper behind it with the
/// tail lamps on its face.
fn back(mesh: &mut Mesh, slot: u32, albedo: f64) {
    let x = BOX_BACK_X_M - 0.005;
    let [y0, y1] = DOOR_Y_M;
    let d = DOOR_HALF_WIDTH_M;
    mesh.quad_with_normal(
        [[x, y0, -d], [x, y0, d], [x, y1, d], [x, y1, -d]],
        [-1.0, 0.0, 0.0],
        albedo * DOOR_SHADE,
        slot,
    );
    let [b0, b1] = REAR_BUMPER_Y_M;
    let b = REAR_BUMPER_HALF_M;
    mesh.aabb(
        [-TRUCK_HALF_LENGTH_M, b0, -b],
        [BOX_BACK_X_M, b1, b],
        REAR_BUMPER_ALBEDO,
        slot,
    );
    let x = -TRUCK_HALF_LENGTH_M - 0.005;
    let [l0, l1] = TAIL_LAMP_Y_M;
    for sz in [-1.0, 1.0] {
        let [inner, outer] = TAIL_LAMP_Z_M.map(|z| sz * z);
        mesh.quad_with_normal(
            [
                [x, l0, inner],
                [x, l0, outer],
                [x, l1, outer],
                [x, l1, inner],
            ],
            [-1.0, 0.0, 0.0],
            LAMP_ALBEDO,
            slot,
        );
    }
}

/// The cab: a box with a windscreen and side windows of dark glass, head lamps and a dark
/// front bumper.
fn cab(mesh: &mut Mesh, slot: u32, albedo: f64) {
    let ([x0, x1], [y0, y1], w) = CAB;
    mesh.aabb([x0, y0, -w], [x1, y1, w], albedo, slot);
    let front = x1 + 0.005;
    let (g0, g1) = (1.6, 2.55);
    mesh.quad_with_normal(
        [
            [front, g0, -w + 0.15],
            [front, g0, w - 0.15],
            [front, g1, w - 0.15],
            [front, g1, -w + 0.15],
        ],
        [1.0, 0.0, 0.0],
        CAR_GLASS_ALBEDO,
        slot,
    );
    for sz in [-1.0, 1.0] {
        let z = sz * (w + 0.005);
        mesh.quad_with_normal(
            [[2.7, g0, z], [3.55, g0, z], [3.55, 2.5, z], [2.7, 2.5, z]],
            [0.0, 0.0, sz],
            CAR_GLASS_ALBEDO,
            slot,
        );
        let [inner, outer] = [sz * (w - 0.4), sz * (w - 0.1)];
        mesh.quad_with_normal(
            [
                [front, 0.95, inner],
                [front, 0.95, outer],
                [front, 1.15, outer],
                [front, 1.15, inner],
            ],
            [1.0, 0.0, 0.0],
            LAMP_ALBEDO,
            slot,
        );
    }
    mesh.aabb(
        [x1, 0.4, -w],
        [TRUCK_HALF_LENGTH_M, 0.8, w],
        CAR_BUMPER_ALBEDO,
        slot,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::test_support::{quads_of, triangles};

    #[test]
    fn a_truck_fits_its_size_with_door_lamps_and_bumper_on_its_back() {
        let mut mesh = Mesh::default();
        truck(&mut mesh, 7, 0.7);
        assert!(mesh.vertices.iter().all(|v| v.object == 7), "slot");
        let extent = |k: usize, f: fn(f64, f64) -> f64, start: f64| {
            mesh.vertices
                .iter()
                .map(|v| f64::from(v.position[k]))
                .fold(start, f)
        };
        let tol = 1e-5;
        assert!(extent(0, f64::max, f64::MIN) <= TRUCK_HALF_LENGTH_M + 0.005 + tol);
        assert!(extent(0, f64::min, f64::MAX) >= -TRUCK_HALF_LENGTH_M - 0.005 - tol);
        assert!(extent(2, f64::max, f64::MIN) <= TRUCK_HALF_WIDTH_M + tol);
        assert!(extent(2, f64::min, f64::MAX) >= -TRUCK_HALF_WIDTH_M - tol);
        assert!((extent(1, f64::max, f64::MIN) - TRUCK_HEIGHT_M).abs() < tol);
        assert_eq!(extent(1, f64::min, f64::MAX), 0.0, "on the ground");
        // Two tail lamps facing back, one door of the box's shade darkened.
        let lamps = quads_of(&mesh, LAMP_ALBEDO)
            .into_iter()
            .filter(|q| q[0][0] < 0.0)
            .count();
        assert_eq!(lamps, 2);
        assert_eq!(quads_of(&mesh, 0.7 * DOOR_SHADE).len(), 1);
        assert!(triangles(&mesh) < 200, "{} triangles", triangles(&mesh));
    }
}
