//! Stages 6 and 7: prediction (paper 2.8, eq. 34–35).
//!
//! Stage 6 evaluates each parameter's motion model one cycle ahead (eq. 34). Stage 7 places
//! every model feature at that predicted location and scale (eq. 35).

use crate::location::Location;
use crate::model::{Feature, Orientation};
use crate::motion::MotionModel;

/// Stage 6 (eq. 34): the object's location `cycles` camera cycles after the current image,
/// from the three motion models [c_x, c_y, scale].
pub fn predict_location(models: &[MotionModel; 3], cycles: f64) -> Location {
    Location::new(
        models[0].predict(cycles),
        models[1].predict(cycles),
        models[2].predict(cycles),
    )
}

/// A model feature placed in the image at a predicted location (stage 7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictedFeature {
    /// The model segment this feature is.
    pub segment: usize,
    /// Horizontal (`y = b_y`) or vertical (`x = b_x`).
    pub orientation: Orientation,
    /// Predicted intercept: b_y for a horizontal line, b_x for a vertical one (eq. 35).
    pub intercept: f64,
    /// Predicted end points along the line: (x_j1, x_j2) of eq. 8 for a horizontal line,
    /// (y_j1, y_j2) of eq. 10 for a vertical one.
    pub extent: [f64; 2],
}

impl PredictedFeature {
    /// Predicted length in pixels.
    pub fn length(&self) -> f64 {
        self.extent[1] - self.extent[0]
    }
}

/// Stage 7 (eq. 35): every feature at `location`. A vertical feature's x intercept is
/// `c_x + u·scale`, a horizontal one's y intercept `c_y + v·scale`; end points scale alike.
pub fn predict_features(features: &[Feature], location: Location, out: &mut Vec<PredictedFeature>) {
    out.clear();
    let s = location.scale;
    out.extend(features.iter().map(|f| {
        let (centre_across, centre_along) = match f.orientation {
            Orientation::Horizontal => (location.c_y, location.c_x),
            Orientation::Vertical => (location.c_x, location.c_y),
        };
        PredictedFeature {
            segment: f.segment,
            orientation: f.orientation,
            intercept: centre_across + f.offset_px * s,
            extent: [
                centre_along + f.extent_px[0] * s,
                centre_along + f.extent_px[1] * s,
            ],
        }
    }));
}
