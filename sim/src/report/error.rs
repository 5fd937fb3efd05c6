//! Errors while writing a run's outputs; each names the file it was writing.

use std::path::PathBuf;

/// Writing one of a run's output files failed.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Creating, writing or flushing a file (or creating its directory) failed.
    #[error("cannot write {}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// Serialising `summary.json` failed.
    #[error("cannot write the summary {}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: serde_json::Error,
    },
    /// Drawing a plot failed.
    #[error("cannot draw the plot {}: {message}", path.display())]
    Plot {
        /// The file.
        path: PathBuf,
        /// What plotters said.
        message: String,
    },
    /// Encoding a PNG failed.
    #[error("cannot write the image {}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: image::ImageError,
    },
    /// Encoding the GIF video failed.
    #[error("cannot write the video {}", path.display())]
    Gif {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: gif::EncodingError,
    },
    /// A video frame's size differs from the first frame's, or does not fit a GIF.
    #[error(
        "cannot write the video {}: frame {frame} is {width}x{height}, the video is {expected_width}x{expected_height} (GIF allows at most 65535x65535)",
        path.display()
    )]
    FrameSize {
        /// The file.
        path: PathBuf,
        /// The frame index.
        frame: u64,
        /// The frame's width, pixels.
        width: u32,
        /// The frame's height, pixels.
        height: u32,
        /// The video's width, pixels.
        expected_width: u32,
        /// The video's height, pixels.
        expected_height: u32,
    },
}

impl ReportError {
    /// An I/O error on `path`.
    pub(crate) fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> ReportError {
        let path = path.into();
        move |source| ReportError::Io { path, source }
    }
}
