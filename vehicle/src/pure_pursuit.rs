//! Pure pursuit: steer along the circle through the rear axle that reaches a look-ahead
//! point on the path (Coulter 1992).
//!
//! In the vehicle frame (x forward, z right) a point at (x, z) lies on the circle through the
//! origin tangent to x with curvature κ = −2z / (x² + z²) (positive turning left). A bicycle
//! model with wheelbase L follows that circle with road-wheel angle δ = atan(L κ).

use rapier3d::math::{Pose, Vector};
use serde::{Deserialize, Serialize};

/// A speed-dependent look-ahead distance: `clamp(base_m + gain_s · speed, min_m, max_m)`.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LookAhead {
    /// Look-ahead at standstill, m.
    pub base_m: f32,
    /// Extra look-ahead per m/s of speed, s.
    pub gain_s: f32,
    /// Shortest look-ahead, m.
    pub min_m: f32,
    /// Longest look-ahead, m.
    pub max_m: f32,
}

impl Default for LookAhead {
    /// 3 m + 0.5 s × speed, within 4–12 m: at 10 m/s, 8 m (about 2.5 wheelbases, smooth
    /// but cutting corners by little on 20 m radius turns).
    fn default() -> Self {
        LookAhead {
            base_m: 3.0,
            gain_s: 0.5,
            min_m: 4.0,
            max_m: 12.0,
        }
    }
}

impl LookAhead {
    /// The look-ahead distance at `speed_mps`, m.
    pub fn distance_m(&self, speed_mps: f32) -> f32 {
        (self.base_m + self.gain_s * speed_mps.abs()).clamp(self.min_m, self.max_m)
    }
}

/// Curvature (1/m, positive left) of the arc from the vehicle-frame origin, tangent to x,
/// through `target_in_vehicle` (y ignored). Zero for a target at the origin.
pub fn curvature_to(target_in_vehicle: Vector) -> f32 {
    let d2 = target_in_vehicle.x * target_in_vehicle.x + target_in_vehicle.z * target_in_vehicle.z;
    if d2 < 1e-6 {
        0.0
    } else {
        -2.0 * target_in_vehicle.z / d2
    }
}

/// Road-wheel angle (rad, positive left) of a bicycle model of `wheelbase_m` on a circle of
/// `curvature` (1/m).
pub fn steer_for_curvature(curvature: f32, wheelbase_m: f32) -> f32 {
    (wheelbase_m * curvature).atan()
}

/// The point at distance `lookahead_m` from `from` (in the ground plane) along `path`,
/// searching forward from the path's start: the first crossing of the look-ahead circle by
/// a segment that leaves it. If the whole path is inside the circle, its last point; if the
/// path starts outside, its first point. `None` for an empty path.
pub fn lookahead_point(path: &[Vector], from: Vector, lookahead_m: f32) -> Option<Vector> {
    let flat = |v: Vector| Vector::new(v.x, 0.0, v.z);
    let c = flat(from);
    let first = flat(*path.first()?);
    if first.distance(c) >= lookahead_m {
        return Some(*path.first()?);
    }
    for w in path.windows(2) {
        let (a, b) = (flat(w[0]), flat(w[1]));
        if b.distance(c) < lookahead_m {
            continue;
        }
        // Solve |a + t (b − a) − c| = r for the t in [0, 1] where the segment leaves.
        let d = b - a;
        let f = a - c;
        let qa = d.dot(d);
        let qb = 2.0 * f.dot(d);
        let qc = f.dot(f) - lookahead_m * lookahead_m;
        let disc = (qb * qb - 4.0 * qa * qc).max(0.0);
        let t = ((-qb + disc.sqrt()) / (2.0 * qa)).clamp(0.0, 1.0);
        return Some(w[0] + (w[1] - w[0]) * t);
    }
    path.last().copied()
}

/// Pure-pursuit steering toward a world-frame point: the curvature for the vehicle at
/// `world_from_vehicle`.
pub fn curvature_toward(world_from_vehicle: &Pose, target_in_world: Vector) -> f32 {
    curvature_to(world_from_vehicle.inverse_transform_point(target_in_world))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_on_circle_gives_its_curvature() {
        // Vehicle at the origin heading +x on a left circle of radius 20 (centre at z = -20).
        let r = 20.0f32;
        for angle in [0.1f32, 0.3, 0.6] {
            let target = Vector::new(r * angle.sin(), 0.0, -(r - r * angle.cos()));
            let k = curvature_to(target);
            assert!((k - 1.0 / r).abs() < 1e-5, "{k}");
        }
    }

    #[test]
    fn lookahead_point_is_at_the_distance() {
        let path: Vec<Vector> = (0..20).map(|i| Vector::new(i as f32, 0.0, 1.0)).collect();
        let p = lookahead_point(&path, Vector::ZERO, 5.0).unwrap();
        assert!((p.length() - 5.0).abs() < 1e-4, "{p}");
        assert!(p.x > 0.0);
    }
}
