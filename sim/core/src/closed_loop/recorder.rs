//! The recorder's row of each frame: the truth against the estimate.

use super::capture::{xz, Captured};
use super::contrast::Faintness;
use super::drive::Driven;
use super::tracking::Tracked;
use super::traffic_truth::{LeadTarget, Seen, TrafficTruth};
use crate::driven_path::DrivenPath;
use crate::plugin::{Estimate, EstimateStatus};
use crate::record::{FrameRecord, LossCause, TrackerStatus};
use sim_render::{target_occluded, Frame, GroundTruth, Scene};
use std::sync::Arc;

/// Whether `estimate` is wrong by the loss tolerance against `truth`, or missing: off by
/// more than a quarter of the target's width in the image (`width_px`) or by more than a
/// quarter of its scale; for an estimate without an image location, the same in metres
/// (a quarter of the target's width `width_m` beside it, a quarter of its range).
pub(super) fn wrong(
    estimate: Option<&Estimate>,
    truth: &GroundTruth,
    width_px: f64,
    width_m: f64,
) -> bool {
    let Some(e) = estimate else {
        return true;
    };
    // Written as "not within", so that a centre that does not project (the target behind
    // the camera) or a non-finite estimate is wrong.
    match (e.cx, e.cy, e.scale) {
        (Some(cx), Some(cy), Some(scale)) => {
            !((cx - truth.c_x).hypot(cy - truth.c_y) <= 0.25 * width_px
                && (scale / truth.scale - 1.0).abs() <= 0.25)
        }
        _ => {
            let [tx, ty, tz] = truth.target_cam_m;
            let dy = e.vertical_m.map_or(0.0, |y| y - ty);
            !((e.lateral_m - tx).hypot(dy) <= 0.25 * width_m
                && (e.range_m / tz - 1.0).abs() <= 0.25)
        }
    }
}

/// The recorder: the only part of the loop that sees the truth, which it holds against the
/// estimate, frame by frame.
pub(super) struct Recorder {
    /// The renderer's scene, for whether scenery hides the target.
    pub(super) scene: Arc<Scene>,
    /// The target's width in the image at the nominal range, pixels.
    pub(super) target_width_px: f64,
    /// The target's width, metres.
    pub(super) target_width_m: f64,
    /// Whether the lead's target is too faint for the paper's threshold.
    pub(super) faint: Faintness,
    /// The lead's driven path, for the chase's lateral deviation (without a lead, the
    /// chase's lane, whole).
    pub(super) lead_path: DrivenPath,
    pub(super) chase_distance_m: f64,
    pub(super) last_chase_xz: [f64; 2],
    /// The judgement in traffic, when the scenario has traffic.
    pub(super) traffic: Option<TrafficTruth>,
    /// Whether the tracker has held the target (in traffic, the vehicle in the chase's
    /// path) yet: from the start when placed on it, else from the first frame its estimate
    /// lies on it. Before, a frame without the target is [`LossCause::NotAcquired`].
    pub(super) acquired: bool,
}

