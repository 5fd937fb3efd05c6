//! The pole line: telephone poles on the right of the road, with cross-arms, insulators and
//! sagging wires between them; some carry a lower cross-arm or a transformer.

use super::bins::Bins;
use super::layer::Layer;
use super::mesh::Mesh;
use super::pole::{pole, PoleFittings};
use super::site::Site;
use super::standing::stand;
use rand::Rng;

/// Straight pieces per wire span: three chords follow a 0.5 m sag over a ~45 m span to
/// within 6 cm (a pixel at 20 m), each an open beam of eight triangles (a flat ribbon
/// would be cheaper but vanishes edge-on when the wire passes above the camera).
const WIRE_PIECES: usize = 3;
/// How far a wire sags at the middle of its span, metres.
const SAG_M: f64 = 0.5;

/// Lays the poles, spaced as the description's density says (drawn from the scene's
/// `"poles"` stream, their fittings from `"pole-fittings"`), clear of intersections, and
/// the wires from each pole to the one before it.
pub(super) fn lay(site: &Site<'_>, bins: &mut Bins) {
    let (route, road_half, length) = (site.route, site.road_half, site.length);
    let d = &site.description.densities;
    let mut poles = site.stream("poles");
    let mut fittings = site.stream("pole-fittings");
    if d.poles_per_km <= 0.0 {
        // None (the density is validated: finite, not negative).
        return;
    }
    // Capped, so that the first pole's draw below stays finite for any positive density
    // (1000 / 1e-320 is infinite); a pole every 1e9 m is none on a route.
    let spacing = (1000.0 / d.poles_per_km).min(1e9);
    let mut s = poles.random_range(-50.0..-50.0 + spacing);
    let mut previous: Option<[[f64; 3]; 2]> = None;
    while s < length + 100.0 {
        let here = s;
        s += spacing * poles.random_range(0.85..1.15);
        if route.near_intersection(here, road_half + 4.0) {
            continue;
        }
        let l = road_half + 2.0;
        let heading = route.at(here)[2];
        let [px, pz] = route.point(here, l);
        let mut item = Mesh::default();
        let kind = PoleFittings::pick(fittings.random_range(0.0..1.0));
        let mut ends = pole(&mut item, [px, pz], heading, kind);
        let base = stand(site.terrain, &mut item);
        for end in &mut ends {
            end[1] += base;
        }
        bins.at(px, pz, Layer::Clutter).append(&item);
        if let Some(prev) = previous {
            let wires = bins.at(px, pz, Layer::Wires);
            for k in 0..2 {
                wire(wires, prev[k], ends[k]);
            }
        }
        previous = Some(ends);
    }
}

/// A wire from `a` to `b`, sagging [`SAG_M`] at the middle, in [`WIRE_PIECES`] beams.
fn wire(wires: &mut Mesh, a: [f64; 3], b: [f64; 3]) {
    let point = |t: f64| {
        [
            a[0] + t * (b[0] - a[0]),
            a[1] + t * (b[1] - a[1]) - 4.0 * SAG_M * t * (1.0 - t),
            a[2] + t * (b[2] - a[2]),
        ]
    };
    for i in 0..WIRE_PIECES {
        wires.beam(
            point(i as f64 / WIRE_PIECES as f64),
            point((i + 1) as f64 / WIRE_PIECES as f64),
            0.02,
            0.12,
        );
    }
}
