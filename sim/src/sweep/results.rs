//! `results.jsonl`: one JSON line per finished point, appended and flushed as it finishes,
//! through one writer so lines never interleave. Reading tolerates a truncated last line (a
//! run killed mid-write); merging dedupes by id and sorts by grid order.

use super::SweepError;
use crate::report::Summary;
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The results file of an unsharded sweep (a shard writes [`super::Shard::file_name`]).
pub const RESULTS_FILE: &str = "results.jsonl";

/// One finished point: its parameters and its run's `summary.json` figures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultRow {
    /// The point's stable id.
    pub id: String,
    /// Its position in the grid order.
    pub index: usize,
    /// Its canonical description (`weave seed=1 tracker.lambda=0.5`).
    pub point: String,
    /// Scenario name.
    pub scenario: String,
    /// Seed.
    pub seed: u64,
    /// Axis path → value.
    pub params: serde_json::Map<String, serde_json::Value>,
    /// The run's [`Summary`], as in `summary.json`.
    pub summary: serde_json::Value,
    /// The sweep's [`super::Sweep::hash`] (its file and the command line's overrides), so
    /// that `--resume` and `merge` can tell rows of another sweep. Empty in rows written
    /// before it was recorded.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub sweep_hash: String,
}

impl ResultRow {
    /// The row of a point of the sweep with hash `sweep_hash`, and its summary.
    pub fn new(point: &super::Point, summary: &Summary, sweep_hash: &str) -> ResultRow {
        ResultRow {
            sweep_hash: sweep_hash.to_owned(),
            id: point.id.clone(),
            index: point.index,
            point: point.describe(),
            scenario: point.scenario_name.clone(),
            seed: point.seed,
            params: point
                .params
                .iter()
                .map(|(p, v)| {
                    (
                        p.clone(),
                        serde_json::to_value(v).expect("TOML values are JSON values"),
                    )
                })
                .collect(),
            summary: serde_json::to_value(summary).expect("a summary serialises"),
        }
    }

    /// A number of the summary by JSON pointer (`/range_error_m/mean_abs`); `None` when
    /// absent or `null`.
    pub fn figure(&self, pointer: &str) -> Option<f64> {
        self.summary.pointer(pointer).and_then(|v| v.as_f64())
    }

    /// An axis value as a number, if it is one.
    pub fn param(&self, path: &str) -> Option<f64> {
        self.params.get(path).and_then(|v| v.as_f64())
    }
}

/// Appends rows to a results file, one whole line per write, flushed at once.
pub struct ResultsWriter {
    path: PathBuf,
    file: Mutex<File>,
}

impl ResultsWriter {
    /// Opens `path` for appending. With `keep_bytes`, first cuts the file to that length
    /// (dropping a truncated last line left by a killed run); without, starts it empty.
    pub fn open(path: &Path, keep_bytes: Option<u64>) -> Result<ResultsWriter, SweepError> {
        let io = |error| SweepError::Io {
            path: path.to_owned(),
            action: "cannot write results",
            error,
        };
        let file = OpenOptions::new()
            .create(true)
            .write(true)
            .truncate(false)
            .open(path)
            .map_err(io)?;
        file.set_len(keep_bytes.unwrap_or(0)).map_err(io)?;
        drop(file);
        let file = OpenOptions::new().append(true).open(path).map_err(io)?;
        Ok(ResultsWriter {
            path: path.to_owned(),
            file: Mutex::new(file),
        })
    }

    /// Writes one row as one line and flushes it.
    pub fn append(&self, row: &ResultRow) -> Result<(), SweepError> {
        let mut line = serde_json::to_string(row).expect("a row serialises");
        line.push('\n');
        let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
        file.write_all(line.as_bytes())
            .and_then(|()| file.flush())
            .map_err(|error| SweepError::Io {
                path: self.path.clone(),
                action: "cannot write results",
                error,
            })
    }
}

