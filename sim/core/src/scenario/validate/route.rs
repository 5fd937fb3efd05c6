//! `[route]`: the segments, the lane and the intersections.

use super::{check, Blame, MAX_ARC_RADIUS_M, MAX_ROUTE_M, MIN_ARC_RADIUS_M};
use crate::scenario::{RouteFile, ScenarioError};
use sim_render::{RouteSegment, RouteSpec};

/// The route, and its length in metres.
pub(super) fn route(r: &RouteFile, f: &Blame) -> Result<(RouteSpec, f64), ScenarioError> {
    let finite_pos = |v: f64| v.is_finite() && v > 0.0;
    f.at(
        "route.lane_width_m",
        check(
            r.lane_width_m.is_finite() && (2.0..=6.0).contains(&r.lane_width_m),
            "must be 2–6 metres",
            r.lane_width_m,
        ),
    )?;
    f.at(
        "route.segments",
        check(!r.segments.is_empty(), "needs at least one segment", "[]"),
    )?;
    let mut segments = Vec::new();
    for (i, s) in r.segments.iter().enumerate() {
        let field = "route.segments";
        let seg = match (s.straight_m, s.arc_radius_m, s.arc_angle_deg) {
            (Some(length_m), None, None) => {
                f.at(
                    field,
                    check(
                        finite_pos(length_m) && length_m <= MAX_ROUTE_M,
                        &format!("segment {i}: straight_m must be > 0 and at most {MAX_ROUTE_M} m"),
                        length_m,
                    ),
                )?;
                RouteSegment::Straight { length_m }
            }
            (None, Some(radius_m), Some(angle_deg)) => {
                f.at(
                    field,
                    check(
                        (MIN_ARC_RADIUS_M..=MAX_ARC_RADIUS_M).contains(&radius_m),
                        &format!(
                            "segment {i}: arc_radius_m must be {MIN_ARC_RADIUS_M}–{MAX_ARC_RADIUS_M} m \
                             (at least the vehicles' turning circles)"
                        ),
                        radius_m,
                    ),
                )?;
                f.at(
                    field,
                    check(
                        angle_deg.is_finite() && angle_deg != 0.0 && angle_deg.abs() <= 360.0,
                        &format!("segment {i}: arc_angle_deg must be non-zero, at most 360"),
                        angle_deg,
                    ),
                )?;
                RouteSegment::Arc {
                    radius_m,
                    angle_deg,
                }
            }
            _ => {
                return Err(f.invalid(field, format!("segment {i}: give either `straight_m`, or both `arc_radius_m` and `arc_angle_deg`")));
            }
        };
        segments.push(seg);
    }
    let route = RouteSpec {
        segments,
        intersections_m: r.intersections_m.clone(),
        lane_width_m: r.lane_width_m,
        lanes: r.lanes,
    };
    let length = length_m(&route);
    f.at(
        "route.segments",
        check(
            length <= MAX_ROUTE_M,
            &format!("the route must be at most {MAX_ROUTE_M} m long"),
            format!("{length:.0} m in all"),
        ),
    )?;
    for &x in &route.intersections_m {
        f.at(
            "route.intersections_m",
            check(
                x.is_finite() && x >= 0.0 && x <= length,
                &format!("stations must lie on the route, 0–{length:.0} m"),
                x,
            ),
        )?;
    }
    Ok((route, length))
}

/// The length of a route's centreline, metres.
pub(crate) fn length_m(route: &RouteSpec) -> f64 {
    route
        .segments
        .iter()
        .map(|s| match s {
            RouteSegment::Straight { length_m } => *length_m,
            RouteSegment::Arc {
                radius_m,
                angle_deg,
            } => radius_m * angle_deg.abs().to_radians(),
        })
        .sum()
}
