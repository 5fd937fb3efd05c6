//! The route's centreline: straights, circular arcs, clothoids and cubics laid end to end
//! on the ground, with crossing roads at intersections. Each piece starts where the one
//! before ends, heading along its end's tangent (the varying pieces are in `route_curve`).
//!
//! The route starts at the world origin heading along world +x. Heading ψ is the rotation
//! about world +y (right-handed), so the direction of travel is `(cos ψ, 0, −sin ψ)` and a
//! positive (left) turn increases ψ. "Right" of the direction of travel is `(sin ψ, 0, cos ψ)`,
//! the vehicle frame's +z.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::elevation::{elevation_at, grade_at};
use super::route_curve::Curve;

/// Half the span over which a lane-offset centreline's curvature is taken, metres
/// ([`Route::curvature_at`]).
pub const OFFSET_CURVATURE_STEP_M: f64 = 0.05;

/// One piece of the centreline.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub enum RouteSegment {
    /// A straight of the given length (metres).
    Straight {
        /// Length, metres.
        length_m: f64,
    },
    /// A circular arc: radius (metres) and turn angle (degrees, positive turns left).
    Arc {
        /// Radius of the centreline, metres.
        radius_m: f64,
        /// Turn angle, degrees; positive is a left turn.
        angle_deg: f64,
    },
    /// A clothoid (Euler spiral, OpenDRIVE's `spiral`): curvature linear in length, from
    /// `curvature_start` to `curvature_end` (1/metres, positive turning left).
    Spiral {
        /// Length, metres.
        length_m: f64,
        /// Curvature at the start, 1/metres (positive turns left).
        curvature_start: f64,
        /// Curvature at the end, 1/metres (positive turns left).
        curvature_end: f64,
    },
    /// OpenDRIVE's `poly3`: in the piece's frame (u along the heading it starts with, v to
    /// the left), `v = a + b·u + c·u² + d·u³`, for `length_m` metres of arc length.
    Poly3 {
        /// Arc length, metres.
        length_m: f64,
        /// `[a, b, c, d]`: metres, 1, 1/metres, 1/metres².
        v: [f64; 4],
    },
    /// OpenDRIVE's `paramPoly3`: in the piece's frame, `u = aU + bU·p + cU·p² + dU·p³` and
    /// `v` likewise, `p` running over `p_range` as the station runs over `length_m` metres.
    ParamPoly3 {
        /// The station's length, metres.
        length_m: f64,
        /// `[aU, bU, cU, dU]`.
        u: [f64; 4],
        /// `[aV, bV, cV, dV]`.
        v: [f64; 4],
        /// What `p` runs over.
        p_range: PRange,
    },
}

/// What a [`RouteSegment::ParamPoly3`]'s parameter runs over (OpenDRIVE's `pRange`).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum PRange {
    /// `p` is the station from the piece's start, 0 to its length (`arcLength`).
    ArcLength,
    /// `p` runs from 0 to 1 (`normalized`).
    Normalized,
}

impl RouteSegment {
    /// The piece's length along the centreline, metres (a `paramPoly3`'s station length).
    pub fn length_m(&self) -> f64 {
        match *self {
            RouteSegment::Straight { length_m }
            | RouteSegment::Spiral { length_m, .. }
            | RouteSegment::Poly3 { length_m, .. }
            | RouteSegment::ParamPoly3 { length_m, .. } => length_m,
            RouteSegment::Arc {
                radius_m,
                angle_deg,
            } => radius_m * angle_deg.to_radians().abs(),
        }
    }
}

