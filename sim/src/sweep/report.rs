//! The sweep's report over its rows: `table.csv` (one row per point), one PNG per numeric
//! axis (see `plots`), and `summary.md` naming the best value of each axis per scenario and
//! overall by [`BEST_RULE`].

use super::results::{axis_paths, scenario_order, FIGURES};
use super::{ResultRow, SweepError};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// How [`best_values`] chooses, as `summary.md` states it.
pub const BEST_RULE: &str = "the value with the least mean tracking-loss time (ground truth) \
over the seeds (and over the other axes' values); ties (within 1 ms) are broken by the least \
mean range error, then the least mean time outside the gap band, then the earlier value. \
Overall, each scenario's means count equally.";

/// An axis value and the mean of each of [`FIGURES`] there.
type ValueMeans = (serde_json::Value, [Option<f64>; FIGURES.len()]);

/// Ties in tracking-loss time closer than this are ties, seconds.
const TIE_S: f64 = 1e-3;

/// The best value of an axis for one scenario (or overall), with its mean figures.
#[derive(Clone, Debug, PartialEq)]
pub struct Best {
    /// The axis value.
    pub value: serde_json::Value,
    /// Mean of each of [`FIGURES`] at that value (`None` where no row had it).
    pub means: [Option<f64>; FIGURES.len()],
}

/// Mean of each figure per distinct axis value (in first-seen order) over `rows`.
fn means_by_value(rows: &[&ResultRow], axis: &str) -> Vec<ValueMeans> {
    let mut values: Vec<serde_json::Value> = Vec::new();
    for r in rows {
        if let Some(v) = r.params.get(axis) {
            if !values.contains(v) {
                values.push(v.clone());
            }
        }
    }
    values
        .into_iter()
        .map(|v| {
            let at: Vec<&&ResultRow> = rows
                .iter()
                .filter(|r| r.params.get(axis) == Some(&v))
                .collect();
            let means = std::array::from_fn(|i| {
                let xs: Vec<f64> = at.iter().filter_map(|r| r.figure(FIGURES[i].1)).collect();
                (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
            });
            (v, means)
        })
        .collect()
}

/// Picks by [`BEST_RULE`] among `(value, means)` in order.
fn pick(candidates: Vec<ValueMeans>) -> Option<Best> {
    let key = |m: &[Option<f64>; FIGURES.len()], i: usize| m[i].unwrap_or(f64::INFINITY);
    let mut best: Option<ValueMeans> = None;
    for (v, m) in candidates {
        let better = match &best {
            None => true,
            Some((_, b)) => {
                let (lost, best_lost) = (key(&m, 0), key(b, 0));
                if (lost - best_lost).abs() > TIE_S {
                    lost < best_lost
                } else if key(&m, 1) != key(b, 1) {
                    key(&m, 1) < key(b, 1)
                } else {
                    key(&m, 2) < key(b, 2)
                }
            }
        };
        if better {
            best = Some((v, m));
        }
    }
    best.map(|(value, means)| Best { value, means })
}

/// The best value of `axis` per scenario (in the rows' order) and overall, by [`BEST_RULE`].
pub fn best_values(rows: &[ResultRow], axis: &str) -> (Vec<(String, Best)>, Option<Best>) {
    let scenarios = scenario_order(rows);
    let mut per_scenario = Vec::new();
    let mut tables = Vec::new();
    for s in &scenarios {
        let mine: Vec<&ResultRow> = rows.iter().filter(|r| &r.scenario == s).collect();
        let means = means_by_value(&mine, axis);
        if let Some(b) = pick(means.clone()) {
            per_scenario.push((s.clone(), b));
        }
        tables.push(means);
    }
    // Overall: the mean over scenarios of each scenario's mean at that value.
    let mut values: Vec<serde_json::Value> = Vec::new();
    for t in &tables {
        for (v, _) in t {
            if !values.contains(v) {
                values.push(v.clone());
            }
        }
    }
    let overall = values
        .into_iter()
        .map(|v| {
            let means = std::array::from_fn(|i| {
                let xs: Vec<f64> = tables
                    .iter()
                    .filter_map(|t| t.iter().find(|(tv, _)| *tv == v).and_then(|(_, m)| m[i]))
                    .collect();
                (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
            });
            (v, means)
        })
        .collect();
    (per_scenario, pick(overall))
}

/// Writes `table.csv`, the plots and `summary.md` into `dir`; returns the paths written.
pub fn write_report(dir: &Path, rows: &[ResultRow]) -> Result<Vec<PathBuf>, SweepError> {
    let write = |name: &str, text: Vec<u8>| -> Result<PathBuf, SweepError> {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|error| SweepError::Io {
            path: path.clone(),
            action: "cannot write the report",
            error,
        })?;
        Ok(path)
    };
    std::fs::create_dir_all(dir).map_err(|error| SweepError::Io {
        path: dir.to_owned(),
        action: "cannot create the report folder",
        error,
    })?;
    let mut written = vec![write("table.csv", table_csv(rows))?];
    written.extend(super::plots::write_plots(dir, rows)?);
    written.push(write("summary.md", summary_md(rows).into_bytes())?);
    Ok(written)
}

/// Columns of `table.csv` after the axis columns: `(header, JSON pointer)`.
const CSV_FIGURES: [(&str, &str); 17] = [
    ("passed", "/passed"),
    ("duration_s", "/duration_s"),
    ("tracking_lost_s", "/tracking_lost_s"),
    ("tracking_loss_events", "/tracking_loss_events"),
    ("imprecise_share", "/imprecise_share"),
    ("tracker_coasting_s", "/tracker_coasting_s"),
    ("range_error_mean_abs_m", "/range_error_m/mean_abs"),
    ("range_error_p95_abs_m", "/range_error_m/p95_abs"),
    ("time_outside_gap_band_s", "/time_outside_gap_band_s"),
    ("gap_min_m", "/gap_m/min"),
    ("gap_mean_m", "/gap_m/mean"),
    ("gap_max_m", "/gap_m/max"),
    ("lateral_mean_abs_m", "/lateral_path_error_m/mean_abs"),
    ("lateral_max_abs_m", "/lateral_path_error_m/max_abs"),
    ("collisions", "/collisions"),
    ("distance_m", "/distance_m"),
    ("wall_s", "/wall_s"),
];

/// A JSON value as a cell: strings as they are, numbers as plain decimals (never `-0`),
/// nothing for `null` or a missing value.
fn json_cell(v: Option<&serde_json::Value>) -> String {
    match v {
        None | Some(serde_json::Value::Null) => String::new(),
        Some(serde_json::Value::String(s)) => s.clone(),
        // Adding 0.0 turns a −0.0 (a sum of no time) into 0.0.
        Some(serde_json::Value::Number(n)) if n.is_f64() => {
            format!("{}", n.as_f64().unwrap_or(f64::NAN) + 0.0)
        }
        Some(v) => v.to_string(),
    }
}

/// `table.csv`: a row per point, the axes' values, then [`CSV_FIGURES`].
fn table_csv(rows: &[ResultRow]) -> Vec<u8> {
    let axes = axis_paths(rows);
    let mut out = crate::report::csv_writer(Vec::new());
    let header = ["index", "id", "scenario", "seed"]
        .into_iter()
        .chain(axes.iter().map(String::as_str))
        .chain(CSV_FIGURES.iter().map(|(h, _)| *h));
    out.write_record(header).expect("writing to memory");
    for r in rows {
        let mut cells = vec![
            r.index.to_string(),
            r.id.clone(),
            r.scenario.clone(),
            r.seed.to_string(),
        ];
        cells.extend(axes.iter().map(|a| json_cell(r.params.get(a))));
        cells.extend(
            CSV_FIGURES
                .iter()
                .map(|(_, pointer)| json_cell(r.summary.pointer(pointer))),
        );
        out.write_record(&cells).expect("writing to memory");
    }
    out.into_inner().expect("writing to memory")
}

fn fmt(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| format!("{:.3}", v + 0.0))
}

