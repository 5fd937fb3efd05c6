//! The loop's tracker: the paper's, run directly (on the part of each frame it reads, rendered
//! again should it read beyond, with its diagnostics), or a plug-in (on the part it asked
//! for, or the whole frame).

use super::capture::track_frame;
use crate::frame_parts::track_part;
use crate::plugin::{estimate_of, CameraModel, Estimate, FrameTracker, PluginError, TrackerInput};
use sim_render::Frame;
use tracker::{EdgeDiagnostic, EgoMotion, GrayView, PixelRect, TrackOutput, Tracker};

/// The tracker the loop runs.
// One per loop, made once and never moved in the loop's steps (see `drive::Chase`).
#[allow(clippy::large_enum_variant)]
pub(super) enum Tracking {
    /// The paper's tracker, as the scenario sets it up.
    Builtin(Tracker),
    /// A plug-in.
    Plugin(PluginTracking),
}

/// A plug-in tracker, with the camera it is told of.
pub(super) struct PluginTracking {
    pub(super) tracker: Box<dyn FrameTracker>,
    /// The camera, its pan reading set for each frame.
    pub(super) camera: CameraModel,
    /// What the plug-in said it will read of the next frame.
    pub(super) next_read: Option<PixelRect>,
}

/// What the tracker made of one frame.
pub(super) struct Tracked {
    /// The paper's tracker's whole output (stages 1–8); `None` for a plug-in.
    pub(super) out: Option<TrackOutput>,
    /// The estimate (`None`: a plug-in had none this frame).
    pub(super) estimate: Option<Estimate>,
    /// Where the estimate puts the target in the camera frame, metres.
    pub(super) position_m: [f64; 3],
    /// Edge points' fates, with diagnostics on (the paper's tracker only).
    pub(super) edges: Vec<EdgeDiagnostic>,
}

/// Why a frame could not be tracked.
pub(super) enum TrackFailure<E> {
    /// Rendering the frame again failed.
    Render(E),
    /// The plug-in failed.
    Plugin(PluginError),
}

impl Tracking {
    /// Tracks `frame` (captured at `t_s`, the pan head reading `pan_reading_rad`, the gyro
    /// `ego` since the last frame). The paper's tracker goes through
    /// [`track_part`] with `render` (rendering more of the frame should it read beyond the
    /// part rendered); a plug-in takes the frame as it is. The second value says whether the
    /// frame was rendered again.
    pub(super) fn track<E>(
        &mut self,
        frame: &mut Frame,
        render: impl FnMut(Option<PixelRect>) -> Result<Frame, E>,
        t_s: f64,
        ego: Option<EgoMotion>,
        diagnostics: bool,
        pan_reading_rad: f64,
    ) -> Result<(Tracked, bool), TrackFailure<E>> {
        match self {
            Tracking::Builtin(t) => {
                let step =
                    |t: &mut Tracker, f: &Frame| track_frame(t, &f.image, t_s, ego, diagnostics);
                let ((out, edges), again) =
                    track_part(t, frame, render, step).map_err(TrackFailure::Render)?;
                let tracked = Tracked {
                    estimate: Some(estimate_of(&out)),
                    position_m: out.position_3d,
                    out: Some(out),
                    edges,
                };
                Ok((tracked, again))
            }
            Tracking::Plugin(p) => {
                p.camera.pan_rad = pan_reading_rad;
                let image = &frame.image;
                let frame = GrayView::new(
                    image.width() as usize,
                    image.height() as usize,
                    image.as_raw(),
                )
                .expect("a rendered frame is whole");
                let input = TrackerInput {
                    frame,
                    t_s,
                    camera: &p.camera,
                    gyro_rad: ego.map(|e| e.rotation_rad),
                };
                let estimate = p.tracker.track(&input).map_err(TrackFailure::Plugin)?;
                if let Some(e) = &estimate {
                    e.validate().map_err(TrackFailure::Plugin)?;
                }
                p.next_read = p.tracker.will_read();
                let position_m =
                    estimate.map_or([f64::NAN; 3], |e| e.position_m(&p.camera.intrinsics));
                let tracked = Tracked {
                    out: None,
                    estimate,
                    position_m,
                    edges: Vec::new(),
                };
                Ok((tracked, false))
            }
        }
    }

    /// The tracker's name, for reports.
    pub(super) fn name(&self) -> String {
        match self {
            Tracking::Builtin(t) => format!("paper tracker ({} mode)", t.config().mode.as_str()),
            Tracking::Plugin(p) => p.tracker.name(),
        }
    }
}
