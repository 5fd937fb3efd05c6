//! The native core of `carfollow/Follow-v0` (`carfollow.env.FollowEnv` is the Gymnasium
//! face of it): one step is one camera frame, the agent's action goes through a delay line
//! with the scenario's latency, jitter and drops (as the built-in tracker's estimates do),
//! and the loop renders the next frame while the agent thinks.
//!
//! An action taken on frame k's observation is applied from the physics step at which an
//! estimate of frame k would reach the controller. With the scenario's latency of at least
//! one frame, the physics to frame k + 1 needs no action of frame k, so frame k + 1 is
//! rendered in the background as soon as frame k has been returned.

use crate::episode::{
    clamped, latency_ok, ActionKind, Episode, EpisodeOptions, Planned, IN_FLIGHT,
};
use crate::errors::run_error;
use crate::plugins::{PyTracker, Raised};
use crate::scenario::plan_of;
use crate::simulation::{frame_array, to_python, truth_dict};
use numpy::PyArray1;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim_core::{ControlInput, EstimateStatus};
use sim_render::Backend;
use std::collections::VecDeque;
use std::sync::Mutex;

/// The estimate observation's length: 8 values, then the actions in flight (2 each).
pub(crate) const ESTIMATE_LEN: usize = 8 + 2 * IN_FLIGHT;
/// An estimate's age when there is none, seconds (the observation's upper bound).
const NO_ESTIMATE_AGE_S: f64 = 10.0;

/// The environment's native core: builds an episode at each reset, steps it a frame at a
/// time with the interpreter released.
#[pyclass(module = "carfollow")]
pub struct GymCore {
    scenario: Py<PyAny>,
    overrides: Option<Py<PyDict>>,
    tracker: Option<Py<PyAny>>,
    options: EpisodeOptions,
    episode: Mutex<Option<Episode>>,
    raised: Raised,
}

#[pymethods]
impl GymCore {
    #[new]
    #[pyo3(signature = (scenario, overrides=None, action="drive", camera=true, backend=None, tracker=None))]
    fn new(
        py: Python<'_>,
        scenario: Py<PyAny>,
        overrides: Option<Py<PyDict>>,
        action: &str,
        camera: bool,
        backend: Option<&str>,
        tracker: Option<Py<PyAny>>,
    ) -> PyResult<GymCore> {
        if let Some(t) = &tracker {
            // Checked here, so that a tracker without `track` fails before any reset.
            PyTracker::new(py, t.clone_ref(py), Raised::default())?;
        }
        Ok(GymCore {
            scenario,
            overrides,
            tracker,
            options: episode_options(action, camera, backend)?,
            episode: Mutex::new(None),
            raised: Raised::default(),
        })
    }

    /// Checks the scenario (as `carfollow check` does) and that its latency lets an action
    /// be applied after the frame it answers: returns the number of frames of an episode.
    fn check(&self, py: Python<'_>) -> PyResult<u64> {
        check_scenario(py, &self.scenario, self.overrides.as_ref())
    }

    /// Starts an episode with the scenario's `seed` (its own when None), ending the last one
    /// first: a reset that fails leaves no episode, and `step()` asks for a reset.
    #[pyo3(signature = (seed=None))]
    fn reset(&self, py: Python<'_>, seed: Option<u64>) -> PyResult<()> {
        let planned = plan_episode(
            py,
            &self.scenario,
            self.overrides.as_ref(),
            self.tracker.as_ref(),
            seed,
            &self.raised,
        )?;
        let options = self.options;
        // The old episode goes first, with the interpreter released: closing its renderer
        // takes tens of milliseconds, and two renderers need not be held at once.
        let old = self
            .episode
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        let episode = py
            .detach(move || {
                drop(old);
                Episode::start(planned, options, false)
            })
            .map_err(|e| run_error(py, e, &self.raised))?;
        *self.episode.lock().unwrap_or_else(|p| p.into_inner()) = Some(episode);
        Ok(())
    }

    /// Takes an action on the last observation and runs to the next frame. Returns
    /// `(reward, terminated, truncated)`.
    fn step(&self, py: Python<'_>, steer: f64, longitudinal: f64) -> PyResult<(f64, bool, bool)> {
        let action = clamped(steer, longitudinal)?;
        let mut slot = self.episode.lock().unwrap_or_else(|p| p.into_inner());
        let e = slot
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("reset() before step()"))?;
        let o = py
            .detach(move || e.advance(action))
            .map_err(|err| run_error(py, err, &self.raised))?;
        Ok((o.reward, o.terminated, o.truncated))
    }

    /// The last frame, uint8 (242, 256).
    fn frame<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<u8>>> {
        self.with(|e| frame_array(py, &e.last.image))
    }

    /// The estimate observation (see `carfollow.env.FollowEnv`), float32.
    fn estimate_observation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        self.with(|e| Ok(PyArray1::from_vec(py, observed(e).to_vec())))
    }

    /// What the step's `info` holds: the time, the frame, the truth (for scoring; the agent
    /// should not act on it), the tracker's estimate, the actions in flight.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with(|e| info(py, e))
    }

    /// The number of frames of an episode.
    fn frames(&self) -> PyResult<u64> {
        self.with(|e| Ok(e.looped.frames()))
    }

    /// Ends the episode (frees the renderer).
    fn close(&self) {
        *self.episode.lock().unwrap_or_else(|p| p.into_inner()) = None;
    }
}

impl GymCore {
    fn with<T>(&self, f: impl FnOnce(&Episode) -> PyResult<T>) -> PyResult<T> {
        let slot = self.episode.lock().unwrap_or_else(|p| p.into_inner());
        match slot.as_ref() {
            Some(e) => f(e),
            None => Err(PyRuntimeError::new_err("reset() first")),
        }
    }
}

