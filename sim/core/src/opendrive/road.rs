//! A road of a file, or a chain of roads linked end to start ([`super::chain`]), as
//! carfollow's route: the reference lines' geometries as route segments, laid from
//! carfollow's origin heading +x (the first road's station 0 is the route's start), each
//! road's stations following the one before's, and the lanes, the same on every road.
//! Whatever the subset cannot follow is refused here.

use super::chain::{chain, starts, ChainedRoad};
use super::geometry::{geometry_end, segment};
use super::model::{OpenDrive, Place, Poly3Record, Road};
use super::OpenDriveError;
use sim_render::RouteSegment;

/// How far a geometry's start may lie from where the one before ends, metres: a millimetre,
/// far above the rounding of files written with 16 digits, far below anything visible.
pub const JOIN_POSITION_M: f64 = 1e-3;
/// How far a geometry's start heading may turn from the one before's end, radians: 0.1
/// mrad, 1 mm of sideways drift over 10 m of the next piece.
pub const JOIN_HEADING_RAD: f64 = 1e-4;
/// How far the stations may disagree with the lengths, metres (`s` of each geometry
/// against the sum of the lengths before it, and the road's `length`).
const STATION_M: f64 = 1e-3;

/// A road as carfollow drives it.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedRoad {
    /// The (first) road's `id`.
    pub id: String,
    /// The roads the route drives, in order, each with where it starts along the route.
    pub roads: Vec<ChainedRoad>,
    /// The reference line, in carfollow's segments.
    pub segments: Vec<RouteSegment>,
    /// Driving lanes each way.
    pub lanes: u32,
    /// Their width, metres (lane 1's when `lane_widths_m` is given).
    pub lane_width_m: f64,
    /// Each driving lane's width, metres, lane 1 first, when they differ; else empty.
    pub lane_widths_m: Vec<f64>,
    /// The non-driving lanes between the centre and lane 1 on each side together, metres:
    /// `route.median_m`.
    pub median_m: f64,
    /// How many lanes make the median on each side: carfollow's lane k is OpenDRIVE's lane
    /// −(k + this).
    pub inner_lanes: u32,
    /// The elevation profile as `route.elevation`'s records (none when the road is level).
    pub elevation: Vec<[f64; 5]>,
    /// The `<laneOffset>` records as `route.lane_offset`'s (none when every one is 0).
    pub lane_offset: Vec<[f64; 5]>,
    /// What the file holds that carfollow reads past and does not draw, a line each
    /// (`check` and `run` say these as warnings).
    pub unapplied: Vec<String>,
}

/// The road `road_id` of `file` (without one, the file's one road, or the first of its
/// chain of roads), and the roads after it along its chain, as carfollow's route;
/// `check_segment` says what is wrong with a segment carfollow cannot drive (too tight a
/// curve), if anything.
pub fn import(
    file: &OpenDrive,
    road_id: Option<&str>,
    check_segment: impl Fn(&RouteSegment) -> Option<String>,
) -> Result<ImportedRoad, OpenDriveError> {
    let path = &file.path;
    let roads = chain(file, road_id)?;
    let mut segments = Vec::new();
    let mut end: Option<[f64; 3]> = None;
    for road in &roads {
        refuse_what_the_road_cannot_be(road, path)?;
        if let (Some(e), Some(g)) = (end, road.geometries.first()) {
            joins(e, g, path, "its road starts", "the road before")?;
        }
        segments.extend(self::segments(road, path, &check_segment)?);
        end = road.geometries.last().map(geometry_end);
    }
    let layout = super::lanes::lanes(roads[0], path)?;
    for road in &roads[1..] {
        let got = super::lanes::lanes(road, path)?;
        if got != layout {
            return Err(road.at.refuse(
                path,
                format!(
                    "its lanes ({got}) differ from road {}'s ({layout}): carfollow's road keeps \
                     its lanes along its length",
                    roads[0].id
                ),
            ));
        }
    }
    let chained = starts(&roads);
    let elevation = elevation(&roads, &chained, path)?;
    let lane_offset = lane_offset(&roads, &chained, &segments, &layout, path)?;
    // The roads' objects, signals and surface data: scenery, which carfollow places and
    // draws its own of; said, not refused.
    let unapplied = roads
        .iter()
        .flat_map(|r| &r.scenery)
        .map(|item| {
            format!(
                "{}:{}: {}: the road's objects, signals and surface data are not drawn (carfollow places and draws its own scenery)",
                path.display(),
                item.line,
                item.element
            )
        })
        .collect();
    Ok(ImportedRoad {
        id: roads[0].id.clone(),
        roads: chained,
        segments,
        lanes: layout.lanes,
        lane_width_m: layout.lane_width_m,
        lane_widths_m: layout.lane_widths_m,
        median_m: layout.median_m,
        inner_lanes: layout.inner_lanes,
        elevation,
        lane_offset,
        unapplied,
    })
}

