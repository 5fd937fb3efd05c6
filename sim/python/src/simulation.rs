//! `carfollow.Simulation`: a scenario's run, stepped one camera frame at a time from Python,
//! with the interpreter released while the loop renders and steps the physics.

use crate::errors::run_error;
use crate::plugins::{PyController, PyTracker, Raised};
use crate::scenario::plan_of;
use crate::types::Estimate;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::{Simulation as Sim, SimulationOptions, Summary};
use sim_core::{ControllerChoice, FrameOutput, FrameRecord, TrackerChoice};
use sim_render::Backend;
use std::path::PathBuf;
use std::sync::Mutex;

/// Camera frames rendered at once by default: two with two cores or more.
pub(crate) fn default_renderers() -> u8 {
    if std::thread::available_parallelism().map_or(1, |n| n.get()) >= 2 {
        2
    } else {
        1
    }
}

/// A JSON-serialisable value as Python's (through `json`).
pub(crate) fn to_python<T: serde::Serialize>(py: Python<'_>, v: &T) -> PyResult<Py<PyAny>> {
    let text = serde_json::to_string(v)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot convert: {e}")))?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// A frame as a numpy array, uint8, (height, width).
pub(crate) fn frame_array<'py>(
    py: Python<'py>,
    image: &image::GrayImage,
) -> PyResult<Bound<'py, PyArray2<u8>>> {
    let (w, h) = image.dimensions();
    PyArray1::from_slice(py, image.as_raw()).reshape([h as usize, w as usize])
}

/// What the truth says of a frame (the recorder's view; never given to the plug-ins).
pub(crate) fn truth_dict<'py>(py: Python<'py>, r: &FrameRecord) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("cx", r.true_cx)?;
    d.set_item("cy", r.true_cy)?;
    d.set_item("scale", r.true_scale)?;
    d.set_item("range_m", r.true_range_m)?;
    d.set_item("lateral_m", r.true_lateral_m)?;
    d.set_item("in_view", r.target_in_view)?;
    d.set_item("partly_out_of_view", r.target_partly_out_of_view)?;
    d.set_item("gap_m", r.gap_m)?;
    d.set_item("lead_speed_mps", r.lead_speed_mps)?;
    d.set_item("chase_speed_mps", r.chase_speed_mps)?;
    d.set_item("lost", r.lost_truth)?;
    d.set_item("loss_cause", r.loss_cause.as_str())?;
    d.set_item("false_alarm", r.false_alarm)?;
    d.set_item("collision", r.collision)?;
    d.set_item("lateral_deviation_m", r.lateral_deviation_m)?;
    // With traffic: the vehicle in the chase's path and every vehicle (`vehicles`: name,
    // kind, xz, heading_rad, speed_mps, station_m, offset_m), the events, the contacts.
    if let Some(t) = &r.traffic {
        d.set_item("traffic", to_python(py, t)?)?;
    }
    Ok(d)
}

/// A scenario's run, stepped one camera frame at a time.
///
/// `scenario` is a path to a scenario file, the name of a shipped scenario (`"nist-grounds"`),
/// or scenario text; `seed` and `overrides` (`{"tracker.lambda": 0.7}`) change it as
/// `carfollow run --set` does. `tracker` is any object with `track(frame, t, camera)` (and
/// optionally `reset(camera, start)`), `controller` any with `control(input)`; `None` runs
/// the built-ins.
#[pyclass(module = "carfollow", name = "Simulation")]
pub struct Simulation {
    inner: Mutex<Option<Sim>>,
    raised: Raised,
    summary: Mutex<Option<Summary>>,
}

impl Simulation {
    /// The simulation, unless it has been finished.
    fn with<T>(&self, f: impl FnOnce(&mut Sim) -> PyResult<T>) -> PyResult<T> {
        let mut inner = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        match inner.as_mut() {
            Some(sim) => f(sim),
            None => Err(PyRuntimeError::new_err(
                "this simulation has finished (run() or finish() was called)",
            )),
        }
    }

    /// The last frame run, through `f`.
    fn last<T>(&self, f: impl FnOnce(Option<&FrameOutput>) -> PyResult<T>) -> PyResult<T> {
        self.with(|sim| f(sim.last()))
    }
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (scenario, seed=None, overrides=None, tracker=None, controller=None, renderers=None, whole_frames=true, backend=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        scenario: &Bound<'_, PyAny>,
        seed: Option<u64>,
        overrides: Option<&Bound<'_, PyDict>>,
        tracker: Option<Py<PyAny>>,
        controller: Option<Py<PyAny>>,
        renderers: Option<u8>,
        whole_frames: bool,
        backend: Option<&str>,
    ) -> PyResult<Simulation> {
        let raised = Raised::default();
        let tracker = match tracker {
            Some(t) => TrackerChoice::Plugin(Box::new(PyTracker::new(py, t, raised.clone())?)),
            None => TrackerChoice::Builtin,
        };
        let controller = match controller {
            Some(c) => {
                ControllerChoice::Plugin(Box::new(PyController::new(py, c, raised.clone())?))
            }
            None => ControllerChoice::Builtin,
        };
        let backend = Backend::choose(backend)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        let plan = plan_of(py, scenario, seed, overrides)?;
        let options = SimulationOptions {
            renderers: renderers.unwrap_or_else(default_renderers),
            tracker,
            controller,
            whole_frames,
            ..SimulationOptions::new(backend)
        };
        let sim = py
            .detach(|| Sim::new(plan, options))
            .map_err(|e| run_error(py, e, &raised))?;
        Ok(Simulation {
            inner: Mutex::new(Some(sim)),
            raised,
            summary: Mutex::new(None),
        })
    }

