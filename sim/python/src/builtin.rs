//! `carfollow.PaperTracker`: the paper's tracker (either mode) as a Python object, with the
//! same `reset` and `track` as a tracker of one's own, so that Python code can wrap it,
//! compare against it, or build on it.

use crate::scenario::{assignments, scenario_of};
use crate::types::{Camera, Estimate};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim_core::{BuiltinTracker, FrameTracker, TrackerInput};
use tracker::GrayView;

/// The paper's tracker with a scenario's settings (`[tracker]`: mode, λ, thresholds; the
/// built-in `nist-grounds` when no scenario is given).
#[pyclass(module = "carfollow", name = "PaperTracker")]
pub struct PaperTracker {
    inner: std::sync::Mutex<BuiltinTracker>,
    name: String,
}

#[pymethods]
impl PaperTracker {
    #[new]
    #[pyo3(signature = (scenario=None, overrides=None))]
    fn new(
        scenario: Option<&Bound<'_, PyAny>>,
        overrides: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let set = assignments(None, overrides)?;
        let s = match scenario {
            Some(scenario) => scenario_of(scenario, &set)?,
            None => sim_core::Scenario::builtin(&set).map_err(crate::errors::scenario_error)?,
        };
        let inner = BuiltinTracker::new(s.tracker.clone());
        Ok(PaperTracker {
            name: inner.name(),
            inner: std::sync::Mutex::new(inner),
        })
    }

    /// Its name in reports.
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    /// Starts it on `camera` at `start` (the teleoperator's placement; it needs cx, cy and
    /// scale). None: robust mode searches the image; the paper's mode cannot.
    #[pyo3(signature = (camera, start=None))]
    fn reset(&self, camera: &Camera, start: Option<Estimate>) -> PyResult<()> {
        let mut t = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        t.reset(&camera.inner, start.as_ref().map(|e| &e.inner))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Stages 1–8 on one frame (uint8, height × width): the estimate.
    fn track(
        &self,
        py: Python<'_>,
        frame: PyReadonlyArray2<'_, u8>,
        t: f64,
        camera: &Camera,
    ) -> PyResult<Option<Estimate>> {
        let shape = frame.shape();
        let (height, width) = (shape[0], shape[1]);
        let pixels = frame
            .as_slice()
            .map_err(|_| PyValueError::new_err("the frame must be a contiguous uint8 array"))?
            .to_vec();
        let mut t_ = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        let inner = &mut *t_;
        py.detach(move || {
            let view = GrayView::new(width, height, &pixels)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            let input = TrackerInput {
                frame: view,
                t_s: t,
                camera: &camera.inner,
                gyro_rad: camera.gyro_rad,
                lane: None,
                speed_mps: None,
            };
            inner
                .track(&input)
                .map(|e| e.map(|inner| Estimate { inner }))
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))
        })
    }
}
