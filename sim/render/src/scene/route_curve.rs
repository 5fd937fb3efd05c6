//! The route's pieces whose curvature varies: the clothoid (OpenDRIVE's `spiral`), the
//! cubic `poly3` and the parametric cubic `paramPoly3`, each evaluated in its own local
//! frame (u forward along the frame's heading, v to its left, as OpenDRIVE's local frame).
//!
//! - A clothoid's heading is θ(s) = κ₀ s + (κ₁ − κ₀) s² / (2L), exact; its position is the
//!   integral of (cos θ, sin θ) by 10-point Gauss–Legendre quadrature from the nearest knot
//!   (knots every [`KNOT_SPACING_M`], themselves integrated the same way), so it holds to
//!   about 1e-12 of its length (the integrand is entire; over 1 m its heading turns at
//!   most a few tenths of a radian, where 10 points are exact to far below that).
//! - `poly3`'s station is arc length: u(s) solves ∫₀ᵘ √(1 + v′²) = s, by Newton's method
//!   from the nearest knot with the same quadrature.
//! - `paramPoly3`'s parameter is the station from the piece's start (`arc_length`) or that
//!   over the length (`normalized`), as OpenDRIVE defines `pRange`: evaluated directly.

use super::route::PRange;

/// Spacing of the knots a varying piece keeps, metres of station: short enough that the
/// quadrature from a knot is exact to rounding, and 50,000 of them on the longest route.
const KNOT_SPACING_M: f64 = 1.0;
/// Newton's iterations at most for `poly3`'s u(s); it converges in three or four.
const MAX_NEWTON: usize = 60;

/// The 10-point Gauss–Legendre nodes on [−1, 1] (positive half) and their weights
/// (Abramowitz and Stegun, table 25.4).
const GL_NODES: [f64; 5] = [
    0.148_874_338_981_631_2,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];
const GL_WEIGHTS: [f64; 5] = [
    0.295_524_224_714_752_9,
    0.269_266_719_309_996_4,
    0.219_086_362_515_982_0,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_1,
];

/// ∫ₐᵇ f by 10-point Gauss–Legendre quadrature, for a function of two values.
fn integrate(a: f64, b: f64, f: impl Fn(f64) -> [f64; 2]) -> [f64; 2] {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let mut sum = [0.0, 0.0];
    for (x, w) in GL_NODES.iter().zip(GL_WEIGHTS) {
        for t in [mid - half * x, mid + half * x] {
            let v = f(t);
            sum[0] += w * v[0];
            sum[1] += w * v[1];
        }
    }
    [sum[0] * half, sum[1] * half]
}

/// A cubic's value, first and second derivative at `t`.
fn cubic(c: &[f64; 4], t: f64) -> [f64; 3] {
    [
        c[0] + t * (c[1] + t * (c[2] + t * c[3])),
        c[1] + t * (2.0 * c[2] + 3.0 * t * c[3]),
        2.0 * c[2] + 6.0 * t * c[3],
    ]
}

/// A piece whose curvature varies, in its local frame.
#[derive(Clone, Debug)]
pub(super) enum Curve {
    /// A clothoid: curvature `k0 + dk·s`; `knots[j]` is `[u, v]` at station `j·KNOT_SPACING_M`.
    Spiral {
        k0: f64,
        dk: f64,
        knots: Vec<[f64; 2]>,
    },
    /// `v = a + b u + c u² + d u³`; `knots[j]` is `[s, u]`.
    Poly3 { v: [f64; 4], knots: Vec<[f64; 2]> },
    /// `u(p)`, `v(p)` cubics, `p = scale · s`.
    ParamPoly3 {
        u: [f64; 4],
        v: [f64; 4],
        scale: f64,
    },
}

