//! The native core of the vector `carfollow/Follow-v0` (`carfollow.vector.FollowVectorEnv`
//! is its Gymnasium face): N episodes in one process, stepped together, each on a thread of
//! its own with the interpreter released. Each episode renders its next frame in the
//! background as soon as its step returns, so the N frames render while the agent thinks.
//!
//! llvmpipe renders the frames of one EGL display one at a time, so the odd-numbered
//! sub-environments render on Mesa's software EGL device, a llvmpipe of its own, and the
//! even-numbered ones on wgpu's display: two frames render at once (the same frames).
//!
//! Every episode is the single environment's (`gym::GymCore`), run by the same code, so a
//! sub-environment reset with seed s gives the frames a single environment reset with s
//! gives, bit for bit. A sub-environment that fails (an exception of its tracker plug-in,
//! an error of its loop, a panic) loses its episode alone: the error names it, and the
//! others keep theirs.

use crate::episode::{clamped, Episode, EpisodeOptions, Outcome, Planned};
use crate::errors::{env_run_error, with_env, with_place};
use crate::gym::{check_scenario, episode_options, info, observed, plan_episode, ESTIMATE_LEN};
use crate::plugins::{PyTracker, Raised};
use numpy::{
    PyArray1, PyArray2, PyArray4, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

/// One sub-environment's setting.
struct Sub {
    scenario: Py<PyAny>,
    overrides: Option<Py<PyDict>>,
    tracker: Option<Py<PyAny>>,
    /// Its tracker plug-in's exception, kept for the caller.
    raised: Raised,
}

/// What a sub-environment does in one call: start an episode or step the one it has.
enum Job {
    Start(Box<Planned>),
    Advance([f64; 2]),
    /// Nothing: the episode stays as it is.
    Keep,
}

/// Why a sub-environment's job failed.
enum Failure {
    Run(sim::RunError),
    Panic(String),
}

/// N episodes stepped together.
#[pyclass(module = "carfollow")]
pub struct VecCore {
    subs: Vec<Sub>,
    options: EpisodeOptions,
    /// Each sub-environment's episode (`None` before its first reset and after it failed).
    episodes: Mutex<Vec<Option<Episode>>>,
}

#[pymethods]
impl VecCore {
    #[new]
    #[pyo3(signature = (scenarios, overrides, trackers=None, action="drive", camera=true, backend=None))]
    fn new(
        py: Python<'_>,
        scenarios: Vec<Py<PyAny>>,
        overrides: Vec<Option<Py<PyDict>>>,
        trackers: Option<Vec<Option<Py<PyAny>>>>,
        action: &str,
        camera: bool,
        backend: Option<&str>,
    ) -> PyResult<VecCore> {
        let n = scenarios.len();
        if n == 0 {
            return Err(PyValueError::new_err("num_envs must be at least 1"));
        }
        let trackers = trackers.unwrap_or_else(|| (0..n).map(|_| None).collect());
        if overrides.len() != n || trackers.len() != n {
            return Err(PyValueError::new_err(format!(
                "{n} scenarios, {} overrides and {} trackers: one of each per environment",
                overrides.len(),
                trackers.len()
            )));
        }
        let subs = scenarios
            .into_iter()
            .zip(overrides)
            .zip(trackers)
            .enumerate()
            .map(|(k, ((scenario, overrides), tracker))| {
                if let Some(t) = &tracker {
                    PyTracker::new(py, t.clone_ref(py), Raised::default())
                        .map_err(|e| in_env(py, e, k))?;
                }
                Ok(Sub {
                    scenario,
                    overrides,
                    tracker,
                    raised: Raised::default(),
                })
            })
            .collect::<PyResult<Vec<Sub>>>()?;
        Ok(VecCore {
            subs,
            options: episode_options(action, camera, backend)?,
            episodes: Mutex::new((0..n).map(|_| None).collect()),
        })
    }

    /// The number of sub-environments.
    #[getter]
    fn num_envs(&self) -> usize {
        self.subs.len()
    }

    /// Checks every sub-environment's scenario (see `GymCore.check`): the frames of an
    /// episode of each.
    fn check(&self, py: Python<'_>) -> PyResult<Vec<u64>> {
        self.subs
            .iter()
            .enumerate()
            .map(|(k, s)| {
                check_scenario(py, &s.scenario, s.overrides.as_ref()).map_err(|e| in_env(py, e, k))
            })
            .collect()
    }

    /// Starts a new episode in the sub-environments of `resets` (index, seed: the
    /// scenario's own when None), all at once; the others keep theirs as they are.
    fn reset_some(&self, py: Python<'_>, resets: Vec<(usize, Option<u64>)>) -> PyResult<()> {
        let keep = (0..self.subs.len()).map(|_| Job::Keep).collect();
        self.run(py, keep, &resets).map(|_| ())
    }

    /// Steps every sub-environment with its row of `actions` (N × 2: steering, then the
    /// longitudinal), except those in `resets` (index, seed), which start a new episode
    /// instead (reward 0, neither terminated nor truncated). Returns the rewards,
    /// `terminated` and `truncated`, one each per sub-environment. An error of one
    /// sub-environment is raised naming it after all have run; its episode is gone (see
    /// `missing`), the others' have taken their step.
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &self,
        py: Python<'py>,
        actions: PyReadonlyArray2<'py, f64>,
        resets: Vec<(usize, Option<u64>)>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
    )> {
        let n = self.subs.len();
        if actions.shape() != [n, 2] {
            return Err(PyValueError::new_err(format!(
                "actions of shape {:?}: expected ({n}, 2)",
                actions.shape()
            )));
        }
        let a = actions.as_array();
        let rows = (0..n)
            .map(|k| clamped(a[[k, 0]], a[[k, 1]]).map_err(|e| in_env(py, e, k)))
            .collect::<PyResult<Vec<_>>>()?;
        let jobs = rows.into_iter().map(Job::Advance).collect();
        let outcomes = self.run(py, jobs, &resets)?;
        Ok((
            PyArray1::from_iter(py, outcomes.iter().map(|o| o.reward)),
            PyArray1::from_iter(py, outcomes.iter().map(|o| o.terminated)),
            PyArray1::from_iter(py, outcomes.iter().map(|o| o.truncated)),
        ))
    }

    /// The sub-environments without an episode: never reset, or failed.
    fn missing(&self) -> Vec<usize> {
        let episodes = self.episodes.lock().unwrap_or_else(|p| p.into_inner());
        (0..episodes.len())
            .filter(|&k| episodes[k].is_none())
            .collect()
    }

    /// The last frames, uint8 (N, 1, 242, 256).
    fn frames<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray4<u8>>> {
        let episodes = self.all()?;
        let (w, h) = episodes[0]
            .as_ref()
            .map_or((0, 0), |e| e.last.image.dimensions());
        let mut pixels = Vec::with_capacity(episodes.len() * (w * h) as usize);
        for e in episodes.iter().flatten() {
            pixels.extend_from_slice(e.last.image.as_raw());
        }
        PyArray1::from_vec(py, pixels).reshape([episodes.len(), 1, h as usize, w as usize])
    }

    /// The estimate observations, float32 (N, 12).
    fn estimate_observations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let episodes = self.all()?;
        let mut values = Vec::with_capacity(episodes.len() * ESTIMATE_LEN);
        for e in episodes.iter().flatten() {
            values.extend_from_slice(&observed(e));
        }
        PyArray1::from_vec(py, values).reshape([episodes.len(), ESTIMATE_LEN])
    }

    /// Each sub-environment's `info` (see `GymCore.info`).
    fn infos<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let episodes = self.all()?;
        let list = PyList::empty(py);
        for e in episodes.iter().flatten() {
            list.append(info(py, e)?)?;
        }
        Ok(list)
    }

    /// The number of frames of each sub-environment's episode.
    fn frames_per_episode(&self) -> PyResult<Vec<u64>> {
        let episodes = self.all()?;
        Ok(episodes
            .iter()
            .flatten()
            .map(|e| e.looped.frames())
            .collect())
    }

    /// Ends every episode (frees the renderers).
    fn close(&self, py: Python<'_>) {
        let old: Vec<Option<Episode>> = {
            let mut episodes = self.episodes.lock().unwrap_or_else(|p| p.into_inner());
            episodes.iter_mut().map(Option::take).collect()
        };
        py.detach(move || drop(old));
    }
}

