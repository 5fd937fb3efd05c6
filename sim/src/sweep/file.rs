//! The raw sweep file, as serde reads it, and the expansion of its axes.
//!
//! ```toml
//! scenarios = ["../weave.toml", "../hard-braking.toml"]   # relative to this file
//! seeds = [1, 2, 3]
//! set = ["duration_s=20"]                                  # common overrides, as --set
//! [axes]
//! tracker.lambda = { from = 0.5, to = 0.98, step = 0.04 }  # inclusive range
//! environment.sun.strength = [0.5, 1.0]                    # or a list of values
//! ```

use serde::Deserialize;
use std::path::PathBuf;

/// A sweep file as written (checked for unknown fields and types only).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Scenario files, relative to the sweep file.
    pub scenarios: Vec<String>,
    /// Seeds; every point runs once per seed.
    pub seeds: Vec<u64>,
    /// Overrides applied to every point before its axis values, as `--set` takes them.
    #[serde(default)]
    pub set: Vec<String>,
    /// Parameter axes by dotted path: a list of values or `{ from, to, step }`.
    #[serde(default)]
    pub axes: toml::Table,
}

/// One scenario of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepScenario {
    /// Its file, resolved against the sweep file's folder.
    pub path: PathBuf,
    /// Its `name` (unique within the sweep; it identifies the scenario in ids and rows).
    pub name: String,
    /// Its text, read once: every point loads the scenario from it.
    pub text: std::sync::Arc<str>,
    /// For an OpenSCENARIO file, the entities that are the chase and the lead.
    pub roles: Roles,
}

/// The entities of an OpenSCENARIO scenario that are the chase and the lead, as `run`'s
/// `--ego` and `--lead` name them (`None`: the default choice).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Roles {
    /// The entity that is the chase.
    pub ego: Option<String>,
    /// The entity that is the lead.
    pub lead: Option<String>,
}

impl Roles {
    /// Whether either is named.
    pub fn given(&self) -> bool {
        self.ego.is_some() || self.lead.is_some()
    }
}

/// An inclusive range `{ from, to, step }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RangeSpec {
    from: toml::Value,
    to: toml::Value,
    step: toml::Value,
}

/// The most values one axis may have (a typo such as `step = 0.0001` should not launch a
/// million runs).
const MAX_AXIS_VALUES: usize = 10_000;

/// Decimal places kept of a range's values: `from + i·step` is rounded to this, so
/// `0.5 + 2·0.04` is written `0.58`, not `0.5800000000000001`.
const RANGE_DECIMALS: i32 = 9;

/// An axis as read: its dotted path and its values.
pub(crate) type RawAxis = (String, Vec<toml::Value>);

/// The axes of a raw `[axes]` table as `(dotted path, value list or range)`, in the table's
/// (sorted) order. Nested tables are walked, so `tracker.lambda = [...]` (a dotted key) and
/// `"tracker.lambda" = [...]` (a quoted key) are the same axis. `Err((path, message))`.
pub(crate) fn flatten_axes(table: &toml::Table) -> Result<Vec<RawAxis>, (String, String)> {
    let mut out = Vec::new();
    walk(String::new(), table, &mut out)?;
    Ok(out)
}

fn walk(
    prefix: String,
    table: &toml::Table,
    out: &mut Vec<RawAxis>,
) -> Result<(), (String, String)> {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value {
            toml::Value::Array(values) => {
                if values.is_empty() {
                    return Err((path, "is an empty list: give at least one value".into()));
                }
                out.push((path, values.clone()));
            }
            toml::Value::Table(t) if ["from", "to", "step"].iter().any(|k| t.contains_key(*k)) => {
                let spec: RangeSpec = value.clone().try_into().map_err(|e: toml::de::Error| {
                    (
                        path.clone(),
                        format!("{} (a range is {{ from, to, step }})", e.message().trim()),
                    )
                })?;
                let values = expand(&spec).map_err(|m| (path.clone(), m))?;
                out.push((path, values));
            }
            toml::Value::Table(t) => walk(path, t, out)?,
            other => {
                return Err((
                    path,
                    format!("= {other}: an axis is a list of values or {{ from, to, step }}"),
                ))
            }
        }
    }
    Ok(())
}

