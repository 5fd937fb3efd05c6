//! The recorder's judgement in traffic: which vehicle's target the estimate holds, against
//! the vehicle in the chase's path, and so whether a frame is lost and why.
//!
//! Without traffic a frame is lost when the estimate is off the lead's target. In traffic
//! the vehicle to hold is the one in the chase's path, which changes: a frame is lost when
//! the estimate holds anything else, or nothing while a vehicle is in the path. Its cause:
//! - `occluded`: the vehicle held is in the lane behind the one in the path (a car cut in
//!   between), or the path vehicle's target is hidden by scenery;
//! - `left_path`: the vehicle held was once the one in the path and has left the lane;
//! - `wrong_vehicle`: the vehicle held never was in the path;
//! - `out_of_view`, `low_contrast` and `tracker`, as without traffic, for the vehicle in
//!   the path (`low_contrast` judged on each vehicle's own model).

use super::capture::Captured;
use super::contrast::Faintness;
use super::recorder::wrong;
use crate::plugin::Estimate;
use crate::record::{Contact, LossCause, TrafficFrame};
use crate::traffic::{self, Road, Vehicles};
use image::GrayImage;
use nalgebra::Isometry3;
use sim_render::{body_from_back_model, ground_truth_of, CameraRig, GroundTruth, VehicleKind};
use tracker::{PixelRect, TargetModel};

/// An actor's target: where its back's model sits on its body, the model, its width in
/// the image at its nominal range, pixels, and whether it is too faint.
struct ActorTarget {
    body_from_target: Isometry3<f64>,
    model: TargetModel,
    width_px: f64,
    faint: Faintness,
}

/// The frame as the tracker read it: its image and the pixels its step read.
pub(super) struct Seen<'a> {
    pub(super) image: &'a GrayImage,
    pub(super) read: Option<PixelRect>,
}

/// The traffic's side of the recorder.
pub(super) struct TrafficTruth {
    road: Road,
    vehicles: Vehicles,
    rig: CameraRig,
    /// Each actor's target, in the list's order after the chase and the lead.
    actors: Vec<ActorTarget>,
    /// Whether each vehicle has been the one in the chase's path.
    was_path: Vec<bool>,
}

/// A frame's judgement in traffic.
pub(super) struct Judged {
    pub(super) frame: TrafficFrame,
    pub(super) lost: bool,
    pub(super) cause: LossCause,
    /// Not lost, the target in view and not hidden, and the tracker not saying `tracking`.
    pub(super) false_alarm: bool,
}

/// The lead's side of a frame: its target's truth, its width in pixels at the nominal
/// range and in metres, whether scenery hides it, and the judgement of its contrast.
pub(super) struct LeadTarget<'a, F: Fn() -> bool> {
    pub(super) truth: &'a GroundTruth,
    pub(super) width_px: f64,
    pub(super) width_m: f64,
    pub(super) occluded: F,
    pub(super) faint: &'a Faintness,
}

impl TrafficTruth {
    /// The judgement for the road and vehicles of a plan, seen through `rig`; `kinds` are
    /// the actors' kinds in the list's order; `edge_threshold` the paper's, on |∇f|.
    pub(super) fn new(
        road: Road,
        vehicles: Vehicles,
        rig: CameraRig,
        kinds: &[VehicleKind],
        edge_threshold: f64,
    ) -> TrafficTruth {
        let focal_px = rig.intrinsics.focal_px()[0];
        let actors = kinds
            .iter()
            .map(|&kind| {
                let model = sim_render::vehicle_back_model(kind);
                ActorTarget {
                    body_from_target: body_from_back_model(kind),
                    width_px: model.size_m()[0] * focal_px / model.nominal_range_m(),
                    faint: Faintness::new(model.features_px(&rig.intrinsics), edge_threshold),
                    model,
                }
            })
            .collect();
        TrafficTruth {
            was_path: vec![false; vehicles.members().len()],
            road,
            vehicles,
            rig,
            actors,
        }
    }

