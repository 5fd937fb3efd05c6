//! A rectangle of pixels: what a step of the tracker read from its image
//! ([`crate::Tracker::last_read`]), so that a renderer may draw only that part of a frame.

use crate::window::Window;

/// How far beyond a window the tracker's pixel operators reach, pixels: edge extraction
/// needs the gradient one pixel beyond the window for non-maximum suppression, and the 3×3
/// Sobel operator one more (`EdgeExtractor::extract`); the noise estimate's 3×3 Laplacian
/// reaches one.
pub const OPERATOR_REACH_PX: usize = 2;

/// Pixels `x0..x1` × `y0..y1` (end exclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PixelRect {
    /// First column.
    pub x0: usize,
    /// First row.
    pub y0: usize,
    /// One past the last column.
    pub x1: usize,
    /// One past the last row.
    pub y1: usize,
}

impl PixelRect {
    /// The whole of a `width × height` image.
    pub fn whole(width: usize, height: usize) -> PixelRect {
        PixelRect {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// The pixels that reading `window` with the tracker's operators touches, within a
    /// `width × height` image.
    pub fn read_by(window: Window, width: usize, height: usize) -> PixelRect {
        PixelRect {
            x0: window.x0,
            y0: window.y0,
            x1: window.x1,
            y1: window.y1,
        }
        .grown(OPERATOR_REACH_PX, width, height)
    }

    /// True when the rectangle holds no pixel.
    pub fn is_empty(&self) -> bool {
        self.x1 <= self.x0 || self.y1 <= self.y0
    }

    /// Width in pixels (0 when empty).
    pub fn width(&self) -> usize {
        self.x1.saturating_sub(self.x0)
    }

    /// Height in pixels (0 when empty).
    pub fn height(&self) -> usize {
        self.y1.saturating_sub(self.y0)
    }

    /// The smallest rectangle holding both (an empty one holds nothing).
    pub fn union(&self, other: &PixelRect) -> PixelRect {
        if self.is_empty() {
            return *other;
        }
        if other.is_empty() {
            return *self;
        }
        PixelRect {
            x0: self.x0.min(other.x0),
            y0: self.y0.min(other.y0),
            x1: self.x1.max(other.x1),
            y1: self.y1.max(other.y1),
        }
    }

    /// The pixels in both (empty when they do not overlap).
    pub fn intersection(&self, other: &PixelRect) -> PixelRect {
        PixelRect {
            x0: self.x0.max(other.x0),
            y0: self.y0.max(other.y0),
            x1: self.x1.min(other.x1),
            y1: self.y1.min(other.y1),
        }
    }

    /// Whether every pixel of `other` lies in this rectangle (an empty one always does).
    pub fn contains(&self, other: &PixelRect) -> bool {
        other.is_empty()
            || (self.x0 <= other.x0
                && self.y0 <= other.y0
                && other.x1 <= self.x1
                && other.y1 <= self.y1)
    }

    /// Grown by `margin` pixels on every side, clipped to a `width × height` image.
    pub fn grown(&self, margin: usize, width: usize, height: usize) -> PixelRect {
        PixelRect {
            x0: self.x0.saturating_sub(margin),
            y0: self.y0.saturating_sub(margin),
            x1: (self.x1 + margin).min(width),
            y1: (self.y1 + margin).min(height),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: usize, y0: usize, x1: usize, y1: usize) -> PixelRect {
        PixelRect { x0, y0, x1, y1 }
    }

    #[test]
    fn union_contains_and_growth() {
        let a = rect(10, 20, 30, 40);
        let b = rect(25, 5, 50, 22);
        let u = a.union(&b);
        assert_eq!(u, rect(10, 5, 50, 40));
        assert!(u.contains(&a) && u.contains(&b));
        assert!(!a.contains(&b));
        assert!(a.contains(&rect(3, 3, 3, 9)), "an empty rectangle");
        assert_eq!(rect(0, 0, 0, 0).union(&a), a);
        assert_eq!(a.grown(15, 40, 45), rect(0, 5, 40, 45));
        assert_eq!(a.intersection(&b), rect(25, 20, 30, 22));
        assert!(a.intersection(&rect(31, 0, 40, 10)).is_empty());
        assert_eq!(
            PixelRect::read_by(
                Window {
                    x0: 1,
                    y0: 8,
                    x1: 20,
                    y1: 30,
                    size_index: 0
                },
                256,
                242
            ),
            rect(0, 6, 22, 32)
        );
    }
}
