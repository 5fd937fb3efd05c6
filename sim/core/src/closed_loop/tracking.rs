//! The loop's tracker, through the plug-in trait whatever it is: the paper's
//! ([`crate::BuiltinTracker`]) or anyone's. It is given the part of each frame rendered;
//! should it say it needs more ([`FrameTracker::track_drawn`]), more is rendered and it
//! tracks the frame again.

use crate::frame_parts::RETRY_MARGIN_PX;
use crate::plugin::{
    CameraModel, Drawn, Estimate, FrameTracker, LaneAhead, PluginError, TrackerInput,
};
use sim_render::Frame;
use tracker::{EdgeDiagnostic, EgoMotion, GrayView, PixelRect, TrackOutput};

/// The tracker the loop runs, with the camera it is told of.
pub(super) struct Tracking {
    pub(super) tracker: Box<dyn FrameTracker>,
    /// The camera, its pan reading set for each frame.
    pub(super) camera: CameraModel,
    /// How many vehicles an estimate may say it holds: the lead and the actors.
    pub(super) targets: usize,
}

/// What the tracker made of one frame.
pub(super) struct Tracked {
    /// The paper's tracker's whole output (stages 1–8); `None` for a tracker that gives
    /// no details.
    pub(super) out: Option<TrackOutput>,
    /// The pixels its step read, when it says.
    pub(super) read: Option<PixelRect>,
    /// The estimate (`None`: none this frame).
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
    /// The tracker failed, or returned what the loop cannot use.
    Plugin(PluginError),
}

impl Tracking {
    /// Tracks `frame` (captured at `t_s`, the pan head reading `pan_reading_rad`, the gyro
    /// `ego` since the last frame, with the chase's lane ahead and its odometer's speed, in
    /// [`TrackerInput`]'s terms), rendering more of it with `render` for as long as the
    /// tracker needs pixels beyond those rendered: first the part it asked for with a
    /// margin, then the whole frame. The second value says whether the frame was rendered
    /// again.
    pub(super) fn track<E>(
        &mut self,
        frame: &mut Frame,
        mut render: impl FnMut(Option<PixelRect>) -> Result<Frame, E>,
        t_s: f64,
        ego: Option<EgoMotion>,
        pan_reading_rad: f64,
        (lane, speed_mps): (Option<&LaneAhead>, Option<f64>),
    ) -> Result<(Tracked, bool), TrackFailure<E>> {
        self.camera.pan_rad = pan_reading_rad;
        let (width, height) = (frame.image.width() as usize, frame.image.height() as usize);
        let whole = PixelRect::whole(width, height);
        let mut again = false;
        let estimate = loop {
            let drawn = frame.exact;
            let input = TrackerInput {
                frame: GrayView::new(width, height, frame.image.as_raw())
                    .expect("a rendered frame is whole"),
                t_s,
                camera: &self.camera,
                gyro_rad: ego.map(|e| e.rotation_rad),
                lane,
                speed_mps,
            };
            let read = match self.tracker.track_drawn(&input, drawn) {
                Ok(Drawn::Tracked(estimate)) => break estimate,
                Ok(Drawn::Needs(read)) => read,
                Err(e) => return Err(TrackFailure::Plugin(e)),
            };
            if drawn == whole {
                return Err(TrackFailure::Plugin(PluginError::Invalid(format!(
                    "a need for pixels {read:?} beyond the whole frame"
                ))));
            }
            // The part read, with a margin, the first time; the whole frame after.
            let larger = drawn.union(&read).grown(RETRY_MARGIN_PX, width, height);
            let part = (!again && larger != whole).then_some(larger);
            *frame = render(part).map_err(TrackFailure::Render)?;
            again = true;
        };
        if let Some(e) = &estimate {
            e.validate().map_err(TrackFailure::Plugin)?;
            self.check_vehicle(e.vehicle)
                .map_err(TrackFailure::Plugin)?;
        }
        let details = self.tracker.take_details();
        let position_m = estimate.map_or([f64::NAN; 3], |e| e.position_m(&self.camera.intrinsics));
        let (out, read, edges) = match details {
            Some(d) => (Some(d.output), Some(d.read), d.edges),
            None => (None, None, Vec::new()),
        };
        let tracked = Tracked {
            out,
            read,
            estimate,
            position_m,
            edges,
        };
        Ok((tracked, again))
    }

    /// Checks that the vehicle an estimate says it holds is one of the scenario's.
    fn check_vehicle(&self, vehicle: Option<usize>) -> Result<(), PluginError> {
        match vehicle {
            Some(v) if v == 0 || v > self.targets => {
                let actors = match self.targets {
                    1 => "no actors".to_string(),
                    2 => "2 the one actor".to_string(),
                    n => format!("2-{n} the actors"),
                };
                Err(PluginError::Invalid(format!(
                    "vehicle = {v}: no such target (1 is the lead, {actors})"
                )))
            }
            _ => Ok(()),
        }
    }

    /// The part of the next frame the tracker said it will read (`None`: it did not say).
    pub(super) fn will_read(&self) -> Option<PixelRect> {
        self.tracker.will_read()
    }

    /// Whether the tracker said its step `ahead` frames on is likely to read the whole frame.
    pub(super) fn may_read_whole(&self, ahead: u64) -> bool {
        self.tracker.may_read_whole(ahead)
    }

    /// Whether the tracker said its step `ahead` frames on will read nothing.
    pub(super) fn will_rest(&self, ahead: u64) -> bool {
        self.tracker.will_rest(ahead)
    }

