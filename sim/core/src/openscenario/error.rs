//! Why an OpenSCENARIO file is refused: one line naming the file, the line and the element.

use std::path::PathBuf;

/// An OpenSCENARIO file carfollow does not read, and why.
#[derive(Debug, thiserror::Error)]
pub enum OscError {
    /// The file (or a catalog or road file it names) cannot be read.
    #[error("{path}: cannot read: {source}")]
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
        /// The XML reader's message.
        message: String,
    },
    /// An element carfollow refuses or cannot map: `message at FILE:LINE`.
    #[error("{message} at {}:{line}", path.display())]
    At {
        /// The file.
        path: PathBuf,
        /// 1-based line of the element.
        line: u32,
        /// What is refused and why, naming the element (`unsupported action
        /// <FollowTrajectoryAction>`).
        message: String,
    },
    /// A `--param NAME=VALUE` that cannot be applied.
    #[error("--param {assignment}: {message}")]
    Param {
        /// The assignment as given.
        assignment: String,
        /// Why.
        message: String,
    },
    /// The road file of `RoadNetwork/LogicFile`, refused.

    /// The road file of `RoadNetwork/LogicFile`, refused.
    #[error(transparent)]
    OpenDrive(#[from] crate::opendrive::OpenDriveError),
    /// Something about the file as a whole (no ego, no lead).
    #[error("{}: {message}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}