/// What the scenario says about the route. The route is the road's centre line (its dashed
/// paint); the road has [`RouteSpec::lanes`] lanes each way, ours to the right of it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct RouteSpec {
    /// The centreline's pieces, in driving order.
    pub segments: Vec<RouteSegment>,
    /// Stations (metres along the centreline) where a road crosses at right angles.
    pub intersections_m: Vec<f64>,
    /// Width of one lane, metres.
    pub lane_width_m: f64,
    /// Lanes in each direction, 1–[`RouteSpec::MAX_LANES`] (1 when not given, and then
    /// not written, so a description of one lane each way reads and writes as before).
    /// Lane k (from 1) of our direction is centred [`RouteSpec::lane_centre_m`] to the right
    /// of the centre line: lane 1 beside it (OpenDRIVE's lane −1), lane `lanes` by the
    /// verge. The oncoming side mirrors ours.
    #[serde(
        default = "RouteSpec::one_lane",
        skip_serializing_if = "RouteSpec::is_one_lane"
    )]
    #[schemars(extend("minimum" = 1, "maximum" = 4))]
    pub lanes: u32,
    /// The road's height along its centreline (OpenDRIVE's `<elevation>` records): each
    /// `[s_m, a, b, c, d]` gives, from station `s_m` to the next record's, the height
    /// `a + b·ds + c·ds² + d·ds³` metres, `ds` metres past `s_m`. Empty: the road is level
    /// at y = 0 (and then not written).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub elevation: Vec<[f64; 5]>,
    /// The median: the width of the strip between the centre line and lane 1 on each side
    /// (OpenDRIVE's inner border or median lanes), metres. 0 (and then not written): lane 1
    /// lies beside the centre line, whose dashed paint divides the two directions; wider,
    /// a solid line runs along each of the median's edges instead.
    #[serde(default, skip_serializing_if = "RouteSpec::is_zero")]
    pub median_m: f64,
    /// Each lane's width, metres, lane 1 first (`lanes` of them), when they differ; empty
    /// (and then not written): every lane is `lane_width_m` wide.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lane_widths_m: Vec<f64>,
    /// The lane offset (OpenDRIVE's `<laneOffset>` records): how far the centre line (the
    /// lanes' common edge, where the dashed paint runs) lies to the left of the reference
    /// line that `segments` lay, metres, as `[s_m, a, b, c, d]` records read as
    /// [`RouteSpec::elevation`]'s are. Stations stay the reference line's. Empty: the
    /// centre line is the reference line (and then not written).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lane_offset: Vec<[f64; 5]>,
}

impl RouteSpec {
    /// The most lanes in each direction a road may have.
    pub const MAX_LANES: u32 = 4;

    /// The lateral offset of the centre of lane `lane` (1-based, counted from the centre
    /// line) of our direction, metres to the right of the centre line: the median, the
    /// widths of the lanes inside it, and half its own, `median_m + (lane − 0.5) ·
    /// lane_width_m` when the lanes are of one width. The oncoming side's lane k is at minus
    /// that. The rule the planner's lane and the renderer's paint share.
    pub fn lane_centre_m(&self, lane: u32) -> f64 {
        if self.lane_widths_m.is_empty() {
            return self.median_m + (f64::from(lane) - 0.5) * self.lane_width_m;
        }
        self.lane_inner_edge_m(lane) + 0.5 * self.lane_width_of(lane)
    }

    /// The width of lane `lane` (1-based), metres.
    pub fn lane_width_of(&self, lane: u32) -> f64 {
        match self.lane_widths_m.get(lane.saturating_sub(1) as usize) {
            Some(&w) => w,
            None => self.lane_width_m,
        }
    }

    /// The lateral offset of the edge of lane `lane` nearer the centre line, metres to the
    /// right of it: the median and the lanes inside it (lane `lanes + 1`'s is the outer
    /// edge of the lanes). Where the paint between lanes runs.
    pub fn lane_inner_edge_m(&self, lane: u32) -> f64 {
        if self.lane_widths_m.is_empty() {
            return self.median_m + f64::from(lane.saturating_sub(1)) * self.lane_width_m;
        }
        let inner: f64 = (1..lane).map(|k| self.lane_width_of(k)).sum();
        self.median_m + inner
    }

    /// The width of our direction's lanes together with the median, metres: from the centre
    /// line to the lanes' outer edge (the edge line is 0.1 m beyond).
    pub fn lanes_width_m(&self) -> f64 {
        if self.lane_widths_m.is_empty() {
            return self.median_m + f64::from(self.lanes) * self.lane_width_m;
        }
        self.lane_inner_edge_m(self.lanes + 1)
    }

    fn is_zero(v: &f64) -> bool {
        *v == 0.0
    }

    fn one_lane() -> u32 {
        1
    }

    fn is_one_lane(lanes: &u32) -> bool {
        *lanes == 1
    }
}

