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
//! (`closed_loop::tracking`): correctness comes first, and the estimates are bit for bit those of
//! whole frames (`sim/tests/cli_run.rs` compares `frames.csv` with and without `--video`).
//! Whole frames are rendered when something needs them: the video, recordings, stills.

use nalgebra::UnitQuaternion;
use std::collections::VecDeque;
use tracker::{Camera, EgoMotion, Location, PixelRect};

/// Margin around the predicted read rectangle, pixels, whatever the prediction's recent
/// record: the read rectangle's edges are whole pixels.
const MARGIN_PX: f64 = 2.0;
/// How many of the latest frames' prediction errors set the margin.
const RECENT_FRAMES: usize = 6;
/// The margin per frame of prediction follows the error this many places from the largest
/// of the latest [`RECENT_FRAMES`] (1: the largest). The prediction's error drifts smoothly
/// as the target speeds up or turns, so the latest errors bound the next one; but one or two
/// frames now and then read farther (a search near the prediction, or the tracker's check
/// of a fit that covers little, which reads the moves' reach around the fit), and a margin
/// that wide for six frames after each would cost more than rendering those frames again.
const ERROR_RANK: usize = 3;
/// The margin per frame of prediction before [`ERROR_RANK`] errors are known, pixels.
const FIRST_ERROR_PX: f64 = 6.0;

/// What the last tracked frame read, and where the tracker said the target was going.
#[derive(Clone, Copy, Debug)]
struct Seen {
    frame_index: u64,
    read: PixelRect,
    /// The predicted image motion of the target per frame, pixels.
    shift_px: [f64; 2],
    /// The predicted growth of the target per frame (ratio of scales).
    zoom: f64,
    /// The camera's orientation then (world from camera).
    camera: UnitQuaternion<f64>,
}

impl Seen {
    /// Where the read rectangle is predicted to be `ahead` frames on, with where it was:
    /// the least and greatest x, then y, pixels, before any margin. `turning`: the camera
    /// (intrinsics) when the tracker turns its prediction with the camera's rotation, and
    /// the camera's orientation `ahead` frames on.
    fn predicted(
        &self,
        ahead: f64,
        turning: Option<(&Camera, &UnitQuaternion<f64>)>,
    ) -> [[f64; 2]; 2] {
        let r = self.read;
        let half = [0.5 * r.width() as f64, 0.5 * r.height() as f64];
        let mut centre =
            [0, 1].map(|k| [r.x0, r.y0][k] as f64 + half[k] + ahead * self.shift_px[k]);
        if let Some((camera, now)) = turning {
            let ego = EgoMotion {
                rotation_rad: camera_turn(&self.camera, now),
            };
            let d = ego.image_shift(camera, Location::new(centre[0], centre[1], 1.0));
            centre = [centre[0] + d[0], centre[1] + d[1]];
        }
        let grow = self.zoom.powf(ahead).max(1.0);
        let was = [[r.x0, r.x1], [r.y0, r.y1]];
        [0, 1].map(|k| {
            let c = centre[k];
            let h = half[k] * grow;
            [(c - h).min(was[k][0] as f64), (c + h).max(was[k][1] as f64)]
        })
    }
}

/// Chooses the part of each frame to render.
#[derive(Clone, Debug)]
pub(crate) struct FrameParts {
    /// Whether every frame is rendered whole (someone needs the images).
    pub(crate) whole_frames: bool,
    /// The camera's intrinsics when the tracker turns its prediction with the camera's
    /// rotation (robust mode's gyro): the parts then turn with it too.
    turning: Option<Camera>,
    width: usize,
    height: usize,
    last: Option<Seen>,
    /// The latest frames' prediction errors: how far beyond its prediction from the frame
    /// before each frame's step read, per frame of prediction, pixels.
    errors: VecDeque<f64>,
    /// Frames whose step read beyond what was rendered, and were rendered again.
    pub(crate) rerendered: u64,
}

impl FrameParts {
    /// For frames `width × height`, whole frames at first; `turning`: see the field.
    pub(crate) fn new(width: u32, height: u32, turning: Option<Camera>) -> FrameParts {
        FrameParts {
            whole_frames: true,
            turning,
            width: width as usize,
            height: height as usize,
            last: None,
            errors: VecDeque::with_capacity(RECENT_FRAMES + 1),
            rerendered: 0,
        }
    }