impl Curve {
    /// A clothoid of `length_m` from curvature `k0` to `k1`.
    pub(super) fn spiral(length_m: f64, k0: f64, k1: f64) -> Curve {
        let dk = (k1 - k0) / length_m;
        let theta = |s: f64| k0 * s + 0.5 * dk * s * s;
        let n = (length_m / KNOT_SPACING_M).ceil().clamp(1.0, 1e7) as usize;
        let mut knots = Vec::with_capacity(n + 1);
        let mut at = [0.0, 0.0];
        knots.push(at);
        for j in 0..n {
            let (a, b) = (j as f64 * KNOT_SPACING_M, (j + 1) as f64 * KNOT_SPACING_M);
            let d = integrate(a, b, |s| [theta(s).cos(), theta(s).sin()]);
            at = [at[0] + d[0], at[1] + d[1]];
            knots.push(at);
        }
        Curve::Spiral { k0, dk, knots }
    }

    /// A `poly3` of arc length `length_m`.
    pub(super) fn poly3(length_m: f64, v: [f64; 4]) -> Curve {
        let speed = |u: f64| (1.0 + cubic(&v, u)[1].powi(2)).sqrt();
        let mut knots = vec![[0.0, 0.0]];
        let (mut s, mut u) = (0.0, 0.0);
        // Steps of about KNOT_SPACING_M of arc (never more: the step in u shrinks with the
        // slope), until past the end.
        while s < length_m && knots.len() < 10_000_000 {
            let h = KNOT_SPACING_M / speed(u);
            if !(h.is_finite() && h > 0.0) {
                break;
            }
            s += integrate(u, u + h, |t| [speed(t), 0.0])[0];
            u += h;
            knots.push([s, u]);
        }
        Curve::Poly3 { v, knots }
    }

    /// A `paramPoly3` of `length_m`.
    pub(super) fn param_poly3(length_m: f64, u: [f64; 4], v: [f64; 4], p_range: PRange) -> Curve {
        let scale = match p_range {
            PRange::ArcLength => 1.0,
            PRange::Normalized => 1.0 / length_m,
        };
        Curve::ParamPoly3 { u, v, scale }
    }

    /// `[u, v, θ, κ]` at station `s` into the piece: the local position, the tangent's
    /// angle from the frame's heading (radians, positive left) and the curvature (1/m).
    pub(super) fn at(&self, s: f64) -> [f64; 4] {
        match self {
            Curve::Spiral { k0, dk, knots } => {
                let theta = |t: f64| k0 * t + 0.5 * dk * t * t;
                let j = ((s / KNOT_SPACING_M).floor().max(0.0) as usize).min(knots.len() - 1);
                let a = j as f64 * KNOT_SPACING_M;
                let d = integrate(a, s, |t| [theta(t).cos(), theta(t).sin()]);
                [
                    knots[j][0] + d[0],
                    knots[j][1] + d[1],
                    theta(s),
                    k0 + dk * s,
                ]
            }
            Curve::Poly3 { v, knots } => {
                let u = poly3_u(v, knots, s);
                let [y, dy, ddy] = cubic(v, u);
                let q = 1.0 + dy * dy;
                [u, y, dy.atan(), ddy / (q * q.sqrt())]
            }
            Curve::ParamPoly3 { u, v, scale } => {
                let p = s * scale;
                let ([x, dx, ddx], [y, dy, ddy]) = (cubic(u, p), cubic(v, p));
                let q = dx * dx + dy * dy;
                let kappa = if q > 0.0 {
                    (dx * ddy - dy * ddx) / (q * q.sqrt())
                } else {
                    0.0
                };
                [x, y, dy.atan2(dx), kappa]
            }
        }
    }
}

/// `poly3`'s u at arc length `s`: Newton's method on ∫ √(1 + v′²) from the knot before.
fn poly3_u(v: &[f64; 4], knots: &[[f64; 2]], s: f64) -> f64 {
    let speed = |u: f64| (1.0 + cubic(v, u)[1].powi(2)).sqrt();
    let j = knots.partition_point(|k| k[0] <= s).saturating_sub(1);
    let [s0, u0] = knots[j];
    let mut u = u0 + (s - s0) / speed(u0);
    for _ in 0..MAX_NEWTON {
        let err = s0 + integrate(u0, u, |t| [speed(t), 0.0])[0] - s;
        let step = err / speed(u);
        u -= step;
        if !step.is_finite() || step.abs() <= 1e-13 * (1.0 + u.abs()) {
            break;
        }
    }
    u
}
