//! A route written as an OpenDRIVE 1.7 road: its centreline's segments as the reference
//! line's geometries (a straight a `line`, an arc an `arc`, a clothoid a `spiral`, the
//! cubics `poly3` and `paramPoly3`), laid from the origin heading east, and its lanes each
//! way as driving lanes of its width. Read back ([`super::import`]), the road gives the
//! very segments written, bit for bit: an arc's curvature and length are chosen among the
//! doubles nearest `1/R` and `R·θ` so that carfollow's reading of them returns `R` and `θ`.

use super::geometry::segment;
use super::model::{Geometry, GeometryKind, Place};
use crate::openscenario::export::xml_out::{a, n, XmlOut};
use sim_render::{PRange, RouteSegment, RouteSpec};

/// How many doubles either side of the first guess are tried for an arc's curvature and
/// length: the guesses are within a few units in the last place of the exact values.
const ULP_SEARCH: i64 = 64;

/// The id the written road has.
pub const ROAD_ID: &str = "1";

/// The route `route` as the text of an OpenDRIVE file named `name`, and whether carfollow
/// reads it back as `route`'s very segments: an arc whose radius and angle no pair of
/// doubles reproduces (the degrees of some products `length·curvature` are not doubles any
/// product rounds to) is written to within a unit in the last place.
pub fn write_road(route: &RouteSpec, name: &str) -> (String, bool) {
    let mut exact = true;
    let mut geometries = Vec::with_capacity(route.segments.len());
    let (mut s, mut pose) = (0.0, [0.0, 0.0, 0.0]);
    for seg in &route.segments {
        let (kind, length) = kind_of(seg);
        let g = Geometry {
            at: place(),
            shape_at: place(),
            s,
            x: pose[0],
            y: pose[1],
            hdg: pose[2],
            length,
            kind,
        };
        exact &= segment(&g) == *seg;
        pose = super::geometry_end(&g);
        pose[2] = pose[2].rem_euclid(std::f64::consts::TAU);
        s += length;
        geometries.push(g);
    }
    let mut x = XmlOut::new();
    x.open("OpenDRIVE", &[]);
    x.empty(
        "header",
        &[
            a("revMajor", 1),
            a("revMinor", 7),
            a("name", name),
            a("version", "1.00"),
            a("date", "1970-01-01T00:00:00"),
            a("vendor", "carfollow"),
        ],
    );
    x.open(
        "road",
        &[
            a("name", name),
            n("length", s),
            a("id", ROAD_ID),
            a("junction", "-1"),
            a("rule", "RHT"),
        ],
    );
    x.empty("type", &[n("s", 0.0), a("type", "rural")]);
    x.open("planView", &[]);
    for g in &geometries {
        geometry(&mut x, g);
    }
    x.close();
    // A level road is one record of height 0, as before profiles were carried.
    x.open("elevationProfile", &[]);
    if route.elevation.is_empty() {
        x.empty("elevation", &poly_attributes(0.0, [0.0; 4]));
    }
    for &[s, a_, b, c, d] in &route.elevation {
        x.empty("elevation", &poly_attributes(s, [a_, b, c, d]));
    }
    x.close();
    x.empty("lateralProfile", &[]);
    lanes(&mut x, route);
    x.close();
    (x.finish(), exact)
}

fn place() -> Place {
    Place {
        line: 0,
        element: String::new(),
    }
}

fn poly_attributes(s: f64, [a_, b, c, d]: [f64; 4]) -> Vec<(&'static str, String)> {
    vec![n("s", s), n("a", a_), n("b", b), n("c", c), n("d", d)]
}

/// A segment's geometry kind and length (an arc's the nearest when none is exact).
fn kind_of(seg: &RouteSegment) -> (GeometryKind, f64) {
    match *seg {
        RouteSegment::Straight { length_m } => (GeometryKind::Line, length_m),
        RouteSegment::Arc {
            radius_m,
            angle_deg,
        } => {
            let (k, length) = exact_arc(radius_m, angle_deg).unwrap_or_else(|| {
                let k = angle_deg.signum() / radius_m;
                (k, angle_deg.to_radians() / k)
            });
            (GeometryKind::Arc(k), length)
        }
        RouteSegment::Spiral {
            length_m,
            curvature_start,
            curvature_end,
        } => (
            GeometryKind::Spiral(curvature_start, curvature_end),
            length_m,
        ),
        RouteSegment::Poly3 { length_m, v } => (GeometryKind::Poly3(v), length_m),
        RouteSegment::ParamPoly3 {
            length_m,
            u,
            v,
            p_range,
        } => (
            GeometryKind::ParamPoly3 {
                u,
                v,
                normalized: p_range == PRange::Normalized,
            },
            length_m,
        ),
    }
}