/// One piece with its start state resolved.
#[derive(Clone, Debug)]
struct Piece {
    start_m: f64,
    length_m: f64,
    x0: f64,
    z0: f64,
    heading0: f64,
    /// The constant curvature of a straight or arc (0 for a varying piece).
    curvature: f64,
    /// A piece whose curvature varies.
    curve: Option<Curve>,
}

/// The resolved centreline: position and heading at any station.
#[derive(Clone, Debug)]
pub struct Route {
    spec: RouteSpec,
    pieces: Vec<Piece>,
    length_m: f64,
}

impl Route {
    /// Lays the segments end to end from the origin. Lengths and radii must be positive
    /// (checked by [`crate::scene::SceneDescription::validate`]).
    pub fn new(spec: RouteSpec) -> Route {
        let mut pieces = Vec::with_capacity(spec.segments.len());
        let (mut s, mut x, mut z, mut heading) = (0.0, 0.0, 0.0, 0.0);
        for segment in &spec.segments {
            let (length_m, curvature, curve) = match *segment {
                RouteSegment::Straight { length_m } => (length_m, 0.0, None),
                RouteSegment::Arc {
                    radius_m,
                    angle_deg,
                } => (
                    radius_m * angle_deg.to_radians().abs(),
                    angle_deg.signum() / radius_m,
                    None,
                ),
                RouteSegment::Spiral {
                    length_m,
                    curvature_start,
                    curvature_end,
                } => (
                    length_m,
                    0.0,
                    Some(Curve::spiral(length_m, curvature_start, curvature_end)),
                ),
                RouteSegment::Poly3 { length_m, v } => {
                    (length_m, 0.0, Some(Curve::poly3(length_m, v)))
                }
                RouteSegment::ParamPoly3 {
                    length_m,
                    u,
                    v,
                    p_range,
                } => (
                    length_m,
                    0.0,
                    Some(Curve::param_poly3(length_m, u, v, p_range)),
                ),
            };
            let piece = Piece {
                start_m: s,
                length_m,
                x0: x,
                z0: z,
                heading0: heading,
                curvature,
                curve,
            };
            [x, z, heading] = piece.at(length_m);
            s += length_m;
            pieces.push(piece);
        }
        Route {
            spec,
            pieces,
            length_m: s,
        }
    }

    /// The specification this route was built from.
    pub fn spec(&self) -> &RouteSpec {
        &self.spec
    }

    /// Total length of the centreline, metres.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    /// `[x, z, heading]` of the centreline at station `s_m` (metres, clamped to the route;
    /// past either end the route continues straight): the reference line's, moved left by
    /// the lane offset ([`RouteSpec::lane_offset`]) along its normal, with the heading of
    /// the line so moved.
    pub fn at(&self, s_m: f64) -> [f64; 3] {
        let offsets = &self.spec.lane_offset;
        if offsets.is_empty() {
            return self.reference_at(s_m);
        }
        let s = s_m.clamp(0.0, self.length_m);
        let [x, z, h] = self.reference_at(s);
        let o = elevation_at(offsets, s);
        let slope = grade_at(offsets, s);
        // The moved line C = R + o·left: C' = (1 − κ·o)·T + o'·left, so it turns left of
        // the reference's heading by atan2(o', 1 − κ·o).
        let k = self.reference_curvature_at(s);
        let (sin, cos) = h.sin_cos();
        let heading = h + slope.atan2(1.0 - k * o);
        let extra = s_m - s;
        [
            x - o * sin + extra * heading.cos(),
            z - o * cos - extra * heading.sin(),
            heading,
        ]
    }

    /// `[x, z, heading]` of the reference line at station `s_m` (the centreline without the
    /// lane offset).
    pub fn reference_at(&self, s_m: f64) -> [f64; 3] {
        let Some(first) = self.pieces.first() else {
            return [s_m, 0.0, 0.0];
        };
        if s_m < 0.0 {
            let [x, z, h] = first.at(0.0);
            return [x + s_m * h.cos(), z - s_m * h.sin(), h];
        }
        let index = self
            .pieces
            .partition_point(|p| p.start_m <= s_m)
            .saturating_sub(1);
        let piece = &self.pieces[index];
        let local = s_m - piece.start_m;
        if local > piece.length_m {
            let [x, z, h] = piece.at(piece.length_m);
            let extra = local - piece.length_m;
            return [x + extra * h.cos(), z - extra * h.sin(), h];
        }
        piece.at(local)
    }

