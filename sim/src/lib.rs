//! carfollow's outputs and tools over the loop: the reports of a run (`frames.csv`,
//! `summary.json` with the `[expect]` verdict, plots, `junit.xml`, the video), recordings
//! that open in Foxglove and replay through the tracker, sweeps over scenarios, seeds and
//! parameters, and the tracker alone on recorded frames. The `carfollow` command line
//! (`main.rs`) is built on it.
//!
//! It sits on `sim-core` (scenarios, the plan, the closed loop) and `sim-render` (the
//! camera world), and is the one layer that writes files.
#![warn(missing_docs)]

mod overlay;
mod recording;
mod report;
mod simulation;
mod sweep;
mod track;

pub use overlay::{draw_frame_overlay, draw_overlay, line, OverlayColour};
pub use recording::{
    replay, topics, ControllerState, GroundTruth, LiveOptions, RecordError, Recorder,
    RecorderOptions, ReplayError, ReplayJob, ReplaySetup, ReplaySummary, SettingChange, Tape,
    TrackerInput, TrackerInputDecoded, TrackerState, TrackerStateDecoded, MCAP_FILE, METADATA_NAME,
    REPLAY_CSV_COLUMNS,
};
pub use report::{
    iso8601_utc, junit_xml, sigma2_column, write_junit, write_plots, CollisionTime, Criterion,
    EventTime, FramesCsv, GapStats, JunitScenario, LateralError, OutputOptions, PlotTrace,
    RangeError, ReportError, RunOutputs, Summary, SummaryBuilder, TrafficSummary,
    FRAMES_CSV_COLUMNS, GIF_DELAYS_CS, PLOT_FILES, SCHEMA_VERSION, TRAFFIC_COLUMNS, VIDEO_OUTPUTS,
};
pub use simulation::{RunError, Simulation, SimulationOptions};
pub use sweep::{
    best_values, dedupe_sorted, merge_dirs, read_failed, read_rows, recording_path, run_point,
    run_points, serve_points, write_failed, write_report, Axis, Best, FailedPoint, Manifest,
    ManifestPoint, Point, ResultRow, ResultsWriter, Roles, Shard, Sweep, SweepError, SweepFile,
    SweepScenario, BEST_RULE, FIGURES, MANIFEST_FILE, OSC_PARAM, RESULTS_FILE,
};
pub use track::{
    frame_files, parse_location, read_frame, run as track, TrackJob, TrackOutputError, TrackSummary,
};
