//! The one error of the OpenDRIVE reader: one line, naming the file, the line and the
//! element refused.

use std::path::PathBuf;

/// Why a road file cannot be driven.
#[derive(Debug, thiserror::Error)]
pub enum OpenDriveError {
    /// Unreadable file.
    #[error("{path}: cannot read road file: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not well-formed XML.
    #[error("{path}:{line}: not well-formed XML: {message}")]
    Xml {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u32,
        /// The XML parser's message.
        message: String,
    },
    /// An element carfollow does not follow, or a value out of its bounds.
    #[error("{path}:{line}: {element}: {reason}")]
    Refused {
        /// The file.
        path: PathBuf,
        /// 1-based line of the element.
        line: u32,
        /// The element as written, its attributes shortened (`<junction id="1">`).
        element: String,
        /// What is wrong, or why it is refused.
        reason: String,
    },
}