    /// The ground pose (vehicle frame: x forward, y up, z right; origin on the ground) at
    /// station `s_m`, offset `lateral_m` to the right of the centreline.
    pub fn pose_at(&self, s_m: f64, lateral_m: f64) -> Isometry3<f64> {
        let [x, z, heading] = self.at(s_m);
        let right = [heading.sin(), heading.cos()];
        Isometry3::from_parts(
            Translation3::new(x + lateral_m * right[0], 0.0, z + lateral_m * right[1]),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), heading),
        )
    }

    /// The point (world x, z) at station `s_m`, `lateral_m` to the right of the centreline.
    pub fn point(&self, s_m: f64, lateral_m: f64) -> [f64; 2] {
        let [x, z, heading] = self.at(s_m);
        [x + lateral_m * heading.sin(), z + lateral_m * heading.cos()]
    }

    /// Curvature (1/metres, positive turning left) of the centreline at station `s_m`; 0
    /// past the ends. With a lane offset, the turn of its heading over the arc length
    /// between [`OFFSET_CURVATURE_STEP_M`] either side.
    pub fn curvature_at(&self, s_m: f64) -> f64 {
        if s_m < 0.0 || s_m > self.length_m {
            return 0.0;
        }
        if self.spec.lane_offset.is_empty() {
            return self.reference_curvature_at(s_m);
        }
        let (a, b) = (
            (s_m - OFFSET_CURVATURE_STEP_M).max(0.0),
            (s_m + OFFSET_CURVATURE_STEP_M).min(self.length_m),
        );
        let ([xa, za, ha], [xb, zb, hb]) = (self.at(a), self.at(b));
        let arc = (xb - xa).hypot(zb - za);
        if arc <= 0.0 {
            return self.reference_curvature_at(s_m);
        }
        let turn = (hb - ha + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        turn / arc
    }

    /// Curvature of the reference line (1/metres, positive turning left) at station `s_m`;
    /// 0 past the ends.
    pub fn reference_curvature_at(&self, s_m: f64) -> f64 {
        if s_m < 0.0 || s_m > self.length_m {
            return 0.0;
        }
        let index = self
            .pieces
            .partition_point(|p| p.start_m <= s_m)
            .saturating_sub(1);
        self.pieces.get(index).map_or(0.0, |p| match &p.curve {
            None => p.curvature,
            Some(curve) => curve.at((s_m - p.start_m).min(p.length_m))[3],
        })
    }

    /// Whether a curve point is within `margin_m` of an intersection's station.
    pub fn near_intersection(&self, s_m: f64, margin_m: f64) -> bool {
        self.spec
            .intersections_m
            .iter()
            .any(|&c| (s_m - c).abs() < margin_m)
    }
}