fn summary_md(rows: &[ResultRow]) -> String {
    let scenarios = scenario_order(rows);
    let mut seeds: Vec<u64> = rows.iter().map(|r| r.seed).collect();
    seeds.sort();
    seeds.dedup();
    let mut md = String::from("# Sweep summary\n\n");
    let _ = writeln!(
        md,
        "{} points: scenarios {}; seeds {}.\n",
        rows.len(),
        scenarios.join(", "),
        seeds
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(md, "**Rule.** The best value of an axis is {BEST_RULE}\n");
    let header =
        "| | tracking lost (s) | range error (m) | outside gap band (s) | path deviation (m) | off > 2 px or 5 % (share) |";
    for axis in axis_paths(rows) {
        let (per, overall) = best_values(rows, &axis);
        let _ = writeln!(md, "## `{axis}`\n");
        let _ = writeln!(md, "Best value, with its mean figures:\n");
        let _ = writeln!(md, "| scenario | best `{axis}` {}", &header[2..]);
        let _ = writeln!(md, "|---|---|---|---|---|---|---|");
        let line = |md: &mut String, name: &str, b: &Best| {
            let _ = writeln!(
                md,
                "| {name} | {} | {} | {} | {} | {} | {} |",
                b.value,
                fmt(b.means[0]),
                fmt(b.means[1]),
                fmt(b.means[2]),
                fmt(b.means[3]),
                fmt(b.means[4])
            );
        };
        for (s, b) in &per {
            line(&mut md, s, b);
        }
        if let Some(b) = &overall {
            line(&mut md, "**overall**", b);
        }
        // Every value, per scenario: mean tracking-loss time / mean range error.
        let _ = writeln!(
            md,
            "\nMean tracking-loss time (s) / mean range error (m) at each value:\n"
        );
        let _ = writeln!(md, "| `{axis}` | {} |", scenarios.join(" | "));
        let _ = writeln!(md, "|---|{}", "---|".repeat(scenarios.len()));
        let tables: BTreeMap<&String, Vec<ValueMeans>> = scenarios
            .iter()
            .map(|s| {
                let mine: Vec<&ResultRow> = rows.iter().filter(|r| &r.scenario == s).collect();
                (s, means_by_value(&mine, &axis))
            })
            .collect();
        let mut values: Vec<serde_json::Value> = Vec::new();
        for r in rows {
            if let Some(v) = r.params.get(&axis) {
                if !values.contains(v) {
                    values.push(v.clone());
                }
            }
        }
        for v in values {
            let cells: Vec<String> = scenarios
                .iter()
                .map(|s| {
                    tables[s]
                        .iter()
                        .find(|(tv, _)| *tv == v)
                        .map_or("".into(), |(_, m)| format!("{} / {}", fmt(m[0]), fmt(m[1])))
                })
                .collect();
            let _ = writeln!(md, "| {v} | {} |", cells.join(" | "));
        }
        md.push('\n');
    }
    md
}
