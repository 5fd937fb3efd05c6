//! Trackers and controllers written in Python, in the loop: any object with
//! `track(frame, t, camera)` (and optionally `reset(camera, start)`), and any object with
//! `control(input)`. They are called with the interpreter attached, from whichever thread
//! of the loop runs them; an exception they raise is kept, ends the run, and is raised again
//! from the call that ran it, with the frame and time added.

use crate::types::{Camera, Command, ControlInput, Estimate};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyString;
use sim_core::{CameraModel, Controller, FrameTracker, PluginError, TrackerInput};
use std::sync::{Arc, Mutex};

/// The first exception a plug-in raised, kept for the caller.
#[derive(Clone, Debug, Default)]
pub(crate) struct Raised(Arc<Mutex<Option<PyErr>>>);

impl Raised {
    /// Keeps `e` (the first one only) and says it as the loop's plug-in error.
    fn keep(&self, e: PyErr, what: &str) -> PluginError {
        let message = Python::attach(|py| {
            let kind = e
                .get_type(py)
                .name()
                .map_or_else(|_| "exception".to_string(), |n| n.to_string());
            format!("{what} raised {kind}: {}", e.value(py))
        });
        let mut slot = self.0.lock().unwrap_or_else(|p| p.into_inner());
        slot.get_or_insert(e);
        PluginError::Failed(message)
    }

    /// The exception kept, if any (taken: it is raised once).
    pub(crate) fn take(&self) -> Option<PyErr> {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).take()
    }
}

/// The name a plug-in goes by in reports: its `name` attribute, or its class's name.
fn name_of(py: Python<'_>, obj: &Py<PyAny>) -> String {
    let obj = obj.bind(py);
    obj.getattr("name")
        .ok()
        .and_then(|n| n.extract::<String>().ok())
        .or_else(|| {
            obj.get_type()
                .name()
                .ok()
                .map(|n: Bound<'_, PyString>| n.to_string())
        })
        .unwrap_or_else(|| "python".into())
}

/// Checks that `obj` has a callable `method`.
fn needs(py: Python<'_>, obj: &Py<PyAny>, method: &str, role: &str) -> PyResult<()> {
    let callable = obj.bind(py).getattr(method).is_ok_and(|m| m.is_callable());
    if callable {
        Ok(())
    } else {
        Err(PyTypeError::new_err(format!(
            "{role}: {} has no method `{method}`",
            obj.bind(py)
                .repr()
                .map_or("the object".into(), |r| r.to_string())
        )))
    }
}

/// A Python tracker.
pub(crate) struct PyTracker {
    obj: Py<PyAny>,
    name: String,
    has_reset: bool,
    raised: Raised,
}

impl PyTracker {
    /// The tracker `obj` (it must have `track`), its exceptions kept in `raised`.
    pub(crate) fn new(py: Python<'_>, obj: Py<PyAny>, raised: Raised) -> PyResult<PyTracker> {
        needs(py, &obj, "track", "tracker")?;
        let has_reset = obj.bind(py).getattr("reset").is_ok_and(|m| m.is_callable());
        Ok(PyTracker {
            name: name_of(py, &obj),
            obj,
            has_reset,
            raised,
        })
    }
}

impl FrameTracker for PyTracker {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn reset(
        &mut self,
        camera: &CameraModel,
        start: Option<&sim_core::Estimate>,
    ) -> Result<(), PluginError> {
        if !self.has_reset {
            return Ok(());
        }
        let camera = Camera {
            inner: camera.clone(),
            gyro_rad: None,
        };
        let start = start.map(|&inner| Estimate { inner });
        Python::attach(|py| {
            self.obj
                .call_method1(py, "reset", (camera, start))
                .map(drop)
        })
        .map_err(|e| self.raised.keep(e, "the tracker's reset()"))
    }

    fn track(
        &mut self,
        input: &TrackerInput<'_>,
    ) -> Result<Option<sim_core::Estimate>, PluginError> {
        let camera = Camera {
            inner: input.camera.clone(),
            gyro_rad: input.gyro_rad,
        };
        let (width, height) = (input.frame.width(), input.frame.height());
        Python::attach(|py| -> PyResult<Option<sim_core::Estimate>> {
            let frame = PyArray1::from_slice(py, input.frame.pixels()).reshape([height, width])?;
            let out = self
                .obj
                .call_method1(py, "track", (frame, input.t_s, camera))?;
            if out.is_none(py) {
                return Ok(None);
            }
            let estimate: Estimate = out.extract(py).map_err(|_| {
                PyTypeError::new_err(format!(
                    "track() must return a carfollow.Estimate or None, not {}",
                    out.bind(py)
                        .get_type()
                        .name()
                        .map_or("something else".into(), |n| n.to_string())
                ))
            })?;
            Ok(Some(estimate.inner))
        })
        .map_err(|e| self.raised.keep(e, "the tracker's track()"))
    }
}

/// A Python controller.
pub(crate) struct PyController {
    obj: Py<PyAny>,
    name: String,
    raised: Raised,
}

impl PyController {
    /// The controller `obj` (it must have `control`), its exceptions kept in `raised`.
    pub(crate) fn new(py: Python<'_>, obj: Py<PyAny>, raised: Raised) -> PyResult<PyController> {
        needs(py, &obj, "control", "controller")?;
        Ok(PyController {
            name: name_of(py, &obj),
            obj,
            raised,
        })
    }
}

impl Controller for PyController {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn control(
        &mut self,
        input: &sim_core::ControlInput,
    ) -> Result<sim_core::Command, PluginError> {
        let input = ControlInput { inner: *input };
        Python::attach(|py| -> PyResult<sim_core::Command> {
            let out = self.obj.call_method1(py, "control", (input,))?;
            let command: Command = out.extract(py).map_err(|_| {
                PyTypeError::new_err(format!(
                    "control() must return a carfollow.Command, not {}",
                    out.bind(py)
                        .get_type()
                        .name()
                        .map_or("something else".into(), |n| n.to_string())
                ))
            })?;
            Ok(command.inner)
        })
        .map_err(|e| self.raised.keep(e, "the controller's control()"))
    }
}