    /// The tracker's name, for reports.
    pub(super) fn name(&self) -> String {
        self.tracker.name()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part that misses the target: the step reads beyond it, so a larger part (or, when
    /// that falls short too, the whole frame) is rendered and tracked again, and the
    /// output is the whole frame's.
    #[test]
    fn a_step_beyond_the_part_renders_the_rest_and_steps_again() {
        use crate::plugin::BuiltinTracker;
        use sim_render::RenderError;
        use sim_render::{builtin_description, builtin_poses, builtin_target, Scene};
        use sim_render::{Backend, CameraRig, FrameInput, RenderOptions, Renderer};
        use tracker::{Location, Tracker, TrackerConfig};

        let scene = std::sync::Arc::new(
            Scene::build(builtin_description(builtin_target(), 5)).expect("scene"),
        );
        let options = RenderOptions {
            backend: Backend::choose(None).expect("backend"),
            ..RenderOptions::default()
        };
        let mut renderer =
            Renderer::new(scene.clone(), CameraRig::default(), &options).expect("renderer");
        let time_s = 3.0;
        let (world_from_chase, world_from_lead) = builtin_poses(
            scene.description(),
            scene.route(),
            &renderer.rig().mount,
            time_s,
        );
        let input = FrameInput::fixed_camera(45, time_s, world_from_chase, world_from_lead);
        let whole = renderer.render(&input).expect("frame");
        let t = whole.truth;
        let camera = renderer.rig().intrinsics;
        let at = Location::new(t.c_x, t.c_y, t.scale);
        let mut reference =
            Tracker::new(builtin_target(), camera, TrackerConfig::default(), at).unwrap();
        let (w, h) = whole.image.dimensions();
        let view = GrayView::new(w as usize, h as usize, whole.image.as_raw()).unwrap();
        let expected = reference.step(view, time_s);
        // The paper's tracker as the loop runs it: through the plug-in trait.
        let new_tracking = || {
            let model = CameraModel {
                intrinsics: camera,
                width: w,
                height: h,
                mount_height_m: 1.5,
                mount_forward_m: 0.0,
                mount_pitch_down_deg: 0.0,
                pan_rad: 0.0,
                target: builtin_target(),
            };
            let start = Estimate {
                cx: Some(t.c_x),
                cy: Some(t.c_y),
                scale: Some(t.scale),
                ..Estimate::new(10.0, 0.0)
            };
            let mut tracker = BuiltinTracker::new(TrackerConfig::default());
            tracker.reset(&model, Some(&start)).unwrap();
            Tracking {
                tracker: Box::new(tracker),
                camera: model,
                targets: 1,
            }
        };
        fn track(
            tracking: &mut Tracking,
            frame: &mut Frame,
            render: impl FnMut(Option<PixelRect>) -> Result<Frame, RenderError>,
            time_s: f64,
        ) -> (TrackOutput, bool) {
            let ok = tracking.track(frame, render, time_s, None, 0.0, (None, None));
            let (tracked, again) = ok.unwrap_or_else(|_| panic!("track"));
            (tracked.out.expect("the paper's tracker's output"), again)
        }

        // A part a few pixels short of what the step reads on every side, as a part
        // predicted from a smaller read falls short: the step reads beyond it.
        let read = reference.last_read();
        let short = PixelRect {
            x0: read.x0 + 6,
            y0: read.y0 + 6,
            x1: read.x1 - 6,
            y1: read.y1 - 6,
        };
        // Tracks the short part; `narrow`: a renderer that draws the short part again
        // whatever part it is asked for. The parts asked for come back too.
        let mut track_short = |narrow: bool| {
            let mut partial = renderer.render_part(&input, Some(short)).expect("frame");
            assert_ne!(partial.image, whole.image);
            let mut tracking = new_tracking();
            let mut asked = Vec::new();
            let render = |p: Option<PixelRect>| {
                asked.push(p);
                renderer.render_part(&input, if narrow { p.map(|_| short) } else { p })
            };
            let (out, again) = track(&mut tracking, &mut partial, render, time_s);
            (out, again, asked, partial)
        };
        let (out, again, asked, partial) = track_short(false);
        assert!(again, "rendered again and stepped again");
        assert_eq!(out, expected);
        // Once: a part holding what the step read, not the whole frame.
        assert_eq!(asked.len(), 1, "{asked:?}");
        let larger = asked[0].expect("a part");
        assert!(larger.contains(&short) && larger.contains(&read));
        assert_eq!(partial.exact, larger);
        let (w, _) = whole.image.dimensions();
        for y in larger.y0..larger.y1 {
            let row = |f: &Frame| f.image.as_raw()[y * w as usize..][larger.x0..larger.x1].to_vec();
            assert_eq!(row(&partial), row(&whole), "row {y}");
        }

        // Should the larger part fall short too, the whole frame.
        let (out, again, asked, partial) = track_short(true);
        assert!(again);
        assert_eq!(asked.len(), 2, "{asked:?}");
        assert_eq!(asked[1], None);
        assert_eq!(out, expected);
        assert_eq!(partial, whole);

        // A part holding what the step reads: no second render.
        let mut enough = renderer.render_part(&input, Some(read)).expect("frame");
        let mut tracking = new_tracking();
        let render = |p| renderer.render_part(&input, p);
        let (out, again) = track(&mut tracking, &mut enough, render, time_s);
        assert!(!again);
        assert_eq!(out, expected);
        assert_eq!(enough.exact, read);
    }
}