impl VecCore {
    /// The episodes, every one there.
    fn all(&self) -> PyResult<std::sync::MutexGuard<'_, Vec<Option<Episode>>>> {
        let episodes = self.episodes.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(k) = episodes.iter().position(Option::is_none) {
            return Err(PyRuntimeError::new_err(format!(
                "environment {k} has no episode: reset() first"
            )));
        }
        Ok(episodes)
    }

    /// Runs `jobs`, one per sub-environment, on threads of their own with the interpreter
    /// released, those in `resets` replaced by a new episode.
    fn run(
        &self,
        py: Python<'_>,
        mut jobs: Vec<Job>,
        resets: &[(usize, Option<u64>)],
    ) -> PyResult<Vec<Outcome>> {
        let n = self.subs.len();
        // Planning reads Python values: done here, before anything runs, so that a scenario
        // that cannot be planned changes no episode.
        for &(k, seed) in resets {
            let s = self.subs.get(k).ok_or_else(|| {
                PyValueError::new_err(format!("environment {k}: there are {n} environments"))
            })?;
            let planned = plan_episode(
                py,
                &s.scenario,
                s.overrides.as_ref(),
                s.tracker.as_ref(),
                seed,
                &s.raised,
            )
            .map_err(|e| in_env(py, e, k))?;
            jobs[k] = Job::Start(Box::new(planned));
        }
        let mut episodes = self.episodes.lock().unwrap_or_else(|p| p.into_inner());
        for (k, job) in jobs.iter().enumerate() {
            if matches!(job, Job::Advance(_)) && episodes[k].is_none() {
                return Err(with_env(
                    py,
                    PyRuntimeError::new_err(format!(
                        "environment {k} has no episode: reset() first"
                    )),
                    k,
                ));
            }
        }
        let options = self.options;
        let slots = &mut *episodes;
        let results: Vec<Result<Outcome, Failure>> = py.detach(move || {
            std::thread::scope(|scope| {
                let running: Vec<_> = slots
                    .iter_mut()
                    .zip(jobs)
                    .enumerate()
                    .map(|(k, (slot, job))| match job {
                        Job::Keep => None,
                        job => Some(scope.spawn(move || run_job(slot, job, options, k % 2 == 1))),
                    })
                    .collect();
                running
                    .into_iter()
                    .map(|t| match t {
                        None => Ok(Outcome::default()),
                        Some(t) => t
                            .join()
                            .unwrap_or_else(|p| Err(Failure::Panic(panic_message(&*p)))),
                    })
                    .collect()
            })
        });
        let mut first_error = None;
        let mut outcomes = Vec::with_capacity(n);
        for (k, result) in results.into_iter().enumerate() {
            match result {
                Ok(o) => outcomes.push(o),
                Err(failure) => {
                    outcomes.push(Outcome::default());
                    let err = match failure {
                        Failure::Run(e) => env_run_error(py, e, &self.subs[k].raised, k),
                        Failure::Panic(m) => with_env(
                            py,
                            PyRuntimeError::new_err(format!("environment {k}: a panic: {m}")),
                            k,
                        ),
                    };
                    first_error.get_or_insert(err);
                }
            }
        }
        match first_error {
            Some(err) => Err(err),
            None => Ok(outcomes),
        }
    }
}