    /// Judges frame `captured` with `estimate`, the tracker's `tracking` status, and
    /// the events and contacts `log` since the frame before; `acquired` says whether the
    /// tracker has held the vehicle in the path yet (set here on the first frame it does):
    /// before, holding nothing while a vehicle is in the path, and saying so, is
    /// [`LossCause::NotAcquired`].
    #[allow(clippy::too_many_arguments)]
    pub(super) fn judge<F: Fn() -> bool>(
        &mut self,
        captured: &Captured,
        states: &[vehicle::VehicleState],
        estimate: Option<&Estimate>,
        tracking: bool,
        lead: LeadTarget<'_, F>,
        seen: Seen<'_>,
        log: (Vec<String>, Vec<Contact>),
        acquired: &mut bool,
    ) -> Judged {
        let input = &captured.input;
        let actor_truth: Vec<GroundTruth> = self
            .actors
            .iter()
            .zip(&input.world_from_actors)
            .map(|(a, pose)| {
                ground_truth_of(
                    &self.rig,
                    &a.body_from_target,
                    &a.model,
                    &input.world_from_chase,
                    pose,
                    input.camera_pan_rad,
                )
            })
            .collect();
        // The list: the chase, the lead (if there is one), then the actors from `first`.
        let first = self.vehicles.first_actor();
        let lead_index = self.vehicles.lead();
        let is_lead = |i: usize| Some(i) == lead_index;
        // Vehicle `i`'s target: its truth, its width at its nominal range in pixels and in
        // metres, and the judgement of its contrast.
        let target = |i: usize| -> (&GroundTruth, f64, f64, &Faintness) {
            if is_lead(i) {
                (lead.truth, lead.width_px, lead.width_m, lead.faint)
            } else {
                let a = &self.actors[i - first];
                let truth = &actor_truth[i - first];
                (truth, a.width_px, a.model.size_m()[0], &a.faint)
            }
        };
        // The vehicle whose target the estimate holds: the nearest in the image of those
        // it is within the loss tolerance of.
        let holds = |i: usize| -> Option<f64> {
            let (truth, width_px, width_m, _) = target(i);
            let e = estimate?;
            (!wrong(Some(e), truth, truth.scale * width_px, width_m)).then(|| {
                let (cx, cy) = (e.cx.unwrap_or(f64::NAN), e.cy.unwrap_or(f64::NAN));
                let d = (cx - truth.c_x).hypot(cy - truth.c_y);
                if d.is_finite() {
                    d
                } else {
                    0.0
                }
            })
        };
        // A tracker that says which vehicle it holds is taken at its word only where the
        // estimate lies on that vehicle's target.
        let tracked = match estimate.and_then(|e| e.vehicle) {
            Some(said) => holds(said).map(|_| said),
            None => (1..self.vehicles.members().len())
                .filter_map(|i| holds(i).map(|d| (i, d)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i),
        };
        let traffic::FrameTruth {
            mut frame,
            path,
            places,
        } = traffic::truth(&mut self.road, &self.vehicles, states, tracked, log);
        frame.path_range_m = path.map_or(f64::NAN, |p| target(p).0.target_cam_m[2]);
        let in_view = |i: usize| target(i).0.in_view;
        // Whether vehicle `i`'s target is hidden by scenery (judged for the lead only) or
        // too faint for the paper's threshold in the pixels the tracker read.
        let unseen = |i: usize| {
            let (truth, _, _, faint) = target(i);
            (is_lead(i) && (lead.occluded)()) || faint.too_faint(seen.image, seen.read, truth)
        };
        let behind = |held: usize, p: usize| {
            places[held].station_m > places[p].station_m
                && self.road.in_corridor(&self.vehicles, &places, 0, held)
        };
        let (lost, cause) = match (path, tracked) {
            (Some(p), Some(t)) if p == t => {
                *acquired = true;
                (false, LossCause::None)
            }
            (_, Some(t)) if path.is_some_and(|p| behind(t, p)) => (true, LossCause::Occluded),
            (_, Some(t)) if self.was_path[t] => (true, LossCause::LeftPath),
            (_, Some(_)) => (true, LossCause::WrongVehicle),
            (Some(_), None) if !*acquired && !tracking => (true, LossCause::NotAcquired),
            (Some(p), None) if !in_view(p) => (true, LossCause::OutOfView),
            (Some(p), None) if is_lead(p) && (lead.occluded)() => (true, LossCause::Occluded),
            (Some(p), None) if unseen(p) => (true, LossCause::LowContrast),
            (Some(_), None) => (true, LossCause::Tracker),
            // Nothing in the path: holding nothing is right, unless the tracker says it
            // tracks something.
            (None, None) if tracking => (true, LossCause::Tracker),
            (None, None) => (false, LossCause::None),
        };
        let false_alarm = !lost && !tracking && path.is_some_and(|p| in_view(p) && !unseen(p));
        if let Some(p) = path {
            self.was_path[p] = true;
        }
        Judged {
            frame,
            lost,
            cause,
            false_alarm,
        }
    }
}
