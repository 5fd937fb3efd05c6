//! The kinds of vehicle a scenario places in traffic, and their drawn shapes: the cars of
//! `car` and the box truck of `truck`.

use super::car::{car, CarBody, CAR_HALF_LENGTH_M, CAR_HALF_WIDTH_M};
use super::mesh::Mesh;
use super::truck::{truck, TRUCK_HALF_LENGTH_M, TRUCK_HALF_WIDTH_M, TRUCK_HEIGHT_M};

/// A kind of vehicle in traffic. Each is drawn in its own frame: x forward, y up, z right,
/// the origin on the ground under the body's centre (as the parked and oncoming cars are).
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum VehicleKind {
    /// A saloon: bonnet, cabin, boot (the parked and oncoming cars' commonest body).
    Sedan,
    /// A hatchback: bonnet, and a cabin reaching to the tail.
    Hatchback,
    /// A van: a short bonnet and a tall box to the tail.
    Van,
    /// A box truck: a cab and a tall cargo box with a roll-up door in its back.
    Truck,
}

impl VehicleKind {
    /// Every kind, in order.
    pub const ALL: [VehicleKind; 4] = [
        VehicleKind::Sedan,
        VehicleKind::Hatchback,
        VehicleKind::Van,
        VehicleKind::Truck,
    ];

    /// The name a description gives it: `"sedan"`, `"hatchback"`, `"van"` or `"truck"`.
    pub fn as_str(self) -> &'static str {
        match self {
            VehicleKind::Sedan => "sedan",
            VehicleKind::Hatchback => "hatchback",
            VehicleKind::Van => "van",
            VehicleKind::Truck => "truck",
        }
    }

    /// The drawn body's `(length_m, width_m, height_m)`: over its bumpers, over its wheels
    /// (a car) or its box (the truck), and from the ground to its roof or box top.
    pub fn dimensions(self) -> (f64, f64, f64) {
        match self.car_body() {
            Some(body) => (
                2.0 * CAR_HALF_LENGTH_M,
                2.0 * CAR_HALF_WIDTH_M,
                body.height_m(),
            ),
            None => (
                2.0 * TRUCK_HALF_LENGTH_M,
                2.0 * TRUCK_HALF_WIDTH_M,
                TRUCK_HEIGHT_M,
            ),
        }
    }

    /// The car body it is drawn as; `None` for the truck.
    pub(super) fn car_body(self) -> Option<CarBody> {
        match self {
            VehicleKind::Sedan => Some(CarBody::Sedan),
            VehicleKind::Hatchback => Some(CarBody::Hatchback),
            VehicleKind::Van => Some(CarBody::Van),
            VehicleKind::Truck => None,
        }
    }
}

/// A vehicle of `kind` in its own frame, in `slot`, painted `albedo`.
pub(super) fn vehicle(mesh: &mut Mesh, slot: u32, albedo: f64, kind: VehicleKind) {
    match kind.car_body() {
        Some(body) => car(mesh, slot, albedo, body),
        None => truck(mesh, slot, albedo),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kinds_dimensions_are_its_drawn_bodys() {
        for kind in VehicleKind::ALL {
            let mut mesh = Mesh::default();
            vehicle(&mut mesh, 3, 0.5, kind);
            let extent = |k: usize| {
                let values = mesh.vertices.iter().map(|v| f64::from(v.position[k]));
                let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(v), h.max(v)));
                hi - lo
            };
            let (length, width, height) = kind.dimensions();
            // Lamps, hubs and glass stand a few millimetres proud of the body.
            assert!((extent(0) - length).abs() < 0.02, "{kind:?} length");
            assert!((extent(2) - width).abs() < 0.02, "{kind:?} width");
            assert!((extent(1) - height).abs() < 1e-5, "{kind:?} height");
        }
    }
}
