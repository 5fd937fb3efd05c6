//! A tracker of our own: normalised cross-correlation on the target's template.
//!
//! The template is cut from the first frame at the scenario's starting estimate (where the
//! teleoperator put the target, as in section 2.2 of the paper). Each frame, it is scaled to
//! three sizes about the last scale and correlated over a window about the position a
//! constant-velocity model predicts; the best match, refined to a sub-pixel peak, is the
//! target. Range comes from the scale (the template's size at scale 1 is the target's at the
//! nominal range), the offsets from the image position by the pinhole model.

use sim_core::{CameraModel, Estimate, EstimateStatus, FrameTracker, PluginError, TrackerInput};
use tracker::{GrayView, PixelRect};

/// How far from the predicted position the match is searched, pixels.
const SEARCH_PX: i64 = 14;
/// Scale steps tried each frame: the last scale times 1/STEP, 1 and STEP.
const SCALE_STEP: f64 = 1.03;
/// A match below this correlation is no match.
const MIN_SCORE: f64 = 0.55;
/// Frames without a match before the tracker says it has lost the target.
const LOST_AFTER: u32 = 8;

/// The template: zero-mean grey values, with the scale it was cut at.
struct Template {
    width: usize,
    height: usize,
    pixels: Vec<f64>,
    scale: f64,
}

/// Normalised cross-correlation on a template of the target.
pub struct NccTracker {
    camera: Option<CameraModel>,
    template: Option<Template>,
    /// Position (pixels) and scale now, and the position's change per frame.
    at: [f64; 3],
    velocity: [f64; 2],
    misses: u32,
}

impl NccTracker {
    /// A tracker that starts at [`FrameTracker::reset`].
    pub fn new() -> NccTracker {
        NccTracker {
            camera: None,
            template: None,
            at: [0.0; 3],
            velocity: [0.0; 2],
            misses: 0,
        }
    }

    /// The target's size in the image at `scale`, pixels.
    fn size_px(camera: &CameraModel, scale: f64) -> [f64; 2] {
        let [w, h] = camera.target.size_m();
        let [fx, fy] = camera.intrinsics.focal_px();
        let r = camera.target.nominal_range_m();
        [w * fx / r * scale, h * fy / r * scale]
    }

    /// The estimate at image position `(cx, cy)` and `scale`.
    fn estimate(
        camera: &CameraModel,
        [cx, cy, scale]: [f64; 3],
        status: EstimateStatus,
    ) -> Estimate {
        let [fx, fy] = camera.intrinsics.focal_px();
        let [c0x, c0y] = camera.intrinsics.image_center_px;
        let range = camera.target.nominal_range_m() / scale;
        Estimate {
            range_m: range,
            lateral_m: (cx - c0x) * range / fx,
            vertical_m: Some((cy - c0y) * range / fy),
            cx: Some(cx),
            cy: Some(cy),
            scale: Some(scale),
            status,
            vehicle: None,
        }
    }

    /// The template cut from `frame` about `(cx, cy)` at `scale`, with a 10 % margin of what
    /// surrounds the board (its edges are what the match locks on to).
    fn cut(camera: &CameraModel, frame: &GrayView<'_>, [cx, cy, scale]: [f64; 3]) -> Template {
        let [w, h] = Self::size_px(camera, scale * 1.1);
        let (width, height) = ((w.round() as usize).max(8), (h.round() as usize).max(8));
        let mut pixels = Vec::with_capacity(width * height);
        for j in 0..height {
            for i in 0..width {
                let x = cx - (width as f64 - 1.0) / 2.0 + i as f64;
                let y = cy - (height as f64 - 1.0) / 2.0 + j as f64;
                pixels.push(bilinear(frame, x, y));
            }
        }
        let mean = pixels.iter().sum::<f64>() / pixels.len() as f64;
        pixels.iter_mut().for_each(|p| *p -= mean);
        Template {
            width,
            height,
            pixels,
            scale,
        }
    }

