//! One road of a file as carfollow's route: its reference line's geometries as route
//! segments, laid from carfollow's origin heading +x (the road's station 0 is the route's
//! start), and its lanes. Whatever the subset cannot follow is refused here.

use super::geometry::{geometry_end, segment};
use super::model::{OpenDrive, Poly3Record, Road};
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
    /// The road's `id`.
    pub id: String,
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

/// The road `road_id` of `file` (the file's one road when `None`), as carfollow's route;
/// `check_segment` says what is wrong with a segment carfollow cannot drive (too tight a
/// curve), if anything.
pub fn import(
    file: &OpenDrive,
    road_id: Option<&str>,
    check_segment: impl Fn(&RouteSegment) -> Option<String>,
) -> Result<ImportedRoad, OpenDriveError> {
    let path = &file.path;
    let road = match road_id {
        Some(id) => {
            file.roads
                .iter()
                .find(|r| r.id == id)
                .ok_or_else(|| OpenDriveError::Refused {
                    path: path.clone(),
                    line: 1,
                    element: "<OpenDRIVE>".into(),
                    reason: format!("no road with id {id:?}"),
                })?
        }
        None => file.roads.first().ok_or_else(|| OpenDriveError::Refused {
            path: path.clone(),
            line: 1,
            element: "<OpenDRIVE>".into(),
            reason: "the file holds no road".into(),
        })?,
    };
    if let Some(other) = file.roads.iter().find(|r| r.id != road.id) {
        return Err(other.at.refuse(
            path,
            "a second road is refused: carfollow's route follows one road, and draws no other",
        ));
    }
    refuse_what_the_road_cannot_be(road, path)?;
    let segments = segments(road, path, check_segment)?;
    let layout = super::lanes::lanes(road, path)?;
    let elevation = elevation(road, path)?;
    let lane_offset = lane_offset(road, &segments, &layout, path)?;
    // The road's objects, signals and surface data: scenery, which carfollow places and
    // draws its own of; said, not refused.
    let unapplied = road
        .scenery
        .iter()
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
        id: road.id.clone(),
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

/// The road's `<elevation>` records as `route.elevation`'s `[s, a, b, c, d]`: none when
/// the road is level (no record, or one constant height throughout: flat ground), else
/// every record, checked as `route.elevation` is and refused at its line.
fn elevation(road: &Road, path: &std::path::Path) -> Result<Vec<[f64; 5]>, OpenDriveError> {
    let level = road.elevations.first().map_or(0.0, |r| r.coefficients[0]);
    let constant = road.elevations.iter().all(|r| {
        let [a, b, c, d] = r.coefficients;
        a == level && b == 0.0 && c == 0.0 && d == 0.0
    });
    if constant {
        return Ok(Vec::new());
    }
    let records: Vec<[f64; 5]> = road
        .elevations
        .iter()
        .map(|r| {
            let [a, b, c, d] = r.coefficients;
            [r.s, a, b, c, d]
        })
        .collect();
    match crate::scenario::elevation_problem(&records, road.length) {
        Some((i, problem)) => Err(road.elevations[i].at.refuse(path, problem)),
        None => Ok(records),
    }
}

/// The road's `<laneOffset>` records as `route.lane_offset`'s `[s, a, b, c, d]`: none when
/// every record is 0, else every record, checked on the road its segments and lanes make
/// as `route.lane_offset` is and refused at its line.
fn lane_offset(
    road: &Road,
    segments: &[RouteSegment],
    layout: &super::lanes::Layout,
    path: &std::path::Path,
) -> Result<Vec<[f64; 5]>, OpenDriveError> {
    if road.lane_offsets.iter().all(|r| r.coefficients == [0.0; 4]) {
        return Ok(Vec::new());
    }
    let records: Vec<[f64; 5]> = road
        .lane_offsets
        .iter()
        .map(|r| {
            let [a, b, c, d] = r.coefficients;
            [r.s, a, b, c, d]
        })
        .collect();
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
        Some((i, problem)) => Err(road.lane_offsets[i].at.refuse(path, problem)),
        None => Ok(spec.lane_offset),
    }
}

/// Refuses junctions, links to other roads, left-hand traffic, a road that is not flat
/// across (superelevation).
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
    for link in &road.links {
        // A road that links to itself is a loop: the route drives it once.
        if !(link.element_type == "road" && link.element_id == road.id) {
            return Err(link.at.refuse(
                path,
                "a link to another road or a junction is refused: carfollow's route follows one road",
            ));
        }
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
        if let Some([x, y, hdg]) = end {
            let gap = (g.x - x).hypot(g.y - y);
            let turn = angle_between(g.hdg, hdg);
            if gap > JOIN_POSITION_M || turn > JOIN_HEADING_RAD {
                return Err(g.at.refuse(
                    path,
                    format!(
                        "its geometry starts {gap:.3e} m and {turn:.3e} rad from where the one \
                         before ends: at most {JOIN_POSITION_M} m and {JOIN_HEADING_RAD} rad"
                    ),
                ));
            }
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
