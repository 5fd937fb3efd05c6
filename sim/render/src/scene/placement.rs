//! Hand-placed clutter: the poles, trees and overpasses a scenario puts where it wants them.

use super::bins::Bins;
use super::description::Placement;
use super::layer::Layer;
use super::mesh::Mesh;
use super::overpass::overpass;
use super::pole::{POLE_ALBEDO, POLE_TOP_M};
use super::site::Site;
use super::standing::stand;
use super::tree::tree;

/// Lays the description's placements, in order; the trees' sizes are drawn from the
/// scene's `"placements"` stream.
pub(super) fn lay(site: &Site<'_>, bins: &mut Bins) {
    let mut placed = site.stream("placements");
    for placement in &site.description.placements {
        match *placement {
            Placement::Pole { x_m, z_m } => {
                // A bare pole: no cross-arm, no wires.
                let mut item = Mesh::default();
                item.upright_box(x_m, z_m, 0.0, 0.13, 0.13, 0.0, POLE_TOP_M, POLE_ALBEDO);
                stand(site.terrain, &mut item);
                bins.at(x_m, z_m, Layer::Clutter).append(&item);
            }
            Placement::Tree { x_m, z_m } => tree(bins, site.terrain, &mut placed, x_m, z_m),
            Placement::Overpass {
                station_m,
                deck_m,
                height_m,
            } => overpass(site, bins, station_m, deck_m, height_m),
        }
    }
}