/// Refuses geometry `g` unless it starts where the one before ended (`end`: x, y, heading)
/// within [`JOIN_POSITION_M`] and [`JOIN_HEADING_RAD`]; `what` and `before` name the two.
fn joins(
    end: [f64; 3],
    g: &super::model::Geometry,
    path: &std::path::Path,
    what: &str,
    before: &str,
) -> Result<(), OpenDriveError> {
    let [x, y, hdg] = end;
    let gap = (g.x - x).hypot(g.y - y);
    let turn = angle_between(g.hdg, hdg);
    if gap > JOIN_POSITION_M || turn > JOIN_HEADING_RAD {
        return Err(g.at.refuse(
            path,
            format!(
                "{what} {gap:.3e} m and {turn:.3e} rad from where {before} ends: at most \
                 {JOIN_POSITION_M} m and {JOIN_HEADING_RAD} rad"
            ),
        ));
    }
    Ok(())
}

/// The records of each road of a chain (`poly3` of each) as one route's `[s, a, b, c, d]`,
/// each road's stations moved on by where it starts, with the place of each: a road with
/// none is at 0 from its start (OpenDRIVE's default), said by a record of 0 at its start.
fn chained_records<'a>(
    roads: &'a [&Road],
    chained: &[ChainedRoad],
    poly3: impl Fn(&'a Road) -> &'a [Poly3Record],
) -> (Vec<[f64; 5]>, Vec<&'a Place>) {
    let (mut records, mut places) = (Vec::new(), Vec::new());
    for (road, c) in roads.iter().zip(chained) {
        let own = poly3(road);
        if own.is_empty() && roads.len() > 1 {
            records.push([c.start_m, 0.0, 0.0, 0.0, 0.0]);
            places.push(&road.at);
        }
        for r in own {
            let [a, b, cc, d] = r.coefficients;
            records.push([c.start_m + r.s, a, b, cc, d]);
            places.push(&r.at);
        }
    }
    (records, places)
}

/// The roads' `<elevation>` records as `route.elevation`'s `[s, a, b, c, d]`: none when
/// the route is level (no record, or one constant height throughout: flat ground), else
/// every record (each road's moved on by where it starts), checked as `route.elevation` is
/// and refused at its line.
fn elevation(
    roads: &[&Road],
    chained: &[ChainedRoad],
    path: &std::path::Path,
) -> Result<Vec<[f64; 5]>, OpenDriveError> {
    let (records, places) = chained_records(roads, chained, |r| &r.elevations);
    let level = records.first().map_or(0.0, |r| r[1]);
    if records
        .iter()
        .all(|r| r[1] == level && r[2] == 0.0 && r[3] == 0.0 && r[4] == 0.0)
    {
        return Ok(Vec::new());
    }
    let length: f64 = chained.iter().map(|c| c.length_m).sum();
    match crate::scenario::elevation_problem(&records, length) {
        Some((i, problem)) => Err(places[i].refuse(path, problem)),
        None => Ok(records),
    }
}