    /// The part of frame `frame_index`, whose camera has the orientation `camera` (world
    /// from camera), to render; `None` for all of it.
    pub(crate) fn needed(
        &self,
        frame_index: u64,
        camera: &UnitQuaternion<f64>,
    ) -> Option<PixelRect> {
        if self.whole_frames {
            return None;
        }
        let seen = self.last?;
        let whole = PixelRect::whole(self.width, self.height);
        if seen.read.is_empty() || seen.read == whole || frame_index <= seen.frame_index {
            return None;
        }
        let ahead = (frame_index - seen.frame_index) as f64;
        let margin = MARGIN_PX + self.error_px() * ahead;
        let [x, y] = seen.predicted(ahead, self.turning.as_ref().map(|c| (c, camera)));
        let lo = |at: f64| (at - margin).floor().max(0.0) as usize;
        let hi = |at: f64, n: usize| ((at + margin).ceil().max(0.0) as usize).min(n);
        let part = PixelRect {
            x0: lo(x[0]),
            y0: lo(y[0]),
            x1: hi(x[1], self.width),
            y1: hi(y[1], self.height),
        };
        Some(part)
    }

    /// Notes what the step of frame `frame_index` (whose camera had the orientation
    /// `camera`) read (`read`), its estimate and its prediction for the next frame.
    pub(crate) fn observe(
        &mut self,
        frame_index: u64,
        e: Location,
        n: Location,
        read: PixelRect,
        camera: UnitQuaternion<f64>,
    ) {
        let finite = [e.c_x, e.c_y, e.scale, n.c_x, n.c_y, n.scale]
            .iter()
            .all(|v| v.is_finite());
        let (shift_px, zoom) = if finite && e.scale > 0.0 && n.scale > 0.0 {
            ([n.c_x - e.c_x, n.c_y - e.c_y], n.scale / e.scale)
        } else {
            ([0.0; 2], 1.0)
        };
        let whole = PixelRect::whole(self.width, self.height);
        if let Some(last) = self.last {
            let was = last.read;
            if !read.is_empty() && read != whole && !was.is_empty() && was != whole {
                let ahead = frame_index.saturating_sub(last.frame_index).max(1) as f64;
                let [x, y] = last.predicted(ahead, self.turning.as_ref().map(|c| (c, &camera)));
                let beyond = (x[0] - read.x0 as f64)
                    .max(read.x1 as f64 - x[1])
                    .max(y[0] - read.y0 as f64)
                    .max(read.y1 as f64 - y[1])
                    .max(0.0);
                if self.errors.len() == RECENT_FRAMES {
                    self.errors.pop_front();
                }
                self.errors.push_back(beyond / ahead);
            }
        }
        self.last = Some(Seen {
            frame_index,
            read,
            shift_px,
            zoom,
            camera,
        });
    }

    /// The margin per frame of prediction, pixels: the [`ERROR_RANK`]th largest of the
    /// latest errors.
    fn error_px(&self) -> f64 {
        if self.errors.len() < ERROR_RANK {
            return FIRST_ERROR_PX;
        }
        // Sorted on the stack: this runs for every frame.
        let mut latest = [0.0; RECENT_FRAMES];
        let latest = &mut latest[..self.errors.len()];
        for (to, &e) in latest.iter_mut().zip(&self.errors) {
            *to = e;
        }
        latest.sort_unstable_by(|a, b| b.total_cmp(a));
        latest[ERROR_RANK - 1]
    }
}

/// The rotation vector (radians) that takes camera orientation `previous` to `now` (both
/// world from camera), in the `previous` camera's frame: what a gyro on the camera reads
/// between them, and what [`EgoMotion`] holds.
pub(crate) fn camera_turn(previous: &UnitQuaternion<f64>, now: &UnitQuaternion<f64>) -> [f64; 3] {
    let turn = (previous.inverse() * now).scaled_axis();
    [turn.x, turn.y, turn.z]
}

