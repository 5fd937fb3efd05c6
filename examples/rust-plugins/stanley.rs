//! A controller of our own: Stanley steering on the lead's breadcrumbs, and a constant
//! time-gap law with a PID on the gap for the speed.
//!
//! Each estimate that comes out of the delay line is placed in the world with the chase's
//! own odometry at the estimate's capture (the controller keeps its recent poses), and
//! dropped as a breadcrumb. Steering is Stanley's law at the front axle against the trail:
//! the heading error to the trail plus `atan(k e / (v + v0))` for the cross-track error `e`.
//! The gap wanted is `d0 + h v`; a PID on its error, with the lead's speed estimated from the
//! range's rate, gives a speed to hold, and throttle or brake follows that speed. With no
//! estimate for `STALE_S`, the chase comes to a controlled stop at `STOP_DECEL_MPS2`.

use sim_core::{Command, ControlInput, Controller, PluginError};
use std::collections::VecDeque;
use vehicle::{CameraMount, Pose, Vector};

/// Stanley's cross-track gain, 1/s, and the speed added at low speed, m/s.
const STANLEY_K: f64 = 1.2;
const STANLEY_V0: f64 = 1.0;
/// The steering limit asked for, radians (the actuator limits it to full lock anyway).
const MAX_STEER_RAD: f64 = 0.45;
/// PID on the gap's error (m): a speed correction, (m/s)/m, per m·s and per m/s.
const KP: f64 = 0.35;
const KI: f64 = 0.02;
const KD: f64 = 0.6;
/// Throttle and brake per m/s of speed error.
const THROTTLE_PER_MPS: f64 = 0.25;
const BRAKE_PER_MPS: f64 = 0.3;
/// No estimate for this long: the controlled stop.
const STALE_S: f64 = 0.6;
/// The controlled stop's deceleration, m/s², and the brake that gives it roughly.
const STOP_DECEL_MPS2: f64 = 2.0;
/// Breadcrumbs closer than this to the last are not dropped, metres.
const CRUMB_SPACING_M: f64 = 0.5;

/// Stanley steering and a constant time-gap PID.
pub struct StanleyPid {
    mount: CameraMount,
    wheelbase_m: f64,
    /// The gap wanted at standstill, metres, and the time gap, seconds.
    standstill_m: f64,
    time_gap_s: f64,
    /// The chase's poses by odometry, newest last: (time, pose).
    poses: VecDeque<(f64, Pose)>,
    /// The lead's positions in the world (x, z), oldest first.
    crumbs: VecDeque<[f64; 2]>,
    /// The last estimate's capture time and gap, and the gap's rate (filtered).
    last_gap: Option<(f64, f64)>,
    gap_rate: f64,
    integral: f64,
    /// The speed being held, for the controlled stop.
    stop_from: Option<(f64, f64)>,
}

impl StanleyPid {
    /// A controller for a chase with this camera mount and wheelbase, keeping
    /// `standstill_m + time_gap_s · v`.
    pub fn new(
        mount: CameraMount,
        wheelbase_m: f64,
        standstill_m: f64,
        time_gap_s: f64,
    ) -> StanleyPid {
        StanleyPid {
            mount,
            wheelbase_m,
            standstill_m,
            time_gap_s,
            poses: VecDeque::new(),
            crumbs: VecDeque::new(),
            last_gap: None,
            gap_rate: 0.0,
            integral: 0.0,
            stop_from: None,
        }
    }

    /// The pose nearest to time `t`.
    fn pose_at(&self, t: f64) -> Option<Pose> {
        self.poses
            .iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .map(|(_, p)| *p)
    }

    /// Heading of the pose's forward axis, radians from +x towards +z.
    fn heading(pose: &Pose) -> f64 {
        let f = pose.rotation * Vector::X;
        f64::from(f.z).atan2(f64::from(f.x))
    }

    /// Stanley's steering at the front axle of `pose`, driving at `speed`.
    fn steer(&mut self, pose: &Pose, speed: f64) -> f64 {
        let front = pose.transform_point(Vector::new(self.wheelbase_m as f32, 0.0, 0.0));
        let front = [f64::from(front.x), f64::from(front.z)];
        // Drop the crumbs well behind the front axle, keeping at least two.
        let theta = Self::heading(pose);
        let (c, s) = (theta.cos(), theta.sin());
        while self.crumbs.len() > 2 {
            let p = self.crumbs[1];
            if (p[0] - front[0]) * c + (p[1] - front[1]) * s < -1.0 {
                self.crumbs.pop_front();
            } else {
                break;
            }
        }
        if self.crumbs.len() < 2 {
            return 0.0;
        }
        // The trail's segment nearest the front axle.
        let (mut best, mut best_d) = (0, f64::INFINITY);
        for i in 0..self.crumbs.len() - 1 {
            let (a, b) = (self.crumbs[i], self.crumbs[i + 1]);
            let d = distance_to_segment(front, a, b).0;
            if d < best_d {
                (best, best_d) = (i, d);
            }
        }
        let (a, b) = (self.crumbs[best], self.crumbs[best + 1]);
        let (_, nearest) = distance_to_segment(front, a, b);
        let path_heading = (b[1] - a[1]).atan2(b[0] - a[0]);
        let heading_error = wrap(path_heading - theta);
        // Cross-track error: positive with the trail to the right (+z of the forward axis).
        let right = [-s, c];
        let e = (nearest[0] - front[0]) * right[0] + (nearest[1] - front[1]) * right[1];
        (heading_error + (STANLEY_K * e).atan2(speed.max(0.0) + STANLEY_V0))
            .clamp(-MAX_STEER_RAD, MAX_STEER_RAD)
    }
}

