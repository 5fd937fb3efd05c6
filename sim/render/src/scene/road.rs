//! The road: its surface along the route and past either end, the edge lines, the dashed
//! centre line and lane lines, and the crossing roads at intersections.

use super::bins::Bins;
use super::description::RoadSurface;
use super::layer::Layer;
use super::material::Material;
use super::object_slot::ObjectSlot;
use super::route::Route;
use super::site::{Site, ROAD_RUNOUT_M};

/// Height of the road surface above the grass, metres; the crossing roads sit just below it
/// and the paint and marks just above, so nothing fights for depth.
const ROAD_Y_M: f64 = 0.02;
/// Height of crossing roads, metres.
const CROSS_ROAD_Y_M: f64 = 0.015;
/// Height of lane paint, cracks, patches and pot holes, metres.
pub(super) const MARK_Y_M: f64 = 0.03;
/// Length of one road quad along an arc, metres (a 60 m arc bends < 2° per quad).
const ROAD_STEP_M: f64 = 2.0;
/// Length of one road quad along a straight, metres: long quads mean few triangles (the
/// road is flat, so length costs nothing in accuracy), and llvmpipe's cost grows with
/// every triangle set up.
const STRAIGHT_STEP_M: f64 = 20.0;
/// Lane paint width, metres (US practice: 4–6 in).
const PAINT_WIDTH_M: f64 = 0.12;
/// Centre-line dashes: dash and period, metres (US practice: 10 ft dash in a 40 ft cycle).
const DASH_M: f64 = 3.0;
/// Centre-line dash period, metres.
const DASH_PERIOD_M: f64 = 12.0;
/// Half length of a crossing road, metres.
const CROSS_ROAD_HALF_M: f64 = 120.0;
/// Albedo of the road's surface.
const ASPHALT: f64 = 0.30;
/// Albedo of the lane paint.
const PAINT: f64 = 0.75;

/// The road's quads along `route` of length `length_m`, from [`ROAD_RUNOUT_M`] before its
/// start to as far past its end: `(s0, s1)`, each station to the next, long on straights
/// ([`STRAIGHT_STEP_M`]) and short on arcs ([`ROAD_STEP_M`]).
pub(super) fn quads(route: &Route, length_m: f64) -> impl Iterator<Item = (f64, f64)> + '_ {
    let mut s = -ROAD_RUNOUT_M;
    std::iter::from_fn(move || {
        if s >= length_m + ROAD_RUNOUT_M {
            return None;
        }
        let straight =
            route.curvature_at(s) == 0.0 && route.curvature_at(s + STRAIGHT_STEP_M) == 0.0;
        let s1 = s + if straight {
            STRAIGHT_STEP_M
        } else {
            ROAD_STEP_M
        };
        let quad = (s, s1);
        s = s1;
        Some(quad)
    })
}

/// The `object` of the road's surfaces (crossing roads, cracks, patches and pot holes
/// too): the world's slot and the surface's material.
pub(super) fn road_object(surface: RoadSurface) -> u32 {
    ObjectSlot::WORLD
        | match surface {
            RoadSurface::Asphalt => Material::ASPHALT,
            RoadSurface::Gravel => Material::GRAVEL,
        }
}

/// How far inside a median's edge its solid line runs, metres: as far as the edge line
/// runs beyond the lanes.
const MEDIAN_LINE_INSET_M: f64 = 0.1;

/// The lateral offset of the solid line along a median's edge, metres from the centre
/// line: just inside the median (its middle when the median is narrower than two insets);
/// `None` without a median.
fn median_line_m(median_m: f64) -> Option<f64> {
    (median_m > 0.0).then(|| (median_m - MEDIAN_LINE_INSET_M).max(0.5 * median_m))
}

