//! carfollow's errors as Python exceptions: bad input is `ValueError` with the line
//! `carfollow check` prints, a missing file `FileNotFoundError`, a run that could not go on
//! `RuntimeError`, and a plug-in's own exception is raised again as it was, with where the
//! run was added to its message.

use crate::plugins::Raised;
use pyo3::exceptions::{PyFileNotFoundError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use sim::RunError;
use sim_core::{LoopError, ScenarioError};

/// A scenario that cannot be used.
pub(crate) fn scenario_error(e: ScenarioError) -> PyErr {
    match &e {
        ScenarioError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(e.to_string())
        }
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A run that stopped: a plug-in's own exception when one raised, else `RuntimeError`.
pub(crate) fn run_error(py: Python<'_>, e: RunError, raised: &Raised) -> PyErr {
    located(py, e, raised, None)
}

/// The same for the sub-environment `env` of a vector environment: its message names the
/// environment, and the exception carries it as `env_index`.
pub(crate) fn env_run_error(py: Python<'_>, e: RunError, raised: &Raised, env: usize) -> PyErr {
    with_env(py, located(py, e, raised, Some(env)), env)
}

/// `err` (raised by the sub-environment `env`) with `env_index` set on it, when it takes
/// attributes.
pub(crate) fn with_env(py: Python<'_>, err: PyErr, env: usize) -> PyErr {
    let _ = err.value(py).setattr("env_index", env);
    err
}

/// A run's error, its place said (with the sub-environment's index, when there is one).
fn located(py: Python<'_>, e: RunError, raised: &Raised, env: Option<usize>) -> PyErr {
    let env_said = env.map_or(String::new(), |k| format!("in environment {k}, "));
    let place = match &e {
        RunError::Loop(LoopError::Plugin {
            what, frame, t_s, ..
        }) => Some(match (frame, t_s) {
            (Some(k), Some(t)) => format!("in the {what} at frame {k}, t = {t:.3} s"),
            (Some(k), None) => format!("in the {what} at frame {k}"),
            _ => format!("in the {what}, before the first frame"),
        }),
        _ => None,
    };
    match (raised.take(), place) {
        (Some(err), Some(place)) => with_place(py, err, &format!("{env_said}{place}")),
        _ => match env {
            Some(k) => PyRuntimeError::new_err(format!("environment {k}: {e}")),
            None => PyRuntimeError::new_err(e.to_string()),
        },
    }
}

/// `err` with `(carfollow: PLACE)` added to its message: to its first argument when that is
/// text, else as a note (PEP 678).
pub(crate) fn with_place(py: Python<'_>, err: PyErr, place: &str) -> PyErr {
    let value = err.value(py);
    let added = (|| -> PyResult<bool> {
        let args = value.getattr("args")?;
        let args = args.cast::<PyTuple>()?;
        let Ok(first) = args.get_item(0).and_then(|a| a.extract::<String>()) else {
            return Ok(false);
        };
        let mut items: Vec<Py<PyAny>> = vec![format!("{first} (carfollow: {place})")
            .into_pyobject(py)?
            .into_any()
            .unbind()];
        for item in args.iter().skip(1) {
            items.push(item.unbind());
        }
        value.setattr("args", PyTuple::new(py, items)?)?;
        Ok(true)
    })()
    .unwrap_or(false);
    if !added {
        let _ = value.call_method1("add_note", (format!("carfollow: {place}"),));
    }
    err
}
