//! Whether a target shows too little contrast for the paper's edge threshold, in the pixels
//! the tracker read: the truth's `low_contrast` cause of a loss, and no false alarm (a
//! target the method cannot see is no target it fails to hold).
//!
//! Each feature of the target's model is laid on the frame where the truth puts it, and
//! the grey levels either side of it, [`SIDE_PX`] off its line, are averaged along the
//! middle of its length: the step between them is the edge the feature gives. The paper's
//! stage 1 passes a step of `2 × edge_threshold` grey levels or more (|∇f| = h/2 for a step
//! of h, `tracker::TrackerConfig::edge_threshold`); a target on which less than
//! [`SHOWN_SHARE`] of the outline, by length, steps that much is too faint. Judged only
//! where every sample lies in the pixels the tracker's step read (the same with and without
//! whole frames rendered); elsewhere it is not judged faint. Nor is a target too small
//! for the judgement to read: one whose nearest parallel features
//! ([`tracker::resolvability::confusable_spacing`]) lie closer than the two sides sampled,
//! `2 × SIDE_PX` apart, where a side's sample falls on the next feature's edge and the step
//! read is no longer this feature's.

use image::GrayImage;
use sim_render::GroundTruth;
use tracker::{Feature, Orientation, PixelRect};

/// How far either side of a feature's line its sides are sampled, pixels: beyond the
/// blur and the operator's reach of the edge itself.
const SIDE_PX: f64 = 2.0;
/// The share of a feature's length sampled, about its middle (its ends meet other
/// features).
const ALONG_SHARE: f64 = 0.6;
/// The least share of the outline, by length, whose step the threshold passes on a target
/// that shows.
const SHOWN_SHARE: f64 = 0.5;
/// The shortest feature judged, pixels in the image.
const MIN_LENGTH_PX: f64 = 4.0;

/// The judgement for one target model.
#[derive(Clone, Debug)]
pub(super) struct Faintness {
    /// The model's features, pixels at scale 1.
    features: Vec<Feature>,
    /// The least step the threshold passes, grey levels.
    step: f64,
    /// The least scale at which the model's nearest parallel features lie `2 × SIDE_PX`
    /// apart, so that the sides sampled for one feature miss the next.
    min_scale: f64,
}

impl Faintness {
    /// The judgement for a model with `features` (pixels at scale 1) under the paper's
    /// `edge_threshold` (on |∇f|, grey levels per pixel).
    pub(super) fn new(features: Vec<Feature>, edge_threshold: f64) -> Faintness {
        let [x, y] = tracker::resolvability::confusable_spacing(&features);
        Faintness {
            features,
            step: 2.0 * edge_threshold,
            min_scale: 2.0 * SIDE_PX / x.min(y),
        }
    }

    /// Whether the target at `truth` is too faint in `image`, judged in the pixels `read`
    /// (none: not judged).
    pub(super) fn too_faint(
        &self,
        image: &GrayImage,
        read: Option<PixelRect>,
        truth: &GroundTruth,
    ) -> bool {
        let Some(read) = read else {
            return false;
        };
        let s = truth.scale;
        if !(s.is_finite() && s > 0.0 && s >= self.min_scale && truth.in_view) {
            return false;
        }
        let (mut shown, mut total) = (0.0, 0.0);
        for f in &self.features {
            let length = s * f.length_px();
            if length < MIN_LENGTH_PX {
                continue;
            }
            let Some(step) = self.step_of(f, image, read, truth) else {
                return false;
            };
            total += length;
            if step >= self.step {
                shown += length;
            }
        }
        total > 0.0 && shown < SHOWN_SHARE * total
    }

