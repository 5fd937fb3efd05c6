//! The `carfollow` Python package's native module (`carfollow._carfollow`): the simulation
//! stepped frame by frame, trackers and controllers written in Python in the loop, and the
//! core of the Gymnasium environment. The logic stays in the Rust crates; this layer
//! converts, releases the interpreter around long work, and turns errors into exceptions.
#![warn(missing_docs)]

mod builtin;
mod episode;
mod errors;
mod gym;
mod plugins;
mod scenario;
mod simulation;
mod types;
mod vec_gym;

use pyo3::prelude::*;

/// The names of the shipped scenarios, which `Simulation` takes by name.
#[pyfunction]
fn shipped_scenarios() -> Vec<&'static str> {
    sim_core::shipped_scenarios().collect()
}

/// Checks a scenario as `carfollow check` does (parsed, validated, planned): returns its
/// name, or raises ValueError with the line `carfollow check` prints (FileNotFoundError for
/// a missing file).
#[pyfunction]
#[pyo3(signature = (scenario, seed=None, overrides=None))]
fn check(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    seed: Option<u64>,
    overrides: Option<&Bound<'_, pyo3::types::PyDict>>,
) -> PyResult<String> {
    let plan = scenario::plan_of(py, scenario, seed, overrides)?;
    Ok(plan.scenario().name.clone())
}

/// The module.
#[pymodule]
fn _carfollow(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<types::Estimate>()?;
    m.add_class::<types::Command>()?;
    m.add_class::<types::ControlInput>()?;
    m.add_class::<types::Camera>()?;
    m.add_class::<gym::GymCore>()?;
    m.add_class::<vec_gym::VecCore>()?;
    m.add_class::<builtin::PaperTracker>()?;
    m.add_function(wrap_pyfunction!(shipped_scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(gym::estimate_space, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
