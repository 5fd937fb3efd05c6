//! The target's location in the image (paper 2.1.2, eq. 1).

/// The 3-vector of eq. 1: the object centre (c_x, c_y) in image pixels (origin top-left,
/// pixel centres at integer coordinates) and the scale, the ratio of the target's current
/// size in the image to its size at nominal range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Location {
    /// Object centre, image x (pixels, right).
    pub c_x: f64,
    /// Object centre, image y (pixels, down).
    pub c_y: f64,
    /// Size relative to the size at nominal range.
    pub scale: f64,
}

impl Location {
    /// A location from its three parameters.
    pub const fn new(c_x: f64, c_y: f64, scale: f64) -> Self {
        Location { c_x, c_y, scale }
    }

    /// The parameters as an array `[c_x, c_y, scale]`.
    pub fn to_array(self) -> [f64; 3] {
        [self.c_x, self.c_y, self.scale]
    }

    /// True when all three parameters are finite and the scale is positive.
    pub fn is_valid(self) -> bool {
        self.c_x.is_finite() && self.c_y.is_finite() && self.scale.is_finite() && self.scale > 0.0
    }
}
