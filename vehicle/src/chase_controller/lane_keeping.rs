//! Lane keeping and a cruise speed for the chase controller, as an adaptive cruise control
//! with a lane-keeping assist drives.
//!
//! With [`ChaseControllerConfig::lane_keeping`] the chase steers by pure pursuit along its
//! own lane's centre line ([`ChaseController::set_lane`]) instead of the breadcrumbs: it
//! projects its position onto the lane and aims at the lane's point one look-ahead
//! ([`crate::LookAhead::distance_m`]) further on (the lane's end at most). Without a lane set
//! it steers straight on (curvature 0) and takes every target as in its lane.
//!
//! The tracker's estimates then decide only the speed, and only while the target is in the
//! lane: an estimate whose position lies further than half the lane's width plus
//! [`LANE_MARGIN_M`] from the centre line is out of it, and after [`LEFT_LANE_ARRIVALS`] of
//! those in a row the target has left the lane ([`ControllerEventKind::TargetLeftLane`]): the
//! range filters and the gap keeper forget it, its estimates are no longer fed to them, and
//! the chase drives at `cruise_speed_mps` ([`ChaseMode::Cruising`]) or, without one, brakes
//! to a stop as after a loss. The next `tracking` estimate in the lane makes it follow again
//! (logged as [`ControllerEventKind::Resumed`]; so is the first target in the lane when it
//! starts cruising). The tracker losing a target that was in the lane still stops the chase
//! ([`ChaseMode::Stopping`]): the vehicle may still be there, unseen; with `resume_after_s`
//! the chase, stopped that long, drives on at the cruise speed, as a driver resuming the
//! cruise control does ([`ControllerEventKind::CruiseResumed`]). While cruising, lost
//! and out-of-lane estimates change nothing, and the speed reference moves to the cruise
//! speed at no more than the gap keeper's `max_accel_mps2` and `max_decel_mps2`; near the
//! lane's end it slows to stop [`STOP_SHORT_OF_END_M`] short of it.

use super::{
    max_curvature, ChaseController, ChaseControllerConfig, ChaseMode, CURVATURE_CHORD_M,
    RESUME_MEASUREMENTS,
};
use crate::clock::{Step, PHYSICS_DT_S};
use crate::controller_event::ControllerEventKind;
use crate::error::{check_range, VehicleError};
use crate::lead_estimate::{LeadEstimate, TrackStatus};
use crate::route::{Route, RouteProjection};
use rapier3d::math::{Pose, Vector};

/// How far beyond half the lane's width an estimate may lie and still count as in the lane,
/// m: a car astride the line is still in the lane, and the tracker's lateral noise at 40 m
/// is a few tenths of a metre.
pub const LANE_MARGIN_M: f32 = 0.5;

/// After this many out-of-lane estimates in a row the target has left the lane: three
/// frames, 0.2 s at 15 Hz. One or two can be the lateral noise of a far target or a car
/// brushing the line; a lane change takes seconds, so three cost little.
pub const LEFT_LANE_ARRIVALS: u32 = 3;

/// The arc length searched either side of the last station when projecting onto the lane,
/// m: far more than the chase travels between two updates, short enough that a lane that
/// doubles back is not confused with itself.
const PROJECT_WINDOW_M: f32 = 25.0;

/// How far short of its lane's end a cruising chase stops, m: a car's length, its rear axle
/// (its station) that far back from the end.
pub const STOP_SHORT_OF_END_M: f32 = 5.0;

/// The time the chase's speed takes to follow its reference, allowed for as a reaction
/// time when it slows for its lane's end, s: the speed controller and the drivetrain lag
/// the reference by a few tenths of a second.
const END_REACTION_S: f32 = 0.5;

/// The spacing of the lane's points whose curvature limits the gap, m (they are resampled at
/// the breadcrumbs' chord, `CURVATURE_CHORD_M`).
const CURVATURE_SAMPLE_M: f32 = 1.0;

/// What the controller does with an arriving estimate under lane keeping.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Verdict {
    /// In the lane (or no lane keeping): fed to the range filters, and it may resume
    /// following.
    Follow,
    /// Out of the lane, but the target has not left it yet: fed, but resumes nothing.
    Tolerate,
    /// Not followed: out of the lane, or in it but not `tracking` after it left.
    Ignore,
}

/// The chase's lane.
#[derive(Clone, Debug)]
struct Lane {
    /// The centre line.
    route: Route,
    /// Half the lane's width, m.
    half_width_m: f32,
    /// The chase's arc length along the lane at the last update, m.
    station_m: Option<f32>,
}

impl Lane {
    /// `p` projected onto the lane near `hint_m`, or anywhere along it without a hint.
    fn project(&self, p: Vector, hint_m: Option<f32>) -> RouteProjection {
        match hint_m {
            Some(s) => self.route.project_near(p, s, PROJECT_WINDOW_M),
            None => self.route.project(p),
        }
    }
}

