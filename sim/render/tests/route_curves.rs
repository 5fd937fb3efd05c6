//! The route's varying pieces against independent evaluations of the same curves: a
//! clothoid against fourth-order Runge–Kutta integration of dx/ds = cos θ, dy/ds = sin θ,
//! dθ/ds = κ(s); `paramPoly3` against its polynomials rotated by hand; `poly3` against
//! its arc length by composite Simpson's rule and bisection. Positions within 1e-6 m,
//! headings within 1e-8 rad; pieces laid end to end join without a step.

use sim_render::{PRange, Route, RouteSegment, RouteSpec};

/// Position tolerance, metres.
const POS_M: f64 = 1e-6;
/// Heading tolerance, radians.
const HDG_RAD: f64 = 1e-8;

fn route(segments: Vec<RouteSegment>) -> Route {
    Route::new(RouteSpec {
        segments,
        intersections_m: vec![],
        lane_width_m: 3.5,
        lanes: 1,
        elevation: Vec::new(),
        median_m: 0.0,
        lane_widths_m: Vec::new(),
        lane_offset: Vec::new(),
    })
}

/// `[x, y, θ]` in OpenDRIVE's sense (y to the left) from the route's `[x, z, ψ]`.
fn left_handed([x, z, h]: [f64; 3]) -> [f64; 3] {
    [x, -z, h]
}

fn close(what: &str, got: [f64; 3], want: [f64; 3]) {
    let d = (got[0] - want[0]).hypot(got[1] - want[1]);
    assert!(
        d < POS_M,
        "{what}: position off by {d:e} m: {got:?} vs {want:?}"
    );
    let dh = (got[2] - want[2]).abs();
    assert!(
        dh < HDG_RAD,
        "{what}: heading off by {dh:e} rad: {got:?} vs {want:?}"
    );
}

/// The clothoid by RK4 with 1 cm steps (its error is O(h⁴): far below 1e-9 m here).
fn rk4_spiral(k0: f64, k1: f64, length: f64, s_end: f64) -> [f64; 3] {
    let kappa = |s: f64| k0 + (k1 - k0) * s / length;
    let f = |s: f64, y: [f64; 3]| [y[2].cos(), y[2].sin(), kappa(s)];
    let h = 0.01;
    let n = (s_end / h).round() as usize;
    let h = s_end / n as f64;
    let mut y = [0.0, 0.0, 0.0];
    for i in 0..n {
        let s = i as f64 * h;
        let a = f(s, y);
        let b = f(
            s + h / 2.0,
            [
                y[0] + h / 2.0 * a[0],
                y[1] + h / 2.0 * a[1],
                y[2] + h / 2.0 * a[2],
            ],
        );
        let c = f(
            s + h / 2.0,
            [
                y[0] + h / 2.0 * b[0],
                y[1] + h / 2.0 * b[1],
                y[2] + h / 2.0 * b[2],
            ],
        );
        let d = f(s + h, [y[0] + h * c[0], y[1] + h * c[1], y[2] + h * c[2]]);
        for k in 0..3 {
            y[k] += h / 6.0 * (a[k] + 2.0 * b[k] + 2.0 * c[k] + d[k]);
        }
    }
    y
}

#[test]
fn a_clothoid_matches_runge_kutta() {
    for (k0, k1, length) in [(0.0, 0.007, 50.0), (-0.1, 0.05, 120.0), (0.01, -0.01, 33.3)] {
        let r = route(vec![RouteSegment::Spiral {
            length_m: length,
            curvature_start: k0,
            curvature_end: k1,
        }]);
        for s in [0.0, 0.37, 5.0, 17.25, length / 2.0, length - 0.01, length] {
            close(
                &format!("spiral {k0}->{k1} at {s}"),
                left_handed(r.at(s)),
                rk4_spiral(k0, k1, length, s),
            );
            let kappa = k0 + (k1 - k0) * s / length;
            assert!((r.curvature_at(s.min(length - 1e-9)) - kappa).abs() < 1e-9);
        }
    }
}

fn cubic(c: [f64; 4], p: f64) -> f64 {
    c[0] + c[1] * p + c[2] * p * p + c[3] * p * p * p
}