/// The options of an environment's episodes, from its arguments.
pub(crate) fn episode_options(
    action: &str,
    camera: bool,
    backend: Option<&str>,
) -> PyResult<EpisodeOptions> {
    Ok(EpisodeOptions {
        kind: ActionKind::parse(action)?,
        whole_frames: camera,
        backend: Backend::choose(backend).map_err(|e| PyValueError::new_err(e.to_string()))?,
    })
}

/// Checks a scenario (as `carfollow check` does) and its latency: the frames of an episode.
pub(crate) fn check_scenario(
    py: Python<'_>,
    scenario: &Py<PyAny>,
    overrides: Option<&Py<PyDict>>,
) -> PyResult<u64> {
    let plan = plan_of(py, scenario.bind(py), None, overrides.map(|o| o.bind(py)))?;
    latency_ok(&plan.scenario().delay)?;
    Ok(plan.scenario().frames())
}

/// What an episode needs from the interpreter: the scenario planned with `seed`, its
/// latency and delay line checked, and the tracker plug-in (its exceptions kept in
/// `raised`).
pub(crate) fn plan_episode(
    py: Python<'_>,
    scenario: &Py<PyAny>,
    overrides: Option<&Py<PyDict>>,
    tracker: Option<&Py<PyAny>>,
    seed: Option<u64>,
    raised: &Raised,
) -> PyResult<Planned> {
    let plan = plan_of(py, scenario.bind(py), seed, overrides.map(|o| o.bind(py)))?;
    let delay = &plan.scenario().delay;
    latency_ok(delay)?;
    vehicle::DelayLine::<[f64; 2]>::new(delay).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let tracker = match tracker {
        Some(t) => Some(PyTracker::new(py, t.clone_ref(py), raised.clone())?),
        None => None,
    };
    Ok(Planned { plan, tracker })
}

/// The estimate observation of an episode's last frame.
pub(crate) fn observed(e: &Episode) -> [f32; ESTIMATE_LEN] {
    let seen = *e.seen.lock().unwrap_or_else(|p| p.into_inner());
    estimate_observation(seen, &e.taken)
}

/// An episode's `info` (see `GymCore::info`).
pub(crate) fn info<'py>(py: Python<'py>, e: &Episode) -> PyResult<Bound<'py, PyDict>> {
    let r = &e.last.record;
    let d = PyDict::new(py);
    d.set_item("t", r.t_s)?;
    d.set_item("frame", r.frame)?;
    d.set_item("truth", truth_dict(py, r)?)?;
    d.set_item("record", to_python(py, r)?)?;
    d.set_item(
        "actions_in_flight",
        e.taken.iter().map(|a| (a[0], a[1])).collect::<Vec<_>>(),
    )?;
    Ok(d)
}

/// The estimate observation: the delayed estimate (range, lateral offset, age, status),
/// the chase's own state (speed, yaw rate, steering, pan), and the actions in flight, each
/// clipped to the observation space's bounds.
pub(crate) fn estimate_observation(
    seen: Option<ControlInput>,
    taken: &VecDeque<[f64; 2]>,
) -> [f32; ESTIMATE_LEN] {
    let mut o = [0.0f32; ESTIMATE_LEN];
    let (low, high) = estimate_bounds();
    if let Some(c) = seen {
        let e = c.estimate;
        o[0] = e.map_or(0.0, |e| e.range_m) as f32;
        o[1] = e.map_or(0.0, |e| e.lateral_m) as f32;
        o[2] = c.captured_t_s.map_or(NO_ESTIMATE_AGE_S, |t| c.t_s - t) as f32;
        o[3] = match e.map(|e| e.status) {
            Some(EstimateStatus::Tracking) => 1.0,
            Some(EstimateStatus::Coasting) => 0.5,
            Some(EstimateStatus::Lost) => 0.0,
            None => -1.0,
        };
        o[4] = c.speed_mps as f32;
        o[5] = c.yaw_rate_rad_s as f32;
        o[6] = c.steering_rad as f32;
        o[7] = c.pan_rad as f32;
    } else {
        o[2] = NO_ESTIMATE_AGE_S as f32;
        o[3] = -1.0;
    }
    for (k, a) in taken.iter().rev().take(IN_FLIGHT).enumerate() {
        o[8 + 2 * k] = a[0] as f32;
        o[9 + 2 * k] = a[1] as f32;
    }
    for (v, (lo, hi)) in o.iter_mut().zip(low.iter().zip(high)) {
        *v = v.clamp(*lo, hi);
    }
    o
}

/// The estimate observation's bounds (low, high).
pub(crate) fn estimate_bounds() -> ([f32; ESTIMATE_LEN], [f32; ESTIMATE_LEN]) {
    let mut low = [-1.0f32; ESTIMATE_LEN];
    let mut high = [1.0f32; ESTIMATE_LEN];
    for (k, (lo, hi)) in [
        (0.0, 200.0),
        (-50.0, 50.0),
        (0.0, NO_ESTIMATE_AGE_S as f32),
        (-1.0, 1.0),
        (0.0, 40.0),
        (-5.0, 5.0),
        (-1.0, 1.0),
        (-3.2, 3.2),
    ]
    .into_iter()
    .enumerate()
    {
        low[k] = lo;
        high[k] = hi;
    }
    (low, high)
}

/// The estimate observation space's bounds, for Python: (low, high) as lists.
#[pyfunction]
pub(crate) fn estimate_space() -> (Vec<f32>, Vec<f32>) {
    let (low, high) = estimate_bounds();
    (low.to_vec(), high.to_vec())
}
