//! The window of interest (paper 2.3): stage 1 works only inside it. It is centred on the
//! predicted target and takes one of seven sizes, chosen from the predicted scale.

use crate::config::TrackerConfig;
use crate::location::Location;

/// A rectangle of pixels `x0..x1` × `y0..y1` (end exclusive), and which of the seven sizes
/// it was made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Window {
    /// First column.
    pub x0: usize,
    /// First row.
    pub y0: usize,
    /// One past the last column.
    pub x1: usize,
    /// One past the last row.
    pub y1: usize,
    /// Index (0–6) into [`TrackerConfig::window_scales`].
    pub size_index: usize,
}

impl Window {
    /// The window for a predicted location. `half_extent_px` is half the target's width and
    /// height at scale 1. The window is clipped to the pixels the 3×3 operator can reach
    /// (one pixel in from every border) and may be empty when the target is out of view.
    pub fn around(
        predicted: Location,
        half_extent_px: [f64; 2],
        config: &TrackerConfig,
        width: usize,
        height: usize,
    ) -> Window {
        let scales = &config.window_scales;
        let size_index = scales
            .iter()
            .position(|&s| s >= predicted.scale)
            .unwrap_or(scales.len() - 1);
        let grow = scales[size_index] * (1.0 + config.window_margin);
        let half_w = half_extent_px[0] * grow + config.zeta_px;
        let half_h = half_extent_px[1] * grow + config.zeta_px;
        let clip = |lo: f64, hi: f64, n: usize| -> (usize, usize) {
            if !(lo.is_finite() && hi.is_finite()) {
                return (1, 1);
            }
            let max = (n - 1) as f64;
            let a = lo.floor().clamp(1.0, max) as usize;
            let b = (hi.ceil() + 1.0).clamp(1.0, max) as usize;
            (a, b.max(a))
        };
        let (x0, x1) = clip(predicted.c_x - half_w, predicted.c_x + half_w, width);
        let (y0, y1) = clip(predicted.c_y - half_h, predicted.c_y + half_h, height);
        Window {
            x0,
            y0,
            x1,
            y1,
            size_index,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.x1 - self.x0
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.y1 - self.y0
    }

    /// True when the window holds no pixel.
    pub fn is_empty(&self) -> bool {
        self.x1 <= self.x0 || self.y1 <= self.y0
    }
}