/// One sub-environment's job, on its own thread (a new episode rendering on the software
/// device with `software_device`). A failure (an error, or a panic, caught here) leaves it
/// no episode.
fn run_job(
    slot: &mut Option<Episode>,
    job: Job,
    options: EpisodeOptions,
    software_device: bool,
) -> Result<Outcome, Failure> {
    let ran = catch_unwind(AssertUnwindSafe(|| match job {
        Job::Start(planned) => {
            // The old episode goes first: two renderers need not be held at once.
            *slot = None;
            Episode::start(*planned, options, software_device).map(|e| {
                *slot = Some(e);
                Outcome::default()
            })
        }
        Job::Advance(action) => slot.as_mut().expect("checked before").advance(action),
        Job::Keep => Ok(Outcome::default()),
    }));
    let result = match ran {
        Ok(Ok(o)) => Ok(o),
        Ok(Err(e)) => Err(Failure::Run(e)),
        Err(panic) => Err(Failure::Panic(panic_message(&*panic))),
    };
    if result.is_err() {
        // Its loop stopped part way: a new episode is the way on.
        let gone = slot.take();
        // A loop that panicked may panic again as it closes: that must not end the process.
        let _ = catch_unwind(AssertUnwindSafe(move || drop(gone)));
    }
    result
}

/// A panic's message.
fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".into())
}

/// `err`, raised for the sub-environment `k`: its message and its `env_index` say so.
fn in_env(py: Python<'_>, err: PyErr, k: usize) -> PyErr {
    with_env(py, with_place(py, err, &format!("environment {k}")), k)
}
