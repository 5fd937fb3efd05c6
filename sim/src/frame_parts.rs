//! Rendering only the part of each frame the tracker reads.
//!
//! The tracker reads only around its window of interest ([`Tracker::last_read`] says which
//! pixels a step read), so the loop renders each frame's colour pass scissored to where the
//! tracker should read it: the rectangle the last tracked frame read, moved and grown as the
//! tracker's own prediction moves and grows the target over the frames between
//! ([`FrameParts::needed`]), with a margin. With two frames in flight, frame k + 1 is
//! submitted before frame k is tracked, so that is a two-frame prediction. When a step turns
//! out to read beyond what was rendered (a search, a surprise), the rest of the frame is
//! rendered and the step run again from a copy of the tracker's state
//! ([`track_part`]): correctness comes first, and the estimates are bit for bit those of
//! whole frames (`sim/tests/cli_run.rs` compares `frames.csv` with and without `--video`).
//! Whole frames are rendered when something needs them: the video, recordings, stills.

use crate::camera::Frame;
use tracker::{EdgeDiagnostic, Location, PixelRect, TrackOutput, Tracker};

/// Margin around the predicted read rectangle, pixels: the robust tracker's search near
/// its prediction reaches [`tracker::robust::LOCAL_SEARCH_PX`] (16 px) beyond the
/// target, and its coverage check a feature spacing and [`tracker::robust::PEAK_PROBE_PX`]
/// beyond the window; a frame whose step reaches farther is rendered whole and tracked again.
const MARGIN_PX: f64 = 12.0;
/// Further margin for each frame of prediction, pixels: what the predicted motion can be
/// off by in a frame (the chase's pitch on a bump moves the target a few pixels a frame).
const MARGIN_PER_FRAME_PX: f64 = 6.0;

/// What the last tracked frame read, and where the tracker said the target was going.
#[derive(Clone, Copy, Debug)]
struct Seen {
    frame_index: u64,
    read: PixelRect,
    /// The predicted image motion of the target per frame, pixels.
    shift_px: [f64; 2],
    /// The predicted growth of the target per frame (ratio of scales).
    zoom: f64,
}

/// Chooses the part of each frame to render.
#[derive(Clone, Debug)]
pub(crate) struct FrameParts {
    /// Whether every frame is rendered whole (someone needs the images).
    pub(crate) whole_frames: bool,
    width: usize,
    height: usize,
    last: Option<Seen>,
    /// Frames whose step read beyond what was rendered, and were rendered whole.
    pub(crate) rerendered: u64,
}

impl FrameParts {
    /// For frames `width × height`, whole frames at first.
    pub(crate) fn new(width: u32, height: u32) -> FrameParts {
        FrameParts {
            whole_frames: true,
            width: width as usize,
            height: height as usize,
            last: None,
            rerendered: 0,
        }
    }

    /// The part of frame `frame_index` to render; `None` for all of it.
    pub(crate) fn needed(&self, frame_index: u64) -> Option<PixelRect> {
        if self.whole_frames {
            return None;
        }
        let seen = self.last?;
        let whole = PixelRect::whole(self.width, self.height);
        if seen.read.is_empty() || seen.read == whole || frame_index <= seen.frame_index {
            return None;
        }
        let ahead = (frame_index - seen.frame_index) as f64;
        let r = seen.read;
        let half = [0.5 * r.width() as f64, 0.5 * r.height() as f64];
        let centre = [r.x0 as f64 + half[0], r.y0 as f64 + half[1]];
        let grow = seen.zoom.powf(ahead).max(1.0);
        let margin = MARGIN_PX + MARGIN_PER_FRAME_PX * ahead;
        let moved = [0, 1].map(|k| {
            let c = centre[k] + ahead * seen.shift_px[k];
            let h = half[k] * grow;
            [c - h, c + h]
        });
        // Where it was, where it is predicted to be, and the margin around both.
        let lo = |k: usize, at: f64| (moved[k][0].min(at) - margin).floor().max(0.0) as usize;
        let hi = |k: usize, at: f64, n: usize| {
            ((moved[k][1].max(at) + margin).ceil().max(0.0) as usize).min(n)
        };
        let part = PixelRect {
            x0: lo(0, r.x0 as f64),
            y0: lo(1, r.y0 as f64),
            x1: hi(0, r.x1 as f64, self.width),
            y1: hi(1, r.y1 as f64, self.height),
        };
        Some(part)
    }

    /// Notes what the step of frame `frame_index` read (`read`), its estimate and its
    /// prediction for the next frame.
    pub(crate) fn observe(&mut self, frame_index: u64, e: Location, n: Location, read: PixelRect) {
        let finite = [e.c_x, e.c_y, e.scale, n.c_x, n.c_y, n.scale]
            .iter()
            .all(|v| v.is_finite());
        let (shift_px, zoom) = if finite && e.scale > 0.0 && n.scale > 0.0 {
            ([n.c_x - e.c_x, n.c_y - e.c_y], n.scale / e.scale)
        } else {
            ([0.0; 2], 1.0)
        };
        self.last = Some(Seen {
            frame_index,
            read,
            shift_px,
            zoom,
        });
    }
}

