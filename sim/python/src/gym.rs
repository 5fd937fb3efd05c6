//! The native core of `carfollow/Follow-v0` (`carfollow.env.FollowEnv` is the Gymnasium
//! face of it): one step is one camera frame, the agent's action goes through a delay line
//! with the scenario's latency, jitter and drops (as the built-in tracker's estimates do),
//! and the loop renders the next frame while the agent thinks.
//!
//! An action taken on frame k's observation is applied from the physics step at which an
//! estimate of frame k would reach the controller. With the scenario's latency of at least
//! one frame, the physics to frame k + 1 needs no action of frame k, so frame k + 1 is
//! rendered in the background as soon as frame k has been returned.

use crate::errors::run_error;
use crate::plugins::Raised;
use crate::scenario::plan_of;
use crate::simulation::{frame_array, to_python, truth_dict};
use numpy::PyArray1;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim_core::{
    BuiltinController, ClosedLoop, Command, ControlInput, Controller, ControllerChoice, Delivered,
    EstimateStatus, FrameOutput, LoopOptions, PluginError, TrackerChoice,
};
use sim_render::Backend;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use vehicle::{DelayLine, Step, VehicleParams, STEPS_PER_FRAME};

/// Actions still in flight that the estimate observation carries (the latency is under two
/// frames in every shipped scenario: 128 ms is 1.92 frames).
const IN_FLIGHT: usize = 2;
/// The estimate observation's length: 8 values, then the actions in flight (2 each).
pub(crate) const ESTIMATE_LEN: usize = 8 + 2 * IN_FLIGHT;
/// An estimate's age when there is none, seconds (the observation's upper bound).
const NO_ESTIMATE_AGE_S: f64 = 10.0;

/// What the agent commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ActionKind {
    /// Steering (full lock at ±1) and the longitudinal (throttle above 0, brake below).
    Drive,
    /// The longitudinal only; the built-in controller steers (and aims the pan head).
    Longitudinal,
}

/// The controller in the loop: the agent's actions through their delay line.
struct Agent {
    /// Actions queued at their observation's capture step: `[steer, longitudinal]`.
    actions: Arc<Mutex<DelayLine<[f64; 2]>>>,
    /// The action applied now (nothing until the first is due).
    now: [f64; 2],
    max_steer_rad: f64,
    /// The built-in controller, steering, in `Longitudinal`.
    steering: Option<BuiltinController>,
    /// The latest input, for the estimate observation.
    seen: Arc<Mutex<Option<ControlInput>>>,
}

impl Controller for Agent {
    /// The built-in steering hears every estimate delivered, as in the loop.
    fn receive(&mut self, delivered: &Delivered) {
        if let Some(builtin) = &mut self.steering {
            builtin.receive(delivered);
        }
    }

    fn name(&self) -> String {
        match self.steering {
            Some(_) => "gymnasium agent (longitudinal; built-in steering)".into(),
            None => "gymnasium agent".into(),
        }
    }

    fn control(&mut self, input: &ControlInput) -> Result<Command, PluginError> {
        let due = self
            .actions
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .pop_due(Step::from_seconds(input.t_s));
        if let Some(&latest) = due.last() {
            self.now = latest;
        }
        *self.seen.lock().unwrap_or_else(|p| p.into_inner()) = Some(*input);
        let [steer, longitudinal] = self.now;
        let (steering_rad, pan_rate_rad_s) = match &mut self.steering {
            Some(builtin) => {
                let c = builtin.control(input)?;
                (c.steering_rad, c.pan_rate_rad_s)
            }
            None => (steer * self.max_steer_rad, 0.0),
        };
        Ok(Command {
            steering_rad,
            throttle: longitudinal.max(0.0),
            brake: (-longitudinal).max(0.0),
            pan_rate_rad_s,
        })
    }
}

/// One episode.
struct Episode {
    looped: ClosedLoop,
    actions: Arc<Mutex<DelayLine<[f64; 2]>>>,
    seen: Arc<Mutex<Option<ControlInput>>>,
    last: FrameOutput,
    /// The actions taken, newest last (for the observation and the smoothness reward).
    taken: VecDeque<[f64; 2]>,
    gap_band_m: [f64; 2],
    /// The lead's path further than this beside the chase: off the road, metres.
    off_road_m: f64,
}