impl Piece {
    /// `[x, z, heading]` at `local` metres into the piece (closed form for arcs).
    fn at(&self, local: f64) -> [f64; 3] {
        let h0 = self.heading0;
        if let Some(curve) = &self.curve {
            // The local frame: u along the start's heading, v to its left.
            let [u, v, theta, _] = curve.at(local);
            let (sin, cos) = h0.sin_cos();
            return [
                self.x0 + u * cos - v * sin,
                self.z0 - u * sin - v * cos,
                h0 + theta,
            ];
        }
        if self.curvature == 0.0 {
            return [self.x0 + local * h0.cos(), self.z0 - local * h0.sin(), h0];
        }
        let k = self.curvature;
        let h = h0 + k * local;
        [
            self.x0 + (h.sin() - h0.sin()) / k,
            self.z0 + (h.cos() - h0.cos()) / k,
            h,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_circle_left_ends_where_geometry_says() {
        let route = Route::new(RouteSpec {
            segments: vec![RouteSegment::Arc {
                radius_m: 10.0,
                angle_deg: 90.0,
            }],
            intersections_m: vec![],
            lane_width_m: 3.5,
            lanes: 1,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset: Vec::new(),
        });
        // Heading +x, turning left (towards −z): a quarter circle ends at (10, −10) heading −z.
        let [x, z, h] = route.at(route.length_m());
        assert!(
            (x - 10.0).abs() < 1e-9 && (z + 10.0).abs() < 1e-9,
            "{x} {z}"
        );
        assert!((h - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Right of travel is +z at the start.
        let p = route.point(0.0, 2.0);
        assert!((p[1] - 2.0).abs() < 1e-12);
    }
}

#[cfg(test)]
mod lane_tests {
    use super::*;

    #[test]
    fn a_lane_offset_moves_the_centre_line_left_of_the_reference_line() {
        let spec = |lane_offset: Vec<[f64; 5]>| RouteSpec {
            segments: vec![
                RouteSegment::Straight { length_m: 100.0 },
                RouteSegment::Arc {
                    radius_m: 50.0,
                    angle_deg: 90.0,
                },
            ],
            intersections_m: vec![],
            lane_width_m: 3.5,
            lanes: 1,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset,
        };
        let plain = Route::new(spec(Vec::new()));
        // 2 m to the left throughout, then rising by 0.1 m a metre from station 150.
        let moved = Route::new(spec(vec![
            [0.0, 2.0, 0.0, 0.0, 0.0],
            [150.0, 2.0, 0.1, 0.0, 0.0],
        ]));
        for s in [0.0, 50.0, 120.0] {
            let [x, z, h] = plain.at(s);
            let [mx, mz, mh] = moved.at(s);
            // Left of travel is −z at heading 0.
            assert!((mx - (x - 2.0 * h.sin())).abs() < 1e-12, "{s}");
            assert!((mz - (z - 2.0 * h.cos())).abs() < 1e-12, "{s}");
            assert!((mh - h).abs() < 1e-12, "{s}");
            assert_eq!(moved.reference_at(s), plain.at(s));
        }
        // Inside the left curve the centre line is the tighter arc: radius 48 m.
        assert!((moved.curvature_at(120.0) - 1.0 / 48.0).abs() < 1e-6);
        // Moving left at 0.1 m a metre, 3 m inside the curve, it heads left of the
        // reference by atan(0.1 / (1 − 3 / 50)).
        let [_, _, h] = plain.at(160.0);
        let o = 2.0 + 0.1 * 10.0;
        let want = h + 0.1f64.atan2(1.0 - o / 50.0);
        assert!((moved.at(160.0)[2] - want).abs() < 1e-12);
        // Past the ends it goes on straight along its own heading.
        let [ex, ez, eh] = moved.at(moved.length_m());
        let [px, pz, ph] = moved.at(moved.length_m() + 5.0);
        assert!(
            (px - (ex + 5.0 * eh.cos())).abs() < 1e-12
                && (pz - (ez - 5.0 * eh.sin())).abs() < 1e-12
        );
        assert_eq!(ph, eh);
    }

    #[test]
    fn lane_centres_count_from_the_centre_line() {
        let spec = RouteSpec {
            segments: vec![RouteSegment::Straight { length_m: 10.0 }],
            intersections_m: vec![],
            lane_width_m: 3.5,
            lanes: 3,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset: Vec::new(),
        };
        assert_eq!(spec.lane_centre_m(1), 1.75);
        assert_eq!(spec.lane_centre_m(2), 5.25);
        assert_eq!(spec.lane_centre_m(3), 8.75);
        assert_eq!(spec.lanes_width_m(), 10.5);
    }

    #[test]
    fn a_median_and_lanes_of_their_own_widths_move_the_centres() {
        let spec = RouteSpec {
            segments: vec![RouteSegment::Straight { length_m: 10.0 }],
            intersections_m: vec![],
            lane_width_m: 3.65,
            lanes: 3,
            elevation: Vec::new(),
            median_m: 2.6,
            lane_widths_m: vec![3.65, 3.5, 3.9],
            lane_offset: Vec::new(),
        };
        let close = |a: f64, b: f64| assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        close(spec.lane_centre_m(1), 2.6 + 1.825);
        close(spec.lane_centre_m(2), 2.6 + 3.65 + 1.75);
        close(spec.lane_centre_m(3), 2.6 + 3.65 + 3.5 + 1.95);
        close(spec.lane_inner_edge_m(1), 2.6);
        close(spec.lane_inner_edge_m(3), 2.6 + 7.15);
        close(spec.lanes_width_m(), 2.6 + 11.05);
        close(spec.lane_width_of(3), 3.9);
    }
}