    /// The template resampled to `scale`: (width, height, zero-mean values, their norm).
    fn resampled(t: &Template, scale: f64) -> (usize, usize, Vec<f64>, f64) {
        let k = scale / t.scale;
        let (width, height) = (
            ((t.width as f64 * k).round() as usize).max(6),
            ((t.height as f64 * k).round() as usize).max(6),
        );
        let view = |x: f64, y: f64| -> f64 {
            let x = x.clamp(0.0, t.width as f64 - 1.0);
            let y = y.clamp(0.0, t.height as f64 - 1.0);
            let (x0, y0) = (x.floor() as usize, y.floor() as usize);
            let (x1, y1) = ((x0 + 1).min(t.width - 1), (y0 + 1).min(t.height - 1));
            let (fx, fy) = (x - x0 as f64, y - y0 as f64);
            let p = |x: usize, y: usize| t.pixels[y * t.width + x];
            (p(x0, y0) * (1.0 - fx) + p(x1, y0) * fx) * (1.0 - fy)
                + (p(x0, y1) * (1.0 - fx) + p(x1, y1) * fx) * fy
        };
        let mut v = Vec::with_capacity(width * height);
        for j in 0..height {
            for i in 0..width {
                v.push(view((i as f64 + 0.5) / k - 0.5, (j as f64 + 0.5) / k - 0.5));
            }
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        v.iter_mut().for_each(|p| *p -= mean);
        let norm = v.iter().map(|p| p * p).sum::<f64>().sqrt();
        (width, height, v, norm)
    }

    /// The best match about `(px, py)` at `scale`: (score, cx, cy).
    fn search(
        frame: &GrayView<'_>,
        t: &Template,
        px: f64,
        py: f64,
        scale: f64,
    ) -> Option<(f64, f64, f64)> {
        let (w, h, tv, tnorm) = Self::resampled(t, scale);
        if tnorm <= 0.0 {
            return None;
        }
        let (fw, fh) = (frame.width() as i64, frame.height() as i64);
        let half = [(w as f64 - 1.0) / 2.0, (h as f64 - 1.0) / 2.0];
        let (x0c, y0c) = ((px - half[0]).round() as i64, (py - half[1]).round() as i64);
        let side = (2 * SEARCH_PX + 1) as usize;
        let mut scores = vec![f64::NAN; side * side];
        let pixels = frame.pixels();
        for dy in -SEARCH_PX..=SEARCH_PX {
            for dx in -SEARCH_PX..=SEARCH_PX {
                let (x0, y0) = (x0c + dx, y0c + dy);
                if x0 < 0 || y0 < 0 || x0 + w as i64 > fw || y0 + h as i64 > fh {
                    continue;
                }
                let (mut sf, mut sff, mut stf) = (0.0, 0.0, 0.0);
                for j in 0..h {
                    let row = &pixels[(y0 as usize + j) * fw as usize + x0 as usize..][..w];
                    for (f, t) in row.iter().zip(&tv[j * w..(j + 1) * w]) {
                        let f = f64::from(*f);
                        sf += f;
                        sff += f * f;
                        stf += t * f;
                    }
                }
                let n = (w * h) as f64;
                let var = sff - sf * sf / n;
                if var > 1e-9 {
                    let i = ((dy + SEARCH_PX) as usize) * side + (dx + SEARCH_PX) as usize;
                    scores[i] = stf / (tnorm * var.sqrt());
                }
            }
        }
        let (best, score) = scores
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_finite())
            .max_by(|a, b| a.1.total_cmp(b.1))?;
        let (bx, by) = ((best % side) as i64, (best / side) as i64);
        // A parabola through the peak and its neighbours, in each direction.
        let at = |x: i64, y: i64| -> Option<f64> {
            (0..side as i64)
                .contains(&x)
                .then_some(())
                .filter(|_| (0..side as i64).contains(&y))
                .map(|_| scores[y as usize * side + x as usize])
                .filter(|s| s.is_finite())
        };
        let peak = |m: Option<f64>, c: f64, p: Option<f64>| match (m, p) {
            (Some(m), Some(p)) if m - 2.0 * c + p < 0.0 => {
                (0.5 * (m - p) / (m - 2.0 * c + p)).clamp(-0.5, 0.5)
            }
            _ => 0.0,
        };
        let sx = peak(at(bx - 1, by), *score, at(bx + 1, by));
        let sy = peak(at(bx, by - 1), *score, at(bx, by + 1));
        let cx = (x0c + bx - SEARCH_PX) as f64 + sx + half[0];
        let cy = (y0c + by - SEARCH_PX) as f64 + sy + half[1];
        Some((*score, cx, cy))
    }
}

