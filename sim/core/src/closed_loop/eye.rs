//! The loop's eye: the camera (its rig and automatic gain), the tracker, and what the
//! tracker reads of each frame. It sees the world only through the frames it is given and
//! the chase's rate gyro; the truth it captures goes to the recorder, never to the tracker.

use super::capture::{timed, Captured};
use super::drive::Drive;
use super::error::LoopError;
use super::tracking::{TrackFailure, Tracked, Tracking};
use crate::auto_gain::AutoGainControl;
use crate::frame_parts::{camera_turn, FrameParts};
use nalgebra::{Isometry3, UnitQuaternion};
use sim_render::{CameraRig, Frame};
use std::time::Duration;
use tracker::{EgoMotion, PixelRect};
use vehicle::Gyro;

/// The camera and the tracker.
pub(super) struct Eye {
    pub(super) rig: CameraRig,
    /// Scene origin (body centre) in the lead's vehicle frame (rear axle).
    pub(super) lead_from_scene: Isometry3<f64>,
    /// The camera's automatic gain control (gain 1 when off).
    pub(super) auto_gain: AutoGainControl,
    /// Which part of each frame to render.
    pub(super) parts: FrameParts,
    pub(super) tracking: Tracking,
    /// Each frame's output carries its edge points' fates.
    pub(super) diagnostics: bool,
    /// The chase's rate gyro, read between tracked frames for a tracker that reads it
    /// (robust mode's ego-motion aided prediction, plug-ins); `None` for the paper's mode,
    /// which has no use for it.
    pub(super) gyro: Option<Gyro>,
    /// The camera's orientation at the last tracked frame.
    pub(super) last_camera: Option<UnitQuaternion<f64>>,
    /// The gyro's reading handed to the tracker with the last tracked frame.
    pub(super) last_ego: Option<EgoMotion>,
}

/// No pixels: the part rendered of a frame the tracker will not read.
const NOTHING: PixelRect = PixelRect {
    x0: 0,
    y0: 0,
    x1: 0,
    y1: 0,
};

impl Eye {
    /// Step 1, the capture: the world of `drive` at the start of a frame, and the camera's
    /// input for it.
    pub(super) fn capture(&self, drive: &Drive) -> Captured {
        Captured::of(drive, &self.rig, &self.lead_from_scene, &self.auto_gain)
    }

    /// The part of the frame `captured` to render: what the tracker will read, or the
    /// whole frame (`None`).
    pub(super) fn needed(&self, captured: &Captured) -> Option<PixelRect> {
        if self.parts.whole_frames {
            return None;
        }
        if self.tracking.will_rest(1) {
            return Some(NOTHING);
        }
        if self.tracking.may_read_whole(1) {
            return None;
        }
        self.parts
            .needed(
                captured.input.frame_index,
                &captured.world_from_camera.rotation,
            )
            .or_else(|| self.tracking.will_read())
    }

    /// The part of frame `captured` to render when it is submitted before the frame
    /// before it is tracked (two in flight): the paper's tracker's prediction two frames
    /// on; a tracker that gives no details gets whole frames, since what it said it will
    /// read is of the next frame.
    pub(super) fn needed_ahead(&self, captured: &Captured) -> Option<PixelRect> {
        if !self.parts.whole_frames && self.tracking.will_rest(2) {
            return Some(NOTHING);
        }
        if self.tracking.may_read_whole(2) {
            return None;
        }
        self.parts.needed(
            captured.input.frame_index,
            &captured.world_from_camera.rotation,
        )
    }

    /// Step 3: tracks `rendered` (the frame of `captured` as its renderer drew it), rendering
    /// more of it with `render` should the tracker read beyond the part drawn, and notes
    /// what it read for the next frames' parts. Frames are seen in order, once each.
    /// Returns the frame and what the tracker made of it.
    pub(super) fn see<E>(
        &mut self,
        captured: &Captured,
        rendered: Result<Frame, E>,
        render: impl FnMut(Option<PixelRect>) -> Result<Frame, E>,
        track_t: &mut Duration,
    ) -> Result<(Frame, Tracked), LoopError>
    where
        E: Into<LoopError>,
    {
        let mut frame = rendered.map_err(Into::into)?;
        let ego = self.ego_motion(captured);
        let input = &captured.input;
        let (tracked, again) = timed(track_t, || {
            self.tracking.track(
                &mut frame,
                render,
                input.time_s,
                ego,
                captured.pan_reading_rad,
                (
                    captured.lane.as_ref(),
                    Some(f64::from(captured.chase.forward_speed_mps)),
                ),
            )
        })
        .map_err(|f| match f {
            TrackFailure::Render(e) => e.into(),
            TrackFailure::Plugin(error) => LoopError::Plugin {
                what: "tracker",
                frame: None,
                t_s: None,
                error,
            },
        })?;
        self.observe(captured, &tracked, again);
        Ok((frame, tracked))
    }

    /// Step 4: the estimate of frame `captured` into the delay line to the chase's controller.
    pub(super) fn deliver(&self, drive: &mut Drive, captured: &Captured, tracked: &Tracked) {
        if let Some(estimate) = tracked.estimate {
            drive.push_estimate(
                captured.now,
                estimate,
                tracked.position_m,
                captured.pan_reading_rad,
            );
        }
    }

    /// What the tracker read of frame `captured`, for the part of the next frames to render.
    fn observe(&mut self, captured: &Captured, tracked: &Tracked, rerendered: bool) {
        if let (Some(out), Some(read)) = (&tracked.out, tracked.read) {
            self.parts.observe(
                captured.input.frame_index,
                out.estimate,
                out.next,
                read,
                captured.world_from_camera.rotation,
            );
        }
        self.parts.rerendered += u64::from(rerendered);
    }

    /// Meters frame `frame` of `captured` for the automatic gain control, once it is
    /// tracked and before any later frame is captured.
    pub(super) fn meter(&mut self, captured: &Captured, frame: &Frame) {
        let input = &captured.input;
        self.auto_gain
            .observe(input.frame_index, input.auto_gain, &frame.image);
    }

    /// The gyro's reading of the camera's rotation since the last tracked frame, for the
    /// frame `captured` (robust mode and plug-ins only), kept for the frame's output.
    fn ego_motion(&mut self, captured: &Captured) -> Option<EgoMotion> {
        let ego = self.gyro_reading(captured);
        self.last_ego = ego;
        ego
    }

    /// See [`Eye::ego_motion`].
    fn gyro_reading(&mut self, captured: &Captured) -> Option<EgoMotion> {
        let gyro = self.gyro.as_mut()?;
        let now = captured.world_from_camera.rotation;
        let previous = self.last_camera.replace(now)?;
        // The rotation from the last camera orientation to this one, in the last camera's
        // frame; the gyro rides on the camera (on the pan head when there is one), so its
        // axes are the camera's up to a constant rotation.
        let measured = gyro.measure(
            camera_turn(&previous, &now),
            1.0 / f64::from(vehicle::CAMERA_HZ),
        );
        Some(EgoMotion {
            rotation_rad: measured,
        })
    }
}