impl Recorder {
    /// Step 6: the record of frame `frame_index`: truth against estimate, at its capture time.
    pub(super) fn record(
        &mut self,
        frame_index: u64,
        captured: &Captured,
        frame: &Frame,
        tracked: &Tracked,
        driven: Driven,
    ) -> FrameRecord {
        let Driven {
            controls,
            collision,
            chase_mode,
            desired_gap_m,
            traffic_log,
        } = driven;
        let (chase_state, lead_state) = (&captured.chase, &captured.lead);
        let truth = frame.truth;
        let estimate = tracked.estimate.as_ref();
        let width_px = truth.scale * self.target_width_px;
        // Lost: no estimate, or one off by the tolerance, wherever the target is (issue 37:
        // a target partly out of the image but tracked within the tolerance is not lost).
        let lost_truth = wrong(estimate, &truth, width_px, self.target_width_m);
        let world_from_camera = captured.world_from_camera;
        let status = estimate.map_or(TrackerStatus::Coasting, |e| match e.status {
            EstimateStatus::Tracking => TrackerStatus::Tracking,
            EstimateStatus::Coasting => TrackerStatus::Coasting,
            EstimateStatus::Lost => TrackerStatus::Lost,
        });
        // Whether the target is too faint in the pixels the tracker read: asked, as whether
        // it is hidden, only where it decides a loss's cause or a false alarm.
        let faint = || self.faint.too_faint(&frame.image, tracked.read, &truth);
        // Whether scenery hides the target: asked only where it decides something, a loss's
        // cause or a false alarm (a target the tracker cannot see is no false alarm).
        let occluded = || {
            target_occluded(
                &self.scene,
                &captured.input.world_from_chase,
                &captured.input.world_from_lead,
                &captured.input.world_from_actors,
                &world_from_camera,
                captured.input.time_s,
            )
        };
        let (lost_truth, loss_cause, false_alarm, traffic) =
            match (&mut self.traffic, &captured.traffic) {
                (Some(judge), Some(states)) => {
                    let lead = LeadTarget {
                        truth: &truth,
                        width_px: self.target_width_px,
                        width_m: self.target_width_m,
                        occluded,
                        faint: &self.faint,
                    };
                    let tracking = status == TrackerStatus::Tracking;
                    let log = traffic_log.unwrap_or_default();
                    let acquired = &mut self.acquired;
                    let seen = Seen {
                        image: &frame.image,
                        read: tracked.read,
                    };
                    let j = judge.judge(
                        captured, states, estimate, tracking, lead, seen, log, acquired,
                    );
                    (j.lost, j.cause, j.false_alarm, Some(j.frame))
                }
                _ => {
                    self.acquired |= !lost_truth;
                    let cause = if !lost_truth {
                        LossCause::None
                    } else if !self.acquired && status != TrackerStatus::Tracking {
                        LossCause::NotAcquired
                    } else if !truth.in_view {
                        LossCause::OutOfView
                    } else if occluded() {
                        LossCause::Occluded
                    } else if faint() {
                        LossCause::LowContrast
                    } else {
                        LossCause::Tracker
                    };
                    let false_alarm = !lost_truth
                        && status != TrackerStatus::Tracking
                        && truth.in_view
                        && !occluded()
                        && !faint();
                    (lost_truth, cause, false_alarm, None)
                }
            };
        let cam = world_from_camera.translation.vector;
        let [tx, ty, tz] = truth.target_cam_m;
        let target_world = world_from_camera * nalgebra::Point3::new(tx, ty, tz);
        let gap_m = (target_world.x - cam.x).hypot(target_world.z - cam.z);
        let chase_xz = xz(&chase_state.world_from_vehicle);
        let lead_xz = lead_state
            .as_ref()
            .map_or([f64::NAN; 2], |l| xz(&l.world_from_vehicle));
        self.chase_distance_m +=
            (chase_xz[0] - self.last_chase_xz[0]).hypot(chase_xz[1] - self.last_chase_xz[1]);
        self.last_chase_xz = chase_xz;
        if lead_state.is_some() {
            self.lead_path.push(lead_xz);
        }
        let lateral_deviation_m = self.lead_path.distance(chase_xz);
        let track = tracked.out.as_ref();
        let known = |v: Option<f64>| v.unwrap_or(f64::NAN);
        FrameRecord {
            frame: frame_index,
            t_s: captured.input.time_s,
            true_cx: truth.c_x,
            true_cy: truth.c_y,
            true_scale: truth.scale,
            true_range_m: tz,
            true_lateral_m: tx,
            target_in_view: truth.in_view,
            target_partly_out_of_view: truth.partly_in_view,
            est_cx: known(estimate.and_then(|e| e.cx)),
            est_cy: known(estimate.and_then(|e| e.cy)),
            est_scale: known(estimate.and_then(|e| e.scale)),
            est_range_m: known(estimate.map(|e| e.range_m)),
            est_lateral_m: known(estimate.map(|e| e.lateral_m)),
            confidence: track.map_or([f64::NAN; 3], |t| {
                t.measurement.map_or([0.0; 3], |m| m.confidence)
            }),
            status,
            lost_truth,
            gap_m,
            chase_speed_mps: f64::from(chase_state.forward_speed_mps),
            lead_speed_mps: lead_state
                .as_ref()
                .map_or(f64::NAN, |l| f64::from(l.forward_speed_mps)),
            steering_rad: f64::from(controls.steer_rad),
            throttle: f64::from(controls.throttle),
            brake: f64::from(controls.brake),
            lateral_deviation_m,
            chase_distance_m: self.chase_distance_m,
            chase_xz,
            lead_xz,
            collision,
            chase_mode: chase_mode.map_or_else(String::new, |m| format!("{m:?}").to_lowercase()),
            coverage: track.map_or([f64::NAN; 2], |t| t.coverage),
            coverage_gain: track.map_or(f64::NAN, |t| t.coverage_gain),
            tracker_event: track
                .and_then(|t| t.event)
                .map_or_else(String::new, |e| e.as_str().to_string()),
            fit_residual: track
                .and_then(|t| t.measurement)
                .map_or(f64::NAN, |m| m.residual),
            feature_sigma2: track.map_or_else(Vec::new, |t| {
                t.features
                    .iter()
                    .map(|f| f.variance.unwrap_or(f64::NAN))
                    .collect()
            }),
            loss_cause,
            camera_pan_deg: captured.input.camera_pan_rad.to_degrees(),
            desired_gap_m: f64::from(desired_gap_m),
            false_alarm,
            traffic,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The truth of a target 10 m ahead, centred at `(cx, 120)` at scale 1, wholly in view or
    /// partly out of it.
    fn truth(cx: f64, whole: bool) -> GroundTruth {
        GroundTruth {
            c_x: cx,
            c_y: 120.0,
            scale: 1.0,
            target_cam_m: [0.0, 0.0, 10.0],
            in_view: whole,
            partly_in_view: !whole,
        }
    }

    fn at(cx: f64, scale: f64) -> Estimate {
        Estimate {
            cx: Some(cx),
            cy: Some(120.0),
            scale: Some(scale),
            ..Estimate::new(10.0, 0.0)
        }
    }

    #[test]
    fn a_target_partly_out_of_view_but_tracked_within_the_tolerance_is_not_lost() {
        // A 40 px wide target with its centre on the image's right edge: half of it out.
        let t = truth(255.0, false);
        assert!(!wrong(Some(&at(256.0, 1.02)), &t, 40.0, 1.0));
        // Off by more than a quarter of its width, or by more than 25 % in scale: lost,
        // wherever the target is.
        assert!(wrong(Some(&at(266.0, 1.0)), &t, 40.0, 1.0));
        assert!(wrong(Some(&at(255.0, 1.3)), &t, 40.0, 1.0));
        assert!(wrong(Some(&at(266.0, 1.0)), &truth(128.0, true), 40.0, 1.0));
        // No estimate at all is lost.
        assert!(wrong(None, &t, 40.0, 1.0));
    }

    #[test]
    fn a_target_behind_the_camera_or_a_non_finite_estimate_is_lost() {
        let mut behind = truth(f64::NAN, false);
        behind.c_y = f64::NAN;
        behind.target_cam_m = [0.0, 0.0, -10.0];
        assert!(wrong(Some(&at(128.0, 1.0)), &behind, 40.0, 1.0));
        assert!(wrong(Some(&Estimate::new(10.0, 0.0)), &behind, 40.0, 1.0));
        assert!(wrong(
            Some(&at(f64::NAN, 1.0)),
            &truth(128.0, true),
            40.0,
            1.0
        ));
        // The metric judgement, for an estimate without an image location.
        assert!(!wrong(
            Some(&Estimate::new(10.5, 0.1)),
            &truth(128.0, true),
            40.0,
            1.0
        ));
        assert!(wrong(
            Some(&Estimate::new(13.0, 0.0)),
            &truth(128.0, true),
            40.0,
            1.0
        ));
    }
}
