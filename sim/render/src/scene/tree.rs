//! Trees: a trunk and a canopy of clumps with gaps between them, each clump's surface
//! perforated by the renderer (`Layer::Foliage`), so their shadows dapple; and the trees
//! along the route.

use super::bins::Bins;
use super::layer::Layer;
use super::site::Site;
use super::standing::ground_under;
use super::terrain::Terrain;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A tree at world (`x`, `z`), its sizes drawn from `rng`: the trunk in the clutter layer,
/// standing on the lowest ground under it, the canopy's clumps in the foliage layer.
pub(super) fn tree(
    bins: &mut Bins,
    terrain: Option<&Terrain>,
    rng: &mut ChaCha8Rng,
    x: f64,
    z: f64,
) {
    let trunk = rng.random_range(2.5..4.0);
    let base = ground_under(terrain, &[[x - 0.15, z - 0.15], [x + 0.15, z + 0.15]]);
    bins.at(x, z, Layer::Clutter)
        .upright_box(x, z, 0.0, 0.15, 0.15, base, trunk + 1.0, 0.22);
    let mesh = bins.at(x, z, Layer::Foliage);
    for _ in 0..rng.random_range(5..9) {
        let c = [
            x + rng.random_range(-1.6..1.6),
            trunk + rng.random_range(1.0..3.2),
            z + rng.random_range(-1.6..1.6),
        ];
        let r = rng.random_range(0.7..1.6);
        mesh.octahedron(
            c,
            [r, r * rng.random_range(0.7..1.1), r],
            rng.random_range(0.13..0.22),
        );
    }
}

/// Lays the trees along the route, on either side but clear of intersections, drawn from
/// the scene's `"trees"` stream.
pub(super) fn lay_row(site: &Site<'_>, bins: &mut Bins) {
    let (route, road_half, length) = (site.route, site.road_half, site.length);
    let mut trees = site.stream("trees");
    for _ in 0..Site::count(site.description.densities.trees_per_km, length + 150.0) {
        let s = trees.random_range(-50.0..length + 100.0);
        let side = if trees.random_bool(0.5) { 1.0 } else { -1.0 };
        let l = side * (road_half + trees.random_range(4.0..22.0));
        if route.near_intersection(s, road_half + 6.0) {
            continue;
        }
        let [x, z] = route.point(s, l);
        tree(bins, site.terrain, &mut trees, x, z);
    }
}
