//! A route: the road centreline as a polyline on the ground, with arc length.
//!
//! Points are world-frame positions; only x and z are used (the route lies on the ground).
//! Headings are yaw angles about the world's +y: heading ψ points along (cos ψ, 0, −sin ψ),
//! so a positive turn is to the left.

use crate::error::VehicleError;
use rapier3d::math::Vector;

/// Points closer than this are merged, m.
const MIN_SPACING_M: f32 = 1e-3;
/// Arcs are sampled at this spacing, m (the lead's pure pursuit interpolates between).
const ARC_SAMPLE_M: f32 = 0.5;
/// Half-window of arc length over which curvature is estimated, m.
const CURVATURE_HALF_WINDOW_M: f32 = 1.5;

/// The direction of heading `heading_rad` on the ground.
pub fn heading_direction(heading_rad: f32) -> Vector {
    Vector::new(heading_rad.cos(), 0.0, -heading_rad.sin())
}

/// The heading of a ground direction (y ignored).
pub fn direction_heading(direction: Vector) -> f32 {
    (-direction.z).atan2(direction.x)
}

/// A polyline on the ground with cumulative arc length.
#[derive(Clone, Debug, PartialEq)]
pub struct Route {
    points: Vec<Vector>,
    arc_m: Vec<f32>,
    /// Each segment's unit tangent and its heading, computed once: the drivers ask for
    /// them at every physics step, many times over for the lead's preview of the turns.
    tangents: Vec<Vector>,
    headings: Vec<f32>,
}

/// Where a point projects onto a route.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RouteProjection {
    /// Arc length of the closest route point, m.
    pub s_m: f32,
    /// Signed lateral offset of the point from the route, m (positive to the left).
    pub left_offset_m: f32,
}

impl Route {
    /// A route through `points` (y is ignored and set to 0). Repeated points are merged.
    pub fn new(points: Vec<Vector>) -> Result<Route, VehicleError> {
        let mut kept: Vec<Vector> = Vec::with_capacity(points.len());
        for p in points {
            let p = Vector::new(p.x, 0.0, p.z);
            if !p.is_finite() {
                return Err(VehicleError::InvalidParameter {
                    field: "route point",
                    value: f64::NAN,
                    reason: "not finite",
                    allowed: None,
                });
            }
            if kept.last().is_none_or(|q| q.distance(p) > MIN_SPACING_M) {
                kept.push(p);
            }
        }
        if kept.len() < 2 {
            return Err(VehicleError::RouteTooShort { points: kept.len() });
        }
        let mut arc_m = Vec::with_capacity(kept.len());
        let mut s = 0.0;
        arc_m.push(0.0);
        for w in kept.windows(2) {
            s += w[0].distance(w[1]);
            arc_m.push(s);
        }
        let tangents: Vec<Vector> = kept.windows(2).map(|w| (w[1] - w[0]).normalize()).collect();
        let headings = tangents.iter().map(|&t| direction_heading(t)).collect();
        Ok(Route {
            points: kept,
            arc_m,
            tangents,
            headings,
        })
    }

    /// The route's points.
    pub fn points(&self) -> &[Vector] {
        &self.points
    }

    /// Total length, m.
    pub fn length_m(&self) -> f32 {
        *self.arc_m.last().expect("a route has at least two points")
    }

    fn segment_at(&self, s_m: f32) -> usize {
        self.segment_of_count(self.points_up_to(s_m))
    }

    /// How many of the route's points lie at or before arc length `s_m`.
    fn points_up_to(&self, s_m: f32) -> usize {
        self.arc_m.partition_point(|&a| a <= s_m)
    }

    /// The point at arc length `s_m`, extrapolated along the end segments beyond the ends.
    pub fn point_at(&self, s_m: f32) -> Vector {
        let i = self.segment_at(s_m);
        let (a, b) = (self.points[i], self.points[i + 1]);
        let len = self.arc_m[i + 1] - self.arc_m[i];
        a + (b - a) * ((s_m - self.arc_m[i]) / len)
    }

    /// The unit tangent at arc length `s_m`.
    pub fn tangent_at(&self, s_m: f32) -> Vector {
        self.tangents[self.segment_at(s_m)]
    }

    /// The unit normal to the left of the tangent at `s_m`.
    pub fn left_at(&self, s_m: f32) -> Vector {
        let t = self.tangent_at(s_m);
        Vector::new(t.z, 0.0, -t.x)
    }

    /// Signed curvature at `s_m`, 1/m (positive turning left), from the heading change over
    /// a few metres.
    pub fn curvature_at(&self, s_m: f32) -> f32 {
        let (a, b) = self.curvature_window(s_m);
        self.curvature_between(a, self.segment_at(a), b, self.segment_at(b))
    }

