//! Over bumps, the grass verges beside the road, on the height field, so that the road does
//! not stand out of the flat grass.

use super::bins::Bins;
use super::ground::GRASS_ALBEDO;
use super::layer::Layer;
use super::material::Material;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::road::quads;
use super::site::Site;

/// Over bumps, how far the grass verges on the height field reach beyond the road's edge,
/// metres: the flat grass beyond is 5 m or more from the wheels, where a bump's rise of a
/// few centimetres is a pixel at the tracker's ranges.
const VERGE_M: f64 = 5.0;
/// Height of those verges above the ground, metres: above the flat grass, below the road.
const VERGE_Y_M: f64 = 0.005;
/// Longest edge of a verge's pieces on the height field, metres: grass has no paint to
/// fight for depth with, so it may depart from the field by a centimetre or two between
/// vertices (curvature ≤ 0.14 /m for the roughest shipped bumps: 1.7 cm over 1 m).
const VERGE_EDGE_M: f64 = 1.0;

/// Lays the verges beside each of the road's quads over the bump patch (none on flat
/// ground), draped on the height field, in the ground layer.
pub(super) fn lay(site: &Site<'_>, bins: &mut Bins) {
    let Some(terrain) = site.terrain else {
        return;
    };
    let road_half = site.road_half;
    let grass_object = ObjectSlot::WORLD | Material::GRASS;
    for (s, s1) in quads(site.route, site.length) {
        let mid = site.world(0.5 * (s + s1), 0.0, 0.0);
        if !terrain.covers(mid[0], mid[2]) {
            continue;
        }
        let mut verges = Mesh::default();
        for (l0, l1) in [
            (-road_half - VERGE_M, -road_half),
            (road_half, road_half + VERGE_M),
        ] {
            let (y, albedo) = (VERGE_Y_M, GRASS_ALBEDO);
            site.strip(&mut verges, [s, s1, l0, l1], y, albedo, grass_object);
        }
        bins.at(mid[0], mid[2], Layer::Ground)
            .append(&terrain.drape(&verges, VERGE_EDGE_M));
    }
}