#[test]
fn a_param_poly3_matches_its_polynomials() {
    let u = [0.0, 1.0, -0.0012, 2.1e-6];
    let v = [0.0, 0.0, 0.004, -1.3e-5];
    let length: f64 = 80.0;
    // After a 20 m straight and a left arc, so the piece's frame is turned and moved.
    let before = vec![
        RouteSegment::Straight { length_m: 20.0 },
        RouteSegment::Arc {
            radius_m: 50.0,
            angle_deg: 30.0,
        },
    ];
    for p_range in [PRange::ArcLength, PRange::Normalized] {
        let (u, v) = match p_range {
            PRange::ArcLength => (u, v),
            // The same curve with p over 0–1.
            PRange::Normalized => (
                [
                    u[0],
                    u[1] * length,
                    u[2] * length.powi(2),
                    u[3] * length.powi(3),
                ],
                [
                    v[0],
                    v[1] * length,
                    v[2] * length.powi(2),
                    v[3] * length.powi(3),
                ],
            ),
        };
        let mut segments = before.clone();
        segments.push(RouteSegment::ParamPoly3 {
            length_m: length,
            u,
            v,
            p_range,
        });
        let r = route(segments);
        let start = 20.0 + 50.0 * 30f64.to_radians();
        let [x0, y0, h0] = left_handed(r.at(start));
        for ds in [0.0, 1.0, 12.5, 40.0, 79.9, 80.0] {
            let p = match p_range {
                PRange::ArcLength => ds,
                PRange::Normalized => ds / length,
            };
            let (lu, lv) = (cubic(u, p), cubic(v, p));
            let du = u[1] + 2.0 * u[2] * p + 3.0 * u[3] * p * p;
            let dv = v[1] + 2.0 * v[2] * p + 3.0 * v[3] * p * p;
            let want = [
                x0 + lu * h0.cos() - lv * h0.sin(),
                y0 + lu * h0.sin() + lv * h0.cos(),
                h0 + dv.atan2(du),
            ];
            close(
                &format!("{p_range:?} at {ds}"),
                left_handed(r.at(start + ds)),
                want,
            );
        }
    }
}

#[test]
fn a_poly3_is_laid_by_arc_length() {
    let c = [0.0, 0.05, 0.002, -1.0e-5];
    let length = 60.0;
    let r = route(vec![RouteSegment::Poly3 {
        length_m: length,
        v: c,
    }]);
    let slope = |u: f64| c[1] + 2.0 * c[2] * u + 3.0 * c[3] * u * u;
    let speed = |u: f64| (1.0 + slope(u).powi(2)).sqrt();
    // Arc length to u by composite Simpson with 20,000 intervals.
    let arc = |u: f64| {
        let n = 20_000;
        let h = u / n as f64;
        let mut sum = speed(0.0) + speed(u);
        for i in 1..n {
            sum += speed(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        sum * h / 3.0
    };
    for s in [0.0, 3.0, 25.0, 59.0, 60.0] {
        let (mut lo, mut hi) = (0.0, s + 1.0);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if arc(mid) < s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let u = 0.5 * (lo + hi);
        close(
            &format!("poly3 at {s}"),
            left_handed(r.at(s)),
            [u, cubic(c, u), slope(u).atan()],
        );
    }
}

#[test]
fn pieces_join_without_a_step() {
    let segments = vec![
        RouteSegment::Straight { length_m: 30.0 },
        RouteSegment::Spiral {
            length_m: 40.0,
            curvature_start: 0.0,
            curvature_end: 0.02,
        },
        RouteSegment::Arc {
            radius_m: 50.0,
            angle_deg: 40.0,
        },
        RouteSegment::Spiral {
            length_m: 40.0,
            curvature_start: 0.02,
            curvature_end: -0.01,
        },
        RouteSegment::ParamPoly3 {
            length_m: 50.0,
            u: [0.0, 1.0, 0.0, 0.0],
            v: [0.0, 0.0, -0.005, 0.0],
            p_range: PRange::ArcLength,
        },
        RouteSegment::Poly3 {
            length_m: 30.0,
            v: [0.0, 0.0, 0.003, 0.0],
        },
    ];
    let r = route(segments.clone());
    let mut s = 0.0;
    for seg in &segments[..segments.len() - 1] {
        s += seg.length_m();
        let eps = 1e-7;
        let (a, b) = (r.at(s - eps), r.at(s + eps));
        let d = (a[0] - b[0]).hypot(a[1] - b[1]);
        assert!(d < 3e-7, "a step of {d:e} m at the join at {s} m");
        assert!((a[2] - b[2]).abs() < 1e-6, "a kink at {s} m: {a:?} {b:?}");
    }
    assert!((r.length_m() - s - 30.0).abs() < 1e-9);
}
