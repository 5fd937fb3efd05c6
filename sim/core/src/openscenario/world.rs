//! `WorldPosition`: a point of the file's own frame (x east, y north, heading
//! counter-clockwise from +x) put on the road, as its station along the reference line and
//! its offset across it.

use sim_render::{Route, RouteSegment, RouteSpec};

/// How far apart the reference line is sampled before the nearest point is refined, m:
/// shorter than any curve carfollow drives bends back on itself (its tightest arc's radius
/// is tens of metres), so the nearest sample is on the nearest stretch.
const SAMPLE_M: f64 = 0.5;
/// How closely the nearest point's station is refined, m.
const REFINE_M: f64 = 1e-9;

/// The road's reference line in the file's frame.
#[derive(Clone, Debug)]
pub struct ReferenceLine {
    /// Where the first geometry starts: `[x, y, hdg]`.
    origin: [f64; 3],
    /// The line as carfollow lays it (from its origin, heading +x).
    route: Route,
}

/// A point of the file's frame on the road.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnRoad {
    /// Station along the reference line, m.
    pub s_m: f64,
    /// Offset to the left of the reference line, m (OpenDRIVE's t).
    pub t_m: f64,
    /// The reference line's heading there, in the file's frame, radians.
    pub heading_rad: f64,
}

impl ReferenceLine {
    /// The reference line of `segments`, its first geometry starting at `origin`
    /// (`[x, y, hdg]` in the file's frame).
    pub fn new(origin: [f64; 3], segments: Vec<RouteSegment>) -> ReferenceLine {
        let route = Route::new(RouteSpec {
            segments,
            intersections_m: Vec::new(),
            lane_width_m: 3.5,
            lanes: 1,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset: Vec::new(),
        });
        ReferenceLine { origin, route }
    }

    /// `(u, v)`, the point `(x, y)` of the file's frame in carfollow's laying of the line
    /// (u forward from its start, v to the left).
    fn local(&self, x: f64, y: f64) -> [f64; 2] {
        let [x0, y0, h0] = self.origin;
        let (sin, cos) = h0.sin_cos();
        let (dx, dy) = (x - x0, y - y0);
        [dx * cos + dy * sin, -dx * sin + dy * cos]
    }

    /// The squared distance from `(u, v)` to the line's point at station `s`.
    fn distance2(&self, [u, v]: [f64; 2], s: f64) -> f64 {
        let [x, z, _] = self.route.at(s);
        (u - x).powi(2) + (v + z).powi(2)
    }

    /// The point `(x, y)` of the file's frame on the road: the nearest point of the
    /// reference line, `None` when that is one of its ends (the point lies before its start
    /// or past its end).
    pub fn project(&self, x: f64, y: f64) -> Option<OnRoad> {
        let p = self.local(x, y);
        let length = self.route.length_m();
        let samples = (length / SAMPLE_M).ceil().max(1.0) as usize;
        let station = |k: usize| length * k as f64 / samples as f64;
        let nearest = (0..=samples)
            .min_by(|&a, &b| {
                self.distance2(p, station(a))
                    .total_cmp(&self.distance2(p, station(b)))
            })
            .unwrap_or(0);
        // Golden-section search between the neighbouring samples.
        let (mut lo, mut hi) = (
            station(nearest.saturating_sub(1)),
            station((nearest + 1).min(samples)),
        );
        let ratio = 0.5 * (5f64.sqrt() - 1.0);
        while hi - lo > REFINE_M {
            let a = hi - ratio * (hi - lo);
            let b = lo + ratio * (hi - lo);
            if self.distance2(p, a) <= self.distance2(p, b) {
                hi = b;
            } else {
                lo = a;
            }
        }
        // The search leaves the station as exact as the flat minimum of the distance lets
        // it (about 1e-7 m); a few steps along the line's tangent to where the point lies
        // square across it make it exact.
        let along_at = |s: f64| {
            let [x_s, z_s, h] = self.route.at(s);
            (p[0] - x_s) * h.cos() + (p[1] + z_s) * h.sin()
        };
        let mut s_m = 0.5 * (lo + hi);
        for _ in 0..3 {
            s_m = (s_m + along_at(s_m)).clamp(0.0, length);
        }
        // At an end, the point is beyond it unless it lies square across the line there.
        let [x_s, z_s, h] = self.route.at(s_m);
        let along = along_at(s_m);
        if (s_m <= REFINE_M || s_m >= length - REFINE_M) && along.abs() > 1e-6 {
            return None;
        }
        let t_m = -(p[0] - x_s) * h.sin() + (p[1] + z_s) * h.cos();
        Some(OnRoad {
            s_m,
            t_m,
            heading_rad: h + self.origin[2],
        })
    }

    /// The reference line's heading at station `s_m`, in the file's frame, radians.
    pub fn heading_at(&self, s_m: f64) -> f64 {
        self.route.at(s_m)[2] + self.origin[2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line from (100, 50) heading 30°, 100 m, then a left arc of radius 50 m through 90°.
    fn line() -> ReferenceLine {
        ReferenceLine::new(
            [100.0, 50.0, 30f64.to_radians()],
            vec![
                RouteSegment::Straight { length_m: 100.0 },
                RouteSegment::Arc {
                    radius_m: 50.0,
                    angle_deg: 90.0,
                },
            ],
        )
    }

    #[test]
    fn points_beside_the_line_come_back_as_their_station_and_offset() {
        let line = line();
        let h0 = 30f64.to_radians();
        for (s, t) in [
            (0.0, -1.75),
            (10.0, 2.0),
            (99.0, -5.25),
            (140.0, -1.75),
            (175.0, 3.0),
        ] {
            // The point by the standard's own geometry: along the heading, then across it.
            let (x, y, h) = if s <= 100.0 {
                let (x, y) = (100.0 + s * h0.cos(), 50.0 + s * h0.sin());
                (x - t * h0.sin(), y + t * h0.cos(), h0)
            } else {
                // On the arc: its centre 50 m to the left of the straight's end.
                let (ex, ey) = (100.0 + 100.0 * h0.cos(), 50.0 + 100.0 * h0.sin());
                let (cx, cy) = (ex - 50.0 * h0.sin(), ey + 50.0 * h0.cos());
                let turned = h0 + (s - 100.0) / 50.0;
                let r = 50.0 - t;
                (cx + r * turned.sin(), cy - r * turned.cos(), turned)
            };
            let on = line.project(x, y).expect("on the road");
            assert!((on.s_m - s).abs() < 1e-6, "s {s}: {on:?}");
            assert!((on.t_m - t).abs() < 1e-6, "t {t}: {on:?}");
            assert!((on.heading_rad - h).abs() < 1e-9, "h at {s}: {on:?}");
        }
    }

    #[test]
    fn points_before_the_start_or_past_the_end_are_off_the_road() {
        let line = ReferenceLine::new(
            [0.0, 0.0, 0.0],
            vec![RouteSegment::Straight { length_m: 100.0 }],
        );
        assert!(line.project(-1.0, 0.0).is_none());
        assert!(line.project(101.0, -2.0).is_none());
        let on = line.project(50.0, -3.0).unwrap();
        assert!(
            (on.s_m - 50.0).abs() < 1e-6 && (on.t_m + 3.0).abs() < 1e-12,
            "{on:?}"
        );
        assert!(line.project(100.0, 2.0).is_some());
        assert!(line.project(0.0, 2.0).is_some());
    }
}
