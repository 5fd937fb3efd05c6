//! Which scenario Python means: a path to a scenario file, the name of a shipped scenario
//! (`"nist-grounds"`, `"weave"`), or scenario text (TOML) — with a seed and overrides, and
//! planned (as `carfollow check` plans it) before anything runs.

use crate::errors::scenario_error;
use pyo3::exceptions::{PyFileNotFoundError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use sim_core::{shipped_scenarios, Plan, Scenario};
use std::path::{Path, PathBuf};

/// A Python value as a TOML value, for an override (`{"tracker.lambda": 0.7}`).
fn toml_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<toml::Value>> =
            v.try_iter()?.map(|item| toml_value(key, &item?)).collect();
        return Ok(toml::Value::Array(items?));
    }
    Err(PyValueError::new_err(format!(
        "overrides[{key:?}] = {}: must be a bool, int, float, str or a list of them",
        v.repr().map_or("?".into(), |r| r.to_string())
    )))
}

/// The overrides as `--set` assignments, the seed's last.
pub(crate) fn assignments(
    seed: Option<u64>,
    overrides: Option<&Bound<'_, PyDict>>,
) -> PyResult<Vec<String>> {
    let mut set = Vec::new();
    if let Some(overrides) = overrides {
        for (k, v) in overrides.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err("overrides' keys must be str (\"tracker.lambda\")")
            })?;
            set.push(format!("{key}={}", toml_value(&key, &v)?));
        }
    }
    if let Some(seed) = seed {
        set.push(format!("seed={seed}"));
    }
    Ok(set)
}

/// The scenario `scenario` names, with `set` applied.
pub(crate) fn scenario_of(scenario: &Bound<'_, PyAny>, set: &[String]) -> PyResult<Scenario> {
    let text: Option<String> = scenario.extract::<String>().ok();
    let path: Option<PathBuf> = scenario.extract::<PathBuf>().ok();
    if let Some(text) = text.as_deref().filter(|t| t.contains('\n')) {
        // Scenario text: its target relative to here, or a shipped one.
        return Scenario::from_text(text, Path::new("<text>"), Path::new("."), set)
            .map_err(scenario_error);
    }
    if let Some(path) = path.as_ref().filter(|p| p.is_file()) {
        return Scenario::load(path, set).map_err(scenario_error);
    }
    if let Some(found) = text
        .as_deref()
        .and_then(|name| Scenario::shipped(name, set))
    {
        return found.map_err(scenario_error);
    }
    match (text, path) {
        (_, Some(path)) => Err(PyFileNotFoundError::new_err(format!(
            "{}: no such scenario file, nor a shipped scenario of that name ({})",
            path.display(),
            shipped_scenarios().collect::<Vec<_>>().join(", ")
        ))),
        _ => Err(PyTypeError::new_err(
            "scenario must be a path, a shipped scenario's name or scenario text",
        )),
    }
}

/// The plan of the scenario `scenario` names, with `seed` and `overrides`.
pub(crate) fn plan_of(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    seed: Option<u64>,
    overrides: Option<&Bound<'_, PyDict>>,
) -> PyResult<Plan> {
    let set = assignments(seed, overrides)?;
    let scenario = scenario_of(scenario, &set)?;
    py.detach(|| Plan::new(&scenario)).map_err(scenario_error)
}