    /// The grey-level step across feature `f` of the target at `truth`: `None` when a
    /// sample lies outside `read`.
    fn step_of(
        &self,
        f: &Feature,
        image: &GrayImage,
        read: PixelRect,
        truth: &GroundTruth,
    ) -> Option<f64> {
        let s = truth.scale;
        let [lo, hi] = f.extent_px.map(|e| s * e);
        let middle = 0.5 * (lo + hi);
        let half = 0.5 * ALONG_SHARE * (hi - lo);
        let samples = (2.0 * half).floor().max(1.0) as usize;
        let across = s * f.offset_px;
        let (mut a, mut b) = (0.0, 0.0);
        for k in 0..samples {
            let along = middle - half + (k as f64 + 0.5) * (2.0 * half / samples as f64);
            // Pixel centres are at integer coordinates.
            let (x, y, dx, dy) = match f.orientation {
                Orientation::Horizontal => (truth.c_x + along, truth.c_y + across, 0.0, SIDE_PX),
                Orientation::Vertical => (truth.c_x + across, truth.c_y + along, SIDE_PX, 0.0),
            };
            a += grey(image, read, x - dx, y - dy)?;
            b += grey(image, read, x + dx, y + dy)?;
        }
        Some((a - b).abs() / samples as f64)
    }
}

/// The grey level of the pixel nearest `(x, y)`, when it lies in `read`.
fn grey(image: &GrayImage, read: PixelRect, x: f64, y: f64) -> Option<f64> {
    let (i, j) = (x.round(), y.round());
    let inside = i >= read.x0 as f64
        && i < read.x1 as f64
        && j >= read.y0 as f64
        && j < read.y1 as f64
        && i < f64::from(image.width())
        && j < f64::from(image.height());
    inside.then(|| f64::from(image.get_pixel(i as u32, j as u32)[0]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use tracker::synth::{draw, nist_ten_segment, SynthScene};
    use tracker::{Camera, Location};

    /// The board at `at` drawn with every edge of its model a step of `contrast` grey
    /// levels (its white `contrast` above its paint and the background), with noise.
    fn board(at: Location, contrast: f64) -> GrayImage {
        let scene = SynthScene {
            noise_sigma: 2.0,
            blur_sigma: 0.6,
            background: 100.0,
            board: 100.0 + contrast,
            paint: 100.0,
            ..SynthScene::default()
        };
        let pixels = draw(&nist_ten_segment(), &Camera::default(), at, &scene, 3);
        GrayImage::from_raw(256, 242, pixels).unwrap()
    }

    fn truth(at: Location) -> GroundTruth {
        GroundTruth {
            c_x: at.c_x,
            c_y: at.c_y,
            scale: at.scale,
            target_cam_m: [0.0, 0.0, 10.0 / at.scale],
            in_view: true,
            partly_in_view: true,
        }
    }

    #[test]
    fn a_board_is_faint_below_the_threshold_step_and_not_above_it() {
        let faint = Faintness::new(nist_ten_segment().features_px(&Camera::default()), 8.0);
        let whole = Some(PixelRect::whole(256, 242));
        for scale in [0.6, 1.0, 1.8] {
            let at = Location::new(128.0, 115.0, scale);
            for (contrast, expected) in [(6.0, true), (12.0, true), (24.0, false), (120.0, false)] {
                let image = board(at, contrast);
                assert_eq!(
                    faint.too_faint(&image, whole, &truth(at)),
                    expected,
                    "scale {scale}, {contrast} grey levels"
                );
            }
            // Not judged without the pixels: none read, or the target beyond those read.
            let image = board(at, 6.0);
            assert!(!faint.too_faint(&image, None, &truth(at)));
            let left = PixelRect {
                x0: 0,
                y0: 0,
                x1: 100,
                y1: 242,
            };
            assert!(!faint.too_faint(&image, Some(left), &truth(at)));
        }
    }

    #[test]
    fn a_board_too_small_for_its_sides_to_miss_the_next_edge_is_not_judged() {
        let features = nist_ten_segment().features_px(&Camera::default());
        let faint = Faintness::new(features.clone(), 8.0);
        let [x, y] = tracker::resolvability::confusable_spacing(&features);
        let least = 2.0 * SIDE_PX / x.min(y);
        assert!(least > 0.1 && least < 0.6, "least scale {least}");
        let whole = Some(PixelRect::whole(256, 242));
        let (below, above) = (0.9 * least, 1.1 * least);
        let faint_at = |scale: f64| {
            let at = Location::new(128.0, 115.0, scale);
            faint.too_faint(&board(at, 6.0), whole, &truth(at))
        };
        assert!(!faint_at(below), "judged at scale {below}");
        assert!(faint_at(above), "not judged at scale {above}");
    }
}