/// The lane keeping's state inside the controller.
#[derive(Clone, Debug)]
pub(super) struct LaneState {
    lane: Option<Lane>,
    /// Out-of-lane estimates in a row.
    out_arrivals: u32,
    /// Whether the target has left the lane (and is not followed).
    target_left: bool,
    /// The target's arc length along the lane at its last in-lane estimate, m.
    target_station_m: Option<f32>,
    /// The speed reference while cruising, m/s.
    cruise_ref_mps: f32,
}

impl LaneState {
    /// No lane yet; a cruise would start from `speed_mps`.
    pub(super) fn new(speed_mps: f32) -> LaneState {
        LaneState {
            lane: None,
            out_arrivals: 0,
            target_left: false,
            target_station_m: None,
            cruise_ref_mps: speed_mps.max(0.0),
        }
    }

    /// One step of `dt_s` of the cruise's speed reference toward `cruise_speed_mps`, within
    /// the gap keeper's acceleration and deceleration limits: the reference and its
    /// acceleration. Near the lane's end the cruise speed gives way to the speed from which
    /// the gap keeper's deceleration, after [`END_REACTION_S`], stops the chase
    /// [`STOP_SHORT_OF_END_M`] short of it: the lane, and the road it is drawn on, end
    /// there (as the lead stops at the road's end).
    pub(super) fn cruise_ref(&mut self, config: &ChaseControllerConfig, dt_s: f32) -> (f32, f32) {
        let g = &config.gap_keeper;
        let mut want = config.cruise_speed_mps.unwrap_or(0.0);
        if let Some(lane) = &self.lane {
            if let Some(s) = lane.station_m {
                let room = (lane.route.length_m() - STOP_SHORT_OF_END_M - s).max(0.0);
                // The speed v with v·t + v²/2a = room: a reaction time's travel, then
                // braking at a.
                let (a, t) = (g.max_decel_mps2, END_REACTION_S);
                want = want.min(a * ((t * t + 2.0 * room / a).sqrt() - t));
            }
        }
        let change =
            (want - self.cruise_ref_mps).clamp(-g.max_decel_mps2 * dt_s, g.max_accel_mps2 * dt_s);
        self.cruise_ref_mps += change;
        (self.cruise_ref_mps, change / dt_s)
    }
}

/// Checks `cruise_speed_mps` (0.5–70 m/s, and only with `lane_keeping`); the mode to start
/// in: cruising when a cruise speed is set, else following.
pub(super) fn validate_and_start(
    config: &ChaseControllerConfig,
) -> Result<ChaseMode, VehicleError> {
    if let Some(resume) = config.resume_after_s {
        check_range("resume_after_s", f64::from(resume), 0.0, 600.0)?;
        if config.cruise_speed_mps.is_none() {
            return Err(VehicleError::InvalidParameter {
                field: "resume_after_s",
                value: f64::from(resume),
                reason: "needs cruise_speed_mps: the speed to drive on at",
                allowed: None,
            });
        }
    }
    let Some(cruise) = config.cruise_speed_mps else {
        return Ok(ChaseMode::Following);
    };
    check_range("cruise_speed_mps", f64::from(cruise), 0.5, 70.0)?;
    if !config.lane_keeping {
        return Err(VehicleError::InvalidParameter {
            field: "cruise_speed_mps",
            value: f64::from(cruise),
            reason: "needs lane_keeping: without a lane nothing steers the chase while no \
                     target is followed",
            allowed: None,
        });
    }
    Ok(ChaseMode::Cruising)
}

impl ChaseController {
    /// Stopped after a loss ([`ChaseMode::Stopped`], since its last
    /// [`ControllerEventKind::Stopped`]) for `resume_after_s` at step `now`: cruises again
    /// from the speed `v`, logged as [`ControllerEventKind::CruiseResumed`].
    pub(super) fn resume_cruise_if_due(&mut self, now: Step, v: f32) {
        let Some(after_s) = self.config.resume_after_s else {
            return;
        };
        let stopped_at = self
            .events
            .iter()
            .rev()
            .find(|e| e.kind == ControllerEventKind::Stopped)
            .map(|e| e.step);
        if !stopped_at.is_some_and(|at| now.since(at) as f32 * PHYSICS_DT_S >= after_s) {
            return;
        }
        self.log(now, ControllerEventKind::CruiseResumed);
        self.mode = ChaseMode::Cruising;
        self.lane.cruise_ref_mps = v.max(0.0);
        self.speed.reset();
    }