/// `frame` at `(x, y)`, bilinear, clamped to the image.
fn bilinear(frame: &GrayView<'_>, x: f64, y: f64) -> f64 {
    let (w, h) = (frame.width(), frame.height());
    let x = x.clamp(0.0, w as f64 - 1.0);
    let y = y.clamp(0.0, h as f64 - 1.0);
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
    let (fx, fy) = (x - x0 as f64, y - y0 as f64);
    let p = |x: usize, y: usize| f64::from(frame.get(x, y));
    (p(x0, y0) * (1.0 - fx) + p(x1, y0) * fx) * (1.0 - fy)
        + (p(x0, y1) * (1.0 - fx) + p(x1, y1) * fx) * fy
}

impl FrameTracker for NccTracker {
    fn name(&self) -> String {
        "normalised cross-correlation (example)".into()
    }

    fn reset(&mut self, camera: &CameraModel, start: Option<&Estimate>) -> Result<(), PluginError> {
        let Some((Some(cx), Some(cy), Some(scale))) = start.map(|s| (s.cx, s.cy, s.scale)) else {
            return Err(PluginError::Failed(
                "the correlation tracker needs a starting image position and scale".into(),
            ));
        };
        *self = NccTracker::new();
        self.camera = Some(camera.clone());
        self.at = [cx, cy, scale];
        Ok(())
    }

    fn track(&mut self, input: &TrackerInput<'_>) -> Result<Option<Estimate>, PluginError> {
        let camera = input.camera;
        let frame = &input.frame;
        let Some(template) = &self.template else {
            self.template = Some(Self::cut(camera, frame, self.at));
            return Ok(Some(Self::estimate(
                camera,
                self.at,
                EstimateStatus::Tracking,
            )));
        };
        let [x, y, s] = self.at;
        let (px, py) = (x + self.velocity[0], y + self.velocity[1]);
        let best = [s / SCALE_STEP, s, s * SCALE_STEP]
            .into_iter()
            .filter_map(|scale| Self::search(frame, template, px, py, scale).map(|m| (m, scale)))
            .max_by(|a, b| a.0 .0.total_cmp(&b.0 .0));
        match best {
            Some(((score, cx, cy), scale)) if score >= MIN_SCORE => {
                self.velocity = [
                    0.5 * self.velocity[0] + 0.5 * (cx - x),
                    0.5 * self.velocity[1] + 0.5 * (cy - y),
                ];
                self.at = [cx, cy, scale];
                self.misses = 0;
                Ok(Some(Self::estimate(
                    camera,
                    self.at,
                    EstimateStatus::Tracking,
                )))
            }
            _ => {
                // No match: hold the position, let the velocity decay, and coast; after
                // LOST_AFTER frames say so.
                self.misses += 1;
                self.velocity = [0.5 * self.velocity[0], 0.5 * self.velocity[1]];
                Ok((self.misses >= LOST_AFTER)
                    .then(|| Self::estimate(camera, self.at, EstimateStatus::Lost)))
            }
        }
    }

    /// Only the search window is read: the loop renders only it.
    fn will_read(&self) -> Option<PixelRect> {
        let camera = self.camera.as_ref()?;
        self.template.as_ref()?;
        let [x, y, s] = self.at;
        let [w, h] = Self::size_px(camera, s * SCALE_STEP * 1.1);
        let reach_x = w / 2.0 + SEARCH_PX as f64 + self.velocity[0].abs() + 2.0;
        let reach_y = h / 2.0 + SEARCH_PX as f64 + self.velocity[1].abs() + 2.0;
        let (width, height) = (camera.width as f64, camera.height as f64);
        let clamp = |v: f64, hi: f64| v.clamp(0.0, hi) as usize;
        Some(PixelRect {
            x0: clamp((x - reach_x).floor(), width),
            y0: clamp((y - reach_y).floor(), height),
            x1: clamp((x + reach_x).ceil() + 1.0, width),
            y1: clamp((y + reach_y).ceil() + 1.0, height),
        })
    }
}