/// Lays the road strip, quad by quad, each with its pieces of the edge lines (just beyond
/// each direction's lanes, and with a median just inside each of its edges).
pub(super) fn lay_surface(site: &Site<'_>, bins: &mut Bins) {
    let (route, lanes_width, road_half) = (site.route, site.lanes_width, site.road_half);
    let road_object = road_object(site.description.road_surface);
    let paint_object = ObjectSlot::WORLD | Material::PAINT;
    for (s, s1) in quads(route, site.length) {
        let mid = site.world(0.5 * (s + s1), 0.0, 0.0);
        let mesh = bins.at(mid[0], mid[2], Layer::Surface);
        let lateral = [s, s1, -road_half, road_half];
        site.strip(mesh, lateral, ROAD_Y_M, ASPHALT, road_object);
        let median = median_line_m(site.description.route.median_m);
        let edges = [-1.0, 1.0].into_iter().flat_map(|side| {
            let median = median.map(|m| side * m);
            std::iter::once(side * (lanes_width + 0.1)).chain(median)
        });
        for l in edges {
            let mut a = s;
            // Edge lines stop across intersections: in short pieces near one, else in
            // one piece per road quad.
            let clear = !route.near_intersection(0.5 * (s + s1), road_half + 1.0 + (s1 - s));
            let piece = if clear { s1 - s } else { ROAD_STEP_M };
            while a < s1 {
                let b = (a + piece).min(s1);
                if !route.near_intersection(0.5 * (a + b), road_half + 1.0) {
                    let w = 0.5 * PAINT_WIDTH_M;
                    site.strip(mesh, [a, b, l - w, l + w], MARK_Y_M, PAINT, paint_object);
                }
                a = b;
            }
        }
    }
}

/// Lays the dashed centre line, and with more than one lane each way the dashed lines
/// between lanes (the same paint, dash and period, at each lane's inner edge,
/// `RouteSpec::lane_inner_edge_m`, either side of the centre line for lanes 2 to
/// `lanes`), stopping across intersections. Each dash's lines are laid together, the
/// centre line's first. With a median there is no centre line: solid lines run along the
/// median's edges instead ([`lay_median_lines`]).
pub(super) fn lay_centre_line(site: &Site<'_>, bins: &mut Bins) {
    let paint_object = ObjectSlot::WORLD | Material::PAINT;
    let spec = &site.description.route;
    let lanes = spec.lanes;
    let centre = (spec.median_m == 0.0).then_some(0.0);
    let mut s = -ROAD_RUNOUT_M;
    while s < site.length + ROAD_RUNOUT_M {
        if !site
            .route
            .near_intersection(s + 0.5 * DASH_M, site.road_half + 1.0)
        {
            let w = 0.5 * PAINT_WIDTH_M;
            let lines = (2..=lanes).flat_map(|k| {
                let l = spec.lane_inner_edge_m(k);
                [-l, l]
            });
            for l in centre.into_iter().chain(lines) {
                let mid = site.world(s + 0.5 * DASH_M, l, 0.0);
                let mesh = bins.at(mid[0], mid[2], Layer::Surface);
                site.strip(
                    mesh,
                    [s, s + DASH_M, l - w, l + w],
                    MARK_Y_M,
                    PAINT,
                    paint_object,
                );
            }
        }
        s += DASH_PERIOD_M;
    }
}

/// Lays crossing roads at intersections, at right angles to the route.
pub(super) fn lay_crossings(site: &Site<'_>, bins: &mut Bins) {
    let road_half = site.road_half;
    let road_object = road_object(site.description.road_surface);
    for &c in &site.description.route.intersections_m {
        let [x, z, heading] = site.route.at(c);
        let along = [heading.sin(), heading.cos()]; // the route's right = the crossing's direction
        let across = [heading.cos(), -heading.sin()];
        let mut t = -CROSS_ROAD_HALF_M;
        while t < CROSS_ROAD_HALF_M {
            let t1 = t + 10.0;
            let p = |t: f64, w: f64| {
                [
                    x + t * along[0] + w * across[0],
                    CROSS_ROAD_Y_M,
                    z + t * along[1] + w * across[1],
                ]
            };
            let centre = p(t + 5.0, 0.0);
            bins.at(centre[0], centre[2], Layer::Surface).polygon(
                &[
                    p(t, -road_half),
                    p(t1, -road_half),
                    p(t1, road_half),
                    p(t, road_half),
                ],
                ASPHALT * 0.95,
                road_object,
            );
            t = t1;
        }
    }
}
