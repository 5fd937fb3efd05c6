//! `sweep.json`, beside a sweep's results: which sweep they belong to (the file, its hash
//! with the command line's overrides) and its whole grid, so that `merge` can say which
//! points are missing and `--resume` can refuse results of another experiment. And
//! `failed*.txt`: the points of a run that could not complete, one a line.

use super::{Point, Sweep, SweepError};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The manifest's file name in a sweep's output folder.
pub const MANIFEST_FILE: &str = "sweep.json";

/// One point of the grid, as the manifest lists it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestPoint {
    /// Position in the grid order.
    pub index: usize,
    /// Stable id.
    pub id: String,
    /// Canonical description.
    pub point: String,
}

/// What a sweep folder's results are results of.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The sweep file, as given.
    pub sweep: String,
    /// [`Sweep::hash`]: the sweep file's text and the command line's overrides.
    pub hash: String,
    /// The command line's overrides.
    pub overrides: Vec<String>,
    /// The whole grid (every shard's points), in grid order.
    pub points: Vec<ManifestPoint>,
}

fn io<'a>(path: &'a Path, action: &'static str) -> impl FnOnce(std::io::Error) -> SweepError + 'a {
    move |error| SweepError::Io {
        path: path.to_owned(),
        action,
        error,
    }
}

impl Manifest {
    /// The manifest of `sweep` run with the command line's `overrides`.
    pub fn of(sweep: &Sweep, overrides: &[String]) -> Manifest {
        Manifest {
            sweep: sweep.path.display().to_string(),
            hash: sweep.hash.clone(),
            overrides: overrides.to_vec(),
            points: sweep
                .points
                .iter()
                .map(|p: &Point| ManifestPoint {
                    index: p.index,
                    id: p.id.clone(),
                    point: p.describe(),
                })
                .collect(),
        }
    }

    /// The manifest in `dir`, if there is one.
    pub fn read(dir: &Path) -> Result<Option<Manifest>, SweepError> {
        let path = dir.join(MANIFEST_FILE);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(io(&path, "cannot read the sweep manifest")(e)),
        };
        serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| SweepError::Row {
                path,
                line: e.line(),
                message: e.to_string(),
            })
    }

    /// Writes it to `dir` whole or not at all (shards of one sweep write the same file
    /// into the same folder).
    pub fn write(&self, dir: &Path) -> Result<PathBuf, SweepError> {
        let path = dir.join(MANIFEST_FILE);
        let tmp = dir.join(format!(".{MANIFEST_FILE}.{}", std::process::id()));
        let mut text = serde_json::to_string_pretty(self).expect("a manifest serialises");
        text.push('\n');
        std::fs::write(&tmp, text).map_err(io(&tmp, "cannot write the sweep manifest"))?;
        std::fs::rename(&tmp, &path).map_err(io(&path, "cannot write the sweep manifest"))?;
        Ok(path)
    }
}

/// A point that could not complete, as `failed*.txt` lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct FailedPoint {
    /// Position in the grid order.
    pub index: usize,
    /// Stable id.
    pub id: String,
    /// Canonical description.
    pub point: String,
    /// Why, on one line.
    pub error: String,
}

/// Writes `failed` to `path`, one tab-separated line each (`index`, `id`, `point`,
/// `error`); with none, removes the file, so a finished rerun leaves none behind.
pub fn write_failed(path: &Path, failed: &[FailedPoint]) -> Result<(), SweepError> {
    if failed.is_empty() {
        return match std::fs::remove_file(path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(io(path, "cannot remove the failed points file")(e))
            }
            _ => Ok(()),
        };
    }
    let mut text = String::new();
    for f in failed {
        let one_line = |s: &str| s.replace(['\t', '\n', '\r'], " ");
        text.push_str(&format!(
            "{}\t{}\t{}\t{}\n",
            f.index,
            f.id,
            one_line(&f.point),
            one_line(&f.error)
        ));
    }
    std::fs::write(path, text).map_err(io(path, "cannot write the failed points file"))
}

/// The failed points listed in every `failed*.txt` of `dir`.
pub fn read_failed(dir: &Path) -> Result<Vec<FailedPoint>, SweepError> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(out);
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("failed") && n.ends_with(".txt"))
        })
        .collect();
    files.sort();
    for file in files {
        let text =
            std::fs::read_to_string(&file).map_err(io(&file, "cannot read failed points"))?;
        for line in text.lines() {
            let mut parts = line.splitn(4, '\t');
            if let (Some(index), Some(id), Some(point), Some(error)) =
                (parts.next(), parts.next(), parts.next(), parts.next())
            {
                if let Ok(index) = index.parse() {
                    out.push(FailedPoint {
                        index,
                        id: id.into(),
                        point: point.into(),
                        error: error.into(),
                    });
                }
            }
        }
    }
    Ok(out)
}