    /// [`Route::curvature_at`] for arc lengths asked in an order that never decreases (a
    /// preview of the road ahead), finding the segments by walking on from the last ones
    /// instead of searching: the same values.
    pub fn curvature_walk(&self) -> CurvatureWalk<'_> {
        CurvatureWalk {
            route: self,
            up_to: None,
        }
    }

    /// The window `curvature_at(s_m)` measures the heading change over.
    fn curvature_window(&self, s_m: f32) -> (f32, f32) {
        (
            (s_m - CURVATURE_HALF_WINDOW_M).max(0.0),
            (s_m + CURVATURE_HALF_WINDOW_M).min(self.length_m()),
        )
    }

    /// The segment holding arc length `s_m` given `up_to`, how many points lie at or before
    /// it along the route: what [`Route::segment_at`]'s search finds.
    fn segment_of_count(&self, up_to: usize) -> usize {
        up_to.clamp(1, self.points.len() - 1) - 1
    }

    /// The heading change from arc length `a` (in segment `ia`) to `b` (in `ib`) over the
    /// distance between them (0 over a window too short to measure).
    fn curvature_between(&self, a: f32, ia: usize, b: f32, ib: usize) -> f32 {
        if b - a < 1e-3 {
            return 0.0;
        }
        let ha = self.headings[ia];
        let hb = self.headings[ib];
        let mut d = hb - ha;
        while d > std::f32::consts::PI {
            d -= std::f32::consts::TAU;
        }
        while d < -std::f32::consts::PI {
            d += std::f32::consts::TAU;
        }
        d / (b - a)
    }

    /// Projects `p` onto the route, searching only arc lengths within `window_m` of
    /// `s_hint_m` (so a route that doubles back is not confused with itself).
    pub fn project_near(&self, p: Vector, s_hint_m: f32, window_m: f32) -> RouteProjection {
        let p = Vector::new(p.x, 0.0, p.z);
        let first = self.segment_at(s_hint_m - window_m);
        let last = self.segment_at(s_hint_m + window_m);
        let mut best = (f32::INFINITY, 0.0, 0.0);
        for i in first..=last {
            let (a, b) = (self.points[i], self.points[i + 1]);
            let ab = b - a;
            let len2 = ab.length_squared();
            let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
            let q = a + ab * t;
            let d2 = p.distance_squared(q);
            if d2 < best.0 {
                let left = Vector::new(ab.z, 0.0, -ab.x).normalize();
                let s = self.arc_m[i] + t * len2.sqrt();
                best = (d2, s, (p - q).dot(left));
            }
        }
        RouteProjection {
            s_m: best.1,
            left_offset_m: best.2,
        }
    }

    /// Projects `p` onto the whole route.
    pub fn project(&self, p: Vector) -> RouteProjection {
        self.project_near(p, 0.0, self.length_m() + 1.0)
    }
}

/// Builds a route from straights and circular arcs, turtle fashion.
#[derive(Clone, Debug)]
pub struct RouteBuilder {
    points: Vec<Vector>,
    heading_rad: f32,
}

impl RouteBuilder {
    /// Starts at `start` (y ignored) heading `heading_rad`.
    pub fn new(start: Vector, heading_rad: f32) -> RouteBuilder {
        RouteBuilder {
            points: vec![Vector::new(start.x, 0.0, start.z)],
            heading_rad,
        }
    }

    fn last(&self) -> Vector {
        *self.points.last().expect("builder starts with a point")
    }

    /// Goes straight on for `length_m`.
    pub fn straight(mut self, length_m: f32) -> RouteBuilder {
        let p = self.last() + heading_direction(self.heading_rad) * length_m;
        self.points.push(p);
        self
    }

    /// Turns through `angle_rad` (positive left) on a circle of `radius_m`.
    pub fn arc(mut self, radius_m: f32, angle_rad: f32) -> RouteBuilder {
        let start = self.last();
        let h0 = self.heading_rad;
        let sign = angle_rad.signum();
        // The centre lies to the left for a left turn.
        let left = heading_direction(h0 + sign * std::f32::consts::FRAC_PI_2);
        let centre = start + left * radius_m;
        let n = ((radius_m * angle_rad.abs()) / ARC_SAMPLE_M)
            .ceil()
            .max(1.0) as usize;
        for k in 1..=n {
            let h = h0 + angle_rad * k as f32 / n as f32;
            let radial = heading_direction(h - sign * std::f32::consts::FRAC_PI_2);
            self.points.push(centre + radial * radius_m);
        }
        self.heading_rad = h0 + angle_rad;
        self
    }

    /// The finished route.
    pub fn build(self) -> Result<Route, VehicleError> {
        Route::new(self.points)
    }
}

/// [`Route::curvature_at`] along arc lengths that never decrease (see
/// [`Route::curvature_walk`]).
pub struct CurvatureWalk<'a> {
    route: &'a Route,
    /// How many of the route's points lie at or before the window's start, and its end, of
    /// the last arc length asked; searched for at the first.
    up_to: Option<(usize, usize)>,
}