/// The environment's native core: builds an episode at each reset, steps it a frame at a
/// time with the interpreter released.
#[pyclass(module = "carfollow")]
pub struct GymCore {
    scenario: Py<PyAny>,
    overrides: Option<Py<PyDict>>,
    kind: ActionKind,
    whole_frames: bool,
    backend: Backend,
    episode: Mutex<Option<Episode>>,
    raised: Raised,
}

#[pymethods]
impl GymCore {
    #[new]
    #[pyo3(signature = (scenario, overrides=None, action="drive", camera=true, backend=None))]
    fn new(
        scenario: Py<PyAny>,
        overrides: Option<Py<PyDict>>,
        action: &str,
        camera: bool,
        backend: Option<&str>,
    ) -> PyResult<GymCore> {
        let kind = match action {
            "drive" => ActionKind::Drive,
            "longitudinal" => ActionKind::Longitudinal,
            other => {
                return Err(PyValueError::new_err(format!(
                    "action = {other:?}: must be \"drive\" or \"longitudinal\""
                )))
            }
        };
        Ok(GymCore {
            scenario,
            overrides,
            kind,
            whole_frames: camera,
            backend: Backend::choose(backend).map_err(|e| PyValueError::new_err(e.to_string()))?,
            episode: Mutex::new(None),
            raised: Raised::default(),
        })
    }

    /// Checks the scenario (as `carfollow check` does) and that its latency lets an action
    /// be applied after the frame it answers: returns the number of frames of an episode.
    fn check(&self, py: Python<'_>) -> PyResult<u64> {
        let plan = plan_of(
            py,
            self.scenario.bind(py),
            None,
            self.overrides.as_ref().map(|o| o.bind(py)),
        )?;
        latency_ok(&plan.scenario().delay)?;
        Ok(plan.scenario().frames())
    }

    /// Starts an episode with the scenario's `seed` (its own when None), ending the last one
    /// first: a reset that fails leaves no episode, and `step()` asks for a reset.
    #[pyo3(signature = (seed=None))]
    fn reset(&self, py: Python<'_>, seed: Option<u64>) -> PyResult<()> {
        let plan = plan_of(
            py,
            self.scenario.bind(py),
            seed,
            self.overrides.as_ref().map(|o| o.bind(py)),
        )?;
        let s = plan.scenario().clone();
        latency_ok(&s.delay)?;
        let line = DelayLine::new(&s.delay).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let actions = Arc::new(Mutex::new(line));
        let seen = Arc::new(Mutex::new(None));
        let steering = match self.kind {
            ActionKind::Drive => None,
            ActionKind::Longitudinal => Some(
                BuiltinController::new(s.chase.clone(), s.chase_initial_speed_mps)
                    .map_err(|e| PyValueError::new_err(e.to_string()))?,
            ),
        };
        let agent = Agent {
            actions: actions.clone(),
            now: [0.0; 2],
            max_steer_rad: f64::from(VehicleParams::hmmwv_m998().max_steer_rad),
            steering,
            seen: seen.clone(),
        };
        let options = LoopOptions {
            // One renderer: two in flight run the physics a frame ahead, which would need
            // the agent's next action before it is taken.
            renderers: 1,
            whole_frames: self.whole_frames,
            tracker: TrackerChoice::Builtin,
            controller: ControllerChoice::Plugin(Box::new(agent)),
            ..LoopOptions::new(self.backend)
        };
        let raised = &self.raised;
        // The old episode goes first, with the interpreter released: closing its renderer
        // takes tens of milliseconds, and two renderers need not be held at once.
        let old = self
            .episode
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        let episode = py
            .detach(move || -> Result<Episode, sim::RunError> {
                drop(old);
                let mut looped = ClosedLoop::start(plan, options)?;
                let last = looped.step()?.expect("a scenario has at least one frame");
                looped.prefetch()?;
                Ok(Episode {
                    looped,
                    actions,
                    seen,
                    last,
                    taken: VecDeque::new(),
                    gap_band_m: s.expect.gap_band_m.unwrap_or([5.0, 15.0]),
                    off_road_m: 1.5 * s.route.lane_width_m,
                })
            })
            .map_err(|e| run_error(py, e, raised))?;
        *self.episode.lock().unwrap_or_else(|p| p.into_inner()) = Some(episode);
        Ok(())
    }

