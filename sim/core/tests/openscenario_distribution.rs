//! OpenSCENARIO `ParameterValueDistribution` files read into their runs: esmini's
//! (MPL-2.0, `tests/data/openscenario/esmini/xosc/cut-in_parameter_set.xosc`), expanded
//! as the standard combines deterministic distributions, and stochastic ones of each
//! shape, drawn with the moments and bounds they declare. Run with
//! `cargo test --release -p sim-core --test openscenario_distribution`.

use sim_core::openscenario::{read_distribution, Distribution};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/openscenario")
}

#[test]
fn esminis_distribution_is_every_combination_of_its_distributions() {
    let d = read_distribution(&data().join("esmini/xosc/cut-in_parameter_set.xosc")).unwrap();
    assert!(d.scenario.ends_with("cut-in.xosc"));
    assert_eq!(d.scenario_line, 5);
    assert_eq!(d.random_seed, None);
    let names: Vec<&str> = d.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "HostVehicle",
            "TargetVehicle",
            "EgoSpeed",
            "TargetSpeedFactor"
        ]
    );
    // 2 value sets × 2 speeds × 3 factors (1.1 to 1.5 by 0.2, inclusive).
    assert_eq!(d.runs.len(), 12);
    let text = |run: &Vec<(String, String)>| {
        run.iter()
            .map(|(n, v)| format!("{n}={v}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    assert_eq!(
        text(&d.runs[0]),
        "HostVehicle=car_blue TargetVehicle=car_yellow EgoSpeed=70.0 TargetSpeedFactor=1.1"
    );
    assert_eq!(
        text(&d.runs[5]),
        "HostVehicle=car_blue TargetVehicle=car_yellow EgoSpeed=110.0 TargetSpeedFactor=1.5"
    );
    assert_eq!(
        text(&d.runs[11]),
        "TargetVehicle=van_red EgoSpeed=110.0 TargetSpeedFactor=1.5"
    );
}

/// A stochastic distribution of `cut-in.xosc`'s `LeadSpeed` of `runs` runs, `shape`
/// its distribution.
fn stochastic(dir: &tempfile::TempDir, runs: usize, shape: &str) -> Distribution {
    std::fs::copy(data().join("cut-in.xosc"), dir.path().join("cut-in.xosc")).unwrap();
    let text = format!(
        r#"<?xml version="1.0"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="3" date="2026-11-27T00:00:00" description="d" author="a"/>
  <ParameterValueDistribution>
    <ScenarioFile filepath="cut-in.xosc"/>
    <Stochastic numberOfTestRuns="{runs}" randomSeed="7">
      <StochasticDistribution parameterName="LeadSpeed">{shape}</StochasticDistribution>
    </Stochastic>
  </ParameterValueDistribution>
</OpenSCENARIO>"#
    );
    let path = dir.path().join("d.xosc");
    std::fs::write(&path, text).unwrap();
    read_distribution(&path).unwrap()
}

fn values(d: &Distribution) -> Vec<f64> {
    d.runs.iter().map(|r| r[0].1.parse().unwrap()).collect()
}

fn mean_var(xs: &[f64]) -> (f64, f64) {
    let m = xs.iter().sum::<f64>() / xs.len() as f64;
    let v = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / xs.len() as f64;
    (m, v)
}

#[test]
fn stochastic_draws_have_the_moments_and_bounds_they_declare() {
    let dir = tempfile::tempdir().unwrap();
    let n = 5000;
    let (m, v) = mean_var(&values(&stochastic(
        &dir,
        n,
        r#"<NormalDistribution expectedValue="50" variance="16"/>"#,
    )));
    assert!((m - 50.0).abs() < 0.3 && (v - 16.0).abs() < 1.0, "{m} {v}");
    let (m, v) = mean_var(&values(&stochastic(
        &dir,
        n,
        r#"<LogNormalDistribution expectedValue="50" variance="100"/>"#,
    )));
    assert!(
        (m - 50.0).abs() < 0.6 && (v - 100.0).abs() < 10.0,
        "{m} {v}"
    );
    let drawn = stochastic(
        &dir,
        n,
        r#"<PoissonDistribution expectedValue="30"><Range lowerLimit="0" upperLimit="1000"/></PoissonDistribution>"#,
    );
    assert!(drawn.runs.iter().all(|r| r[0].1.parse::<u64>().is_ok()));
    let (m, v) = mean_var(&values(&drawn));
    assert!((m - 30.0).abs() < 0.4 && (v - 30.0).abs() < 3.0, "{m} {v}");
    let xs = values(&stochastic(
        &dir,
        n,
        r#"<UniformDistribution><Range lowerLimit="20" upperLimit="30"/></UniformDistribution>"#,
    ));
    assert!(xs.iter().all(|x| (20.0..=30.0).contains(x)));
    let (m, _) = mean_var(&xs);
    assert!((m - 25.0).abs() < 0.2, "{m}");
    // Truncated to one side of the mean: every draw inside.
    let xs = values(&stochastic(
        &dir,
        n,
        r#"<NormalDistribution expectedValue="50" variance="16"><Range lowerLimit="50" upperLimit="52"/></NormalDistribution>"#,
    ));
    assert!(xs.iter().all(|x| (50.0..=52.0).contains(x)));
    let sets = stochastic(
        &dir,
        n,
        r#"<ProbabilityDistributionSet><Element value="40" weight="1"/><Element value="60" weight="3"/></ProbabilityDistributionSet>"#,
    );
    let sixty = sets.runs.iter().filter(|r| r[0].1 == "60").count() as f64 / n as f64;
    assert!((sixty - 0.75).abs() < 0.03, "{sixty}");
    // The same file, the same draws.
    let a = stochastic(
        &dir,
        20,
        r#"<NormalDistribution expectedValue="50" variance="16"/>"#,
    );
    let b = stochastic(
        &dir,
        20,
        r#"<NormalDistribution expectedValue="50" variance="16"/>"#,
    );
    assert_eq!(a.runs, b.runs);
    assert_eq!(a.random_seed, Some(7));
}