/// Tracks `frame` with `step` (the tracker's step on an image). When the frame is only
/// partly rendered and the step read beyond its exact pixels, the tracker goes back to its
/// state before the step, `whole` renders the whole frame into `frame` (on whichever
/// renderer is free: the images are the same), and the step runs again; the second value
/// says whether that happened.
pub(crate) fn track_part<E>(
    tracker: &mut Tracker,
    frame: &mut Frame,
    whole: impl FnOnce() -> Result<Frame, E>,
    step: impl Fn(&mut Tracker, &Frame) -> (TrackOutput, Vec<EdgeDiagnostic>),
) -> Result<((TrackOutput, Vec<EdgeDiagnostic>), bool), E> {
    let all = PixelRect::whole(frame.image.width() as usize, frame.image.height() as usize);
    if frame.exact == all {
        return Ok((step(tracker, frame), false));
    }
    let before = tracker.clone();
    let out = step(tracker, frame);
    if frame.exact.contains(&tracker.last_read()) {
        return Ok((out, false));
    }
    *tracker = before;
    *frame = whole()?;
    Ok((step(tracker, frame), true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_part_follows_the_prediction_and_grows_with_it() {
        let mut parts = FrameParts::new(256, 242);
        parts.whole_frames = false;
        assert_eq!(parts.needed(1), None, "nothing seen yet: the whole frame");
        let read = PixelRect {
            x0: 100,
            y0: 90,
            x1: 160,
            y1: 130,
        };
        parts.observe(
            4,
            Location::new(130.0, 110.0, 1.0),
            Location::new(134.0, 108.0, 1.1),
            read,
        );
        let one = parts.needed(5).unwrap();
        let two = parts.needed(6).unwrap();
        assert!(one.contains(&read) && two.contains(&one));
        // Two frames on, the rectangle (60 × 40, grown 21 %) moved by (8, −4), plus margins.
        let m = MARGIN_PX + 2.0 * MARGIN_PER_FRAME_PX;
        assert_eq!(two.x1, (130.0 + 8.0 + 30.0 * 1.21 + m).ceil() as usize);
        assert_eq!(two.y0, (110.0 - 4.0 - 20.0 * 1.21 - m).floor() as usize);
        assert!(two.width() < 256 / 2, "{two:?}");
        // A step that read the whole frame (a search) asks for the whole next one.
        let at = Location::new(130.0, 110.0, 1.0);
        parts.observe(5, at, at, PixelRect::whole(256, 242));
        assert_eq!(parts.needed(6), None);
        // As does a loop that needs whole frames.
        parts.observe(6, at, at, read);
        parts.whole_frames = true;
        assert_eq!(parts.needed(7), None);
    }

    /// A part that misses the target: the step reads beyond it, so the frame is rendered
    /// whole and tracked again, and the output is the whole frame's.
    #[test]
    fn a_step_beyond_the_part_renders_the_rest_and_steps_again() {
        use crate::camera::{Backend, CameraRig, FrameInput, RenderOptions, Renderer};
        use crate::scene::{builtin_description, builtin_poses, builtin_target, Scene};
        use tracker::{GrayView, TrackerConfig};

        let scene = Scene::build(builtin_description(builtin_target(), 5)).expect("scene");
        let options = RenderOptions {
            backend: Backend::choose(None).expect("backend"),
            ..RenderOptions::default()
        };
        let mut renderer = Renderer::new(&scene, CameraRig::default(), &options).expect("renderer");
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
        let new_tracker = || {
            let at = Location::new(t.c_x, t.c_y, t.scale);
            Tracker::new(builtin_target(), camera, TrackerConfig::default(), at).unwrap()
        };
        let step = |tracker: &mut Tracker, f: &Frame| {
            let (w, h) = f.image.dimensions();
            let view = GrayView::new(w as usize, h as usize, f.image.as_raw()).unwrap();
            (tracker.step(view, time_s), Vec::new())
        };
        let mut reference = new_tracker();
        let (expected, _) = step(&mut reference, &whole);

        // A corner far from the target: the step reads beyond it.
        let corner = PixelRect {
            x0: 0,
            y0: 0,
            x1: 12,
            y1: 12,
        };
        let mut partial = renderer.render_part(&input, Some(corner)).expect("frame");
        assert_ne!(partial.image, whole.image);
        let mut tracker = new_tracker();
        let ((out, _), again) =
            track_part(&mut tracker, &mut partial, || renderer.render(&input), step)
                .expect("track");
        assert!(again, "rendered whole and stepped again");
        assert_eq!(out, expected);
        assert_eq!(partial, whole);

        // A part holding what the step reads: no second render.
        let read = reference.last_read();
        let mut enough = renderer.render_part(&input, Some(read)).expect("frame");
        let mut tracker = new_tracker();
        let ((out, _), again) =
            track_part(&mut tracker, &mut enough, || renderer.render(&input), step).expect("track");
        assert!(!again);
        assert_eq!(out, expected);
        assert_eq!(enough.exact, read);
    }
}