/// The double `k` steps of one unit in the last place from `x` (same sign).
fn ulps(x: f64, k: i64) -> f64 {
    f64::from_bits((x.to_bits() as i64 + k) as u64)
}

/// `(curvature, length)` of an OpenDRIVE arc that carfollow reads back as an arc of radius
/// `radius_m` turning `angle_deg` (see `geometry::segment`: radius `1/|k|`, angle
/// `(length·k)` in degrees).
fn exact_arc(radius_m: f64, angle_deg: f64) -> Option<(f64, f64)> {
    let sign = angle_deg.signum();
    let k0 = sign / radius_m;
    let k = (0..=ULP_SEARCH)
        .flat_map(|i| [i, -i])
        .map(|i| ulps(k0, i))
        .find(|k| 1.0 / k.abs() == radius_m)?;
    let l0 = angle_deg.to_radians() / k;
    (0..=ULP_SEARCH)
        .flat_map(|i| [i, -i])
        .map(|i| ulps(l0, i))
        .find(|l| *l > 0.0 && (l * k).to_degrees() == angle_deg)
        .map(|l| (k, l))
}

fn geometry(x: &mut XmlOut, g: &Geometry) {
    x.open(
        "geometry",
        &[
            n("s", g.s),
            n("x", g.x),
            n("y", g.y),
            n("hdg", g.hdg),
            n("length", g.length),
        ],
    );
    match g.kind {
        GeometryKind::Line => x.empty("line", &[]),
        GeometryKind::Arc(k) => x.empty("arc", &[n("curvature", k)]),
        GeometryKind::Spiral(k0, k1) => x.empty("spiral", &[n("curvStart", k0), n("curvEnd", k1)]),
        GeometryKind::Poly3([pa, pb, pc, pd]) => {
            x.empty("poly3", &[n("a", pa), n("b", pb), n("c", pc), n("d", pd)])
        }
        GeometryKind::ParamPoly3 { u, v, normalized } => x.empty(
            "paramPoly3",
            &[
                n("aU", u[0]),
                n("bU", u[1]),
                n("cU", u[2]),
                n("dU", u[3]),
                n("aV", v[0]),
                n("bV", v[1]),
                n("cV", v[2]),
                n("dV", v[3]),
                a(
                    "pRange",
                    if normalized {
                        "normalized"
                    } else {
                        "arcLength"
                    },
                ),
            ],
        ),
    }
    x.close();
}

/// The lanes inside the driving lanes on each side of `route`'s road as written: one
/// `border` lane of the median, when there is one. Carfollow's lane k is OpenDRIVE's lane
/// −(k + this).
pub fn inner_lanes(route: &RouteSpec) -> i64 {
    i64::from(route.median_m != 0.0)
}

