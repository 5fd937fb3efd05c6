//! An OpenSCENARIO `ParameterValueDistribution` file as a sweep: one scenario (the file's
//! `ScenarioFile`), one seed (the scenario's own, or `--set seed=N`), and a point per run
//! of the distribution, its params the scenario's parameters (`$EgoSpeed = 70`), given
//! to the scenario as `--param` gives them. The grid order is the distribution's (see
//! `sim_core::openscenario::read_distribution`); ids, results, `--resume`, shards and the
//! report are a sweep file's.

use super::file::{Roles, SweepScenario};
use super::grid::{id_of, load_scenario, sweep_hash, Axis, Inputs, OSC_PARAM};
use super::{Point, Sweep, SweepError};
use sim_core::{planning_key, Plan, ScenarioError};
use std::collections::BTreeSet;
use std::path::Path;

/// The field a point's error is said of: the distribution's `ScenarioFile` element.
const SCENARIO_FIELD: &str = "ScenarioFile";

impl Sweep {
    /// [`Sweep::load`] of a parameter distribution file (`plan`: whether each point is
    /// planned, as `load` does, or only loaded, as `load_checked` does).
    pub(super) fn read_distribution(
        path: &Path,
        extra_set: &[String],
        roles: &Roles,
        plan: bool,
    ) -> Result<Sweep, SweepError> {
        let distribution = sim_core::openscenario::read_distribution(path)?;
        let text = std::fs::read_to_string(path).map_err(|error| SweepError::Io {
            path: path.to_owned(),
            action: "cannot read the sweep",
            error,
        })?;
        let at_scenario = |point: String, e: ScenarioError| SweepError::Point {
            path: path.to_owned(),
            line: distribution.scenario_line as usize,
            column: 1,
            field: SCENARIO_FIELD.into(),
            point,
            error: Box::new(e),
        };
        let scenario_path = distribution.scenario.clone();
        let scenario_text = std::fs::read_to_string(&scenario_path).map_err(|source| {
            at_scenario(
                scenario_path.display().to_string(),
                ScenarioError::Io {
                    path: scenario_path.clone(),
                    source,
                },
            )
        })?;
        let mut scenario = SweepScenario {
            path: scenario_path.clone(),
            name: String::new(),
            text: scenario_text.into(),
            roles: roles.clone(),
        };
        let set = extra_set.to_vec();
        let base = load_scenario(&scenario, &set, Vec::new())
            .map_err(|e| at_scenario(scenario_path.display().to_string(), e))?;
        scenario.name = base.name.clone();
        let seed = base.seed;

        let points: Vec<Point> = distribution
            .runs
            .iter()
            .enumerate()
            .map(|(index, run)| {
                let mut point = Point {
                    index,
                    id: String::new(),
                    scenario: 0,
                    scenario_name: scenario.name.clone(),
                    seed,
                    params: run
                        .iter()
                        .map(|(name, value)| (format!("{OSC_PARAM}{name}"), value_of(value)))
                        .collect(),
                };
                point.id = id_of(&point, &set);
                point
            })
            .collect();

        // Every point loaded (and planned, one of each planning key) before anything runs;
        // the files they read, for the hash.
        let mut planned_keys = BTreeSet::new();
        let mut inputs = Inputs::of([scenario_path.clone()]);
        for point in &points {
            let loaded = load_scenario(&scenario, &point.overrides(&set), point.osc_params());
            if let Ok(s) = &loaded {
                inputs.note(s, &scenario_path);
            }
            let planned = match loaded {
                Ok(s) if plan && planned_keys.insert(planning_key(&s)) => Plan::new(&s).map(|_| ()),
                Ok(_) => Ok(()),
                Err(e) => Err(e),
            };
            planned.map_err(|e| at_scenario(point.describe(), e))?;
        }
        let axes = distribution
            .parameters
            .iter()
            .map(|p| {
                let path = format!("{OSC_PARAM}{}", p.name);
                let mut values: Vec<toml::Value> = Vec::new();
                for point in &points {
                    if let Some((_, v)) = point.params.iter().find(|(q, _)| *q == path) {
                        if !values.contains(v) {
                            values.push(v.clone());
                        }
                    }
                }
                Axis { path, values }
            })
            .collect();
        Ok(Sweep {
            plans: planned_keys.len(),
            hash: sweep_hash(&text, extra_set, &inputs),
            path: path.to_owned(),
            scenarios: vec![scenario],
            seeds: vec![seed],
            set,
            axes,
            points,
            distribution: Some(distribution),
        })
    }
}

/// A parameter's value as a point's param: a number where the text is one as written
/// back (`70`, `1.5`), so that the report can plot it; the text otherwise (`car_red`,
/// `007`).
fn value_of(text: &str) -> toml::Value {
    if let Ok(i) = text.parse::<i64>() {
        if i.to_string() == text {
            return toml::Value::Integer(i);
        }
    }
    if let Ok(f) = text.parse::<f64>() {
        let v = toml::Value::Float(f);
        if f.is_finite() && v.to_string() == text {
            return v;
        }
    }
    toml::Value::String(text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_numbers_only_where_they_read_back_as_written() {
        assert_eq!(value_of("70"), toml::Value::Integer(70));
        assert_eq!(value_of("1.5"), toml::Value::Float(1.5));
        assert_eq!(value_of("70.0"), toml::Value::Float(70.0));
        assert_eq!(value_of("007"), toml::Value::String("007".into()));
        assert_eq!(value_of("car_red"), toml::Value::String("car_red".into()));
    }
}