/// How far beyond what a step read (on a part that fell short) the second part reaches,
/// pixels. On the pixels it lacked the step may read differently (the tracker's check of a
/// fit that covers little reads the reach of its moves, which depends on the fit), and then
/// the whole frame is rendered; but in every shipped scenario, in both modes, the second step reads
/// exactly what the first did (about 1,100 second parts, none short), so the margin is the
/// least, as for [`MARGIN_PX`]: a wider one only renders more pixels on the loop's
/// critical path.
pub(crate) const RETRY_MARGIN_PX: usize = 2;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_part_follows_the_prediction_and_grows_with_it() {
        let still = UnitQuaternion::identity();
        let mut parts = FrameParts::new(256, 242, None);
        parts.whole_frames = false;
        assert_eq!(
            parts.needed(1, &still),
            None,
            "nothing seen yet: the whole frame"
        );
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
            still,
        );
        let one = parts.needed(5, &still).unwrap();
        let two = parts.needed(6, &still).unwrap();
        assert!(one.contains(&read) && two.contains(&one));
        // Two frames on, the rectangle (60 × 40, grown 21 %) moved by (8, −4), plus margins
        // (no errors known yet).
        let m = MARGIN_PX + 2.0 * FIRST_ERROR_PX;
        assert_eq!(two.x1, (130.0 + 8.0 + 30.0 * 1.21 + m).ceil() as usize);
        assert_eq!(two.y0, (110.0 - 4.0 - 20.0 * 1.21 - m).floor() as usize);
        assert!(two.width() < 256 / 2, "{two:?}");
        // A step that read the whole frame (a search) asks for the whole next one.
        let at = Location::new(130.0, 110.0, 1.0);
        parts.observe(5, at, at, PixelRect::whole(256, 242), still);
        assert_eq!(parts.needed(6, &still), None);
        // As does a loop that needs whole frames.
        parts.observe(6, at, at, read, still);
        parts.whole_frames = true;
        assert_eq!(parts.needed(7, &still), None);
    }

    /// A read rectangle of 60 × 40 px at (`x`, 90), the target not moving.
    fn read_at(x: usize) -> PixelRect {
        PixelRect {
            x0: x,
            y0: 90,
            x1: x + 60,
            y1: 130,
        }
    }

    #[test]
    fn the_margin_follows_the_latest_errors_and_ignores_a_stray_one() {
        let still = UnitQuaternion::identity();
        let at = Location::new(130.0, 110.0, 1.0);
        let mut parts = FrameParts::new(256, 242, None);
        parts.whole_frames = false;
        // The target drifts 3 px a frame that the prediction (standing still) misses.
        for k in 0..8 {
            parts.observe(k, at, at, read_at(100 + 3 * k as usize), still);
        }
        assert_eq!(parts.error_px(), 3.0);
        let next = parts.needed(8, &still).unwrap();
        assert_eq!(next.x1, (100 + 21 + 60) + (MARGIN_PX + 3.0) as usize);
        // A steady prediction: the margin shrinks to the least.
        for k in 8..16 {
            parts.observe(k, at, at, read_at(121), still);
        }
        assert_eq!(parts.error_px(), 0.0);
        // One frame that reads 15 px farther (the coverage check's band) does not widen
        // the margin of the frames after it; three do.
        parts.observe(16, at, at, read_at(121).grown(15, 256, 242), still);
        parts.observe(17, at, at, read_at(121), still);
        assert_eq!(parts.error_px(), 0.0);
        for k in 18..21 {
            parts.observe(k, at, at, read_at(121 + 5 * (k as usize - 17)), still);
        }
        assert_eq!(parts.error_px(), 5.0);
    }

    #[test]
    fn with_a_turning_prediction_the_part_turns_with_the_camera() {
        let camera = Camera::default();
        let at = Location::new(128.0, 121.0, 1.0);
        let read = read_at(98);
        let before = UnitQuaternion::identity();
        // The camera turns right by 1° (about its y axis, down in the camera frame).
        let after =
            UnitQuaternion::from_axis_angle(&nalgebra::Vector3::y_axis(), 1f64.to_radians());
        let mut turning = FrameParts::new(256, 242, Some(camera));
        let mut fixed = FrameParts::new(256, 242, None);
        for parts in [&mut turning, &mut fixed] {
            parts.whole_frames = false;
            parts.observe(1, at, at, read, before);
        }
        let shift = EgoMotion {
            rotation_rad: [0.0, 1f64.to_radians(), 0.0],
        }
        .image_shift(&camera, Location::new(128.0, 110.0, 1.0));
        assert!(
            shift[0] < -5.0,
            "turning right moves the scene left: {shift:?}"
        );
        let turned = turning.needed(2, &after).unwrap();
        let still = fixed.needed(2, &after).unwrap();
        // Where it was stays in the part; the part reaches as far left as the turn moves it.
        assert_eq!(turned.x1, still.x1);
        let m = MARGIN_PX + FIRST_ERROR_PX;
        assert_eq!(turned.x0, (98.0 + shift[0] - m).floor() as usize);
        assert!(turned.x0 < still.x0);
    }
}
