//! `[route]`: the segments (or an OpenDRIVE road), the lane and the intersections.

use super::elevation::elevation_problem;
use super::lane_offset::lane_offset_problem;
use super::{check, Blame, MAX_ARC_RADIUS_M, MAX_ROUTE_M, MIN_ARC_RADIUS_M};
use crate::opendrive::ImportedRoad;
use crate::scenario::{OpenDriveFile, RouteFile, ScenarioError, SegmentFile};
use sim_render::{PRange, Route, RouteSegment, RouteSpec};

/// Spacing of the stations a varying piece's curvature is checked at, metres: the drivers'
/// polyline samples the route every metre.
const CURVATURE_CHECK_M: f64 = 0.25;

/// What reads `route.opendrive`'s road, and whether the file (or a `--set`) gives a field.
pub(crate) struct RoadSource<'a> {
    /// Reads and imports the road file.
    pub(crate) load: &'a dyn Fn(&OpenDriveFile) -> Result<ImportedRoad, ScenarioError>,
    /// Whether the scenario gives the dotted field itself.
    pub(crate) gives: &'a dyn Fn(&str) -> bool,
}

/// The route, its length in metres, and what its road file holds that is not drawn (a
/// warning line each).
pub(super) fn route(
    r: &RouteFile,
    f: &Blame,
    roads: &RoadSource,
) -> Result<(RouteSpec, f64, Vec<String>), ScenarioError> {
    let mut unapplied = Vec::new();
    let route = match &r.opendrive {
        Some(od) => {
            if !r.segments.is_empty() {
                return Err(f.invalid(
                    "route.segments",
                    "cannot be given with `route.opendrive`: give one or the other".into(),
                ));
            }
            for field in [
                "route.lanes",
                "route.lane_width_m",
                "route.lane_widths_m",
                "route.median_m",
            ] {
                if (roads.gives)(field) {
                    return Err(f.invalid(
                        field,
                        "cannot be given with `route.opendrive`: the road file's lanes give it"
                            .into(),
                    ));
                }
            }
            if (roads.gives)("route.elevation") {
                return Err(f.invalid(
                    "route.elevation",
                    "cannot be given with `route.opendrive`: the road file's elevation profile \
                     gives it"
                        .into(),
                ));
            }
            if (roads.gives)("route.lane_offset") {
                return Err(f.invalid(
                    "route.lane_offset",
                    "cannot be given with `route.opendrive`: the road file's `<laneOffset>` \
                     records give it"
                        .into(),
                ));
            }
            let road = (roads.load)(od)?;
            unapplied = road.unapplied;
            RouteSpec {
                segments: road.segments,
                intersections_m: r.intersections_m.clone(),
                lane_width_m: road.lane_width_m,
                lanes: road.lanes,
                elevation: road.elevation,
                median_m: road.median_m,
                lane_widths_m: road.lane_widths_m,
                lane_offset: road.lane_offset,
            }
        }
        None => RouteSpec {
            segments: segments(r, f)?,
            intersections_m: r.intersections_m.clone(),
            lane_width_m: lane_widths(r, f, roads)?,
            lanes: r.lanes,
            elevation: r.elevation.clone(),
            median_m: median(r, f)?,
            lane_widths_m: r.lane_widths_m.clone(),
            lane_offset: r.lane_offset.clone(),
        },
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
    // An OpenDRIVE road's profile was checked on import, naming its line.
    if r.opendrive.is_none() {
        if let Some((i, problem)) = elevation_problem(&route.elevation, length) {
            return Err(f.invalid("route.elevation", format!("record {i}: {problem}")));
        }
        if let Some((i, problem)) = lane_offset_problem(&route) {
            return Err(f.invalid("route.lane_offset", format!("record {i}: {problem}")));
        }
    }
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
    Ok((route, length, unapplied))
}

/// The lanes' widths: `route.lane_widths_m`, each 2–6 m and one per lane, given instead
/// of `route.lane_width_m`. Returns the one width the route keeps as `lane_width_m`:
/// `lane_width_m`'s, or lane 1's.
fn lane_widths(r: &RouteFile, f: &Blame, roads: &RoadSource) -> Result<f64, ScenarioError> {
    let field = "route.lane_widths_m";
    let Some(&first) = r.lane_widths_m.first() else {
        return Ok(r.lane_width_m);
    };
    if (roads.gives)("route.lane_width_m") {
        return Err(f.invalid(
            field,
            "cannot be given with `route.lane_width_m`: give one width for every lane, or \
             each lane's"
                .into(),
        ));
    }
    let (given, lanes) = (r.lane_widths_m.len(), r.lanes as usize);
    f.at(
        field,
        check(
            given == lanes,
            &format!("one width per lane: `route.lanes` is {lanes}"),
            format!("{given} widths"),
        ),
    )?;
    for (i, &w) in r.lane_widths_m.iter().enumerate() {
        f.at(
            field,
            check(
                w.is_finite() && (2.0..=6.0).contains(&w),
                &format!("lane {}'s width must be 2–6 metres", i + 1),
                w,
            ),
        )?;
    }
    Ok(first)
}

/// `route.median_m`: 0–10 m.
fn median(r: &RouteFile, f: &Blame) -> Result<f64, ScenarioError> {
    f.at(
        "route.median_m",
        check(
            r.median_m.is_finite() && (0.0..=MAX_MEDIAN_M).contains(&r.median_m),
            &format!("must be 0–{MAX_MEDIAN_M} metres"),
            r.median_m,
        ),
    )?;
    Ok(r.median_m)
}

/// The widest median carfollow draws, metres: the paved road is laid across it, and a
/// wider strip is a verge between two carriageways, which carfollow does not draw.
const MAX_MEDIAN_M: f64 = 10.0;

/// `route.segments`, each checked.
fn segments(r: &RouteFile, f: &Blame) -> Result<Vec<RouteSegment>, ScenarioError> {
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
        if let Some(seg) = varying(s) {
            let seg = seg.map_err(|m| f.invalid(field, format!("segment {i}: {m}")))?;
            if let Some(problem) = segment_problem(&seg) {
                return Err(f.invalid(field, format!("segment {i}: {problem}")));
            }
            segments.push(seg);
            continue;
        }
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
                return Err(f.invalid(field, format!("segment {i}: {ONE_KIND}")));
            }
        };
        segments.push(seg);
    }
    Ok(segments)
}