/// The lane offset's records (one of 0 without one), then one lane section: `lanes`
/// driving lanes each way of `lane_width_m` (or each of its `lane_widths_m`), beyond a `border` lane of `median_m` each way when the road has a
/// median, ids counting out from the centre lane 0; the centre line solid (none with a
/// median, whose edges are solid instead), lanes running the same way divided by broken
/// lines, the verges solid.
fn lanes(x: &mut XmlOut, route: &RouteSpec) {
    x.open("lanes", &[]);
    // No offset is one record of 0, as before offsets were carried.
    if route.lane_offset.is_empty() {
        x.empty("laneOffset", &poly_attributes(0.0, [0.0; 4]));
    }
    for &[s, a, b, c, d] in &route.lane_offset {
        x.empty("laneOffset", &poly_attributes(s, [a, b, c, d]));
    }
    x.open("laneSection", &[n("s", 0.0)]);
    let count = route.lanes as i32;
    let inner = inner_lanes(route) as i32;
    // The lane `id` (its sign the side): its type, width and the mark along its outer edge.
    let layout = |id: i32| -> (&str, f64, &str) {
        let k = id.abs() - inner;
        if k == 0 {
            return ("border", route.median_m, "solid");
        }
        let mark = if k == count { "solid" } else { "broken" };
        ("driving", route.lane_width_of(k as u32), mark)
    };
    let lane = |x: &mut XmlOut, id: i32| {
        let (kind, width, mark) = layout(id);
        x.open("lane", &[a("id", id), a("type", kind), a("level", "false")]);
        x.empty(
            "width",
            &[
                n("sOffset", 0.0),
                n("a", width),
                n("b", 0.0),
                n("c", 0.0),
                n("d", 0.0),
            ],
        );
        x.empty(
            "roadMark",
            &[
                n("sOffset", 0.0),
                a("type", mark),
                a("weight", "standard"),
                a("color", "standard"),
                n("width", 0.12),
            ],
        );
        x.close();
    };
    x.open("left", &[]);
    for id in (1..=count + inner).rev() {
        lane(x, id);
    }
    x.close();
    x.open("center", &[]);
    x.open(
        "lane",
        &[a("id", 0), a("type", "none"), a("level", "false")],
    );
    let centre_mark = if inner == 1 { "none" } else { "solid" };
    x.empty(
        "roadMark",
        &[
            n("sOffset", 0.0),
            a("type", centre_mark),
            a("weight", "standard"),
            a("color", "standard"),
            n("width", 0.12),
        ],
    );
    x.close();
    x.close();
    x.open("right", &[]);
    for id in 1..=count + inner {
        lane(x, -id);
    }
    x.close();
    x.close();
    x.close();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arcs_read_back_exactly() {
        for (r, deg) in [(50.0, 90.0), (120.0, -45.0), (8.0, 360.0), (9999.0, -0.3)] {
            let (k, l) = exact_arc(r, deg).expect("an exact arc");
            assert_eq!(1.0 / k.abs(), r);
            assert_eq!((l * k).to_degrees(), deg);
        }
    }

    #[test]
    fn a_route_reads_back_as_its_segments() {
        let route = RouteSpec {
            segments: vec![
                RouteSegment::Straight { length_m: 100.0 },
                RouteSegment::Spiral {
                    length_m: 30.0,
                    curvature_start: 0.0,
                    curvature_end: 0.02,
                },
                RouteSegment::Arc {
                    radius_m: 50.0,
                    angle_deg: 90.0,
                },
                RouteSegment::Poly3 {
                    length_m: 40.0,
                    v: [0.0, 0.0, 0.001, -1e-5],
                },
            ],
            intersections_m: vec![],
            lane_width_m: 3.25,
            lanes: 2,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset: Vec::new(),
        };
        let (text, exact) = write_road(&route, "t");
        assert!(exact);
        let file = super::super::parse(&text, std::path::Path::new("t.xodr")).unwrap();
        let road = super::super::import(&file, None, |_| None).unwrap();
        assert_eq!(road.segments, route.segments);
        assert_eq!((road.lanes, road.lane_width_m), (2, 3.25));
        assert!(road.elevation.is_empty());
        assert_eq!((road.median_m, road.lane_widths_m.len()), (0.0, 0));
        // A median and lanes of their own widths are written and read back exactly.
        let mut divided = route.clone();
        (divided.median_m, divided.lane_widths_m) = (2.6, vec![3.65, 3.5]);
        divided.lane_width_m = 3.65;
        let (text, _) = write_road(&divided, "t");
        let file = super::super::parse(&text, std::path::Path::new("t.xodr")).unwrap();
        let road = super::super::import(&file, None, |_| None).unwrap();
        assert_eq!(road.lanes, 2);
        assert_eq!(road.median_m, 2.6);
        assert_eq!(road.lane_widths_m, vec![3.65, 3.5]);
        assert_eq!(road.lane_width_m, 3.65);
        // A profile is written record for record and read back bit for bit.
        let mut hilly = route.clone();
        hilly.elevation = vec![
            [0.0, 0.0, 0.0, 1.0 / 3000.0, 0.0],
            [60.0, 1.2, 0.04, -1e-4 / 3.0, 1e-7],
        ];
        let (text, _) = write_road(&hilly, "t");
        let file = super::super::parse(&text, std::path::Path::new("t.xodr")).unwrap();
        let road = super::super::import(&file, None, |_| None).unwrap();
        assert_eq!(road.elevation, hilly.elevation);
        assert!(road.lane_offset.is_empty());
        // So is a lane offset.
        let mut shifted = route.clone();
        shifted.lane_offset = vec![
            [0.0, 0.0, 0.0, 0.0, 0.0],
            [20.0, 0.0, 0.0, 0.0075, -0.00025],
            [40.0, 1.0, 0.0, 0.0, 0.0],
        ];
        let (text, _) = write_road(&shifted, "t");
        let file = super::super::parse(&text, std::path::Path::new("t.xodr")).unwrap();
        let road = super::super::import(&file, None, |_| None).unwrap();
        assert_eq!(road.lane_offset, shifted.lane_offset);
        // 60° is no product of two doubles in degrees: said, and written to an ulp.
        let mut near = route.clone();
        near.segments[2] = RouteSegment::Arc {
            radius_m: 60.0,
            angle_deg: -60.0,
        };
        let (text, exact) = write_road(&near, "t");
        assert!(!exact);
        let file = super::super::parse(&text, std::path::Path::new("t.xodr")).unwrap();
        let road = super::super::import(&file, None, |_| None).unwrap();
        let RouteSegment::Arc {
            radius_m,
            angle_deg,
        } = road.segments[2]
        else {
            panic!("{:?}", road.segments[2]);
        };
        assert!((radius_m - 60.0).abs() < 1e-12 && (angle_deg + 60.0).abs() < 1e-12);
    }
}
