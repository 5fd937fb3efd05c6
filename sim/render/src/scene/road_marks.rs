//! Cracks, patches and pot holes: dark marks on the road, drawn from the scene's
//! `"road-marks"` stream.

use super::bins::Bins;
use super::layer::Layer;
use super::mesh::Mesh;
use super::road::{road_object, MARK_Y_M};
use super::site::Site;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A kind of mark: one mark drawn from the stream, its vertices' `object` the one given,
/// and where it is binned (its centre, or where a crack ends).
type Mark = fn(&Site<'_>, &mut ChaCha8Rng, u32) -> ([f64; 3], Mesh);

/// Lays the cracks, then the patches, then the pot holes, at the densities the description
/// gives, each in the bin of the point it ends at (a crack) or is centred on.
pub(super) fn lay(site: &Site<'_>, bins: &mut Bins) {
    let mut marks = site.stream("road-marks");
    let object = road_object(site.description.road_surface);
    let d = &site.description.densities;
    let kinds: [(f64, Mark); 3] = [
        (d.cracks_per_km, crack),
        (d.patches_per_km, patch),
        (d.potholes_per_km, pothole),
    ];
    for (per_km, mark) in kinds {
        for _ in 0..Site::count(per_km, site.length) {
            let (at, mesh) = mark(site, &mut marks, object);
            bins.at(at[0], at[2], Layer::Surface).append(&mesh);
        }
    }
}

/// Where a mark is, drawn from `marks`: a station on the route and a lateral offset within
/// the lanes, of both directions.
fn spot(site: &Site<'_>, marks: &mut ChaCha8Rng) -> (f64, f64) {
    let s = marks.random_range(0.0..site.length);
    let l = marks.random_range(-site.lanes_width..site.lanes_width);
    (s, l)
}

/// The corners of a mark, each a station and a lateral offset, on the road at the marks'
/// height.
fn on_road(site: &Site<'_>, corners: [[f64; 2]; 4]) -> [[f64; 3]; 4] {
    corners.map(|[s, l]| site.world(s, l, MARK_Y_M))
}

/// A crack: a thin zig-zag of three to six pieces, along the road or across it.
fn crack(site: &Site<'_>, marks: &mut ChaCha8Rng, object: u32) -> ([f64; 3], Mesh) {
    let road_half = site.road_half;
    let (mut s, mut l) = spot(site, marks);
    let transverse = marks.random_bool(0.4);
    let mut mesh = Mesh::default();
    for _ in 0..marks.random_range(3..7) {
        let (ds, dl) = if transverse {
            (marks.random_range(-0.3..0.3), marks.random_range(0.3..0.8))
        } else {
            (
                marks.random_range(0.4..1.0),
                marks.random_range(-0.25..0.25),
            )
        };
        let (s1, l1) = (s + ds, (l + dl).clamp(-road_half, road_half));
        let w = 0.025;
        let corners = [[s, l - w], [s1, l1 - w], [s1, l1 + w], [s, l + w]];
        mesh.polygon(&on_road(site, corners), 0.10, object);
        (s, l) = (s1, l1);
    }
    (site.world(s, l, 0.0), mesh)
}

/// A patch: a rectangle of darker or lighter asphalt.
fn patch(site: &Site<'_>, marks: &mut ChaCha8Rng, object: u32) -> ([f64; 3], Mesh) {
    let (s, l) = spot(site, marks);
    let (hs, hl) = (marks.random_range(0.5..1.5), marks.random_range(0.4..1.0));
    let albedo = if marks.random_bool(0.5) { 0.18 } else { 0.40 };
    let mut mesh = Mesh::default();
    let corners = [
        [s - hs, l - hl],
        [s + hs, l - hl],
        [s + hs, l + hl],
        [s - hs, l + hl],
    ];
    mesh.polygon(&on_road(site, corners), albedo, object);
    (site.world(s, l, 0.0), mesh)
}

/// A pot hole: a dark, ragged octagon.
fn pothole(site: &Site<'_>, marks: &mut ChaCha8Rng, object: u32) -> ([f64; 3], Mesh) {
    let (s, l) = spot(site, marks);
    let r = marks.random_range(0.2..0.5);
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 8.0;
            let rr = r * marks.random_range(0.7..1.2);
            site.world(s + rr * a.cos(), l + rr * a.sin(), MARK_Y_M)
        })
        .collect();
    let mut mesh = Mesh::default();
    mesh.polygon(&corners, 0.06, object);
    (site.world(s, l, 0.0), mesh)
}