/// What a segment must give.
const ONE_KIND: &str = "give one kind: `straight_m`; `arc_radius_m` and `arc_angle_deg`; \
    `spiral_m`, `curvature_start` and `curvature_end`; `poly3_m` and `poly3`; or \
    `param_poly3_m`, `u` and `v` (and `p_range`)";

/// A clothoid or cubic segment, when `s` gives one (`Err` when it mixes kinds).
fn varying(s: &SegmentFile) -> Option<Result<RouteSegment, String>> {
    let spiral = [s.spiral_m, s.curvature_start, s.curvature_end];
    let constant = s.straight_m.is_some() || s.arc_radius_m.is_some() || s.arc_angle_deg.is_some();
    let kinds = [
        spiral.iter().any(Option::is_some),
        s.poly3_m.is_some() || s.poly3.is_some(),
        s.param_poly3_m.is_some() || s.u.is_some() || s.v.is_some() || s.p_range.is_some(),
    ];
    let given = kinds.iter().filter(|&&k| k).count();
    if given == 0 {
        return None;
    }
    if given > 1 || constant {
        return Some(Err(ONE_KIND.into()));
    }
    Some(
        match (spiral, (s.poly3_m, s.poly3), (s.param_poly3_m, s.u, s.v)) {
            ([Some(length_m), Some(curvature_start), Some(curvature_end)], _, _) => {
                Ok(RouteSegment::Spiral {
                    length_m,
                    curvature_start,
                    curvature_end,
                })
            }
            (_, (Some(length_m), Some(v)), _) => Ok(RouteSegment::Poly3 { length_m, v }),
            (_, _, (Some(length_m), Some(u), Some(v))) => Ok(RouteSegment::ParamPoly3 {
                length_m,
                u,
                v,
                p_range: s.p_range.unwrap_or(PRange::ArcLength),
            }),
            _ => Err(ONE_KIND.into()),
        },
    )
}

/// What is wrong with a segment the vehicles cannot drive, if anything: its numbers
/// finite, its length (0, [`MAX_ROUTE_M`]], an arc's radius within the scenario's bounds,
/// and a varying piece's curvature at most 1/[`MIN_ARC_RADIUS_M`] at every
/// [`CURVATURE_CHECK_M`] (the vehicles' turning circles). The OpenDRIVE importer asks the
/// same of every geometry.
pub(crate) fn segment_problem(seg: &RouteSegment) -> Option<String> {
    let numbers: Vec<f64> = match *seg {
        RouteSegment::Straight { length_m } => vec![length_m],
        RouteSegment::Arc {
            radius_m,
            angle_deg,
        } => vec![radius_m, angle_deg],
        RouteSegment::Spiral {
            length_m,
            curvature_start,
            curvature_end,
        } => vec![length_m, curvature_start, curvature_end],
        RouteSegment::Poly3 { length_m, v } => [&[length_m][..], &v].concat(),
        RouteSegment::ParamPoly3 { length_m, u, v, .. } => [&[length_m][..], &u, &v].concat(),
    };
    if numbers.iter().any(|v| !v.is_finite()) {
        return Some("its numbers must be finite".into());
    }
    let length = seg.length_m();
    if !(length > 0.0 && length <= MAX_ROUTE_M) {
        return Some(format!(
            "its length {length} m must be > 0 and at most {MAX_ROUTE_M} m"
        ));
    }
    let max_curvature = 1.0 / MIN_ARC_RADIUS_M;
    match *seg {
        RouteSegment::Straight { .. } => None,
        RouteSegment::Arc { radius_m, .. } => {
            (!(MIN_ARC_RADIUS_M..=MAX_ARC_RADIUS_M).contains(&radius_m)).then(|| {
                format!("its radius {radius_m} m must be {MIN_ARC_RADIUS_M}–{MAX_ARC_RADIUS_M} m")
            })
        }
        _ => {
            let route = Route::new(RouteSpec {
                segments: vec![seg.clone()],
                intersections_m: vec![],
                lane_width_m: 3.5,
                lanes: 1,
                elevation: Vec::new(),
                median_m: 0.0,
                lane_widths_m: Vec::new(),
                lane_offset: Vec::new(),
            });
            let n = (length / CURVATURE_CHECK_M).ceil() as usize;
            (0..=n)
                .map(|k| (k as f64 * CURVATURE_CHECK_M).min(length))
                .find_map(|s| {
                    let kappa = route.curvature_at(s);
                    let [x, z, h] = route.at(s);
                    let fine = kappa.abs() <= max_curvature
                        && x.is_finite()
                        && z.is_finite()
                        && h.is_finite();
                    let bad = !fine;
                    bad.then(|| {
                        format!(
                            "its curvature at {s:.2} m into it is {kappa:.4} per metre: at most \
                             {max_curvature} (a radius of {MIN_ARC_RADIUS_M} m, the vehicles' \
                             turning circles)"
                        )
                    })
                })
        }
    }
}

/// The length of a route's centreline, metres.
pub(crate) fn length_m(route: &RouteSpec) -> f64 {
    route.segments.iter().map(RouteSegment::length_m).sum()
}