/// The roads' `<laneOffset>` records as `route.lane_offset`'s `[s, a, b, c, d]`: none when
/// every record is 0, else every record (each road's moved on by where it starts), checked
/// on the road its segments and lanes make as `route.lane_offset` is and refused at its
/// line.
fn lane_offset(
    roads: &[&Road],
    chained: &[ChainedRoad],
    segments: &[RouteSegment],
    layout: &super::lanes::Layout,
    path: &std::path::Path,
) -> Result<Vec<[f64; 5]>, OpenDriveError> {
    let (records, places) = chained_records(roads, chained, |r| &r.lane_offsets);
    if records.iter().all(|r| r[1..] == [0.0; 4]) {
        return Ok(Vec::new());
    }
    let spec = sim_render::RouteSpec {
        segments: segments.to_vec(),
        intersections_m: Vec::new(),
        lane_width_m: layout.lane_width_m,
        lanes: layout.lanes,
        elevation: Vec::new(),
        median_m: layout.median_m,
        lane_widths_m: layout.lane_widths_m.clone(),
        lane_offset: records,
    };
    match crate::scenario::lane_offset_problem(&spec) {
        Some((i, problem)) => Err(places[i].refuse(path, problem)),
        None => Ok(spec.lane_offset),
    }
}

/// Refuses a road in a junction, left-hand traffic, a road that is not flat across
/// (superelevation); its links are the chain's ([`super::chain`]).
fn refuse_what_the_road_cannot_be(
    road: &Road,
    path: &std::path::Path,
) -> Result<(), OpenDriveError> {
    if road.junction != "-1" {
        return Err(road.at.refuse(path, "a road inside a junction is refused"));
    }
    if road.rule != "RHT" {
        return Err(road.at.refuse(
            path,
            "left-hand traffic is refused: carfollow drives on the right",
        ));
    }
    let zero = |r: &Poly3Record| r.coefficients.iter().all(|&c| c == 0.0);
    if let Some(r) = road.superelevations.iter().find(|r| !zero(r)) {
        return Err(r.at.refuse(
            path,
            "superelevation is refused: carfollow's road is flat across",
        ));
    }
    Ok(())
}

/// The reference line as segments, each geometry checked against the one before.
fn segments(
    road: &Road,
    path: &std::path::Path,
    check_segment: impl Fn(&RouteSegment) -> Option<String>,
) -> Result<Vec<RouteSegment>, OpenDriveError> {
    if road.geometries.is_empty() {
        return Err(road.at.refuse(path, "the road has no geometry"));
    }
    let mut out = Vec::with_capacity(road.geometries.len());
    let mut station = 0.0;
    let mut end: Option<[f64; 3]> = None;
    for g in &road.geometries {
        if g.length.is_nan() || g.length <= 0.0 {
            return Err(g.at.refuse(
                path,
                format!("its geometry's length {} must be positive", g.length),
            ));
        }
        if (g.s - station).abs() > STATION_M {
            return Err(g.at.refuse(
                path,
                format!(
                    "its geometry starts at s = {} where the lengths before end at {station}",
                    g.s
                ),
            ));
        }
        if let Some(e) = end {
            joins(e, g, path, "its geometry starts", "the one before")?;
        }
        let seg = segment(g);
        if let Some(problem) = check_segment(&seg) {
            return Err(g.shape_at.refuse(path, problem));
        }
        let e = geometry_end(g);
        if !e.iter().all(|v| v.is_finite()) {
            return Err(g
                .at
                .refuse(path, "the geometry does not end anywhere finite"));
        }
        end = Some(e);
        station += g.length;
        out.push(seg);
    }
    if (road.length - station).abs() > STATION_M {
        return Err(road.at.refuse(
            path,
            format!(
                "its length {} differs from its geometries' {station}",
                road.length
            ),
        ));
    }
    Ok(out)
}

/// The angle between two headings, radians, 0–π.
fn angle_between(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}
