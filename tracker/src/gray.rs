//! A borrowed 8-bit grey image: the tracker's only input.

use thiserror::Error;

/// A row-major 8-bit grey image, borrowed. Pixel (x, y) is `pixels[y * width + x]`, centred
/// at image coordinates (x, y).
#[derive(Clone, Copy, Debug)]
pub struct GrayView<'a> {
    width: usize,
    height: usize,
    pixels: &'a [u8],
}

/// An image the tracker cannot use.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum ImageError {
    /// The buffer's length is not width × height.
    #[error("image buffer holds {len} bytes, but {width}×{height} needs {}", width * height)]
    BadLength {
        /// Stated width.
        width: usize,
        /// Stated height.
        height: usize,
        /// Buffer length.
        len: usize,
    },
    /// The 3×3 gradient operator needs at least 3×3 pixels.
    #[error("image is {width}×{height}; the tracker needs at least 3×3")]
    TooSmall {
        /// Width.
        width: usize,
        /// Height.
        height: usize,
    },
}

impl<'a> GrayView<'a> {
    /// Wraps a buffer of `width × height` grey levels.
    pub fn new(width: usize, height: usize, pixels: &'a [u8]) -> Result<Self, ImageError> {
        if pixels.len() != width * height {
            return Err(ImageError::BadLength {
                width,
                height,
                len: pixels.len(),
            });
        }
        if width < 3 || height < 3 {
            return Err(ImageError::TooSmall { width, height });
        }
        Ok(GrayView {
            width,
            height,
            pixels,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The pixels, row-major.
    pub fn pixels(&self) -> &'a [u8] {
        self.pixels
    }

    /// The grey level at (x, y).
    pub fn get(&self, x: usize, y: usize) -> u8 {
        self.pixels[y * self.width + x]
    }
}