    /// Takes an action on the last observation and runs to the next frame. Returns
    /// `(reward, terminated, truncated)`.
    fn step(&self, py: Python<'_>, steer: f64, longitudinal: f64) -> PyResult<(f64, bool, bool)> {
        if !(steer.is_finite() && longitudinal.is_finite()) {
            return Err(PyValueError::new_err("the action must be finite"));
        }
        let action = [steer.clamp(-1.0, 1.0), longitudinal.clamp(-1.0, 1.0)];
        let raised = &self.raised;
        let mut slot = self.episode.lock().unwrap_or_else(|p| p.into_inner());
        let e = slot
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("reset() before step()"))?;
        let captured = Step(e.last.record.frame * u64::from(STEPS_PER_FRAME));
        e.actions
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(captured, action);
        let previous = e.taken.back().copied().unwrap_or(action);
        e.taken.push_back(action);
        while e.taken.len() > IN_FLIGHT {
            e.taken.pop_front();
        }
        let looped = &mut e.looped;
        let out = py
            .detach(move || -> Result<Option<FrameOutput>, sim::RunError> {
                let out = looped.step()?;
                looped.prefetch()?;
                Ok(out)
            })
            .map_err(|err| run_error(py, err, raised))?;
        let Some(out) = out else {
            return Ok((0.0, false, true));
        };
        e.last = out;
        let r = &e.last.record;
        let smooth = (action[0] - previous[0]).abs() + (action[1] - previous[1]).abs();
        let reward = reward(r, e.gap_band_m, smooth);
        let terminated = r.collision || r.lateral_deviation_m > e.off_road_m;
        let truncated = !terminated && e.looped.frame() >= e.looped.frames();
        Ok((reward, terminated, truncated))
    }

    /// The last frame, uint8 (242, 256).
    fn frame<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<u8>>> {
        self.with(|e| frame_array(py, &e.last.image))
    }

    /// The estimate observation (see `carfollow.env.FollowEnv`), float32.
    fn estimate_observation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        self.with(|e| {
            let seen = *e.seen.lock().unwrap_or_else(|p| p.into_inner());
            Ok(PyArray1::from_vec(
                py,
                estimate_observation(seen, &e.taken).to_vec(),
            ))
        })
    }

    /// What the step's `info` holds: the time, the frame, the truth (for scoring; the agent
    /// should not act on it), the tracker's estimate, the actions in flight.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with(|e| {
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
        })
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

/// An action must be applied after the frame it answers: the latency less the jitter at
/// least one frame.
fn latency_ok(d: &vehicle::DelayLineConfig) -> PyResult<()> {
    let frame_ms = 1000.0 / f64::from(vehicle::CAMERA_HZ);
    if d.latency_ms - d.jitter_ms < frame_ms {
        return Err(PyValueError::new_err(format!(
            "`loop.latency_ms` − `loop.jitter_ms` = {} ms: the environment needs at least one \
             frame ({frame_ms:.1} ms), so that an action takes effect after the frame it answers",
            d.latency_ms - d.jitter_ms
        )));
    }
    Ok(())
}

/// The default reward of one frame (documented in `carfollow.env.FollowEnv`): +1 inside the
/// gap band, less the distance outside it over 5 m (down to −1); −1 when the target is out of
/// the camera's view; −10 on a collision; −0.1 times the action's change since the last.
fn reward(r: &sim_core::FrameRecord, band: [f64; 2], change: f64) -> f64 {
    let [lo, hi] = band;
    let outside = (lo - r.gap_m).max(r.gap_m - hi).max(0.0);
    let gap = if outside == 0.0 {
        1.0
    } else {
        -(outside / 5.0).min(1.0)
    };
    let view = if r.target_in_view { 0.0 } else { -1.0 };
    let collision = if r.collision { -10.0 } else { 0.0 };
    gap + view + collision - 0.1 * change
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