    /// Sets the chase's own lane for `lane_keeping`: its centre line `lane` (world x, z; y is
    /// ignored) and half its width, m (negative taken as 0). The chase steers along it, and
    /// a target further than `half_width_m` + [`LANE_MARGIN_M`] from it is out of the lane.
    /// Without a lane, lane keeping steers straight on (curvature 0) and every target
    /// counts as in the lane. Without `lane_keeping` the lane is not used.
    pub fn set_lane(&mut self, lane: Route, half_width_m: f32) {
        self.lane.lane = Some(Lane {
            route: lane,
            half_width_m: half_width_m.max(0.0),
            station_m: None,
        });
        self.lane.target_station_m = None;
    }

    /// The lane point pure pursuit aims at: one look-ahead beyond the chase's station (at
    /// most the lane's end); `None` without a lane. Updates the chase's station.
    pub(super) fn lane_aim(&mut self, pose: &Pose, speed_mps: f32) -> Option<Vector> {
        let lookahead_m = self.config.lookahead.distance_m(speed_mps);
        let lane = self.lane.lane.as_mut()?;
        let s = lane.project(pose.translation, lane.station_m).s_m;
        lane.station_m = Some(s);
        Some(
            lane.route
                .point_at((s + lookahead_m).min(lane.route.length_m())),
        )
    }

    /// The lane's largest curvature from the chase's station to the followed target's (or
    /// the gap keeper's wanted gap ahead when no target is followed), 1/m; 0 without a lane.
    pub(super) fn lane_curvature_ahead(&self, speed_mps: f32) -> f32 {
        let Some(lane) = &self.lane.lane else {
            return 0.0;
        };
        let Some(from) = lane.station_m else {
            return 0.0;
        };
        let to = match (self.mode, self.lane.target_station_m) {
            (ChaseMode::Following, Some(s)) if s > from => s,
            _ => from + self.config.gap_keeper.desired_gap_m(speed_mps),
        }
        .min(lane.route.length_m());
        let n = ((to - from) / CURVATURE_SAMPLE_M).ceil().max(0.0) as usize;
        let points: Vec<Vector> = (0..=n)
            .map(|k| {
                let s = (from + k as f32 * CURVATURE_SAMPLE_M).min(to);
                lane.route.point_at(s)
            })
            .collect();
        max_curvature(&points, CURVATURE_CHORD_M)
    }

    /// Whether the target of an arriving (not lost) estimate, at `target_world_m`, is
    /// followed; the chase was at `chase_at_capture` when its frame was captured. After
    /// [`LEFT_LANE_ARRIVALS`] out-of-lane estimates in a row the target has left the lane:
    /// the filters and the gap keeper are reset and, if it was followed, the event is logged
    /// and the chase cruises or stops from `speed_mps`.
    pub(super) fn judge_target(
        &mut self,
        now: Step,
        estimate: &LeadEstimate,
        chase_at_capture: Vector,
        target_world_m: Vector,
        speed_mps: f32,
    ) -> Verdict {
        if !self.config.lane_keeping {
            return Verdict::Follow;
        }
        let Some(lane) = &self.lane.lane else {
            return Verdict::Follow;
        };
        // Search for the target near the chase's station at capture plus its distance.
        let chase_s = lane.project(chase_at_capture, lane.station_m).s_m;
        let flat = |v: Vector| Vector::new(v.x, 0.0, v.z);
        let hint_m = chase_s + flat(chase_at_capture).distance(flat(target_world_m));
        let at = lane.project(target_world_m, Some(hint_m));
        let in_lane = at.left_offset_m.abs() <= lane.half_width_m + LANE_MARGIN_M;
        let state = &mut self.lane;
        if in_lane {
            state.out_arrivals = 0;
            if state.target_left && estimate.status != TrackStatus::Tracking {
                return Verdict::Ignore;
            }
            state.target_left = false;
            state.target_station_m = Some(at.s_m);
            return Verdict::Follow;
        }
        state.out_arrivals = state.out_arrivals.saturating_add(1);
        if state.target_left {
            return Verdict::Ignore;
        }
        if state.out_arrivals < LEFT_LANE_ARRIVALS {
            return if self.mode == ChaseMode::Following {
                Verdict::Tolerate
            } else {
                Verdict::Ignore
            };
        }
        // It has left the lane.
        state.target_left = true;
        state.target_station_m = None;
        self.range.reset_measuring(RESUME_MEASUREMENTS);
        self.alarm_range.reset_measuring(RESUME_MEASUREMENTS);
        self.gap_keeper.reset(speed_mps);
        self.closing_since = None;
        if self.mode == ChaseMode::Following {
            self.log(
                now,
                ControllerEventKind::TargetLeftLane {
                    offset_m: at.left_offset_m,
                },
            );
            let v = speed_mps.max(0.0);
            if self.config.cruise_speed_mps.is_some() {
                self.mode = ChaseMode::Cruising;
                self.lane.cruise_ref_mps = v;
            } else {
                self.mode = ChaseMode::Stopping;
                self.stop_ref_mps = v;
            }
            self.speed.reset();
        }
        Verdict::Ignore
    }
}

#[cfg(test)]
mod tests;