    /// Runs one camera frame (1/15 s, with the physics steps in it). Returns False when the
    /// scenario was over already.
    fn step(&self, py: Python<'_>) -> PyResult<bool> {
        let raised = &self.raised;
        self.with(|sim| {
            let sim: &mut Sim = sim;
            py.detach(move || sim.step().map(|out| out.is_some()))
                .map_err(|e| run_error(py, e, raised))
        })
    }

    /// Whether the run is over.
    #[getter]
    fn done(&self) -> PyResult<bool> {
        self.with(|sim| Ok(sim.done()))
    }

    /// The time of the last frame run, seconds (0 before the first).
    #[getter]
    fn t(&self) -> PyResult<f64> {
        self.last(|out| Ok(out.map_or(0.0, |o| o.record.t_s)))
    }

    /// The index of the last frame run (None before the first).
    #[getter]
    fn frame_index(&self) -> PyResult<Option<u64>> {
        self.last(|out| Ok(out.map(|o| o.record.frame)))
    }

    /// The last camera frame: numpy uint8, shape (242, 256), row-major; None before the
    /// first step.
    #[getter]
    fn frame<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<u8>>>> {
        self.last(|out| out.map(|o| frame_array(py, &o.image)).transpose())
    }

    /// The ground truth of the last frame (a dict; the plug-ins never see it). In a
    /// scenario with traffic, its "traffic" entry lists every vehicle ("vehicles": the
    /// chase, the lead and the actors, each with its name, kind, position, heading, speed
    /// and place on the road), the vehicle in the chase's path with the gap and the time to
    /// collision, the vehicle tracked, and the events and contacts since the last frame.
    #[getter]
    fn truth(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        self.last(|out| {
            out.map(|o| truth_dict(py, &o.record).map(|d| d.into_any().unbind()))
                .transpose()
        })
    }

    /// The tracker's estimate of the last frame (a dict; None when it had none).
    #[getter]
    fn estimate(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        self.last(|out| {
            let Some(o) = out else { return Ok(None) };
            let Some(e) = o.estimate else { return Ok(None) };
            let d = PyDict::new(py);
            d.set_item("range_m", e.range_m)?;
            d.set_item("lateral_m", e.lateral_m)?;
            d.set_item("vertical_m", e.vertical_m)?;
            d.set_item("cx", e.cx)?;
            d.set_item("cy", e.cy)?;
            d.set_item("scale", e.scale)?;
            d.set_item("status", e.status.as_str())?;
            Ok(Some(d.into_any().unbind()))
        })
    }

    /// The last frame's estimate as a carfollow.Estimate (None when it had none).
    #[getter]
    fn estimate_object(&self) -> PyResult<Option<Estimate>> {
        self.last(|out| Ok(out.and_then(|o| o.estimate).map(|inner| Estimate { inner })))
    }

    /// The last frame's record: every column of frames.csv (a dict).
    #[getter]
    fn record(&self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        self.last(|out| out.map(|o| to_python(py, &o.record)).transpose())
    }

    /// The scenario's name.
    #[getter]
    fn name(&self) -> PyResult<String> {
        self.with(|sim| Ok(sim.scenario().name.clone()))
    }

    /// How many frames the run has.
    #[getter]
    fn frames(&self) -> PyResult<u64> {
        self.with(|sim| Ok(sim.looped().frames()))
    }

    /// Runs to the end and returns the summary (as summary.json has it). With `out`, the
    /// usual outputs are written there as the run goes: frames.csv (with the frames run so
    /// far), summary.json, the plots and junit.xml. The simulation is finished after it.
    #[pyo3(signature = (out=None))]
    fn run(&self, py: Python<'_>, out: Option<PathBuf>) -> PyResult<Py<PyAny>> {
        let raised = &self.raised;
        let mut inner = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        let Some(mut sim) = inner.take() else {
            return Err(PyRuntimeError::new_err(
                "this simulation has finished already",
            ));
        };
        let summary = py
            .detach(|| -> Result<Summary, sim::RunError> {
                if let Some(dir) = &out {
                    sim.write_to(dir)?;
                }
                // Nothing looks at the frames any more: only what the tracker reads.
                sim.set_whole_frames(false);
                while sim.step()?.is_some() {}
                sim.finish().map(|(summary, _)| summary)
            })
            .map_err(|e| run_error(py, e, raised))?;
        let dict = to_python(py, &summary)?;
        *self.summary.lock().unwrap_or_else(|p| p.into_inner()) = Some(summary);
        Ok(dict)
    }

    /// Writes the usual outputs of the frames run so far into `dir` (frames.csv,
    /// summary.json, the plots, junit.xml) and returns the summary.
    fn write_outputs(&self, py: Python<'_>, dir: PathBuf) -> PyResult<Py<PyAny>> {
        let raised = &self.raised;
        let summary = self.with(|sim| {
            let sim: &mut Sim = sim;
            py.detach(move || sim.write_outputs(&dir))
                .map_err(|e| run_error(py, e, raised))
        })?;
        to_python(py, &summary)
    }

    /// The tracker's name.
    #[getter]
    fn tracker_name(&self) -> PyResult<String> {
        self.with(|sim| Ok(sim.looped().tracker_name()))
    }

    /// The controller's name.
    #[getter]
    fn controller_name(&self) -> PyResult<String> {
        self.with(|sim| Ok(sim.looped().controller_name()))
    }

    fn __repr__(&self) -> String {
        let inner = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        match inner.as_ref() {
            Some(sim) => format!(
                "Simulation({:?}, frame {}/{})",
                sim.scenario().name,
                sim.looped().frame(),
                sim.looped().frames()
            ),
            None => "Simulation(finished)".into(),
        }
    }
}
