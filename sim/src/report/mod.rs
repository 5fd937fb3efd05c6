//! The outputs of a closed-loop run, written from its [`FrameRecord`](sim_core::FrameRecord)s:
//! `frames.csv` (streamed), `summary.json`, PNG plots, an optional GIF video with PNG stills,
//! and `junit.xml` for CI systems. [`RunOutputs`] is the one entry point the loop calls.
//!
//! Everything here only reads records and writes files: identical records give byte-identical
//! files (the wall-clock time is an input, never read here).

mod error;
mod frames_csv;
mod junit;
mod outputs;
pub(crate) mod plots;
mod summary;
mod video;

pub use error::ReportError;
pub use frames_csv::{csv_writer, sigma2_column, FramesCsv, FRAMES_CSV_COLUMNS, TRAFFIC_COLUMNS};
pub use junit::{iso8601_utc, junit_xml, write_junit, JunitScenario};
pub use outputs::{OutputOptions, RunOutputs, VIDEO_OUTPUTS};
pub use plots::{write_plots, PlotTrace, PLOT_FILES};
pub use summary::{
    CollisionTime, Criterion, EndedBy, EventTime, GapStats, LateralError, RangeError, Summary,
    SummaryBuilder, TrafficSummary, SCHEMA_VERSION,
};
pub use video::{VideoWriter, GIF_DELAYS_CS};
