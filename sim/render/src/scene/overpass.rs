//! The overpass: a bridge carrying another road across the route, whose shadow lies across
//! the road as a band with straight edges.

use super::bins::Bins;
use super::layer::Layer;
use super::object_slot::ObjectSlot;
use super::site::Site;
use super::standing::ground_under;

/// An overpass across the route at `station_m`: a deck 1 m thick, `deck_m` wide along the
/// route and reaching 12 m beyond the road's edges, on two abutment walls that stand on the
/// ground (over bumps, from the lowest ground under each up to the deck).
pub(super) fn overpass(
    site: &Site<'_>,
    bins: &mut Bins,
    station_m: f64,
    deck_m: f64,
    height_m: f64,
) {
    let (route, terrain, road_half) = (site.route, site.terrain, site.road_half);
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
        let c = [x + l * across[0], z + l * across[2]];
        let corner = |a: f64, b: f64| {
            [
                c[0] + a * along[0] + b * across[0],
                c[1] + a * along[2] + b * across[2],
            ]
        };
        let (ha, hb) = (0.5 * deck_m, 0.4);
        let base = ground_under(
            terrain,
            &[
                corner(-ha, -hb),
                corner(ha, -hb),
                corner(ha, hb),
                corner(-ha, hb),
            ],
        );
        mesh.oriented_box(
            [c[0], 0.5 * (base + height_m), c[1]],
            [along, [0.0, 1.0, 0.0], across],
            [ha, 0.5 * (height_m - base), hb],
            0.55,
            ObjectSlot::WORLD,
        );
    }
}