impl CurvatureWalk<'_> {
    /// The route's curvature at `s_m`, no less than the last arc length asked: exactly
    /// [`Route::curvature_at`]`(s_m)`.
    pub fn at(&mut self, s_m: f32) -> f32 {
        let route = self.route;
        let (a, b) = route.curvature_window(s_m);
        // The window's ends never move back, so neither do the counts: after the first
        // search, a few steps on each time.
        let walk = |mut up_to: usize, at: f32| {
            while up_to < route.arc_m.len() && route.arc_m[up_to] <= at {
                up_to += 1;
            }
            up_to
        };
        let (up_to_a, up_to_b) = match self.up_to {
            None => (route.points_up_to(a), route.points_up_to(b)),
            Some((up_to_a, up_to_b)) => (walk(up_to_a, a), walk(up_to_b, b)),
        };
        self.up_to = Some((up_to_a, up_to_b));
        route.curvature_between(
            a,
            route.segment_of_count(up_to_a),
            b,
            route.segment_of_count(up_to_b),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The walk gives `curvature_at`'s values to the bit, from before the start to past the
    /// end of a route of turns both ways and straights, in steps of several sizes.
    #[test]
    fn the_curvature_walk_gives_curvature_at() {
        let r = RouteBuilder::new(Vector::new(3.0, 0.0, -2.0), 0.4)
            .straight(12.0)
            .arc(15.0, 1.2)
            .arc(-9.0, 2.0)
            .straight(0.7)
            .arc(30.0, -0.5)
            .straight(20.0)
            .build()
            .unwrap();
        for step in [0.01, 0.25, 1.0, 1.7, 4.0] {
            let mut walk = r.curvature_walk();
            let mut s = -3.0f32;
            while s < r.length_m() + 3.0 {
                assert_eq!(walk.at(s).to_bits(), r.curvature_at(s).to_bits(), "s {s}");
                s += step;
            }
        }
        // Windows that start or end exactly on a point of the route, where the segment
        // changes.
        let mut exact: Vec<f32> = r
            .arc_m
            .iter()
            .flat_map(|&v| [v + CURVATURE_HALF_WINDOW_M, v - CURVATURE_HALF_WINDOW_M])
            .filter(|&s| {
                r.arc_m.contains(&(s - CURVATURE_HALF_WINDOW_M))
                    || r.arc_m.contains(&(s + CURVATURE_HALF_WINDOW_M))
            })
            .collect();
        exact.sort_by(f32::total_cmp);
        assert!(exact.len() > 20, "{}", exact.len());
        let mut walk = r.curvature_walk();
        for &s in &exact {
            assert_eq!(walk.at(s).to_bits(), r.curvature_at(s).to_bits(), "s {s}");
        }
        // Asked twice at one arc length: the same.
        let mut walk = r.curvature_walk();
        assert_eq!(walk.at(20.0).to_bits(), walk.at(20.0).to_bits());
    }

    #[test]
    fn arc_has_the_right_length_and_curvature() {
        let r = RouteBuilder::new(Vector::ZERO, 0.0)
            .straight(10.0)
            .arc(20.0, std::f32::consts::FRAC_PI_2)
            .straight(10.0)
            .build()
            .unwrap();
        let expected = 20.0 + 20.0 * std::f32::consts::FRAC_PI_2;
        assert!((r.length_m() - expected).abs() < 0.05, "{}", r.length_m());
        let k = r.curvature_at(10.0 + 15.0);
        assert!((k - 0.05).abs() < 0.002, "{k}");
        // A left turn from +x ends heading -z.
        let end = r.tangent_at(r.length_m());
        assert!((end - Vector::new(0.0, 0.0, -1.0)).length() < 1e-3);
    }

    #[test]
    fn tangents_and_curvature_agree_with_their_plain_definitions() {
        let r = RouteBuilder::new(Vector::new(3.0, 0.0, -7.0), 0.4)
            .straight(12.0)
            .arc(15.0, 1.2)
            .arc(-9.0, 2.0)
            .straight(0.7)
            .arc(30.0, -0.5)
            .build()
            .unwrap();
        // Each segment's tangent and heading from its two points, as computed at every call.
        let plain_tangent = |s: f32| {
            let i = r.segment_at(s);
            (r.points[i + 1] - r.points[i]).normalize()
        };
        let plain_curvature = |s: f32| {
            let a = (s - CURVATURE_HALF_WINDOW_M).max(0.0);
            let b = (s + CURVATURE_HALF_WINDOW_M).min(r.length_m());
            if b - a < 1e-3 {
                return 0.0;
            }
            let mut d = direction_heading(plain_tangent(b)) - direction_heading(plain_tangent(a));
            while d > std::f32::consts::PI {
                d -= std::f32::consts::TAU;
            }
            while d < -std::f32::consts::PI {
                d += std::f32::consts::TAU;
            }
            d / (b - a)
        };
        let mut s = -5.0;
        while s < r.length_m() + 5.0 {
            assert_eq!(r.tangent_at(s), plain_tangent(s), "tangent at {s}");
            assert_eq!(
                r.curvature_at(s).to_bits(),
                plain_curvature(s).to_bits(),
                "curvature at {s}"
            );
            s += 0.0173;
        }
    }

    #[test]
    fn projection_gives_signed_offset() {
        let r = RouteBuilder::new(Vector::ZERO, 0.0)
            .straight(10.0)
            .build()
            .unwrap();
        let p = r.project(Vector::new(4.0, 0.0, -1.0));
        assert!((p.s_m - 4.0).abs() < 1e-5);
        assert!((p.left_offset_m - 1.0).abs() < 1e-5);
    }
}