/// The values of an inclusive range, counted by integers so that no float drift adds or
/// loses the last value: `n = floor((to − from)/step + ε) + 1` values `from + i·step`.
/// Integer bounds and step give integers.
fn expand(spec: &RangeSpec) -> Result<Vec<toml::Value>, String> {
    let as_f64 = |v: &toml::Value, name: &str| match v {
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::Float(f) => Ok(*f),
        other => Err(format!("`{name}` = {other}: must be a number")),
    };
    let (from, to, step) = (
        as_f64(&spec.from, "from")?,
        as_f64(&spec.to, "to")?,
        as_f64(&spec.step, "step")?,
    );
    if !(from.is_finite() && to.is_finite() && step.is_finite()) || step <= 0.0 {
        return Err(format!(
            "= {{ from = {from}, to = {to}, step = {step} }}: needs finite bounds and step > 0"
        ));
    }
    if to < from {
        return Err(format!(
            "= {{ from = {from}, to = {to} }}: needs from <= to"
        ));
    }
    // The ε forgives a step that does not divide the span exactly in binary (0.48 / 0.04).
    let steps = ((to - from) / step + 1e-6).floor();
    if steps + 1.0 > MAX_AXIS_VALUES as f64 {
        return Err(format!(
            "has {} values; at most {MAX_AXIS_VALUES} are allowed",
            steps + 1.0
        ));
    }
    let integers = [&spec.from, &spec.to, &spec.step]
        .iter()
        .all(|v| matches!(v, toml::Value::Integer(_)));
    let scale = 10f64.powi(RANGE_DECIMALS);
    Ok((0..=steps as i64)
        .map(|i| {
            if integers {
                toml::Value::Integer(from as i64 + i * step as i64)
            } else {
                let v = ((from + i as f64 * step) * scale).round() / scale;
                // Adding 0.0 turns a −0.0 into 0.0.
                toml::Value::Float(v + 0.0)
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes(text: &str) -> Vec<RawAxis> {
        let t: toml::Table = toml::from_str(text).unwrap();
        flatten_axes(&t).unwrap()
    }

    #[test]
    fn a_range_is_inclusive_without_drift() {
        let a = axes("tracker.lambda = { from = 0.5, to = 0.98, step = 0.04 }");
        assert_eq!(a[0].0, "tracker.lambda");
        let v: Vec<f64> = a[0].1.iter().map(|v| v.as_float().unwrap()).collect();
        assert_eq!(v.len(), 13);
        assert_eq!(v[2], 0.58);
        assert_eq!(*v.last().unwrap(), 0.98);
    }

    #[test]
    fn integer_ranges_stay_integers_and_quoted_keys_equal_dotted_ones() {
        let a = axes("\"loop.latency_ms\" = { from = 0, to = 200, step = 100 }");
        assert_eq!(a[0].0, "loop.latency_ms");
        assert_eq!(a[0].1, vec![0.into(), 100.into(), 200.into()]);
    }

    #[test]
    fn bad_ranges_name_the_axis() {
        for text in [
            "a.b = { from = 1.0, to = 0.0, step = 0.1 }",
            "a.b = { from = 0.0, to = 1.0, step = 0.0 }",
            "a.b = { from = 0.0, to = 1.0 }",
            "a.b = { from = 0.0, to = 1.0, step = 0.5, by = 2 }",
            "a.b = 3",
            "a.b = []",
        ] {
            let t: toml::Table = toml::from_str(text).unwrap();
            let (path, _) = flatten_axes(&t).unwrap_err();
            assert_eq!(path, "a.b", "{text}");
        }
    }
}