/// The distance from `p` to the segment `a`–`b`, and the nearest point on it.
fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, [f64; 2]) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let u = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + u * dx, a[1] + u * dy];
    (((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt(), q)
}

/// An angle in (−π, π].
fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    a - t * ((a + std::f64::consts::PI) / t).floor()
}

impl Controller for StanleyPid {
    fn name(&self) -> String {
        "Stanley steering and constant time-gap PID (example)".into()
    }

    fn control(&mut self, input: &ControlInput) -> Result<Command, PluginError> {
        let (t, v) = (input.t_s, input.speed_mps);
        self.poses.push_back((t, input.world_from_chase));
        while self.poses.front().is_some_and(|(pt, _)| t - pt > 2.0) {
            self.poses.pop_front();
        }
        if let (true, Some(est), Some(captured), Some(pan)) = (
            input.fresh,
            input.estimate,
            input.captured_t_s,
            input.captured_pan_rad,
        ) {
            if let Some(then) = self.pose_at(captured) {
                let [x, y, z] = [est.lateral_m, est.vertical_m.unwrap_or(0.0), est.range_m];
                let in_vehicle = self
                    .mount
                    .vehicle_from_camera_panned(pan as f32)
                    .transform_point(Vector::new(x as f32, y as f32, z as f32));
                let w = then.transform_point(in_vehicle);
                let crumb = [f64::from(w.x), f64::from(w.z)];
                let far = self.crumbs.back().is_none_or(|l| {
                    ((l[0] - crumb[0]).powi(2) + (l[1] - crumb[1]).powi(2)).sqrt()
                        >= CRUMB_SPACING_M
                });
                if far {
                    self.crumbs.push_back(crumb);
                }
            }
            let gap = est.range_m.hypot(est.lateral_m);
            if let Some((t0, g0)) = self.last_gap {
                if captured > t0 {
                    let rate = (gap - g0) / (captured - t0);
                    self.gap_rate += 0.3 * (rate - self.gap_rate);
                }
            }
            self.last_gap = Some((captured, gap));
        }
        let steering = self.steer(&input.world_from_chase, v);
        // The pan head, where there is one, turns towards the target.
        let pan_rate = input
            .estimate
            .map_or(0.0, |e| 1.5 * e.lateral_m.atan2(e.range_m));

        let fresh_enough = self.last_gap.is_some_and(|(c, _)| t - c <= STALE_S + 0.13);
        let (throttle, brake) = match (fresh_enough, self.last_gap) {
            (true, Some((_, gap))) => {
                self.stop_from = None;
                let wanted = self.standstill_m + self.time_gap_s * v;
                let error = gap - wanted;
                self.integral = (self.integral + error / 120.0).clamp(-20.0, 20.0);
                let lead_speed = (v + self.gap_rate).max(0.0);
                let target =
                    (lead_speed + KP * error + KI * self.integral + KD * self.gap_rate).max(0.0);
                let dv = target - v;
                if dv >= 0.0 {
                    ((THROTTLE_PER_MPS * dv).min(1.0), 0.0)
                } else {
                    (0.0, (BRAKE_PER_MPS * -dv).min(1.0))
                }
            }
            _ => {
                // The controlled stop: follow a speed ramp down at STOP_DECEL_MPS2.
                let (t0, v0) = *self.stop_from.get_or_insert((t, v));
                let target = (v0 - STOP_DECEL_MPS2 * (t - t0)).max(0.0);
                let dv = target - v;
                self.integral = 0.0;
                if dv >= 0.0 || v < 0.1 {
                    (0.0, if v < 0.1 { 0.3 } else { 0.0 })
                } else {
                    (0.0, (BRAKE_PER_MPS * -dv).min(1.0))
                }
            }
        };
        Ok(Command {
            steering_rad: steering,
            throttle,
            brake,
            pan_rate_rad_s: pan_rate,
        })
    }
}
