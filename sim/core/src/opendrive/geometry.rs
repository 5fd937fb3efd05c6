//! A `<geometry>` as a route segment, and where it ends in the file's own frame.

use super::model::{Geometry, GeometryKind};
use sim_render::{PRange, Route, RouteSegment, RouteSpec};

/// The route segment a geometry is, exactly: a line a straight, an arc an arc (or, with a
/// radius beyond the scenario's arcs, a clothoid of constant curvature, the same curve), a
/// spiral a clothoid, `poly3` and `paramPoly3` the cubics.
pub(super) fn segment(g: &Geometry) -> RouteSegment {
    let length_m = g.length;
    match g.kind {
        GeometryKind::Line => RouteSegment::Straight { length_m },
        GeometryKind::Arc(k) if k != 0.0 && 1.0 / k.abs() <= crate::scenario::MAX_ARC_RADIUS_M => {
            RouteSegment::Arc {
                radius_m: 1.0 / k.abs(),
                angle_deg: (length_m * k).to_degrees(),
            }
        }
        GeometryKind::Arc(k) => RouteSegment::Spiral {
            length_m,
            curvature_start: k,
            curvature_end: k,
        },
        GeometryKind::Spiral(k0, k1) => RouteSegment::Spiral {
            length_m,
            curvature_start: k0,
            curvature_end: k1,
        },
        GeometryKind::Poly3(v) => RouteSegment::Poly3 { length_m, v },
        GeometryKind::ParamPoly3 { u, v, normalized } => RouteSegment::ParamPoly3 {
            length_m,
            u,
            v,
            p_range: if normalized {
                PRange::Normalized
            } else {
                PRange::ArcLength
            },
        },
    }
}

/// `[x, y, hdg]` where geometry `g` ends, in the file's frame (x east, y north, heading
/// counter-clockwise), from its own start and shape.
pub fn geometry_end(g: &Geometry) -> [f64; 3] {
    let route = Route::new(RouteSpec {
        segments: vec![segment(g)],
        intersections_m: vec![],
        lane_width_m: 3.5,
        lanes: 1,
        elevation: Vec::new(),
        median_m: 0.0,
        lane_widths_m: Vec::new(),
        lane_offset: Vec::new(),
    });
    // carfollow's frame: x forward, z to the right; the file's: x forward, y to the left.
    let [u, z, theta] = route.at(route.length_m());
    let v = -z;
    let (sin, cos) = g.hdg.sin_cos();
    [
        g.x + u * cos - v * sin,
        g.y + u * sin + v * cos,
        g.hdg + theta,
    ]
}
