//! A gap kept to another vehicle, step by step (see [`crate::KeepSpec`]).

use crate::event_spec::{Keep, KeepSide, KEEP_GAIN_PER_S, KEEP_LAG_S};
use crate::event_spec::{KEEP_REACHED_M, KEEP_REACHED_MPS};
use crate::events::VehicleView;
use crate::PHYSICS_HZ;

/// A kept gap running: the speed and acceleration it asks for.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct KeepState {
    keep: Keep,
    /// The other vehicle's index in the view.
    pub(super) vehicle: usize,
    /// Whether this vehicle is behind the other.
    behind: bool,
    /// The speed asked, m/s, and the acceleration, m/s².
    pub(super) speed_mps: f64,
    pub(super) accel_mps2: f64,
}

impl KeepState {
    /// `keep` to the vehicle `vehicle` of the view, starting from `mine` with `other` where
    /// it is: the side as asked, or (`either`) the side this vehicle is on now.
    pub(super) fn new(
        keep: Keep,
        vehicle: usize,
        mine: &VehicleView,
        other: Option<&VehicleView>,
    ) -> KeepState {
        let behind = match keep.side {
            KeepSide::Behind => true,
            KeepSide::Ahead => false,
            KeepSide::Either => other.is_none_or(|o| mine.station_m <= o.station_m),
        };
        KeepState {
            keep,
            vehicle,
            behind,
            speed_mps: mine.speed_mps.max(0.0),
            accel_mps2: 0.0,
        }
    }

    /// One physics step with the vehicles as they stand: the speed and acceleration asked
    /// move on; returns whether the gap is reached (within [`KEEP_REACHED_M`], the speeds
    /// within [`KEEP_REACHED_MPS`]) and the action ends there (not continuous). Without the
    /// other vehicle in the view, the speed is held.
    pub(super) fn step(&mut self, mine: &VehicleView, other: Option<&VehicleView>) -> bool {
        let Some(other) = other else {
            self.accel_mps2 = 0.0;
            return false;
        };
        let k = &self.keep;
        let (front, back) = if self.behind {
            (other, mine)
        } else {
            (mine, other)
        };
        let gap = if k.axles {
            front.station_m - back.station_m
        } else {
            front.rear_m - back.front_m
        };
        // A time gap is over the speed of the one behind; its error is in metres.
        let want = if k.time {
            k.value * back.speed_mps.max(0.0)
        } else {
            k.value
        };
        let error = gap - want;
        let side = if self.behind { 1.0 } else { -1.0 };
        // Under a jerk limit the acceleration takes `max_accel / jerk` to build: the lag is
        // that long at least, and the gain falls with it so that the loop stays critically
        // damped (`4 · lag · gain = 1`).
        let lag = k
            .max_jerk_mps3
            .map_or(KEEP_LAG_S, |j| KEEP_LAG_S.max(k.max_accel_mps2 / j));
        let gain = KEEP_GAIN_PER_S * KEEP_LAG_S / lag;
        let wanted = (other.speed_mps + side * gain * error).clamp(0.0, k.max_speed_mps);
        let dt = 1.0 / f64::from(PHYSICS_HZ);
        // Nor can the acceleration stop at once: the speed it will have reached when it has
        // ramped to 0 is the one compared with the speed wanted, so that the speed does not
        // overshoot.
        let a = self.accel_mps2;
        let coming = match k.max_jerk_mps3 {
            Some(jerk) => self.speed_mps + a * a.abs() / (2.0 * jerk),
            None => self.speed_mps,
        };
        let mut accel = ((wanted - coming) / lag).clamp(-k.max_decel_mps2, k.max_accel_mps2);
        if let Some(jerk) = k.max_jerk_mps3 {
            accel = accel.clamp(a - jerk * dt, a + jerk * dt);
        }
        self.speed_mps = (self.speed_mps + accel * dt).max(0.0);
        self.accel_mps2 = if self.speed_mps > 0.0 { accel } else { 0.0 };
        // Reached within the same distance whether asked as a gap or as a time gap.
        !k.continuous
            && error.abs() <= KEEP_REACHED_M
            && (mine.speed_mps - other.speed_mps).abs() <= KEEP_REACHED_MPS
    }
}
