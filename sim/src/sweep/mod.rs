//! Sweeps: one scenario setting varied over a grid of scenarios, seeds and parameter axes,
//! run on all cores (or sharded on a batch scheduler), with one JSON line per finished point
//! and a report (CSV table, PNG plots, Markdown summary) over the rows.
//!
//! A sweep file (`scenarios/sweeps/*.toml`) is parsed into a raw [`SweepFile`], then validated
//! into a [`Sweep`]: every point's overrides are applied to its scenario before anything runs,
//! so a bad axis path is refused up front, naming the path. Validation is the scenario's
//! own, the one `check` and `run` use, so a point that passes it runs.
//!
//! Beside the rows, `sweep.json` ([`Manifest`]) names the sweep (a hash of its file and the
//! command line's overrides) and its whole grid: `merge` lists the missing points from it,
//! and `--resume` refuses the rows of another sweep. Points that could not run are listed
//! in `failed*.txt`.
//!
//! An OpenSCENARIO `ParameterValueDistribution` file is a sweep too (`distribution`): its
//! runs are the points, each its scenario file with the run's parameter values.

mod distribution;
mod error;
mod file;
mod grid;
mod manifest;
mod plots;
mod report;
mod results;
mod run;

pub use error::SweepError;
pub use file::{Roles, SweepFile, SweepScenario};
pub use grid::{Axis, Point, Shard, Sweep, OSC_PARAM};
pub use manifest::{
    read_failed, write_failed, FailedPoint, Manifest, ManifestPoint, MANIFEST_FILE,
};
pub use report::{best_values, write_report, Best, BEST_RULE};
pub use results::{
    dedupe_sorted, merge_dirs, read_rows, ResultRow, ResultsWriter, FIGURES, RESULTS_FILE,
};
pub use run::{recording_path, run_point, run_points, serve_points};