/// The rows of a results file, and the length of its complete lines in bytes. A last line
/// without its newline (a killed run) is ignored; a malformed complete line is an error. A
/// missing file has no rows.
pub fn read_rows(path: &Path) -> Result<(Vec<ResultRow>, u64), SweepError> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((Vec::new(), 0)),
        Err(error) => {
            return Err(SweepError::Io {
                path: path.to_owned(),
                action: "cannot read results",
                error,
            })
        }
    };
    let complete = text.rfind('\n').map_or(0, |i| i + 1);
    let mut rows = Vec::new();
    for (i, line) in text[..complete].lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        rows.push(serde_json::from_str(line).map_err(|e| SweepError::Row {
            path: path.to_owned(),
            line: i + 1,
            message: e.to_string(),
        })?);
    }
    Ok((rows, complete as u64))
}

/// Every row of the `results*.jsonl` files in `dirs`, deduplicated by id (the first seen
/// wins) and sorted by grid order.
pub fn merge_dirs(dirs: &[PathBuf]) -> Result<Vec<ResultRow>, SweepError> {
    let mut rows = Vec::new();
    for dir in dirs {
        let entries = std::fs::read_dir(dir).map_err(|error| SweepError::Io {
            path: dir.clone(),
            action: "cannot list results",
            error,
        })?;
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("results") && n.ends_with(".jsonl"))
            })
            .collect();
        files.sort();
        for file in files {
            rows.extend(read_rows(&file)?.0);
        }
    }
    Ok(dedupe_sorted(rows))
}

/// Dedupes by sweep and id (first wins) and sorts by grid order, then id. Rows of two
/// sweeps are both kept, so that whoever merges them sees two sweeps (and refuses them).
pub fn dedupe_sorted(rows: Vec<ResultRow>) -> Vec<ResultRow> {
    let mut seen = std::collections::BTreeSet::new();
    let mut out: Vec<ResultRow> = rows
        .into_iter()
        .filter(|r| seen.insert((r.sweep_hash.clone(), r.id.clone())))
        .collect();
    out.sort_by(|a, b| a.index.cmp(&b.index).then_with(|| a.id.cmp(&b.id)));
    out
}

/// A figure of a point's summary the report compares: `(short name, JSON pointer into the
/// summary, axis label)`.
pub const FIGURES: [(&str, &str, &str); 5] = [
    (
        "tracking_lost_s",
        "/tracking_lost_s",
        "tracking lost (s, ground truth)",
    ),
    (
        "range_error_m",
        "/range_error_m/mean_abs",
        "range error, mean |err| while tracked (m)",
    ),
    (
        "gap_outside_band_s",
        "/time_outside_gap_band_s",
        "time outside the gap band (s)",
    ),
    (
        "path_deviation_m",
        "/lateral_path_error_m/mean_abs",
        "path deviation, mean |lateral| (m)",
    ),
    (
        "imprecise_share",
        "/imprecise_share",
        "share of frames off by > 2 px or > 5 % in scale",
    ),
];

/// Scenario names in the order they first appear.
pub(super) fn scenario_order(rows: &[ResultRow]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for r in rows {
        if !names.contains(&r.scenario) {
            names.push(r.scenario.clone());
        }
    }
    names
}

/// Axis paths in the rows (sorted).
pub(super) fn axis_paths(rows: &[ResultRow]) -> Vec<String> {
    let mut paths: Vec<String> = rows.iter().flat_map(|r| r.params.keys().cloned()).collect();
    paths.sort();
    paths.dedup();
    paths
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(hash: &str, id: &str, index: usize) -> ResultRow {
        ResultRow {
            id: id.into(),
            index,
            point: String::new(),
            scenario: "s".into(),
            seed: 1,
            params: serde_json::Map::new(),
            summary: serde_json::Value::Null,
            sweep_hash: hash.into(),
        }
    }

    /// A point of one sweep seen twice is one row; a row of another sweep with the same id
    /// stays, so that a merge sees two sweeps.
    #[test]
    fn dedupe_keeps_rows_of_other_sweeps() {
        let rows = dedupe_sorted(vec![
            row("a", "p1", 1),
            row("a", "p1", 1),
            row("b", "p1", 1),
        ]);
        let hashes: Vec<&str> = rows.iter().map(|r| r.sweep_hash.as_str()).collect();
        assert_eq!(hashes, ["a", "b"]);
    }
}
