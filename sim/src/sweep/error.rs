//! What can go wrong with a sweep: its file, its points, its results files.

use std::path::PathBuf;
use thiserror::Error;

/// A sweep that cannot be read, validated, run or reported.
#[derive(Debug, Error)]
pub enum SweepError {
    /// Unreadable or unwritable file.
    #[error("{}: {action}: {error}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What was being done (`cannot read the sweep`, ...).
        action: &'static str,
        /// Why (in the message, not the chain: one line per error).
        error: std::io::Error,
    },
    /// Bad TOML, unknown field, wrong type.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The sweep file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong, naming the field.
        message: String,
    },
    /// A value that cannot be used.
    #[error("{}:{line}:{column}: `{field}` {message}", path.display())]
    Invalid {
        /// The sweep file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Dotted field path in the sweep file (`axes.tracker.lambda`, `seeds`, ...).
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A point whose scenario refuses its overrides (a bad axis path or value).
    #[error("{}:{line}:{column}: `{field}`: point {point}: {error}", path.display())]
    Point {
        /// The sweep file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The sweep field the bad override came from (`axes.<path>`, `set`, `scenarios`).
        field: String,
        /// The point's canonical description.
        point: String,
        /// The scenario's own error (boxed: it is large and rare; in the message, not the
        /// chain).
        error: Box<sim_core::ScenarioError>,
    },
    /// A malformed line in a results file.
    #[error("{}:{line}: not a result row: {message}", path.display())]
    Row {
        /// The results file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What serde said.
        message: String,
    },
    /// A point that could not run (the loop failed to start or went wrong).
    #[error("point {point}: {message}")]
    Run {
        /// The point's canonical description.
        point: String,
        /// The loop's error chain.
        message: String,
    },
    /// An OpenSCENARIO parameter distribution file that cannot be read as a sweep.
    #[error(transparent)]
    Distribution(#[from] sim_core::openscenario::OscError),
    /// Drawing or writing the report.
    #[error(transparent)]
    Report(#[from] crate::report::ReportError),
}
